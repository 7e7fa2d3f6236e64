// Geometrically nonlinear (updated-Lagrangian) element kernels of both models, with their exact
// tangents (derivations in docs/theory.md, section "Geometric nonlinearity"):
//  - displacement model: Cauchy stress from the Almansi strain of the total displacement,
//    sigma = C : e, e = (h + h^T - h^T h) / 2, h = du/dx (Eq. (26) corrected); internal force
//    t int B^T sigma da over the current configuration (F^sigma of Eq. (24)) and its exact
//    derivative (K^L + K^sigma plus the terms of the Almansi law's linearization; not symmetric);
//  - mixed model: the incremental Hellinger-Reissner residual relative to the last converged
//    configuration c1 with prestress tau (Eq. (9), (16)-(22) without the linearization (12)):
//    G_u = t int F Sigma grad(N) dA - F_ext, Sigma = tau + S, F = I + du/dX,
//    G_S = t int psi (E(u) - D S) dA, E the Green-Lagrange strain of the increment; its Jacobian
//    [K11(Sigma), K12(u); K12(u)^T, -M] is Eq. (30) at u = 0, S = 0;
//  - follower pressure on the current boundary and its load stiffness;
//  - the push-forward of the nodal 2nd Piola-Kirchhoff stress to Cauchy stress (Eq. (5b)).
// Element type is a template parameter; all device code, no virtual calls. Data flow:
// kernels -> solver.
#pragma once

#include <kernels/ElementDriver.hpp>
#include <kernels/GeometricStiffness.hpp>
#include <kernels/MixedElasticity.hpp>

namespace mixcon {

namespace detail {

/// h[i][j] = sum_a ue[a][i] g[a][j] (gradient of a nodal vector field).
template <int N>
KOKKOS_INLINE_FUNCTION void nodalGradient(const double (&ue)[N][2], const double (&g)[N][2],
                                          double (&h)[2][2]) {
  h[0][0] = h[0][1] = h[1][0] = h[1][1] = 0.0;
  for (int a = 0; a < N; ++a)
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        h[i][j] += ue[a][i] * g[a][j];
}

/// Almansi strain e = (h + h^T - h^T h) / 2 of the spatial displacement gradient h = du/dx.
KOKKOS_INLINE_FUNCTION void almansiStrain(const double (&h)[2][2], double (&e)[2][2]) {
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      e[i][j] = 0.5 * (h[i][j] + h[j][i] - h[0][i] * h[0][j] - h[1][i] * h[1][j]);
}

/// Voigt (xx, yy, engineering xy) of a symmetric tensor and C times it as a tensor.
KOKKOS_INLINE_FUNCTION void stressFromStrainTensor(const PlaneMatrix &c, const double (&e)[2][2],
                                                   double (&s)[2][2]) {
  const double ev[3] = {e[0][0], e[1][1], e[0][1] + e[1][0]};
  double sv[3];
  for (int r = 0; r < 3; ++r)
    sv[r] = c.m[r][0] * ev[0] + c.m[r][1] * ev[1] + c.m[r][2] * ev[2];
  s[0][0] = sv[0];
  s[1][1] = sv[1];
  s[0][1] = s[1][0] = sv[2];
}

/// Green-Lagrange strain E = (F^T F - I) / 2 of a deformation gradient F.
KOKKOS_INLINE_FUNCTION void greenStrain(const double (&f)[2][2], double (&e)[2][2]) {
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      e[i][j] = 0.5 * (f[0][i] * f[0][j] + f[1][i] * f[1][j] - (i == j ? 1.0 : 0.0));
}

/// Cauchy stress of the St. Venant-Kirchhoff law from the spatial displacement gradient h =
/// du/dx: F = (I - h)^-1, E = (F^T F - I) / 2, S = C : E, sigma = F S F^T / det F.
KOKKOS_INLINE_FUNCTION void
svkCauchyFromSpatialGradient(const PlaneMatrix &c, const double (&h)[2][2], double (&s)[2][2]) {
  const double fi[2][2] = {{1.0 - h[0][0], -h[0][1]}, {-h[1][0], 1.0 - h[1][1]}}; // F^-1
  const double di = fi[0][0] * fi[1][1] - fi[0][1] * fi[1][0];
  const double f[2][2] = {{fi[1][1] / di, -fi[0][1] / di}, {-fi[1][0] / di, fi[0][0] / di}};
  double e[2][2], pk2[2][2];
  greenStrain(f, e);
  stressFromStrainTensor(c, e, pk2);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      double v = 0.0;
      for (int k = 0; k < 2; ++k)
        for (int l = 0; l < 2; ++l)
          v += f[i][k] * pk2[k][l] * f[j][l];
      s[i][j] = v * di; // 1 / det F = det F^-1
    }
}

/// Element nodal coordinates x = X + u (current configuration) and displacements.
template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
gatherCurrent(const MeshView<MemorySpace> &m, const Kokkos::View<const double *, MemorySpace> &u,
              LocalIndex e, double (&xe)[Elem::kNumNodes][2], double (&ue)[Elem::kNumNodes][2]) {
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    const LocalIndex n = m.connectivity(e, a);
    for (int i = 0; i < 2; ++i) {
      ue[a][i] = u(2 * n + i);
      xe[a][i] = m.coordinates(n, i) + ue[a][i];
    }
  }
}

