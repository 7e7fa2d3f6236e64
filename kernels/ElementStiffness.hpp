// The element stiffness t int B^T D B dA of the generic element driver (kernels/ElementDriver.hpp)
// in its two forms: SIMD lanes of elements per thread (stiffnessLanes: CPUs and the small elements
// on GPUs) and one team per element (teamElementStiffness: the larger 3D elements on GPUs), the
// choice between them (kTeamStiffness), and their element-matrix and fused CSR-assembly entry
// points; the CSR assembly adds with atomics, or on the host's threads by chunks of elements that
// share no node with plain adds (elementChunks). Layer: kernels.
#pragma once

#include <kernels/ElementGeometry.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

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

/// The weighted gradient products of the node pair (a, b) of W lanes, summed over the quadrature
/// points: mab[m][k][l] += fga[m][l] gb[k][l], with fga = f g_a (f the point's weight
/// t w det J).
template <int Dim, int W>
KOKKOS_INLINE_FUNCTION void addGradientProducts(const double (&fga)[Dim][W],
                                                const double (&gb)[Dim][W],
                                                double (&mab)[Dim][Dim][W]) {
  for (int m = 0; m < Dim; ++m)
    for (int k = 0; k < Dim; ++k)
      for (int l = 0; l < W; ++l)
        mab[m][k][l] += fga[m][l] * gb[k][l];
}

/// The tangent D (Voigt, engineering shear strains) of W lanes as the tensor
/// c[i][m][j][k][l] = C_imjk = D[Voigt::index(i, m)][Voigt::index(j, k)]: with engineering shear
/// strains the Voigt D holds the tensor's entries as they are.
template <int Dim, int W>
KOKKOS_INLINE_FUNCTION void
tangentTensor(const double (&d)[Voigt<Dim>::kSize][Voigt<Dim>::kSize][W],
              double (&c)[Dim][Dim][Dim][Dim][W]) {
  using V = Voigt<Dim>;
  for (int i = 0; i < Dim; ++i)
    for (int m = 0; m < Dim; ++m)
      for (int j = 0; j < Dim; ++j)
        for (int k = 0; k < Dim; ++k)
          for (int l = 0; l < W; ++l)
            c[i][m][j][k][l] = d[V::index(i, m)][V::index(j, k)][l];
}

/// The Dim x Dim block (a, b) of t int B_a^T D B_b dA from the pair's gradient products mab
/// (addGradientProducts) for a constant tangent: acc[r0 + i][c0 + j][l] = sum over m, k of
/// c(i, m, j, k, l) mab[m][k][l], c(i, m, j, k, l) the entry C_imjk of lane l (tangentTensor;
/// a callable, so that the team kernel reads it from its scratch).
template <int Dim, int W, class Tensor, int R, int C>
KOKKOS_INLINE_FUNCTION void contractTangent(const Tensor &c, const double (&mab)[Dim][Dim][W],
                                            double (&acc)[R][C][W], int r0, int c0) {
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) {
      double s[W] = {};
      for (int m = 0; m < Dim; ++m)
        for (int k = 0; k < Dim; ++k)
          for (int l = 0; l < W; ++l)
            s[l] += c(i, m, j, k, l) * mab[m][k][l];
      for (int l = 0; l < W; ++l)
        acc[r0 + i][c0 + j][l] = s[l];
    }
}

/// Adds rows r0 .. r0 + Dim - 1 and columns c0 .. c0 + Dim - 1 of m, times `scale`, as the
/// Dim x Dim block of element e's nodes (p, b) into CSR through the scatter map (map(e, p, b):
/// position of node b in the node-graph row of node p), with atomics (Atomic) or plain adds (the
/// caller's elements own their rows: elementChunks).
template <int Dim, bool Atomic = true, class MemorySpace, class Map, int R, int C>
KOKKOS_INLINE_FUNCTION void addElementBlock(const CsrMatrix<MemorySpace> &a, const Map &map,
                                            const MeshView<MemorySpace, Dim> &mesh, LocalIndex e,
                                            int p, int b, double scale, const double (&m)[R][C],
                                            int r0, int c0) {
  const LocalIndex row = mesh.connectivity(e, p);
  const Offset column = Dim * map(e, p, b);
  for (int i = 0; i < Dim; ++i) {
    const Offset k = a.rowOffsets(Dim * row + i) + column;
    for (int j = 0; j < Dim; ++j) {
      if constexpr (Atomic)
        Kokkos::atomic_add(&a.values(k + j), scale * m[r0 + i][c0 + j]);
      else
        a.values(k + j) += scale * m[r0 + i][c0 + j];
    }
  }
}

} // namespace detail

