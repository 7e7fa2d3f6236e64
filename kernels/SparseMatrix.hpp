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
  for (LocalIndex n = 0; n < nn; ++n) {
    const Offset begin = graph.rowOffsets[n], len = graph.rowOffsets[n + 1] - begin;
    for (int c = 0; c < rowDofs; ++c) {
      const LocalIndex row = n * rowDofs + c;
      Offset k = hr(row);
      for (Offset j = 0; j < len; ++j)
        for (int d = 0; d < columnDofs; ++d)
          hc(k++) = graph.columns[begin + j] * columnDofs + d;
      hr(row + 1) = k;
    }
  }
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
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < npe; ++a) {
      const LocalIndex row = mesh.node(e, a);
      const auto first = graph.columns.begin() + graph.rowOffsets[row];
      const auto last = graph.columns.begin() + graph.rowOffsets[row + 1];
      for (int b = 0; b < npe; ++b)
        h(e, a, b) = static_cast<int>(std::lower_bound(first, last, mesh.node(e, b)) - first);
    }
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

} // namespace mixcon
