// SurfaceContact: node-to-segment search per iteration, statuses and the closed pairs.
#include <contact/SegmentSearch.hpp>
#include <contact/SurfaceContact.hpp>
#include <core/Transfer.hpp>
#include <solver/LocalFrames.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace mixcon {

namespace surface_detail {

/// Current positions x = X + u of every node (u with `stride` unknowns per node).
struct CurrentPositions {
  Kokkos::View<const double *[2], DeviceSpace> coordinates;
  Kokkos::View<const double *, DeviceSpace> u;
  Kokkos::View<double *[2], DeviceSpace> x;
  int stride;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex p) const {
    x(p, 0) = coordinates(p, 0) + u(stride * p);
    x(p, 1) = coordinates(p, 1) + u(stride * p + 1);
  }
};

/// Queries: the positions of the contactor nodes.
struct GatherPoints {
  Kokkos::View<const double *[2], DeviceSpace> x;
  Kokkos::View<const LocalIndex *, DeviceSpace> nodes;
  Kokkos::View<double *[2], DeviceSpace> q;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex k) const {
    q(k, 0) = x(nodes(k), 0);
    q(k, 1) = x(nodes(k), 1);
  }
};

/// Unit normals of every target segment at its two ends (the segment's own normal there).
struct EndNormals {
  Kokkos::View<const double *[2], DeviceSpace> x;
  Kokkos::View<const int *[3], DeviceSpace> segments;
  Kokkos::View<double *[2][2], DeviceSpace> ends;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex j) const {
    double a[2], b[2], mid[2] = {0.0, 0.0};
    const bool quadratic = segments(j, 2) >= 0;
    for (int i = 0; i < 2; ++i) {
      a[i] = x(segments(j, 0), i);
      b[i] = x(segments(j, 1), i);
      if (quadratic)
        mid[i] = x(segments(j, 2), i);
    }
    for (int e = 0; e < 2; ++e) {
      const SegmentProjection pr = projectionAt(a, a, b, mid, quadratic, e == 0 ? -1.0 : 1.0);
      ends(j, e, 0) = pr.normal[0];
      ends(j, e, 1) = pr.normal[1];
    }
  }
};

/// The continuous normal field at each target end node: the average of its segments' end
/// normals (summed in segment order), without its component along a direction held alone (a
/// symmetry line: the surface meets it at right angles, the mirrored segment's normal would
/// cancel that component), normalized.
struct NodalNormals {
  Kokkos::View<const double *[2][2], DeviceSpace> ends;
  Kokkos::View<const Offset *, DeviceSpace> start;
  Kokkos::View<const int *, DeviceSpace> entries;
  Kokkos::View<const int *, DeviceSpace> surface;
  Kokkos::View<const int *[2], DeviceSpace> held;
  Kokkos::View<double *[2], DeviceSpace> nodal;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex t) const {
    double n[2] = {0.0, 0.0};
    for (Offset k = start(t); k < start(t + 1); ++k)
      for (int i = 0; i < 2; ++i)
        n[i] += ends(entries(k) / 2, entries(k) % 2, i);
    const bool hx = held(surface(t), 0) != 0, hy = held(surface(t), 1) != 0;
    if (hx != hy)
      n[hx ? 0 : 1] = 0.0;
    const double l = search_detail::hypot(n[0], n[1]);
    for (int i = 0; i < 2; ++i)
      nodal(t, i) = l > 0.0 ? n[i] / l : n[i];
  }
};