/// Element stiffness t int B^T D B dA (the report's Eq. (25) for D = C) of the W elements first,
/// first + 1, ... (clamped to last: a short final batch repeats its last element) into lane l of
/// ke[i][j][l], dofs node-interleaved (u_1, v_1, u_2, ...). D is the tangent of the element's
/// point law (law.at(e)) at zero strain, evaluated once per element (the law's parameters are per
/// element). In index form the block of nodes (a, b) is K_(a i)(b j) = sum over m, k of C_imjk
/// int g_a[m] g_b[k] t dA, g the physical gradients: the quadrature points sum the gradient
/// products of every node pair a <= b (Dim^2 per pair and point), then each block contracts
/// them with D once (contractTangent). Against forming B_a^T (f D B_b) at every point, as
/// before: 1.8x fewer floating-point operations for Hex8 (13,672 against 24,928 per element),
/// 2.4x for Hex20, 1.2x for Tet10, 1.4-1.6x for Quad4 and Quad8, but 1.7x more for Tet4 (one
/// point: 1,988 against 1,148), whose kernel is bound by writing its matrices and still ran 1.1x
/// faster (bench/bench_linear_stiffness.cpp counts them; docs/performance.md table 3m). The
/// lower blocks are mirrored at the end (D is symmetric).
template <class Elem, int W, class Law, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
stiffnessLanes(const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness, const Law &law,
               LocalIndex first, LocalIndex last,
               double (&ke)[Elem::kDim * Elem::kNumNodes][Elem::kDim * Elem::kNumNodes][W]) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  constexpr int pairs = n * (n + 1) / 2; // a <= b, b-major
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
  double mm[pairs][dim][dim][W];
  for (int p = 0; p < pairs; ++p)
    for (int m = 0; m < dim; ++m)
      for (int k = 0; k < dim; ++k)
        for (int l = 0; l < W; ++l)
          mm[p][m][k][l] = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], dn[n][dim], g[n][dim][W], fg[n][dim][W], det[W], f[W];
    const double w = detail::referencePoint<Elem>(q, sh, dn); // shared by the lanes
    detail::laneGeometry<Elem, W>(xe, dn, g, det);
    for (int l = 0; l < W; ++l)
      f[l] = thickness * w * det[l];
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < dim; ++i)
        for (int l = 0; l < W; ++l)
          fg[a][i][l] = f[l] * g[a][i][l];
    for (int b = 0, p = 0; b < n; ++b)
      for (int a = 0; a <= b; ++a, ++p)
        detail::addGradientProducts<dim, W>(fg[a], g[b], mm[p]);
  }
  double c[dim][dim][dim][dim][W];
  detail::tangentTensor<dim, W>(d, c);
  const auto tensor = [&](int i, int m, int j, int k, int l) { return c[i][m][j][k][l]; };
  for (int b = 0, p = 0; b < n; ++b)
    for (int a = 0; a <= b; ++a, ++p)
      detail::contractTangent<dim, W>(tensor, mm[p], ke, dim * a, dim * b);
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
  for (int p = 0; p < Elem::kNumNodes; ++p)
    for (int b = 0; b < Elem::kNumNodes; ++b)
      detail::addElementBlock<dim>(a, map, m, e, p, b, scale, ke, dim * p, dim * b);
}

