// Mesh queries and validation (host bookkeeping, Jacobian check as a Kokkos reduction).
#include <mesh/Mesh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <vector>

namespace mixcon {

LocalIndex Mesh::sideNode(const BoundaryEdge &e, int k) const {
  return node(e.element, dispatchElement(elementType, [&](auto elem) {
                return decltype(elem)::sideNode(e.edge, k);
              }));
}

int Mesh::nodesPerSide() const {
  return dispatchElement(elementType, [](auto elem) { return decltype(elem)::kNodesPerSide; });
}

std::vector<LocalIndex> Mesh::nodesOf(const std::string &name) const {
  std::vector<LocalIndex> nodes;
  if (auto b = boundaries.find(name); b != boundaries.end()) {
    for (const auto &e : b->second)
      for (int k = 0; k < nodesPerSide(); ++k)
        nodes.push_back(sideNode(e, k));
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

namespace {
template <class Elem> double signedAreaOf(const Mesh &mesh, LocalIndex e) {
  double area = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double xi, eta, w, n[Elem::kNumNodes], dn[Elem::kNumNodes][2];
    Elem::quadraturePoint(q, xi, eta, w);
    Elem::shape(xi, eta, n, dn);
    double j00 = 0, j01 = 0, j10 = 0, j11 = 0;
    for (int a = 0; a < Elem::kNumNodes; ++a) {
      const LocalIndex p = mesh.node(e, a);
      j00 += mesh.x(p) * dn[a][0];
      j01 += mesh.x(p) * dn[a][1];
      j10 += mesh.y(p) * dn[a][0];
      j11 += mesh.y(p) * dn[a][1];
    }
    area += w * (j00 * j11 - j01 * j10);
  }
  return area;
}
} // namespace

double signedArea(const Mesh &mesh, LocalIndex element) {
  return dispatchPlaneElement(mesh.elementType, "this mesh function", [&](auto elem) {
    return signedAreaOf<decltype(elem)>(mesh, element);
  });
}

LocalIndex orientCounterClockwise(Mesh &mesh) {
  // New local node k is old local node swap[k]: (xi, eta) -> (eta, xi) maps corner 1 (1,-1) to
  // corner 3 (-1,1) and mid-side 4 (0,-1) of edge 0-1 to mid-side 7 (-1,0) of edge 3-0.
  constexpr int swap[8] = {0, 3, 2, 1, 7, 6, 5, 4};
  const int npe = mesh.nodesPerElement;
  LocalIndex flipped = 0;
  for (LocalIndex e = 0; e < mesh.numElements(); ++e) {
    if (!(signedArea(mesh, e) < 0.0))
      continue;
    LocalIndex *nodes = &mesh.connectivity[static_cast<std::size_t>(e) * npe];
    LocalIndex old[8];
    std::copy(nodes, nodes + npe, old);
    for (int k = 0; k < npe; ++k)
      nodes[k] = old[swap[k]];
    ++flipped;
  }
  return flipped;
}

namespace {
template <class Elem>
bool naturalCoordinatesOf(const Mesh &mesh, LocalIndex e, double px, double py, double &xi,
                          double &eta) {
  xi = eta = 0.0;
  for (int it = 0; it < 30; ++it) {
    double n[Elem::kNumNodes], dn[Elem::kNumNodes][2];
    Elem::shape(xi, eta, n, dn);
    double fx = -px, fy = -py, j00 = 0, j01 = 0, j10 = 0, j11 = 0;
    for (int a = 0; a < Elem::kNumNodes; ++a) {
      const LocalIndex p = mesh.node(e, a);
      fx += n[a] * mesh.x(p);
      fy += n[a] * mesh.y(p);
      j00 += mesh.x(p) * dn[a][0];
      j01 += mesh.x(p) * dn[a][1];
      j10 += mesh.y(p) * dn[a][0];
      j11 += mesh.y(p) * dn[a][1];
    }
    const double det = j00 * j11 - j01 * j10;
    if (!(std::abs(det) > 0.0))
      return false;
    const double dxi = (j11 * fx - j01 * fy) / det, deta = (-j10 * fx + j00 * fy) / det;
    xi -= dxi;
    eta -= deta;
    if (!(std::abs(xi) < 10.0 && std::abs(eta) < 10.0))
      return false; // far outside: the map is not worth inverting there
    if (std::abs(dxi) + std::abs(deta) < 1e-12)
      return true;
  }
  return false;
}

/// Distance from a point to the boundary of an element: its straight edges, or for a Quad8 the
/// two chords of each curved edge (corner, mid-side, corner).
double distanceToEdges(const Mesh &mesh, LocalIndex e, double px, double py) {
  constexpr int quad4[] = {0, 1, 2, 3}, quad8[] = {0, 4, 1, 5, 2, 6, 3, 7};
  const int *ring = mesh.nodesPerElement == 8 ? quad8 : quad4;
  double d = 1e300;
  for (int k = 0; k < mesh.nodesPerElement; ++k) {
    const LocalIndex a = mesh.node(e, ring[k]),
                     b = mesh.node(e, ring[(k + 1) % mesh.nodesPerElement]);
    const double ex = mesh.x(b) - mesh.x(a), ey = mesh.y(b) - mesh.y(a);
    const double len2 = ex * ex + ey * ey;
    double t = len2 > 0.0 ? ((px - mesh.x(a)) * ex + (py - mesh.y(a)) * ey) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    d = std::min(d, std::hypot(px - mesh.x(a) - t * ex, py - mesh.y(a) - t * ey));
  }
  return d;
}

struct Box {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  void add(double x, double y) {
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  }
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};
} // namespace

bool naturalCoordinates(const Mesh &mesh, LocalIndex element, double x, double y, double &xi,
                        double &eta) {
  return dispatchPlaneElement(mesh.elementType, "this mesh function", [&](auto elem) {
    return naturalCoordinatesOf<decltype(elem)>(mesh, element, x, y, xi, eta);
  });
}

std::optional<Overlap> findOverlap(const Mesh &mesh, const std::vector<LocalIndex> &nodeStart,
                                   const std::vector<LocalIndex> &elementStart, double tolerance) {
  std::optional<Overlap> worst;
  const std::size_t parts = elementStart.size() - 1;
  for (std::size_t j = 0; j < parts; ++j) { // the part whose elements are searched
    const LocalIndex e0 = elementStart[j], e1 = elementStart[j + 1];
    if (e1 <= e0)
      continue;
    std::vector<Box> boxes(e1 - e0);
    Box all;
    for (LocalIndex e = e0; e < e1; ++e) {
      for (int a = 0; a < mesh.nodesPerElement; ++a)
        boxes[e - e0].add(mesh.x(mesh.node(e, a)), mesh.y(mesh.node(e, a)));
      all.add(boxes[e - e0].x0, boxes[e - e0].y0);
      all.add(boxes[e - e0].x1, boxes[e - e0].y1);
    }
    // A grid of about one element per cell over the part's bounding box.
    const double w = all.x1 - all.x0, h = all.y1 - all.y0;
    const double cell = std::max(std::sqrt(w * h / (e1 - e0)), 1e-300);
    const int nx = static_cast<int>(std::clamp(std::ceil(w / cell), 1.0, 4096.0));
    const int ny = static_cast<int>(std::clamp(std::ceil(h / cell), 1.0, 4096.0));
    auto cellOf = [&](double v, double v0, double len, int n) {
      const int c = len > 0.0 ? static_cast<int>((v - v0) / len * n) : 0;
      return std::clamp(c, 0, n - 1);
    };
    std::vector<std::vector<LocalIndex>> grid(static_cast<std::size_t>(nx) * ny);
    for (LocalIndex e = e0; e < e1; ++e) {
      const Box &b = boxes[e - e0];
      for (int cy = cellOf(b.y0, all.y0, h, ny); cy <= cellOf(b.y1, all.y0, h, ny); ++cy)
        for (int cx = cellOf(b.x0, all.x0, w, nx); cx <= cellOf(b.x1, all.x0, w, nx); ++cx)
          grid[static_cast<std::size_t>(cy) * nx + cx].push_back(e);
    }
    for (std::size_t i = 0; i < parts; ++i) {
      if (i == j)
        continue;
      for (LocalIndex n = nodeStart[i]; n < nodeStart[i + 1]; ++n) {
        const double x = mesh.x(n), y = mesh.y(n);
        if (!all.contains(x, y))
          continue;
        const auto &candidates = grid[static_cast<std::size_t>(cellOf(y, all.y0, h, ny)) * nx +
                                      cellOf(x, all.x0, w, nx)];
        for (LocalIndex e : candidates) {
          double xi, eta;
          if (!boxes[e - e0].contains(x, y) || !naturalCoordinates(mesh, e, x, y, xi, eta))
            continue;
          if (!(std::max(std::abs(xi), std::abs(eta)) < 1.0))
            continue;
          const double depth =
              distanceToEdges(mesh, e, x, y) /
              std::hypot(boxes[e - e0].x1 - boxes[e - e0].x0, boxes[e - e0].y1 - boxes[e - e0].y0);
          if (depth > tolerance && (!worst || depth > worst->depth))
            worst = Overlap{n, e, depth};
        }
      }
    }
  }
  return worst;
}

std::vector<LocalIndex> connectedComponents(const Mesh &mesh) {
  // Union-find over the element connectivity (path halving).
  std::vector<LocalIndex> parent(mesh.numNodes());
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    parent[n] = n;
  auto root = [&](LocalIndex n) {
    while (parent[n] != n)
      n = parent[n] = parent[parent[n]];
    return n;
  };
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 1; a < mesh.nodesPerElement; ++a) {
      const LocalIndex r0 = root(mesh.node(e, 0)), r1 = root(mesh.node(e, a));
      if (r0 != r1)
        parent[r1] = r0;
    }
  std::vector<LocalIndex> component(mesh.numNodes()), numberOfRoot(mesh.numNodes(), -1);
  LocalIndex count = 0;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
    LocalIndex &number = numberOfRoot[root(n)];
    if (number < 0)
      number = count++;
    component[n] = number;
  }
  return component;
}

