// Plain host reference implementations (Eigen, loops) that the batched Kokkos kernels are checked
// against. Written independently of kernels/: shape functions from their textbook formulas, the
// B matrix of Eq. (25) built explicitly, K = sum B^T C B w det J t.
#pragma once

#include <kernels/Material.hpp>
#include <mesh/Mesh.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <vector>

namespace mixcon::test {

/// Natural coordinates of the nodes (Quad4: 4 corners; Quad8: + mid-sides), Gmsh order.
inline void naturalNode(int nodes, int a, double &xi, double &eta) {
  static const double x[8] = {-1, 1, 1, -1, 0, 1, 0, -1};
  static const double y[8] = {-1, -1, 1, 1, -1, 0, 1, 0};
  (void)nodes;
  xi = x[a];
  eta = y[a];
}

/// Shape functions and natural derivatives: N (n), dN/dxi, dN/deta.
inline void referenceShape(int nodes, double xi, double eta, Eigen::VectorXd &n,
                           Eigen::MatrixXd &dn) {
  n.resize(nodes);
  dn.resize(nodes, 2);
  for (int a = 0; a < nodes; ++a) {
    double xa, ea;
    naturalNode(nodes, a, xa, ea);
    if (nodes == 4) {
      n(a) = (1 + xi * xa) * (1 + eta * ea) / 4;
      dn(a, 0) = xa * (1 + eta * ea) / 4;
      dn(a, 1) = ea * (1 + xi * xa) / 4;
    } else if (a < 4) {
      n(a) = (1 + xi * xa) * (1 + eta * ea) * (xi * xa + eta * ea - 1) / 4;
      dn(a, 0) = xa * (1 + eta * ea) * (2 * xi * xa + eta * ea) / 4;
      dn(a, 1) = ea * (1 + xi * xa) * (xi * xa + 2 * eta * ea) / 4;
    } else if (xa == 0) {
      n(a) = (1 - xi * xi) * (1 + eta * ea) / 2;
      dn(a, 0) = -xi * (1 + eta * ea);
      dn(a, 1) = (1 - xi * xi) * ea / 2;
    } else {
      n(a) = (1 + xi * xa) * (1 - eta * eta) / 2;
      dn(a, 0) = xa * (1 - eta * eta) / 2;
      dn(a, 1) = -eta * (1 + xi * xa);
    }
  }
}

/// Gauss rule of `order` points per direction on [-1,1]^2.
inline std::vector<std::array<double, 3>> referenceGauss(int order) {
  std::vector<double> x, w;
  if (order == 2) {
    x = {-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)};
    w = {1, 1};
  } else {
    x = {-std::sqrt(0.6), 0, std::sqrt(0.6)};
    w = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  }
  std::vector<std::array<double, 3>> r;
  for (std::size_t j = 0; j < x.size(); ++j)
    for (std::size_t i = 0; i < x.size(); ++i)
      r.push_back({x[i], x[j], w[i] * w[j]});
  return r;
}

inline Eigen::Matrix3d toEigen(const PlaneMatrix &c) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m(i, j) = c.m[i][j];
  return m;
}

/// Element coordinates (n x 2) of element e.
inline Eigen::MatrixXd elementCoordinates(const Mesh &mesh, LocalIndex e) {
  Eigen::MatrixXd x(mesh.nodesPerElement, 2);
  for (int a = 0; a < mesh.nodesPerElement; ++a) {
    x(a, 0) = mesh.x(mesh.node(e, a));
    x(a, 1) = mesh.y(mesh.node(e, a));
  }
  return x;
}

/// Calls f(N, dN/dx, w det J) at every point of the element's Gauss rule (2x2 for Quad4, 3x3 for
/// Quad8), with J(i, k) = d x_i / d xi_k from the element coordinates xe (n x 2).
template <class F> void forEachReferencePoint(const Eigen::MatrixXd &xe, F &&f) {
  const int n = static_cast<int>(xe.rows());
  for (const auto &g : referenceGauss(n == 4 ? 2 : 3)) {
    Eigen::VectorXd sh;
    Eigen::MatrixXd dn;
    referenceShape(n, g[0], g[1], sh, dn);
    const Eigen::Matrix2d j = xe.transpose() * dn;
    f(sh, Eigen::MatrixXd(dn * j.inverse()), g[2] * j.determinant());
  }
}

/// The 3 x 2n strain-displacement matrix [B^L] of Eq. (25) from the gradients dN/dx (n x 2).
inline Eigen::MatrixXd referenceB(const Eigen::MatrixXd &dx) {
  const int n = static_cast<int>(dx.rows());
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(3, 2 * n);
  for (int a = 0; a < n; ++a) {
    b(0, 2 * a) = dx(a, 0);
    b(1, 2 * a + 1) = dx(a, 1);
    b(2, 2 * a) = dx(a, 1);
    b(2, 2 * a + 1) = dx(a, 0);
  }
  return b;
}

/// K^L = t int B^T C B dA with the 3 x 2n matrix B of Eq. (25) built explicitly.
inline Eigen::MatrixXd referenceStiffness(const Eigen::MatrixXd &xe, const Eigen::Matrix3d &c,
                                          double t) {
  const int n = static_cast<int>(xe.rows());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  forEachReferencePoint(xe, [&](const Eigen::VectorXd &, const Eigen::MatrixXd &dx, double w) {
    const Eigen::MatrixXd b = referenceB(dx);
    k += b.transpose() * c * b * (w * t);
  });
  return k;
}