/// True where the element stiffness kernels of ExecSpace run one team per element
/// (teamElementStiffness) rather than SIMD lanes of elements per thread (stiffnessLanes): on GPUs,
/// for the 3D elements of 24 or more unknowns (Hex8, Hex20, Tet10). Measured on an H200
/// (docs/gpu.md, 2026-11-28): the team form writes the element matrices of Hex8, Hex20 and Tet10
/// 1.36x, 2.38x and 1.06x faster and assembles the Hex8 CSR 4.7x faster; it is slower for Quad4,
/// Quad8 and Tet4 (0.15x, 0.81x, 0.42x), whose matrices one thread holds without much spilling.
/// Those figures are of the arithmetic before the gradient products (stiffnessLanes), which has
/// not run on a GPU yet: it holds the pairs' products beside the element matrix. On CPUs the
/// lanes are always taken.
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
/// into CSR through the scatter map (as scatterElementStiffness), with atomics (Atomic) or plain
/// adds (the chunks of elementChunks, one parity at a time).
template <int Dim, class MemorySpace, class Map, bool Atomic = true> struct CsrScatterSink {
  CsrMatrix<MemorySpace> a;
  Map map;
  MeshView<MemorySpace, Dim> mesh;
  double scale;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex e, int p, int b,
                                         const double (&blk)[Dim][Dim]) const {
    addElementBlock<Dim, Atomic>(a, map, mesh, e, p, b, scale, blk, 0, 0);
  }
};

/// The team-per-element stiffness t int B^T D B dA (the arithmetic of stiffnessLanes): one team
/// per element. In the team's scratch: the nodal coordinates, the tangent of the element's law at
/// zero strain as the tensor C_imjk (tangentTensor), and at every quadrature point the physical
/// gradients and the weight t w det J, each quadrature point's geometry computed by one thread.
/// Then one thread per node pair (a, b) sums the pair's gradient products over the quadrature
/// points, contracts them with C into its Dim x Dim block and hands it to the sink. A functor, not
/// a lambda: no nvcc lambda wrapper (docs/gpu.md).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Sink>
struct TeamStiffness {
  using Member = typename Kokkos::TeamPolicy<ExecSpace>::member_type;
  using Scratch = Kokkos::View<double *, typename ExecSpace::scratch_memory_space,
                               Kokkos::MemoryTraits<Kokkos::Unmanaged>>;
  static constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nq = Elem::kNumQp;
  static constexpr int nv = Voigt<dim>::kSize;
  // Scratch layout: gradients g[q][a][i], weights f[q], the tangent tensor C[i][m][j][k]
  // (detail::tangentTensor), coordinates x[a][i].
  static constexpr int kG = 0, kF = nq * n * dim, kD = kF + nq, kX = kD + dim * dim * dim * dim;
  static constexpr int kScratch = kX + n * dim;
  /// Scratch position of the tangent tensor's entry C_imjk.
  KOKKOS_INLINE_FUNCTION static constexpr int tensorAt(int i, int m, int j, int k) {
    return kD + ((i * dim + m) * dim + j) * dim + k;
  }

  MeshView<MemorySpace, dim> mesh;
  double thickness;
  Law law;
  Sink sink;