/// Per contactor: its segment and parameter, the normal of the continuous field at the
/// projection (the segment's normal plus the linear blend of the nodal differences at its
/// ends) and the gap along it: (segment, xi, n_x, n_y, gap), the only numbers per contactor
/// that come to the host. No segment within the radius: far away (gap `far`).
struct ContactorNormals {
  Kokkos::View<const double *[2], DeviceSpace> x;
  Kokkos::View<const LocalIndex *, DeviceSpace> contactors;
  Kokkos::View<const int *, DeviceSpace> segment;
  Kokkos::View<const double *, DeviceSpace> xi;
  Kokkos::View<const double *[2], DeviceSpace> normal, closest;
  Kokkos::View<const double *[2][2], DeviceSpace> ends;
  Kokkos::View<const int *[2], DeviceSpace> segmentEnds;
  Kokkos::View<const double *[2], DeviceSpace> nodal;
  Kokkos::View<double *[5], DeviceSpace> out;
  double far;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex q) const {
    const int j = segment(q);
    out(q, 0) = j;
    out(q, 1) = xi(q);
    if (j < 0) {
      out(q, 2) = normal(q, 0);
      out(q, 3) = normal(q, 1);
      out(q, 4) = far;
      return;
    }
    const double wa = 0.5 * (1 - xi(q)), wb = 0.5 * (1 + xi(q));
    const int ta = segmentEnds(j, 0), tb = segmentEnds(j, 1);
    double n[2];
    for (int i = 0; i < 2; ++i)
      n[i] =
          normal(q, i) + wa * (nodal(ta, i) - ends(j, 0, i)) + wb * (nodal(tb, i) - ends(j, 1, i));
    const double l = search_detail::hypot(n[0], n[1]);
    n[0] /= l;
    n[1] /= l;
    out(q, 2) = n[0];
    out(q, 3) = n[1];
    // The gap along that normal (beyond a segment's end too, where the search's signed
    // distance would include the tangential offset).
    const LocalIndex p = contactors(q);
    out(q, 4) = (x(p, 0) - closest(q, 0)) * n[0] + (x(p, 1) - closest(q, 1)) * n[1];
  }
};

/// Shape functions of a linear (count 2) or quadratic (count 3: ends, then middle) segment.
void segmentWeights(double xi, bool quadratic, double (&w)[3]) {
  if (quadratic) {
    w[0] = 0.5 * xi * (xi - 1);
    w[1] = 0.5 * xi * (xi + 1);
    w[2] = 1 - xi * xi;
  } else {
    w[0] = 0.5 * (1 - xi);
    w[1] = 0.5 * (1 + xi);
    w[2] = 0.0;
  }
}

} // namespace surface_detail

using namespace surface_detail;

std::vector<std::array<LocalIndex, 3>> boundarySegments(const Mesh &mesh, const std::string &name) {
  const auto b = mesh.boundaries.find(name);
  if (b == mesh.boundaries.end())
    throw InputError(mesh.source + ": no boundary named '" + name +
                     "' (known: " + mesh.namedSets() + ")");
  std::vector<std::array<LocalIndex, 3>> segs;
  for (const BoundaryEdge &e : b->second)
    segs.push_back({mesh.edgeNode(e, 0), mesh.edgeNode(e, 1),
                    mesh.nodesPerEdge() == 3 ? mesh.edgeNode(e, 2) : -1});
  return segs;
}

