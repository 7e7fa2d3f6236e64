// The nonlinear mixed model's matrix-free Jacobian action (kernels/MixedJacobianAction.hpp):
//  - 2D: applyMixedIncrementJacobian / applyMixedCurrentJacobian against the assembled Jacobian
//    (assembleMixedIncrement / assembleMixedCurrent) times the same direction, on distorted Quad4
//    and Quad8 meshes with random state u, S, tau and direction, a = 0 and 0.3, colored and
//    atomic scatter, repeated (the tests run with several OpenMP threads: a race shows as a
//    mismatch), to 1e-12 relative; assembleMixedStressRows (C = J_S,u, M = -J_S,S on their own)
//    against the same blocks of the assembled J;
//  - 3D: applyMixedJacobian on two distorted Hex8 elements sharing a face (a hand-made
//    MeshView<.., 3>), both forms, against mixedElement's element Jacobians assembled by hand
//    times the direction;
//  - NonlinearMixedModel with MixedNewtonSolverOptions::jacobian: Newton on a stretched
//    and sheared strip (prescribed displacements, both forms, a = 0 and 0.05) takes the same
//    iterations, residuals and GMRES iterations as the assembled Jacobian and reaches the same
//    displacements and stresses to 1e-8.
#include <kernels/MixedJacobianAction.hpp>
#include <solver/NonlinearMixedModel.hpp>
#include <support/KernelFixture.hpp>

#include <gtest/gtest.h>

#include <random>

