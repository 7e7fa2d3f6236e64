// Mesh queries and validation (host bookkeeping, Jacobian check as a Kokkos reduction).
#include <mesh/Mesh.hpp>

#include <algorithm>
#include <sstream>

namespace mixcon {

LocalIndex Mesh::edgeNode(const BoundaryEdge &e, int k) const {
  const int local =
      elementType == ElementType::Quad8 ? Quad8::edgeNode(e.edge, k) : Quad4::edgeNode(e.edge, k);
  return node(e.element, local);
}

std::vector<LocalIndex> Mesh::nodesOf(const std::string &name) const {
  std::vector<LocalIndex> nodes;
  if (auto b = boundaries.find(name); b != boundaries.end()) {
    for (const auto &e : b->second)
      for (int k = 0; k < nodesPerEdge(); ++k)
        nodes.push_back(edgeNode(e, k));
  } else if (auto s = nodeSets.find(name); s != nodeSets.end()) {
    nodes = s->second;
  } else {
    throw InputError(source + ": no boundary or node set named '" + name +
                     "' (known: " + namedSets() + ")");
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

std::string Mesh::namedSets() const {
  std::string names;
  for (const auto &[n, v] : boundaries)
    names += (names.empty() ? "" : " ") + n;
  for (const auto &[n, v] : nodeSets)
    names += (names.empty() ? "" : " ") + n;
  return names;
}

int Mesh::regionIndex(const std::string &name) const {
  auto it = std::find(regionNames.begin(), regionNames.end(), name);
  return it == regionNames.end() ? -1 : static_cast<int>(it - regionNames.begin());
}

void Mesh::finalizeIds() {
  if (nodeIds.size() != static_cast<std::size_t>(numNodes())) {
    nodeIds.resize(numNodes());
    for (LocalIndex i = 0; i < numNodes(); ++i)
      nodeIds[i] = i + 1;
  }
  if (elementIds.size() != static_cast<std::size_t>(numElements())) {
    elementIds.resize(numElements());
    for (LocalIndex i = 0; i < numElements(); ++i)
      elementIds[i] = i + 1;
  }
}

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace mesh_detail {
template <class Elem> Kokkos::MinLoc<double, LocalIndex>::value_type minJacobian(const Mesh &mesh) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto dev = toDevice<Exec::memory_space>(mesh);
  using Reducer = Kokkos::MinLoc<double, LocalIndex>;
  typename Reducer::value_type result;
  Kokkos::parallel_reduce(
      "mixcon::mesh::minJacobian", Kokkos::RangePolicy<Exec>(0, mesh.numElements()),
      KOKKOS_LAMBDA(LocalIndex e, typename Reducer::value_type & acc) {
        double xe[Elem::kNumNodes][2];
        for (int a = 0; a < Elem::kNumNodes; ++a) {
          xe[a][0] = dev.coordinates(dev.connectivity(e, a), 0);
          xe[a][1] = dev.coordinates(dev.connectivity(e, a), 1);
        }
        // Sample the quadrature points and the nodes: a Quad8 can fold at a corner while
        // its Gauss points stay positive.
        for (int q = 0; q < Elem::kNumQp + Elem::kNumNodes; ++q) {
          double xi, eta, w;
          if (q < Elem::kNumQp)
            Elem::quadraturePoint(q, xi, eta, w);
          else
            Elem::nodeNatural(q - Elem::kNumQp, xi, eta);
          double n[Elem::kNumNodes], dn[Elem::kNumNodes][2], dndx[Elem::kNumNodes][2];
          Elem::shape(xi, eta, n, dn);
          const double det = physicalGradients<Elem>(xe, dn, dndx);
          if (det < acc.val) {
            acc.val = det;
            acc.loc = e;
          }
        }
      },
      Reducer(result));
  return result;
}
} // namespace mesh_detail
using namespace mesh_detail;

void validateMesh(const Mesh &mesh) {
  if (mesh.numElements() == 0)
    throw InputError(mesh.source + ": mesh has no elements");
  const int expected = mesh.elementType == ElementType::Quad8 ? 8 : 4;
  if (mesh.nodesPerElement != expected)
    throw InputError(mesh.source + ": inconsistent nodes per element");
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < mesh.nodesPerElement; ++a) {
      const LocalIndex n = mesh.node(e, a);
      if (n < 0 || n >= mesh.numNodes())
        throw InputError(mesh.source + ": element " + std::to_string(mesh.elementIds[e]) +
                         " references a node that does not exist");
    }
  const auto r = dispatchElement(mesh.elementType,
                                 [&](auto elem) { return minJacobian<decltype(elem)>(mesh); });
  // Relative threshold: the Jacobian scales with the element area.
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
    xmin = std::min(xmin, mesh.x(n));
    xmax = std::max(xmax, mesh.x(n));
    ymin = std::min(ymin, mesh.y(n));
    ymax = std::max(ymax, mesh.y(n));
  }
  const double scale = (xmax - xmin) * (ymax - ymin) / mesh.numElements();
  if (!(r.val > 1e-12 * scale)) {
    std::ostringstream msg;
    msg << mesh.source << ": element " << mesh.elementIds[r.loc]
        << " has a non-positive Jacobian determinant (" << r.val
        << "): it is inverted, degenerate or its nodes are not counter-clockwise (nodes";
    for (int a = 0; a < mesh.nodesPerElement; ++a)
      msg << " " << mesh.nodeIds[mesh.node(r.loc, a)];
    msg << ")";
    throw InputError(msg.str());
  }
}

} // namespace mixcon
