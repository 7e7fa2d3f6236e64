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
//  - follower pressures on the current boundary and their load stiffness
//  (kernels/FollowerPressure.hpp);
//  - the push-forward of the nodal 2nd Piola-Kirchhoff stress to Cauchy stress (Eq. (5b)).
// Element type is a template parameter; all device code, no virtual calls. Data flow:
// kernels -> solver.
#pragma once

#include <kernels/ElementDriver.hpp>
#include <kernels/FollowerPressure.hpp>
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
/// AlmansiPoint with its material's Voigt stiffness [C] (plane in 2D, solid in 3D).
template <class MemorySpace, int Dim = 2> struct AlmansiLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<typename ElementData<MemorySpace, Dim>::Stiffness *, MemorySpace> stiffness;
  KOKKOS_INLINE_FUNCTION AlmansiPoint<Dim> at(LocalIndex e) const {
    return AlmansiPoint<Dim>{stiffness(material(e))};
  }
};

/// Displacement model, element e: internal force fe = t int B^T sigma da on the current
/// configuration x = X + u (X: d.mesh) and, when `Tangent`, its exact derivative ke = d fe / du
/// (the element driver's spatialElement with the Almansi point law). Returns false when the
/// current element is inverted (det dx/dxi <= 0 at a quadrature point).
template <class Elem, bool Tangent, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool
almansiElement(const ElementData<MemorySpace, Elem::kDim> &d,
               const Kokkos::View<const double *, MemorySpace> &u, LocalIndex e,
               double (&fe)[Elem::kDim * Elem::kNumNodes],
               double (&ke)[Elem::kDim * Elem::kNumNodes][Elem::kDim * Elem::kNumNodes]) {
  return spatialElement<Elem, Tangent>(d.mesh, d.thickness,
                                       AlmansiLaw<MemorySpace, Elem::kDim>{d.material, d.stiffness},
                                       u, e, fe, ke);
}

/// The St. Venant-Kirchhoff point law of the displacement model for the element driver: element
/// e's SaintVenantKirchhoffPoint with its material's Voigt stiffness [C].
template <class MemorySpace, int Dim = 2> struct SaintVenantKirchhoffLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<typename ElementData<MemorySpace, Dim>::Stiffness *, MemorySpace> stiffness;
  KOKKOS_INLINE_FUNCTION SaintVenantKirchhoffPoint<Dim> at(LocalIndex e) const {
    return SaintVenantKirchhoffPoint<Dim>{stiffness(material(e))};
  }
};

/// Displacement model with the St. Venant-Kirchhoff law, element e, total Lagrangian on the
/// reference configuration X (d.mesh): fe = t int P grad_X(N) dA, P = F S, S = C : E,
/// E = (F^T F - I) / 2, F = I + du/dX (the same internal force as t int B^T sigma da with
/// sigma = F S F^T / J); ke = d fe / du exactly (material part with dE = sym(F^T dF), geometric
/// part dF S): the element driver's materialElement with the St. Venant-Kirchhoff point law.
/// Returns false for an inverted element.
template <class Elem, bool Tangent, class MemorySpace>
KOKKOS_INLINE_FUNCTION bool
svkElement(const ElementData<MemorySpace, Elem::kDim> &d,
           const Kokkos::View<const double *, MemorySpace> &u, LocalIndex e,
           double (&fe)[Elem::kDim * Elem::kNumNodes],
           double (&ke)[Elem::kDim * Elem::kNumNodes][Elem::kDim * Elem::kNumNodes]) {
  return materialElement<Elem, Tangent>(
      d.mesh, d.thickness,
      SaintVenantKirchhoffLaw<MemorySpace, Elem::kDim>{d.material, d.stiffness}, u, e, fe, ke);
}

/// Cauchy stress (Voigt<Dim>) of `law` with Voigt stiffness c at the spatial displacement
/// gradient h = du/dx: C times the Almansi strain of h, or for St. Venant-Kirchhoff
/// F S F^T / det F with F = (I - h)^-1, S = C : E(F).
template <int Dim>
KOKKOS_INLINE_FUNCTION Vector<Voigt<Dim>::kSize>
spatialCauchyStress(ElasticLaw law, const Mat<Voigt<Dim>::kSize, Voigt<Dim>::kSize> &c,
                    const Mat<Dim, Dim> &h) {
  if (law != ElasticLaw::SaintVenantKirchhoff)
    return AlmansiPoint<Dim>{c}.stress(h);
  Mat<Dim, Dim> fi{}, f{}; // F^-1 = I - h and F
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j)
      fi.m[i][j] = (i == j ? 1.0 : 0.0) - h.m[i][j];
  const double inverseJ = inverse(fi, f); // det F^-1 = 1 / det F
  const Mat<Dim, Dim> pk2 = voigtToStress<Dim>(SaintVenantKirchhoffPoint<Dim>{c}.stress(f));
  Mat<Dim, Dim> sigma = matmulNT(matmul(f, pk2), f);
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j)
      sigma.m[i][j] *= inverseJ;
  return stressToVoigt<Dim>(sigma);
}

