// Patch tests (Irons & Razzaque; MacNeal & Harder 1985): on distorted Quad4 and Quad8 meshes,
// prescribing a linear displacement field on the boundary must reproduce it exactly inside, with
// exactly constant stress. Reference: the linear field itself.
#include <mesh/Generators.hpp>
#include <solver/DisplacementModel.hpp>
#include <support/Patch.hpp>

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
  const test::PatchCase pc = test::makePatchCase(type);
  const Mesh &mesh = pc.mesh;
  const PlaneMatrix &c = pc.c;
  LinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), {c}, 1.0);
  const auto exact = test::PatchCase::field;
  pc.prescribeBoundary(model);
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
  const auto &sig = pc.sigma;
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
