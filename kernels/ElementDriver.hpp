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
// (teamElementStiffness, the larger 3D elements on GPUs; kTeamStiffness). Layer: kernels.
#pragma once

#include <core/ElementTraits.hpp>
#include <kernels/MixedPointPhysics.hpp>
#include <kernels/PointPhysics.hpp>
#include <kernels/SparseMatrix.hpp>

namespace mixcon {

/// Elements per work item of the stiffness driver: a batch of consecutive elements computed in
/// SIMD lanes on CPUs (every scalar of the element loop becomes an array over the lanes, and the
/// lane loops are the innermost, unit-stride ones the compiler vectorizes); one element per
/// thread on GPUs. 4 lanes measured 1.2-1.6x over 1 (2 threads, SSE2 code,
/// bench_linear_stiffness); 2 and 8 were slower than 4.
template <class ExecSpace>
constexpr int kStiffnessLanes =
    Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible ? 4 : 1;

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

/// Element stiffness t int B^T D B dA (the report's Eq. (25) for D = C) of the W elements first,
/// first + 1, ... (clamped to last: a short final batch repeats its last element) into lane l of
/// ke[i][j][l], dofs node-interleaved (u_1, v_1, u_2, ...). D is the tangent of the element's
/// point law (law.at(e)) at zero strain, evaluated once per element (the law's parameters are per
/// element). B_a (Voigt x Dim) has B_a[k][r] = g_a[c] and, for a shear component,
/// B_a[k][c] = g_a[r], (r, c) = (Voigt::row(k), Voigt::col(k)). Per quadrature point: the
/// gradients, D B_b for every node, the Dim x Dim blocks B_a^T (D B_b) for a <= b; the lower
/// blocks mirrored at the end (D is symmetric).
template <class Elem, int W, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
stiffnessLanes(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness, const Law &law,
               LocalIndex first, LocalIndex last,
               double (&ke)[Elem::kDim * Elem::kNumNodes][Elem::kDim * Elem::kNumNodes][W]) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  using V = Voigt<dim>;
  constexpr int nv = V::kSize;
  double xe[n][dim][W], d[nv][nv][W];
  for (int l = 0; l < W; ++l) {
    const LocalIndex e = first + l < last ? first + l : last;
    for (int a = 0; a < n; ++a) {
      const LocalIndex k = mesh.connectivity(e, a);
      for (int i = 0; i < dim; ++i)
        xe[a][i][l] = mesh.coordinates(k, i);
    }
    const auto t = law.at(e).tangent(Vector<nv>{});
    for (int r = 0; r < nv; ++r)
      for (int s = 0; s < nv; ++s)
        d[r][s][l] = t.m[r][s];
  }
  for (int i = 0; i < dim * n; ++i)
    for (int j = 0; j < dim * n; ++j)
      for (int l = 0; l < W; ++l)
        ke[i][j][l] = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], dn[n][dim], g[n][dim][W], det[W], f[W];
    const double w = detail::referencePoint<Elem>(q, sh, dn); // shared by the lanes
    detail::laneGeometry<Elem, W>(xe, dn, g, det);
    for (int l = 0; l < W; ++l)
      f[l] = thickness * w * det[l];
    for (int b = 0; b < n; ++b) {
      // f D B_b: column j gathers D's normal column j and the shear columns touching j.
      double db[nv][dim][W];
      for (int k = 0; k < nv; ++k)
        for (int j = 0; j < dim; ++j)
          for (int l = 0; l < W; ++l) {
            double s = d[k][j][l] * g[b][j][l];
            for (int m = dim; m < nv; ++m) {
              if (V::row(m) == j)
                s += d[k][m][l] * g[b][V::col(m)][l];
              if (V::col(m) == j)
                s += d[k][m][l] * g[b][V::row(m)][l];
            }
            db[k][j][l] = s * f[l];
          }
      // Blocks B_a^T (f D B_b), a <= b: row i gathers the normal row i and the shear rows
      // touching i.
      for (int a = 0; a <= b; ++a)
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j)
            for (int l = 0; l < W; ++l) {
              double s = g[a][i][l] * db[i][j][l];
              for (int k = dim; k < nv; ++k) {
                if (V::row(k) == i)
                  s += g[a][V::col(k)][l] * db[k][j][l];
                if (V::col(k) == i)
                  s += g[a][V::row(k)][l] * db[k][j][l];
              }
              ke[dim * a + i][dim * b + j][l] += s;
            }
    }
  }
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < b; ++a)
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          for (int l = 0; l < W; ++l)
            ke[dim * b + j][dim * a + i][l] = ke[dim * a + i][dim * b + j][l];
}