/// Cauchy stress of `law` (Almansi by default) of total displacements u at natural point
/// (xi, eta) of a 2D element e (a functor for recoverNodalStress).
template <class Elem, class MemorySpace> struct AlmansiPointStress {
  ElementData<MemorySpace> d;
  Kokkos::View<const double *, MemorySpace> u;
  ElasticLaw law = ElasticLaw::Almansi;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex e, double xi, double eta,
                                         double (&sig)[3]) const {
    constexpr int n = Elem::kNumNodes;
    double xe[n][2], ue[n][2], sh[n], dn[n][2], g[n][2];
    detail::gatherCurrent<Elem>(d.mesh, u, e, xe, ue);
    Elem::shape(xi, eta, sh, dn);
    physicalGradients<Elem>(xe, dn, g);
    const auto s = spatialCauchyStress<2>(law, d.stiffness(d.material(e)),
                                          detail::displacementGradient<Elem>(ue, g));
    for (int k = 0; k < 3; ++k)
      sig[k] = s.v[k];
  }
};

/// Cauchy stress of `law` at a point of a solid element for recoverSolidNodalStress: the
/// gradients on the current configuration xe + ue, h = du/dx, spatialCauchyStress.
template <class Elem, class MemorySpace> struct SolidCauchyStress {
  static_assert(Elem::kDim == 3, "the solid form of AlmansiPointStress");
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<SolidMatrix *, MemorySpace> stiffness;
  ElasticLaw law = ElasticLaw::Almansi;
  KOKKOS_INLINE_FUNCTION Vector<6> operator()(LocalIndex e, const double (&xe)[Elem::kNumNodes][3],
                                              const double (&ue)[Elem::kNumNodes][3],
                                              const double (&dn)[Elem::kNumNodes][3]) const {
    constexpr int n = Elem::kNumNodes;
    double xc[n][3], g[n][3];
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 3; ++i)
        xc[a][i] = xe[a][i] + ue[a][i];
    detail::pointGeometry<Elem>(xc, dn, g);
    return spatialCauchyStress<3>(law, stiffness(material(e)),
                                  detail::displacementGradient<Elem>(ue, g));
  }
};

/// Cauchy stress of `law` (Voigt<Dim>) and the spatial displacement gradient du/dx at every
/// quadrature point for total displacements u: stress(e, q, .), grad(e, q, i Dim + j) =
/// du_i/dx_j (2D: du/dx, du/dy, dv/dx, dv/dy), xq(e, q, .) the current quadrature-point
/// coordinates.
template <class Elem, class ExecSpace, class MemorySpace, class StressView, class GradientView,
          class PointView>
