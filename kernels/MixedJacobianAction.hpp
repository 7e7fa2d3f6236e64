// The nonlinear mixed model's Jacobian applied without element or global matrices (issue 16,
// item 3, for the Hellinger-Reissner residual of kernels/ElementDriver.hpp's mixedElement): y = J
// dx element by element, at the quadrature points. Per element: gather the coordinates, the
// state x (u, S) and the direction dx (du, dS); per quadrature point: the geometry, the point
// law's response and derivatives (kernels/MixedPointPhysics.hpp, evaluate<true>), then the
// directional derivative of the element residual, which is the driver's ke applied to dx:
//   dl = grad(du) (on X, or on the current x = X + u), dh = A dl with A = I (incremental form) or
//   I - h (current form), ds = psi dS,
//   dP = dP/dh : dh + dP/ds ds,  dr = dr/dh : dh + dr/ds ds (+ r div(du), current form),
//   y_u(a, i) += da (dP_ij g_aj + [current] P_ij (g_aj div(du) - g_am dl_mj)),
//   y_S(a, c) += da psi_a dr_c,
// the bracketed terms being the change of da and of the current gradients with the
// configuration. Nothing is stored between applies (the point law is re-evaluated: the
// matrix-free end of MFEM's partial / full assembly split); the element results are scattered
// with atomic adds (devices) or per element color with plain adds (host spaces), the coloring of
// kernels/MixedMatrixFree.hpp. Dimension generic (FieldLayout<Dim>, Voigt<Dim>, any law whose
// point is a MixedIncrementPoint<Dim> / MixedCurrentPoint<Dim>). For the block-triangular
// preconditioner without assembled blocks (the 3D models, solver/SolidMixedSolve.hpp): the stress
// rows' blocks C and M by partial assembly (their matrices at every quadrature point). Layer:
// kernels.
#pragma once

#include <kernels/ElementDriver.hpp>
#include <kernels/MixedMatrixFree.hpp>
#include <kernels/Nonlinear.hpp>