SurfaceContact::SurfaceContact(LocalIndex numNodes, std::vector<SurfaceContactSpec> specs,
                               std::vector<long> nodeIds)
    : nodeIds_(std::move(nodeIds)), specs_(std::move(specs)), numNodes_(numNodes) {
  std::set<LocalIndex> contactors, targets;
  for (std::size_t s = 0; s < specs_.size(); ++s) {
    const auto &sp = specs_[s];
    if (sp.contactor.empty() || sp.target.empty())
      throw InputError(pairLabel(static_cast<int>(s)) +
                       ": the contactor or the target surface is empty");
    std::set<LocalIndex> unique(sp.contactor.begin(), sp.contactor.end());
    for (LocalIndex n : unique) {
      node_.push_back(n);
      spec_.push_back(static_cast<int>(s));
      contactors.insert(n);
    }
    for (const auto &seg : sp.target)
      for (LocalIndex n : seg)
        if (n >= 0)
          targets.insert(n);
  }
  for (std::size_t s = 0, first = 0; s < specs_.size(); ++s) {
    DeviceSurface d;
    d.first = first;
    const auto &sp = specs_[s];
    d.segments = Kokkos::View<int *[3], DeviceSpace>("mixcon::surface::segments", sp.target.size());
    auto hs = hostMirror(d.segments);
    for (std::size_t j = 0; j < sp.target.size(); ++j)
      for (int a = 0; a < 3; ++a)
        hs(j, a) = sp.target[j][a];
    copyToDevice(d.segments, hs);
    while (first < node_.size() && spec_[first] == static_cast<int>(s))
      ++first;
    d.contactors =
        Kokkos::View<LocalIndex *, DeviceSpace>("mixcon::surface::contactors", first - d.first);
    auto hq = hostMirror(d.contactors);
    for (std::size_t k = d.first; k < first; ++k)
      hq(k - d.first) = node_[k];
    copyToDevice(d.contactors, hq);
    // The target end nodes and the (segment, end) pairs at each, in segment order.
    std::vector<LocalIndex> ends;
    for (const auto &seg : sp.target)
      for (int e = 0; e < 2; ++e)
        ends.push_back(seg[e]);
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    const auto local = [&](LocalIndex n) {
      return static_cast<int>(std::lower_bound(ends.begin(), ends.end(), n) - ends.begin());
    };
    std::vector<std::vector<int>> at(ends.size());
    std::vector<int> segmentEnds;
    for (std::size_t j = 0; j < sp.target.size(); ++j)
      for (int e = 0; e < 2; ++e) {
        at[local(sp.target[j][e])].push_back(static_cast<int>(2 * j + e));
        segmentEnds.push_back(local(sp.target[j][e]));
      }
    std::vector<Offset> start{0};
    std::vector<int> entries;
    for (const auto &a : at) {
      entries.insert(entries.end(), a.begin(), a.end());
      start.push_back(static_cast<Offset>(entries.size()));
    }
    d.targetNodes =
        Kokkos::View<LocalIndex *, DeviceSpace>("mixcon::surface::targetNodes", ends.size());
    copyToDevice(d.targetNodes, ends);
    d.targetStart =
        Kokkos::View<Offset *, DeviceSpace>("mixcon::surface::targetStart", start.size());
    copyToDevice(d.targetStart, start);
    d.targetEnds = Kokkos::View<int *, DeviceSpace>("mixcon::surface::targetEnds", entries.size());
    copyToDevice(d.targetEnds, entries);
    d.segmentEnds =
        Kokkos::View<int *[2], DeviceSpace>("mixcon::surface::segmentEnds", sp.target.size());
    auto he = hostMirror(d.segmentEnds);
    for (std::size_t j = 0; j < sp.target.size(); ++j)
      for (int e = 0; e < 2; ++e)
        he(j, e) = segmentEnds[2 * j + e];
    copyToDevice(d.segmentEnds, he);
    device_.push_back(d);
  }
  for (LocalIndex n : contactors)
    if (targets.count(n))
      throw InputError("node " + std::to_string(Mesh::externalId(nodeIds_, n)) +
                       " is both a contactor and a target node; the surfaces of a "
                       "node_to_segment contact must not share nodes");
  const std::size_t m = node_.size();
  status_.assign(m, ContactStatus::Open);
  segment_.assign(m, -1);
  anchorSegment_.assign(m, -1);
  committedSegment_.assign(m, -1);
  xi_.assign(m, 0.0);
  anchorXi_.assign(m, 0.0);
  committedXi_.assign(m, 0.0);
  gap_.assign(m, 0.0);
  normal_.assign(2 * m, 0.0);
  normalForce_.assign(m, 0.0);
  tangentForce_.assign(m, 0.0);
  friction_.assign(2 * static_cast<std::size_t>(numNodes_), 0.0);
  prescribed_.assign(2 * static_cast<std::size_t>(numNodes_), 0);
  surfaceNodes_.assign(contactors.begin(), contactors.end());
  surfaceNodes_.insert(surfaceNodes_.end(), targets.begin(), targets.end());
  std::sort(surfaceNodes_.begin(), surfaceNodes_.end());
  surfaceNodes_.erase(std::unique(surfaceNodes_.begin(), surfaceNodes_.end()), surfaceNodes_.end());
  deviceSurfaceNodes_ = Kokkos::View<LocalIndex *, DeviceSpace>("mixcon::surface::surfaceNodes",
                                                                surfaceNodes_.size());
  copyToDevice(deviceSurfaceNodes_, surfaceNodes_);
  surfaceHeld_ =
      Kokkos::View<int *[2], DeviceSpace>("mixcon::surface::surfaceHeld", surfaceNodes_.size());
  for (DeviceSurface &d : device_) { // the surface index of each target node
    const auto ends = toHostVector(d.targetNodes);
    std::vector<int> index(ends.size());
    for (std::size_t t = 0; t < ends.size(); ++t)
      index[t] =
          static_cast<int>(std::lower_bound(surfaceNodes_.begin(), surfaceNodes_.end(), ends[t]) -
                           surfaceNodes_.begin());
    d.targetSurface =
        Kokkos::View<int *, DeviceSpace>("mixcon::surface::targetSurface", index.size());
    copyToDevice(d.targetSurface, index);
  }
}

