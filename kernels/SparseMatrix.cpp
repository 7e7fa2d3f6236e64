// Node graph construction (host): node -> elements -> nodes, sorted and unique per row.
#include <kernels/SparseMatrix.hpp>

#include <algorithm>

namespace mixcon {

NodeGraph buildNodeGraph(const Mesh &mesh) {
  const LocalIndex nn = mesh.numNodes(), ne = mesh.numElements();
  const int npe = mesh.nodesPerElement;
  // node -> elements (CSR)
  std::vector<Offset> nodeElemOffsets(nn + 1, 0);
  for (LocalIndex e = 0; e < ne; ++e)
    for (int a = 0; a < npe; ++a)
      ++nodeElemOffsets[mesh.node(e, a) + 1];
  for (LocalIndex n = 0; n < nn; ++n)
    nodeElemOffsets[n + 1] += nodeElemOffsets[n];
  std::vector<LocalIndex> nodeElems(nodeElemOffsets[nn]);
  {
    std::vector<Offset> fill(nodeElemOffsets.begin(), nodeElemOffsets.end() - 1);
    for (LocalIndex e = 0; e < ne; ++e)
      for (int a = 0; a < npe; ++a)
        nodeElems[fill[mesh.node(e, a)]++] = e;
  }
  NodeGraph g;
  g.rowOffsets.assign(nn + 1, 0);
  std::vector<LocalIndex> row;
  for (LocalIndex n = 0; n < nn; ++n) {
    row.clear();
    row.push_back(n); // keep isolated nodes' diagonal so the matrix stays square and regular
    for (Offset k = nodeElemOffsets[n]; k < nodeElemOffsets[n + 1]; ++k)
      for (int b = 0; b < npe; ++b)
        row.push_back(mesh.node(nodeElems[k], b));
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    g.columns.insert(g.columns.end(), row.begin(), row.end());
    g.rowOffsets[n + 1] = static_cast<Offset>(g.columns.size());
  }
  return g;
}

} // namespace mixcon
