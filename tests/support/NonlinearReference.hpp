// Plain host references of the geometrically nonlinear residuals (Eigen, one element after
// another, written independently of the kernels): the displacement model's internal force through
// F = dx/dX and b^-1, and the current-configuration mixed residual. Shared by the tests and the
// benchmarks (speed-up of the batched kernels over them).
#pragma once

#include <support/KernelFixture.hpp>

namespace mixcon::test {

/// Almansi strain (I - b^-1) / 2 from F = dx/dX at a point with natural gradients dn, reference
/// and current element coordinates xe0, xe.
inline Eigen::Matrix2d referenceAlmansi(const Eigen::MatrixXd &xe0, const Eigen::MatrixXd &xe,
                                        const Eigen::MatrixXd &dn) {
  const Eigen::Matrix2d fgrad = (xe.transpose() * dn) * (xe0.transpose() * dn).inverse();
  return 0.5 * (Eigen::Matrix2d::Identity() - (fgrad * fgrad.transpose()).inverse());
}

/// Calls f(sh, bx, strain, da) at every Gauss point of an element with reference and current
/// coordinates xe0, xe (n x 2): shape functions sh, the 3 x 2n [B] of the current configuration,
/// the engineering Almansi strain (e_xx, e_yy, 2 e_xy) and the current area weight w det J t.
template <class F>
void forEachAlmansiPoint(const Eigen::MatrixXd &xe0, const Eigen::MatrixXd &xe, double t, F &&f) {
  const int n = static_cast<int>(xe.rows());
  for (const auto &q : referenceGauss(n == 4 ? 2 : 3)) {
    Eigen::VectorXd sh;
    Eigen::MatrixXd dn;
    referenceShape(n, q[0], q[1], sh, dn);
    const Eigen::Matrix2d j = xe.transpose() * dn;
    const Eigen::Matrix2d strain = referenceAlmansi(xe0, xe, dn);
    f(sh, referenceB(dn * j.inverse()),
      Eigen::Vector3d(strain(0, 0), strain(1, 1), 2 * strain(0, 1)), q[2] * j.determinant() * t);
  }
}

/// Host reference of the displacement model's internal force: F = dx/dX, b^-1 = (F F^T)^-1,
/// e = (I - b^-1)/2, sigma = C e, f = t int B(x)^T sigma da over the current element.
inline Eigen::VectorXd referenceAlmansiForce(const Fixture &f, const Eigen::VectorXd &u) {
  Eigen::VectorXd force = Eigen::VectorXd::Zero(2 * f.mesh.numNodes());
  const int n = f.mesh.nodesPerElement;
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
    const Eigen::MatrixXd xe0 = elementCoordinates(f.mesh, e);
    Eigen::MatrixXd xe = xe0;
    for (int a = 0; a < n; ++a)
      xe.row(a) += u.segment<2>(2 * f.mesh.node(e, a)).transpose();
    const Eigen::Matrix3d c = toEigen(f.materials[f.elementMaterial[e]]);
    Eigen::VectorXd fe = Eigen::VectorXd::Zero(2 * n);
    forEachAlmansiPoint(xe0, xe, f.data.thickness,
                        [&](const Eigen::VectorXd &, const Eigen::MatrixXd &b,
                            const Eigen::Vector3d &strain,
                            double da) { fe += b.transpose() * (c * strain) * da; });
    for (int a = 0; a < n; ++a)
      force.segment<2>(2 * f.mesh.node(e, a)) += fe.segment<2>(2 * a);
  }
  return force;
}

