// The geometrically nonlinear displacement model on solids (issue 17): Hex8, Hex20, Tet4 and Tet10
// on a distorted box with a rotated orthotropic material (all 21 entries of C non-zero):
//  - the assembled tangent (element kernels of both laws, Almansi and St. Venant-Kirchhoff, plus
//    the follower face pressure's load stiffness, after scatter) against central finite
//    differences of the assembled residual at finite strain plus a rotation about an oblique
//    axis: relative 1e-6, the bound of the 2D tests (issue 4);
//  - objectivity: a rigid rotation of 0.7 rad gives zero stress (Gauss points and nodes) and zero
//    internal force, and rotates a follower pressure's nodal forces with the body;
//  - the follower pressure on the undeformed body equals the dead pressure of the linear face
//    load kernel (assembleFaceLoads; both use detail::faceFrame), and its resultant is the closed
//    form p A n on the flat face (A = 1 x 1.2).
// tangent: report (the report's K^L + K^sigma of the current configuration) against a plain host
// K^L + K^sigma on all four solids, and its Newton path on a Hex20 cantilever against the exact
// tangent's.
// The geometrically nonlinear mixed model (all four solids): the Jacobians of its current and
// incremental forms against finite differences of their residuals (a = 0 and 0.1, with the
// follower face pressure), a stress-free rigid rotation with no residual, and the incremental
// form's push-forward of the nodal stress (both updates) against closed forms: a rigid rotation
// of a random prestress and a homogeneous increment.
// The constant-stress (homogeneous finite deformation) patch tests of both models, against the
// closed-form Cauchy stress, are in tests/validation/test_solid.cpp.
#include <solver/Nonlinear.hpp>
#include <support/KernelFixture.hpp>
#include <support/ModelDifferences.hpp>
#include <support/SolidMesh.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace mixcon;
using namespace mixcon::test;