/// Kinematics and Almansi-law stress at quadrature point q of an element with current nodal
/// coordinates xe and displacements ue: shape functions, gradients g on the current
/// configuration, h = du/dx, Almansi strain es and C es; returns the integration weight da
/// (thickness times w det); `valid` is cleared for a non-positive Jacobian.
template <class Elem>
KOKKOS_INLINE_FUNCTION double
almansiPoint(int q, const double (&xe)[Elem::kNumNodes][2], const double (&ue)[Elem::kNumNodes][2],
             const PlaneMatrix &c, double thickness, double (&sh)[Elem::kNumNodes],
             double (&g)[Elem::kNumNodes][2], double (&h)[2][2], double (&es)[2][2],
             double (&s)[2][2], bool &valid) {
  double xi, eta, w, dn[Elem::kNumNodes][2];
  Elem::quadraturePoint(q, xi, eta, w);
  Elem::shape(xi, eta, sh, dn);
  const double det = physicalGradients<Elem>(xe, dn, g);
  if (!(det > 0.0))
    valid = false;
  nodalGradient<Elem::kNumNodes>(ue, g, h);
  almansiStrain(h, es);
  stressFromStrainTensor(c, es, s);
  return thickness * w * det;
}

/// Variation of the Almansi strain for the perturbation delta u_b = unit vector m
/// (dl[k][l] = delta_km g_bl): de = sym(dl) - (dl^T e + e dl).
KOKKOS_INLINE_FUNCTION void almansiVariation(const double (&gb)[2], int m, const double (&es)[2][2],
                                             double (&de)[2][2]) {
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l)
      de[k][l] = 0.5 * ((k == m ? gb[l] : 0.0) + (l == m ? gb[k] : 0.0)) - gb[k] * es[m][l] -
                 es[k][m] * gb[l];
}

} // namespace detail

/// The Almansi point law of the displacement model for the element driver: element e's
/// AlmansiPoint with its material's plane stiffness [C].
template <class MemorySpace> struct AlmansiLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<PlaneMatrix *, MemorySpace> stiffness;
  KOKKOS_INLINE_FUNCTION AlmansiPoint<2> at(LocalIndex e) const {
    return AlmansiPoint<2>{stiffness(material(e))};
  }
};

/// Displacement model, element e: internal force fe = t int B^T sigma da on the current
/// configuration x = X + u (X: d.mesh) and, when `Tangent`, its exact derivative ke = d fe / du
/// (the element driver's spatialElement with the Almansi point law). Returns false when the
/// current element is inverted (det dx/dxi <= 0 at a quadrature point).
template <class Elem, bool Tangent, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool almansiElement(const ElementData<MemorySpace> &d,
                                           const Kokkos::View<const double *, MemorySpace> &u,
                                           LocalIndex e, double (&fe)[2 * Elem::kNumNodes],
                                           double (&ke)[2 * Elem::kNumNodes][2 * Elem::kNumNodes]) {
  return spatialElement<Elem, Tangent>(
      d.mesh, d.thickness, AlmansiLaw<MemorySpace>{d.material, d.stiffness}, u, e, fe, ke);
}

/// The St. Venant-Kirchhoff point law of the displacement model for the element driver: element
/// e's SaintVenantKirchhoffPoint with its material's plane stiffness [C].
template <class MemorySpace> struct SaintVenantKirchhoffLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<PlaneMatrix *, MemorySpace> stiffness;
  KOKKOS_INLINE_FUNCTION SaintVenantKirchhoffPoint<2> at(LocalIndex e) const {
    return SaintVenantKirchhoffPoint<2>{stiffness(material(e))};
  }
};

/// Displacement model with the St. Venant-Kirchhoff law, element e, total Lagrangian on the
/// reference configuration X (d.mesh): fe = t int P grad_X(N) dA, P = F S, S = C : E,
/// E = (F^T F - I) / 2, F = I + du/dX (the same internal force as t int B^T sigma da with
/// sigma = F S F^T / J); ke = d fe / du exactly (material part with dE = sym(F^T dF), geometric
/// part dF S): the element driver's materialElement with the St. Venant-Kirchhoff point law.
/// Returns false for an inverted element.
template <class Elem, bool Tangent, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool svkElement(const ElementData<MemorySpace> &d,
                                       const Kokkos::View<const double *, MemorySpace> &u,
                                       LocalIndex e, double (&fe)[2 * Elem::kNumNodes],
                                       double (&ke)[2 * Elem::kNumNodes][2 * Elem::kNumNodes]) {
  return materialElement<Elem, Tangent>(
      d.mesh, d.thickness, SaintVenantKirchhoffLaw<MemorySpace>{d.material, d.stiffness}, u, e, fe,
      ke);
}

/// Cauchy stress of `law` from the spatial displacement gradient h = du/dx.
KOKKOS_INLINE_FUNCTION void cauchyFromSpatialGradient(ElasticLaw law, const PlaneMatrix &c,
                                                      const double (&h)[2][2], double (&s)[2][2]) {
  if (law == ElasticLaw::SaintVenantKirchhoff) {
    detail::svkCauchyFromSpatialGradient(c, h, s);
  } else {
    double es[2][2];
    detail::almansiStrain(h, es);
    detail::stressFromStrainTensor(c, es, s);
  }
}