/// Element stiffness of element e (one lane of stiffnessLanes, the same arithmetic).
template <class Elem, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
elementStiffness(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness, const Law &law,
                 LocalIndex e,
                 double (&ke)[Elem::kDim * Elem::kNumNodes][Elem::kDim * Elem::kNumNodes]) {
  constexpr int nd = Elem::kDim * Elem::kNumNodes;
  double k[nd][nd][1];
  stiffnessLanes<Elem, 1>(mesh, thickness, law, e, e, k);
  for (int i = 0; i < nd; ++i)
    for (int j = 0; j < nd; ++j)
      ke[i][j] = k[i][j][0];
}

/// Adds an element matrix (node-interleaved, Dim dofs per node) times `scale` into CSR through
/// the scatter map (map(e, p, b): position of node b in the node-graph row of node p).
template <class Elem, class MemorySpace, class Map>
KOKKOS_INLINE_FUNCTION void scatterElementStiffness(
    const CsrMatrix<MemorySpace> &a, const Map &map, const MeshView<MemorySpace, Elem::kDim> &m,
    LocalIndex e, double scale,
    const double (&ke)[Elem::kDim * Elem::kNumNodes][Elem::kDim * Elem::kNumNodes]) {
  constexpr int dim = Elem::kDim;
  for (int p = 0; p < Elem::kNumNodes; ++p) {
    const LocalIndex row = m.connectivity(e, p);
    for (int i = 0; i < dim; ++i) {
      const Offset start = a.rowOffsets(dim * row + i);
      for (int b = 0; b < Elem::kNumNodes; ++b) {
        const Offset k = start + dim * map(e, p, b);
        for (int j = 0; j < dim; ++j)
          Kokkos::atomic_add(&a.values(k + j), scale * ke[dim * p + i][dim * b + j]);
      }
    }
  }
}

/// True where the element stiffness kernels of ExecSpace run one team per element
/// (teamElementStiffness) rather than SIMD lanes of elements per thread (stiffnessLanes): on GPUs,
/// for the 3D elements of 24 or more unknowns (Hex8, Hex20, Tet10). Measured on an H200
/// (docs/gpu.md, 2026-11-28): the team form writes the element matrices of Hex8, Hex20 and Tet10
/// 1.36x, 2.38x and 1.06x faster and assembles the Hex8 CSR 4.7x faster; it is slower for Quad4,
/// Quad8 and Tet4 (0.15x, 0.81x, 0.42x), whose matrices one thread holds without much spilling.
/// On CPUs the lanes are always taken.
template <class ExecSpace, class Elem>
constexpr bool kTeamStiffness =
    !Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible && Elem::kDim == 3 &&
    Elem::kDim * Elem::kNumNodes >= 24;

namespace detail {

/// Where teamElementStiffness puts a Dim x Dim block (a, b) of element e: into the element
/// matrices ke(e, i, j).
template <int Dim, class View> struct ElementMatrixSink {
  View ke;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex e, int a, int b,
                                         const double (&blk)[Dim][Dim]) const {
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j)
        ke(e, Dim * a + i, Dim * b + j) = blk[i][j];
  }
};