namespace mixcon {

/// y_e = ke dx_e of element e (ke: mixedElement's Jacobian at state x, prestress tau), computed
/// at the quadrature points; ye[a][k]: node a's unknown k (FieldLayout's mixed order). Elem gives
/// the quadrature rule too (the 3D models pass MixedRule<Elem>).
template <class Elem, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
mixedJacobianActionElement(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                           const Law &law, const Kokkos::View<const double *, MemorySpace> &x,
                           const Kokkos::View<const double *, MemorySpace> &tau,
                           const Kokkos::View<const double *, MemorySpace> &dx, LocalIndex e,
                           double (&ye)[Elem::kNumNodes][LayoutOf<Elem>::kMixedUnknowns]) {
  using L = LayoutOf<Elem>;
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nv = L::kNumStresses;
  constexpr int so = L::kStressOffset;
  const auto point = law.at(e);
  using Point = decltype(point);
  constexpr bool current = Point::kCurrentConfiguration;
  double xe[n][dim], ue[n][dim], se[n][nv], te[n][nv], due[n][dim], dse[n][nv];
  detail::gatherMixedElement<Elem, Point>(mesh, x, tau, e, xe, ue, se, te);
  detail::gatherMixedUnknowns<Elem>(mesh, dx, e, due, dse);
  for (int a = 0; a < n; ++a)
    for (int k = 0; k < L::kMixedUnknowns; ++k)
      ye[a][k] = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], dn[n][dim], g[n][dim];
    const double w = detail::referencePoint<Elem>(q, sh, dn);
    const double jw = thickness * w * detail::pointGeometry<Elem>(xe, dn, g);
    const Mat<dim, dim> h = detail::displacementGradient<Elem>(ue, g);
    const Mat<dim, dim> dl = detail::displacementGradient<Elem>(due, g);
    Vector<nv> sv{}, tv{}, ds{};
    for (int a = 0; a < n; ++a)
      for (int c = 0; c < nv; ++c) {
        sv.v[c] += sh[a] * se[a][c];
        tv.v[c] += sh[a] * te[a][c];
        ds.v[c] += sh[a] * dse[a][c];
      }
    const MixedPointResponse<dim> r = point.template evaluate<true>(h, sv, tv);
    // dh = A dl, A = I - h (current) or I.
    Mat<dim, dim> dh = dl;
    double div = 0.0;
    if (current) {
      for (int k = 0; k < dim; ++k) {
        div += dl.m[k][k];
        for (int l = 0; l < dim; ++l)
          for (int m = 0; m < dim; ++m)
            dh.m[k][l] -= h.m[k][m] * dl.m[m][l];
      }
    }
    Mat<dim, dim> dp{};
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j) {
        double v = 0.0;
        for (int k = 0; k < dim; ++k)
          for (int l = 0; l < dim; ++l)
            v += r.dStressDGrad.m[i * dim + j][k * dim + l] * dh.m[k][l];
        for (int c = 0; c < nv; ++c)
          v += r.dStressDStress.m[i * dim + j][c] * ds.v[c];
        dp.m[i][j] = v;
      }
    Vector<nv> dr{};
    for (int c = 0; c < nv; ++c) {
      double v = current ? r.compatibility.v[c] * div : 0.0;
      for (int k = 0; k < dim; ++k)
        for (int l = 0; l < dim; ++l)
          v += r.dCompatibilityDGrad.m[c][k * dim + l] * dh.m[k][l];
      for (int k = 0; k < nv; ++k)
        v += r.dCompatibilityDStress.m[c][k] * ds.v[k];
      dr.v[c] = jw * v;
    }
    // Current form: the test gradients and da move, d(g_aj da) = da (g_aj div - g_am dl_mj).
    for (int a = 0; a < n; ++a) {
      for (int i = 0; i < dim; ++i) {
        double v = 0.0;
        for (int j = 0; j < dim; ++j) {
          v += dp.m[i][j] * g[a][j];
          if (current) {
            double gm = 0.0; // sum_m g_am dl_mj
            for (int m = 0; m < dim; ++m)
              gm += g[a][m] * dl.m[m][j];
            v += r.stress.m[i][j] * (g[a][j] * div - gm);
          }
        }
        ye[a][i] += jw * v;
      }
      for (int c = 0; c < nv; ++c)
        ye[a][so + c] += sh[a] * dr.v[c];
    }
  }
}

/// How y = J dx reaches the nodes: atomic adds, or the element colors of
/// kernels/MixedMatrixFree.hpp (elements(colorOffsets[c] .. colorOffsets[c + 1] - 1) share no
/// node; one launch per color, plain adds).
template <class MemorySpace> struct MixedElementColors {
  static constexpr int kMaxColors = MixedMatrixFreeOperators<MemorySpace>::kMaxColors;
  MixedScatter scatter = MixedScatter::Atomic;
  Kokkos::View<LocalIndex *, MemorySpace> elements;
  int numColors = 0;
  LocalIndex colorOffsets[kMaxColors + 1] = {};
};

/// The element colors of a host mesh for `scatter` (Colored: the greedy coloring of
/// kernels/MixedMatrixFree.hpp; falls back to Atomic when more colors would be needed).
template <class MemorySpace>
MixedElementColors<MemorySpace> mixedElementColors(const Mesh &mesh, MixedScatter scatter) {
  MixedElementColors<MemorySpace> out;
  if (scatter != MixedScatter::Colored)
    return out;
  MixedMatrixFreeOperators<MemorySpace> op;
  if (!detail::colorElements(mesh, op))
    return out;
  out.scatter = MixedScatter::Colored;
  out.elements = op.coloredElements;
  out.numColors = op.numColors;
  for (int c = 0; c <= op.numColors; ++c)
    out.colorOffsets[c] = op.colorOffsets[c];
  return out;
}