/// Cauchy stress (Almansi law) of total displacements u at natural point (xi, eta) of element e
/// (a functor for recoverNodalStress).
template <class Elem, class MemorySpace> struct AlmansiPointStress {
  ElementData<MemorySpace> d;
  Kokkos::View<const double *, MemorySpace> u;
  ElasticLaw law = ElasticLaw::Almansi;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex e, double xi, double eta,
                                         double (&sig)[3]) const {
    constexpr int n = Elem::kNumNodes;
    double xe[n][2], ue[n][2], sh[n], dn[n][2], g[n][2], h[2][2], s[2][2];
    detail::gatherCurrent<Elem>(d.mesh, u, e, xe, ue);
    Elem::shape(xi, eta, sh, dn);
    physicalGradients<Elem>(xe, dn, g);
    detail::nodalGradient<n>(ue, g, h);
    cauchyFromSpatialGradient(law, d.stiffness(d.material(e)), h, s);
    sig[0] = s[0][0];
    sig[1] = s[1][1];
    sig[2] = s[0][1];
  }
};

/// Cauchy stress (Almansi law) and spatial displacement gradient du/dx at every quadrature point
/// for total displacements u: stress(e, q, 0..2) = (xx, yy, xy), grad(e, q, 0..3) = (du/dx,
/// du/dy, dv/dx, dv/dy); xq(e, q, 0..1) the current quadrature-point coordinates.
template <class Elem, class ExecSpace, class MemorySpace>
void almansiGaussPointStress(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                             const Kokkos::View<const double *, MemorySpace> &u,
                             const Kokkos::View<double **[3], MemorySpace> &stress,
                             const Kokkos::View<double **[4], MemorySpace> &grad,
                             const Kokkos::View<double **[2], MemorySpace> &xq,
                             ElasticLaw law = ElasticLaw::Almansi) {
  Kokkos::parallel_for(
      "mixcon::kernels::almansiGaussPointStress",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes;
        double xe[n][2], ue[n][2];
        detail::gatherCurrent<Elem>(d.mesh, u, e, xe, ue);
        const PlaneMatrix c = d.stiffness(d.material(e));
        bool valid = true;
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double sh[n], g[n][2], h[2][2], es[2][2], s[2][2];
          detail::almansiPoint<Elem>(q, xe, ue, c, d.thickness, sh, g, h, es, s, valid);
          if (law != ElasticLaw::Almansi)
            cauchyFromSpatialGradient(law, c, h, s);
          stress(e, q, 0) = s[0][0];
          stress(e, q, 1) = s[1][1];
          stress(e, q, 2) = s[0][1];
          grad(e, q, 0) = h[0][0];
          grad(e, q, 1) = h[0][1];
          grad(e, q, 2) = h[1][0];
          grad(e, q, 3) = h[1][1];
          double x = 0.0, y = 0.0;
          for (int a = 0; a < n; ++a) {
            x += sh[a] * xe[a][0];
            y += sh[a] * xe[a][1];
          }
          xq(e, q, 0) = x;
          xq(e, q, 1) = y;
        }
      });
}

/// Nodal stresses s (3 per node) interpolated with the shape functions at every quadrature point:
/// out(e, q, 0..2).
template <class Elem, class ExecSpace, class MemorySpace>
void interpolateNodalStress(const ExecSpace &exec, const MeshView<MemorySpace> &mesh,
                            const Kokkos::View<const double *, MemorySpace> &s,
                            const Kokkos::View<double **[3], MemorySpace> &out) {
  const NodalStressField<MemorySpace> field{mesh, s};
  Kokkos::parallel_for(
      "mixcon::kernels::interpolateNodalStress",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double xi, eta, w, sh[Elem::kNumNodes], dn[Elem::kNumNodes][2], t[3];
          Elem::quadraturePoint(q, xi, eta, w);
          Elem::shape(xi, eta, sh, dn);
          field(e, q, sh, t);
          for (int c = 0; c < 3; ++c)
            out(e, q, c) = t[c];
        }
      });
}

/// Adds an element matrix with `Ndof` interleaved unknowns per node into `a` (pattern from
/// expandGraph(graph, Ndof)) through the scatter map of the graph.
template <int Ndof, class Elem, class MemorySpace, class Map>
KOKKOS_INLINE_FUNCTION void
scatterBlockMatrix(const CsrMatrix<MemorySpace> &a, const Map &map, const MeshView<MemorySpace> &m,
                   LocalIndex e,
                   const double (&ke)[Ndof * Elem::kNumNodes][Ndof * Elem::kNumNodes]) {
  for (int p = 0; p < Elem::kNumNodes; ++p) {
    const LocalIndex row = m.connectivity(e, p);
    for (int i = 0; i < Ndof; ++i) {
      const Offset start = a.rowOffsets(Ndof * row + i);
      for (int b = 0; b < Elem::kNumNodes; ++b) {
        const Offset k = start + Ndof * map(e, p, b);
        for (int j = 0; j < Ndof; ++j)
          Kokkos::atomic_add(&a.values(k + j), ke[Ndof * p + i][Ndof * b + j]);
      }
    }
  }
}

