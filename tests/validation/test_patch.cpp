// Patch tests (Irons & Razzaque; MacNeal & Harder 1985): on distorted Quad4 and Quad8 meshes,
// prescribing a linear displacement field on the boundary must reproduce it exactly inside, with
// exactly constant stress. Reference: the linear field itself.
#include <mesh/Generators.hpp>
#include <solver/DisplacementModel.hpp>
#include <support/Reference.hpp>

#include <gtest/gtest.h>

using namespace mixcon;

class PatchTest : public ::testing::TestWithParam<std::tuple<ElementType, LinearSolverType>> {};
INSTANTIATE_TEST_SUITE_P(
    Elements, PatchTest,
    ::testing::Combine(::testing::Values(ElementType::Quad4, ElementType::Quad8),
                       ::testing::Values(LinearSolverType::Direct, LinearSolverType::Amg)),
    [](const auto &info) {
      return std::string(std::get<0>(info.param) == ElementType::Quad8 ? "Quad8" : "Quad4") +
             (std::get<1>(info.param) == LinearSolverType::Amg ? "Amg" : "Direct");
    });

TEST_P(PatchTest, LinearFieldIsReproducedExactly) {
  const auto [type, solver] = GetParam();
  Mesh mesh = rectangleMesh(2.0, 1.5, 5, 4, type, -0.3, 0.2);
  test::distortInterior(mesh, 0.4, 0.3, 11);
  validateMesh(mesh);
  const PlaneMatrix c = orthotropicStiffness({1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4},
                                             PlaneAnalysis::PlaneStress, 0.35);
  LinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), {c}, 1.0);
  auto exact = [](double x, double y) {
    return std::array<double, 2>{1e-3 + 2e-3 * x - 1e-3 * y, -2e-3 + 5e-4 * x + 3e-3 * y};
  };
  for (const char *side : {"left", "right", "bottom", "top"})
    for (LocalIndex n : mesh.nodesOf(side)) {
      const auto u = exact(mesh.x(n), mesh.y(n));
      model.prescribe(n, 0, u[0]);
      model.prescribe(n, 1, u[1]);
    }
  LinearSolverOptions o;
  o.type = solver;
  o.tolerance = 1e-13;
  model.setup(o, MPI_COMM_WORLD);
  ASSERT_TRUE(model.solve(1.0).converged);
  const auto u = model.displacementHost();
  int interior = 0;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
    const auto ue = exact(mesh.x(n), mesh.y(n));
    EXPECT_NEAR(u[2 * n], ue[0], 1e-11) << "node " << n;
    EXPECT_NEAR(u[2 * n + 1], ue[1], 1e-11) << "node " << n;
    interior += mesh.x(n) > -0.29 && mesh.x(n) < 1.69 && mesh.y(n) > 0.21 && mesh.y(n) < 1.69;
  }
  EXPECT_GT(interior, 5); // the test has free interior nodes to get right
  // Constant stress C eps with eps = (2e-3, 3e-3, -1e-3 + 5e-4).
  const double eps[3] = {2e-3, 3e-3, -5e-4};
  double sig[3];
  applyStiffness(c, eps, sig);
  const auto s = model.nodalStressHost();
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    for (int k = 0; k < 3; ++k)
      ASSERT_NEAR(s[3 * n + k], sig[k], 1e-8 * std::abs(sig[0])) << "node " << n;
  // No spurious reactions at interior nodes.
  const auto r = model.reactionHost(1.0);
  std::vector<int> onBoundary(mesh.numNodes(), 0);
  for (const char *side : {"left", "right", "bottom", "top"})
    for (LocalIndex n : mesh.nodesOf(side))
      onBoundary[n] = 1;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    if (!onBoundary[n]) {
      EXPECT_NEAR(std::hypot(r[2 * n], r[2 * n + 1]), 0.0, 1e-6 * std::abs(sig[0]));
    }
}