  KOKKOS_INLINE_FUNCTION void operator()(const Member &team) const {
    const LocalIndex e = team.league_rank();
    const Scratch s(team.team_scratch(0), kScratch);
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, n * dim), [&](int k) {
      s(kX + k) = mesh.coordinates(mesh.connectivity(e, k / dim), k % dim);
    });
    Kokkos::single(Kokkos::PerTeam(team), [&]() {
      const auto t = law.at(e).tangent(Vector<nv>{});
      double d[nv][nv][1], c[dim][dim][dim][dim][1];
      for (int r = 0; r < nv; ++r)
        for (int k = 0; k < nv; ++k)
          d[r][k][0] = t.m[r][k];
      tangentTensor<dim, 1>(d, c);
      for (int i = 0; i < dim; ++i)
        for (int m = 0; m < dim; ++m)
          for (int j = 0; j < dim; ++j)
            for (int k = 0; k < dim; ++k)
              s(tensorAt(i, m, j, k)) = c[i][m][j][k][0];
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
      // The arithmetic of stiffnessLanes with one lane: the pair's gradient products over the
      // quadrature points, then one contraction with D.
      double mab[dim][dim][1] = {}, acc[dim][dim][1];
      for (int q = 0; q < nq; ++q) {
        double fga[dim][1], gb[dim][1];
        for (int i = 0; i < dim; ++i) {
          fga[i][0] = s(kF + q) * s(kG + dim * (n * q + a) + i);
          gb[i][0] = s(kG + dim * (n * q + b) + i);
        }
        addGradientProducts<dim, 1>(fga, gb, mab);
      }
      const auto tensor = [&](int i, int m, int j, int k, int) { return s(tensorAt(i, m, j, k)); };
      contractTangent<dim, 1>(tensor, mab, acc, 0, 0);
      double blk[dim][dim];
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          blk[i][j] = acc[i][j][0];
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
    // the node pairs in whole warps of 32 threads
    constexpr int pairs = (Elem::kNumNodes * Elem::kNumNodes + 31) / 32 * 32;
    const Kokkos::TeamPolicy<ExecSpace> probe =
        Kokkos::TeamPolicy<ExecSpace>(exec, ne, Kokkos::AUTO).set_scratch_size(0, scratch);
    const int most = probe.team_size_max(f, Kokkos::ParallelForTag());
    teamSize = host ? 1 : pairs < most ? pairs : most;
  }
  Kokkos::parallel_for(
      "mixcon::kernels::teamElementStiffness",
      Kokkos::TeamPolicy<ExecSpace>(exec, ne, teamSize).set_scratch_size(0, scratch), f);
}

namespace detail {

/// The stiffness of the W elements first, first + 1, ... below end (stiffnessLanes), each Dim x Dim
/// block (p, b) of element e handed to `sink(e, p, b, block)`.
template <class Elem, int W, class Law, class MemorySpace, class Sink>
KOKKOS_INLINE_FUNCTION void laneBatch(const MeshView<MemorySpace, Elem::kDim> &mesh,
                                      double thickness, const Law &law, LocalIndex first,
                                      LocalIndex end, const Sink &sink) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nd = dim * n;
  double k[nd][nd][W];
  stiffnessLanes<Elem, W>(mesh, thickness, law, first, end - 1, k);
  for (int l = 0; l < W && first + l < end; ++l)
    for (int p = 0; p < n; ++p)
      for (int b = 0; b < n; ++b) {
        double blk[dim][dim];
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j)
            blk[i][j] = k[dim * p + i][dim * b + j][l];
        sink(first + l, p, b, blk);
      }
}

} // namespace detail

/// The stiffness of every element by SIMD lanes of elements per thread (stiffnessLanes), each
/// Dim x Dim block (p, b) of element e handed to `sink(e, p, b, block)` (the sinks of
/// teamElementStiffness): kernel `label`.
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Sink>
void laneElementStiffness(const ExecSpace &exec, const char *label,
                          const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                          const Law &law, const Sink &sink) {
  constexpr int W = kStiffnessLanes<ExecSpace>;
  const LocalIndex ne = static_cast<LocalIndex>(mesh.connectivity.extent(0));
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(exec, 0, (ne + W - 1) / W),
      KOKKOS_LAMBDA(LocalIndex batch) {
        detail::laneBatch<Elem, W>(mesh, thickness, law, batch * W, ne, sink);
      });
}

/// Consecutive elements cut into chunks for an assembly without atomics on the host's threads:
/// the nodes of chunk c lie in [lo_c, hi_c] with hi_c < lo_(c+2), so no two chunks of one parity
/// share a node (hi_c < lo_(c+2) <= hi_(c+2) < lo_(c+4) ...): the even chunks run at once, then
/// the odd ones, each chunk's elements in order on one thread with plain adds. The sums then
/// depend on the mesh only, not on the threads' timing (atomics add in any order). size == 0: no
/// such cut (elementChunks found none): atomics.
struct ElementChunks {
  LocalIndex size = 0;  ///< elements per chunk (the last one may be short)
  LocalIndex count = 0; ///< chunks
};