/// Fused residual + tangent assembly shared by the nonlinear models: `kernel.template
/// compute<Tangent>(e, ge, ke)` gives element e's residual and (when Tangent) matrix with `Ndof`
/// interleaved unknowns per node; g += residuals (atomics), a += matrices when a.numRows > 0
/// (scatter map `map`). Returns the first element the kernel reports inverted, or -1.
/// Per-thread memory: ke[nd][nd] with nd = Ndof kNumNodes, 8 nd^2 bytes: mixed model (Ndof =
/// 5 in 2D, 9 in 3D) 3.2 KB for Quad4, 12.8 KB for Quad8, 41.5 KB for Hex8 and 259 KB for
/// Hex20; the displacement model 0.5 KB (Quad4), 2 KB (Quad8), 4.6 KB (Hex8), 29 KB (Hex20).
/// assembleNonlinearRows needs one node's row block only (8 Ndof nd bytes: mixed Quad8 1.6 KB,
/// Hex8 5.2 KB, Hex20 13 KB).
template <int Ndof, class Elem, class ExecSpace, class MemorySpace, class Kernel, class Map>
LocalIndex assembleNonlinear(const ExecSpace &exec, const MeshView<MemorySpace> &mesh,
                             const Kernel &kernel, const Map &map, const CsrMatrix<MemorySpace> &a,
                             const Kokkos::View<double *, MemorySpace> &g) {
  LocalIndex inverted = -1;
  const bool tangent = a.numRows > 0;
  Kokkos::parallel_reduce(
      "mixcon::kernels::assembleNonlinear",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e, LocalIndex & first) {
        constexpr int nd = Ndof * Elem::kNumNodes;
        double ge[nd], ke[nd][nd];
        const bool ok = tangent ? kernel.template compute<true>(e, ge, ke)
                                : kernel.template compute<false>(e, ge, ke);
        if (!ok && e < first)
          first = e;
        for (int p = 0; p < Elem::kNumNodes; ++p) {
          const LocalIndex node = mesh.connectivity(e, p);
          for (int i = 0; i < Ndof; ++i)
            Kokkos::atomic_add(&g(Ndof * node + i), ge[Ndof * p + i]);
        }
        if (tangent)
          scatterBlockMatrix<Ndof, Elem>(a, map, mesh, e, ke);
      },
      Kokkos::Min<LocalIndex>(inverted));
  return inverted == Kokkos::reduction_identity<LocalIndex>::min() ? -1 : inverted;
}

/// assembleNonlinear with the Jacobian produced and scattered one test node (row block) at a
/// time: `kernel.template computeRows<Tangent, Rows>(e, first, ge, ke)` gives the rows of the
/// test nodes first .. first + Rows - 1 (ge[Ndof Rows], ke[Ndof Rows][Ndof kNumNodes]). With a
/// tangent, each thread computes its element's kNumNodes row blocks one after another (the
/// geometry and the point law once per block), so that it holds Ndof x nd doubles instead of
/// nd x nd; the residual alone is one pass. Same results as assembleNonlinear up to rounding of
/// the atomics' order.
template <int Ndof, class Elem, class ExecSpace, class MemorySpace, class Kernel, class Map>
LocalIndex assembleNonlinearRows(const ExecSpace &exec, const MeshView<MemorySpace> &mesh,
                                 const Kernel &kernel, const Map &map,
                                 const CsrMatrix<MemorySpace> &a,
                                 const Kokkos::View<double *, MemorySpace> &g) {
  LocalIndex inverted = -1;
  const bool tangent = a.numRows > 0;
  Kokkos::parallel_reduce(
      "mixcon::kernels::assembleNonlinearRows",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e, LocalIndex & first) {
        constexpr int n = Elem::kNumNodes, nd = Ndof * n;
        if (!tangent) {
          double ge[nd], ke[nd][nd]; // ke is not touched without a tangent
          if (!kernel.template computeRows<false, n>(e, 0, ge, ke) && e < first)
            first = e;
          for (int p = 0; p < n; ++p) {
            const LocalIndex node = mesh.connectivity(e, p);
            for (int i = 0; i < Ndof; ++i)
              Kokkos::atomic_add(&g(Ndof * node + i), ge[Ndof * p + i]);
          }
          return;
        }
        for (int p = 0; p < n; ++p) {
          double ge[Ndof], ke[Ndof][nd];
          if (!kernel.template computeRows<true, 1>(e, p, ge, ke) && e < first)
            first = e;
          const LocalIndex row = mesh.connectivity(e, p);
          for (int i = 0; i < Ndof; ++i) {
            Kokkos::atomic_add(&g(Ndof * row + i), ge[i]);
            const Offset start = a.rowOffsets(Ndof * row + i);
            for (int b = 0; b < n; ++b) {
              const Offset k = start + Ndof * map(e, p, b);
              for (int j = 0; j < Ndof; ++j)
                Kokkos::atomic_add(&a.values(k + j), ke[i][Ndof * b + j]);
            }
          }
        }
      },
      Kokkos::Min<LocalIndex>(inverted));
  return inverted == Kokkos::reduction_identity<LocalIndex>::min() ? -1 : inverted;
}