void SurfaceContact::targetPoint(int s, int segment, double xi, double (&x)[2],
                                 LocalIndex (&nodes)[3], double (&w)[3], int &count) const {
  const auto &seg = specs_[s].target[segment];
  const bool quadratic = seg[2] >= 0;
  segmentWeights(xi, quadratic, w);
  count = quadratic ? 3 : 2;
  x[0] = x[1] = 0.0;
  for (int a = 0; a < count; ++a) {
    nodes[a] = seg[a];
    x[0] += w[a] * position_[2 * static_cast<std::size_t>(seg[a])];
    x[1] += w[a] * position_[2 * static_cast<std::size_t>(seg[a]) + 1];
  }
}

LocalIndex SurfaceContact::detect(const Kokkos::View<const double *[2], DeviceSpace> &coordinates,
                                  const Kokkos::View<const double *, DeviceSpace> &u, int stride) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const LocalIndex nn = static_cast<LocalIndex>(coordinates.extent(0));
  Kokkos::View<double *[2], DeviceSpace> x("mixcon::surface::positions", nn);
  Kokkos::parallel_for("mixcon::surface::positions", Kokkos::RangePolicy<Exec>(0, nn),
                       CurrentPositions{coordinates, u, x, stride});
  {
    // Only the contactor and target nodes' positions come to the host.
    const LocalIndex ns = static_cast<LocalIndex>(surfaceNodes_.size());
    Kokkos::View<double *[2], DeviceSpace> xs("mixcon::surface::surfacePositions", ns);
    Kokkos::parallel_for("mixcon::surface::gatherSurface", Kokkos::RangePolicy<Exec>(0, ns),
                         GatherPoints{x, deviceSurfaceNodes_, xs});
    const auto h = copyToHost(xs);
    position_.resize(2 * static_cast<std::size_t>(nn), 0.0);
    for (LocalIndex k = 0; k < ns; ++k) {
      position_[2 * static_cast<std::size_t>(surfaceNodes_[k])] = h(k, 0);
      position_[2 * static_cast<std::size_t>(surfaceNodes_[k]) + 1] = h(k, 1);
    }
  }
  if (meanLength_.empty()) { // reference lengths, from the first detection
    for (const auto &sp : specs_) {
      double total = 0.0, longest = 0.0;
      std::vector<double> start;
      for (const auto &seg : sp.target) {
        start.push_back(total);
        const double l = std::hypot(position_[2 * seg[1]] - position_[2 * seg[0]],
                                    position_[2 * seg[1] + 1] - position_[2 * seg[0] + 1]);
        total += l;
        longest = std::max(longest, l);
      }
      arcStart_.push_back(start);
      meanLength_.push_back(total / static_cast<double>(sp.target.size()));
      extent_.push_back(std::max(total, longest));
    }
  }
  LocalIndex penetrating = 0;
  for (std::size_t s = 0; s < specs_.size(); ++s) {
    const auto &sp = specs_[s];
    const DeviceSurface &dev = device_[s];
    const LocalIndex ns = static_cast<LocalIndex>(sp.target.size());
    const LocalIndex nq = static_cast<LocalIndex>(dev.contactors.extent(0));
    Kokkos::View<double *[2], DeviceSpace> queries("mixcon::surface::queries", nq);
    Kokkos::parallel_for("mixcon::surface::gather", Kokkos::RangePolicy<Exec>(0, nq),
                         GatherPoints{x, dev.contactors, queries});
    const SegmentSet<DeviceSpace> set{x, dev.segments};
    SegmentGrid<Exec> grid;
    grid.build(Exec(), set, 2.0 * meanLength_[s] + 1e-300);
    SearchResults<DeviceSpace> found(nq);
    grid.query(Exec(), queries, found);
    // A continuous normal field: at each target node the average of its segments' unit
    // normals there; along a segment its own normal plus the linear blend of the differences
    // at its ends. Without it a contactor on a vertex where two segments meet at an angle has
    // no equilibrium direction (the force would jump between the two segment normals) and the
    // iterations drift. Built on the device; 5 numbers per contactor come to the host.
    Kokkos::View<double *[2][2], DeviceSpace> ends("mixcon::surface::endNormals", ns);
    Kokkos::parallel_for("mixcon::surface::endNormals", Kokkos::RangePolicy<Exec>(0, ns),
                         EndNormals{x, dev.segments, ends});
    const LocalIndex nt = static_cast<LocalIndex>(dev.targetNodes.extent(0));
    Kokkos::View<double *[2], DeviceSpace> nodal("mixcon::surface::nodalNormals", nt);
    Kokkos::parallel_for("mixcon::surface::nodalNormals", Kokkos::RangePolicy<Exec>(0, nt),
                         NodalNormals{ends, dev.targetStart, dev.targetEnds, dev.targetSurface,
                                      surfaceHeld_, nodal});
    Kokkos::View<double *[5], DeviceSpace> out("mixcon::surface::contactors", nq);
    Kokkos::parallel_for("mixcon::surface::contactorNormals", Kokkos::RangePolicy<Exec>(0, nq),
                         ContactorNormals{x, dev.contactors, found.segment, found.xi, found.normal,
                                          found.closest, ends, dev.segmentEnds, nodal, out,
                                          2.0 * meanLength_[s]});
    const auto h = copyToHost(out);
    for (LocalIndex q = 0; q < nq; ++q) {
      const std::size_t k = dev.first + q;
      segment_[k] = static_cast<int>(h(q, 0));
      xi_[k] = h(q, 1);
      normal_[2 * k] = h(q, 2);
      normal_[2 * k + 1] = h(q, 3);
      gap_[k] = h(q, 4);
      penetrating += segment_[k] >= 0 && gap_[k] < 0.0;
    }
  }
  if (saved_.status.empty() && saved_.committedGap.empty()) {
    // The state of the first detection (the initial one, at rest) is where a node that closes
    // in the first increment starts from; kept through a rollback before anything is
    // committed. (Where it already holds the first increment's motion, a node that closes
    // there is anchored where it is, as before.)
    saved_.committedSegment = segment_;
    saved_.committedXi = xi_;
    saved_.committedGap = gap_;
  }
  buildPairs();
  return penetrating;
}

