// The element geometry shared by the generic element driver's kernels (kernels/ElementDriver.hpp,
// kernels/ElementStiffness.hpp): the reference shape functions and weight of a quadrature point,
// the physical gradients and det J of one element or of W elements in SIMD lanes, and the gathers
// of an element's coordinates and unknowns. Layer: kernels.
#pragma once

#include <core/ElementTraits.hpp>
#include <kernels/PointPhysics.hpp>
#include <kernels/SparseMatrix.hpp>

namespace mixcon {
namespace detail {

/// Shape functions and natural derivatives at quadrature point q of the element rule; returns
/// the quadrature weight.
template <class Elem>
KOKKOS_INLINE_FUNCTION double referencePoint(int q, double (&sh)[Elem::kNumNodes],
                                             double (&dn)[Elem::kNumNodes][Elem::kDim]) {
  double xi[Elem::kDim], w;
  Elem::quadraturePoint(q, xi, w);
  Elem::shape(xi, sh, dn);
  return w;
}

/// Geometry of W elements (lanes) at one reference point: physical gradients g[a][i][l] =
/// d N_a / d x_i of lane l from the nodal coordinates xe[a][i][l] and the natural derivatives dn
/// (shared by the lanes); det[l] = det(d x / d xi). In 2D the 2x2 inverse is written out (the
/// arithmetic of the 2D kernels); in 3D J^-1 comes from core/Tensor.hpp's adjugate inverse.
template <class Elem, int W>
KOKKOS_INLINE_FUNCTION void laneGeometry(const double (&xe)[Elem::kNumNodes][Elem::kDim][W],
                                         const double (&dn)[Elem::kNumNodes][Elem::kDim],
                                         double (&g)[Elem::kNumNodes][Elem::kDim][W],
                                         double (&det)[W]) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  static_assert(dim == 2 || dim == 3, "the element driver's geometry is 2D or 3D");
  if constexpr (dim == 2) {
    double j00[W] = {}, j01[W] = {}, j10[W] = {}, j11[W] = {};
    for (int a = 0; a < n; ++a)
      for (int l = 0; l < W; ++l) {
        j00[l] += xe[a][0][l] * dn[a][0];
        j01[l] += xe[a][0][l] * dn[a][1];
        j10[l] += xe[a][1][l] * dn[a][0];
        j11[l] += xe[a][1][l] * dn[a][1];
      }
    double i00[W], i01[W], i10[W], i11[W];
    for (int l = 0; l < W; ++l) {
      det[l] = j00[l] * j11[l] - j01[l] * j10[l];
      const double inv = 1.0 / det[l];
      i00[l] = j11[l] * inv;
      i01[l] = -j01[l] * inv;
      i10[l] = -j10[l] * inv;
      i11[l] = j00[l] * inv;
    }
    for (int a = 0; a < n; ++a)
      for (int l = 0; l < W; ++l) {
        g[a][0][l] = dn[a][0] * i00[l] + dn[a][1] * i10[l];
        g[a][1][l] = dn[a][0] * i01[l] + dn[a][1] * i11[l];
      }
  } else {
    for (int l = 0; l < W; ++l) {
      // J[i][j] = d x_i / d xi_j; d N_a / d x_i = sum_j dn[a][j] (J^-1)[j][i].
      Mat<dim, dim> jac{}, inv{};
      for (int a = 0; a < n; ++a)
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j)
            jac.m[i][j] += xe[a][i][l] * dn[a][j];
      det[l] = inverse(jac, inv);
      for (int a = 0; a < n; ++a)
        for (int i = 0; i < dim; ++i) {
          double v = 0.0;
          for (int j = 0; j < dim; ++j)
            v += dn[a][j] * inv.m[j][i];
          g[a][i][l] = v;
        }
    }
  }
}

/// Physical gradients g and det J of one element (one lane of laneGeometry).
template <class Elem>
KOKKOS_INLINE_FUNCTION double pointGeometry(const double (&xe)[Elem::kNumNodes][Elem::kDim],
                                            const double (&dn)[Elem::kNumNodes][Elem::kDim],
                                            double (&g)[Elem::kNumNodes][Elem::kDim]) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  double xl[n][dim][1], gl[n][dim][1], det[1];
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < dim; ++i)
      xl[a][i][0] = xe[a][i];
  laneGeometry<Elem, 1>(xl, dn, gl, det);
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < dim; ++i)
      g[a][i] = gl[a][i][0];
  return det[0];
}

/// Nodal coordinates of element e.
template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void gatherElementCoordinates(const MeshView<MemorySpace, Elem::kDim> &m,
                                                     LocalIndex e,
                                                     double (&xe)[Elem::kNumNodes][Elem::kDim]) {
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    const LocalIndex node = m.connectivity(e, a);
    for (int i = 0; i < Elem::kDim; ++i)
      xe[a][i] = m.coordinates(node, i);
  }
}