/// Element kernel of the displacement model for assembleNonlinear (almansiElement).
template <class Elem, class MemorySpace> struct AlmansiKernel {
  ElementData<MemorySpace> d;
  Kokkos::View<const double *, MemorySpace> u;
  template <bool Tangent>
  KOKKOS_INLINE_FUNCTION bool
  compute(LocalIndex e, double (&fe)[2 * Elem::kNumNodes],
          double (&ke)[2 * Elem::kNumNodes][2 * Elem::kNumNodes]) const {
    return almansiElement<Elem, Tangent>(d, u, e, fe, ke);
  }
};

/// Element kernel of the displacement model with the St. Venant-Kirchhoff law (svkElement).
template <class Elem, class MemorySpace> struct SvkKernel {
  ElementData<MemorySpace> d;
  Kokkos::View<const double *, MemorySpace> u;
  template <bool Tangent>
  KOKKOS_INLINE_FUNCTION bool
  compute(LocalIndex e, double (&fe)[2 * Elem::kNumNodes],
          double (&ke)[2 * Elem::kNumNodes][2 * Elem::kNumNodes]) const {
    return svkElement<Elem, Tangent>(d, u, e, fe, ke);
  }
};

/// Displacement model: f += internal force of every element at total displacement u, and, when
/// `a.numRows > 0`, a += tangent (2 dofs per node, scatter map `map`). Returns the first
/// inverted element, or -1.
template <class Elem, class ExecSpace, class MemorySpace, class Map>
LocalIndex assembleAlmansi(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                           const Kokkos::View<const double *, MemorySpace> &u, const Map &map,
                           const CsrMatrix<MemorySpace> &a,
                           const Kokkos::View<double *, MemorySpace> &f) {
  return assembleNonlinear<2, Elem>(exec, d.mesh, AlmansiKernel<Elem, MemorySpace>{d, u}, map, a,
                                    f);
}

/// How the mixed assemblies produce the Jacobian: the whole element matrix per thread
/// (assembleNonlinear, the default: measured faster in 2D), or one test node's row block at a
/// time (assembleNonlinearRows: per-thread memory O(Ndof nd) instead of O(nd^2), for elements
/// whose nd^2 does not fit a GPU thread).
enum class MixedJacobianBlocks { Element, NodeRows };

/// The incremental Hellinger-Reissner point law of the mixed model for the element driver:
/// element e's MixedIncrementPoint with its material's plane stiffness [C] and compliance [D]
/// and the stabilization a.
template <class MemorySpace> struct MixedIncrementLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<PlaneMatrix *, MemorySpace> stiffness, compliance;
  double a = 0.0;
  KOKKOS_INLINE_FUNCTION MixedIncrementPoint<2> at(LocalIndex e) const {
    const int k = material(e);
    return MixedIncrementPoint<2>{stiffness(k), compliance(k), a};
  }
};

/// The current-configuration Hellinger-Reissner point law of the mixed model for the element
/// driver: element e's MixedCurrentPoint with its material's [C], [D] and the stabilization a.
template <class MemorySpace> struct MixedCurrentLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<PlaneMatrix *, MemorySpace> stiffness, compliance;
  double a = 0.0;
  KOKKOS_INLINE_FUNCTION MixedCurrentPoint<2> at(LocalIndex e) const {
    const int k = material(e);
    return MixedCurrentPoint<2>{stiffness(k), compliance(k), a};
  }
};

/// Mixed model, element e: the incremental Hellinger-Reissner residual ge (5 per node: G_u x, y,
/// G_S xx, yy, xy; without external loads) at increment (u, S) from configuration c1 (d.mesh)
/// with nodal prestress tau, and when `Tangent` its Jacobian ke:
/// G_u = t int F Sigma grad(N) dA, G_S = t int psi (1 - a) (E(u) - D S) dA. With stabilization
/// a > 0 the equilibrium stress is Sigma = tau + (1 - a) S + a C E(u) and the stress equations
/// are scaled by (1 - a): the nonlinear form of the linear model's a Kd + (1 - a) K12 M^-1 K12^T
/// (a = 0: the report's model). The element driver's mixedElement with MixedIncrementPoint
/// (total Lagrangian on c1). Returns false for an inverted element (in c1 or in the incremented
/// configuration).
template <class Elem, bool Tangent, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool mixedIncrementElement(
    const MixedElementData<MemorySpace> &d, const Kokkos::View<const double *, MemorySpace> &tau,
    const Kokkos::View<const double *, MemorySpace> &x, double a, LocalIndex e,
    double (&ge)[5 * Elem::kNumNodes], double (&ke)[5 * Elem::kNumNodes][5 * Elem::kNumNodes]) {
  return mixedElement<Elem, Tangent>(
      d.mesh, d.thickness, MixedIncrementLaw<MemorySpace>{d.material, d.stiffness, d.compliance, a},
      x, tau, e, ge, ke);
}