void SurfaceContact::buildPairs() {
  pairs_.clear();
  deviceConstraintsFresh_ = false;
  for (LocalIndex p : surfaceNodes_) // friction acts on contactor and target nodes only
    friction_[2 * static_cast<std::size_t>(p)] = friction_[2 * static_cast<std::size_t>(p) + 1] =
        0.0;
  if (position_.empty()) {
    uploadFriction();
    return;
  }
  for (std::size_t k = 0; k < node_.size(); ++k) {
    if (status_[k] == ContactStatus::Open || segment_[k] < 0)
      continue;
    const int s = spec_[k];
    SurfacePair p;
    p.node = node_[k];
    p.normal[0] = normal_[2 * k];
    p.normal[1] = normal_[2 * k + 1];
    double t[1][2];
    tangentBasis<2>(p.normal, t);
    p.tangent[0] = t[0][0];
    p.tangent[1] = t[0][1];
    double xt[2];
    targetPoint(s, segment_[k], xi_[k], xt, p.normalNodes, p.normalWeights, p.normalCount);
    p.normalStep = -gap_[k];
    const double *xc = &position_[2 * static_cast<std::size_t>(p.node)];
    if (status_[k] == ContactStatus::Stick && anchorSegment_[k] >= 0) {
      p.stick = true;
      double xa[2];
      targetPoint(s, anchorSegment_[k], anchorXi_[k], xa, p.tangentNodes, p.tangentWeights,
                  p.tangentCount);
      p.tangentStep = -(p.tangent[0] * (xc[0] - xa[0]) + p.tangent[1] * (xc[1] - xa[1]));
    } else if (status_[k] == ContactStatus::Slip) {
      // Friction mu N against the slip (sign kept from the tangential force that started it),
      // on the contactor, and equal and opposite on the target nodes.
      const double f = specs_[s].friction * std::max(normalForce_[k], 0.0) *
                       (tangentForce_[k] > 0 ? 1.0 : (tangentForce_[k] < 0 ? -1.0 : 0.0));
      for (int i = 0; i < 2; ++i) {
        friction_[2 * static_cast<std::size_t>(p.node) + i] += f * p.tangent[i];
        for (int a = 0; a < p.normalCount; ++a)
          friction_[2 * static_cast<std::size_t>(p.normalNodes[a]) + i] -=
              p.normalWeights[a] * f * p.tangent[i];
      }
    }
    pairs_.push_back(p);
  }
  uploadFriction();
}