namespace detail {
/// y(Width k + c) += ye[a][c] for node k = node a of element e: atomic adds, or plain adds (the
/// element's color owns its nodes).
template <bool Atomic, int Width, class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
scatterNodeValues(const Kokkos::View<LocalIndex **, Kokkos::LayoutRight, MemorySpace> &connectivity,
                  LocalIndex e, const double (&ye)[Elem::kNumNodes][Width],
                  const Kokkos::View<double *, MemorySpace> &y) {
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    const LocalIndex k = connectivity(e, a);
    for (int c = 0; c < Width; ++c) {
      if constexpr (Atomic)
        Kokkos::atomic_add(&y(Width * k + c), ye[a][c]);
      else
        y(Width * k + c) += ye[a][c];
    }
  }
}

/// Runs f.template element<Atomic>(e) for every element: one launch with Atomic = true, or one
/// launch per color of `colors` with Atomic = false (the elements of a color share no node).
template <class ExecSpace, class MemorySpace, class Functor>
void forEachElementScattered(const ExecSpace &exec, LocalIndex numElements,
                             const MixedElementColors<MemorySpace> &colors, const char *label,
                             const Functor &f) {
  if (colors.scatter == MixedScatter::Atomic) {
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<ExecSpace>(exec, 0, numElements),
        KOKKOS_LAMBDA(LocalIndex e) { f.template element<true>(e); });
    return;
  }
  const auto list = colors.elements;
  for (int c = 0; c < colors.numColors; ++c)
    Kokkos::parallel_for(
        label,
        Kokkos::RangePolicy<ExecSpace>(exec, colors.colorOffsets[c], colors.colorOffsets[c + 1]),
        KOKKOS_LAMBDA(LocalIndex i) { f.template element<false>(list(i)); });
}

/// One element of applyMixedJacobian.
template <class Elem, class Law, class MemorySpace> struct MixedJacobianAction {
  MeshView<MemorySpace, Elem::kDim> mesh;
  double thickness;
  Law law;
  Kokkos::View<const double *, MemorySpace> x, tau, dx;
  Kokkos::View<double *, MemorySpace> y;
  template <bool Atomic> KOKKOS_INLINE_FUNCTION void element(LocalIndex e) const {
    double ye[Elem::kNumNodes][LayoutOf<Elem>::kMixedUnknowns];
    mixedJacobianActionElement<Elem>(mesh, thickness, law, x, tau, dx, e, ye);
    scatterNodeValues<Atomic, LayoutOf<Elem>::kMixedUnknowns, Elem>(mesh.connectivity, e, ye, y);
  }
};
} // namespace detail

/// y = J dx (y overwritten) for the mixed Jacobian J of mixedElement with `law` at state x and
/// prestress tau, every element of `mesh`, scattered as `colors` says.
template <class Elem, class ExecSpace, class Law, class MemorySpace>
void applyMixedJacobian(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                        double thickness, const Law &law,
                        const Kokkos::View<const double *, MemorySpace> &x,
                        const Kokkos::View<const double *, MemorySpace> &tau,
                        const Kokkos::View<const double *, MemorySpace> &dx,
                        const Kokkos::View<double *, MemorySpace> &y,
                        const MixedElementColors<MemorySpace> &colors) {
  Kokkos::deep_copy(exec, y, 0.0);
  detail::forEachElementScattered(
      exec, static_cast<LocalIndex>(mesh.connectivity.extent(0)), colors,
      "mixcon::kernels::mixedJacobianAction",
      detail::MixedJacobianAction<Elem, Law, MemorySpace>{mesh, thickness, law, x, tau, dx, y});
}

