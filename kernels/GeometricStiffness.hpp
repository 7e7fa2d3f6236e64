// The initial-stress terms shared by both models (Eq. (25) and (31)): the geometric stiffness
// K^sigma = K11 = t int [B^sigma]^T [tau] [B^sigma] dA and the stress force
// F^sigma = F^NL = t int [B^L]^T {tau} dA, for a stress field tau given either at the quadrature
// points (displacement model: Cauchy stress of the current configuration) or at the nodes
// (mixed model: interpolated with the shape functions). The field is a small device functor
// (template parameter, no virtual calls). Data flow: kernels -> solver.
#pragma once

#include <kernels/LinearElasticity.hpp>

namespace mixcon {

/// tau (xx, yy, xy) at quadrature point q of element e from nodal stresses s (3 per node).
template <class MemorySpace> struct NodalStressField {
  MeshView<MemorySpace> mesh;
  Kokkos::View<const double *, MemorySpace> s;
  template <int N>
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex e, int, const double (&sh)[N],
                                         double (&tau)[3]) const {
    tau[0] = tau[1] = tau[2] = 0.0;
    for (int b = 0; b < N; ++b) {
      const LocalIndex k = mesh.connectivity(e, b);
      for (int c = 0; c < 3; ++c)
        tau[c] += sh[b] * s(3 * k + c);
    }
  }
};

/// tau (xx, yy, xy) stored per quadrature point: tau(e, q, c).
template <class MemorySpace> struct GaussPointStressField {
  Kokkos::View<const double **[3], MemorySpace> tau;
  template <int N>
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex e, int q, const double (&)[N],
                                         double (&t)[3]) const {
    for (int c = 0; c < 3; ++c)
      t[c] = tau(e, q, c);
  }
};

/// K^sigma of element e: kg[2a+i][2b+i] = t int g_a^T tau g_b dA (the 4 x 2n [B^sigma] and the
/// 4 x 4 [tau] of Eq. (25) multiplied out).
template <class Elem, class MemorySpace, class Field>
KOKKOS_INLINE_FUNCTION void
geometricStiffness(const ElementData<MemorySpace> &d, const Field &field, LocalIndex e,
                   double (&kg)[2 * Elem::kNumNodes][2 * Elem::kNumNodes]) {
  constexpr int n = Elem::kNumNodes;
  double xe[n][2];
  detail::gatherCoordinates<Elem>(d.mesh, e, xe);
  for (int i = 0; i < 2 * n; ++i)
    for (int j = 0; j < 2 * n; ++j)
      kg[i][j] = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double xi, eta, w, sh[n], dn[n][2], g[n][2], tau[3];
    Elem::quadraturePoint(q, xi, eta, w);
    Elem::shape(xi, eta, sh, dn);
    const double f = d.thickness * w * physicalGradients<Elem>(xe, dn, g);
    field(e, q, sh, tau);
    for (int a = 0; a < n; ++a) {
      const double ta0 = (tau[0] * g[a][0] + tau[2] * g[a][1]) * f;
      const double ta1 = (tau[2] * g[a][0] + tau[1] * g[a][1]) * f;
      for (int b = a; b < n; ++b) { // upper triangle; symmetric
        const double v = ta0 * g[b][0] + ta1 * g[b][1];
        kg[2 * a][2 * b] += v;
        kg[2 * a + 1][2 * b + 1] += v;
      }
    }
  }
  for (int a = 1; a < n; ++a)
    for (int b = 0; b < a; ++b) {
      kg[2 * a][2 * b] = kg[2 * b][2 * a];
      kg[2 * a + 1][2 * b + 1] = kg[2 * b + 1][2 * a + 1];
    }
}

/// Element geometric stiffness matrices of all elements into kg(e, i, j) (E x 2n x 2n).
template <class Elem, class ExecSpace, class MemorySpace, class Field, class... P>
void computeGeometricStiffness(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                               const Field &field, const Kokkos::View<double ***, P...> &kg) {
  Kokkos::parallel_for(
      "mixcon::kernels::geometricStiffness",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int nd = 2 * Elem::kNumNodes;
        double k[nd][nd];
        geometricStiffness<Elem>(d, field, e, k);
        for (int i = 0; i < nd; ++i)
          for (int j = 0; j < nd; ++j)
            kg(e, i, j) = k[i][j];
      });
}

/// Adds K^sigma of all elements into `a` (2 dofs per node) through the scatter map of a's graph.
template <class Elem, class ExecSpace, class MemorySpace, class Field, class Map>
void assembleGeometricStiffness(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                                const Field &field, const Map &map,
                                const CsrMatrix<MemorySpace> &a) {
  Kokkos::parallel_for(
      "mixcon::kernels::assembleGeometricStiffness",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int nd = 2 * Elem::kNumNodes;
        double k[nd][nd];
        geometricStiffness<Elem>(d, field, e, k);
        scatterElementMatrix<Elem>(a, map, d.mesh, e, k);
      });
}

