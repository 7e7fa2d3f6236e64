// Sparse matrix structures for element assembly: the node adjacency graph of a mesh, its
// expansion to a dof-level CSR matrix with interleaved nodal unknowns (node * dofsPerNode + comp),
// and the precomputed element-to-CSR scatter map. Data flow: mesh -> kernels (this) -> solver.
#pragma once

#include <core/Transfer.hpp>
#include <mesh/Mesh.hpp>

namespace mixcon {

/// Compressed sparse rows on `MemorySpace`. Rows are the locally owned unknowns; columns are local
/// indices (single rank: equal to global ones; with MPI the DofMap translates them).
template <class MemorySpace> struct CsrMatrix {
  Kokkos::View<Offset *, MemorySpace> rowOffsets;  ///< numRows + 1
  Kokkos::View<LocalIndex *, MemorySpace> columns; ///< sorted within each row
  Kokkos::View<double *, MemorySpace> values;
  LocalIndex numRows = 0;
  LocalIndex numColumns = 0;
  Offset numNonzeros() const { return static_cast<Offset>(columns.extent(0)); }
};

/// Node-to-node adjacency (every pair of nodes sharing an element, self included), host side.
struct NodeGraph {
  std::vector<Offset> rowOffsets;
  std::vector<LocalIndex> columns;
  LocalIndex numNodes() const { return static_cast<LocalIndex>(rowOffsets.size()) - 1; }
};

NodeGraph buildNodeGraph(const Mesh &mesh);

/// Nodes within two element layers of each node (the pattern of K12 M_L^-1 K12^T), self included.
NodeGraph secondNeighbourGraph(const NodeGraph &graph);

/// For a symmetric graph: t[p] is the position of entry (j, i) for the entry p = (i, j).
std::vector<Offset> transposePositions(const NodeGraph &graph);

/// Expands the node graph to a CSR pattern with `rowDofs` interleaved unknowns per node in the
/// rows and `columnDofs` in the columns (rectangular when they differ: a coupling block such as
/// the stresses' rows against the displacements' columns), values zero-initialized.
template <class MemorySpace>
CsrMatrix<MemorySpace> expandGraph(const NodeGraph &graph, int rowDofs, int columnDofs) {
  const LocalIndex nn = graph.numNodes();
  CsrMatrix<MemorySpace> a;
  a.numRows = nn * rowDofs;
  a.numColumns = nn * columnDofs;
  const Offset nnz = static_cast<Offset>(graph.columns.size()) * rowDofs * columnDofs;
  a.rowOffsets = Kokkos::View<Offset *, MemorySpace>("mixcon::csr::rowOffsets", a.numRows + 1);
  a.columns = Kokkos::View<LocalIndex *, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::csr::columns"), nnz);
  a.values = Kokkos::View<double *, MemorySpace>("mixcon::csr::values", nnz);
  auto hr = hostMirror(a.rowOffsets);
  auto hc = hostMirror(a.columns);
  hr(0) = 0;
  // node n's rows start at rowDofs columnDofs graph.rowOffsets[n], each len columnDofs long: the
  // nodes are independent (on the host's threads)
  Kokkos::parallel_for("mixcon::csr::expandGraph", HostRange(0, nn), [&](LocalIndex n) {
    const Offset begin = graph.rowOffsets[n], len = graph.rowOffsets[n + 1] - begin;
    Offset k = begin * rowDofs * columnDofs;
    for (int c = 0; c < rowDofs; ++c) {
      for (Offset j = 0; j < len; ++j)
        for (int d = 0; d < columnDofs; ++d)
          hc(k++) = graph.columns[begin + j] * columnDofs + d;
      hr(n * rowDofs + c + 1) = k;
    }
  });
  Kokkos::DefaultHostExecutionSpace().fence();
  copyToDevice(a.rowOffsets, hr);
  copyToDevice(a.columns, hc);
  return a;
}

/// The square pattern with `dofsPerNode` interleaved unknowns per node.
template <class MemorySpace>
CsrMatrix<MemorySpace> expandGraph(const NodeGraph &graph, int dofsPerNode) {
  return expandGraph<MemorySpace>(graph, dofsPerNode, dofsPerNode);
}

/// Element-to-graph scatter map: map(e, a, b) is the position of node(e, b) within the graph row
/// of node(e, a). The dof entry (a, i; b, j) of element e lives at CSR offset
/// rowOffsets[node(e,a)*d + i] + map(e, a, b) * d + j for d unknowns per node.
template <class MemorySpace>
Kokkos::View<int ***, Kokkos::LayoutRight, MemorySpace> elementScatterMap(const Mesh &mesh,
                                                                          const NodeGraph &graph) {
  const int npe = mesh.nodesPerElement;
  Kokkos::View<int ***, Kokkos::LayoutRight, MemorySpace> map("mixcon::assembly::scatterMap",
                                                              mesh.numElements(), npe, npe);
  auto h = hostMirror(map);
  Kokkos::parallel_for( // the elements are independent (on the host's threads)
      "mixcon::assembly::scatterMap", HostRange(0, mesh.numElements()), [&](LocalIndex e) {
        for (int a = 0; a < npe; ++a) {
          const LocalIndex row = mesh.node(e, a);
          const auto first = graph.columns.begin() + graph.rowOffsets[row];
          const auto last = graph.columns.begin() + graph.rowOffsets[row + 1];
          for (int b = 0; b < npe; ++b)
            h(e, a, b) = static_cast<int>(std::lower_bound(first, last, mesh.node(e, b)) - first);
        }
      });
  Kokkos::DefaultHostExecutionSpace().fence();
  copyToDevice(map, h);
  return map;
}

/// y = A x on the device.
template <class ExecSpace, class MemorySpace>
void multiply(const ExecSpace &exec, const CsrMatrix<MemorySpace> &a,
              const Kokkos::View<const double *, MemorySpace> &x,
              const Kokkos::View<double *, MemorySpace> &y) {
  auto ro = a.rowOffsets;
  auto co = a.columns;
  auto va = a.values;
  Kokkos::parallel_for(
      "mixcon::csr::multiply", Kokkos::RangePolicy<ExecSpace>(exec, 0, a.numRows),
      KOKKOS_LAMBDA(LocalIndex i) {
        double s = 0.0;
        for (Offset k = ro(i); k < ro(i + 1); ++k)
          s += va(k) * x(co(k));
        y(i) = s;
      });
}

/// The d x d node blocks of a CSR matrix whose pattern is a node graph expanded with d unknowns
/// per node (expandGraph): row (I, a) holds, for each neighbour J of node I in ascending order,
/// the d columns J d + b. Its values are then read in the CSR's own order (block row I starts at
/// d^2 offsets(I), its row a at d^2 offsets(I) + a d deg(I)), and the columns from one node index
/// per block: 8 + 4 / d^2 bytes per nonzero instead of the CSR's 12 (the product's traffic).
template <class MemorySpace> struct NodeBlocks {
  Kokkos::View<Offset *, MemorySpace> offsets;     ///< nodes + 1, in blocks
  Kokkos::View<LocalIndex *, MemorySpace> columns; ///< each block's node column
  int d = 0;                                       ///< 0: the matrix is not such an expansion
  LocalIndex numNodes() const { return d > 0 ? static_cast<LocalIndex>(offsets.extent(0)) - 1 : 0; }
};

/// The node blocks of `a` with d (2 or 3) unknowns per node, or none (d = 0) where a's pattern is
/// not a node graph expanded that way (every entry checked) or is not square.
template <class ExecSpace, class MemorySpace>
NodeBlocks<MemorySpace> nodeBlocks(const ExecSpace &exec, const CsrMatrix<MemorySpace> &a, int d) {
  NodeBlocks<MemorySpace> blocks;
  if ((d != 2 && d != 3) || a.numRows != a.numColumns || a.numRows % d != 0 || a.numRows == 0)
    return blocks;
  const LocalIndex nodes = a.numRows / d;
  const auto ro = a.rowOffsets;
  const auto co = a.columns;
  Kokkos::View<Offset *, MemorySpace> offsets("mixcon::csr::nodeBlockOffsets", nodes + 1);
  LocalIndex wrong = 0;
  Kokkos::parallel_reduce(
      "mixcon::csr::nodeBlockCheck", Kokkos::RangePolicy<ExecSpace>(exec, 0, nodes),
      KOKKOS_LAMBDA(LocalIndex node, LocalIndex & bad) {
        const Offset first = ro(d * node), length = ro(d * node + 1) - first;
        if (length % d != 0 || (node == 0 && first != 0)) {
          ++bad;
          return;
        }
        const Offset degree = length / d;
        for (int r = 0; r < d; ++r) {
          const Offset row = ro(d * node + r);
          if (ro(d * node + r + 1) - row != length) {
            ++bad;
            return;
          }
          for (Offset j = 0; j < degree; ++j) {
            const LocalIndex c0 = co(first + d * j);
            if (c0 % d != 0) {
              ++bad;
              return;
            }
            for (int c = 0; c < d; ++c)
              if (co(row + d * j + c) != c0 + c) {
                ++bad;
                return;
              }
          }
        }
        offsets(node + 1) = degree;
      },
      wrong);
  if (wrong > 0)
    return blocks;
  Kokkos::parallel_scan(
      "mixcon::csr::nodeBlockScan", Kokkos::RangePolicy<ExecSpace>(exec, 0, nodes + 1),
      KOKKOS_LAMBDA(LocalIndex i, Offset & sum, bool last) {
        sum += offsets(i);
        if (last)
          offsets(i) = sum;
      });
  Offset count = 0;
  Kokkos::deep_copy(exec, count, Kokkos::subview(offsets, nodes));
  exec.fence();
  Kokkos::View<LocalIndex *, MemorySpace> columns(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::csr::nodeBlockColumns"), count);
  Kokkos::parallel_for(
      "mixcon::csr::nodeBlockColumns", Kokkos::RangePolicy<ExecSpace>(exec, 0, nodes),
      KOKKOS_LAMBDA(LocalIndex node) {
        const Offset first = ro(d * node);
        for (Offset j = offsets(node); j < offsets(node + 1); ++j)
          columns(j) = co(first + d * (j - offsets(node))) / d;
      });
  blocks.offsets = offsets;
  blocks.columns = columns;
  blocks.d = d;
  return blocks;
}

namespace detail {
/// The D rows of one node of a matrix stored by node blocks (offsets bo, node columns bc, values
/// va in the CSR's order): sink(i, (A x)_i) for each of its rows i in order, each sum in the CSR
/// product's order. Row after row, through the values in memory order (the node's D rows read
/// side by side were 2.7x slower here: the prefetcher follows one stream, not D short ones).
/// The product below and the copied V-cycle's rows (solver/AmgCycle.cpp) both read blocks here.
template <int D, class Offsets, class Columns, class Values, class X, class Sink>
KOKKOS_INLINE_FUNCTION void nodeBlockRows(LocalIndex node, const Offsets &bo, const Columns &bc,
                                          const Values &va, const X &x, const Sink &sink) {
  using Scalar = typename Values::non_const_value_type;
  const Offset first = bo(node), last = bo(node + 1);
  Offset at = D * D * first;
  for (int r = 0; r < D; ++r) {
    Scalar s = 0;
    for (Offset j = first; j < last; ++j) {
      const LocalIndex c = D * bc(j);
      for (int k = 0; k < D; ++k)
        s += va(at + k) * x(c + k);
      at += D;
    }
    sink(D * node + r, s);
  }
}

/// y = A x over node blocks of D unknowns: the CSR's values, its sums in the CSR's order (each row
/// as the CSR product adds it).
template <int D, class ExecSpace, class MemorySpace>
void multiplyNodeBlocks(const ExecSpace &exec, const NodeBlocks<MemorySpace> &blocks,
                        const Kokkos::View<const double *, MemorySpace> &values,
                        const Kokkos::View<const double *, MemorySpace> &x,
                        const Kokkos::View<double *, MemorySpace> &y) {
  const auto bo = blocks.offsets;
  const auto bc = blocks.columns;
  Kokkos::parallel_for(
      "mixcon::csr::multiplyNodeBlocks", Kokkos::RangePolicy<ExecSpace>(exec, 0, blocks.numNodes()),
      KOKKOS_LAMBDA(LocalIndex node) {
        nodeBlockRows<D>(node, bo, bc, values, x, [&](LocalIndex i, double s) { y(i) = s; });
      });
}
} // namespace detail

/// y = A x for A's values in the CSR order of its node blocks (nodeBlocks(A), d = 2 or 3): the
/// same sums as multiply() on A, with a third less traffic.
template <class ExecSpace, class MemorySpace>
void multiply(const ExecSpace &exec, const NodeBlocks<MemorySpace> &blocks,
              const Kokkos::View<const double *, MemorySpace> &values,
              const Kokkos::View<const double *, MemorySpace> &x,
              const Kokkos::View<double *, MemorySpace> &y) {
  if (blocks.d == 3)
    detail::multiplyNodeBlocks<3>(exec, blocks, values, x, y);
  else
    detail::multiplyNodeBlocks<2>(exec, blocks, values, x, y);
}

} // namespace mixcon