void SurfaceContact::uploadFriction() {
  std::vector<LocalIndex> nodes;
  std::vector<double> values;
  for (LocalIndex p : surfaceNodes_) {
    const double fx = friction_[2 * static_cast<std::size_t>(p)],
                 fy = friction_[2 * static_cast<std::size_t>(p) + 1];
    if (fx != 0.0 || fy != 0.0) {
      nodes.push_back(p);
      values.push_back(fx);
      values.push_back(fy);
    }
  }
  frictionNodes_ = {};
  frictionValues_ = {};
  if (nodes.empty())
    return;
  frictionNodes_ =
      Kokkos::View<LocalIndex *, DeviceSpace>("mixcon::surface::frictionNodes", nodes.size());
  frictionValues_ =
      Kokkos::View<double *[2], DeviceSpace>("mixcon::surface::frictionValues", nodes.size());
  copyToDevice(frictionNodes_, nodes);
  const auto h = hostMirror(frictionValues_);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int i = 0; i < 2; ++i)
      h(k, i) = values[2 * k + i];
  copyToDevice(frictionValues_, h);
}

int SurfaceContact::closeTouching(double tolerance) {
  int closed = 0;
  for (std::size_t k = 0; k < node_.size(); ++k)
    if (status_[k] == ContactStatus::Open && segment_[k] >= 0 &&
        gap_[k] <= tolerance * meanLength_[spec_[k]]) {
      status_[k] = specs_[spec_[k]].friction > 0.0 ? ContactStatus::Stick : ContactStatus::Slip;
      anchorSegment_[k] = committedSegment_[k] = segment_[k];
      anchorXi_[k] = committedXi_[k] = xi_[k];
      ++closed;
    }
  buildPairs();
  return closed;
}

int SurfaceContact::updateStatus(const std::vector<double> &g, int stride, std::string &log,
                                 const std::vector<double> *, bool frozen) {
  std::ostringstream out;
  int changes = 0;
  for (std::size_t k = 0; k < node_.size(); ++k) {
    const LocalIndex p = node_[k];
    const double n[2] = {normal_[2 * k], normal_[2 * k + 1]};
    double t[1][2];
    tangentBasis<2>(n, t);
    const double n0 = n[0], n1 = n[1];
    // The multipliers: the contactor's contact force, its residual without the friction force
    // already applied. With one component held by a Dirichlet condition the other carries the
    // normal force alone (a symmetry line); there is then no tangential multiplier.
    const double gx = g[stride * p] + friction_[2 * p];
    const double gy = g[stride * p + 1] + friction_[2 * p + 1];
    const bool hx = prescribed_[2 * p] != 0, hy = prescribed_[2 * p + 1] != 0;
    double nForce = gx * n0 + gy * n1, tForce = gx * t[0][0] + gy * t[0][1];
    if (hx != hy) {
      const int other = hx ? 1 : 0;
      nForce = (other == 0 ? gx : gy) / (other == 0 ? n0 : n1);
      tForce = 0.0;
    }
    const double mu = specs_[spec_[k]].friction;
    const ContactStatus before = status_[k];
    // Stick again when the node moves along its friction force (the slip reversed): relative
    // tangential motion since the last commit, measured on the target.
    bool reversed = false;
    if (status_[k] == ContactStatus::Slip && segment_[k] >= 0) {
      double xc[2], w[3];
      LocalIndex nodes[3];
      int count = 0;
      targetPoint(spec_[k], committedSegment_[k] >= 0 ? committedSegment_[k] : segment_[k],
                  committedXi_[k], xc, nodes, w, count);
      const double *x = &position_[2 * static_cast<std::size_t>(p)];
      const double moved = t[0][0] * (x[0] - xc[0]) + t[0][1] * (x[1] - xc[1]);
      reversed =
          moved * tangentForce_[k] > 1e-12 * meanLength_[spec_[k]] * std::abs(tangentForce_[k]);
    }
    // A closed node that lost its target segment (moved beyond the search radius) opens.
    const double compression = segment_[k] >= 0 ? nForce : -1.0;
    CoulombInput in{nForce,  tForce, compression, tForce, mu, segment_[k] >= 0 && gap_[k] < 0.0,
                    reversed};
    const CoulombOutcome r =
        updateCoulomb(status_[k], normalForce_[k], tangentForce_[k], in, frozen);
    if (r.anchor) {
      // A node that closes sticks where it crossed the target during the increment (anchored
      // at the end of the increment instead, it carries the relative motion of the rest of the
      // increment as a spurious stick displacement: the stick tractions then scatter node to
      // node, docs/contact.md); a slipping node that reverses sticks where it was at the last
      // converged state (stick is the trial state from there).
      const bool reverses = before == ContactStatus::Slip && committedSegment_[k] >= 0;
      if (reverses) {
        anchorSegment_[k] = committedSegment_[k];
        anchorXi_[k] = committedXi_[k];
      } else {
        crossingPoint(k, anchorSegment_[k], anchorXi_[k]);
      }
      if (before == ContactStatus::Open) {
        committedSegment_[k] = segment_[k];
        committedXi_[k] = xi_[k];
      }
    }
    if (!r.changed)
      continue;
    ++changes;
    // "contact: node <mesh id> on contact <1-based> ('<contactor> -> <target>'): ..."
    out << "    contact: node " << Mesh::externalId(nodeIds_, p) << " on " << pairLabel(spec_[k])
        << ": ";
    if (r.friction)
      out << "friction " << r.previousFriction << " -> " << tangentForce_[k] << "\n";
    else
      out << contactStatusName(before) << " -> " << contactStatusName(status_[k]) << " (gap "
          << gap_[k] << ", N " << nForce << ", T " << tForce << ")\n";
  }
  buildPairs();
  log = out.str();
  return changes;
}