/// Where teamElementStiffness puts a Dim x Dim block (p, b) of element e: added times `scale`
/// into CSR through the scatter map (as scatterElementStiffness), with atomics.
template <int Dim, class MemorySpace, class Map> struct CsrScatterSink {
  CsrMatrix<MemorySpace> a;
  Map map;
  MeshView<MemorySpace, Dim> mesh;
  double scale;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex e, int p, int b,
                                         const double (&blk)[Dim][Dim]) const {
    const LocalIndex row = mesh.connectivity(e, p);
    const Offset column = Dim * map(e, p, b);
    for (int i = 0; i < Dim; ++i) {
      const Offset k = a.rowOffsets(Dim * row + i) + column;
      for (int j = 0; j < Dim; ++j)
        Kokkos::atomic_add(&a.values(k + j), scale * blk[i][j]);
    }
  }
};

/// The team-per-element stiffness t int B^T D B dA (the arithmetic of stiffnessLanes): one team
/// per element. In the team's scratch: the nodal coordinates, the tangent D of the element's law
/// at zero strain, and at every quadrature point the physical gradients and the weight
/// t w det J, each quadrature point's geometry computed by one thread. Then one thread per node
/// pair (a, b) sums its Dim x Dim block B_a^T (f D B_b) over the quadrature points and hands it
/// to the sink. A functor, not a lambda: no nvcc lambda wrapper (docs/gpu.md).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Sink>
struct TeamStiffness {
  using Member = typename Kokkos::TeamPolicy<ExecSpace>::member_type;
  using Scratch = Kokkos::View<double *, typename ExecSpace::scratch_memory_space,
                               Kokkos::MemoryTraits<Kokkos::Unmanaged>>;
  static constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nq = Elem::kNumQp;
  static constexpr int nv = Voigt<dim>::kSize;
  // Scratch layout: gradients g[q][a][i], weights f[q], D[r][s], coordinates x[a][i].
  static constexpr int kG = 0, kF = nq * n * dim, kD = kF + nq, kX = kD + nv * nv;
  static constexpr int kScratch = kX + n * dim;

  MeshView<MemorySpace, dim> mesh;
  double thickness;
  Law law;
  Sink sink;

  KOKKOS_INLINE_FUNCTION void operator()(const Member &team) const {
    using V = Voigt<dim>;
    const LocalIndex e = team.league_rank();
    const Scratch s(team.team_scratch(0), kScratch);
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, n * dim), [&](int k) {
      s(kX + k) = mesh.coordinates(mesh.connectivity(e, k / dim), k % dim);
    });
    Kokkos::single(Kokkos::PerTeam(team), [&]() {
      const auto t = law.at(e).tangent(Vector<nv>{});
      for (int r = 0; r < nv; ++r)
        for (int c = 0; c < nv; ++c)
          s(kD + nv * r + c) = t.m[r][c];
    });
    team.team_barrier();
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, nq), [&](int q) {
      double sh[n], dn[n][dim], xe[n][dim], g[n][dim];
      const double w = referencePoint<Elem>(q, sh, dn);
      for (int a = 0; a < n; ++a)
        for (int i = 0; i < dim; ++i)
          xe[a][i] = s(kX + dim * a + i);
      const double det = pointGeometry<Elem>(xe, dn, g);
      for (int a = 0; a < n; ++a)
        for (int i = 0; i < dim; ++i)
          s(kG + dim * (n * q + a) + i) = g[a][i];
      s(kF + q) = thickness * w * det;
    });
    team.team_barrier();
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, n * n), [&](int p) {
      const int a = p / n, b = p % n;
      double d[nv][nv], blk[dim][dim] = {};
      for (int r = 0; r < nv; ++r)
        for (int c = 0; c < nv; ++c)
          d[r][c] = s(kD + nv * r + c);
      for (int q = 0; q < nq; ++q) {
        double ga[dim], gb[dim];
        for (int i = 0; i < dim; ++i) {
          ga[i] = s(kG + dim * (n * q + a) + i);
          gb[i] = s(kG + dim * (n * q + b) + i);
        }
        const double f = s(kF + q);
        // f D B_b and B_a^T (f D B_b) as in stiffnessLanes.
        double db[nv][dim];
        for (int k = 0; k < nv; ++k)
          for (int j = 0; j < dim; ++j) {
            double v = d[k][j] * gb[j];
            for (int m = dim; m < nv; ++m) {
              if (V::row(m) == j)
                v += d[k][m] * gb[V::col(m)];
              if (V::col(m) == j)
                v += d[k][m] * gb[V::row(m)];
            }
            db[k][j] = v * f;
          }
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) {
            double v = ga[i] * db[i][j];
            for (int k = dim; k < nv; ++k) {
              if (V::row(k) == i)
                v += ga[V::col(k)] * db[k][j];
              if (V::col(k) == i)
                v += ga[V::row(k)] * db[k][j];
            }
            blk[i][j] += v;
          }
      }
      sink(e, a, b, blk);
    });
  }
};

} // namespace detail