namespace {

/// Rotation by `angle` about the unit axis (1, 2, 3) / sqrt(14) (Rodrigues).
Eigen::Matrix3d obliqueRotation(double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
}

/// Displacements of the rigid motion x = R X (plus `random` times a random field of seed 5).
Eigen::VectorXd rotatedBy(const Mesh &mesh, const Eigen::Matrix3d &r, double random) {
  const LocalIndex nn = mesh.numNodes();
  Eigen::VectorXd u = random * randomVector(3 * nn, 5);
  for (LocalIndex k = 0; k < nn; ++k) {
    const Eigen::Vector3d x(mesh.x(k), mesh.y(k), mesh.z(k));
    u.segment<3>(3 * k) += r * x - x;
  }
  return u;
}

struct Solid {
  Mesh mesh;
  std::vector<int> material;
  std::vector<SolidMatrix> stiffness;
};

/// The distorted 1 x 2 x 1 box of `type` with the rotated orthotropic solid (moduli up to 1.6e3).
Solid makeSolid(ElementType type) {
  Solid s{distortedBox(1, type), {}, {rotatedOrthotropicSolid()}};
  s.material.assign(s.mesh.numElements(), 0);
  return s;
}

/// The support and loads of the tangent tests (node 0 fixed, a dead traction on zmax and, if
/// `follower`, a follower pressure on xmax) given to `model`, then set up with the direct solver.
template <class Model>
std::unique_ptr<Model> loadedModel(std::unique_ptr<Model> model, const Solid &s, bool follower) {
  for (int i = 0; i < 3; ++i)
    model->prescribe(0, i, 0.0);
  model->addSideLoad(s.mesh.boundaries.at("zmax"), {10.0, -20.0, -30.0}, 0.0);
  if (follower)
    model->addFollowerPressure(s.mesh.boundaries.at("xmax"), 40.0);
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  model->setup(o, MPI_COMM_WORLD);
  return model;
}

std::unique_ptr<NonlinearDisplacementModel> makeModel(const Solid &s, ElasticLaw law,
                                                      bool follower) {
  auto model = std::make_unique<NonlinearDisplacementModel>(s.mesh, s.material, s.stiffness);
  model->setElasticLaw(law);
  return loadedModel(std::move(model), s, follower);
}

class SolidNonlinear : public ::testing::TestWithParam<ElementType> {};

TEST_P(SolidNonlinear, TangentOfBothLawsIsFiniteDifferenceOfResidual) {
  const Solid s = makeSolid(GetParam());
  // Finite strain (random displacements of 0.03 on cells of about 1) plus a rotation of 0.3 rad.
  const Eigen::VectorXd u = rotatedBy(s.mesh, obliqueRotation(0.3), 0.03);
  for (ElasticLaw law : {ElasticLaw::Almansi, ElasticLaw::SaintVenantKirchhoff}) {
    const auto model = makeModel(s, law, true);
    model->setDisplacement(toStd(u));
    ASSERT_TRUE(std::isfinite(model->evaluate(1.0, true)));
    const Eigen::MatrixXd k = toDense(model->tangent());
    ASSERT_EQ(k.rows(), 3 * s.mesh.numNodes());
    const Eigen::MatrixXd fd = finiteDifferenceTangent(*model, u);
    EXPECT_LT(relativeError(k, fd), 1e-6) << "law " << static_cast<int>(law);
    // Neither the Almansi tangent nor a follower load stiffness is symmetric: a symmetric
    // approximation would fail the comparison above.
    EXPECT_GT(relativeError(k, Eigen::MatrixXd(k.transpose())), 1e-4);
  }
}

TEST_P(SolidNonlinear, RigidRotationIsStressFreeAndRotatesFollowerForces) {
  const Solid s = makeSolid(GetParam());
  const Eigen::Matrix3d r = obliqueRotation(0.7);
  const Eigen::VectorXd u = rotatedBy(s.mesh, r, 0.0);
  const LocalIndex nn = s.mesh.numNodes();
  const double modulus = 1.6e3;
  for (ElasticLaw law : {ElasticLaw::Almansi, ElasticLaw::SaintVenantKirchhoff}) {
    // Internal force and stresses: no load at all (lambda = 0).
    const auto model = makeModel(s, law, false);
    model->setDisplacement(toStd(u));
    model->evaluate(0.0, false);
    EXPECT_LT(hostVector(model->residual()).cwiseAbs().maxCoeff(), 1e-12 * modulus);
    std::vector<double> xq, sq;
    int nq = 0;
    model->gaussPointStressHost(xq, sq, nq);
    ASSERT_EQ(sq.size(), 6u * nq * s.mesh.numElements());
    for (double v : sq)
      EXPECT_NEAR(v, 0.0, 1e-13 * modulus);
    const auto nodal = model->nodalStressHost();
    ASSERT_EQ(nodal.size(), 6u * nn);
    for (double v : nodal)
      EXPECT_NEAR(v, 0.0, 1e-13 * modulus);
  }
  // The follower pressure's nodal forces turn with the body: f(R) = R f(I) node by node. The
  // internal force is zero in both states, so the residual difference at lambda = 1 is -f_p.
  const auto with = makeModel(s, ElasticLaw::Almansi, true);
  const auto without = makeModel(s, ElasticLaw::Almansi, false);
  const auto pressureForce = [&](const Eigen::VectorXd &state) {
    with->setDisplacement(toStd(state));
    without->setDisplacement(toStd(state));
    with->evaluate(1.0, false);
    without->evaluate(1.0, false);
    return Eigen::VectorXd(hostVector(without->residual()) - hostVector(with->residual()));
  };
  const Eigen::VectorXd f0 = pressureForce(Eigen::VectorXd::Zero(3 * nn));
  const Eigen::VectorXd f1 = pressureForce(u);
  ASSERT_GT(f0.cwiseAbs().maxCoeff(), 1.0);
  for (LocalIndex k = 0; k < nn; ++k)
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(f1(3 * k + i), (r * f0.segment<3>(3 * k))(i), 1e-11 * f0.cwiseAbs().maxCoeff())
          << "node " << k;
}

TEST_P(SolidNonlinear, FollowerPressureOnTheUndeformedBodyIsTheDeadPressure) {
  const Solid s = makeSolid(GetParam());
  NonlinearDisplacementModel follower(s.mesh, s.material, s.stiffness);
  NonlinearDisplacementModel dead(s.mesh, s.material, s.stiffness);
  follower.addFollowerPressure(s.mesh.boundaries.at("ymax"), 7.0);
  dead.addSideLoad(s.mesh.boundaries.at("ymax"), {0.0, 0.0, 0.0}, 7.0);
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  for (NonlinearDisplacementModel *m : {&follower, &dead}) {
    m->prescribe(0, 0, 0.0);
    m->setup(o, MPI_COMM_WORLD);
    m->evaluate(1.0, false);
  }
  const Eigen::VectorXd a = hostVector(follower.residual()), b = hostVector(dead.residual());
  ASSERT_GT(b.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-13 * b.cwiseAbs().maxCoeff());
  // The residual holds -f_ext = p A n (n = +y, the outward normal of ymax; zero internal force).
  double resultant[3] = {0.0, 0.0, 0.0};
  for (LocalIndex k = 0; k < s.mesh.numNodes(); ++k)
    for (int i = 0; i < 3; ++i)
      resultant[i] += a(3 * k + i);
  EXPECT_NEAR(resultant[0], 0.0, 1e-12);
  EXPECT_NEAR(resultant[1], 7.0 * 1.0 * 1.2, 1e-12);
  EXPECT_NEAR(resultant[2], 0.0, 1e-12);
}

/// The report's tangent K^L + K^sigma (Eq. (24)-(25)) of the whole mesh, written out plainly on
/// the host (Eigen): on the current configuration x = X + u, K = sum over elements and
/// quadrature points of w det J (B^T C B + (g_a . tau g_b) I), B the 6 x 3n small-strain matrix
/// (Voigt xx, yy, zz, yz, xz, xy, engineering shears), g the current shape-function gradients,
/// tau = C e the Cauchy stress of the Almansi strain e = (h + h^T - h^T h) / 2, h = du/dx.
Eigen::MatrixXd hostReportTangent(const Solid &s, const Eigen::VectorXd &u) {
  const Mesh &mesh = s.mesh;
  const LocalIndex nn = mesh.numNodes();
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(3 * nn, 3 * nn);
  Eigen::Matrix<double, 6, 6> c;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      c(i, j) = s.stiffness[0].m[i][j];
  const int row[6] = {0, 1, 2, 1, 0, 0}, col[6] = {0, 1, 2, 2, 2, 1};
  dispatchElement(mesh.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    if constexpr (Elem::kDim == 3) {
      constexpr int n = Elem::kNumNodes;
      for (LocalIndex e = 0; e < mesh.numElements(); ++e) {
        Eigen::Matrix<double, n, 3> x, ue;
        for (int a = 0; a < n; ++a) {
          const LocalIndex p = mesh.connectivity[n * e + a];
          ue.row(a) = u.segment<3>(3 * p).transpose();
          x.row(a) = Eigen::RowVector3d(mesh.x(p), mesh.y(p), mesh.z(p)) + ue.row(a);
        }
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double xi[3], w, sh[n], dn[n][3];
          Elem::quadraturePoint(q, xi, w);
          Elem::shape(xi, sh, dn);
          Eigen::Matrix<double, n, 3> d;
          for (int a = 0; a < n; ++a)
            d.row(a) = Eigen::RowVector3d(dn[a][0], dn[a][1], dn[a][2]);
          const Eigen::Matrix3d j = x.transpose() * d; // dx/dxi
          const Eigen::Matrix<double, n, 3> g = d * j.inverse();
          const Eigen::Matrix3d h = ue.transpose() * g;
          const Eigen::Matrix3d strain = 0.5 * (h + h.transpose() - h.transpose() * h);
          Eigen::Matrix<double, 6, 1> ev;
          for (int m = 0; m < 6; ++m)
            ev(m) = (m < 3 ? 1.0 : 2.0) * strain(row[m], col[m]);
          const Eigen::Matrix<double, 6, 1> tv = c * ev;
          Eigen::Matrix3d tau;
          for (int m = 0; m < 6; ++m)
            tau(row[m], col[m]) = tau(col[m], row[m]) = tv(m);
          Eigen::Matrix<double, 6, 3 *n> b = Eigen::Matrix<double, 6, 3 * n>::Zero();
          for (int a = 0; a < n; ++a)
            for (int m = 0; m < 6; ++m) {
              b(m, 3 * a + row[m]) += g(a, col[m]);
              if (m >= 3)
                b(m, 3 * a + col[m]) += g(a, row[m]);
            }
          const double f = w * j.determinant();
          const Eigen::Matrix<double, 3 * n, 3 *n> ke = f * b.transpose() * c * b;
          const Eigen::Matrix<double, n, n> kg = f * g * tau * g.transpose();
          for (int a = 0; a < n; ++a)
            for (int bn = 0; bn < n; ++bn) {
              const LocalIndex p = mesh.connectivity[n * e + a], r = mesh.connectivity[n * e + bn];
              k.block<3, 3>(3 * p, 3 * r) +=
                  ke.template block<3, 3>(3 * a, 3 * bn) + kg(a, bn) * Eigen::Matrix3d::Identity();
            }
        }
      }
    }
  });
  return k;
}

