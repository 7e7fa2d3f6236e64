// The generic batched element driver of both models (issue 16, item 2: the libCEED / MFEM split
// of element loops and point physics). One loop shape for every element type and every point law:
// gather the element's nodal coordinates (and unknowns), compute the geometry at each quadrature
// point (Jacobian, det J, physical gradients from the traits), call the point law, and reduce to
// the element stiffness t int B^T D B dA, the element residual t int B^T sigma dA or, for the
// mixed (Hellinger-Reissner) model, its residual and Jacobian (mixedElement), then scatter into
// CSR through the element-to-CSR map with atomics. The element sizes come from the traits
// (Elem::kNumNodes, kNumQp, kDim: 2D quadrilaterals and the 3D Hex8; meshes are
// MeshView<MemorySpace, Elem::kDim>, and in 3D the thickness t is 1), the point physics from a
// "law": a small copyable struct with `Point at(LocalIndex e) const` giving element e's point
// functor (kernels/PointPhysics.hpp: stress(eps), tangent(eps); kernels/MixedPointPhysics.hpp:
// evaluate<Tangent>(h, s, tau)). The stiffness comes in two forms: SIMD lanes of elements per
// thread (stiffnessLanes, CPUs and the small elements on GPUs) and one team per element
// (teamElementStiffness, the larger 3D elements on GPUs; kTeamStiffness), in
// kernels/ElementStiffness.hpp; the shared geometry is kernels/ElementGeometry.hpp. Layer: kernels.
#pragma once

#include <kernels/ElementStiffness.hpp>
#include <kernels/MixedPointPhysics.hpp>

namespace mixcon {

/// Small-strain residual of element e at displacements u: fe = t int B^T sigma dA with sigma =
/// law.at(e).stress(eps(u)) at every quadrature point, dofs node-interleaved.
template <class Elem, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
elementResidual(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness, const Law &law,
                const Kokkos::View<const double *, MemorySpace> &u, LocalIndex e,
                double (&fe)[Elem::kDim * Elem::kNumNodes]) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  using V = Voigt<dim>;
  double xe[n][dim], ue[n][dim];
  detail::gatherElementCoordinates<Elem>(mesh, e, xe);
  detail::gatherElementDisplacements<Elem>(mesh, u, e, ue);
  const auto point = law.at(e);
  for (int i = 0; i < dim * n; ++i)
    fe[i] = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], dn[n][dim], g[n][dim];
    const double w = detail::referencePoint<Elem>(q, sh, dn);
    const double f = thickness * w * detail::pointGeometry<Elem>(xe, dn, g);
    const auto sig = point.stress(smallStrain(detail::displacementGradient<Elem>(ue, g)));
    for (int a = 0; a < n; ++a)
      for (int k = 0; k < V::kSize; ++k) {
        const int r = V::row(k), c = V::col(k);
        fe[dim * a + r] += f * g[a][c] * sig.v[k];
        if (V::isShear(k))
          fe[dim * a + c] += f * g[a][r] * sig.v[k];
      }
  }
}

/// Adds the small-strain residual of every element (elementResidual) into f (atomics).
template <class Elem, class ExecSpace, class Law, class MemorySpace>
void assembleElementResidual(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                             double thickness, const Law &law,
                             const Kokkos::View<const double *, MemorySpace> &u,
                             const Kokkos::View<double *, MemorySpace> &f) {
  Kokkos::parallel_for(
      "mixcon::kernels::assembleElementResidual",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int dim = Elem::kDim;
        double fe[dim * Elem::kNumNodes];
        elementResidual<Elem>(mesh, thickness, law, u, e, fe);
        for (int a = 0; a < Elem::kNumNodes; ++a) {
          const LocalIndex node = mesh.connectivity(e, a);
          for (int i = 0; i < dim; ++i)
            Kokkos::atomic_add(&f(LayoutOf<Elem>::displacementDof(node, i)), fe[dim * a + i]);
        }
      });
}