/// Mixed model in the current configuration (the default form, path independent): unknowns the
/// total displacement u and the nodal Cauchy stress tau (5 per node in x), reference geometry
/// d.mesh, current x = X + u. Residual ge: G_u = t int B(x)^T [(1 - a) tau + a C e(u)] da,
/// G_S = (1 - a) t int psi (e(u) - D tau) da with e the Almansi strain of the total
/// displacement (the displacement model's law, imposed weakly); Jacobian ke exact (not
/// symmetric). At u = 0 it is the linear model; its Newton step from any state is Eq. (30) with
/// the 2nd Piola-Kirchhoff increment pushed forward to first order (docs/theory.md). The element
/// driver's mixedElement with MixedCurrentPoint (updated Lagrangian).
template <class Elem, bool Tangent, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool
mixedCurrentElement(const MixedElementData<MemorySpace> &d,
                    const Kokkos::View<const double *, MemorySpace> &x, double a, LocalIndex e,
                    double (&ge)[5 * Elem::kNumNodes],
                    double (&ke)[5 * Elem::kNumNodes][5 * Elem::kNumNodes]) {
  return mixedElement<Elem, Tangent>(
      d.mesh, d.thickness, MixedCurrentLaw<MemorySpace>{d.material, d.stiffness, d.compliance, a},
      x, Kokkos::View<const double *, MemorySpace>(), e, ge, ke);
}

/// Element kernel of the mixed model's current form for assembleNonlinear.
template <class Elem, class MemorySpace> struct MixedCurrentKernel {
  MixedElementData<MemorySpace> d;
  Kokkos::View<const double *, MemorySpace> x;
  double stabilization;
  template <bool Tangent>
  KOKKOS_INLINE_FUNCTION bool
  compute(LocalIndex e, double (&ge)[5 * Elem::kNumNodes],
          double (&ke)[5 * Elem::kNumNodes][5 * Elem::kNumNodes]) const {
    return mixedCurrentElement<Elem, Tangent>(d, x, stabilization, e, ge, ke);
  }
  template <bool Tangent, int Rows>
  KOKKOS_INLINE_FUNCTION bool computeRows(LocalIndex e, int first, double (&ge)[5 * Rows],
                                          double (&ke)[5 * Rows][5 * Elem::kNumNodes]) const {
    return mixedElementRows<Elem, Tangent, Rows>(
        d.mesh, d.thickness,
        MixedCurrentLaw<MemorySpace>{d.material, d.stiffness, d.compliance, stabilization}, x,
        Kokkos::View<const double *, MemorySpace>(), e, first, ge, ke);
  }
};

/// Mixed model in the current configuration: g += residual of every element, a += Jacobian when
/// a.numRows > 0 (5 unknowns per node; `blocks`: see MixedJacobianBlocks). Returns the first
/// inverted element, or -1.
template <class Elem, class ExecSpace, class MemorySpace, class Map>
LocalIndex assembleMixedCurrent(const ExecSpace &exec, const MixedElementData<MemorySpace> &d,
                                const Kokkos::View<const double *, MemorySpace> &x,
                                double stabilization, const Map &map,
                                const CsrMatrix<MemorySpace> &a,
                                const Kokkos::View<double *, MemorySpace> &g,
                                MixedJacobianBlocks blocks = MixedJacobianBlocks::Element) {
  const MixedCurrentKernel<Elem, MemorySpace> kernel{d, x, stabilization};
  return blocks == MixedJacobianBlocks::NodeRows
             ? assembleNonlinearRows<5, Elem>(exec, d.mesh, kernel, map, a, g)
             : assembleNonlinear<5, Elem>(exec, d.mesh, kernel, map, a, g);
}

/// Element kernel of the mixed model's incremental form for assembleNonlinear.
template <class Elem, class MemorySpace> struct MixedIncrementKernel {
  MixedElementData<MemorySpace> d;
  Kokkos::View<const double *, MemorySpace> tau, x;
  double stabilization;
  template <bool Tangent>
  KOKKOS_INLINE_FUNCTION bool
  compute(LocalIndex e, double (&ge)[5 * Elem::kNumNodes],
          double (&ke)[5 * Elem::kNumNodes][5 * Elem::kNumNodes]) const {
    return mixedIncrementElement<Elem, Tangent>(d, tau, x, stabilization, e, ge, ke);
  }
  template <bool Tangent, int Rows>
  KOKKOS_INLINE_FUNCTION bool computeRows(LocalIndex e, int first, double (&ge)[5 * Rows],
                                          double (&ke)[5 * Rows][5 * Elem::kNumNodes]) const {
    return mixedElementRows<Elem, Tangent, Rows>(
        d.mesh, d.thickness,
        MixedIncrementLaw<MemorySpace>{d.material, d.stiffness, d.compliance, stabilization}, x,
        tau, e, first, ge, ke);
  }
};

/// Mixed model: g += the incremental residual of every element (5 unknowns per node, interleaved
/// u, v, Sxx, Syy, Sxy; stabilization a as in mixedIncrementElement) and, when `a.numRows > 0`, a
/// += its Jacobian (`blocks`: see MixedJacobianBlocks). Returns the first inverted element, or
/// -1.
template <class Elem, class ExecSpace, class MemorySpace, class Map>
LocalIndex assembleMixedIncrement(const ExecSpace &exec, const MixedElementData<MemorySpace> &d,
                                  const Kokkos::View<const double *, MemorySpace> &tau,
                                  const Kokkos::View<const double *, MemorySpace> &x,
                                  double stabilization, const Map &map,
                                  const CsrMatrix<MemorySpace> &a,
                                  const Kokkos::View<double *, MemorySpace> &g,
                                  MixedJacobianBlocks blocks = MixedJacobianBlocks::Element) {
  const MixedIncrementKernel<Elem, MemorySpace> kernel{d, tau, x, stabilization};
  return blocks == MixedJacobianBlocks::NodeRows
             ? assembleNonlinearRows<5, Elem>(exec, d.mesh, kernel, map, a, g)
             : assembleNonlinear<5, Elem>(exec, d.mesh, kernel, map, a, g);
}

