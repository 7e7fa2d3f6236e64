// Geometrically nonlinear kernels and models (kernels/Nonlinear.hpp, solver/Nonlinear.hpp):
//  - residuals against plain host references written independently (the displacement model's
//    through the deformation gradient F = dx/dX and b^-1, the mixed model through an explicit
//    nonlinear [B] matrix);
//  - assembled tangents (element kernels + follower-pressure load stiffness, after scatter)
//    against central finite differences of the assembled residual, on distorted meshes with two
//    anisotropic materials, non-zero prestress / finite strain: relative 1e-6 (issue 4);
//  - objectivity: a rigid rotation gives zero Almansi stress and rotates the mixed model's
//    nodal stresses by the push-forward of Eq. (5b).
#include <kernels/Nonlinear.hpp>
#include <solver/Nonlinear.hpp>
#include <support/KernelFixture.hpp>
#include <support/ModelDifferences.hpp>
#include <support/NonlinearReference.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace mixcon;
using namespace mixcon::test;

namespace {

LinearSolverOptions directOptions() {
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  return o;
}

/// Host reference of the mixed incremental residual (5 per node) from configuration `mesh`.
Eigen::VectorXd referenceMixedResidual(const Fixture &f, const Eigen::VectorXd &tau,
                                       const Eigen::VectorXd &x) {
  const int n = f.mesh.nodesPerElement;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(5 * f.mesh.numNodes());
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
    const Eigen::MatrixXd xe = elementCoordinates(f.mesh, e);
    const Eigen::Matrix3d d = toEigen(f.materials[f.elementMaterial[e]]).inverse();
    Eigen::MatrixXd ue(n, 2);
    Eigen::VectorXd se(3 * n), te(3 * n);
    for (int a = 0; a < n; ++a) {
      const LocalIndex k = f.mesh.node(e, a);
      ue.row(a) = x.segment<2>(5 * k).transpose();
      se.segment<3>(3 * a) = x.segment<3>(5 * k + 2);
      te.segment<3>(3 * a) = tau.segment<3>(3 * k);
    }
    Eigen::VectorXd gu = Eigen::VectorXd::Zero(2 * n), gs = Eigen::VectorXd::Zero(3 * n);
    forEachReferencePoint(xe, [&](const Eigen::VectorXd &sh, const Eigen::MatrixXd &dx, double w) {
      Eigen::MatrixXd psi = Eigen::MatrixXd::Zero(3, 3 * n);
      for (int a = 0; a < n; ++a)
        for (int c = 0; c < 3; ++c)
          psi(c, 3 * a + c) = sh(a);
      const Eigen::Matrix2d h = ue.transpose() * dx; // h(i, j) = du_i / dX_j
      const Eigen::Matrix2d fg = Eigen::Matrix2d::Identity() + h;
      const Eigen::Matrix2d green = 0.5 * (fg.transpose() * fg - Eigen::Matrix2d::Identity());
      const Eigen::Vector3d ev(green(0, 0), green(1, 1), 2 * green(0, 1));
      Eigen::MatrixXd bnl(3, 2 * n);
      for (int a = 0; a < n; ++a)
        for (int m = 0; m < 2; ++m) {
          bnl(0, 2 * a + m) = fg(m, 0) * dx(a, 0);
          bnl(1, 2 * a + m) = fg(m, 1) * dx(a, 1);
          bnl(2, 2 * a + m) = fg(m, 0) * dx(a, 1) + fg(m, 1) * dx(a, 0);
        }
      const Eigen::Vector3d sv = psi * se, total = psi * (te + se);
      gu += bnl.transpose() * total * (w * f.data.thickness);
      gs += psi.transpose() * (ev - d * sv) * (w * f.data.thickness);
    });
    for (int a = 0; a < n; ++a) {
      const LocalIndex k = f.mesh.node(e, a);
      g.segment<2>(5 * k) += gu.segment<2>(2 * a);
      g.segment<3>(5 * k + 2) += gs.segment<3>(3 * a);
    }
  }
  return g;
}