// tangent: report in 3D: the assembled tangent at a finite strain with a 0.3 rad rotation is the
// plain host K^L + K^sigma above to 1e-10, symmetric, and not the exact tangent (which has the
// non-symmetric terms of the Almansi law's dependence on the configuration).
TEST_P(SolidNonlinear, ReportTangentIsLinearPlusGeometricStiffnessOfTheCurrentConfiguration) {
  const Solid s = makeSolid(GetParam());
  const Eigen::VectorXd u = rotatedBy(s.mesh, obliqueRotation(0.3), 0.03);
  Eigen::MatrixXd k[2];
  for (int m = 0; m < 2; ++m) {
    auto model = std::make_unique<NonlinearDisplacementModel>(s.mesh, s.material, s.stiffness);
    model->setTangent(m == 0 ? TangentKind::Report : TangentKind::Exact);
    model = loadedModel(std::move(model), s, false);
    model->setDisplacement(toStd(u));
    ASSERT_TRUE(std::isfinite(model->evaluate(1.0, true)));
    k[m] = toDense(model->tangent());
  }
  const Eigen::MatrixXd reference = hostReportTangent(s, u);
  EXPECT_LT(relativeError(k[0], reference), 1e-10);
  EXPECT_LT(relativeError(k[0], Eigen::MatrixXd(k[0].transpose())), 1e-13) << "symmetric";
  EXPECT_GT(relativeError(k[1], k[0]), 1e-4) << "the exact tangent differs";
}

