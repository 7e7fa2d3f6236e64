// The upper block triangle of a symmetric matrix stored by node blocks, and y = A x from it on the
// host's threads: each off-diagonal block read once for both of its products (A_IJ x_J into row I,
// A_IJ^T x_I into row J), half the bytes of the whole matrix's product (the CG's product with K).
// Host-accessible memory only: the rows of a chunk of nodes are one thread's. Layer: kernels.
#pragma once

#include <kernels/SparseMatrix.hpp>

#include <algorithm>

namespace mixcon {

/// The blocks (I, J >= I) of a matrix with symmetric node blocks (nodeBlocks), for y = A x. The
/// nodes are cut into chunks of consecutive nodes, run by the host's threads: a chunk adds into its
/// own rows, and keeps what it adds to rows past its last node in its spill, which lies in the next
/// chunk's rows (a chunk is longer than the node numbering's bandwidth); the spills are added
/// after.
template <class MemorySpace> struct SymmetricBlocks {
  Kokkos::View<Offset *, MemorySpace> offsets;     ///< nodes + 1, in upper blocks
  Kokkos::View<LocalIndex *, MemorySpace> columns; ///< each block's node column (at least its row)
  Kokkos::View<double *, MemorySpace> values;      ///< d^2 per block, row-major
  LocalIndex chunkNodes = 0;                       ///< nodes per chunk (the last one may be short)
  LocalIndex chunks = 0;                           ///< at least the minChunks asked for
  Kokkos::View<Offset *, MemorySpace> spillStart;  ///< chunks + 1, in unknowns
  Kokkos::View<double *, MemorySpace> spill;       ///< what each chunk adds past its last node
  int d = 0;                                       ///< 0: none
  LocalIndex numNodes() const { return d > 0 ? static_cast<LocalIndex>(offsets.extent(0)) - 1 : 0; }
};

/// The upper block triangle of the matrix with node blocks `blocks` and values `values` (in the
/// CSR's order), which the caller says is symmetric (the blocks below the diagonal are not read,
/// as a Cholesky factorization does not read that triangle), or none (d = 0) where the memory is
/// not the host's, a node has no diagonal block, or there would be fewer than `minChunks` chunks.
/// A chunk has `minChunkNodes` nodes, more where the numbering's bandwidth needs it: the chunks
/// and so the product's sums depend on the mesh only, not on the host's threads.
template <class MemorySpace>
SymmetricBlocks<MemorySpace>
symmetricBlocks(const NodeBlocks<MemorySpace> &blocks,
                const Kokkos::View<const double *, MemorySpace> &values, int minChunks,
                LocalIndex minChunkNodes = 16384) {
  SymmetricBlocks<MemorySpace> s;
  const int d = blocks.d;
  const LocalIndex nodes = blocks.numNodes();
  if (!kHostAccessible<MemorySpace> || d == 0 || nodes == 0)
    return s;
  Kokkos::DefaultExecutionSpace().fence(); // the blocks and values, where a device wrote them
  const auto bo = blocks.offsets;
  const auto bc = blocks.columns;
  // each node's diagonal block (so no row is empty), then the numbering's bandwidth
  Kokkos::View<Offset *, MemorySpace> diagonal("mixcon::csr::symmetricDiagonal", nodes);
  LocalIndex missing = 0, bandwidth = 0;
  Kokkos::parallel_reduce(
      "mixcon::csr::symmetricDiagonals", HostRange(0, nodes),
      [=](LocalIndex i, LocalIndex &bad) { // host memory: the row's columns are in order
        const LocalIndex *first = bc.data() + bo(i), *last = bc.data() + bo(i + 1);
        const LocalIndex *at = std::lower_bound(first, last, i);
        diagonal(i) = at - first;
        if (at == last || *at != i)
          ++bad;
      },
      missing);
  if (missing > 0)
    return s;
  Kokkos::parallel_reduce(
      "mixcon::csr::symmetricBandwidth", HostRange(0, nodes),
      [=](LocalIndex i, LocalIndex &band) { band = std::max(band, bc(bo(i + 1) - 1) - i); },
      Kokkos::Max<LocalIndex>(bandwidth));
  const LocalIndex chunkNodes = std::max(minChunkNodes, bandwidth + 1);
  const LocalIndex chunks = (nodes + chunkNodes - 1) / chunkNodes;
  if (chunks < minChunks)
    return s;
  s.offsets = Kokkos::View<Offset *, MemorySpace>("mixcon::csr::symmetricOffsets", nodes + 1);
  const auto offsets = s.offsets;
  Kokkos::parallel_scan("mixcon::csr::symmetricScan", HostRange(0, nodes + 1),
                        [=](LocalIndex i, Offset &sum, bool last) {
                          const Offset count = i < nodes ? bo(i + 1) - bo(i) - diagonal(i) : 0;
                          if (last)
                            offsets(i) = sum;
                          sum += count;
                        });
  Kokkos::DefaultHostExecutionSpace().fence();
  const Offset count = offsets(nodes);
  s.columns = Kokkos::View<LocalIndex *, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::csr::symmetricColumns"), count);
  s.values = Kokkos::View<double *, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::csr::symmetricValues"),
      count * d * d);
  const auto columns = s.columns;
  const auto upper = s.values;
  Kokkos::parallel_for("mixcon::csr::symmetricCopy", HostRange(0, nodes), [=](LocalIndex i) {
    const Offset fi = bo(i), di = bo(i + 1) - fi;
    for (Offset p = diagonal(i); p < di; ++p) {
      const Offset b = offsets(i) + p - diagonal(i);
      columns(b) = bc(fi + p);
      for (int r = 0; r < d; ++r)
        for (int k = 0; k < d; ++k)
          upper(d * d * b + d * r + k) = values(d * d * fi + d * r * di + d * p + k);
    }
  });
  // each chunk's spill: from its end to the last column its blocks reach
  s.spillStart =
      Kokkos::View<Offset *, MemorySpace>("mixcon::csr::symmetricSpillStart", chunks + 1);
  for (LocalIndex c = 0; c < chunks; ++c) {
    const LocalIndex first = c * chunkNodes, end = std::min(nodes, first + chunkNodes);
    LocalIndex reach = end;
    for (LocalIndex i = std::max(first, end - bandwidth); i < end; ++i)
      reach = std::max(reach, bc(bo(i + 1) - 1) + 1);
    s.spillStart(c + 1) = s.spillStart(c) + d * static_cast<Offset>(reach - end);
  }
  s.spill =
      Kokkos::View<double *, MemorySpace>("mixcon::csr::symmetricSpill", s.spillStart(chunks));
  Kokkos::DefaultHostExecutionSpace().fence();
  s.chunkNodes = chunkNodes;
  s.chunks = chunks;
  s.d = d;
  return s;
}

