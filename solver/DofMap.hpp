// Global numbering of the unknowns: interleaved nodal unknowns (node * dofsPerNode + component)
// with the ownership range of this rank, so that MPI distribution (hypre ParCSR rows per rank)
// slots in without changing the solver interfaces. Data flow: solver.
#pragma once

#include <core/Compat.hpp>
#include <core/Tensor.hpp>

#include <cstdint>

namespace mixcon {

using GlobalIndex = std::int64_t;

/// Spatial dimension of the solver's models (2: the element kernels they call are 2D) and the
/// per-node unknowns of their fields (core/Tensor.hpp): kNumDisplacements (2), kNumStresses (3,
/// Voigt), kMixedUnknowns (5). Per-node counts and strides in solver/ and io/ are these
/// constants, so that a 3D model changes the dimension here rather than literals.
inline constexpr int kModelDim = 2;
using ModelLayout = FieldLayout<kModelDim>;

struct DofMap {
  int dofsPerNode = ModelLayout::kDisplacementUnknowns;
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