/// Small-strain stress (Voigt) of the point law at every quadrature point of the element rule:
/// stress(e, q, k) of a rank-3 View (E x kNumQp x Voigt size).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class StressView>
void quadraturePointStress(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                           const Law &law, const Kokkos::View<const double *, MemorySpace> &u,
                           const StressView &stress) {
  Kokkos::parallel_for(
      "mixcon::kernels::quadraturePointStress",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
        double xe[n][dim], ue[n][dim];
        detail::gatherElementCoordinates<Elem>(mesh, e, xe);
        detail::gatherElementDisplacements<Elem>(mesh, u, e, ue);
        const auto point = law.at(e);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double sh[n], dn[n][dim], g[n][dim];
          detail::referencePoint<Elem>(q, sh, dn);
          detail::pointGeometry<Elem>(xe, dn, g);
          const auto sig = point.stress(smallStrain(detail::displacementGradient<Elem>(ue, g)));
          for (int k = 0; k < Voigt<dim>::kSize; ++k)
            stress(e, q, k) = sig.v[k];
        }
      });
}

/// Updated-Lagrangian element of a spatial point law (kernels/PointPhysics.hpp: Cauchy stress
/// stress(h) of the displacement gradient h = du/dx on the current configuration x = X + u, and
/// tangent(h) = d sigma / d h) at total displacements u (Dim per node): fe = t int B^T sigma da
/// over the current element and, when `Tangent`, its exact derivative ke = d fe / du. For the
/// perturbation delta u_b = unit vector m (dl = d delta u / dx = e_m (x) g_b): dh = (I - h) dl,
/// dsigma = tangent : dh, d(da) = da g_bm, d g_aj = -g_am g_bj, so
/// d(sigma_ij g_aj da) = (dsigma_ij g_aj + sigma_ij (g_aj g_bm - g_am g_bj)) da.
/// Returns false when the current element is inverted (det dx/dxi <= 0 at a quadrature point).
template <class Elem, bool Tangent, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool
spatialElement(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness, const Law &law,
               const Kokkos::View<const double *, MemorySpace> &u, LocalIndex e,
               double (&fe)[Elem::kDim * Elem::kNumNodes],
               double (&ke)[Elem::kDim * Elem::kNumNodes][Elem::kDim * Elem::kNumNodes]) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  constexpr int nv = Voigt<dim>::kSize;
  double xe[n][dim], ue[n][dim];
  detail::gatherElementCoordinates<Elem>(mesh, e, xe);
  detail::gatherElementDisplacements<Elem>(mesh, u, e, ue);
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < dim; ++i)
      xe[a][i] += ue[a][i]; // current configuration
  const auto point = law.at(e);
  bool valid = true;
  detail::clearElement<Tangent>(fe, ke);
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], dn[n][dim], g[n][dim];
    const double w = detail::referencePoint<Elem>(q, sh, dn);
    const double det = detail::pointGeometry<Elem>(xe, dn, g);
    if (!(det > 0.0))
      valid = false;
    const double jw = thickness * w * det;
    const Mat<dim, dim> h = detail::displacementGradient<Elem>(ue, g);
    const Mat<dim, dim> s = voigtToStress<dim>(point.stress(h));
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < dim; ++i)
        fe[dim * a + i] += jw * detail::rowTimesGradient<dim>(s, i, g[a]);
    if (!Tangent)
      continue;
    // am(c, m dim + l) = sum_k tangent(c, k dim + l) (delta_km - h_km): dsigma_c for the
    // perturbation (b, m) is sum_l am(c, m dim + l) g_bl.
    const auto t = point.tangent(h);
    Mat<nv, dim * dim> am{};
    for (int c = 0; c < nv; ++c)
      for (int m = 0; m < dim; ++m)
        for (int l = 0; l < dim; ++l) {
          double v = 0.0;
          for (int k = 0; k < dim; ++k)
            v += t.m[c][k * dim + l] * ((k == m ? 1.0 : 0.0) - h.m[k][m]);
          am.m[c][m * dim + l] = v;
        }
    for (int b = 0; b < n; ++b)
      for (int m = 0; m < dim; ++m) {
        Vector<nv> dsv{};
        for (int c = 0; c < nv; ++c)
          for (int l = 0; l < dim; ++l)
            dsv.v[c] += am.m[c][m * dim + l] * g[b][l];
        const Mat<dim, dim> ds = voigtToStress<dim>(dsv);
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < dim; ++i) {
            double v = 0.0;
            for (int j = 0; j < dim; ++j)
              v += ds.m[i][j] * g[a][j] + s.m[i][j] * (g[a][j] * g[b][m] - g[a][m] * g[b][j]);
            ke[dim * a + i][dim * b + m] += jw * v;
          }
      }
  }
  return valid;
}

