// Host-side unstructured mesh: node coordinates (as many per node as the element type's spatial
// dimension; the generators and the Gmsh reader make 2D quadrilateral meshes), connectivity, named
// regions, boundaries (element edges) and node sets, plus its device-resident mirror. First stage
// of the data flow: mesh -> kernels -> solver -> contact -> io.
#pragma once

#include <core/ElementTraits.hpp>

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace mixcon {

/// Raised for invalid user input (problem files, meshes). Messages name the file, line or entity.
class InputError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// An element side on a boundary: element index and local side number (ElementTraits sideNode): an
/// edge of a 2D element, a face of a 3D one. Taking the side from the element keeps its
/// orientation: in 2D the outward normal is on the edge's right, in 3D the face's nodes run
/// counter-clockwise seen from outside.
struct BoundaryEdge {
  LocalIndex element;
  int edge; ///< local side number (edge in 2D, face in 3D)
};
using BoundarySide = BoundaryEdge; ///< the dimension-generic name

/// Spatial dimension of an element type (its traits' kDim): 2 for the quadrilaterals, 3 for the
/// solids.

inline int spatialDimension(ElementType type) {
  return dispatchElement(type, [](auto elem) { return decltype(elem)::kDim; });
}

struct Mesh {
  ElementType elementType = ElementType::Quad4;
  int nodesPerElement = 4;
  std::vector<double> coordinates;      ///< dim() * numNodes, interleaved x, y (, z)
  std::vector<LocalIndex> connectivity; ///< nodesPerElement * numElements (2D: counter-clockwise)
  std::vector<int> elementRegion;       ///< index into regionNames per element
  std::vector<std::string> regionNames;
  std::map<std::string, std::vector<BoundaryEdge>>
      boundaries; ///< element sides (2D edges, 3D faces)
  std::map<std::string, std::vector<LocalIndex>> nodeSets;
  std::vector<long> nodeIds;    ///< external (file) id of each node, for messages
  std::vector<long> elementIds; ///< external (file) id of each element, for messages
  std::string source;           ///< file name or generator, for messages
  /// Things the user should know about the input that did not stop it (e.g. elements the reader
  /// reoriented), one line each without a trailing newline; the program prints them to stderr.
  std::vector<std::string> warnings;

  /// Spatial dimension: coordinates per node, the element type's kDim.
  int dim() const { return spatialDimension(elementType); }
  LocalIndex numNodes() const { return static_cast<LocalIndex>(coordinates.size() / dim()); }
  LocalIndex numElements() const {
    return nodesPerElement ? static_cast<LocalIndex>(connectivity.size() / nodesPerElement) : 0;
  }
  LocalIndex node(LocalIndex element, int local) const {
    return connectivity[static_cast<std::size_t>(element) * nodesPerElement + local];
  }
  /// Coordinate i (0 = x, 1 = y, 2 = z; i < dim()) of node n.
  double coordinate(LocalIndex n, int i) const {
    return coordinates[static_cast<std::size_t>(dim()) * static_cast<std::size_t>(n) + i];
  }
  double x(LocalIndex n) const { return coordinate(n, 0); }
  double y(LocalIndex n) const { return coordinate(n, 1); }
  double z(LocalIndex n) const { return coordinate(n, 2); } ///< 3D meshes only
  /// Local node k of the boundary side `e` (an edge in 2D, a face in 3D) and the nodes per side.
  LocalIndex sideNode(const BoundaryEdge &e, int k) const;
  int nodesPerSide() const;
  /// The 2D names of sideNode and nodesPerSide (the sides of a quadrilateral are its edges).
  LocalIndex edgeNode(const BoundaryEdge &e, int k) const { return sideNode(e, k); }
  int nodesPerEdge() const { return nodesPerSide(); }
  /// Sorted unique nodes of a boundary or node set; throws InputError for an unknown name.
  std::vector<LocalIndex> nodesOf(const std::string &name) const;
  bool hasBoundary(const std::string &name) const { return boundaries.count(name) != 0; }
  bool hasNodeSet(const std::string &name) const { return nodeSets.count(name) != 0; }
  int regionIndex(const std::string &name) const; ///< -1 when absent
  /// The names of all boundaries and node sets, space separated, for messages.
  std::string namedSets() const;
  /// Fills default external ids (index + 1) where a generator left them empty.
  void finalizeIds();
  /// The external id of node n (its Gmsh tag, or n + 1 where nodeIds is not filled): the number
  /// every message and output file names the node by.
  long nodeId(LocalIndex n) const { return externalId(nodeIds, n); }
  /// The external id of element e (its Gmsh tag, or e + 1 where elementIds is not filled).
  long elementId(LocalIndex e) const { return externalId(elementIds, e); }
  /// ids[i], or i + 1 where `ids` does not reach i (a mesh built without external ids).
  static long externalId(const std::vector<long> &ids, LocalIndex i) {
    return static_cast<std::size_t>(i) < ids.size() ? ids[static_cast<std::size_t>(i)]
                                                    : static_cast<long>(i) + 1;
  }
};

/// Signed area of an element, the integral of its Jacobian determinant (element quadrature):
/// positive for counter-clockwise nodes.
double signedArea(const Mesh &mesh, LocalIndex element);

/// Reorders the nodes of every element whose signed area is negative (clockwise) so that it is
/// counter-clockwise: Quad4 corners 0 3 2 1; Quad8 corners 0 3 2 1 and mid-side nodes 7 6 5 4.
/// This is the element with its natural coordinates swapped (xi <-> eta), which negates the
/// Jacobian determinant at every point, so an element whose Jacobian changes sign inside (a
/// bow-tie, a fold) stays invalid and validateMesh still refuses it. Call before boundary edges
/// are taken from the elements. Returns the number of elements reoriented.
LocalIndex orientCounterClockwise(Mesh &mesh);

/// How thick a solid mesh is, counted in elements: 2 V / (A h), with V the volume and A the
/// area of its boundary (the faces that only one element has, each the flat polygon of its
/// corners) and h = (V / n)^(1/3) the edge of a cube holding an element's share of the volume
/// (n the elements; a tetrahedron counts as a sixth of a cube). A plate of k layers of cubic
/// elements gives about k, a cube of N^3 elements N / 3, a bar of k x k elements through its
/// section about k / 2. A plate of k layers of thickness t with an in-plane size s gives about
/// k (t / s)^(2/3): less for flat elements, more where they are finer in plane than through the
/// thickness. A measure for the AMG's defaults (io/ProblemAnalysis.cpp), not a count of layers.
/// Linear in the elements (the faces bucketed by their smallest corner; 0.2 s for the million
/// hexahedra of the cube N = 100). Meshes of the 3D solids only (0 for another or an empty mesh).
double elementLayers(const Mesh &mesh);

/// Natural coordinates (xi, eta) of the point (x, y) in an element (Newton on the isoparametric
/// map from the centre); false when it does not converge (a point far outside).
bool naturalCoordinates(const Mesh &mesh, LocalIndex element, double x, double y, double &xi,
                        double &eta);

/// A node of one part of a mesh inside an element of another part (findOverlap).
struct Overlap {
  LocalIndex node = -1;    ///< mesh index of the node
  LocalIndex element = -1; ///< mesh index of the element it lies in
  double depth = 0.0;      ///< its distance from the element's edges over the element's diameter
};

/// Parts of a mesh (e.g. merged bodies) are consecutive ranges: part k owns nodes
/// [nodeStart[k], nodeStart[k+1]) and elements [elementStart[k], elementStart[k+1]); both lists
/// end with the totals. Returns the deepest node of a part that lies inside an element of another
/// part farther from that element's edges than `tolerance` times its diameter (the diagonal of
/// its bounding box; a square's centre is at 0.35), so that nodes on a shared or touching
/// interface, or on a circle that the other part's straight edges cut as chords, pass. Elements are
/// binned in a grid per part; only nodes inside a part's bounding box are located.
std::optional<Overlap> findOverlap(const Mesh &mesh, const std::vector<LocalIndex> &nodeStart,
                                   const std::vector<LocalIndex> &elementStart, double tolerance);

/// The body of every node: nodes connected through elements share a number; bodies are numbered
/// 0, 1, ... in the order of their first node.
std::vector<LocalIndex> connectedComponents(const Mesh &mesh);

/// The nodes connected to `seeds` through elements (the bodies they lie on), sorted.
std::vector<LocalIndex> connectedNodes(const Mesh &mesh, const std::vector<LocalIndex> &seeds);

/// Checks connectivity bounds and the Jacobian sign at every quadrature point and node of every
/// element (on the device), and that every node belongs to an element; throws InputError naming
/// the first inverted or degenerate element or the first node used by no element.
void validateMesh(const Mesh &mesh);

/// Device-resident copy of the geometry and topology the element kernels read: `Dim` coordinates
/// per node (the element traits' kDim), nodes per element as the connectivity's second extent.
template <class MemorySpace, int Dim = 2> struct MeshView {
  static constexpr int kDim = Dim;
  Kokkos::View<double *[Dim], MemorySpace> coordinates;
  Kokkos::View<LocalIndex **, Kokkos::LayoutRight, MemorySpace> connectivity;
};

/// Copies a host mesh to `MemorySpace` as a MeshView of dimension `Dim`; throws
/// std::invalid_argument when `Dim` is not the mesh's dimension (its element type's kDim).
template <class MemorySpace, int Dim = 2> MeshView<MemorySpace, Dim> toDevice(const Mesh &mesh) {
  if (mesh.dim() != Dim)
    throw std::invalid_argument("toDevice: mesh '" + mesh.source + "' is " +
                                std::to_string(mesh.dim()) + "D, a " + std::to_string(Dim) +
                                "D MeshView was asked for");
  MeshView<MemorySpace, Dim> v;
  v.coordinates =
      Kokkos::View<double *[Dim], MemorySpace>("mixcon::mesh::coordinates", mesh.numNodes());
  v.connectivity = Kokkos::View<LocalIndex **, Kokkos::LayoutRight, MemorySpace>(
      "mixcon::mesh::connectivity", mesh.numElements(), mesh.nodesPerElement);
  auto hc = Kokkos::create_mirror_view(v.coordinates);
  auto he = Kokkos::create_mirror_view(v.connectivity);
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    for (int i = 0; i < Dim; ++i)
      hc(n, i) = mesh.coordinate(n, i);
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < mesh.nodesPerElement; ++a)
      he(e, a) = mesh.node(e, a);
  Kokkos::deep_copy(v.coordinates, hc);
  Kokkos::deep_copy(v.connectivity, he);
  return v;
}

} // namespace mixcon
