// The mixed model's solver paths agree: the direct saddle-point solve (sparse LU of the full
// [K11 + a Kd, (1-a) K12; (1-a) K12^T, -(1-a) M] system) and the Schur-complement Krylov solves
// with BoomerAMG (assembled lumped S_a; matrix-free consistent S_a with inner CG on M), for a = 0
// and a > 0, on an orthotropic plate with a hole. With a compressive prestress beyond buckling
// (K11 makes S indefinite), flexible GMRES still reproduces the direct solution.
#include <mesh/Generators.hpp>
#include <solver/MixedModel.hpp>
#include <solver/Rules.hpp>

#include <support/MixedSolution.hpp>
#include <support/Params.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace mixcon;

namespace {

using test::maxRelativeDifference;
using Solution = test::MixedSolution;

Solution solvePlate(ElementType type, const MixedOptions &o) {
  const Mesh mesh = plateWithHoleMesh(1.0, 4.0, 4.0, 6, 5, type, 1.3);
  const PlaneMatrix c = orthotropicStiffness({1.4e5, 1.0e4, 1.0e4, 5.0e3, 0.3, 0.3, 0.4},
                                             PlaneAnalysis::PlaneStress, 0.3);
  MixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), {c}, 1.0);
  for (LocalIndex n : mesh.nodesOf("left"))
    model.prescribe(n, 0, 0.0);
  for (LocalIndex n : mesh.nodesOf("bottom"))
    model.prescribe(n, 1, 0.0);
  model.addEdgeLoad(mesh.boundaries.at("right"), 10.0, 0.0, 0.0);
  model.addEdgeLoad(mesh.boundaries.at("top"), 0.0, 0.0, 3.0);
  model.setup(o, MPI_COMM_WORLD);
  return test::solveMixed(model);
}

} // namespace

class MixedSolverTest : public ::testing::TestWithParam<ElementType> {};
INSTANTIATE_TEST_SUITE_P(Elements, MixedSolverTest, test::bothElements(), test::elementName);

TEST_P(MixedSolverTest, DirectSaddlePointEqualsSchurAmgPaths) {
  for (auto compliance : {ComplianceMass::Consistent, ComplianceMass::Lumped}) {
    if (compliance == ComplianceMass::Lumped && massLumping(GetParam()) != MassLumping::RowSum)
      continue; // refused for Quad8 (test_mixed_kernels)
    for (double a : {0.0, 0.05}) {
      MixedOptions o;
      o.compliance = compliance;
      o.stabilization = a;
      o.linear.type = LinearSolverType::Direct;
      const Solution direct = solvePlate(GetParam(), o);
      ASSERT_TRUE(direct.stats.converged);
      for (auto krylov : {KrylovMethod::Cg, KrylovMethod::Gmres}) {
        o.linear.type = LinearSolverType::Amg;
        o.linear.tolerance = 1e-12;
        o.innerTolerance = 1e-13;
        o.krylov = krylov;
        const Solution amg = solvePlate(GetParam(), o);
        const std::string what =
            std::string(compliance == ComplianceMass::Lumped ? "lumped" : "consistent") +
            " a=" + std::to_string(a) + (krylov == KrylovMethod::Cg ? " CG" : " GMRES");
        ASSERT_TRUE(amg.stats.converged) << what << " residual " << amg.stats.relativeResidual;
        EXPECT_GT(amg.stats.iterations, 1) << what;
        EXPECT_LT(maxRelativeDifference(amg.u, direct.u), 1e-8) << what;
        EXPECT_LT(maxRelativeDifference(amg.s, direct.s), 1e-8) << what;
      }
    }
  }
}

TEST_P(MixedSolverTest, ReactionsBalanceTheAppliedLoad) {
  MixedOptions o;
  o.linear.tolerance = 1e-12;
  const Solution r = solvePlate(GetParam(), o);
  ASSERT_TRUE(r.stats.converged);
  // Right edge: traction 10 over height 4 -> Fx = 40, balanced by the symmetry support on x = 0.
  // Top: pressure 3 over width 4 -> Fy = -12, balanced on y = 0.
  double rx = 0, ry = 0;
  for (std::size_t n = 0; n < r.reaction.size() / 2; ++n) {
    rx += r.reaction[2 * n];
    ry += r.reaction[2 * n + 1];
  }
  EXPECT_NEAR(rx, -40.0, 1e-8 * 40);
  EXPECT_NEAR(ry, 12.0, 1e-8 * 40);
}