namespace detail {
/// The stress rows of the mixed Jacobian at point q of element e (nodal data xe, ue, se, te of
/// gatherMixedElement): the shape values sh and gradients g, jw (weight times area or volume),
/// dr(c, Dim m + l) = d r_c / d dl_ml, the stress row c's derivative by the gradient dl =
/// grad(du) on the law's configuration (through A = I - h, and with the change of the area or
/// volume r_c div(du), in the current form), and ds = d r / d s (the law's
/// dCompatibilityDStress). C du at the point is jw dr dl, M dS is -jw ds (psi dS).
template <class Elem, class Point>
KOKKOS_INLINE_FUNCTION void
stressRowsAtPoint(const Point &point, double thickness, int q,
                  const double (&xe)[Elem::kNumNodes][Elem::kDim],
                  const double (&ue)[Elem::kNumNodes][Elem::kDim],
                  const double (&se)[Elem::kNumNodes][LayoutOf<Elem>::kNumStresses],
                  const double (&te)[Elem::kNumNodes][LayoutOf<Elem>::kNumStresses],
                  double (&sh)[Elem::kNumNodes], double (&g)[Elem::kNumNodes][Elem::kDim],
                  double &jw, Mat<LayoutOf<Elem>::kNumStresses, Elem::kDim * Elem::kDim> &dr,
                  Mat<LayoutOf<Elem>::kNumStresses, LayoutOf<Elem>::kNumStresses> &ds) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nv = LayoutOf<Elem>::kNumStresses;
  constexpr bool current = Point::kCurrentConfiguration;
  double dn[n][dim];
  const double w = referencePoint<Elem>(q, sh, dn);
  jw = thickness * w * pointGeometry<Elem>(xe, dn, g);
  const Mat<dim, dim> h = displacementGradient<Elem>(ue, g);
  Vector<nv> sv{}, tv{};
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < nv; ++c) {
      sv.v[c] += sh[a] * se[a][c];
      tv.v[c] += sh[a] * te[a][c];
    }
  const MixedPointResponse<dim> r = point.template evaluate<true>(h, sv, tv);
  // d r_c / d dl_ml = sum_k d r_c / d h_kl A_km (+ r_c delta_ml, current form).
  for (int c = 0; c < nv; ++c)
    for (int m = 0; m < dim; ++m)
      for (int l = 0; l < dim; ++l) {
        double v = current && m == l ? r.compatibility.v[c] : 0.0;
        for (int k = 0; k < dim; ++k)
          v += r.dCompatibilityDGrad.m[c][k * dim + l] *
               ((k == m ? 1.0 : 0.0) - (current ? h.m[k][m] : 0.0));
        dr.m[c][dim * m + l] = v;
      }
  ds = r.dCompatibilityDStress;
}
} // namespace detail

/// The stress rows of the mixed Jacobian on their own (what the matrix-free product's block
/// preconditioner needs): c += J_S,u (pattern expandGraph(graph, nv, Dim)) and m += -J_S,S
/// (expandGraph(graph, nv)), the same entries as mixedElement's ke, scattered with atomics
/// through the element scatter map (map(e, a, b): position of node b in node a's graph row).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Map>
void assembleMixedStressRows(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                             double thickness, const Law &law,
                             const Kokkos::View<const double *, MemorySpace> &x,
                             const Kokkos::View<const double *, MemorySpace> &tau, const Map &map,
                             const CsrMatrix<MemorySpace> &c, const CsrMatrix<MemorySpace> &m) {
  using L = LayoutOf<Elem>;
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nv = L::kNumStresses;
  const LocalIndex ne = static_cast<LocalIndex>(mesh.connectivity.extent(0));
  using GradientRows = Mat<nv, dim * dim>;
  using StressRows = Mat<nv, nv>;
  Kokkos::parallel_for(
      "mixcon::kernels::mixedStressRows", Kokkos::RangePolicy<ExecSpace>(exec, 0, ne),
      KOKKOS_LAMBDA(LocalIndex e) {
        const auto point = law.at(e);
        using Point = decltype(point);
        double xe[n][dim], ue[n][dim], se[n][nv], te[n][nv];
        detail::gatherMixedElement<Elem, Point>(mesh, x, tau, e, xe, ue, se, te);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double sh[n], g[n][dim], jw;
          GradientRows dr;
          StressRows ds;
          detail::stressRowsAtPoint<Elem>(point, thickness, q, xe, ue, se, te, sh, g, jw, dr, ds);
          for (int a = 0; a < n; ++a) {
            const LocalIndex row = mesh.connectivity(e, a);
            const double fa = jw * sh[a];
            for (int v = 0; v < nv; ++v) {
              const Offset cs = c.rowOffsets(nv * row + v), ms = m.rowOffsets(nv * row + v);
              for (int b = 0; b < n; ++b) {
                const Offset cb = cs + dim * map(e, a, b), mb = ms + nv * map(e, a, b);
                for (int mm = 0; mm < dim; ++mm) {
                  double s = 0.0;
                  for (int l = 0; l < dim; ++l)
                    s += dr.m[v][mm * dim + l] * g[b][l];
                  Kokkos::atomic_add(&c.values(cb + mm), fa * s);
                }
                for (int k = 0; k < nv; ++k)
                  Kokkos::atomic_add(&m.values(mb + k), -fa * sh[b] * ds.m[v][k]);
              }
            }
          }
        }
      });
}