// The 3D form of ReportCantilever.ExactTangentConvergesFasterThanTheReportsToTheSameState
// (tests/validation/test_nonlinear_cantilever.cpp): a 10 x 1 x 1 Hex20 cantilever (clamped at
// x = 0, a downward traction on its top face of qL^3/EI = 5 at load factor 1), two increments
// iterated to a residual of 1e-10: the report's symmetric K^L + K^sigma reaches the state of the
// exact tangent (the deflection of the tip node (10, 0.5, 1) to 1e-7) with linear convergence, i.e.
// more iterations.
TEST(SolidReportTangent, ReachesTheExactTangentsStateWithMoreIterations) {
  const Mesh mesh = boxMesh(10.0, 1.0, 1.0, 10, 1, 1, ElementType::Hex20);
  const std::vector<SolidMatrix> c{IsotropicMaterial{1e4, 0.3}.stiffness()};
  const double q = 5.0 * 1e4 / 12.0 / 1000.0; // qL^3/EI = 5 with EI = E / 12, L = 10
  LocalIndex tip = 0;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    if (std::abs(mesh.x(n) - 10.0) + std::abs(mesh.y(n) - 0.5) + std::abs(mesh.z(n) - 1.0) < 1e-9)
      tip = n;
  double deflection[2];
  int iterations[2] = {0, 0};
  for (int m = 0; m < 2; ++m) {
    NonlinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), c);
    model.setTangent(m == 0 ? TangentKind::Exact : TangentKind::Report);
    for (LocalIndex n : mesh.nodesOf("xmin"))
      for (int i = 0; i < 3; ++i)
        model.prescribe(n, i, 0.0);
    model.addSideLoad(mesh.boundaries.at("zmax"), {0.0, 0.0, -q}, 0.0);
    LinearSolverOptions o;
    o.type = LinearSolverType::Direct;
    model.setup(o, MPI_COMM_WORLD);
    NonlinearOptions opts;
    opts.residualTolerance = 1e-10;
    opts.maxIterations = 60;
    LoadStepper stepper(model, opts);
    for (double lambda : {0.5, 1.0}) {
      const IncrementOutcome out = stepper.advance(lambda);
      ASSERT_TRUE(out.converged) << out.message;
      iterations[m] += out.iterations;
    }
    deflection[m] = model.displacementHost()[3 * tip + 2];
  }
  EXPECT_LT(deflection[0], -1.0) << "a large deflection";
  EXPECT_NEAR(deflection[1], deflection[0], 1e-7 * std::abs(deflection[0]));
  EXPECT_LT(iterations[0] + 4, iterations[1])
      << "exact " << iterations[0] << ", report " << iterations[1];
}