bool SurfaceContact::penetrationWithin(double relative, std::string &where) const {
  double worst = 0.0;
  std::size_t at = 0;
  for (std::size_t k = 0; k < node_.size(); ++k) {
    if (status_[k] == ContactStatus::Open)
      continue;
    const double ratio = -gap_[k] / std::max(extent_[spec_[k]], 1e-300);
    if (ratio > worst) {
      worst = ratio;
      at = k;
    }
  }
  if (worst <= relative)
    return true;
  std::ostringstream m;
  m << "contactor node " << Mesh::externalId(nodeIds_, node_[at]) << " of " << pairLabel(spec_[at])
    << " penetrates its target by " << -gap_[at] << " (" << worst
    << " of the target surface's length)";
  where = m.str();
  return false;
}

void SurfaceContact::crossingPoint(std::size_t k, int &segment, double &xi) const {
  segment = segment_[k];
  xi = xi_[k];
  if (saved_.committedGap.empty())
    return;
  const int s0 = saved_.committedSegment[k];
  const double a = crossingFraction(saved_.committedGap[k], gap_[k]), xi0 = saved_.committedXi[k];
  if (s0 < 0 || segment < 0 || a < 0.0)
    return; // no start to interpolate from (or not a crossing): where it is now
  if (s0 == segment) {
    xi = xi0 + a * (xi_[k] - xi0);
    return;
  }
  // Two segments sharing an end: a path coordinate along them, zero at the shared end,
  // negative on the start's segment, in current chord lengths.
  const auto &seg = specs_[static_cast<std::size_t>(spec_[k])].target;
  const auto &from = seg[static_cast<std::size_t>(s0)],
             &to = seg[static_cast<std::size_t>(segment)];
  int endFrom = -1, endTo = -1;
  for (int e = 0; e < 2; ++e)
    for (int f = 0; f < 2; ++f)
      if (from[e] == to[f]) {
        endFrom = e;
        endTo = f;
      }
  if (endFrom < 0) {
    // Farther than the next segment: the point a fraction a of the way along the chord from
    // where the start's material point is now to the current projection, projected back onto
    // the nearest target segment (all of this contact's: a node closing after a long slide).
    double p0[2], p1[2], w[3];
    LocalIndex nodes[3];
    int count = 0;
    targetPoint(spec_[k], s0, xi0, p0, nodes, w, count);
    targetPoint(spec_[k], segment, xi_[k], p1, nodes, w, count);
    const double q[2] = {p0[0] + a * (p1[0] - p0[0]), p0[1] + a * (p1[1] - p0[1])};
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < seg.size(); ++j) {
      const bool quadratic = seg[j][2] >= 0;
      double ends[3][2] = {}; // the end nodes, then the middle one of a quadratic segment
      for (int e = 0; e < (quadratic ? 3 : 2); ++e)
        for (int i = 0; i < 2; ++i)
          ends[e][i] = position_[2 * static_cast<std::size_t>(seg[j][e]) + i];
      const SegmentProjection r = projectOntoSegment(q, ends[0], ends[1], ends[2], quadratic);
      if (r.distance2 < best) {
        best = r.distance2;
        segment = static_cast<int>(j);
        xi = r.xi;
      }
    }
    return;
  }
  const auto length = [this](const auto &ends) {
    const double *p = &position_[2 * static_cast<std::size_t>(ends[0])];
    const double *q = &position_[2 * static_cast<std::size_t>(ends[1])];
    return std::hypot(q[0] - p[0], q[1] - p[1]);
  };
  const double lFrom = length(from), lTo = length(to);
  const double xiFrom = endFrom == 0 ? -1.0 : 1.0, xiTo = endTo == 0 ? -1.0 : 1.0;
  const double start = -0.5 * std::abs(xi0 - xiFrom) * lFrom;
  const double end = 0.5 * std::abs(xi_[k] - xiTo) * lTo;
  const double at = start + a * (end - start);
  if (at < 0.0) {
    segment = s0;
    xi = xiFrom - xiFrom * 2.0 * (-at) / std::max(lFrom, 1e-300);
  } else {
    xi = xiTo - xiTo * 2.0 * at / std::max(lTo, 1e-300);
  }
}

