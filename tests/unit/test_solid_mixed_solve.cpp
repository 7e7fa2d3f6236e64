// The block-triangular AMG solve of the 3D mixed models (solver: amg, solver/SolidMixedSolve.hpp)
// against their direct solve (sparse LU of the same operator or Jacobian), issue 17:
//  - linear model (SolidMixedModel), distorted-box patch test with the rotated orthotropic
//    solid: the AMG solve reproduces the linear field and the exact constant nodal stresses;
//  - linear model, a 10 x 1 x 1 cantilever under a tip shear (Hex8 and Hex20, a = 0 and 0.05):
//    displacements and stresses equal to the direct solve's to 1e-6 of their largest value, in a
//    bounded number of GMRES iterations;
//  - geometrically nonlinear model (SolidNonlinearMixedModel: current form on Hex8 and Hex20,
//    incremental form on Hex8), the same cantilever to a tip deflection of about a fifth of its
//    length in three load steps: the same states as with the direct solver, step by step;
//  - the same three runs with the Jacobian applied matrix-free (SolidMixedMatrixFree), and its
//    products (J v, C v, M z, M's nodal blocks) against the assembled Jacobian's;
//  - both models fall back to the direct LU, reported, where the iterative solve fails, and keep
//    it for the later solves;
//  - the CG on M's preconditioner (invertStressBlocks, applyStressBlocks) against Eigen's inverses
//    of the nodal 6 x 6 blocks, with the Jacobi fall back of a singular block.
#include <mesh/Generators.hpp>
#include <solver/Nonlinear.hpp>
#include <solver/SolidMixedModel.hpp>
#include <solver/SolidMixedSolve.hpp>
#include <support/Differences.hpp>
#include <support/KernelFixture.hpp>
#include <support/ModelDifferences.hpp>
#include <support/SolidMesh.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

using namespace mixcon;
using mixcon::test::denseToCsr;
using mixcon::test::distortedBox;
using mixcon::test::hostVector;
using mixcon::test::maxRelativeDifference;
using mixcon::test::randomVector;
using mixcon::test::rotatedOrthotropicSolid;

namespace {

double maxAbs(const std::vector<double> &v) {
  double m = 0.0;
  for (double x : v)
    m = std::max(m, std::abs(x));
  return m;
}

LinearSolverOptions solverOptions(LinearSolverType type) {
  LinearSolverOptions o;
  o.type = type;
  o.tolerance = 1e-10;
  o.directFallbackUnknowns = 0; // a failing iterative solve must fail the test
  return o;
}

/// The cantilever 10 x 1 x 1 (n x 1 x 1 elements along x, 2 through the section), clamped at
/// x = 0, isotropic E = 1e3, nu = 0.3, a shear traction q on its end face.
Mesh cantileverMesh(ElementType type) { return boxMesh(10.0, 1.0, 1.0, 10, 2, 2, type); }

template <class Model> void loadCantilever(const Mesh &mesh, Model &model, double q) {
  for (LocalIndex n : mesh.nodesOf("xmin"))
    for (int i = 0; i < 3; ++i)
      model.prescribe(n, i, 0.0);
  model.addSideLoad(mesh.boundaries.at("xmax"), {0.0, 0.0, -q}, 0.0);
}

const std::vector<SolidMatrix> kIsotropic{IsotropicMaterial{1e3, 0.3}.stiffness()};

} // namespace