/// The geometrically nonlinear mixed model (current form) on the distorted box of `type`, with
/// stabilization a, the loads of makeModel and, if `follower`, its follower face pressure.
std::unique_ptr<SolidNonlinearMixedModel> makeMixedModel(const Solid &s, double a, bool follower) {
  return loadedModel(std::make_unique<SolidNonlinearMixedModel>(s.mesh, s.material, s.stiffness, a),
                     s, follower);
}

/// Unknowns of the mixed model (9 per node): displacements u, stresses `stress` times a random
/// field of seed 9.
Eigen::VectorXd mixedState(const Eigen::VectorXd &u, double stress) {
  const Eigen::Index nn = u.size() / 3;
  const Eigen::VectorXd s = stress * randomVector(6 * nn, 9);
  Eigen::VectorXd x(9 * nn);
  for (Eigen::Index k = 0; k < nn; ++k) {
    x.segment<3>(9 * k) = u.segment<3>(3 * k);
    x.segment<6>(9 * k + 3) = s.segment<6>(6 * k);
  }
  return x;
}

class SolidNonlinearMixed : public ::testing::TestWithParam<ElementType> {};

// The Jacobian of the 3D mixed model's current form (element driver with MixedCurrentPoint<3>,
// row-block assembly, follower face pressure with Ndof = 9) against central finite differences of
// its residual, at finite strain with a 0.3 rad rotation and stresses of the order of the strain
// times the moduli, for the report's model (a = 0) and a stabilized one.
TEST_P(SolidNonlinearMixed, JacobianIsFiniteDifferenceOfResidual) {
  const Solid s = makeSolid(GetParam());
  const Eigen::VectorXd x = mixedState(rotatedBy(s.mesh, obliqueRotation(0.3), 0.03), 50.0);
  for (double a : {0.0, 0.1}) {
    const auto model = makeMixedModel(s, a, true);
    model->setUnknowns(toStd(x));
    ASSERT_TRUE(std::isfinite(model->evaluate(1.0, true)));
    const Eigen::MatrixXd k = toDense(model->tangent());
    ASSERT_EQ(k.rows(), 9 * s.mesh.numNodes());
    const Eigen::MatrixXd fd = finiteDifferenceTangent(
        *model, x,
        [](SolidNonlinearMixedModel &m, const std::vector<double> &v) { m.setUnknowns(v); });
    EXPECT_LT(relativeError(k, fd), 1e-6) << "a = " << a;
    EXPECT_GT(relativeError(k, Eigen::MatrixXd(k.transpose())), 1e-4) << "not symmetric";
  }
}

// A rigid rotation of 0.7 rad with zero stresses is an equilibrium state without loads: zero
// residual in the equilibrium and the compatibility rows (the Almansi strain of a rotation is
// zero).
TEST_P(SolidNonlinearMixed, RigidRotationWithoutStressHasNoResidual) {
  const Solid s = makeSolid(GetParam());
  const Eigen::VectorXd x = mixedState(rotatedBy(s.mesh, obliqueRotation(0.7), 0.0), 0.0);
  const auto model = makeMixedModel(s, 0.05, false);
  model->setUnknowns(toStd(x));
  ASSERT_TRUE(std::isfinite(model->evaluate(0.0, false)));
  EXPECT_LT(hostVector(model->residual()).cwiseAbs().maxCoeff(), 1e-12 * 1.6e3);
  // A stress state is not: the same rotation with stresses leaves a compatibility residual.
  model->setUnknowns(toStd(mixedState(rotatedBy(s.mesh, obliqueRotation(0.7), 0.0), 50.0)));
  model->evaluate(0.0, false);
  EXPECT_GT(hostVector(model->residual()).cwiseAbs().maxCoeff(), 1e-3);
}