/// max |got - ref| / max |ref| over the force rows (part 0) or the stress rows (part 1).
double partError(const Eigen::VectorXd &got, const Eigen::VectorXd &ref, int part) {
  double err = 0.0, scale = 0.0;
  for (Eigen::Index k = 0; k < got.size() / 5; ++k)
    for (int c = part ? 2 : 0; c < (part ? 5 : 2); ++c) {
      err = std::max(err, std::abs(got(5 * k + c) - ref(5 * k + c)));
      scale = std::max(scale, std::abs(ref(5 * k + c)));
    }
  return err / scale;
}

/// Random mixed unknowns: displacements of size 0.03, stresses of size 2e3 (5 per node).
Eigen::VectorXd randomMixedState(LocalIndex nn, unsigned seed, Eigen::VectorXd *scale = nullptr) {
  Eigen::VectorXd x = randomVector(5 * nn, seed), s(5 * nn);
  for (LocalIndex k = 0; k < nn; ++k) {
    s.segment<2>(5 * k).setConstant(0.03);
    s.segment<3>(5 * k + 2).setConstant(2e3);
  }
  if (scale)
    *scale = s;
  return x.cwiseProduct(s);
}

/// A finite-strain state (random displacements of size 0.03, strains of about 5-10 %) plus a
/// rigid rotation of 0.3 rad.
Eigen::VectorXd strainedAndRotated(const Fixture &f) {
  Eigen::VectorXd u = 0.03 * randomVector(2 * f.mesh.numNodes(), 5);
  const double th = 0.3;
  for (LocalIndex k = 0; k < f.mesh.numNodes(); ++k) {
    const double x = f.mesh.x(k), y = f.mesh.y(k);
    u(2 * k) += (std::cos(th) - 1) * x - std::sin(th) * y;
    u(2 * k + 1) += std::sin(th) * x + (std::cos(th) - 1) * y;
  }
  return u;
}

class NonlinearModels : public ::testing::TestWithParam<ElementType> {};

TEST_P(NonlinearModels, AlmansiResidualMatchesHostReference) {
  const Fixture f = makeFixture(GetParam(), 3, 2);
  NonlinearDisplacementModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
  for (LocalIndex n : f.mesh.nodesOf("left"))
    model.prescribe(n, 0, 0.0);
  model.setup(directOptions(), MPI_COMM_WORLD);
  const Eigen::VectorXd u = 0.03 * randomVector(2 * f.mesh.numNodes(), 11);
  model.setDisplacement(toStd(u));
  model.evaluate(0.0, false); // lambda = 0: the internal force alone
  const Eigen::VectorXd got = hostVector(model.residual());
  const Eigen::VectorXd ref = referenceAlmansiForce(f, u);
  EXPECT_LT((got - ref).cwiseAbs().maxCoeff(), 1e-10 * ref.cwiseAbs().maxCoeff());
}

TEST_P(NonlinearModels, DisplacementTangentIsFiniteDifferenceOfResidual) {
  const Fixture f = makeFixture(GetParam(), 3, 2);
  NonlinearDisplacementModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
  for (LocalIndex n : f.mesh.nodesOf("left"))
    model.prescribe(n, 0, 0.0);
  model.addEdgeLoad(f.mesh.boundaries.at("top"), 0.0, -2.0e3, 0.0);
  model.addFollowerPressure(f.mesh.boundaries.at("right"), 4.0e3);
  model.setup(directOptions(), MPI_COMM_WORLD);
  // Finite strain (about 5-10 %) plus a rotation of 0.3 rad: a prestressed, rotated state.
  const Eigen::VectorXd u = strainedAndRotated(f);
  model.setDisplacement(toStd(u));
  model.evaluate(1.0, true);
  const Eigen::MatrixXd k = toDense(model.tangent());
  const Eigen::MatrixXd fd = finiteDifferenceTangent(model, u);
  EXPECT_LT(relativeError(k, fd), 1e-6);
  // The exact tangent of the Almansi law is not symmetric: a symmetric approximation (the
  // report's K^L + K^sigma) would fail the comparison above.
  EXPECT_GT(relativeError(k, Eigen::MatrixXd(k.transpose())), 1e-4);
}

