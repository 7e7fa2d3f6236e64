// The contact and hybrid sections of the problem file: rigid obstacles (checked to start outside
// the body), node-to-segment pairs, and the measured displacements of a hybrid run
// (io/ProblemReader.hpp). Data flow: io (input side).
#include <io/ProblemReader.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mixcon::detail {

namespace {

/// How far a node may start inside a rigid obstacle, as a fraction of its body's size (the
/// diagonal of its bounding box): rounding of nodes placed on the obstacle's circle or line.
constexpr double kPenetrationTolerance = 1e-4;

/// Refuses a rigid obstacle that starts inside the body of its contact boundary: the deepest node
/// of that body (every node connected to the boundary) penetrating it by more than
/// kPenetrationTolerance of the body's size.
void checkObstacleOutside(const YamlItem &c, const ContactSpec &s, const Mesh &mesh) {
  const std::vector<LocalIndex> boundary = mesh.nodesOf(s.boundary);
  const std::vector<LocalIndex> body = connectedNodes(mesh, boundary);
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (LocalIndex n : body) {
    x0 = std::min(x0, mesh.x(n));
    x1 = std::max(x1, mesh.x(n));
    y0 = std::min(y0, mesh.y(n));
    y1 = std::max(y1, mesh.y(n));
  }
  const double size = std::hypot(x1 - x0, y1 - y0), tolerance = kPenetrationTolerance * size;
  double deepest = tolerance;
  LocalIndex node = -1;
  for (LocalIndex n : body) {
    const double dx = mesh.x(n) - s.point[0], dy = mesh.y(n) - s.point[1];
    const double depth = s.type == "rigid_circle" ? s.radius - std::hypot(dx, dy)
                                                  : -(dx * s.normal[0] + dy * s.normal[1]);
    if (depth > deepest) {
      deepest = depth;
      node = n;
    }
  }
  if (node < 0)
    return;
  const bool onBoundary = std::binary_search(boundary.begin(), boundary.end(), node);
  std::ostringstream msg;
  msg << "the " << s.type << " starts inside the body: node " << mesh.nodeIds[node] << " ("
      << (onBoundary ? "on boundary '" + s.boundary + "'" : "of the body of '" + s.boundary + "'")
      << ", at " << mesh.x(node) << ", " << mesh.y(node) << ") is " << deepest
      << " inside it (tolerance " << tolerance << ", " << kPenetrationTolerance
      << " of the body's size); an obstacle may touch the body at the start but not penetrate it";
  c.fail(msg.str());
}

} // namespace

void readContact(const YamlItem &list, Problem &p) {
  list.requireSequence();
  for (std::size_t i = 0; i < list.node.size(); ++i) {
    const YamlItem c = list.at(i);
    ContactSpec s;
    s.line = c.line();
    s.type = c.required("type").choice({"rigid_circle", "rigid_half_plane", "node_to_segment"});
    if (s.type == "node_to_segment") {
      c.allowOnly({"type", "contactor", "target", "friction"});
      for (const char *key : {"contactor", "target"}) {
        const YamlItem b = c.required(key);
        if (!p.mesh.hasBoundary(b.string()))
          b.fail("unknown boundary '" + b.string() + "' (mesh has: " + p.mesh.namedSets() + ")");
        checkNotEmpty(p.mesh, b, b.string());
      }
      s.boundary = c["contactor"].string();
      s.target = c["target"].string();
      if (s.boundary == s.target)
        c["target"].fail("the contactor and the target must be different boundaries");
      if (c.has("friction")) {
        s.friction = c["friction"].number();
        if (!(s.friction >= 0.0))
          c["friction"].fail("the friction coefficient must be 0 or positive");
      }
      for (const auto &o : p.contact)
        if ((o.type == "node_to_segment") != (s.type == "node_to_segment"))
          c.fail("node_to_segment contact and rigid obstacles in one problem are not supported "
                 "in this version");
      p.contact.push_back(s);
      continue;
    }
    for (const auto &o : p.contact)
      if (o.type == "node_to_segment")
        c.fail("node_to_segment contact and rigid obstacles in one problem are not supported in "
               "this version");
    if (s.type == "rigid_circle")
      c.allowOnly({"type", "boundary", "center", "radius", "friction", "drive", "status_from"});
    else
      c.allowOnly({"type", "boundary", "point", "normal", "friction", "drive", "status_from"});
    if (c.has("status_from")) {
      s.statusFromStress = c["status_from"].choice({"stresses", "forces"}) == "stresses";
      if (p.model.formulation != Formulation::Mixed)
        c["status_from"].fail("status_from applies to formulation: mixed (the displacement "
                              "model has no nodal stress unknowns; its contact forces decide)");
    }
    const YamlItem b = c.required("boundary");
    s.boundary = b.string();
    if (!p.mesh.hasBoundary(s.boundary))
      b.fail("unknown boundary '" + s.boundary + "' (mesh has: " + p.mesh.namedSets() + ")");
    checkNotEmpty(p.mesh, b, s.boundary);
    if (s.type == "rigid_circle") {
      s.point = c.required("center").pair();
      s.radius = c.required("radius").positive();
    } else {
      s.point = c.required("point").pair();
      s.normal = c.required("normal").pair();
      const double len = std::hypot(s.normal[0], s.normal[1]);
      if (!(len > 0.0))
        c["normal"].fail("the normal must not be zero");
      s.normal = {s.normal[0] / len, s.normal[1] / len};
    }
    checkObstacleOutside(c, s, p.mesh);
    if (c.has("friction")) {
      s.friction = c["friction"].number();
      if (!(s.friction >= 0.0))
        c["friction"].fail("the friction coefficient must be 0 or positive");
    }
    if (c.has("drive"))
      readDrive(c["drive"], s.driveDisplacement, s.driveForce, s.forceDriven);
    p.contact.push_back(s);
  }
}