/// Host reference of the current-configuration mixed residual (a = 0): G_u = t int B(x)^T tau da,
/// G_S = t int psi (e - D tau) da, e = (I - b^-1) / 2 from F = dx/dX.
inline Eigen::VectorXd referenceMixedCurrent(const Fixture &f, const Eigen::VectorXd &x) {
  const int n = f.mesh.nodesPerElement;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(5 * f.mesh.numNodes());
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
    const Eigen::MatrixXd xe0 = elementCoordinates(f.mesh, e);
    Eigen::MatrixXd xe = xe0;
    Eigen::VectorXd te(3 * n);
    for (int a = 0; a < n; ++a) {
      const LocalIndex k = f.mesh.node(e, a);
      xe.row(a) += x.segment<2>(5 * k).transpose();
      te.segment<3>(3 * a) = x.segment<3>(5 * k + 2);
    }
    const Eigen::Matrix3d d = toEigen(f.materials[f.elementMaterial[e]]).inverse();
    Eigen::VectorXd gu = Eigen::VectorXd::Zero(2 * n), gs = Eigen::VectorXd::Zero(3 * n);
    forEachAlmansiPoint(xe0, xe, f.data.thickness,
                        [&](const Eigen::VectorXd &sh, const Eigen::MatrixXd &b,
                            const Eigen::Vector3d &strain, double da) {
                          Eigen::MatrixXd psi = Eigen::MatrixXd::Zero(3, 3 * n);
                          for (int a = 0; a < n; ++a)
                            for (int c = 0; c < 3; ++c)
                              psi(c, 3 * a + c) = sh(a);
                          const Eigen::Vector3d tau = psi * te;
                          gu += b.transpose() * tau * da;
                          gs += psi.transpose() * (strain - d * tau) * da;
                        });
    for (int a = 0; a < n; ++a) {
      const LocalIndex k = f.mesh.node(e, a);
      g.segment<2>(5 * k) += gu.segment<2>(2 * a);
      g.segment<3>(5 * k + 2) += gs.segment<3>(3 * a);
    }
  }
  return g;
}

/// Host reference of the St. Venant-Kirchhoff internal force, total Lagrangian: F = I + du/dX,
/// E = (F^T F - I) / 2, S = C E, f = t int B_NL(F)^T S dA over the reference element, with the
/// explicit 3 x 2n nonlinear strain-displacement matrix B_NL(F).
inline Eigen::VectorXd referenceSvkForce(const Fixture &f, const Eigen::VectorXd &u) {
  const int n = f.mesh.nodesPerElement;
  Eigen::VectorXd force = Eigen::VectorXd::Zero(2 * f.mesh.numNodes());
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
    const Eigen::MatrixXd xe = elementCoordinates(f.mesh, e);
    Eigen::MatrixXd ue(n, 2);
    for (int a = 0; a < n; ++a)
      ue.row(a) = u.segment<2>(2 * f.mesh.node(e, a)).transpose();
    const Eigen::Matrix3d c = toEigen(f.materials[f.elementMaterial[e]]);
    Eigen::VectorXd fe = Eigen::VectorXd::Zero(2 * n);
    forEachReferencePoint(xe, [&](const Eigen::VectorXd &, const Eigen::MatrixXd &dx, double w) {
      const Eigen::Matrix2d fg = Eigen::Matrix2d::Identity() + ue.transpose() * dx;
      const Eigen::Matrix2d green = 0.5 * (fg.transpose() * fg - Eigen::Matrix2d::Identity());
      Eigen::MatrixXd bnl(3, 2 * n);
      for (int a = 0; a < n; ++a)
        for (int m = 0; m < 2; ++m) {
          bnl(0, 2 * a + m) = fg(m, 0) * dx(a, 0);
          bnl(1, 2 * a + m) = fg(m, 1) * dx(a, 1);
          bnl(2, 2 * a + m) = fg(m, 0) * dx(a, 1) + fg(m, 1) * dx(a, 0);
        }
      fe += bnl.transpose() * c * Eigen::Vector3d(green(0, 0), green(1, 1), 2 * green(0, 1)) *
            (w * f.data.thickness);
    });
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 2; ++i)
        force(2 * f.mesh.node(e, a) + i) += fe(2 * a + i);
  }
  return force;
}

} // namespace mixcon::test