namespace detail {
template <int D, class MemorySpace>
void multiplySymmetric(const SymmetricBlocks<MemorySpace> &s,
                       const Kokkos::View<const double *, MemorySpace> &x,
                       const Kokkos::View<double *, MemorySpace> &y) {
  const auto bo = s.offsets;
  const auto bc = s.columns;
  const auto va = s.values;
  const auto start = s.spillStart;
  const auto spill = s.spill;
  const LocalIndex nodes = s.numNodes(), chunkNodes = s.chunkNodes;
  Kokkos::DefaultExecutionSpace().fence(); // x, where a device wrote it
  Kokkos::parallel_for("mixcon::csr::symmetricZero", HostRange(0, D * nodes),
                       [=](LocalIndex i) { y(i) = 0.0; });
  Kokkos::deep_copy(Kokkos::DefaultHostExecutionSpace(), spill, 0.0);
  // a chunk's nodes in order on one thread: its own rows, then its spill
  Kokkos::parallel_for(
      "mixcon::csr::symmetricChunks",
      Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace, Kokkos::Schedule<Kokkos::Dynamic>>(
          0, s.chunks),
      [=](LocalIndex c) {
        const LocalIndex first = c * chunkNodes, end = std::min(nodes, first + chunkNodes);
        const Offset own = static_cast<Offset>(D) * end, spilled = start(c);
        for (LocalIndex i = first; i < end; ++i) {
          double xi[D], yi[D] = {};
          for (int r = 0; r < D; ++r)
            xi[r] = x(D * i + r);
          for (Offset b = bo(i); b < bo(i + 1); ++b) {
            const Offset j = D * static_cast<Offset>(bc(b)), at = D * D * b;
            for (int r = 0; r < D; ++r)
              for (int k = 0; k < D; ++k)
                yi[r] += va(at + D * r + k) * x(j + k);
            if (j == D * static_cast<Offset>(i))
              continue;
            for (int k = 0; k < D; ++k) {
              double t = 0.0;
              for (int r = 0; r < D; ++r)
                t += va(at + D * r + k) * xi[r];
              if (j < own)
                y(j + k) += t;
              else
                spill(spilled + j - own + k) += t;
            }
          }
          for (int r = 0; r < D; ++r)
            y(D * i + r) += yi[r];
        }
      });
  // chunk c's spill into the first rows of chunk c + 1 (no two chunks' spills share a row)
  Kokkos::parallel_for("mixcon::csr::symmetricSpills", HostRange(0, s.chunks), [=](LocalIndex c) {
    const Offset own = static_cast<Offset>(D) * std::min(nodes, (c + 1) * chunkNodes);
    for (Offset k = start(c); k < start(c + 1); ++k)
      y(own + k - start(c)) += spill(k);
  });
  Kokkos::DefaultHostExecutionSpace().fence();
}
} // namespace detail

/// y = A x from A's upper block triangle (symmetricBlocks, d = 2 or 3) on the host's threads. The
/// sums differ from the CSR product's only in their order; they do not depend on the thread count.
template <class MemorySpace>
void multiply(const SymmetricBlocks<MemorySpace> &s,
              const Kokkos::View<const double *, MemorySpace> &x,
              const Kokkos::View<double *, MemorySpace> &y) {
  if (s.d == 3)
    detail::multiplySymmetric<3>(s, x, y);
  else
    detail::multiplySymmetric<2>(s, x, y);
}

} // namespace mixcon