// The St. Venant-Kirchhoff law: the total-Lagrangian residual against the host reference (1e-10),
// the Cauchy stress output against F S F^T / J (through a rigid rotation: objectivity), and the
// exact tangent against central finite differences (1e-6), at finite strain plus rotation.
TEST_P(NonlinearModels, SaintVenantKirchhoffResidualAndTangent) {
  const Fixture f = makeFixture(GetParam(), 3, 2);
  NonlinearDisplacementModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
  model.setElasticLaw(ElasticLaw::SaintVenantKirchhoff);
  for (LocalIndex n : f.mesh.nodesOf("left"))
    model.prescribe(n, 0, 0.0);
  model.addFollowerPressure(f.mesh.boundaries.at("right"), 4.0e3);
  model.setup(directOptions(), MPI_COMM_WORLD);
  const Eigen::VectorXd u = strainedAndRotated(f);
  model.setDisplacement(toStd(u));
  model.evaluate(0.0, false);
  const Eigen::VectorXd ref = referenceSvkForce(f, u);
  EXPECT_LT((hostVector(model.residual()) - ref).cwiseAbs().maxCoeff(),
            1e-10 * ref.cwiseAbs().maxCoeff());
  // The Almansi law gives a different force at this strain (the laws differ at second order).
  EXPECT_GT((referenceAlmansiForce(f, u) - ref).cwiseAbs().maxCoeff(),
            1e-3 * ref.cwiseAbs().maxCoeff());
  model.evaluate(1.0, true);
  const Eigen::MatrixXd k = toDense(model.tangent());
  const Eigen::MatrixXd fd = finiteDifferenceTangent(model, u);
  EXPECT_LT(relativeError(k, fd), 1e-6);
  // Gauss-point Cauchy stress = F S F^T / J with F from the reference gradients.
  std::vector<double> xq, sq, gq, cq;
  int npe = 0;
  model.gaussPointFieldsHost(xq, sq, npe, gq, cq);
  const auto gauss = referenceGauss(f.mesh.nodesPerElement == 4 ? 2 : 3);
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
    const Eigen::MatrixXd xe = elementCoordinates(f.mesh, e);
    const Eigen::Matrix3d c = toEigen(f.materials[f.elementMaterial[e]]);
    Eigen::MatrixXd ue(f.mesh.nodesPerElement, 2);
    for (int a = 0; a < f.mesh.nodesPerElement; ++a)
      ue.row(a) = u.segment<2>(2 * f.mesh.node(e, a)).transpose();
    for (const auto &gp : gauss) {
      Eigen::VectorXd sh;
      Eigen::MatrixXd dn;
      referenceShape(f.mesh.nodesPerElement, gp[0], gp[1], sh, dn);
      // The kernel's point with the same reference coordinates.
      const Eigen::Vector2d xp = xe.transpose() * sh;
      int q = -1;
      for (int r = 0; r < npe; ++r) {
        const std::size_t i = 2 * (static_cast<std::size_t>(e) * npe + r);
        if (std::hypot(xq[i] - xp(0), xq[i + 1] - xp(1)) < 1e-12)
          q = r;
      }
      ASSERT_GE(q, 0);
      const Eigen::MatrixXd dx = dn * (xe.transpose() * dn).inverse();
      const Eigen::Matrix2d fg = Eigen::Matrix2d::Identity() + ue.transpose() * dx;
      const Eigen::Matrix2d green = 0.5 * (fg.transpose() * fg - Eigen::Matrix2d::Identity());
      const Eigen::Vector3d sv = c * Eigen::Vector3d(green(0, 0), green(1, 1), 2 * green(0, 1));
      Eigen::Matrix2d pk2;
      pk2 << sv(0), sv(2), sv(2), sv(1);
      const Eigen::Matrix2d sigma = fg * pk2 * fg.transpose() / fg.determinant();
      const std::size_t at = 3 * (static_cast<std::size_t>(e) * npe + q);
      const double scale = sigma.cwiseAbs().maxCoeff();
      EXPECT_NEAR(sq[at], sigma(0, 0), 1e-10 * scale);
      EXPECT_NEAR(sq[at + 1], sigma(1, 1), 1e-10 * scale);
      EXPECT_NEAR(sq[at + 2], sigma(0, 1), 1e-10 * scale);
    }
  }
}

