// Host-side unstructured 2D mesh: node coordinates, quadrilateral connectivity, named regions,
// boundaries (element edges) and node sets, plus its device-resident mirror. First stage of the
// data flow: mesh -> kernels -> solver -> contact -> io.
#pragma once

#include <kernels/ElementTraits.hpp>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace mixcon {

/// Raised for invalid user input (problem files, meshes). Messages name the file, line or entity.
class InputError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// An element edge on a boundary: element index and local edge number (see ElementTraits edgeNode).
/// Taking the edge from the element keeps its orientation: the outward normal is on its right.
struct BoundaryEdge {
  LocalIndex element;
  int edge;
};

struct Mesh {
  ElementType elementType = ElementType::Quad4;
  int nodesPerElement = 4;
  std::vector<double> coordinates;      ///< 2 * numNodes, interleaved x, y
  std::vector<LocalIndex> connectivity; ///< nodesPerElement * numElements, counter-clockwise
  std::vector<int> elementRegion;       ///< index into regionNames per element
  std::vector<std::string> regionNames;
  std::map<std::string, std::vector<BoundaryEdge>> boundaries;
  std::map<std::string, std::vector<LocalIndex>> nodeSets;
  std::vector<long> nodeIds;    ///< external (file) id of each node, for messages
  std::vector<long> elementIds; ///< external (file) id of each element, for messages
  std::string source;           ///< file name or generator, for messages

  LocalIndex numNodes() const { return static_cast<LocalIndex>(coordinates.size() / 2); }
  LocalIndex numElements() const {
    return nodesPerElement ? static_cast<LocalIndex>(connectivity.size() / nodesPerElement) : 0;
  }
  LocalIndex node(LocalIndex element, int local) const {
    return connectivity[static_cast<std::size_t>(element) * nodesPerElement + local];
  }
  double x(LocalIndex n) const { return coordinates[2 * static_cast<std::size_t>(n)]; }
  double y(LocalIndex n) const { return coordinates[2 * static_cast<std::size_t>(n) + 1]; }
  /// Local node k of edge `edge` of `element`.
  LocalIndex edgeNode(const BoundaryEdge &e, int k) const;
  int nodesPerEdge() const { return elementType == ElementType::Quad8 ? 3 : 2; }
  /// Sorted unique nodes of a boundary or node set; throws InputError for an unknown name.
  std::vector<LocalIndex> nodesOf(const std::string &name) const;
  bool hasBoundary(const std::string &name) const { return boundaries.count(name) != 0; }
  bool hasNodeSet(const std::string &name) const { return nodeSets.count(name) != 0; }
  int regionIndex(const std::string &name) const; ///< -1 when absent
  /// The names of all boundaries and node sets, space separated, for messages.
  std::string namedSets() const;
  /// Fills default external ids (index + 1) where a generator left them empty.
  void finalizeIds();
};

/// Checks connectivity bounds and the Jacobian sign at every quadrature point and node of every
/// element (on the device); throws InputError naming the first inverted or degenerate element.
void validateMesh(const Mesh &mesh);

/// Device-resident copy of the geometry and topology the element kernels read.
template <class MemorySpace> struct MeshView {
  Kokkos::View<double *[2], MemorySpace> coordinates;
  Kokkos::View<LocalIndex **, Kokkos::LayoutRight, MemorySpace> connectivity;
};

/// Copies a host mesh to `MemorySpace`.
template <class MemorySpace> MeshView<MemorySpace> toDevice(const Mesh &mesh) {
  MeshView<MemorySpace> v;
  v.coordinates =
      Kokkos::View<double *[2], MemorySpace>("mixcon::mesh::coordinates", mesh.numNodes());
  v.connectivity = Kokkos::View<LocalIndex **, Kokkos::LayoutRight, MemorySpace>(
      "mixcon::mesh::connectivity", mesh.numElements(), mesh.nodesPerElement);
  auto hc = Kokkos::create_mirror_view(v.coordinates);
  auto he = Kokkos::create_mirror_view(v.connectivity);
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
    hc(n, 0) = mesh.x(n);
    hc(n, 1) = mesh.y(n);
  }
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < mesh.nodesPerElement; ++a)
      he(e, a) = mesh.node(e, a);
  Kokkos::deep_copy(v.coordinates, hc);
  Kokkos::deep_copy(v.connectivity, he);
  return v;
}

} // namespace mixcon