/// Runs the team-per-element stiffness over every element of the mesh, each block handed to
/// `sink` (detail::ElementMatrixSink or detail::CsrScatterSink). teamSize 0 chooses: the node
/// pairs rounded up to whole warps on GPUs (at most what the kernel's registers allow), one
/// thread on CPUs. The unit tests pass 2 or 3 on CPU threads so that the team's shared scratch
/// and barriers are exercised there too.
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Sink>
void teamElementStiffness(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                          double thickness, const Law &law, const Sink &sink, int teamSize = 0) {
  using F = detail::TeamStiffness<Elem, ExecSpace, Law, MemorySpace, Sink>;
  const int ne = static_cast<int>(mesh.connectivity.extent(0));
  if (ne == 0)
    return;
  const F f{mesh, thickness, law, sink};
  const auto scratch = Kokkos::PerTeam(F::Scratch::shmem_size(F::kScratch));
  if (teamSize <= 0) {
    constexpr bool host = Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible;
    constexpr int pairs = Elem::kNumNodes * Elem::kNumNodes;
    const Kokkos::TeamPolicy<ExecSpace> probe =
        Kokkos::TeamPolicy<ExecSpace>(exec, ne, Kokkos::AUTO).set_scratch_size(0, scratch);
    const int most = probe.team_size_max(f, Kokkos::ParallelForTag());
    teamSize = host ? 1 : (pairs + 31) / 32 * 32 < most ? (pairs + 31) / 32 * 32 : most;
  }
  Kokkos::parallel_for(
      "mixcon::kernels::teamElementStiffness",
      Kokkos::TeamPolicy<ExecSpace>(exec, ne, teamSize).set_scratch_size(0, scratch), f);
}

/// Element stiffness matrices of all elements into ke(e, i, j), SIMD lanes of elements per thread
/// (stiffnessLanes).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class... P>
void computeElementStiffnessLanes(const ExecSpace &exec,
                                  const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                                  const Law &law, const Kokkos::View<double ***, P...> &ke) {
  constexpr int nd = Elem::kDim * Elem::kNumNodes;
  constexpr int W = kStiffnessLanes<ExecSpace>;
  const LocalIndex ne = static_cast<LocalIndex>(mesh.connectivity.extent(0));
  Kokkos::parallel_for(
      "mixcon::kernels::elementStiffness",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, (ne + W - 1) / W), KOKKOS_LAMBDA(LocalIndex batch) {
        const LocalIndex first = batch * W;
        double k[nd][nd][W];
        stiffnessLanes<Elem, W>(mesh, thickness, law, first, ne - 1, k);
        for (int l = 0; l < W && first + l < ne; ++l)
          for (int i = 0; i < nd; ++i)
            for (int j = 0; j < nd; ++j)
              ke(first + l, i, j) = k[i][j][l];
      });
}