using namespace mixcon;
using namespace mixcon::test;
using Exec = Kokkos::DefaultExecutionSpace;

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace mixed_jacobian_action_tests {

struct Setup {
  Fixture f;
  MixedElementData<Memory> d;
};

Setup makeSetup(ElementType type) {
  Setup s;
  s.f = makeFixture(type, 7, 5);
  s.d.mesh = s.f.data.mesh;
  s.d.material = s.f.data.material;
  s.d.stiffness = s.f.data.stiffness;
  s.d.thickness = s.f.data.thickness;
  s.d.compliance = Kokkos::View<PlaneMatrix *, Memory>("compliance", 2);
  auto hc = Kokkos::create_mirror_view(s.d.compliance);
  for (int m = 0; m < 2; ++m)
    invert3(s.f.materials[m], hc(m));
  Kokkos::deep_copy(s.d.compliance, hc);
  return s;
}

/// Random mixed vector with displacements of order `du` and stresses of order `ds`.
template <int Dim> Eigen::VectorXd mixedVector(int nn, unsigned seed, double du, double ds) {
  using L = FieldLayout<Dim>;
  Eigen::VectorXd x = randomVector(L::kMixedUnknowns * nn, seed);
  for (int k = 0; k < nn; ++k) {
    x.segment<Dim>(L::mixedDisplacementDof(k, 0)) *= du;
    x.segment<L::kNumStresses>(L::mixedStressDof(k, 0)) *= ds;
  }
  return x;
}

template <class Elem> void actionCase(ElementType type) {
  const Setup s = makeSetup(type);
  const int nn = s.f.mesh.numNodes();
  const Eigen::VectorXd x = mixedVector<2>(nn, 71, 0.03, 1e4);
  const Eigen::VectorXd dx = mixedVector<2>(nn, 73, 1.0, 1e5);
  const Eigen::VectorXd tau = 1e4 * randomVector(3 * nn, 75);
  const auto vx = Kokkos::View<const double *, Memory>(toView(x));
  const auto vdx = Kokkos::View<const double *, Memory>(toView(dx));
  const auto vtau = Kokkos::View<const double *, Memory>(toView(tau));
  const NodeGraph graph = buildNodeGraph(s.f.mesh);
  const auto map = elementScatterMap<Memory>(s.f.mesh, graph);
  const auto colored = mixedElementColors<Memory>(s.f.mesh, MixedScatter::Colored);
  ASSERT_EQ(colored.scatter, MixedScatter::Colored);
  ASSERT_GT(colored.numColors, 1);
  const MixedElementColors<Memory> atomic;
  for (bool incremental : {true, false})
    for (double a : {0.0, 0.3}) {
      SCOPED_TRACE(::testing::Message()
                   << Elem::kName << (incremental ? " incremental" : " current") << " a = " << a);
      CsrMatrix<Memory> jac = expandGraph<Memory>(graph, 5);
      Kokkos::View<double *, Memory> g("g", x.size());
      const LocalIndex inverted =
          incremental ? assembleMixedIncrement<Elem>(Exec(), s.d, vtau, vx, a, map, jac, g)
                      : assembleMixedCurrent<Elem>(Exec(), s.d, vx, a, map, jac, g);
      ASSERT_EQ(inverted, -1);
      const Eigen::MatrixXd dense = toDense(jac);
      const Eigen::VectorXd expected = dense * dx;
      ASSERT_GT(expected.cwiseAbs().maxCoeff(), 0.0);
      // The stress rows on their own: C = J_S,u and M = -J_S,S.
      CsrMatrix<Memory> c = expandGraph<Memory>(graph, 3, 2), m = expandGraph<Memory>(graph, 3);
      if (incremental)
        assembleMixedStressRows<Elem>(
            Exec(), s.d.mesh, s.d.thickness,
            MixedIncrementLaw<Memory>{s.d.material, s.d.stiffness, s.d.compliance, a}, vx, vtau,
            map, c, m);
      else
        assembleMixedStressRows<Elem>(
            Exec(), s.d.mesh, s.d.thickness,
            MixedCurrentLaw<Memory>{s.d.material, s.d.stiffness, s.d.compliance, a}, vx, vtau, map,
            c, m);
      Eigen::MatrixXd jc(3 * nn, 2 * nn), jm(3 * nn, 3 * nn);
      for (int p = 0; p < nn; ++p)
        for (int v = 0; v < 3; ++v) {
          for (int q = 0; q < nn; ++q) {
            for (int i = 0; i < 2; ++i)
              jc(3 * p + v, 2 * q + i) = dense(5 * p + 2 + v, 5 * q + i);
            for (int k = 0; k < 3; ++k)
              jm(3 * p + v, 3 * q + k) = -dense(5 * p + 2 + v, 5 * q + 2 + k);
          }
        }
      EXPECT_LT(relativeError(toDense(c), jc), 1e-12) << "C";
      EXPECT_LT(relativeError(toDense(m), jm), 1e-12) << "M";
      for (const auto *colors : {&colored, &atomic})
        for (int repeat = 0; repeat < 4; ++repeat) {
          Kokkos::View<double *, Memory> y("y", x.size());
          Kokkos::deep_copy(y, 1.0); // overwritten, not accumulated
          if (incremental)
            applyMixedIncrementJacobian<Elem>(Exec(), s.d, vtau, vx, a, vdx, y, *colors);
          else
            applyMixedCurrentJacobian<Elem>(Exec(), s.d, vx, a, vdx, y, *colors);
          EXPECT_LT(relativeError(toEigen(y), expected), 1e-12)
              << (colors == &colored ? "colored" : "atomic") << " repeat " << repeat;
        }
    }
}

TEST(MixedJacobianAction, Quad4EqualsAssembledJacobianTimesVector) {
  actionCase<Quad4>(ElementType::Quad4);
}
TEST(MixedJacobianAction, Quad8EqualsAssembledJacobianTimesVector) {
  actionCase<Quad8>(ElementType::Quad8);
}

// ---------------------------------------------------------------------------------------------
// 3D: two Hex8 elements sharing a face, against mixedElement's element Jacobians.

template <class Point> struct UniformLaw {
  Point point;
  KOKKOS_INLINE_FUNCTION Point at(LocalIndex) const { return point; }
};

/// Nodes on a distorted 3 x 2 x 2 grid (x fastest), elements [0, 1] x [0, 1] x [0, 1] and
/// [1, 2] x [0, 1] x [0, 1] in Hex8 order.
MeshView<Memory, 3> twoHexes() {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  MeshView<Memory, 3> m;
  m.coordinates = Kokkos::View<double *[3], Memory>("coordinates", 12);
  m.connectivity = Kokkos::View<LocalIndex **, Kokkos::LayoutRight, Memory>("connectivity", 2, 8);
  auto hc = Kokkos::create_mirror_view(m.coordinates);
  auto he = Kokkos::create_mirror_view(m.connectivity);
  const auto id = [](int i, int j, int k) { return i + 3 * j + 6 * k; };
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) {
        const int p = id(i, j, k);
        hc(p, 0) = 0.6 * i + 0.1 * j + u(rng);
        hc(p, 1) = 0.5 * j + u(rng);
        hc(p, 2) = 0.4 * k + 0.05 * i + u(rng);
      }
  for (int e = 0; e < 2; ++e) {
    const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                              {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int a = 0; a < 8; ++a)
      he(e, a) = id(e + corner[a][0], corner[a][1], corner[a][2]);
  }
  Kokkos::deep_copy(m.coordinates, hc);
  Kokkos::deep_copy(m.connectivity, he);
  return m;
}