// The nodal 6 x 6 block inverses of a 4-node stress matrix (6 per node) with coupled off-diagonal
// blocks (which the preconditioner ignores): the SPD blocks' inverses are Eigen's to 1e-12, the
// singular block of node 2 (rank 5, its diagonal non-zero) falls back to the inverse of its
// diagonal, and applyStressBlocks multiplies block by block.
TEST(SolidMixedSolve, StressBlockInversesAreTheNodalBlocksInverses) {
  constexpr int kNodes = 4;
  const Eigen::MatrixXd r = Eigen::MatrixXd::Random(6 * kNodes, 6 * kNodes);
  Eigen::MatrixXd m = r * r.transpose() + 6.0 * Eigen::MatrixXd::Identity(6 * kNodes, 6 * kNodes);
  // Node 2's block made singular: its last row and column repeat the fifth.
  m.row(12 + 5) = m.row(12 + 4);
  m.col(12 + 5) = m.col(12 + 4);
  const Eigen::MatrixXd block2 = m.block<6, 6>(12, 12);
  ASSERT_LT(std::abs(block2.determinant()), 1e-9 * block2.norm());
  const CsrMatrix<DeviceSpace> csr = denseToCsr(m);
  Kokkos::View<SolidMatrix *, DeviceSpace> inverse("inverse", kNodes);
  invertStressBlocks(csr, inverse);
  const Eigen::VectorXd a = randomVector(6 * kNodes, 3);
  Kokkos::View<double *, DeviceSpace> ad("a", 6 * kNodes), yd("y", 6 * kNodes);
  auto ah = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ad);
  for (int i = 0; i < 6 * kNodes; ++i)
    ah(i) = a(i);
  Kokkos::deep_copy(ad, ah);
  applyStressBlocks(inverse, ad, yd);
  const Eigen::VectorXd y = hostVector(yd);
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), inverse);
  for (int p = 0; p < kNodes; ++p) {
    const Eigen::Matrix<double, 6, 6> b = m.block<6, 6>(6 * p, 6 * p);
    const Eigen::Matrix<double, 6, 6> expect =
        p == 2 ? Eigen::Matrix<double, 6, 6>(b.diagonal().cwiseInverse().asDiagonal())
               : Eigen::Matrix<double, 6, 6>(b.inverse());
    Eigen::Matrix<double, 6, 6> got;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        got(i, j) = h(p).m[i][j];
    EXPECT_LT((got - expect).norm(), 1e-12 * expect.norm()) << "node " << p;
    EXPECT_LT((y.segment<6>(6 * p) - expect * a.segment<6>(6 * p)).norm(),
              1e-12 * (expect * a.segment<6>(6 * p)).norm())
        << "node " << p;
  }
}

TEST(SolidMixedSolve, PatchTestWithTheAmgSolve) {
  for (ElementType type :
       {ElementType::Hex8, ElementType::Hex20, ElementType::Tet4, ElementType::Tet10}) {
    const Mesh mesh = distortedBox(3, type);
    const SolidMatrix c = rotatedOrthotropicSolid();
    SolidMixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), {c}, 0.05);
    const Vector<6> strain{{2e-3, 1.1e-3, 1.3e-3, 0.5e-3, 0.1e-3, -0.2e-3}};
    const auto field = [](double x, double y, double z) {
      return std::array<double, 3>{1e-3 * (2.0 * x - 0.5 * y + 0.7 * z),
                                   1e-3 * (0.3 * x + 1.1 * y - 0.4 * z),
                                   1e-3 * (-0.6 * x + 0.9 * y + 1.3 * z)};
    };
    for (const char *face : {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"})
      for (LocalIndex p : mesh.nodesOf(face)) {
        const auto ue = field(mesh.x(p), mesh.y(p), mesh.z(p));
        for (int i = 0; i < 3; ++i)
          model.prescribe(p, i, ue[i]);
      }
    model.setup(solverOptions(LinearSolverType::Amg), MPI_COMM_WORLD);
    const LinearSolveStats s = model.solve(1.0);
    ASSERT_TRUE(s.converged) << elementTypeName(type);
    const auto u = model.displacementHost();
    for (LocalIndex p = 0; p < mesh.numNodes(); ++p) {
      const auto ue = field(mesh.x(p), mesh.y(p), mesh.z(p));
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(u[3 * p + i], ue[i], 1e-10) << elementTypeName(type) << " node " << p;
    }
    const Vector<6> sigma = matvec(c, strain);
    const auto st = model.nodalStressHost();
    for (LocalIndex p = 0; p < mesh.numNodes(); ++p)
      for (int k = 0; k < 6; ++k)
        ASSERT_NEAR(st[6 * p + k], sigma.v[k], 1e-7 * std::abs(sigma.v[0]))
            << elementTypeName(type) << " node " << p;
  }
}