void readDrive(const YamlItem &d, std::array<double, 2> &displacement, std::array<double, 2> &force,
               std::array<bool, 2> &forceDriven) {
  d.requireMap();
  d.allowOnly({"displacement", "force"});
  // Per component either a displacement or a force (the other list holds null there).
  std::array<int, 2> given{0, 0};
  for (const char *key : {"displacement", "force"}) {
    if (!d.has(key))
      continue;
    const YamlItem v = d[key];
    if (!v.node.IsSequence() || v.node.size() != 2)
      v.fail("expected a list of two entries [x, y] (numbers, or null for a component "
             "given by the other list)");
    const bool isForce = std::string(key) == "force";
    for (int i = 0; i < 2; ++i) {
      if (v.at(i).node.IsNull())
        continue;
      ++given[i];
      (isForce ? force : displacement)[i] = v.at(i).number();
      forceDriven[i] = isForce;
    }
  }
  for (int i = 0; i < 2; ++i)
    if (given[i] != 1)
      d.fail(std::string("component ") + (i == 0 ? "x" : "y") +
             " of the drive must be given exactly once, as a displacement or as a force "
             "(write null in the other list)");
}

void readHybrid(const YamlItem &top, Problem &p, const std::string &baseDirectory) {
  const YamlItem h = top["hybrid"];
  h.requireMap();
  h.allowOnly({"measurements", "boundary", "center", "symmetrize", "max_distance", "threshold"});
  if (top.has("contact"))
    h.fail("a hybrid run replaces the contact by the measured displacements: remove the "
           "contact section");
  HybridSpec s;
  s.line = h.line();
  s.boundary = h.required("boundary").string();
  if (!p.mesh.hasBoundary(s.boundary))
    h["boundary"].fail("unknown boundary '" + s.boundary + "' (mesh has: " + p.mesh.namedSets() +
                       ")");
  checkNotEmpty(p.mesh, h["boundary"], s.boundary);
  if (h.has("center"))
    s.center = h["center"].pair();
  if (h.has("symmetrize"))
    s.symmetrize = h["symmetrize"].boolean();
  s.maxDistance = h.required("max_distance").positive();
  if (h.has("threshold")) {
    s.threshold = h["threshold"].number();
    if (!(s.threshold >= 0.0 && s.threshold < 1.0))
      h["threshold"].fail("threshold must lie in [0, 1) (a fraction of the peak |sigma_rr|)");
  }
  s.measurements = joinPath(baseDirectory, h.required("measurements").string());
  s.steps = readMeasurements(s.measurements);
  checkNearBoundary(p.mesh, s.boundary, s.steps, s.maxDistance, s.measurements, s.symmetrize,
                    s.center[1]);
  p.hybrid = s;
}

} // namespace mixcon::detail