/// Total-Lagrangian element of a material point law (kernels/PointPhysics.hpp: 2nd Piola-Kirchhoff
/// stress stress(F) of the deformation gradient F = I + du/dX on the reference configuration X,
/// and tangent(F) = d S / d F) at total displacements u (Dim per node): fe = t int P grad_X(N) dA
/// with P = F S and, when `Tangent`, its exact derivative ke = d fe / du: for delta u_b = unit
/// vector m, dF = e_m (x) g_b and dP_ij = delta_im (g_b S)_j + F_ik dS_kj, dS = tangent : dF.
/// Returns false for an inverted element (det dX/dxi <= 0 or det F <= 0 at a quadrature point).
template <class Elem, bool Tangent, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool
materialElement(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness, const Law &law,
                const Kokkos::View<const double *, MemorySpace> &u, LocalIndex e,
                double (&fe)[Elem::kDim * Elem::kNumNodes],
                double (&ke)[Elem::kDim * Elem::kNumNodes][Elem::kDim * Elem::kNumNodes]) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  constexpr int nv = Voigt<dim>::kSize;
  double xe[n][dim], ue[n][dim];
  detail::gatherElementCoordinates<Elem>(mesh, e, xe);
  detail::gatherElementDisplacements<Elem>(mesh, u, e, ue);
  const auto point = law.at(e);
  bool valid = true;
  detail::clearElement<Tangent>(fe, ke);
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], dn[n][dim], g[n][dim];
    const double w = detail::referencePoint<Elem>(q, sh, dn);
    const double det = detail::pointGeometry<Elem>(xe, dn, g);
    Mat<dim, dim> f = detail::displacementGradient<Elem>(ue, g);
    for (int i = 0; i < dim; ++i)
      f.m[i][i] += 1.0;
    if (!(det > 0.0) || !(determinant(f) > 0.0))
      valid = false;
    const double jw = thickness * w * det;
    const Mat<dim, dim> s = voigtToStress<dim>(point.stress(f));
    const Mat<dim, dim> p = matmul(f, s);
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < dim; ++i)
        fe[dim * a + i] += jw * detail::rowTimesGradient<dim>(p, i, g[a]);
    if (!Tangent)
      continue;
    const auto t = point.tangent(f);
    for (int b = 0; b < n; ++b) {
      double gs[dim]; // (g_b S)_j
      for (int j = 0; j < dim; ++j) {
        gs[j] = 0.0;
        for (int k = 0; k < dim; ++k)
          gs[j] += g[b][k] * s.m[k][j];
      }
      for (int m = 0; m < dim; ++m) {
        // dS = tangent(:, m dim + l) g_bl; dP = e_m (x) (g_b S) + F dS.
        Vector<nv> dsv{};
        for (int c = 0; c < nv; ++c)
          for (int l = 0; l < dim; ++l)
            dsv.v[c] += t.m[c][m * dim + l] * g[b][l];
        Mat<dim, dim> dp = matmul(f, voigtToStress<dim>(dsv));
        for (int j = 0; j < dim; ++j)
          dp.m[m][j] += gs[j];
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < dim; ++i)
            ke[dim * a + i][dim * b + m] += jw * detail::rowTimesGradient<dim>(dp, i, g[a]);
      }
    }
  }
  return valid;
}