TEST_P(NonlinearModels, MixedCurrentResidualMatchesHostReference) {
  const Fixture f = makeFixture(GetParam(), 3, 2);
  NonlinearMixedModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
  for (LocalIndex n : f.mesh.nodesOf("left"))
    model.prescribe(n, 0, 0.0);
  model.setup(directOptions(), MPI_COMM_WORLD);
  const Eigen::VectorXd x = randomMixedState(f.mesh.numNodes(), 14);
  model.setIncrement(toStd(x));
  model.evaluate(0.0, false);
  const Eigen::VectorXd got = hostVector(model.residual());
  const Eigen::VectorXd ref = referenceMixedCurrent(f, x);
  EXPECT_LT(partError(got, ref, 0), 1e-10) << "forces";
  EXPECT_LT(partError(got, ref, 1), 1e-10) << "stress equations";
}

TEST_P(NonlinearModels, MixedIncrementalResidualMatchesHostReference) {
  const Fixture f = makeFixture(GetParam(), 3, 2);
  NonlinearMixedModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
  model.setForm(MixedForm::Incremental);
  for (LocalIndex n : f.mesh.nodesOf("left"))
    model.prescribe(n, 0, 0.0);
  model.setup(directOptions(), MPI_COMM_WORLD);
  const LocalIndex nn = f.mesh.numNodes();
  const Eigen::VectorXd tau = 3e3 * randomVector(3 * nn, 3);
  const Eigen::VectorXd x = randomMixedState(nn, 4);
  model.setPrestress(toStd(tau));
  model.setIncrement(toStd(x));
  model.evaluate(0.0, false);
  const Eigen::VectorXd got = hostVector(model.residual());
  const Eigen::VectorXd ref = referenceMixedResidual(f, tau, x);
  EXPECT_LT(partError(got, ref, 0), 1e-10) << "forces";
  EXPECT_LT(partError(got, ref, 1), 1e-10) << "stress equations";
}

TEST_P(NonlinearModels, MixedJacobianIsFiniteDifferenceOfResidual) {
  const Fixture f = makeFixture(GetParam(), 3, 2);
  const LocalIndex nn = f.mesh.numNodes();
  for (MixedForm form : {MixedForm::Current, MixedForm::Incremental})
    for (double a : {0.0, 0.05}) {
      SCOPED_TRACE(std::string(form == MixedForm::Current ? "current" : "incremental") +
                   " form, a = " + std::to_string(a));
      NonlinearMixedModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
      model.setForm(form);
      model.setStabilization(a);
      for (LocalIndex n : f.mesh.nodesOf("left"))
        model.prescribe(n, 0, 0.0);
      model.addFollowerPressure(f.mesh.boundaries.at("right"), 4.0e3);
      model.addFollowerPressure(f.mesh.boundaries.at("top"), -1.0e3);
      model.setup(directOptions(), MPI_COMM_WORLD);
      Eigen::VectorXd scale;
      const Eigen::VectorXd x = randomMixedState(nn, 9, &scale);
      if (form == MixedForm::Incremental) // prestress of the incremental form
        model.setPrestress(toStd(3e3 * randomVector(3 * nn, 8)));
      model.setIncrement(toStd(x));
      model.evaluate(1.0, true);
      const Eigen::MatrixXd k = toDense(model.tangent());
      Eigen::MatrixXd fd(k.rows(), k.cols());
      for (int j = 0; j < x.size(); ++j) {
        const double h = 1e-5 * scale(j);
        Eigen::VectorXd xp = x, xm = x;
        xp(j) += h;
        xm(j) -= h;
        model.setIncrement(toStd(xp));
        model.evaluate(1.0, false);
        const Eigen::VectorXd gp = hostVector(model.residual());
        model.setIncrement(toStd(xm));
        model.evaluate(1.0, false);
        fd.col(j) = (gp - hostVector(model.residual())) / (2 * h);
      }
      // Block-wise: the four blocks have different units.
      for (int rb = 0; rb < 2; ++rb)
        for (int cb = 0; cb < 2; ++cb) {
          std::vector<int> rows, cols;
          for (LocalIndex q = 0; q < nn; ++q) {
            for (int c = rb ? 2 : 0; c < (rb ? 5 : 2); ++c)
              rows.push_back(5 * q + c);
            for (int c = cb ? 2 : 0; c < (cb ? 5 : 2); ++c)
              cols.push_back(5 * q + c);
          }
          EXPECT_LT(relativeError(k(rows, cols), fd(rows, cols)), 1e-6)
              << "block (" << rb << ", " << cb << ")";
        }
    }
}