/// The stress rows of the mixed Jacobian, [C -M], by partial assembly (what products with C and
/// M need, stored per quadrature point instead of per node pair), at state x, prestress tau
/// (Elem gives the rule): at point q of element e, with detail::stressRowsAtPoint's dr and ds,
/// pc(e, q, Dim^2 c + Dim m + l) = jw dr(c, Dim m + l) (C du at the point is pc grad(du)) and
/// pm(e, q, nv i + j) = -jw ds(i, j); and M's nodal diagonal blocks blocks(k) += sum_q sh_a^2 pm(e,
/// q) for node k = node a of e (blocks zeroed here). pc: (elements, Elem::kNumQp, nv Dim^2); pm:
/// (elements, Elem::kNumQp, nv^2); blocks: one nv x nv matrix per node.
template <class Elem, class ExecSpace, class Law, class MemorySpace>
void assembleMixedStressRowsPartial(
    const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
    const Law &law, const Kokkos::View<const double *, MemorySpace> &x,
    const Kokkos::View<const double *, MemorySpace> &tau,
    const Kokkos::View<double ***, MemorySpace> &pc,
    const Kokkos::View<double ***, MemorySpace> &pm,
    const Kokkos::View<Mat<LayoutOf<Elem>::kNumStresses, LayoutOf<Elem>::kNumStresses> *,
                       MemorySpace> &blocks) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nv = LayoutOf<Elem>::kNumStresses;
  using GradientRows = Mat<nv, dim * dim>;
  using StressRows = Mat<nv, nv>;
  Kokkos::deep_copy(exec, blocks, StressRows{});
  Kokkos::parallel_for(
      "mixcon::kernels::mixedStressRowsPartial",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        const auto point = law.at(e);
        using Point = decltype(point);
        double xe[n][dim], ue[n][dim], se[n][nv], te[n][nv];
        detail::gatherMixedElement<Elem, Point>(mesh, x, tau, e, xe, ue, se, te);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double sh[n], g[n][dim], jw;
          GradientRows dr;
          StressRows ds;
          detail::stressRowsAtPoint<Elem>(point, thickness, q, xe, ue, se, te, sh, g, jw, dr, ds);
          for (int c = 0; c < nv; ++c)
            for (int ml = 0; ml < dim * dim; ++ml)
              pc(e, q, dim * dim * c + ml) = jw * dr.m[c][ml];
          for (int i = 0; i < nv; ++i)
            for (int j = 0; j < nv; ++j)
              pm(e, q, nv * i + j) = -jw * ds.m[i][j];
          for (int a = 0; a < n; ++a) {
            const LocalIndex k = mesh.connectivity(e, a);
            for (int i = 0; i < nv; ++i)
              for (int j = 0; j < nv; ++j)
                Kokkos::atomic_add(&blocks(k).m[i][j], sh[a] * sh[a] * pm(e, q, nv * i + j));
          }
        }
      });
}