/// Displacements of element e from u (Dim unknowns per node, node-interleaved).
template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
gatherElementDisplacements(const MeshView<MemorySpace, Elem::kDim> &m,
                           const Kokkos::View<const double *, MemorySpace> &u, LocalIndex e,
                           double (&ue)[Elem::kNumNodes][Elem::kDim]) {
  using L = LayoutOf<Elem>;
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    const LocalIndex node = m.connectivity(e, a);
    for (int i = 0; i < Elem::kDim; ++i)
      ue[a][i] = u(L::displacementDof(node, i));
  }
}

/// Displacement gradient grad(i, j) = sum_a ue[a][i] g[a][j].
template <class Elem>
KOKKOS_INLINE_FUNCTION Mat<Elem::kDim, Elem::kDim>
displacementGradient(const double (&ue)[Elem::kNumNodes][Elem::kDim],
                     const double (&g)[Elem::kNumNodes][Elem::kDim]) {
  Mat<Elem::kDim, Elem::kDim> h{};
  for (int a = 0; a < Elem::kNumNodes; ++a)
    for (int i = 0; i < Elem::kDim; ++i)
      for (int j = 0; j < Elem::kDim; ++j)
        h.m[i][j] += ue[a][i] * g[a][j];
  return h;
}

/// (s grad N_a)_i = sum_j s_ij g_a[j]: row i of a stress-like tensor times the physical gradient
/// of one shape function (the element residual's and tangent's test-function contraction).
template <int Dim>
KOKKOS_INLINE_FUNCTION double rowTimesGradient(const Mat<Dim, Dim> &s, int i,
                                               const double (&ga)[Dim]) {
  double v = 0.0;
  for (int j = 0; j < Dim; ++j)
    v += s.m[i][j] * ga[j];
  return v;
}

/// fe = 0 and, when `Tangent`, ke = 0 (the element arrays of the finite-strain loops).
template <bool Tangent, int N>
KOKKOS_INLINE_FUNCTION void clearElement(double (&fe)[N], double (&ke)[N][N]) {
  for (int i = 0; i < N; ++i) {
    fe[i] = 0.0;
    if (Tangent)
      for (int j = 0; j < N; ++j)
        ke[i][j] = 0.0;
  }
}

/// The mixed unknowns of element e in v: displacements ue[a][i] and stresses se[a][c] (Voigt)
/// of its nodes, from the interleaved FieldLayout<Dim> vector.
template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
gatherMixedUnknowns(const MeshView<MemorySpace, Elem::kDim> &mesh,
                    const Kokkos::View<const double *, MemorySpace> &v, LocalIndex e,
                    double (&ue)[Elem::kNumNodes][Elem::kDim],
                    double (&se)[Elem::kNumNodes][LayoutOf<Elem>::kNumStresses]) {
  using L = LayoutOf<Elem>;
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    const LocalIndex k = mesh.connectivity(e, a);
    for (int i = 0; i < Elem::kDim; ++i)
      ue[a][i] = v(L::mixedDisplacementDof(k, i));
    for (int c = 0; c < L::kNumStresses; ++c)
      se[a][c] = v(L::mixedStressDof(k, c));
  }
}

/// What a mixed point law `Point` needs of element e: nodal coordinates xe (moved by ue when the
/// law integrates over the current configuration), the unknowns ue, se of x and the prestress
/// te of tau (zero unless Point::kPrestress).
template <class Elem, class Point, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
gatherMixedElement(const MeshView<MemorySpace, Elem::kDim> &mesh,
                   const Kokkos::View<const double *, MemorySpace> &x,
                   const Kokkos::View<const double *, MemorySpace> &tau, LocalIndex e,
                   double (&xe)[Elem::kNumNodes][Elem::kDim],
                   double (&ue)[Elem::kNumNodes][Elem::kDim],
                   double (&se)[Elem::kNumNodes][LayoutOf<Elem>::kNumStresses],
                   double (&te)[Elem::kNumNodes][LayoutOf<Elem>::kNumStresses]) {
  constexpr int nv = LayoutOf<Elem>::kNumStresses;
  gatherElementCoordinates<Elem>(mesh, e, xe);
  gatherMixedUnknowns<Elem>(mesh, x, e, ue, se);
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    const LocalIndex k = mesh.connectivity(e, a);
    for (int i = 0; i < Elem::kDim; ++i)
      if (Point::kCurrentConfiguration)
        xe[a][i] += ue[a][i];
    for (int c = 0; c < nv; ++c)
      te[a][c] = Point::kPrestress ? tau(nv * k + c) : 0.0;
  }
}

} // namespace detail

} // namespace mixcon