TEST_P(NonlinearModels, MixedAmgCorrectionsEqualDirect) {
  // Both iterative solves (solver: amg) — flexible GMRES on the Jacobian with the block
  // lower-triangular preconditioner, and on the Schur complement — give the same Newton
  // correction as the sparse LU of the full Jacobian, with prescribed displacements driving a
  // non-zero target.
  const Fixture f = makeFixture(GetParam(), 4, 3);
  const LocalIndex nn = f.mesh.numNodes();
  for (MixedForm form : {MixedForm::Current, MixedForm::Incremental}) {
    SCOPED_TRACE(form == MixedForm::Current ? "current form" : "incremental form");
    std::vector<double> corrected[3];
    for (int k = 0; k < 3; ++k) {
      NonlinearMixedModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
      model.setForm(form);
      model.setStabilization(0.05);
      for (LocalIndex n : f.mesh.nodesOf("left")) {
        model.prescribe(n, 0, 0.0);
        model.prescribe(n, 1, 0.01);
      }
      model.addFollowerPressure(f.mesh.boundaries.at("right"), 4.0e3);
      MixedNewtonSolverOptions so;
      so.method = k == 2 ? MixedNewtonSolver::Schur : MixedNewtonSolver::BlockTriangular;
      model.setIterativeSolver(so);
      LinearSolverOptions o;
      o.type = k == 0 ? LinearSolverType::Direct : LinearSolverType::Amg;
      o.tolerance = 1e-10;
      model.setup(o, MPI_COMM_WORLD);
      Eigen::VectorXd x = randomMixedState(nn, 31);
      x *= 0.3;
      if (form == MixedForm::Incremental)
        model.setPrestress(toStd(1e3 * randomVector(3 * nn, 32)));
      model.setIncrement(toStd(x));
      model.evaluate(1.0, true);
      double inc = 0.0;
      const LinearSolveStats s = model.correct(1.0, inc);
      ASSERT_TRUE(s.converged);
      corrected[k] = model.nodalStressHost();
      const auto u = model.displacementHost();
      corrected[k].insert(corrected[k].end(), u.begin(), u.end());
    }
    const Eigen::Map<const Eigen::VectorXd> a(corrected[0].data(), corrected[0].size());
    for (int k = 1; k < 3; ++k) {
      SCOPED_TRACE(k == 1 ? "block triangular" : "Schur complement");
      const Eigen::Map<const Eigen::VectorXd> b(corrected[k].data(), corrected[k].size());
      const Eigen::Index ns = 3 * nn;
      EXPECT_LT((a.head(ns) - b.head(ns)).norm(), 1e-7 * a.head(ns).norm()) << "stresses";
      EXPECT_LT((a.tail(2 * nn) - b.tail(2 * nn)).norm(), 1e-7 * a.tail(2 * nn).norm())
          << "displacements";
    }
  }
}