/// The mixed model's incremental form (the report's literal scheme) on the distorted box of
/// `type`, set up as makeMixedModel's, with the push-forward `update`.
std::unique_ptr<SolidNonlinearMixedModel> makeIncrementalModel(const Solid &s, double a,
                                                               bool follower, StressUpdate update) {
  auto model = std::make_unique<SolidNonlinearMixedModel>(s.mesh, s.material, s.stiffness, a);
  model->setForm(MixedForm::Incremental);
  model->setStressUpdate(update);
  return loadedModel(std::move(model), s, follower);
}

/// Voigt (xx, yy, zz, yz, xz, xy) <-> symmetric tensor.
Eigen::Matrix3d voigtTensor(const Eigen::Ref<const Eigen::VectorXd> &v) {
  Eigen::Matrix3d t;
  for (int k = 0; k < 6; ++k)
    t(Voigt<3>::row(k), Voigt<3>::col(k)) = t(Voigt<3>::col(k), Voigt<3>::row(k)) = v(k);
  return t;
}

// The Jacobian of the incremental form (MixedIncrementPoint<3> on c1 with a nodal prestress, row-
// block assembly, follower face pressure) against central finite differences of its residual, at
// an increment of finite strain with a 0.3 rad rotation, stress increments and a prestress of the
// order of the strain times the moduli, a = 0 and 0.1. Without the follower pressure it is
// symmetric (Eq. (30): [K11(tau + S), K12(u); K12(u)^T, -M]), unlike the current form's.
TEST_P(SolidNonlinearMixed, IncrementalJacobianIsFiniteDifferenceOfResidual) {
  const Solid s = makeSolid(GetParam());
  const Eigen::VectorXd x = mixedState(rotatedBy(s.mesh, obliqueRotation(0.3), 0.03), 50.0);
  const Eigen::VectorXd tau = 50.0 * randomVector(6 * s.mesh.numNodes(), 13);
  for (double a : {0.0, 0.1})
    for (bool follower : {true, false}) {
      SCOPED_TRACE("a = " + std::to_string(a) + (follower ? ", follower pressure" : ""));
      const auto model = makeIncrementalModel(s, a, follower, StressUpdate::Projected);
      model->setPrestress(toStd(tau));
      model->setUnknowns(toStd(x));
      ASSERT_TRUE(std::isfinite(model->evaluate(1.0, true)));
      const Eigen::MatrixXd k = toDense(model->tangent());
      const Eigen::MatrixXd fd = finiteDifferenceTangent(
          *model, x,
          [](SolidNonlinearMixedModel &m, const std::vector<double> &v) { m.setUnknowns(v); });
      EXPECT_LT(relativeError(k, fd), 1e-6);
      const double asymmetry = relativeError(k, Eigen::MatrixXd(k.transpose()));
      if (follower)
        EXPECT_GT(asymmetry, 1e-8) << "the follower pressure's load stiffness";
      else
        EXPECT_LT(asymmetry, 1e-12) << "symmetric";
    }
}

// The push-forward at the end of an increment, both updates: a prestress of random nodal values
// carried through a rigid rotation of 0.7 rad (S = 0) becomes R tau R^T at every node (the L2
// projection reproduces it: the mass of the rotated configuration is the same), the total
// displacement is the rotation's, and the configuration moves with the body: the next
// increment, from zero, has the internal forces of the unrotated body rotated by R.
TEST_P(SolidNonlinearMixed, IncrementalCommitRotatesThePrestressWithTheBody) {
  const Solid s = makeSolid(GetParam());
  const LocalIndex nn = s.mesh.numNodes();
  const Eigen::Matrix3d r = obliqueRotation(0.7);
  const Eigen::VectorXd u = rotatedBy(s.mesh, r, 0.0);
  const Eigen::VectorXd tau = 1e3 * randomVector(6 * nn, 21);
  for (StressUpdate update : {StressUpdate::Projected, StressUpdate::NodalAverage}) {
    SCOPED_TRACE(update == StressUpdate::Projected ? "projected" : "nodal average");
    const auto model = makeIncrementalModel(s, 0.0, false, update);
    model->setPrestress(toStd(tau));
    model->setUnknowns(toStd(mixedState(u, 0.0)));
    model->commit();
    const auto got = model->nodalStressHost();
    const auto du = model->displacementHost();
    ASSERT_EQ(got.size(), 6 * static_cast<std::size_t>(nn));
    for (LocalIndex k = 0; k < nn; ++k) {
      const Eigen::Matrix3d expect = r * voigtTensor(tau.segment<6>(6 * k)) * r.transpose();
      for (int c = 0; c < 6; ++c)
        ASSERT_NEAR(got[6 * k + c], expect(Voigt<3>::row(c), Voigt<3>::col(c)), 1e-9 * 1e3)
            << "node " << k << " component " << c;
      for (int i = 0; i < 3; ++i)
        ASSERT_NEAR(du[3 * k + i], u(3 * k + i), 1e-14) << "node " << k;
    }
    // Internal forces of the prestress (zero increment, no load at lambda = 0): before the
    // rotation (a model of its own) and after it.
    const auto unrotated = makeIncrementalModel(s, 0.0, false, update);
    unrotated->setPrestress(toStd(tau));
    ASSERT_TRUE(std::isfinite(unrotated->evaluate(0.0, false)));
    const Eigen::VectorXd g0 = hostVector(unrotated->residual());
    model->setUnknowns(std::vector<double>(9 * nn, 0.0));
    ASSERT_TRUE(std::isfinite(model->evaluate(0.0, false)));
    const Eigen::VectorXd g1 = hostVector(model->residual());
    const double scale = g0.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 1.0);
    for (LocalIndex k = 0; k < nn; ++k) {
      const Eigen::Vector3d expect = r * g0.segment<3>(9 * k);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(g1(9 * k + i), expect(i), 1e-10 * scale) << "node " << k;
    }
  }
}