TEST(SolidMixedSolve, LinearCantileverAsTheDirectSolve) {
  for (ElementType type : {ElementType::Hex8, ElementType::Hex20})
    for (double a : {0.0, 0.05}) {
      const Mesh mesh = cantileverMesh(type);
      // 0: direct, 1: AMG on the assembled operator, 2: AMG with the operator matrix-free.
      std::vector<double> u[3], s[3], r[3];
      int iterations[3] = {};
      for (int k = 0; k < 3; ++k) {
        SolidMixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), kIsotropic, a);
        loadCantilever(mesh, model, 1.0);
        model.setIterativeSolver(1e-2, kSolidMixedRestart,
                                 k == 2 ? JacobianForm::MatrixFree : JacobianForm::Assembled);
        model.setup(solverOptions(k == 0 ? LinearSolverType::Direct : LinearSolverType::Amg),
                    MPI_COMM_WORLD);
        ASSERT_EQ(model.matrixFree(), k == 2);
        const LinearSolveStats st = model.solve(1.0);
        ASSERT_TRUE(st.converged) << elementTypeName(type) << " a = " << a;
        iterations[k] = st.iterations;
        u[k] = model.displacementHost();
        s[k] = model.nodalStressHost();
        r[k] = model.reactionHost(1.0);
      }
      std::printf("  %s a = %.2f: %d GMRES iterations (assembled), %d (matrix-free)\n",
                  elementTypeName(type).c_str(), a, iterations[1], iterations[2]);
      for (int k = 1; k < 3; ++k) {
        EXPECT_LT(maxRelativeDifference(u[k], u[0]), 1e-6) << elementTypeName(type) << " a = " << a;
        EXPECT_LT(maxRelativeDifference(s[k], s[0]), 1e-6) << elementTypeName(type) << " a = " << a;
        EXPECT_LT(maxRelativeDifference(r[k], r[0]), 1e-6) << elementTypeName(type) << " a = " << a;
        // Measured 48-94 (Debian's sequential hypre) and 52-173 (threaded hypre 2.26).
        EXPECT_LE(iterations[k], 300) << elementTypeName(type) << " a = " << a;
      }
      // The same operator, the same preconditioner: the iterations agree but for rounding (and
      // the threaded BoomerAMG's run-to-run differences: 173 and 176 measured for Hex20, a = 0).
      EXPECT_LE(std::abs(iterations[2] - iterations[1]), 2 + iterations[1] / 10)
          << elementTypeName(type) << " a = " << a;
    }
}