/// K^sigma of solid element e on the configuration of `mesh` (the current one), from the Cauchy
/// stress tau(e, q, k) (Voigt<3>: xx, yy, zz, yz, xz, xy) at its quadrature points:
/// kg[3a + i][3b + i] = int g_a . tau g_b dv, g the physical shape-function gradients (the solid
/// form of geometricStiffness, Eq. (25) in 3D).
template <class Elem, class MemorySpace, class TauView>
KOKKOS_INLINE_FUNCTION void
solidGeometricStiffness(const MeshView<MemorySpace, 3> &mesh, const TauView &tau, LocalIndex e,
                        double (&kg)[3 * Elem::kNumNodes][3 * Elem::kNumNodes]) {
  static_assert(Elem::kDim == 3, "the solid form of geometricStiffness");
  constexpr int n = Elem::kNumNodes;
  double xe[n][3];
  detail::gatherElementCoordinates<Elem>(mesh, e, xe);
  for (int i = 0; i < 3 * n; ++i)
    for (int j = 0; j < 3 * n; ++j)
      kg[i][j] = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], dn[n][3], g[n][3];
    const double w = detail::referencePoint<Elem>(q, sh, dn);
    const double f = w * detail::pointGeometry<Elem>(xe, dn, g);
    Vector<Voigt<3>::kSize> tv;
    for (int k = 0; k < Voigt<3>::kSize; ++k)
      tv.v[k] = tau(e, q, k);
    const Mat<3, 3> t = voigtToStress<3>(tv);
    for (int a = 0; a < n; ++a) {
      double ta[3];
      for (int i = 0; i < 3; ++i)
        ta[i] = f * (t.m[i][0] * g[a][0] + t.m[i][1] * g[a][1] + t.m[i][2] * g[a][2]);
      for (int b = a; b < n; ++b) { // upper triangle; symmetric
        const double v = ta[0] * g[b][0] + ta[1] * g[b][1] + ta[2] * g[b][2];
        for (int i = 0; i < 3; ++i)
          kg[3 * a + i][3 * b + i] += v;
      }
    }
  }
  for (int a = 1; a < n; ++a)
    for (int b = 0; b < a; ++b)
      for (int i = 0; i < 3; ++i)
        kg[3 * a + i][3 * b + i] = kg[3 * b + i][3 * a + i];
}

/// Adds K^sigma of all solid elements into `a` (3 dofs per node) through the scatter map of a's
/// graph (solidGeometricStiffness).
template <class Elem, class ExecSpace, class MemorySpace, class TauView, class Map>
void assembleSolidGeometricStiffness(const ExecSpace &exec, const MeshView<MemorySpace, 3> &mesh,
                                     const TauView &tau, const Map &map,
                                     const CsrMatrix<MemorySpace> &a) {
  Kokkos::parallel_for(
      "mixcon::kernels::assembleSolidGeometricStiffness",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int nd = 3 * Elem::kNumNodes;
        double k[nd][nd];
        solidGeometricStiffness<Elem>(mesh, tau, e, k);
        scatterElementStiffness<Elem>(a, map, mesh, e, 1.0, k);
      });
}

/// Adds F^sigma = t int [B^L]^T {tau} dA to f (2 per node), element by element.
template <class Elem, class ExecSpace, class MemorySpace, class Field>
void assembleStressForce(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                         const Field &field, const Kokkos::View<double *, MemorySpace> &f) {
  Kokkos::parallel_for(
      "mixcon::kernels::stressForce", Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes;
        double xe[n][2], fe[n][2] = {};
        detail::gatherCoordinates<Elem>(d.mesh, e, xe);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double xi, eta, w, sh[n], dn[n][2], g[n][2], tau[3];
          Elem::quadraturePoint(q, xi, eta, w);
          Elem::shape(xi, eta, sh, dn);
          const double jw = d.thickness * w * physicalGradients<Elem>(xe, dn, g);
          field(e, q, sh, tau);
          for (int a = 0; a < n; ++a) {
            fe[a][0] += (g[a][0] * tau[0] + g[a][1] * tau[2]) * jw;
            fe[a][1] += (g[a][1] * tau[1] + g[a][0] * tau[2]) * jw;
          }
        }
        for (int a = 0; a < n; ++a) {
          const LocalIndex node = d.mesh.connectivity(e, a);
          Kokkos::atomic_add(&f(2 * node), fe[a][0]);
          Kokkos::atomic_add(&f(2 * node + 1), fe[a][1]);
        }
      });
}

} // namespace mixcon
