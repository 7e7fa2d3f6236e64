// Global numbering of the unknowns: interleaved nodal unknowns (node * dofsPerNode + component)
// with the ownership range of this rank, so that MPI distribution (hypre ParCSR rows per rank)
// slots in without changing the solver interfaces. Data flow: solver.
#pragma once

#include <core/Compat.hpp>

#include <cstdint>

namespace mixcon {

using GlobalIndex = std::int64_t;

struct DofMap {
  int dofsPerNode = 2;
  LocalIndex numLocalNodes = 0;
  GlobalIndex ownedBegin = 0; ///< global index of this rank's first owned unknown
  GlobalIndex numGlobal = 0;  ///< unknowns over all ranks

  LocalIndex numOwned() const { return numLocalNodes * dofsPerNode; }
  GlobalIndex ownedEnd() const { return ownedBegin + numOwned(); } ///< one past the last
  KOKKOS_INLINE_FUNCTION LocalIndex dof(LocalIndex node, int component) const {
    return node * dofsPerNode + component;
  }

  /// Single-rank numbering.
  static DofMap serial(LocalIndex numNodes, int dofsPerNode) {
    DofMap m;
    m.dofsPerNode = dofsPerNode;
    m.numLocalNodes = numNodes;
    m.ownedBegin = 0;
    m.numGlobal = static_cast<GlobalIndex>(numNodes) * dofsPerNode;
    return m;
  }
};

} // namespace mixcon