TEST(SolidMixedSolve, NonlinearCantileverAsTheDirectSolve) {
  // The current form on both hexahedra, the incremental form (on c1 with the prestress) on Hex8.
  for (const auto &[type, form] : {std::pair{ElementType::Hex8, MixedForm::Current},
                                   std::pair{ElementType::Hex20, MixedForm::Current},
                                   std::pair{ElementType::Hex8, MixedForm::Incremental}}) {
    SCOPED_TRACE(form == MixedForm::Current ? "current form" : "incremental form");
    const Mesh mesh = cantileverMesh(type);
    // 0: direct, 1: AMG on the assembled Jacobian, 2: AMG with the Jacobian matrix-free.
    std::vector<double> u[3][3], s[3][3];
    for (int k = 0; k < 3; ++k) {
      SolidNonlinearMixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), kIsotropic,
                                     0.05);
      model.setForm(form);
      loadCantilever(mesh, model, 0.5); // linear theory: tip deflection 2 (a fifth of L) at 1
      MixedNewtonSolverOptions mo;
      mo.restart = kSolidMixedRestart;
      mo.jacobian = k == 2 ? JacobianForm::MatrixFree : JacobianForm::Assembled;
      model.setIterativeSolver(mo);
      model.setup(solverOptions(k == 0 ? LinearSolverType::Direct : LinearSolverType::Amg),
                  MPI_COMM_WORLD);
      ASSERT_EQ(model.matrixFree(), k == 2);
      if (k == 2) {
        EXPECT_NE(model.solverName().find("matrix-free"), std::string::npos) << model.solverName();
      }
      LoadStepper stepper(model, NonlinearOptions{});
      for (int step = 0; step < 3; ++step) {
        const IncrementOutcome o = stepper.advance((step + 1) / 3.0);
        ASSERT_TRUE(o.converged) << elementTypeName(type) << " solver " << k << ": " << o.message;
        u[k][step] = model.displacementHost();
        s[k][step] = model.nodalStressHost();
        if (k > 0)
          std::printf("  %s step %d (%s): %d Newton iterations, %d GMRES iterations\n",
                      elementTypeName(type).c_str(), step + 1, k == 1 ? "assembled" : "matrix-free",
                      o.iterations, o.linearIterations);
      }
    }
    EXPECT_GT(maxAbs(u[0][2]), 1.0) << "a large deflection";
    for (int k = 1; k < 3; ++k)
      for (int step = 0; step < 3; ++step) {
        EXPECT_LT(maxRelativeDifference(u[k][step], u[0][step]), 1e-6) << "step " << step + 1;
        EXPECT_LT(maxRelativeDifference(s[k][step], s[0][step]), 1e-6) << "step " << step + 1;
      }
  }
}

// Where the block-triangular solve does not converge (here: a limit of 2 GMRES iterations), both
// 3D mixed models fall back to the direct LU and say so, unless the fall back is off.
TEST(SolidMixedSolve, FailingIterativeSolveFallsBackToTheDirectLu) {
  const Mesh mesh = boxMesh(4.0, 1.0, 1.0, 4, 1, 1, ElementType::Hex8);
  for (bool allowed : {true, false}) {
    LinearSolverOptions o = solverOptions(LinearSolverType::Amg);
    o.maxIterations = 2;
    o.directFallbackUnknowns = allowed ? 200000 : 0;
    SolidMixedModel linear(mesh, std::vector<int>(mesh.numElements(), 0), kIsotropic, 0.05);
    loadCantilever(mesh, linear, 1.0);
    linear.setup(o, MPI_COMM_WORLD);
    const LinearSolveStats s = linear.solve(1.0);
    EXPECT_EQ(s.converged, allowed);
    EXPECT_EQ(s.note.find("falling back to the direct LU") != std::string::npos, allowed) << s.note;
    if (allowed) { // the LU stays: the next solve has no GMRES iterations and nothing to report
      const LinearSolveStats again = linear.solve(0.5);
      EXPECT_TRUE(again.converged);
      EXPECT_TRUE(again.note.empty()) << again.note;
      EXPECT_NE(linear.solverName().find("LU"), std::string::npos) << linear.solverName();
    }
    SolidNonlinearMixedModel nonlinear(mesh, std::vector<int>(mesh.numElements(), 0), kIsotropic,
                                       0.05);
    loadCantilever(mesh, nonlinear, 1.0);
    nonlinear.setup(o, MPI_COMM_WORLD);
    nonlinear.evaluate(1.0, true);
    double increment = 0.0;
    const LinearSolveStats n = nonlinear.correct(1.0, increment);
    EXPECT_EQ(n.converged, allowed);
    EXPECT_EQ(n.note.find("falling back to the direct LU") != std::string::npos, allowed) << n.note;
    if (allowed) {
      nonlinear.evaluate(1.0, true);
      const LinearSolveStats again = nonlinear.correct(1.0, increment);
      EXPECT_TRUE(again.converged);
      EXPECT_TRUE(again.note.empty()) << again.note;
      EXPECT_NE(nonlinear.solverName().find("LU"), std::string::npos) << nonlinear.solverName();
    }
  }
}