TEST(MixedPrestress, GmresSolvesTheIndefiniteSchurComplement) {
  // A clamped strip 10 x 1 under an axial compressive prestress of 30x its Euler load (Quad4
  // in bending is stiff, so well beyond 1x): K11 makes
  // S indefinite (a negative Rayleigh quotient on the first buckling shape).
  const double l = 10.0, h = 1.0, e = 1.0e3, nu = 0.3;
  const Mesh mesh = rectangleMesh(l, h, 30, 3, ElementType::Quad4, 0.0, -h / 2);
  const double euler = M_PI * M_PI * e * h * h / (12.0 * 4.0 * l * l); // cantilever, stress
  std::vector<double> tau(3 * mesh.numNodes(), 0.0);
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    tau[3 * n] = -30.0 * euler;
  auto solve = [&](LinearSolverType type, KrylovMethod krylov, ComplianceMass m, double *rayleigh) {
    MixedModel model(mesh, std::vector<int>(mesh.numElements(), 0),
                     {isotropicStiffness(e, nu, PlaneAnalysis::PlaneStress)}, 1.0);
    for (LocalIndex n : mesh.nodesOf("left")) {
      model.prescribe(n, 0, 0.0);
      model.prescribe(n, 1, 0.0);
    }
    model.addEdgeLoad(mesh.boundaries.at("right"), 0.0, 0.01, 0.0);
    model.setInitialStress(tau);
    MixedOptions o;
    o.linear.type = type;
    o.linear.tolerance = 1e-11;
    o.linear.maxIterations = 3000;
    o.krylov = krylov;
    o.compliance = m;
    model.setup(o, MPI_COMM_WORLD);
    if (rayleigh) {
      Kokkos::View<double *, DeviceSpace> v("v", model.dofs().numOwned()), sv("sv", v.extent(0));
      auto hv = Kokkos::create_mirror_view(v);
      for (LocalIndex n = 0; n < mesh.numNodes(); ++n) { // beam mode: u = -y v'(x), v(x)
        const double k = M_PI / (2.0 * l);
        hv(2 * n) = -mesh.y(n) * k * std::sin(k * mesh.x(n));
        hv(2 * n + 1) = 1.0 - std::cos(k * mesh.x(n));
      }
      Kokkos::deep_copy(v, hv);
      model.applySchur(v, sv);
      *rayleigh = dot(v, sv);
    }
    const auto st = model.solve(1.0);
    return std::make_pair(st, model.displacementHost());
  };
  for (auto m : {ComplianceMass::Consistent, ComplianceMass::Lumped}) {
    double rayleigh = 0.0;
    const auto direct = solve(LinearSolverType::Direct, KrylovMethod::Gmres, m, &rayleigh);
    EXPECT_LT(rayleigh, 0.0) << "the prestress should make S indefinite";
    ASSERT_TRUE(direct.first.converged);
    const auto gmres = solve(LinearSolverType::Amg, KrylovMethod::Gmres, m, nullptr);
    ASSERT_TRUE(gmres.first.converged) << gmres.first.relativeResidual;
    EXPECT_LT(maxRelativeDifference(gmres.second, direct.second), 1e-8);
  }
}

// The model guards its own options for host codes that bypass the problem reader, with the rule the
// reader applies (solver/Rules.hpp): the stabilization range and lumped compliance on Quad8.
TEST(MixedModelGuards, SetupRefusesWhatTheOptionRulesRefuse) {
  const PlaneMatrix c = isotropicStiffness(1000.0, 0.3, PlaneAnalysis::PlaneStress);
  auto refusal = [&](ElementType type, const MixedOptions &o) -> std::string {
    const Mesh mesh = rectangleMesh(2.0, 1.0, 2, 1, type);
    MixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), {c}, 1.0);
    try {
      model.setup(o, MPI_COMM_WORLD);
    } catch (const InputError &e) {
      return e.what();
    }
    return "no error";
  };
  MixedOptions o;
  o.stabilization = 1.0;
  EXPECT_NE(refusal(ElementType::Quad4, o).find(*rules::stabilizationRange(1.0)), std::string::npos)
      << refusal(ElementType::Quad4, o);
  o.stabilization = 0.0;
  o.compliance = ComplianceMass::Lumped;
  const std::string lumped = refusal(ElementType::Quad8, o);
  EXPECT_EQ(lumped,
            "mixed model: " + *rules::lumpedCompliance(ComplianceMass::Lumped, ElementType::Quad8))
      << lumped;
}
