// Global numbering of the unknowns: interleaved nodal unknowns (node * dofsPerNode + component)
// with the ownership range of this rank, so that MPI distribution (hypre ParCSR rows per rank)
// slots in without changing the solver interfaces. Data flow: solver.
#pragma once

#include <core/Compat.hpp>
#include <core/Tensor.hpp>

#include <cstdint>

namespace mixcon {

using GlobalIndex = std::int64_t;

/// Spatial dimension of the models that are 2D only so far (the mixed and the geometrically
/// nonlinear ones, contact) and the per-node unknowns of their fields (core/Tensor.hpp):
/// kNumDisplacements (2), kNumStresses (3, Voigt), kMixedUnknowns (5). Their per-node counts and
/// strides are these constants rather than literals. The linear displacement model takes its
/// dimension from the mesh (DofMap::dofsPerNode = Mesh::dim()).
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