template <class Point> void hexCase(double a) {
  using L = FieldLayout<3>;
  constexpr int nu = L::kMixedUnknowns, nd = nu * 8;
  const MeshView<Memory, 3> mesh = twoHexes();
  const OrthotropicMaterial mat{{1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.3, 0.35, 0.8e5, 0.6e5},
                                matmul(rotationAboutZ(0.7), rotationAboutX(0.4))};
  const UniformLaw<Point> law{Point{mat.stiffness(), mat.compliance(), a}};
  const int nn = 12;
  const Eigen::VectorXd x = mixedVector<3>(nn, 81, 0.03, 1e4);
  const Eigen::VectorXd dx = mixedVector<3>(nn, 83, 1.0, 1e5);
  const Eigen::VectorXd tau = 1e4 * randomVector(6 * nn, 85);
  const auto vx = Kokkos::View<const double *, Memory>(toView(x));
  const auto vdx = Kokkos::View<const double *, Memory>(toView(dx));
  const auto vtau = Kokkos::View<const double *, Memory>(toView(tau));
  Kokkos::View<double ***, Memory> ke("ke", 2, nd, nd);
  Kokkos::parallel_for(
      "mixcon::test::hexJacobians", Kokkos::RangePolicy<Exec>(0, 2), KOKKOS_LAMBDA(LocalIndex e) {
        double gl[nd], kl[nd][nd];
        mixedElement<Hex8, true>(mesh, 1.0, law, vx, vtau, e, gl, kl);
        for (int i = 0; i < nd; ++i)
          for (int j = 0; j < nd; ++j)
            ke(e, i, j) = kl[i][j];
      });
  auto hke = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
  auto hconn = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mesh.connectivity);
  Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(nu * nn, nu * nn);
  for (int e = 0; e < 2; ++e)
    for (int p = 0; p < 8; ++p)
      for (int i = 0; i < nu; ++i)
        for (int b = 0; b < 8; ++b)
          for (int j = 0; j < nu; ++j)
            jac(nu * hconn(e, p) + i, nu * hconn(e, b) + j) += hke(e, nu * p + i, nu * b + j);
  const Eigen::VectorXd expected = jac * dx;
  ASSERT_GT(expected.cwiseAbs().maxCoeff(), 0.0);
  for (int repeat = 0; repeat < 3; ++repeat) {
    Kokkos::View<double *, Memory> y("y", x.size());
    applyMixedJacobian<Hex8>(Exec(), mesh, 1.0, law, vx, vtau, vdx, y,
                             MixedElementColors<Memory>{});
    EXPECT_LT(relativeError(toEigen(y), expected), 1e-12) << "repeat " << repeat;
  }
}

TEST(MixedJacobianAction, Hex8IncrementEqualsElementJacobiansTimesVector) {
  hexCase<MixedIncrementPoint<3>>(0.0);
  hexCase<MixedIncrementPoint<3>>(0.3);
}
TEST(MixedJacobianAction, Hex8CurrentEqualsElementJacobiansTimesVector) {
  hexCase<MixedCurrentPoint<3>>(0.0);
  hexCase<MixedCurrentPoint<3>>(0.3);
}