/// Follower pressure p (positive into the body) on element edges, on the current configuration:
/// nodal coordinates m.coordinates + u (u: displacement dofs `Ndof * node + i` of `u`).
/// Adds -f_ext to g (the residual is internal minus external force) and, when mat.numRows > 0,
/// the load stiffness -d f_ext / du to mat. The pressure force is linear in the nodal positions:
/// f_a = -p t int N_a (dy/ds, -dx/ds) ds.
template <int Ndof, class Elem, class ExecSpace, class MemorySpace, class Map>
void assembleFollowerPressure(const ExecSpace &exec, const MeshView<MemorySpace> &m,
                              const Kokkos::View<const double *, MemorySpace> &u,
                              const Kokkos::View<LocalIndex *[2], MemorySpace> &edges,
                              const Kokkos::View<const double *, MemorySpace> &pressure,
                              double scale, double thickness, const Map &map,
                              const CsrMatrix<MemorySpace> &mat,
                              const Kokkos::View<double *, MemorySpace> &g) {
  const bool tangent = mat.numRows > 0;
  Kokkos::parallel_for(
      "mixcon::kernels::followerPressure", Kokkos::RangePolicy<ExecSpace>(exec, 0, edges.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        constexpr int ne = Elem::kNodesPerEdge;
        const LocalIndex e = edges(k, 0);
        const int edge = edges(k, 1);
        const double p = scale * pressure(k) * thickness;
        int local[ne];
        LocalIndex nodes[ne];
        double xe[ne][2], fe[ne][2] = {}, kab[ne][ne] = {};
        for (int a = 0; a < ne; ++a) {
          local[a] = Elem::edgeNode(edge, a);
          nodes[a] = m.connectivity(e, local[a]);
          for (int i = 0; i < 2; ++i)
            xe[a][i] = m.coordinates(nodes[a], i) + u(Ndof * nodes[a] + i);
        }
        for (int q = 0; q < Elem::kNumEdgeQp; ++q) {
          double s, w, sh[ne], ds[ne];
          detail::gauss1d(Elem::kNumEdgeQp, q, s, w);
          edgeShape<ne>(s, sh, ds);
          double tx = 0.0, ty = 0.0;
          for (int a = 0; a < ne; ++a) {
            tx += ds[a] * xe[a][0];
            ty += ds[a] * xe[a][1];
          }
          for (int a = 0; a < ne; ++a) {
            fe[a][0] -= p * w * sh[a] * ty;
            fe[a][1] += p * w * sh[a] * tx;
            for (int b = 0; b < ne; ++b)
              kab[a][b] += p * w * sh[a] * ds[b];
          }
        }
        for (int a = 0; a < ne; ++a)
          for (int i = 0; i < 2; ++i)
            Kokkos::atomic_add(&g(Ndof * nodes[a] + i), -fe[a][i]);
        if (!tangent)
          return;
        // -d f_ax / d y_b = p t int N_a dN_b/ds, -d f_ay / d x_b = -p t int N_a dN_b/ds.
        for (int a = 0; a < ne; ++a)
          for (int b = 0; b < ne; ++b) {
            const Offset base = Ndof * map(e, local[a], local[b]);
            Kokkos::atomic_add(&mat.values(mat.rowOffsets(Ndof * nodes[a]) + base + 1), kab[a][b]);
            Kokkos::atomic_add(&mat.values(mat.rowOffsets(Ndof * nodes[a] + 1) + base), -kab[a][b]);
          }
      });
}

/// Right-hand side of the L2 projection of the pushed-forward stress onto the nodal stress space
/// of the new configuration c2: b(3 k + c) = t int_c2 psi_k tau2_c da = t int_c1 psi_k
/// (F Sigma F^T)_c dA (the Jacobian J of tau2 = F Sigma F^T / J cancels against da = J dA), with
/// Sigma = tau + S interpolated and F = I + du/dX1 at the quadrature points of c1 (d.mesh).
template <class Elem, class ExecSpace, class MemorySpace>
void pushForwardProjectionLoad(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                               const Kokkos::View<const double *, MemorySpace> &tau,
                               const Kokkos::View<const double *, MemorySpace> &x,
                               const Kokkos::View<double *, MemorySpace> &b) {
  Kokkos::parallel_for(
      "mixcon::kernels::pushForwardProjectionLoad",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes;
        double xe[n][2], ue[n][2], be[n][3] = {};
        detail::gatherCoordinates<Elem>(d.mesh, e, xe);
        LocalIndex nodes[n];
        for (int a = 0; a < n; ++a) {
          nodes[a] = d.mesh.connectivity(e, a);
          ue[a][0] = x(5 * nodes[a]);
          ue[a][1] = x(5 * nodes[a] + 1);
        }
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double xi, eta, w, sh[n], dn[n][2], g[n][2], h[2][2];
          Elem::quadraturePoint(q, xi, eta, w);
          Elem::shape(xi, eta, sh, dn);
          const double jw = d.thickness * w * physicalGradients<Elem>(xe, dn, g);
          detail::nodalGradient<n>(ue, g, h);
          const double f[2][2] = {{1.0 + h[0][0], h[0][1]}, {h[1][0], 1.0 + h[1][1]}};
          double sv[3] = {};
          for (int a = 0; a < n; ++a)
            for (int c = 0; c < 3; ++c)
              sv[c] += sh[a] * (tau(3 * nodes[a] + c) + x(5 * nodes[a] + 2 + c));
          const double sig[2][2] = {{sv[0], sv[2]}, {sv[2], sv[1]}};
          double k[2][2];
          for (int i = 0; i < 2; ++i)
            for (int l = 0; l < 2; ++l) {
              double v = 0.0;
              for (int p = 0; p < 2; ++p)
                for (int r = 0; r < 2; ++r)
                  v += f[i][p] * sig[p][r] * f[l][r];
              k[i][l] = v;
            }
          for (int a = 0; a < n; ++a) {
            be[a][0] += jw * sh[a] * k[0][0];
            be[a][1] += jw * sh[a] * k[1][1];
            be[a][2] += jw * sh[a] * k[0][1];
          }
        }
        for (int a = 0; a < n; ++a)
          for (int c = 0; c < 3; ++c)
            Kokkos::atomic_add(&b(3 * nodes[a] + c), be[a][c]);
      });
}