namespace {
using Exec = Kokkos::DefaultExecutionSpace;

/// J of SolidMixedKernel with `law` at state x (zero prestress), assembled by the generic element
/// driver (what the models assemble, itself checked against finite differences in
/// test_nonlinear_3d.cpp).
template <class Law>
CsrMatrix<DeviceSpace> assembledJacobian(const Mesh &mesh, const ElementData<DeviceSpace, 3> &d,
                                         const Law &law,
                                         const Kokkos::View<const double *, DeviceSpace> &x,
                                         Kokkos::View<const double *, DeviceSpace> tau = {}) {
  const NodeGraph graph = buildNodeGraph(mesh);
  const auto map = elementScatterMap<DeviceSpace>(mesh, graph);
  CsrMatrix<DeviceSpace> j = expandGraph<DeviceSpace>(graph, 9);
  Kokkos::View<double *, DeviceSpace> g("g", 9 * mesh.numNodes());
  if (tau.extent(0) == 0)
    tau = Kokkos::View<double *, DeviceSpace>("tau", 6 * mesh.numNodes());
  dispatchSolidElement(mesh.elementType, "test", [&](auto elem) {
    using Elem = decltype(elem);
    assembleNonlinearRows<9, Elem>(
        Exec(), d.mesh, SolidMixedKernel<Elem, DeviceSpace, Law>{d.mesh, law, x, tau}, map, j, g);
  });
  return j;
}

Kokkos::View<const double *, DeviceSpace> deviceCopy(const Eigen::VectorXd &v) {
  Kokkos::View<double *, DeviceSpace> d("v", v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (Eigen::Index i = 0; i < v.size(); ++i)
    h(i) = v(i);
  Kokkos::deep_copy(d, h);
  return d;
}

/// v restricted to `width` of every 9 unknowns from `offset` (a node's displacements or stresses).
Eigen::VectorXd part(const Eigen::VectorXd &v, int offset, int width) {
  Eigen::VectorXd p(v.size() / 9 * width);
  for (Eigen::Index n = 0; n < v.size() / 9; ++n)
    p.segment(width * n, width) = v.segment(9 * n + offset, width);
  return p;
}
} // namespace

// The matrix-free products of SolidMixedMatrixFree against the assembled Jacobian of the same
// state (a distorted box, the rotated orthotropic solid, all four solids, a = 0 and 0.05): the
// current law at a finite strain with a 0.3 rad rotation and non-zero stresses (the nonlinear
// model), the incremental law at x = 0 (the linear model's operator) and at the same finite
// strain with a prestress (the nonlinear model's incremental form). J v, C v (the stress
// rows of J [v; 0]), M z (minus the stress rows of J [0; z]) and M's nodal 6 x 6 blocks, to 1e-12
// of their size.
TEST(SolidMixedMatrixFree, ProductsAreThoseOfTheAssembledJacobian) {
  for (ElementType type :
       {ElementType::Hex8, ElementType::Hex20, ElementType::Tet4, ElementType::Tet10})
    for (double a : {0.0, 0.05})
      for (int form = 0; form < 3; ++form) { // current, linear, incremental with a prestress
        const bool current = form == 0, prestressed = form == 2;
        const std::string what = elementTypeName(type) +
                                 (current       ? " current"
                                  : prestressed ? " incremental"
                                                : " linear") +
                                 " a = " + std::to_string(a);
        const Mesh mesh = distortedBox(2, type);
        const LocalIndex nn = mesh.numNodes();
        const SolidMatrix c = rotatedOrthotropicSolid();
        ElementData<DeviceSpace, 3> d;
        d.mesh = toDevice<DeviceSpace, 3>(mesh);
        d.material = Kokkos::View<int *, DeviceSpace>("material", mesh.numElements());
        d.stiffness = detail::deviceMatrices({c}, "stiffness");
        const auto compliance = detail::deviceMatrices(detail::solidCompliances({c}), "compliance");
        // The state: a rotation of 0.3 rad about z with a 5 % stretch in x, and stresses of the
        // size of the material's stiffness times 1e-2 (current law and prestressed incremental
        // law, whose prestress is of the same size); zero (the linear operator).
        Eigen::VectorXd x = Eigen::VectorXd::Zero(9 * nn);
        const Eigen::VectorXd tau =
            prestressed ? Eigen::VectorXd(1e-2 * c.m[0][0] * randomVector(6 * nn, 12))
                        : Eigen::VectorXd::Zero(6 * nn);
        if (current || prestressed) {
          const double ct = std::cos(0.3), st = std::sin(0.3);
          const Eigen::VectorXd s = 1e-2 * c.m[0][0] * randomVector(9 * nn, 11);
          for (LocalIndex p = 0; p < nn; ++p) {
            const double X = 1.05 * mesh.x(p), Y = mesh.y(p), Z = mesh.z(p);
            x(9 * p + 0) = ct * X - st * Y - mesh.x(p);
            x(9 * p + 1) = st * X + ct * Y - mesh.y(p);
            x(9 * p + 2) = 0.02 * Y + 0.01 * Z * Z;
            x.segment<6>(9 * p + 3) = s.segment<6>(9 * p + 3);
          }
        }
        const auto xd = deviceCopy(x);
        const CsrMatrix<DeviceSpace> j =
            current
                ? assembledJacobian(
                      mesh, d,
                      MixedCurrentLaw<DeviceSpace, 3>{d.material, d.stiffness, compliance, a}, xd)
                : assembledJacobian(
                      mesh, d,
                      MixedIncrementLaw<DeviceSpace, 3>{d.material, d.stiffness, compliance, a}, xd,
                      deviceCopy(tau));
        SolidMixedMatrixFree mf(mesh, d, compliance, a, current,
                                prestressed ? deviceCopy(tau)
                                            : Kokkos::View<const double *, DeviceSpace>());
        mf.update(xd);
        const Eigen::VectorXd v = randomVector(9 * nn, 5);
        Kokkos::View<double *, DeviceSpace> y("y", 9 * nn);
        multiply(Exec(), j, deviceCopy(v), y);
        const Eigen::VectorXd jv = hostVector(y);
        mf.applyJacobian(deviceCopy(v), y);
        EXPECT_LT((hostVector(y) - jv).norm(), 1e-12 * jv.norm()) << what;
        // C v3 and M z against the stress rows of J [v3; 0] and J [0; z].
        Eigen::VectorXd vu = v, vs = v;
        for (LocalIndex p = 0; p < nn; ++p) {
          vu.segment<6>(9 * p + 3).setZero();
          vs.segment<3>(9 * p).setZero();
        }
        multiply(Exec(), j, deviceCopy(vu), y);
        const Eigen::VectorXd cv = part(hostVector(y), 3, 6);
        multiply(Exec(), j, deviceCopy(vs), y);
        const Eigen::VectorXd mz = -part(hostVector(y), 3, 6);
        ASSERT_GT(mz.norm(), 0.0) << what;
        ASSERT_GT(cv.norm(), 0.0) << what;
        Kokkos::View<double *, DeviceSpace> w("w", 6 * nn);
        mf.applyCoupling(deviceCopy(part(v, 0, 3)), w);
        EXPECT_LT((hostVector(w) - cv).norm(), 1e-12 * cv.norm()) << what;
        mf.applyStressBlock(deviceCopy(part(v, 3, 6)), w);
        EXPECT_LT((hostVector(w) - mz).norm(), 1e-12 * mz.norm()) << what;
        // M's nodal blocks: minus J's (stress, stress) diagonal blocks.
        const auto rows = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), j.rowOffsets);
        const auto cols = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), j.columns);
        const auto vals = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), j.values);
        const auto blocks =
            Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mf.operators().stressBlocks);
        double worst = 0.0, size = 0.0;
        for (LocalIndex p = 0; p < nn; ++p)
          for (int r = 0; r < 6; ++r)
            for (Offset k = rows(9 * p + 3 + r); k < rows(9 * p + 4 + r); ++k)
              if (cols(k) / 9 == p && cols(k) % 9 >= 3) {
                worst = std::max(worst, std::abs(blocks(p).m[r][cols(k) % 9 - 3] + vals(k)));
                size = std::max(size, std::abs(vals(k)));
              }
        EXPECT_GT(size, 0.0) << what;
        EXPECT_LT(worst, 1e-12 * size) << what;
      }
}

