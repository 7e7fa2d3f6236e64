// The mixed model's solver paths agree: the direct saddle-point solve (sparse LU of the full
// [K11 + a Kd, (1-a) K12; (1-a) K12^T, -(1-a) M] system), the Schur-complement Krylov solves
// with BoomerAMG (assembled lumped S_a; matrix-free consistent S_a with inner CG on M) and the
// block-triangular preconditioned GMRES on the whole saddle point, for a = 0 and a > 0, with and
// without a prestress, on an orthotropic plate with a hole. With a compressive prestress beyond
// buckling (K11 makes S indefinite), the GMRES solves still reproduce the direct solution. The
// block-triangular method's iterations stay within a bound the Schur method also meets.
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

Solution solvePlate(ElementType type, const MixedOptions &o, bool prestress = false) {
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
  if (prestress) { // a smooth, non-uniform field of mixed sign (K11 != 0, S stays definite)
    std::vector<double> tau(3 * mesh.numNodes());
    for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
      tau[3 * n] = 2.0e3 * std::cos(0.7 * mesh.x(n)) - 500.0;
      tau[3 * n + 1] = 1.0e3 * std::sin(0.5 * mesh.y(n));
      tau[3 * n + 2] = 300.0 * mesh.x(n) * mesh.y(n) / 16.0;
    }
    model.setInitialStress(tau);
  }
  model.setup(o, MPI_COMM_WORLD);
  return test::solveMixed(model);
}

} // namespace

class MixedSolverTest : public ::testing::TestWithParam<ElementType> {};
INSTANTIATE_TEST_SUITE_P(Elements, MixedSolverTest, test::bothElements(), test::elementName);

TEST_P(MixedSolverTest, DirectSaddlePointEqualsSchurAmgPaths) {
  struct Iterative {
    MixedLinearMethod method;
    KrylovMethod krylov;
    const char *name;
  };
  const Iterative paths[] = {
      {MixedLinearMethod::Schur, KrylovMethod::Cg, "Schur CG"},
      {MixedLinearMethod::Schur, KrylovMethod::Gmres, "Schur GMRES"},
      {MixedLinearMethod::BlockTriangular, KrylovMethod::Cg, "block-triangular"}};
  for (auto compliance : {ComplianceMass::Consistent, ComplianceMass::Lumped}) {
    if (compliance == ComplianceMass::Lumped && massLumping(GetParam()) != MassLumping::RowSum)
      continue; // refused for Quad8 (test_mixed_kernels)
    for (double a : {0.0, 0.05}) {
      for (bool prestress : {false, true}) {
        MixedOptions o;
        o.compliance = compliance;
        o.stabilization = a;
        o.linear.type = LinearSolverType::Direct;
        const Solution direct = solvePlate(GetParam(), o, prestress);
        ASSERT_TRUE(direct.stats.converged);
        for (const Iterative &path : paths) {
          if (prestress && path.method == MixedLinearMethod::Schur &&
              path.krylov == KrylovMethod::Cg)
            continue; // K11: S is not SPD, GMRES below
          o.linear.type = LinearSolverType::Amg;
          o.linear.tolerance = 1e-12;
          o.innerTolerance = 1e-13;
          o.method = path.method;
          o.krylov = path.krylov;
          const Solution amg = solvePlate(GetParam(), o, prestress);
          const std::string what =
              std::string(compliance == ComplianceMass::Lumped ? "lumped" : "consistent") +
              " a=" + std::to_string(a) + (prestress ? " prestressed " : " ") + path.name;
          ASSERT_TRUE(amg.stats.converged) << what << " residual " << amg.stats.relativeResidual;
          EXPECT_GT(amg.stats.iterations, 1) << what;
          EXPECT_LT(maxRelativeDifference(amg.u, direct.u), 1e-8) << what;
          EXPECT_LT(maxRelativeDifference(amg.s, direct.s), 1e-8) << what;
        }
      }
    }
  }
}

// A broken block-triangular preconditioner (a wrong stress-row scale, S~ or M~ off, C missing)
// takes hundreds of iterations or does not converge; working, it needs about the Schur method's
// count (measured on this strip to 1e-8, block-triangular against Schur: Quad4 at ny = 16 51
// against 44 (a = 0.05) and 90 against 83 (a = 0.01); Quad8 at ny = 8 55 against 49 and 97
// against 86).
TEST_P(MixedSolverTest, BlockTriangularIterationsStayNearTheSchurMethods) {
  for (double a : {0.05, 0.01}) {
    MixedOptions o;
    o.stabilization = a;
    o.linear.tolerance = 1e-8;
    o.method = MixedLinearMethod::Schur;
    const int ny = GetParam() == ElementType::Quad8 ? 8 : 16;
    const test::StripSolve schurRun = test::solveShearedStrip(GetParam(), ny, o);
    o.method = MixedLinearMethod::BlockTriangular;
    const test::StripSolve blockRun = test::solveShearedStrip(GetParam(), ny, o);
    const LinearSolveStats &schur = schurRun.stats, &block = blockRun.stats;
    const std::string &schurName = schurRun.solverName, &blockName = blockRun.solverName;
    const long inner = blockRun.innerIterations;
    ASSERT_TRUE(schur.converged);
    ASSERT_TRUE(block.converged) << block.relativeResidual;
    EXPECT_NE(schurName.find("flexible CG on matrix-free S_a"), std::string::npos) << schurName;
    EXPECT_NE(blockName.find("block-triangular"), std::string::npos) << blockName;
    const int bound = a == 0.05 ? 70 : 140; // both methods meet it
    EXPECT_LE(schur.iterations, bound) << "a = " << a;
    EXPECT_LE(block.iterations, bound) << "a = " << a;
    EXPECT_LE(block.iterations, 1.3 * schur.iterations) << "a = " << a;
    // The loose CG on M inside the preconditioner: a few iterations per application.
    EXPECT_LE(inner, 12L * block.iterations) << "a = " << a;
  }
}

TEST(MixedLinearMethod, AutoIsBlockTriangularForConsistentAndSchurForLumpedM) {
  EXPECT_EQ(resolveLinearMethod(MixedLinearMethod::Auto, ComplianceMass::Consistent),
            MixedLinearMethod::BlockTriangular);
  EXPECT_EQ(resolveLinearMethod(MixedLinearMethod::Auto, ComplianceMass::Lumped),
            MixedLinearMethod::Schur);
  EXPECT_EQ(resolveLinearMethod(MixedLinearMethod::Schur, ComplianceMass::Consistent),
            MixedLinearMethod::Schur);
  EXPECT_EQ(resolveLinearMethod(MixedLinearMethod::BlockTriangular, ComplianceMass::Lumped),
            MixedLinearMethod::BlockTriangular);
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
  auto solve = [&](LinearSolverType type, MixedLinearMethod method, ComplianceMass m,
                   double *rayleigh) {
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
    o.krylov = KrylovMethod::Gmres;
    o.method = method;
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
    const auto direct = solve(LinearSolverType::Direct, MixedLinearMethod::Auto, m, &rayleigh);
    EXPECT_LT(rayleigh, 0.0) << "the prestress should make S indefinite";
    ASSERT_TRUE(direct.first.converged);
    for (auto method : {MixedLinearMethod::Schur, MixedLinearMethod::BlockTriangular}) {
      const auto gmres = solve(LinearSolverType::Amg, method, m, nullptr);
      ASSERT_TRUE(gmres.first.converged) << gmres.first.relativeResidual;
      EXPECT_LT(maxRelativeDifference(gmres.second, direct.second), 1e-8);
    }
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