/// Adds the scalar consistent mass t int psi_a psi_b da of every element into `a` (1 dof per
/// node, pattern expandGraph(graph, 1)).
template <class Elem, class ExecSpace, class MemorySpace, class Map>
void assembleScalarMass(const ExecSpace &exec, const MeshView<MemorySpace> &mesh, double thickness,
                        const Map &map, const CsrMatrix<MemorySpace> &a) {
  Kokkos::parallel_for(
      "mixcon::kernels::assembleScalarMass",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes;
        double gx[n][n], gy[n][n], m[n][n];
        mixedIntegrals<Elem>(mesh, e, thickness, gx, gy, m);
        scatterBlockMatrix<1, Elem>(a, map, mesh, e, m);
      });
}

/// Push-forward of the nodal stresses at the end of a mixed increment (Eq. (9), (5b)):
/// tau <- F (tau + S) F^T / det F with F = I + du/dX1 averaged over the elements sharing each
/// node (each element's gradient evaluated at the node). x holds (u, v, Sxx, Syy, Sxy) per node.
template <class Elem, class ExecSpace, class MemorySpace>
void pushForwardNodalStress(const ExecSpace &exec, const MeshView<MemorySpace> &m,
                            const Kokkos::View<const double *, MemorySpace> &x,
                            const Kokkos::View<double *, MemorySpace> &tau) {
  const LocalIndex nn = m.coordinates.extent(0);
  Kokkos::View<double *[5], MemorySpace> acc("mixcon::kernels::nodalDeformationGradient", nn);
  Kokkos::parallel_for(
      "mixcon::kernels::nodalDeformationGradient",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, m.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes;
        double xe[n][2], ue[n][2];
        detail::gatherCoordinates<Elem>(m, e, xe);
        for (int a = 0; a < n; ++a) {
          const LocalIndex k = m.connectivity(e, a);
          ue[a][0] = x(5 * k);
          ue[a][1] = x(5 * k + 1);
        }
        for (int a = 0; a < n; ++a) {
          double xi, eta, sh[n], dn[n][2], g[n][2], h[2][2];
          Elem::nodeNatural(a, xi, eta);
          Elem::shape(xi, eta, sh, dn);
          physicalGradients<Elem>(xe, dn, g);
          detail::nodalGradient<n>(ue, g, h);
          const LocalIndex k = m.connectivity(e, a);
          Kokkos::atomic_add(&acc(k, 0), h[0][0]);
          Kokkos::atomic_add(&acc(k, 1), h[0][1]);
          Kokkos::atomic_add(&acc(k, 2), h[1][0]);
          Kokkos::atomic_add(&acc(k, 3), h[1][1]);
          Kokkos::atomic_add(&acc(k, 4), 1.0);
        }
      });
  Kokkos::parallel_for(
      "mixcon::kernels::pushForwardNodalStress", Kokkos::RangePolicy<ExecSpace>(exec, 0, nn),
      KOKKOS_LAMBDA(LocalIndex k) {
        const double c = acc(k, 4) > 0.0 ? 1.0 / acc(k, 4) : 0.0;
        const double f[2][2] = {{1.0 + c * acc(k, 0), c * acc(k, 1)},
                                {c * acc(k, 2), 1.0 + c * acc(k, 3)}};
        const double j = f[0][0] * f[1][1] - f[0][1] * f[1][0];
        const double s[2][2] = {{tau(3 * k) + x(5 * k + 2), tau(3 * k + 2) + x(5 * k + 4)},
                                {tau(3 * k + 2) + x(5 * k + 4), tau(3 * k + 1) + x(5 * k + 3)}};
        double t[2][2];
        for (int i = 0; i < 2; ++i)
          for (int l = 0; l < 2; ++l) {
            double v = 0.0;
            for (int p = 0; p < 2; ++p)
              for (int q = 0; q < 2; ++q)
                v += f[i][p] * s[p][q] * f[l][q];
            t[i][l] = v / j;
          }
        tau(3 * k) = t[0][0];
        tau(3 * k + 1) = t[1][1];
        tau(3 * k + 2) = t[0][1];
      });
}

} // namespace mixcon