namespace detail {
/// One element of applyMixedCouplingPartial: the gradients on the law's configuration
/// recomputed from the coordinates (moved by the state's displacements when Current).
template <class Elem, bool Current, class MemorySpace> struct MixedCouplingPartialAction {
  static constexpr int kNodes = Elem::kNumNodes, kStresses = LayoutOf<Elem>::kNumStresses;
  MeshView<MemorySpace, Elem::kDim> mesh;
  Kokkos::View<const double *, MemorySpace> x;
  Kokkos::View<const double ***, MemorySpace> pc;
  Kokkos::View<const double *, MemorySpace> v;
  Kokkos::View<double *, MemorySpace> w;
  template <bool Atomic> KOKKOS_INLINE_FUNCTION void element(LocalIndex e) const {
    constexpr int n = kNodes, nv = kStresses, dim = Elem::kDim;
    using L = LayoutOf<Elem>;
    double xe[n][dim], ve[n][dim], ye[n][nv];
    gatherElementCoordinates<Elem>(mesh, e, xe);
    for (int a = 0; a < n; ++a) {
      const LocalIndex k = mesh.connectivity(e, a);
      for (int i = 0; i < dim; ++i) {
        if constexpr (Current)
          xe[a][i] += x(L::mixedDisplacementDof(k, i));
        ve[a][i] = v(dim * k + i);
      }
      for (int c = 0; c < nv; ++c)
        ye[a][c] = 0.0;
    }
    for (int q = 0; q < Elem::kNumQp; ++q) {
      double sh[n], dn[n][dim], g[n][dim];
      referencePoint<Elem>(q, sh, dn);
      pointGeometry<Elem>(xe, dn, g);
      const Mat<dim, dim> dl = displacementGradient<Elem>(ve, g);
      double dr[nv];
      for (int c = 0; c < nv; ++c) {
        double s = 0.0;
        for (int m = 0; m < dim; ++m)
          for (int l = 0; l < dim; ++l)
            s += pc(e, q, dim * dim * c + dim * m + l) * dl.m[m][l];
        dr[c] = s;
      }
      for (int a = 0; a < n; ++a)
        for (int c = 0; c < nv; ++c)
          ye[a][c] += sh[a] * dr[c];
    }
    scatterNodeValues<Atomic, nv, Elem>(mesh.connectivity, e, ye, w);
  }
};
} // namespace detail

/// w = C v (w overwritten; v: Dim displacements per node, w: nv stresses per node) from the
/// point matrices pc of assembleMixedStressRowsPartial at state x (its displacements move the
/// nodes when the law integrates over the current configuration), scattered as `colors` says.
template <class Elem, bool Current, class ExecSpace, class MemorySpace>
void applyMixedCouplingPartial(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                               const Kokkos::View<const double *, MemorySpace> &x,
                               const Kokkos::View<const double ***, MemorySpace> &pc,
                               const Kokkos::View<const double *, MemorySpace> &v,
                               const Kokkos::View<double *, MemorySpace> &w,
                               const MixedElementColors<MemorySpace> &colors) {
  Kokkos::deep_copy(exec, w, 0.0);
  detail::forEachElementScattered(
      exec, static_cast<LocalIndex>(mesh.connectivity.extent(0)), colors,
      "mixcon::kernels::mixedCouplingPartialAction",
      detail::MixedCouplingPartialAction<Elem, Current, MemorySpace>{mesh, x, pc, v, w});
}