/// Element stiffness matrices of all elements into ke(e, i, j), one team per element.
template <class Elem, class ExecSpace, class Law, class MemorySpace, class... P>
void computeElementStiffnessTeam(const ExecSpace &exec,
                                 const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                                 const Law &law, const Kokkos::View<double ***, P...> &ke,
                                 int teamSize = 0) {
  using Sink = detail::ElementMatrixSink<Elem::kDim, Kokkos::View<double ***, P...>>;
  teamElementStiffness<Elem>(exec, mesh, thickness, law, Sink{ke}, teamSize);
}

/// Element stiffness matrices of all elements into ke(e, i, j) (extent E x Dim n x Dim n): one
/// team per element where kTeamStiffness, else SIMD lanes of elements per thread.
template <class Elem, class ExecSpace, class Law, class MemorySpace, class... P>
void computeElementStiffness(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                             double thickness, const Law &law,
                             const Kokkos::View<double ***, P...> &ke) {
  if constexpr (kTeamStiffness<ExecSpace, Elem>)
    computeElementStiffnessTeam<Elem>(exec, mesh, thickness, law, ke);
  else
    computeElementStiffnessLanes<Elem>(exec, mesh, thickness, law, ke);
}

/// Computes the stiffness of every element and adds it times `scale` into `a` (pattern from
/// expandGraph(graph, Dim)) via the scatter map from elementScatterMap: one pass, no
/// element-matrix storage, atomics; `a.values` is not zeroed. SIMD lanes of elements per thread.
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Map>
void assembleElementStiffnessLanes(const ExecSpace &exec,
                                   const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                                   const Law &law, const Map &map, const CsrMatrix<MemorySpace> &a,
                                   double scale = 1.0) {
  constexpr int nd = Elem::kDim * Elem::kNumNodes;
  constexpr int W = kStiffnessLanes<ExecSpace>;
  const LocalIndex ne = static_cast<LocalIndex>(mesh.connectivity.extent(0));
  Kokkos::parallel_for(
      "mixcon::kernels::assembleElementStiffness",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, (ne + W - 1) / W), KOKKOS_LAMBDA(LocalIndex batch) {
        const LocalIndex first = batch * W;
        double kw[nd][nd][W];
        stiffnessLanes<Elem, W>(mesh, thickness, law, first, ne - 1, kw);
        for (int l = 0; l < W && first + l < ne; ++l) {
          double k[nd][nd];
          for (int i = 0; i < nd; ++i)
            for (int j = 0; j < nd; ++j)
              k[i][j] = kw[i][j][l];
          scatterElementStiffness<Elem>(a, map, mesh, first + l, scale, k);
        }
      });
}

/// assembleElementStiffnessLanes with one team per element.
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Map>
void assembleElementStiffnessTeam(const ExecSpace &exec,
                                  const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                                  const Law &law, const Map &map, const CsrMatrix<MemorySpace> &a,
                                  double scale = 1.0, int teamSize = 0) {
  using Sink = detail::CsrScatterSink<Elem::kDim, MemorySpace, Map>;
  teamElementStiffness<Elem>(exec, mesh, thickness, law, Sink{a, map, mesh, scale}, teamSize);
}

/// Computes the stiffness of every element and adds it times `scale` into `a` (pattern from
/// expandGraph(graph, Dim)) via the scatter map from elementScatterMap: one pass, no
/// element-matrix storage, atomics; `a.values` is not zeroed. One team per element where
/// kTeamStiffness, else SIMD lanes of elements per thread.
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Map>
void assembleElementStiffness(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                              double thickness, const Law &law, const Map &map,
                              const CsrMatrix<MemorySpace> &a, double scale = 1.0) {
  if constexpr (kTeamStiffness<ExecSpace, Elem>)
    assembleElementStiffnessTeam<Elem>(exec, mesh, thickness, law, map, a, scale);
  else
    assembleElementStiffnessLanes<Elem>(exec, mesh, thickness, law, map, a, scale);
}

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