void SurfaceContact::commit() {
  committedSegment_ = segment_;
  committedXi_ = xi_;
  saved_ = {status_,      anchorSegment_, committedSegment_, anchorXi_,
            committedXi_, normalForce_,   tangentForce_,     gap_};
}

void SurfaceContact::rollback() {
  if (saved_.status.empty()) {
    std::fill(status_.begin(), status_.end(), ContactStatus::Open);
    std::fill(normalForce_.begin(), normalForce_.end(), 0.0);
    std::fill(tangentForce_.begin(), tangentForce_.end(), 0.0);
  } else {
    status_ = saved_.status;
    anchorSegment_ = saved_.anchorSegment;
    committedSegment_ = saved_.committedSegment;
    anchorXi_ = saved_.anchorXi;
    committedXi_ = saved_.committedXi;
    normalForce_ = saved_.normalForce;
    tangentForce_ = saved_.tangentForce;
  }
  buildPairs();
}

std::string SurfaceContact::pairLabel(int s) const {
  return "contact " + std::to_string(s + 1) + " ('" + specs_[static_cast<std::size_t>(s)].name +
         "')";
}

std::string SurfaceContact::signature() const { return statusSignature(status_); }

void SurfaceContact::saveCommitted(Checkpoint &state) const {
  const std::size_t m = node_.size();
  const bool none = saved_.status.empty(); // nothing committed yet: the initial state
  const std::vector<double> zero(m, 0.0);
  const std::vector<int> noSegment(m, -1);
  const std::vector<ContactStatus> open(m, ContactStatus::Open);
  state.putIntegers("contact/status", none ? open : saved_.status);
  state.putIntegers("contact/anchor_segment", none ? noSegment : saved_.anchorSegment);
  state.putIntegers("contact/committed_segment", none ? noSegment : saved_.committedSegment);
  state.put("contact/anchor_xi", none ? zero : saved_.anchorXi);
  state.put("contact/committed_xi", none ? zero : saved_.committedXi);
  state.put("contact/normal_force", none ? zero : saved_.normalForce);
  state.put("contact/tangential_force", none ? zero : saved_.tangentForce);
  state.put("contact/committed_gap", none ? zero : saved_.committedGap);
}

void SurfaceContact::restoreCommitted(const Checkpoint &state) {
  const std::size_t m = node_.size();
  Saved s;
  s.status = state.getIntegers<ContactStatus>("contact/status", m);
  s.anchorSegment = state.getIntegers<int>("contact/anchor_segment", m);
  s.committedSegment = state.getIntegers<int>("contact/committed_segment", m);
  s.anchorXi = state.get("contact/anchor_xi", m);
  s.committedXi = state.get("contact/committed_xi", m);
  s.normalForce = state.get("contact/normal_force", m);
  s.tangentForce = state.get("contact/tangential_force", m);
  // Written since the crossing-point anchor; without it a node that closes in the next
  // increment is anchored where the increment ends.
  s.committedGap =
      state.getOr("contact/committed_gap", m, std::numeric_limits<double>::quiet_NaN());
  saved_ = std::move(s);
  rollback();
}

LocalIndex SurfaceContact::numClosed() const { return countClosed(status_); }

double SurfaceContact::angle(LocalIndex k) const {
  return std::atan2(normal_[2 * k + 1], normal_[2 * k]);
}

double SurfaceContact::arcCoordinate(LocalIndex k) const {
  if (segment_[k] < 0 || arcStart_.empty())
    return 0.0;
  const int s = spec_[k];
  const auto &seg = specs_[s].target;
  const double start = arcStart_[s][segment_[k]];
  const double end =
      segment_[k] + 1 < static_cast<int>(seg.size()) ? arcStart_[s][segment_[k] + 1] : extent_[s];
  return start + 0.5 * (xi_[k] + 1) * (end - start);
}

} // namespace mixcon