// ---------------------------------------------------------------------------------------------
// The nonlinear mixed model with the matrix-free Jacobian against the assembled one.

struct NewtonRun {
  std::vector<double> residuals, solution;
  std::vector<int> linearIterations;
};

NewtonRun newton(const Fixture &f, MixedForm form, double a, bool matrixFree) {
  NonlinearMixedModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
  model.setForm(form);
  model.setStabilization(a);
  for (LocalIndex n : f.mesh.nodesOf("left")) {
    model.prescribe(n, 0, 0.0);
    model.prescribe(n, 1, 0.0);
  }
  for (LocalIndex n : f.mesh.nodesOf("right")) {
    model.prescribe(n, 0, 0.15);
    model.prescribe(n, 1, 0.3);
  }
  MixedNewtonSolverOptions so;
  so.method = MixedNewtonSolver::BlockTriangular;
  so.jacobian = matrixFree ? JacobianForm::MatrixFree : JacobianForm::Assembled;
  model.setIterativeSolver(so);
  LinearSolverOptions o;
  o.type = LinearSolverType::Amg;
  o.tolerance = 1e-12;
  model.setup(o, MPI_COMM_WORLD);
  EXPECT_EQ(model.matrixFree(), matrixFree);
  if (matrixFree) {
    EXPECT_EQ(model.tangent().numNonzeros(), 0) << "J must not be stored";
  }
  NewtonRun run;
  run.residuals.push_back(model.evaluate(1.0, true));
  for (int it = 0; it < 12 && (it == 0 || run.residuals.back() > 1e-10); ++it) {
    double inc = 0.0;
    const LinearSolveStats s = model.correct(1.0, inc);
    EXPECT_TRUE(s.converged);
    run.linearIterations.push_back(s.iterations);
    run.residuals.push_back(model.evaluate(1.0, true));
  }
  run.solution = model.nodalStressHost();
  const auto u = model.displacementHost();
  run.solution.insert(run.solution.end(), u.begin(), u.end());
  return run;
}

template <class Elem> void newtonCase(ElementType type) {
  const Fixture f = makeFixture(type, 6, 3);
  for (MixedForm form : {MixedForm::Current, MixedForm::Incremental})
    for (double a : {0.0, 0.05}) {
      SCOPED_TRACE(::testing::Message()
                   << Elem::kName << (form == MixedForm::Current ? " current" : " incremental")
                   << " a = " << a);
      const NewtonRun assembled = newton(f, form, a, false);
      const NewtonRun free = newton(f, form, a, true);
      ASSERT_LT(assembled.residuals.back(), 1e-10) << "the assembled Newton converges";
      ASSERT_GT(assembled.residuals.size(), 3u) << "a nonlinear problem";
      ASSERT_EQ(free.residuals.size(), assembled.residuals.size()) << "Newton iterations";
      for (std::size_t i = 0; i < free.residuals.size(); ++i)
        if (assembled.residuals[i] > 1e-6) { // above the level where GMRES's rounding shows
          EXPECT_NEAR(free.residuals[i], assembled.residuals[i], 1e-8 * assembled.residuals[i])
              << "iteration " << i;
        }
      for (std::size_t i = 0; i < free.linearIterations.size(); ++i)
        EXPECT_NEAR(free.linearIterations[i], assembled.linearIterations[i], 1)
            << "iteration " << i;
      const Eigen::Map<const Eigen::VectorXd> x0(assembled.solution.data(),
                                                 assembled.solution.size()),
          x1(free.solution.data(), free.solution.size());
      EXPECT_LT((x1 - x0).cwiseAbs().maxCoeff(), 1e-8 * x0.cwiseAbs().maxCoeff());
    }
}

TEST(MixedJacobianAction, Quad4MatrixFreeNewtonEqualsAssembled) {
  newtonCase<Quad4>(ElementType::Quad4);
}
TEST(MixedJacobianAction, Quad8MatrixFreeNewtonEqualsAssembled) {
  newtonCase<Quad8>(ElementType::Quad8);
}

} // namespace mixed_jacobian_action_tests