void almansiGaussPointStress(const ExecSpace &exec, const ElementData<MemorySpace, Elem::kDim> &d,
                             const Kokkos::View<const double *, MemorySpace> &u,
                             const StressView &stress, const GradientView &grad,
                             const PointView &xq, ElasticLaw law = ElasticLaw::Almansi) {
  Kokkos::parallel_for(
      "mixcon::kernels::almansiGaussPointStress",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
        double xe[n][dim], ue[n][dim];
        detail::gatherElementCoordinates<Elem>(d.mesh, e, xe);
        detail::gatherElementDisplacements<Elem>(d.mesh, u, e, ue);
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < dim; ++i)
            xe[a][i] += ue[a][i]; // current configuration
        const auto c = d.stiffness(d.material(e));
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double sh[n], dn[n][dim], g[n][dim];
          detail::referencePoint<Elem>(q, sh, dn);
          detail::pointGeometry<Elem>(xe, dn, g);
          const Mat<dim, dim> h = detail::displacementGradient<Elem>(ue, g);
          const auto s = spatialCauchyStress<dim>(law, c, h);
          for (int k = 0; k < Voigt<dim>::kSize; ++k)
            stress(e, q, k) = s.v[k];
          for (int i = 0; i < dim; ++i) {
            double x = 0.0;
            for (int a = 0; a < n; ++a)
              x += sh[a] * xe[a][i];
            xq(e, q, i) = x;
            for (int j = 0; j < dim; ++j)
              grad(e, q, i * dim + j) = h.m[i][j];
          }
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
scatterBlockMatrix(const CsrMatrix<MemorySpace> &a, const Map &map,
                   const MeshView<MemorySpace, Elem::kDim> &m, LocalIndex e,
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
LocalIndex assembleNonlinear(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
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
LocalIndex
assembleNonlinearRows(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                      const Kernel &kernel, const Map &map, const CsrMatrix<MemorySpace> &a,
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
  static constexpr int kDofs = Elem::kDim * Elem::kNumNodes;
  ElementData<MemorySpace, Elem::kDim> d;
  Kokkos::View<const double *, MemorySpace> u;
  template <bool Tangent>
  KOKKOS_INLINE_FUNCTION bool compute(LocalIndex e, double (&fe)[kDofs],
                                      double (&ke)[kDofs][kDofs]) const {
    return almansiElement<Elem, Tangent>(d, u, e, fe, ke);
  }
};

/// Element kernel of the displacement model with the St. Venant-Kirchhoff law (svkElement).
template <class Elem, class MemorySpace> struct SvkKernel {
  static constexpr int kDofs = Elem::kDim * Elem::kNumNodes;
  ElementData<MemorySpace, Elem::kDim> d;
  Kokkos::View<const double *, MemorySpace> u;
  template <bool Tangent>
  KOKKOS_INLINE_FUNCTION bool compute(LocalIndex e, double (&fe)[kDofs],
                                      double (&ke)[kDofs][kDofs]) const {
    return svkElement<Elem, Tangent>(d, u, e, fe, ke);
  }
};

/// Displacement model: f += internal force of every element at total displacement u, and, when
/// `a.numRows > 0`, a += tangent (Dim dofs per node, scatter map `map`). Returns the first
/// inverted element, or -1.
template <class Elem, class ExecSpace, class MemorySpace, class Map>
LocalIndex assembleAlmansi(const ExecSpace &exec, const ElementData<MemorySpace, Elem::kDim> &d,
                           const Kokkos::View<const double *, MemorySpace> &u, const Map &map,
                           const CsrMatrix<MemorySpace> &a,
                           const Kokkos::View<double *, MemorySpace> &f) {
  return assembleNonlinear<Elem::kDim, Elem>(exec, d.mesh, AlmansiKernel<Elem, MemorySpace>{d, u},
                                             map, a, f);
}

/// How the mixed assemblies produce the Jacobian: the whole element matrix per thread
/// (assembleNonlinear, the default: measured faster in 2D), or one test node's row block at a
/// time (assembleNonlinearRows: per-thread memory O(Ndof nd) instead of O(nd^2), for elements
/// whose nd^2 does not fit a GPU thread).
enum class MixedJacobianBlocks { Element, NodeRows };

/// The incremental Hellinger-Reissner point law of the mixed model for the element driver:
/// element e's MixedIncrementPoint with its material's plane stiffness [C] and compliance [D]
/// and the stabilization a.
template <class MemorySpace, int Dim = 2> struct MixedIncrementLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<typename ElementData<MemorySpace, Dim>::Stiffness *, MemorySpace> stiffness,
      compliance;
  double a = 0.0;
  KOKKOS_INLINE_FUNCTION MixedIncrementPoint<Dim> at(LocalIndex e) const {
    const int k = material(e);
    return MixedIncrementPoint<Dim>{stiffness(k), compliance(k), a};
  }
};

/// The Hellinger-Reissner element of a solid for assembleNonlinearRows (9 unknowns per node: u,
/// v, w, then the Voigt stresses), mixedElementRows with the point law `Law` at the unknowns x
/// (and the nodal prestress tau where the law has one):
///  - MixedIncrementLaw<MemorySpace, 3> at x = 0, tau = 0 (the undeformed, unstressed state) is
///    the linear mixed operator [a K^L, (1 - a) K12; (1 - a) K12^T, -(1 - a) M] (F = I,
///    Sigma = 0: no geometric term), with a zero residual there (SolidMixedModel);
///  - MixedCurrentLaw<MemorySpace, 3> is the geometrically nonlinear model in the current
///    configuration: x the total displacements and Cauchy stresses, tau unused
///    (SolidNonlinearMixedModel, form Current);
///  - MixedIncrementLaw<MemorySpace, 3> on the last converged configuration c1 (mesh) at an
///    increment x with the nodal prestress tau is the report's incremental form
///    (SolidNonlinearMixedModel, form Incremental).
template <class Elem, class MemorySpace, class Law = MixedIncrementLaw<MemorySpace, 3>>
struct SolidMixedKernel {
  static_assert(Elem::kDim == 3, "the 3D mixed element");
  static constexpr int kUnknowns = LayoutOf<Elem>::kMixedUnknowns;
  MeshView<MemorySpace, 3> mesh;
  Law law;
  Kokkos::View<const double *, MemorySpace> x, tau;
  template <bool Tangent, int Rows>
  KOKKOS_INLINE_FUNCTION bool
  computeRows(LocalIndex e, int first, double (&ge)[kUnknowns * Rows],
              double (&ke)[kUnknowns * Rows][kUnknowns * Elem::kNumNodes]) const {
    // The rule that integrates M exactly (core/ElementTraits.hpp MixedRule; tetrahedra).
    return mixedElementRows<MixedRule<Elem>, Tangent, Rows>(mesh, 1.0, law, x, tau, e, first, ge,
                                                            ke);
  }
};

/// The current-configuration Hellinger-Reissner point law of the mixed model for the element
/// driver: element e's MixedCurrentPoint with its material's [C], [D] (plane in 2D, solid in 3D)
/// and the stabilization a.
template <class MemorySpace, int Dim = 2> struct MixedCurrentLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<typename ElementData<MemorySpace, Dim>::Stiffness *, MemorySpace> stiffness,
      compliance;
  double a = 0.0;
  KOKKOS_INLINE_FUNCTION MixedCurrentPoint<Dim> at(LocalIndex e) const {
    const int k = material(e);
    return MixedCurrentPoint<Dim>{stiffness(k), compliance(k), a};
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

/// Right-hand side of the L2 projection of the pushed-forward stress onto the nodal stress space
/// of the new configuration c2 (2D and 3D): b(nv k + c) = t int_c2 psi_k tau2_c da = t int_c1
/// psi_k (F Sigma F^T)_c dA (the Jacobian J of tau2 = F Sigma F^T / J cancels against da = J dA),
/// with Sigma = tau + S interpolated and F = I + du/dX1 at the points of MixedRule<Elem> (the rule
/// of M) on c1 (mesh). nv = Voigt<Dim>::kSize stresses per node in tau and b; x holds the mixed
/// unknowns (LayoutOf<Elem>: displacements, then the stress increments S).
template <class Elem, class ExecSpace, class MemorySpace>
void pushForwardProjectionLoad(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                               double thickness,
                               const Kokkos::View<const double *, MemorySpace> &tau,
                               const Kokkos::View<const double *, MemorySpace> &x,
                               const Kokkos::View<double *, MemorySpace> &b) {
  using L = LayoutOf<Elem>;
  using Rule = MixedRule<Elem>;
  Kokkos::parallel_for(
      "mixcon::kernels::pushForwardProjectionLoad",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nv = L::kNumStresses;
        constexpr int nu = L::kMixedUnknowns, so = L::kStressOffset;
        double xe[n][dim], ue[n][dim], be[n][nv] = {};
        detail::gatherElementCoordinates<Elem>(mesh, e, xe);
        LocalIndex nodes[n];
        for (int a = 0; a < n; ++a) {
          nodes[a] = mesh.connectivity(e, a);
          for (int i = 0; i < dim; ++i)
            ue[a][i] = x(nu * nodes[a] + i);
        }
        for (int q = 0; q < Rule::kNumQp; ++q) {
          double sh[n], dn[n][dim], g[n][dim];
          const double w = detail::referencePoint<Rule>(q, sh, dn);
          const double jw = thickness * w * detail::pointGeometry<Elem>(xe, dn, g);
          Mat<dim, dim> f = detail::displacementGradient<Elem>(ue, g);
          for (int i = 0; i < dim; ++i)
            f.m[i][i] += 1.0;
          Vector<nv> sv{};
          for (int a = 0; a < n; ++a)
            for (int c = 0; c < nv; ++c)
              sv.v[c] += sh[a] * (tau(nv * nodes[a] + c) + x(nu * nodes[a] + so + c));
          const Vector<nv> k = stressToVoigt<dim>(matmulNT(matmul(f, voigtToStress<dim>(sv)), f));
          for (int a = 0; a < n; ++a)
            for (int c = 0; c < nv; ++c)
              be[a][c] += jw * sh[a] * k.v[c];
        }
        for (int a = 0; a < n; ++a)
          for (int c = 0; c < nv; ++c)
            Kokkos::atomic_add(&b(nv * nodes[a] + c), be[a][c]);
      });
}

/// Adds the scalar consistent mass t int psi_a psi_b da of every element into `a` (1 dof per
/// node, pattern expandGraph(graph, 1)), on MixedRule<Elem> (exact for the mass of tetrahedra).
template <class Elem, class ExecSpace, class MemorySpace, class Map>
void assembleScalarMass(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                        double thickness, const Map &map, const CsrMatrix<MemorySpace> &a) {
  using Rule = MixedRule<Elem>;
  Kokkos::parallel_for(
      "mixcon::kernels::assembleScalarMass",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
        double xe[n][dim], m[n][n] = {};
        detail::gatherElementCoordinates<Elem>(mesh, e, xe);
        for (int q = 0; q < Rule::kNumQp; ++q) {
          double sh[n], dn[n][dim], g[n][dim];
          const double w = detail::referencePoint<Rule>(q, sh, dn);
          const double jw = thickness * w * detail::pointGeometry<Elem>(xe, dn, g);
          for (int p = 0; p < n; ++p)
            for (int r = 0; r < n; ++r)
              m[p][r] += jw * sh[p] * sh[r];
        }
        scatterBlockMatrix<1, Elem>(a, map, mesh, e, m);
      });
}

/// Push-forward of the nodal stresses at the end of a mixed increment (Eq. (9), (5b)), 2D and
/// 3D: tau <- F (tau + S) F^T / det F with F = I + du/dX1 averaged over the elements sharing each
/// node (each element's gradient evaluated at the node). x holds the mixed unknowns
/// (LayoutOf<Elem>), tau Voigt<Dim>::kSize stresses per node.
template <class Elem, class ExecSpace, class MemorySpace>
void pushForwardNodalStress(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &m,
                            const Kokkos::View<const double *, MemorySpace> &x,
                            const Kokkos::View<double *, MemorySpace> &tau) {
  using L = LayoutOf<Elem>;
  const LocalIndex nn = m.coordinates.extent(0);
  // Per node: the summed gradients (row by row) and the number of elements.
  Kokkos::View<double * [Elem::kDim * Elem::kDim + 1], MemorySpace> acc(
      "mixcon::kernels::nodalDeformationGradient", nn);
  Kokkos::parallel_for(
      "mixcon::kernels::nodalDeformationGradient",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, m.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nu = L::kMixedUnknowns;
        double xe[n][dim], ue[n][dim];
        detail::gatherElementCoordinates<Elem>(m, e, xe);
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < dim; ++i)
            ue[a][i] = x(nu * m.connectivity(e, a) + i);
        for (int a = 0; a < n; ++a) {
          double xi[dim], sh[n], dn[n][dim], g[n][dim];
          Elem::nodeNatural(a, xi);
          Elem::shape(xi, sh, dn);
          detail::pointGeometry<Elem>(xe, dn, g);
          const Mat<dim, dim> h = detail::displacementGradient<Elem>(ue, g);
          const LocalIndex k = m.connectivity(e, a);
          for (int i = 0; i < dim; ++i)
            for (int j = 0; j < dim; ++j)
              Kokkos::atomic_add(&acc(k, dim * i + j), h.m[i][j]);
          Kokkos::atomic_add(&acc(k, dim * dim), 1.0);
        }
      });
  Kokkos::parallel_for(
      "mixcon::kernels::pushForwardNodalStress", Kokkos::RangePolicy<ExecSpace>(exec, 0, nn),
      KOKKOS_LAMBDA(LocalIndex k) {
        constexpr int dim = Elem::kDim, nv = L::kNumStresses;
        constexpr int nu = L::kMixedUnknowns, so = L::kStressOffset;
        const double c = acc(k, dim * dim) > 0.0 ? 1.0 / acc(k, dim * dim) : 0.0;
        Mat<dim, dim> f{};
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j)
            f.m[i][j] = (i == j ? 1.0 : 0.0) + c * acc(k, dim * i + j);
        const double j = determinant(f);
        Vector<nv> sv{};
        for (int v = 0; v < nv; ++v)
          sv.v[v] = tau(nv * k + v) + x(nu * k + so + v);
        const Vector<nv> t = stressToVoigt<dim>(matmulNT(matmul(f, voigtToStress<dim>(sv)), f));
        for (int v = 0; v < nv; ++v)
          tau(nv * k + v) = t.v[v] / j;
      });
}

} // namespace mixcon