/// The chunks of elementChunks's rule for the elements of type Elem in `mesh`: `base` consecutive
/// elements per chunk, doubled until no two chunks of one parity share a node, if that leaves at
/// least `minChunks` chunks (and two); else none. Host memory and a host execution space only
/// (else none). A pass over the connectivity plus a serial pass over its blocks of `base`
/// elements (the cube N = 100: 489 blocks; chunks of 16,384 elements).
template <class Elem, class ExecSpace, class MemorySpace>
ElementChunks elementChunks(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                            LocalIndex minChunks, LocalIndex base = 2048) {
  constexpr bool host = Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible;
  if constexpr (!host || !kHostAccessible<MemorySpace>) {
    return {};
  } else {
    using Wide = std::int64_t; // block bounds past the last element stay in range
    const Wide ne = static_cast<Wide>(mesh.connectivity.extent(0));
    if (ne == 0 || base <= 0)
      return {};
    const LocalIndex blocks = static_cast<LocalIndex>((ne + base - 1) / base);
    const LocalIndex least = std::max<LocalIndex>(minChunks, 2);
    if (blocks < least)
      return {};
    Kokkos::View<LocalIndex *, Kokkos::HostSpace> low(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::kernels::chunkLow"), blocks);
    Kokkos::View<LocalIndex *, Kokkos::HostSpace> high(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::kernels::chunkHigh"), blocks);
    const auto conn = mesh.connectivity;
    exec.fence(); // the connectivity, where a kernel on exec wrote it
    Kokkos::parallel_for("mixcon::kernels::chunkNodeRanges",
                         Kokkos::RangePolicy<ExecSpace>(exec, 0, blocks), [=](LocalIndex k) {
                           const Wide first = static_cast<Wide>(k) * base;
                           const Wide end = std::min(ne, first + base);
                           LocalIndex lo = conn(first, 0), hi = lo;
                           for (Wide e = first; e < end; ++e)
                             for (int a = 0; a < Elem::kNumNodes; ++a) {
                               lo = std::min(lo, conn(e, a));
                               hi = std::max(hi, conn(e, a));
                             }
                           low(k) = lo;
                           high(k) = hi;
                         });
    exec.fence();
    for (LocalIndex merge = 1; (blocks + merge - 1) / merge >= least; merge *= 2) {
      const LocalIndex chunks = (blocks + merge - 1) / merge;
      std::vector<LocalIndex> chunkLow(chunks), chunkHigh(chunks);
      for (LocalIndex c = 0; c < chunks; ++c) {
        chunkLow[c] = low(c * merge);
        chunkHigh[c] = high(c * merge);
        for (LocalIndex k = c * merge + 1; k < std::min(blocks, (c + 1) * merge); ++k) {
          chunkLow[c] = std::min(chunkLow[c], low(k));
          chunkHigh[c] = std::max(chunkHigh[c], high(k));
        }
      }
      bool apart = true;
      for (LocalIndex c = 0; c + 2 < chunks && apart; ++c)
        apart = chunkHigh[c] < chunkLow[c + 2];
      if (apart)
        return {static_cast<LocalIndex>(std::min<Wide>(ne, static_cast<Wide>(base) * merge)),
                chunks};
    }
    return {};
  }
}

/// The stiffness of every element by SIMD lanes of elements per thread (stiffnessLanes), chunk by
/// chunk (ElementChunks: the even chunks at once, then the odd ones, each on one thread), each
/// Dim x Dim block (p, b) of element e handed to `sink(e, p, b, block)`: kernel `label`. Host
/// execution spaces only (a chunk runs its elements in order).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Sink>
void chunkElementStiffness(const ExecSpace &exec, const char *label,
                           const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                           const Law &law, const ElementChunks &chunks, const Sink &sink) {
  static_assert(Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible,
                "chunkElementStiffness runs on the host's threads");
  constexpr int W = kStiffnessLanes<ExecSpace>;
  const LocalIndex ne = static_cast<LocalIndex>(mesh.connectivity.extent(0));
  const LocalIndex size = chunks.size, count = chunks.count;
  for (LocalIndex parity = 0; parity < 2; ++parity) {
    Kokkos::parallel_for(label,
                         Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>(
                             exec, 0, (count - parity + 1) / 2),
                         [=](LocalIndex k) {
                           const LocalIndex first = (2 * k + parity) * size;
                           const LocalIndex end = size < ne - first ? first + size : ne;
                           for (LocalIndex batch = first; batch < end; batch += W)
                             detail::laneBatch<Elem, W>(mesh, thickness, law, batch, end, sink);
                         });
    exec.fence(); // the odd chunks add into rows the even ones share with them
  }
}

/// Element stiffness matrices of all elements into ke(e, i, j), SIMD lanes of elements per thread
/// (stiffnessLanes).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class... P>
void computeElementStiffnessLanes(const ExecSpace &exec,
                                  const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                                  const Law &law, const Kokkos::View<double ***, P...> &ke) {
  using Sink = detail::ElementMatrixSink<Elem::kDim, Kokkos::View<double ***, P...>>;
  laneElementStiffness<Elem>(exec, "mixcon::kernels::elementStiffness", mesh, thickness, law,
                             Sink{ke});
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
/// element-matrix storage; `a.values` is not zeroed. SIMD lanes of elements per thread. On the
/// host's threads by the chunks of `chunks` (elementChunks<Elem> of this mesh) with plain adds
/// where it has some, else with atomics: the Hex8 assembly of 110,592 elements took 503 ms with
/// the atomics and 214 ms by chunks on one thread (docs/performance.md table 3p).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Map>
void assembleElementStiffnessLanes(const ExecSpace &exec,
                                   const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                                   const Law &law, const Map &map, const CsrMatrix<MemorySpace> &a,
                                   double scale, const ElementChunks &chunks) {
  constexpr int dim = Elem::kDim;
  constexpr char label[] = "mixcon::kernels::assembleElementStiffness";
  if constexpr (Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible) {
    if (chunks.size > 0) {
      using Plain = detail::CsrScatterSink<dim, MemorySpace, Map, false>;
      chunkElementStiffness<Elem>(exec, label, mesh, thickness, law, chunks,
                                  Plain{a, map, mesh, scale});
      return;
    }
  }
  using Sink = detail::CsrScatterSink<dim, MemorySpace, Map>;
  laneElementStiffness<Elem>(exec, label, mesh, thickness, law, Sink{a, map, mesh, scale});
}

/// assembleElementStiffnessLanes on the chunks elementChunks finds (at least one per host thread
/// and parity: the cube N = 100's 62 chunks serve up to 31 threads), atomics where it finds none
/// (a small mesh, a scattered numbering, more threads) or off the host.
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Map>
void assembleElementStiffnessLanes(const ExecSpace &exec,
                                   const MeshView<MemorySpace, Elem::kDim> &mesh, double thickness,
                                   const Law &law, const Map &map, const CsrMatrix<MemorySpace> &a,
                                   double scale = 1.0) {
  ElementChunks chunks;
  if constexpr (Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible)
    chunks = elementChunks<Elem>(exec, mesh, 2 * static_cast<LocalIndex>(exec.concurrency()));
  assembleElementStiffnessLanes<Elem>(exec, mesh, thickness, law, map, a, scale, chunks);
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
/// element-matrix storage; `a.values` is not zeroed. One team per element where kTeamStiffness
/// (atomics), else SIMD lanes of elements per thread (on the host by element chunks without
/// atomics where elementChunks finds them).
template <class Elem, class ExecSpace, class Law, class MemorySpace, class Map>
void assembleElementStiffness(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &mesh,
                              double thickness, const Law &law, const Map &map,
                              const CsrMatrix<MemorySpace> &a, double scale = 1.0) {
  if constexpr (kTeamStiffness<ExecSpace, Elem>)
    assembleElementStiffnessTeam<Elem>(exec, mesh, thickness, law, map, a, scale);
  else
    assembleElementStiffnessLanes<Elem>(exec, mesh, thickness, law, map, a, scale);
}

} // namespace mixcon