// jacobian: auto (JacobianForm::Automatic, the default): the 3D mixed models apply their Jacobian
// without its matrix above kSolidMixedDirectFallback unknowns with solver: amg
// (docs/performance.md: the same iterations, 2.5-3.2x less memory, the same or less time at 1e6
// unknowns), and keep it assembled below (where the direct LU is the fall back), where asked for,
// and (the nonlinear model) under follower pressures. (The direct solver factors the assembled J:
// the models take the matrix-free form with solver: amg only.) Setups only: the matrix-free
// solves are checked against the assembled ones above.
TEST(SolidMixedSolve, AutomaticJacobianIsMatrixFreeAboveTheDirectFallbackBound) {
  const Mesh small = cantileverMesh(ElementType::Hex8);
  const Mesh large = boxMesh(10.0, 1.0, 1.0, 62, 9, 9, ElementType::Hex8); // 6,300 nodes
  ASSERT_LE(9L * small.numNodes(), kSolidMixedDirectFallback);
  ASSERT_GT(9L * large.numNodes(), kSolidMixedDirectFallback);
  struct Case {
    const Mesh *mesh;
    JacobianForm form;
    bool follower, matrixFree;
  };
  for (const Case &c : {Case{&small, JacobianForm::Automatic, false, false},
                        Case{&large, JacobianForm::Automatic, false, true},
                        Case{&large, JacobianForm::Assembled, false, false},
                        Case{&small, JacobianForm::MatrixFree, false, true},
                        Case{&large, JacobianForm::Automatic, true, false}}) {
    const std::string what = std::to_string(c.mesh->numNodes()) + " nodes, form " +
                             std::to_string(static_cast<int>(c.form)) + ", follower " +
                             std::to_string(c.follower);
    const std::vector<int> material(c.mesh->numElements(), 0);
    if (!c.follower) { // the linear model
      SolidMixedModel model(*c.mesh, material, kIsotropic, 0.05);
      loadCantilever(*c.mesh, model, 1.0);
      model.setIterativeSolver(1e-2, kSolidMixedRestart, c.form);
      model.setup(solverOptions(LinearSolverType::Amg), MPI_COMM_WORLD);
      EXPECT_EQ(model.matrixFree(), c.matrixFree) << "linear, " << what;
    }
    SolidNonlinearMixedModel model(*c.mesh, material, kIsotropic, 0.05);
    for (LocalIndex n : c.mesh->nodesOf("xmin"))
      for (int i = 0; i < 3; ++i)
        model.prescribe(n, i, 0.0);
    if (c.follower)
      model.addFollowerPressure(c.mesh->boundaries.at("xmax"), 1.0);
    else
      model.addSideLoad(c.mesh->boundaries.at("xmax"), {0.0, 0.0, -1.0}, 0.0);
    MixedNewtonSolverOptions mo;
    mo.restart = kSolidMixedRestart;
    mo.jacobian = c.form;
    model.setIterativeSolver(mo);
    model.setup(solverOptions(LinearSolverType::Amg), MPI_COMM_WORLD);
    EXPECT_EQ(model.matrixFree(), c.matrixFree) << "nonlinear, " << what;
  }
}
