// The initial-stress kernels (kernels/GeometricStiffness.hpp) for both stress fields — nodal
// stresses interpolated with the shape functions (mixed model: K11, F^NL) and stresses stored per
// quadrature point (displacement model: K^sigma, F^sigma) — against the host reference of
// Eq. (25)/(31) with [B^sigma] and [tau] built explicitly, and K^sigma as the finite-difference
// tangent (Hessian) of the nonlinear-strain energy t int tau_ij eta_ij dA.
#include <kernels/GeometricStiffness.hpp>
#include <solver/Krylov.hpp>
#include <support/KernelFixture.hpp>

#include <gtest/gtest.h>

using namespace mixcon;
using namespace mixcon::test;
using Exec = Kokkos::DefaultExecutionSpace;

namespace {

enum class FieldKind { Nodal, GaussPoint };

/// A random stress field of either kind: the device functor for the kernels and the host
/// tau(e, q, N) for the reference.
struct StressFieldCase {
  FieldKind kind;
  Eigen::VectorXd nodal;                          ///< 3 per node
  Kokkos::View<double **[3], Memory> gaussPoints; ///< (E, nq, 3)
  Kokkos::View<double *, Memory> nodalView;
  Eigen::Vector3d at(const Mesh &mesh, LocalIndex e, int q, const Eigen::VectorXd &sh) const {
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    if (kind == FieldKind::Nodal) {
      for (int a = 0; a < mesh.nodesPerElement; ++a)
        t += sh(a) * nodal.segment<3>(3 * mesh.node(e, a));
    } else {
      auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), gaussPoints);
      t = Eigen::Vector3d(h(e, q, 0), h(e, q, 1), h(e, q, 2));
    }
    return t;
  }
};

StressFieldCase makeField(FieldKind kind, const Mesh &mesh, int numQp) {
  StressFieldCase c{kind, 100.0 * randomVector(3 * mesh.numNodes(), 5), {}, {}};
  c.nodalView = toView(c.nodal);
  c.gaussPoints = Kokkos::View<double **[3], Memory>("tau", mesh.numElements(), numQp);
  auto h = Kokkos::create_mirror_view(c.gaussPoints);
  const Eigen::VectorXd r = 100.0 * randomVector(3 * numQp * mesh.numElements(), 6);
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int q = 0; q < numQp; ++q)
      for (int k = 0; k < 3; ++k)
        h(e, q, k) = r(3 * (e * numQp + q) + k);
  Kokkos::deep_copy(c.gaussPoints, h);
  return c;
}

/// Runs f(field functor) with the device functor of the case's kind.
template <class F> void withDeviceField(const StressFieldCase &c, const Fixture &fx, F &&f) {
  if (c.kind == FieldKind::Nodal)
    f(NodalStressField<Memory>{fx.data.mesh, ConstDeviceVector(c.nodalView)});
  else
    f(GaussPointStressField<Memory>{c.gaussPoints});
}

template <class Elem, class Field>
void runKernels(const Fixture &fx, const Field &field, const Kokkos::View<double ***, Memory> &kg,
                const Kokkos::View<double *, Memory> &force) {
  computeGeometricStiffness<Elem>(Exec(), fx.data, field, kg);
  assembleStressForce<Elem>(Exec(), fx.data, field, force);
}

} // namespace

class GeometricTest : public ::testing::TestWithParam<std::tuple<ElementType, FieldKind>> {};
INSTANTIATE_TEST_SUITE_P(
    Fields, GeometricTest,
    ::testing::Combine(::testing::Values(ElementType::Quad4, ElementType::Quad8),
                       ::testing::Values(FieldKind::Nodal, FieldKind::GaussPoint)),
    [](const auto &info) {
      return std::string(std::get<0>(info.param) == ElementType::Quad8 ? "Quad8" : "Quad4") +
             (std::get<1>(info.param) == FieldKind::Nodal ? "Nodal" : "GaussPoint");
    });

TEST_P(GeometricTest, StiffnessAndStressForceMatchReferenceAndAreTheEnergyTangent) {
  // Not a structured binding: `type` is captured by a lambda below (C++20 for a binding).
  const ElementType type = std::get<0>(GetParam());
  const FieldKind kind = std::get<1>(GetParam());
  const Fixture fx = makeFixture(type, 4, 3);
  const int nn = fx.mesh.numNodes(), n = fx.mesh.nodesPerElement, ne = fx.mesh.numElements();
  const int nq = type == ElementType::Quad8 ? 9 : 4;
  const StressFieldCase field = makeField(kind, fx.mesh, nq);
  Kokkos::View<double ***, Memory> kg("kg", ne, 2 * n, 2 * n);
  Kokkos::View<double *, Memory> force("force", 2 * nn);
  withDeviceField(field, fx, [&](const auto &f) {
    dispatchPlaneElement(type, "this 2D test",
                         [&](auto elem) { runKernels<decltype(elem)>(fx, f, kg, force); });
  });
  auto hg = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), kg);
  Eigen::VectorXd fref = Eigen::VectorXd::Zero(2 * nn);
  for (LocalIndex e = 0; e < ne; ++e) {
    const auto xe = elementCoordinates(fx.mesh, e);
    const auto tauAt = [&](int q, const Eigen::VectorXd &sh) {
      return field.at(fx.mesh, e, q, sh);
    };
    Eigen::MatrixXd rk, k(2 * n, 2 * n);
    Eigen::VectorXd rf;
    referenceGeometricAt(xe, tauAt, fx.data.thickness, rk, rf);
    for (int i = 0; i < 2 * n; ++i)
      for (int j = 0; j < 2 * n; ++j)
        k(i, j) = hg(e, i, j);
    ASSERT_LT(relativeError(k, rk), 1e-12) << "K^sigma of element " << e;
    ASSERT_LT((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-12 * k.cwiseAbs().maxCoeff());
    for (int a = 0; a < n; ++a)
      fref.segment<2>(2 * fx.mesh.node(e, a)) += rf.segment<2>(2 * a);
    // K^sigma is the Hessian of the nonlinear-strain energy: central differences along v of
    // W(u + h v) give v^T K u (first) and v^T K v (second).
    const auto energy = [&](const Eigen::VectorXd &u) {
      return referenceInitialStressEnergy(xe, tauAt, fx.data.thickness, u);
    };
    const Eigen::VectorXd u = 1e-2 * randomVector(2 * n, 100 + e), v = randomVector(2 * n, 200 + e);
    const double h = 1e-4;
    const double first = (energy(u + h * v) - energy(u - h * v)) / (2 * h);
    const double second = (energy(u + h * v) - 2 * energy(u) + energy(u - h * v)) / (h * h);
    const double scale = k.cwiseAbs().maxCoeff();
    EXPECT_NEAR(first, v.dot(k * u), 1e-8 * scale * u.norm() * v.norm()) << "element " << e;
    EXPECT_NEAR(second, v.dot(k * v), 1e-4 * scale * v.squaredNorm()) << "element " << e;
  }
  EXPECT_LT(relativeError(toEigen(force), fref), 1e-12);
}