/// Mixed blocks of Eq. (31) with [B^L] (3 x 2n) and [psi^sigma] (3 x 3n) built explicitly:
/// k12 = t int B^T Psi dA, k22 = t int Psi^T D Psi dA.
inline void referenceMixed(const Eigen::MatrixXd &xe, const Eigen::Matrix3d &d, double t,
                           Eigen::MatrixXd &k12, Eigen::MatrixXd &k22) {
  const int n = static_cast<int>(xe.rows());
  k12 = Eigen::MatrixXd::Zero(2 * n, 3 * n);
  k22 = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  forEachReferencePoint(xe, [&](const Eigen::VectorXd &sh, const Eigen::MatrixXd &dx, double w) {
    Eigen::MatrixXd psi = Eigen::MatrixXd::Zero(3, 3 * n);
    for (int a = 0; a < n; ++a)
      for (int c = 0; c < 3; ++c)
        psi(c, 3 * a + c) = sh(a);
    k12 += referenceB(dx).transpose() * psi * (w * t);
    k22 += psi.transpose() * d * psi * (w * t);
  });
}

/// Geometric stiffness K^sigma = K11 = t int [B^sigma]^T [tau] [B^sigma] dA (Eq. (25), (31)) with
/// the 4 x 2n [B^sigma] and the 4 x 4 [tau] of the report, tau = tauAt(q, N) at quadrature point q
/// (xi fastest, as the kernels number them). Also F = t int [B^L]^T {tau} dA into fnl (2n).
template <class TauAt>
void referenceGeometricAt(const Eigen::MatrixXd &xe, const TauAt &tauAt, double t,
                          Eigen::MatrixXd &kg, Eigen::VectorXd &fnl) {
  const int n = static_cast<int>(xe.rows());
  kg = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  fnl = Eigen::VectorXd::Zero(2 * n);
  int q = 0;
  forEachReferencePoint(xe, [&](const Eigen::VectorXd &sh, const Eigen::MatrixXd &dx, double w) {
    const Eigen::Vector3d tau = tauAt(q++, sh);
    Eigen::MatrixXd bs = Eigen::MatrixXd::Zero(4, 2 * n);
    for (int a = 0; a < n; ++a) {
      bs(0, 2 * a) = dx(a, 0);
      bs(1, 2 * a) = dx(a, 1);
      bs(2, 2 * a + 1) = dx(a, 0);
      bs(3, 2 * a + 1) = dx(a, 1);
    }
    Eigen::Matrix4d tm = Eigen::Matrix4d::Zero();
    tm(0, 0) = tm(2, 2) = tau(0);
    tm(1, 1) = tm(3, 3) = tau(1);
    tm(0, 1) = tm(1, 0) = tm(2, 3) = tm(3, 2) = tau(2);
    kg += bs.transpose() * tm * bs * (w * t);
    fnl += referenceB(dx).transpose() * tau * (w * t);
  });
}

/// Nonlinear-strain energy t int tau_ij eta_ij dA, eta_ij = 1/2 u_k,i u_k,j (Eq. (10)), of element
/// displacements u (2n), tau = tauAt(q, N): its Hessian is K^sigma.
template <class TauAt>
double referenceInitialStressEnergy(const Eigen::MatrixXd &xe, const TauAt &tauAt, double t,
                                    const Eigen::VectorXd &u) {
  const int n = static_cast<int>(xe.rows());
  double energy = 0.0;
  int q = 0;
  forEachReferencePoint(xe, [&](const Eigen::VectorXd &sh, const Eigen::MatrixXd &dx, double w) {
    const Eigen::Vector3d tau = tauAt(q++, sh);
    Eigen::Matrix2d grad = Eigen::Matrix2d::Zero(); // grad(k, i) = u_k,i
    for (int a = 0; a < n; ++a)
      for (int c = 0; c < 2; ++c)
        for (int i = 0; i < 2; ++i)
          grad(c, i) += u(2 * a + c) * dx(a, i);
    const Eigen::Matrix2d eta = 0.5 * grad.transpose() * grad;
    energy += (tau(0) * eta(0, 0) + tau(1) * eta(1, 1) + 2 * tau(2) * eta(0, 1)) * w * t;
  });
  return energy;
}

/// Moves interior nodes of a mesh randomly by up to `amount` times the local spacing `h`
/// (boundary nodes stay), keeping elements valid for modest amounts. Mid-side nodes of Quad8
/// elements are re-centred on their straight edges, so distorted elements stay affine-edged.
inline void distortInterior(Mesh &mesh, double h, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-amount * h, amount * h);
  std::vector<int> onBoundary(mesh.numNodes(), 0);
  for (const auto &[name, edges] : mesh.boundaries)
    for (const auto &e : edges)
      for (int k = 0; k < mesh.nodesPerEdge(); ++k)
        onBoundary[mesh.edgeNode(e, k)] = 1;
  std::vector<int> isCorner(mesh.numNodes(), 0);
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < 4; ++a)
      isCorner[mesh.node(e, a)] = 1;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    if (!onBoundary[n] && isCorner[n]) {
      mesh.coordinates[2 * n] += d(rng);
      mesh.coordinates[2 * n + 1] += d(rng);
    }
  if (mesh.nodesPerElement == 8)
    for (LocalIndex e = 0; e < mesh.numElements(); ++e)
      for (int k = 0; k < 4; ++k) {
        const LocalIndex a = mesh.node(e, k), b = mesh.node(e, (k + 1) % 4),
                         m = mesh.node(e, 4 + k);
        if (onBoundary[m])
          continue;
        mesh.coordinates[2 * m] = 0.5 * (mesh.x(a) + mesh.x(b));
        mesh.coordinates[2 * m + 1] = 0.5 * (mesh.y(a) + mesh.y(b));
      }
}

} // namespace mixcon::test