namespace detail {
/// One element of applyMixedStressMass.
template <class Elem, class MemorySpace> struct MixedStressMassAction {
  static constexpr int kNodes = Elem::kNumNodes, kStresses = LayoutOf<Elem>::kNumStresses;
  Kokkos::View<LocalIndex **, Kokkos::LayoutRight, MemorySpace> connectivity;
  Kokkos::View<const double ***, MemorySpace> pm;
  Kokkos::View<const double *, MemorySpace> z;
  Kokkos::View<double *, MemorySpace> y;
  template <bool Atomic> KOKKOS_INLINE_FUNCTION void element(LocalIndex e) const {
    constexpr int n = kNodes, nv = kStresses;
    double ze[n][nv], ye[n][nv];
    for (int a = 0; a < n; ++a)
      for (int c = 0; c < nv; ++c) {
        ze[a][c] = z(nv * connectivity(e, a) + c);
        ye[a][c] = 0.0;
      }
    for (int q = 0; q < Elem::kNumQp; ++q) {
      double xi[Elem::kDim], w, sh[n], dn[n][Elem::kDim];
      Elem::quadraturePoint(q, xi, w);
      Elem::shape(xi, sh, dn);
      double s[nv] = {}, t[nv] = {};
      for (int a = 0; a < n; ++a)
        for (int c = 0; c < nv; ++c)
          s[c] += sh[a] * ze[a][c];
      for (int i = 0; i < nv; ++i)
        for (int j = 0; j < nv; ++j)
          t[i] += pm(e, q, nv * i + j) * s[j];
      for (int a = 0; a < n; ++a)
        for (int c = 0; c < nv; ++c)
          ye[a][c] += sh[a] * t[c];
    }
    scatterNodeValues<Atomic, nv, Elem>(connectivity, e, ye, y);
  }
};
} // namespace detail

/// y = M z (y overwritten; z, y: nv stresses per node) from the point matrices pm of
/// assembleMixedStressRowsPartial, scattered as `colors` says.
template <class Elem, class ExecSpace, class MemorySpace>
void applyMixedStressMass(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                          const Kokkos::View<const double ***, MemorySpace> &pm,
                          const Kokkos::View<const double *, MemorySpace> &z,
                          const Kokkos::View<double *, MemorySpace> &y,
                          const MixedElementColors<MemorySpace> &colors) {
  Kokkos::deep_copy(exec, y, 0.0);
  detail::forEachElementScattered(
      exec, static_cast<LocalIndex>(mesh.connectivity.extent(0)), colors,
      "mixcon::kernels::mixedStressMassAction",
      detail::MixedStressMassAction<Elem, MemorySpace>{mesh.connectivity, pm, z, y});
}

/// y = J dx of the 2D incremental form (assembleMixedIncrement's J at increment x, prestress
/// tau, stabilization a).
template <class Elem, class ExecSpace, class MemorySpace>
void applyMixedIncrementJacobian(const ExecSpace &exec, const MixedElementData<MemorySpace> &d,
                                 const Kokkos::View<const double *, MemorySpace> &tau,
                                 const Kokkos::View<const double *, MemorySpace> &x, double a,
                                 const Kokkos::View<const double *, MemorySpace> &dx,
                                 const Kokkos::View<double *, MemorySpace> &y,
                                 const MixedElementColors<MemorySpace> &colors) {
  applyMixedJacobian<Elem>(exec, d.mesh, d.thickness,
                           MixedIncrementLaw<MemorySpace>{d.material, d.stiffness, d.compliance, a},
                           x, tau, dx, y, colors);
}

/// y = J dx of the 2D current form (assembleMixedCurrent's J at x, stabilization a).
template <class Elem, class ExecSpace, class MemorySpace>
void applyMixedCurrentJacobian(const ExecSpace &exec, const MixedElementData<MemorySpace> &d,
                               const Kokkos::View<const double *, MemorySpace> &x, double a,
                               const Kokkos::View<const double *, MemorySpace> &dx,
                               const Kokkos::View<double *, MemorySpace> &y,
                               const MixedElementColors<MemorySpace> &colors) {
  applyMixedJacobian<Elem>(exec, d.mesh, d.thickness,
                           MixedCurrentLaw<MemorySpace>{d.material, d.stiffness, d.compliance, a},
                           x, Kokkos::View<const double *, MemorySpace>(), dx, y, colors);
}

} // namespace mixcon