std::vector<LocalIndex> connectedNodes(const Mesh &mesh, const std::vector<LocalIndex> &seeds) {
  const std::vector<LocalIndex> component = connectedComponents(mesh);
  std::vector<char> wanted(mesh.numNodes(), 0);
  for (LocalIndex s : seeds)
    wanted[component[s]] = 1;
  std::vector<LocalIndex> nodes;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    if (wanted[component[n]])
      nodes.push_back(n);
  return nodes;
}

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace mesh_detail {
/// Magnitude beyond which a Jacobian determinant counts as overflowed (a double's range).
constexpr double kJacobianOverflow = 1e308;

template <class Elem> Kokkos::MinLoc<double, LocalIndex>::value_type minJacobian(const Mesh &mesh) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto dev = toDevice<Exec::memory_space, Elem::kDim>(mesh);
  using Reducer = Kokkos::MinLoc<double, LocalIndex>;
  typename Reducer::value_type result;
  Kokkos::parallel_reduce(
      "mixcon::mesh::minJacobian", Kokkos::RangePolicy<Exec>(0, mesh.numElements()),
      KOKKOS_LAMBDA(LocalIndex e, typename Reducer::value_type & acc) {
        constexpr int dim = Elem::kDim;
        double xe[Elem::kNumNodes][dim];
        for (int a = 0; a < Elem::kNumNodes; ++a)
          for (int i = 0; i < dim; ++i)
            xe[a][i] = dev.coordinates(dev.connectivity(e, a), i);
        // Sample the quadrature points and the nodes: a Quad8 can fold at a corner while
        // its Gauss points stay positive.
        for (int q = 0; q < Elem::kNumQp + Elem::kNumNodes; ++q) {
          double xi[dim], w;
          if (q < Elem::kNumQp)
            Elem::quadraturePoint(q, xi, w);
          else
            Elem::nodeNatural(q - Elem::kNumQp, xi);
          double n[Elem::kNumNodes], dn[Elem::kNumNodes][dim];
          Elem::shape(xi, n, dn);
          // A determinant that overflows (or is NaN) counts as the worst: it is reported, and the
          // reduction always ends on an element.
          const double raw = jacobianDeterminant<Elem>(xe, dn);
          const double det =
              raw > -kJacobianOverflow && raw < kJacobianOverflow ? raw : -kJacobianOverflow;
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
  const int expected =
      dispatchElement(mesh.elementType, [](auto elem) { return decltype(elem)::kNumNodes; });
  if (mesh.nodesPerElement != expected)
    throw InputError(mesh.source + ": inconsistent nodes per element");
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < mesh.nodesPerElement; ++a) {
      const LocalIndex n = mesh.node(e, a);
      if (n < 0 || n >= mesh.numNodes())
        throw InputError(mesh.source + ": element " + std::to_string(mesh.elementIds[e]) +
                         " references a node that does not exist");
    }
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    for (int i = 0; i < mesh.dim(); ++i)
      if (!std::isfinite(mesh.coordinate(n, i)))
        throw InputError(mesh.source + ": node " + std::to_string(mesh.nodeId(n)) +
                         " has a coordinate that is not a finite number");
  const auto r = dispatchElement(mesh.elementType,
                                 [&](auto elem) { return minJacobian<decltype(elem)>(mesh); });
  if (r.val <= -kJacobianOverflow)
    throw InputError(mesh.source + ": element " + std::to_string(mesh.elementId(r.loc)) +
                     ": its Jacobian determinant is not a finite number in double precision "
                     "(coordinates too large: give the model in other units)");
  // Relative threshold: the Jacobian scales with the element area (volume in 3D).
  double scale = 1.0 / mesh.numElements();
  for (int i = 0; i < mesh.dim(); ++i) {
    double lo = 1e300, hi = -1e300;
    for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
      lo = std::min(lo, mesh.coordinate(n, i));
      hi = std::max(hi, mesh.coordinate(n, i));
    }
    scale *= hi - lo;
  }
  if (!(r.val > 1e-12 * scale)) {
    std::ostringstream msg;
    msg << mesh.source << ": element " << mesh.elementIds[r.loc]
        << " has a non-positive Jacobian determinant (" << r.val << "): it is inverted, degenerate "
        << (mesh.dim() == 2 ? "or its nodes are not counter-clockwise"
                            : "or its nodes are not in Gmsh's order (the first face "
                              "counter-clockwise seen from inside the element)")
        << " (nodes";
    for (int a = 0; a < mesh.nodesPerElement; ++a)
      msg << " " << mesh.nodeIds[mesh.node(r.loc, a)];
    msg << ")";
    throw InputError(msg.str());
  }
  // A node in no element has no stiffness: its row of the system is empty (singular). Checked
  // after the elements, so that a degenerate element (a repeated node) is named as such.
  std::vector<char> used(mesh.numNodes(), 0);
  for (LocalIndex n : mesh.connectivity)
    used[n] = 1;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
    if (!used[n])
      throw InputError(mesh.source + ": node " + std::to_string(mesh.nodeIds[n]) +
                       " is used by no element (it would have no stiffness); remove it from the "
                       "mesh or connect it to an element");
}

double elementLayers(const Mesh &mesh) {
  if (mesh.dim() != 3 || mesh.numElements() == 0)
    return 0.0;
  return dispatchSolidElement(mesh.elementType, "elementLayers", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int kCorners = Elem::kSimplex ? 3 : 4; // a face's corners: its first side nodes
    const std::size_t faces = static_cast<std::size_t>(mesh.numElements()) * Elem::kNumSides;
    // face F = element * kNumSides + side: its corners sorted (the last unused on a triangle)
    const auto key = [&](std::size_t face) {
      std::array<LocalIndex, 4> k{-1, -1, -1, -1};
      const LocalIndex e = static_cast<LocalIndex>(face / Elem::kNumSides);
      for (int c = 0; c < kCorners; ++c)
        k[c] = mesh.node(e, Elem::sideNode(static_cast<int>(face % Elem::kNumSides), c));
      std::sort(k.begin(), k.begin() + kCorners);
      return k;
    };
    const auto smallest = [&](std::size_t face) { // key(face)[0]
      const LocalIndex e = static_cast<LocalIndex>(face / Elem::kNumSides);
      const int side = static_cast<int>(face % Elem::kNumSides);
      LocalIndex k = mesh.node(e, Elem::sideNode(side, 0));
      for (int c = 1; c < kCorners; ++c)
        k = std::min(k, mesh.node(e, Elem::sideNode(side, c)));
      return static_cast<std::size_t>(k);
    };
    // The faces in buckets by their smallest corner (a counting sort): a face is on the boundary
    // where no other face of its bucket has its corners.
    std::vector<std::size_t> offsets(static_cast<std::size_t>(mesh.numNodes()) + 1, 0);
    for (std::size_t f = 0; f < faces; ++f)
      ++offsets[smallest(f) + 1];
    for (std::size_t n = 0; n + 1 < offsets.size(); ++n)
      offsets[n + 1] += offsets[n];
    std::vector<std::size_t> bucket(faces), next(offsets.begin(), offsets.end() - 1);
    for (std::size_t f = 0; f < faces; ++f)
      bucket[next[smallest(f)]++] = f;
    // Over the boundary faces: A, and V = (1/3) sum of x . n A (the divergence theorem; the
    // corners run counter-clockwise seen from outside). n A of a flat polygon is half the cross
    // product of its diagonals (a quadrilateral) or of two edges (a triangle).
    double area = 0.0, volume = 0.0;
    std::vector<std::array<LocalIndex, 4>> keys;
    for (std::size_t n = 0; n + 1 < offsets.size(); ++n) {
      keys.clear();
      for (std::size_t i = offsets[n]; i < offsets[n + 1]; ++i)
        keys.push_back(key(bucket[i]));
      for (std::size_t i = 0; i < keys.size(); ++i) {
        if (std::count(keys.begin(), keys.end(), keys[i]) > 1)
          continue; // shared by two elements: inside
        const std::size_t f = bucket[offsets[n] + i];
        const LocalIndex e = static_cast<LocalIndex>(f / Elem::kNumSides);
        const int side = static_cast<int>(f % Elem::kNumSides);
        double x[kCorners][3], centre[3] = {0.0, 0.0, 0.0};
        for (int c = 0; c < kCorners; ++c)
          for (int d = 0; d < 3; ++d) {
            x[c][d] = mesh.coordinate(mesh.node(e, Elem::sideNode(side, c)), d);
            centre[d] += x[c][d] / kCorners;
          }
        double u[3], v[3]; // quadrilateral: the diagonals 0-2 and 1-3; triangle: edges 0-1, 0-2
        for (int d = 0; d < 3; ++d) {
          u[d] = kCorners == 4 ? x[2][d] - x[0][d] : x[1][d] - x[0][d];
          v[d] = kCorners == 4 ? x[3][d] - x[1][d] : x[2][d] - x[0][d];
        }
        const double na[3] = {0.5 * (u[1] * v[2] - u[2] * v[1]), 0.5 * (u[2] * v[0] - u[0] * v[2]),
                              0.5 * (u[0] * v[1] - u[1] * v[0])};
        area += std::sqrt(na[0] * na[0] + na[1] * na[1] + na[2] * na[2]);
        volume += (centre[0] * na[0] + centre[1] * na[1] + centre[2] * na[2]) / 3.0;
      }
    }
    const double cells = Elem::kSimplex ? mesh.numElements() / 6.0 : mesh.numElements();
    if (!(volume > 0.0) || !(area > 0.0))
      return 0.0;
    return 2.0 * volume / (area * std::cbrt(volume / cells));
  });
}

} // namespace mixcon