/// Mixed (Hellinger-Reissner) element of a mixed point law (kernels/MixedPointPhysics.hpp) at
/// the unknowns x (FieldLayout<Dim>::kMixedUnknowns per node, interleaved: Dim displacements,
/// then the Voigt stress components) and, when Point::kPrestress, the nodal prestress tau (Voigt
/// size per node): ge(a, i) = t int P_ij g_aj da, ge(a, Dim + c) = t int psi_a r_c da, with the
/// point law's P and r of the displacement gradient h, the interpolated stress unknowns s and
/// prestress; and, when `Tangent`, the exact Jacobian ke = d ge / d x. The kinematics come from
/// Point::kCurrentConfiguration:
///  - false (total Lagrangian on X = mesh): h = du/dX; for delta u_b = unit vector m,
///    dh = e_m (x) g_b;
///  - true (updated Lagrangian on x = X + u): h = du/dx; dh = (I - h) dl with dl = e_m (x) g_b,
///    d(da) = da g_bm and d g_aj = -g_am g_bj, so the stress rows get P_ij (g_aj g_bm - g_am g_bj)
///    and the compatibility rows r_c g_bm.
/// The stress unknowns enter through psi_b: d/ds_(b,c) = psi_b d/ds_c. Returns false for an
/// inverted element (det of the integration map <= 0, or det(I + h) <= 0 in total Lagrangian).
/// mixedElementRows gives the rows of the test nodes first .. first + Rows - 1 only (ge and ke row
/// blocks, ke against every unknown of the element): the whole element for Rows = kNumNodes,
/// first = 0 (mixedElement), or one node's row block (Rows = 1) with per-thread memory
/// O(nd) instead of O(nd^2), at the price of the geometry and the point law once per block.
template <class Elem, bool Tangent, int Rows, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool
mixedElementRows(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness, const Law &law,
                 const Kokkos::View<const double *, MemorySpace> &x,
                 const Kokkos::View<const double *, MemorySpace> &tau, LocalIndex e, int first,
                 double (&ge)[LayoutOf<Elem>::kMixedUnknowns * Rows],
                 double (&ke)[LayoutOf<Elem>::kMixedUnknowns * Rows]
                             [LayoutOf<Elem>::kMixedUnknowns * Elem::kNumNodes]) {
  using L = LayoutOf<Elem>;
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nv = L::kNumStresses;
  constexpr int nu = L::kMixedUnknowns, so = L::kStressOffset;
  const auto point = law.at(e);
  using Point = decltype(point);
  constexpr bool current = Point::kCurrentConfiguration;
  double xe[n][dim], ue[n][dim], se[n][nv], te[n][nv];
  detail::gatherMixedElement<Elem, Point>(mesh, x, tau, e, xe, ue, se, te);
  bool valid = true;
  for (int i = 0; i < nu * Rows; ++i) {
    ge[i] = 0.0;
    if (Tangent)
      for (int j = 0; j < nu * n; ++j)
        ke[i][j] = 0.0;
  }
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], dn[n][dim], g[n][dim];
    const double w = detail::referencePoint<Elem>(q, sh, dn);
    const double det = detail::pointGeometry<Elem>(xe, dn, g);
    const double jw = thickness * w * det;
    const Mat<dim, dim> h = detail::displacementGradient<Elem>(ue, g);
    if (!(det > 0.0))
      valid = false;
    if (!current) {
      Mat<dim, dim> f = h;
      for (int i = 0; i < dim; ++i)
        f.m[i][i] += 1.0;
      if (!(determinant(f) > 0.0))
        valid = false;
    }
    Vector<nv> sv{}, tv{};
    for (int a = 0; a < n; ++a)
      for (int c = 0; c < nv; ++c) {
        sv.v[c] += sh[a] * se[a][c];
        tv.v[c] += sh[a] * te[a][c];
      }
    const MixedPointResponse<dim> r = point.template evaluate<Tangent>(h, sv, tv);
    for (int ar = 0; ar < Rows; ++ar) {
      const int a = first + ar;
      for (int i = 0; i < dim; ++i)
        ge[nu * ar + i] += jw * detail::rowTimesGradient<dim>(r.stress, i, g[a]);
      for (int c = 0; c < nv; ++c)
        ge[nu * ar + so + c] += jw * sh[a] * r.compatibility.v[c];
    }
    if (!Tangent)
      continue;
    // Derivatives along dl = d(delta u)/d(x or X): dh = A dl with A = I - h (current) or I.
    Mat<dim * dim, dim * dim> dp{}; // d P_ij / d dl_ml
    Mat<nv, dim * dim> dr{};        // d r_c / d dl_ml
    for (int m = 0; m < dim; ++m)
      for (int l = 0; l < dim; ++l)
        for (int k = 0; k < dim; ++k) {
          const double akm = current ? (k == m ? 1.0 : 0.0) - h.m[k][m] : (k == m ? 1.0 : 0.0);
          if (akm == 0.0)
            continue;
          for (int ij = 0; ij < dim * dim; ++ij)
            dp.m[ij][m * dim + l] += r.dStressDGrad.m[ij][k * dim + l] * akm;
          for (int c = 0; c < nv; ++c)
            dr.m[c][m * dim + l] += r.dCompatibilityDGrad.m[c][k * dim + l] * akm;
        }
    for (int b = 0; b < n; ++b)
      for (int m = 0; m < dim; ++m) {
        double dpb[dim][dim], drb[nv];
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) {
            double v = 0.0;
            for (int l = 0; l < dim; ++l)
              v += dp.m[i * dim + j][m * dim + l] * g[b][l];
            dpb[i][j] = v;
          }
        for (int c = 0; c < nv; ++c) {
          double v = current ? r.compatibility.v[c] * g[b][m] : 0.0;
          for (int l = 0; l < dim; ++l)
            v += dr.m[c][m * dim + l] * g[b][l];
          drb[c] = v;
        }
        for (int ar = 0; ar < Rows; ++ar) {
          const int a = first + ar;
          for (int i = 0; i < dim; ++i) {
            double v = 0.0;
            for (int j = 0; j < dim; ++j) {
              v += dpb[i][j] * g[a][j];
              if (current)
                v += r.stress.m[i][j] * (g[a][j] * g[b][m] - g[a][m] * g[b][j]);
            }
            ke[nu * ar + i][nu * b + m] += jw * v;
          }
          for (int c = 0; c < nv; ++c)
            ke[nu * ar + so + c][nu * b + m] += jw * sh[a] * drb[c];
        }
      }
    for (int ar = 0; ar < Rows; ++ar) {
      const int a = first + ar;
      double gps[dim][nv]; // sum_j d P_ij / d s_c g_aj
      for (int i = 0; i < dim; ++i)
        for (int c = 0; c < nv; ++c) {
          double v = 0.0;
          for (int j = 0; j < dim; ++j)
            v += r.dStressDStress.m[i * dim + j][c] * g[a][j];
          gps[i][c] = jw * v;
        }
      for (int b = 0; b < n; ++b) {
        for (int i = 0; i < dim; ++i)
          for (int c = 0; c < nv; ++c)
            ke[nu * ar + i][nu * b + so + c] += sh[b] * gps[i][c];
        const double v = jw * sh[a] * sh[b];
        for (int c = 0; c < nv; ++c)
          for (int k = 0; k < nv; ++k)
            ke[nu * ar + so + c][nu * b + so + k] += v * r.dCompatibilityDStress.m[c][k];
      }
    }
  }
  return valid;
}

/// The whole mixed element: mixedElementRows with every test node.
template <class Elem, bool Tangent, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool
mixedElement(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness, const Law &law,
             const Kokkos::View<const double *, MemorySpace> &x,
             const Kokkos::View<const double *, MemorySpace> &tau, LocalIndex e,
             double (&ge)[LayoutOf<Elem>::kMixedUnknowns * Elem::kNumNodes],
             double (&ke)[LayoutOf<Elem>::kMixedUnknowns * Elem::kNumNodes]
                         [LayoutOf<Elem>::kMixedUnknowns * Elem::kNumNodes]) {
  return mixedElementRows<Elem, Tangent, Elem::kNumNodes>(mesh, thickness, law, x, tau, e, 0, ge,
                                                          ke);
}

} // namespace mixcon