// A homogeneous increment x = F X1 (8 % strain, 0.4 rad) of a constant prestress tau0 and stress
// increment S0: both updates give the closed form F (tau0 + S0) F^T / det F at every node.
TEST_P(SolidNonlinearMixed, IncrementalCommitPushesAHomogeneousStateForward) {
  const Solid s = makeSolid(GetParam());
  const LocalIndex nn = s.mesh.numNodes();
  Eigen::Matrix3d g;
  g << 0.08, -0.03, 0.05, 0.02, -0.06, 0.04, -0.05, 0.03, 0.07;
  const Eigen::Matrix3d f = obliqueRotation(0.4) * (Eigen::Matrix3d::Identity() + g);
  Eigen::Matrix<double, 6, 1> tau0, s0;
  tau0 << 120.0, -40.0, 75.0, 30.0, -55.0, 18.0;
  s0 << -20.0, 65.0, 10.0, -12.0, 40.0, 33.0;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(9 * nn), tau(6 * nn);
  for (LocalIndex k = 0; k < nn; ++k) {
    const Eigen::Vector3d p(s.mesh.x(k), s.mesh.y(k), s.mesh.z(k));
    x.segment<3>(9 * k) = f * p - p;
    x.segment<6>(9 * k + 3) = s0;
    tau.segment<6>(6 * k) = tau0;
  }
  const Eigen::Matrix3d expect = f * voigtTensor(tau0 + s0) * f.transpose() / f.determinant();
  for (StressUpdate update : {StressUpdate::Projected, StressUpdate::NodalAverage}) {
    SCOPED_TRACE(update == StressUpdate::Projected ? "projected" : "nodal average");
    const auto model = makeIncrementalModel(s, 0.0, false, update);
    model->setPrestress(toStd(tau));
    model->setUnknowns(toStd(x));
    const auto before = model->nodalStressHost(); // tau + S during the increment
    model->commit();
    const auto got = model->nodalStressHost();
    for (LocalIndex k = 0; k < nn; ++k)
      for (int c = 0; c < 6; ++c) {
        ASSERT_NEAR(before[6 * k + c], tau0(c) + s0(c), 1e-12 * 1e3);
        ASSERT_NEAR(got[6 * k + c], expect(Voigt<3>::row(c), Voigt<3>::col(c)), 1e-10 * 1e3)
            << "node " << k << " component " << c;
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Solids, SolidNonlinearMixed,
                         ::testing::Values(ElementType::Hex8, ElementType::Hex20, ElementType::Tet4,
                                           ElementType::Tet10),
                         [](const auto &info) { return elementTypeName(info.param); });

INSTANTIATE_TEST_SUITE_P(Solids, SolidNonlinear,
                         ::testing::Values(ElementType::Hex8, ElementType::Hex20, ElementType::Tet4,
                                           ElementType::Tet10),
                         [](const auto &info) { return elementTypeName(info.param); });

} // namespace