TEST_P(NonlinearModels, RigidRotationIsStressFreeAndRotatesNodalStress) {
  const Fixture f = makeFixture(GetParam(), 3, 2);
  const double th = 0.7, c = std::cos(th), s = std::sin(th);
  const LocalIndex nn = f.mesh.numNodes();
  Eigen::VectorXd u(2 * nn);
  for (LocalIndex k = 0; k < nn; ++k) {
    u(2 * k) = (c - 1) * f.mesh.x(k) - s * f.mesh.y(k);
    u(2 * k + 1) = s * f.mesh.x(k) + (c - 1) * f.mesh.y(k);
  }
  NonlinearDisplacementModel disp(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
  disp.prescribe(0, 0, 0.0);
  disp.setup(directOptions(), MPI_COMM_WORLD);
  disp.setDisplacement(toStd(u));
  std::vector<double> xq, sq;
  int nq = 0;
  disp.gaussPointStressHost(xq, sq, nq);
  for (double v : sq) // round-off of the moduli (up to 1.6e6) times 1e-14
    EXPECT_NEAR(v, 0.0, 1e-14 * 1.6e6);

  const Eigen::VectorXd tau = 1e3 * randomVector(3 * nn, 21);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  for (StressUpdate update : {StressUpdate::Projected, StressUpdate::NodalAverage}) {
    NonlinearMixedModel mixed(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
    mixed.setForm(MixedForm::Incremental); // the form whose stress is pushed forward
    mixed.setStressUpdate(update);
    mixed.prescribe(0, 0, 0.0);
    mixed.setup(directOptions(), MPI_COMM_WORLD);
    mixed.setPrestress(toStd(tau));
    Eigen::VectorXd x = Eigen::VectorXd::Zero(5 * nn);
    for (LocalIndex k = 0; k < nn; ++k)
      x.segment<2>(5 * k) = u.segment<2>(2 * k);
    mixed.setIncrement(toStd(x));
    mixed.commit();
    const auto got = mixed.nodalStressHost();
    for (LocalIndex k = 0; k < nn; ++k) {
      Eigen::Matrix2d t;
      t << tau(3 * k), tau(3 * k + 2), tau(3 * k + 2), tau(3 * k + 1);
      const Eigen::Matrix2d expect = r * t * r.transpose();
      EXPECT_NEAR(got[3 * k], expect(0, 0), 1e-9 * 1e3);
      EXPECT_NEAR(got[3 * k + 1], expect(1, 1), 1e-9 * 1e3);
      EXPECT_NEAR(got[3 * k + 2], expect(0, 1), 1e-9 * 1e3);
    }
  }
}

TEST_P(NonlinearModels, InvertedElementIsNamed) {
  const Fixture f = makeFixture(GetParam(), 3, 2);
  NonlinearDisplacementModel model(f.mesh, f.elementMaterial, f.materials, f.data.thickness);
  model.prescribe(0, 0, 0.0);
  model.setup(directOptions(), MPI_COMM_WORLD);
  // Push the third corner of element 1 through its first corner.
  const LocalIndex e = 1, a = f.mesh.node(e, 0), c = f.mesh.node(e, 2);
  std::vector<double> u(2 * f.mesh.numNodes(), 0.0);
  u[2 * c] = 1.5 * (f.mesh.x(a) - f.mesh.x(c));
  u[2 * c + 1] = 1.5 * (f.mesh.y(a) - f.mesh.y(c));
  model.setDisplacement(u);
  EXPECT_FALSE(std::isfinite(model.evaluate(1.0, false)));
  ASSERT_GE(model.invertedElement(), 0);
  bool shares = false; // the element found uses the moved node
  for (int k = 0; k < f.mesh.nodesPerElement; ++k)
    shares = shares || f.mesh.node(model.invertedElement(), k) == c;
  EXPECT_TRUE(shares);
  EXPECT_NE(model.invertedElementMessage().find("is inverted"), std::string::npos);
  model.setDisplacement(std::vector<double>(u.size(), 0.0));
  EXPECT_TRUE(std::isfinite(model.evaluate(1.0, false)));
  EXPECT_EQ(model.invertedElement(), -1);
}

INSTANTIATE_TEST_SUITE_P(Elements, NonlinearModels,
                         ::testing::Values(ElementType::Quad4, ElementType::Quad8),
                         [](const auto &info) {
                           return std::string(info.param == ElementType::Quad4 ? "Quad4" : "Quad8");
                         });

} // namespace
