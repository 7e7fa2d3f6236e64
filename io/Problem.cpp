// YAML problem-file reader (yaml-cpp). Every map is checked against its allowed keys; every error
// names file:line:column and the key path (e.g. "materials[1].E").
#include <io/Problem.hpp>
#include <io/ProblemChecks.hpp>
#include <kernels/MixedElasticity.hpp>
#include <mesh/Generators.hpp>
#include <mesh/GmshReader.hpp>

#include <yaml-cpp/yaml.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace mixcon {

namespace {

/// A YAML node with its path in the document, for messages.
struct Item {
  YAML::Node node;
  std::string path;
  const std::string *file;

  [[noreturn]] void fail(const std::string &msg) const {
    std::ostringstream s;
    s << *file;
    const auto m = node.Mark();
    if (m.line >= 0)
      s << ":" << m.line + 1 << ":" << m.column + 1;
    s << ": " << (path.empty() ? "" : path + ": ") << detail::clipQuoted(msg);
    throw InputError(s.str());
  }
  int line() const { return node.Mark().line + 1; }
  bool has(const char *key) const { return node.IsMap() && node[key]; }
  Item operator[](const char *key) const {
    return Item{node[key], path.empty() ? key : path + "." + key, file};
  }
  Item at(std::size_t i) const { return Item{node[i], path + "[" + std::to_string(i) + "]", file}; }
  Item required(const char *key) const {
    if (!has(key))
      fail(std::string("missing required key '") + key + "'");
    return (*this)[key];
  }
  void requireMap() const {
    if (!node.IsMap())
      fail("expected a map of key: value");
  }
  void requireSequence() const {
    if (!node.IsSequence())
      fail("expected a list");
  }
  /// Rejects keys outside `allowed` (typos must not be silently ignored).
  void allowOnly(std::initializer_list<const char *> allowed) const {
    requireMap();
    for (auto it = node.begin(); it != node.end(); ++it) {
      if (!it->first.IsScalar())
        Item{it->first, path, file}.fail("a key must be a plain word, not a list or a map");
      const std::string key = it->first.Scalar();
      bool ok = false;
      for (const char *a : allowed)
        ok = ok || key == a;
      if (!ok) {
        std::string list;
        for (const char *a : allowed)
          list += std::string(list.empty() ? "" : ", ") + a;
        Item{it->first, path, file}.fail("unknown key '" + key + "' (allowed: " + list + ")");
      }
    }
  }
  double number() const {
    if (!node.IsScalar())
      fail("expected a number");
    try {
      const double v = node.as<double>();
      if (!std::isfinite(v))
        fail("expected a finite number");
      return v;
    } catch (const YAML::Exception &) {
      fail("expected a number, found '" + node.Scalar() + "'");
    }
  }
  double positive() const {
    const double v = number();
    if (!(v > 0.0))
      fail("must be positive");
    return v;
  }
  int integer() const {
    if (!node.IsScalar())
      fail("expected an integer");
    try {
      return node.as<int>();
    } catch (const YAML::Exception &) {
      fail("expected an integer, found '" + node.Scalar() + "'");
    }
  }
  std::string string() const {
    if (!node.IsScalar())
      fail("expected a string");
    return node.Scalar();
  }
  bool boolean() const {
    try {
      return node.as<bool>();
    } catch (const YAML::Exception &) {
      fail("expected true or false");
    }
  }
  std::array<double, 2> pair() const {
    if (!node.IsSequence() || node.size() != 2)
      fail("expected a list of two numbers [x, y]");
    return {at(0).number(), at(1).number()};
  }
  std::array<int, 2> intPair() const {
    if (!node.IsSequence() || node.size() != 2)
      fail("expected a list of two integers");
    return {at(0).integer(), at(1).integer()};
  }
  /// One of the listed words.
  std::string choice(std::initializer_list<const char *> options) const {
    const std::string v = string();
    std::string list;
    for (const char *o : options) {
      if (v == o)
        return v;
      list += std::string(list.empty() ? "" : ", ") + o;
    }
    fail("unknown value '" + v + "' (expected one of: " + list + ")");
  }
};

ElementType elementType(const Item &i) {
  const std::string v = i.string();
  if (v == "quad4")
    return ElementType::Quad4;
  if (v == "quad8")
    return ElementType::Quad8;
  i.fail("unsupported element '" + v + "' (supported: quad4, quad8)");
}

/// Most load steps `increments` may ask for (their load factors are stored up front).
constexpr int kMaxIncrements = 1000000;

/// Most elements a mesh generator may build: connectivity indices are LocalIndex (8 per Quad8
/// element), and a generated mesh takes about 1 kB per element on the host while it is built.
double maxGeneratedElements() {
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
  return 2.0e4; // fuzz targets: one input stays within the fuzzer's memory and time limits
#else
  const double index = std::numeric_limits<LocalIndex>::max() / 8.0;
  const double pages = static_cast<double>(sysconf(_SC_PHYS_PAGES));
  const double pageSize = static_cast<double>(sysconf(_SC_PAGE_SIZE));
  return pages > 0 && pageSize > 0 ? std::min(index, pages * pageSize / 1024.0) : index;
#endif
}

/// Refuses generator divisions that would build `elements` elements beyond maxGeneratedElements,
/// before anything is allocated.
void checkGeneratedSize(const Item &divisions, double elements) {
  const double limit = maxGeneratedElements();
  if (elements > limit) {
    std::ostringstream s;
    s << "these divisions make " << elements << " elements, more than the " << limit
      << " a generated mesh may have (index range and memory)";
    divisions.fail(s.str());
  }
}

std::string joinPath(const std::string &base, const std::string &file) {
  if (file.empty() || file[0] == '/' || base.empty())
    return file;
  return base + "/" + file;
}

/// How far a node of one body may lie inside an element of another at the start, as a fraction
/// of that element's diameter: straight edges cut a circle of the other body as chords, by
/// (chord length) x (angle in radians) / 8, about 0.03 of the chord at 15 degrees, while a
/// misplaced body goes deep.
constexpr double kOverlapTolerance = 0.1;
/// How far a node may start inside a rigid obstacle, as a fraction of its body's size (the
/// diagonal of its bounding box): rounding of nodes placed on the obstacle's circle or line.
constexpr double kPenetrationTolerance = 1e-4;

/// Refuses bodies that overlap at the start: a node of one body strictly inside an element of
/// another (touching along a contact interface is fine).
void checkBodiesApart(const Item &list, const std::vector<MeshBody> &bodies, const Mesh &mesh) {
  std::vector<LocalIndex> nodeStart{0}, elementStart{0};
  for (const auto &b : bodies) {
    nodeStart.push_back(nodeStart.back() + b.mesh.numNodes());
    elementStart.push_back(elementStart.back() + b.mesh.numElements());
  }
  const auto o = findOverlap(mesh, nodeStart, elementStart, kOverlapTolerance);
  if (!o)
    return;
  auto partOf = [](const std::vector<LocalIndex> &start, LocalIndex k) {
    return static_cast<std::size_t>(std::upper_bound(start.begin(), start.end(), k) -
                                    start.begin() - 1);
  };
  const std::size_t bn = partOf(nodeStart, o->node), be = partOf(elementStart, o->element);
  std::ostringstream msg;
  msg << "body '" << bodies[bn].name << "' overlaps body '" << bodies[be].name
      << "' at the start: node " << mesh.nodeIds[o->node] << " (node "
      << bodies[bn].mesh.nodeIds[o->node - nodeStart[bn]] << " of '" << bodies[bn].name
      << "') lies inside element " << mesh.elementIds[o->element] << " (element "
      << bodies[be].mesh.elementIds[o->element - elementStart[be]] << " of '" << bodies[be].name
      << "'), " << o->depth << " of that element's diameter from its edges (tolerance "
      << kOverlapTolerance << "); bodies may touch but not overlap: check their offsets and sizes";
  list.at(bn).fail(msg.str());
}

/// Refuses a rigid obstacle that starts inside the body of its contact boundary: the deepest node
/// of that body (every node connected to the boundary) penetrating it by more than
/// kPenetrationTolerance of the body's size.
void checkObstacleOutside(const Item &c, const ContactSpec &s, const Mesh &mesh) {
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

Mesh readMesh(const Item &m, const std::string &baseDir, bool body = false) {
  if (!body && m.has("bodies")) {
    // Several bodies, each a mesh of its own (file or generator) moved by its offset.
    m.allowOnly({"bodies"});
    const Item list = m["bodies"];
    list.requireSequence();
    if (list.node.size() == 0)
      list.fail("expected at least one body");
    std::vector<MeshBody> bodies;
    for (std::size_t i = 0; i < list.node.size(); ++i) {
      const Item b = list.at(i);
      b.requireMap();
      MeshBody mb;
      mb.name = b.required("name").string();
      if (mb.name.empty() || mb.name.find('.') != std::string::npos)
        b["name"].fail("a body name must be non-empty and contain no '.'");
      for (const auto &o : bodies)
        if (o.name == mb.name)
          b["name"].fail("the body name '" + mb.name + "' is used twice");
      if (b.has("offset")) {
        const auto off = b["offset"].pair();
        mb.offset[0] = off[0];
        mb.offset[1] = off[1];
      }
      mb.mesh = readMesh(b, baseDir, true);
      if (!bodies.empty() && mb.mesh.elementType != bodies.front().mesh.elementType)
        b.fail("every body needs the same element type as the first one");
      bodies.push_back(std::move(mb));
    }
    Mesh mesh = mergeMeshes(bodies);
    validateMesh(mesh);
    for (const auto &b : bodies)
      for (const auto &w : b.mesh.warnings)
        mesh.warnings.push_back("body '" + b.name + "': " + w);
    checkBodiesApart(list, bodies, mesh);
    return mesh;
  }
  if (body)
    m.allowOnly({"name", "offset", "file", "generator", "element"});
  else
    m.allowOnly({"file", "generator", "element", "bodies"});
  if (m.has("file") == m.has("generator"))
    m.fail("give exactly one of 'file' or 'generator'" +
           std::string(body ? "" : " (or a list of 'bodies')"));
  Mesh mesh;
  if (m.has("file")) {
    const std::string path = joinPath(baseDir, m["file"].string());
    try {
      openInputFile(path, "mesh file");
    } catch (const InputError &e) {
      m["file"].fail(e.what());
    }
    mesh = readGmsh(path);
    if (m.has("element")) {
      const ElementType want = elementType(m["element"]);
      if (want != mesh.elementType)
        m["element"].fail(std::string("the mesh file has ") +
                          (mesh.elementType == ElementType::Quad8 ? "quad8" : "quad4") +
                          " elements but the problem asks for " + m["element"].string());
    }
  } else {
    if (m.has("element"))
      m["element"].fail("for a generator, give 'element' inside 'generator'");
    const Item g = m["generator"];
    g.requireMap();
    const std::string type =
        g.required("type").choice({"rectangle", "quarter_annulus", "plate_with_hole",
                                   "quarter_disk", "half_disk", "pinned_plate"});
    const ElementType et = g.has("element") ? elementType(g["element"]) : ElementType::Quad4;
    try {
      if (type == "rectangle") {
        g.allowOnly({"type", "element", "size", "divisions", "origin", "grading"});
        const auto size = g.required("size").pair();
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 1.0 * div[0] * div[1]);
        const auto origin = g.has("origin") ? g["origin"].pair() : std::array<double, 2>{0, 0};
        const auto grading =
            g.has("grading") ? g["grading"].pair() : std::array<double, 2>{1.0, 1.0};
        mesh = rectangleMesh(size[0], size[1], div[0], div[1], et, origin[0], origin[1], grading[0],
                             grading[1]);
      } else if (type == "quarter_annulus") {
        g.allowOnly({"type", "element", "inner_radius", "outer_radius", "divisions", "grading"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 1.0 * div[0] * div[1]);
        mesh = quarterAnnulusMesh(g.required("inner_radius").number(),
                                  g.required("outer_radius").number(), div[0], div[1], et,
                                  g.has("grading") ? g["grading"].number() : 1.0);
      } else if (type == "plate_with_hole") {
        g.allowOnly({"type", "element", "hole_radius", "width", "height", "divisions", "grading"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 2.0 * div[0] * div[1]);
        mesh = plateWithHoleMesh(g.required("hole_radius").number(), g.required("width").number(),
                                 g.required("height").number(), div[0], div[1], et,
                                 g.has("grading") ? g["grading"].number() : 1.0);
      } else if (type == "half_disk") {
        g.allowOnly({"type", "element", "radius", "divisions"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 2.0 * div[0] * div[0] + 4.0 * div[0] * div[1]);
        mesh = halfDiskMesh(g.required("radius").number(), div[0], div[1], et);
      } else if (type == "pinned_plate") {
        g.allowOnly({"type", "element", "hole_radius", "half_width", "end_distance", "length",
                     "divisions", "grading"});
        const Item d = g.required("divisions");
        if (!d.node.IsSequence() || d.node.size() != 4)
          d.fail("expected four integers [around the hole per 60 degrees, radial, end block, "
                 "far block]");
        const std::array<double, 4> n{1.0 * d.at(0).integer(), 1.0 * d.at(1).integer(),
                                      1.0 * d.at(2).integer(), 1.0 * d.at(3).integer()};
        checkGeneratedSize(d, 3 * n[0] * n[1] + n[0] * (n[2] + n[3]));
        mesh =
            pinnedPlateMesh(g.required("hole_radius").number(), g.required("half_width").number(),
                            g.required("end_distance").number(), g.required("length").number(),
                            d.at(0).integer(), d.at(1).integer(), d.at(2).integer(),
                            d.at(3).integer(), et, g.has("grading") ? g["grading"].number() : 1.0);
      } else {
        g.allowOnly({"type", "element", "radius", "divisions", "grading"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 1.0 * div[0] * div[0] + 2.0 * div[0] * div[1]);
        const auto grading =
            g.has("grading") ? g["grading"].pair() : std::array<double, 2>{1.0, 1.0};
        mesh = quarterDiskMesh(g.required("radius").number(), div[0], div[1], et, grading[0],
                               grading[1]);
      }
    } catch (const GeneratorError &e) { // the keys' own errors above carry their location already
      g.fail(e.what());
    }
  }
  validateMesh(mesh);
  return mesh;
}

ModelSpec readModel(const Item &m) {
  m.allowOnly({"formulation", "analysis", "thickness", "geometric_nonlinearity", "compliance",
               "stabilization", "stress_element", "mixed_form", "stress_update", "elastic_law"});
  ModelSpec s;
  if (m.has("formulation"))
    s.formulation = m["formulation"].choice({"displacement", "mixed"}) == "mixed"
                        ? Formulation::Mixed
                        : Formulation::Displacement;
  for (const char *key : {"compliance", "stabilization", "stress_element"})
    if (m.has(key) && s.formulation != Formulation::Mixed)
      m[key].fail(std::string(key) + " applies to formulation: mixed only");
  if (m.has("compliance"))
    s.mixed.compliance = m["compliance"].choice({"consistent", "lumped"}) == "lumped"
                             ? ComplianceMass::Lumped
                             : ComplianceMass::Consistent;
  if (m.has("stabilization")) {
    s.mixed.stabilization = m["stabilization"].number();
    if (!(s.mixed.stabilization >= 0.0 && s.mixed.stabilization < 1.0))
      m["stabilization"].fail("stabilization must lie in [0, 1) (0: the report's model)");
  }
  if (m.has("stress_element"))
    s.stressElement = elementType(m["stress_element"]);
  if (m.has("analysis"))
    s.analysis = m["analysis"].choice({"plane_stress", "plane_strain"}) == "plane_strain"
                     ? PlaneAnalysis::PlaneStrain
                     : PlaneAnalysis::PlaneStress;
  if (m.has("thickness"))
    s.thickness = m["thickness"].positive();
  if (m.has("geometric_nonlinearity")) {
    s.geometricNonlinearity = m["geometric_nonlinearity"].boolean();
    if (s.geometricNonlinearity && s.formulation == Formulation::Mixed)
      for (const char *key : {"compliance", "stress_element"})
        if (m.has(key))
          m[key].fail(std::string(key) + " applies to the linear mixed model's Schur solver; the "
                                         "geometrically nonlinear mixed model uses the "
                                         "consistent M and equal-order interpolation");
  }
  const bool nonlinearMixed = s.geometricNonlinearity && s.formulation == Formulation::Mixed;
  for (const char *key : {"mixed_form", "stress_update"})
    if (m.has(key) && !nonlinearMixed)
      m[key].fail(std::string(key) + " applies to formulation: mixed with "
                                     "geometric_nonlinearity: true only");
  if (nonlinearMixed && !m.has("stabilization"))
    s.mixed.stabilization = 0.0; // the report's model unless asked otherwise
  if (m.has("mixed_form"))
    s.mixedForm = m["mixed_form"].choice({"current", "incremental"}) == "incremental"
                      ? MixedForm::Incremental
                      : MixedForm::Current;
  if (m.has("elastic_law")) {
    if (!s.geometricNonlinearity || s.formulation != Formulation::Displacement)
      m["elastic_law"].fail("elastic_law applies to formulation: displacement with "
                            "geometric_nonlinearity: true only");
    s.elasticLaw = m["elastic_law"].choice({"almansi", "saint_venant_kirchhoff"}) == "almansi"
                       ? ElasticLaw::Almansi
                       : ElasticLaw::SaintVenantKirchhoff;
  }
  if (m.has("stress_update")) {
    if (s.mixedForm != MixedForm::Incremental)
      m["stress_update"].fail("stress_update applies to mixed_form: incremental only");
    s.stressUpdate = m["stress_update"].choice({"projected", "nodal_average"}) == "nodal_average"
                         ? StressUpdate::NodalAverage
                         : StressUpdate::Projected;
  }
  return s;
}

MaterialSpec readMaterial(const Item &m, PlaneAnalysis analysis) {
  MaterialSpec s;
  s.line = m.line();
  m.requireMap();
  s.region = m.required("region").string();
  s.type = m.required("type").choice({"isotropic", "orthotropic", "anisotropic"});
  const double deg = m.has("angle") ? m["angle"].number() : 0.0;
  const double theta = deg * M_PI / 180.0;
  if (s.type == "isotropic") {
    m.allowOnly({"region", "type", "E", "nu"});
    s.youngs = m.required("E").positive();
    s.poisson = m.required("nu").number();
    if (!(s.poisson > -1.0 && s.poisson < 0.5))
      m["nu"].fail("Poisson's ratio must lie in (-1, 0.5)");
    s.stiffness = isotropicStiffness(s.youngs, s.poisson, analysis);
  } else if (s.type == "orthotropic") {
    m.allowOnly({"region", "type", "E1", "E2", "E3", "G12", "nu12", "nu13", "nu23", "angle"});
    OrthotropicConstants k{};
    k.e1 = m.required("E1").positive();
    k.e2 = m.required("E2").positive();
    k.g12 = m.required("G12").positive();
    k.nu12 = m.required("nu12").number();
    if (analysis == PlaneAnalysis::PlaneStrain) {
      k.e3 = m.required("E3").positive();
      k.nu13 = m.required("nu13").number();
      k.nu23 = m.required("nu23").number();
    } else { // out-of-plane constants do not enter plane stress
      k.e3 = m.has("E3") ? m["E3"].positive() : k.e2;
      k.nu13 = m.has("nu13") ? m["nu13"].number() : 0.0;
      k.nu23 = m.has("nu23") ? m["nu23"].number() : 0.0;
    }
    s.stiffness = orthotropicStiffness(k, analysis, theta);
  } else {
    m.allowOnly({"region", "type", "C11", "C12", "C16", "C22", "C26", "C66", "angle"});
    PlaneMatrix c{};
    c.m[0][0] = m.required("C11").number();
    c.m[0][1] = c.m[1][0] = m.required("C12").number();
    c.m[0][2] = c.m[2][0] = m.has("C16") ? m["C16"].number() : 0.0;
    c.m[1][1] = m.required("C22").number();
    c.m[1][2] = c.m[2][1] = m.has("C26") ? m["C26"].number() : 0.0;
    c.m[2][2] = m.required("C66").number();
    s.stiffness = rotateStiffness(c, theta);
  }
  if (!isPositiveDefinite(s.stiffness))
    m.fail("the material's constitutive matrix is not positive definite (check the constants)");
  return s;
}

/// The document's content (parseProblem turns what yaml-cpp throws on a node into an InputError).
Problem parseDocument(const std::string &yamlText, const std::string &name,
                      const std::string &baseDirectory) {
  Problem p;
  p.file = name;
  YAML::Node root;
  try {
    root = YAML::Load(yamlText);
  } catch (const YAML::ParserException &e) {
    throw InputError(name + ":" + std::to_string(e.mark.line + 1) + ":" +
                     std::to_string(e.mark.column + 1) + ": malformed YAML: " + e.msg);
  }
  detail::checkDuplicateKeys(root, name);
  const Item top{root, "", &p.file};
  if (!root.IsMap())
    top.fail("a problem file is a YAML map with keys mesh, model, materials, ...");
  top.allowOnly({"mesh", "model", "materials", "boundary_conditions", "loads", "contact", "hybrid",
                 "steps", "solver", "output", "verification", "title"});

  p.mesh = readMesh(top.required("mesh"), baseDirectory);
  if (top.has("model")) {
    const Item m = top["model"];
    p.model = readModel(m);
    if (p.model.formulation == Formulation::Mixed) {
      try {
        checkMixedPairing(p.mesh.elementType, p.model.stressElement.value_or(p.mesh.elementType));
        if (p.model.mixed.compliance == ComplianceMass::Lumped &&
            massLumping(p.mesh.elementType) != MassLumping::RowSum)
          throw InputError("compliance: lumped is not available for quad8 elements (their "
                           "positive HRZ lumping fails the constant-stress patch test); use "
                           "compliance: consistent");
      } catch (const InputError &e) {
        m.fail(e.what());
      }
    }
  }

  // Materials: one per region, every region covered.
  const Item mats = top.required("materials");
  if (!mats.node.IsNull()) // an empty list reads as null: then every region lacks a material
    mats.requireSequence();
  for (std::size_t i = 0; i < mats.node.size(); ++i) {
    const Item m = mats.at(i);
    MaterialSpec s = readMaterial(m, p.model.analysis);
    if (p.mesh.regionIndex(s.region) < 0) {
      std::string known;
      for (const auto &r : p.mesh.regionNames)
        known += " " + r;
      m["region"].fail("unknown region '" + s.region + "' (mesh regions:" + known + ")");
    }
    for (const auto &o : p.materials)
      if (o.region == s.region)
        m["region"].fail("region '" + s.region + "' already has a material");
    p.materials.push_back(s);
  }
  for (const auto &r : p.mesh.regionNames) {
    bool found = false;
    for (const auto &m : p.materials)
      found = found || m.region == r;
    if (!found)
      mats.fail("region '" + r + "' has no material");
  }

  // A named set that exists but holds nothing (an empty Gmsh physical group): what acts on it
  // would act on nothing.
  auto checkNotEmpty = [&](const Item &i, const std::string &target) {
    if (p.mesh.nodesOf(target).empty())
      i.fail(std::string(p.mesh.hasBoundary(target) ? "boundary '" : "node set '") + target +
             "' is empty (" + (p.mesh.hasBoundary(target) ? "no edges" : "no nodes") +
             " in the mesh): it would act on nothing");
  };
  auto checkTarget = [&](const Item &i, const std::string &target) {
    if (!p.mesh.hasBoundary(target) && !p.mesh.hasNodeSet(target)) {
      i.fail("unknown boundary or node set '" + target + "' (mesh has: " + p.mesh.namedSets() +
             ")");
    }
    checkNotEmpty(i, target);
  };

  const Item bcs = top.required("boundary_conditions");
  if (!bcs.node.IsNull())
    bcs.requireSequence();
  for (std::size_t i = 0; i < bcs.node.size(); ++i) {
    const Item b = bcs.at(i);
    b.allowOnly({"boundary", "node_set", "ux", "uy"});
    if (b.has("boundary") == b.has("node_set"))
      b.fail("give exactly one of 'boundary' or 'node_set'");
    DirichletSpec d;
    d.line = b.line();
    const Item t = b.has("boundary") ? b["boundary"] : b["node_set"];
    d.target = t.string();
    checkTarget(t, d.target);
    if (b.has("ux"))
      d.ux = b["ux"].number();
    if (b.has("uy"))
      d.uy = b["uy"].number();
    if (!d.ux && !d.uy)
      b.fail("a boundary condition needs 'ux' and/or 'uy'");
    p.dirichlet.push_back(d);
  }
  if (p.dirichlet.empty())
    bcs.fail("no Dirichlet condition anywhere: the body is free to move as a rigid body");
  detail::checkDirichletConflicts(p.mesh, p.dirichlet, p.file, p.mesh.warnings);

  if (top.has("loads")) {
    const Item loads = top["loads"];
    loads.requireSequence();
    for (std::size_t i = 0; i < loads.node.size(); ++i) {
      const Item l = loads.at(i);
      l.allowOnly({"boundary", "node_set", "region", "traction", "pressure", "force", "body_force",
                   "follower"});
      LoadSpec s;
      s.line = l.line();
      const int kinds =
          l.has("traction") + l.has("pressure") + l.has("force") + l.has("body_force");
      if (kinds != 1)
        l.fail("give exactly one of 'traction', 'pressure', 'force' or 'body_force'");
      if (l.has("traction") || l.has("pressure")) {
        const Item t = l.required("boundary");
        s.target = t.string();
        if (!p.mesh.hasBoundary(s.target))
          t.fail("unknown boundary '" + s.target + "' (tractions and pressures act on boundaries)");
        checkNotEmpty(t, s.target);
        if (l.has("traction")) {
          s.kind = LoadKind::Traction;
          s.vector = l["traction"].pair();
        } else {
          s.kind = LoadKind::Pressure;
          s.pressure = l["pressure"].number();
        }
      } else if (l.has("force")) {
        const Item t = l.has("node_set") ? l["node_set"] : l.required("boundary");
        s.target = t.string();
        checkTarget(t, s.target);
        s.kind = LoadKind::Force;
        s.vector = l["force"].pair();
      } else {
        const Item t = l.required("region");
        s.target = t.string();
        if (p.mesh.regionIndex(s.target) < 0)
          t.fail("unknown region '" + s.target + "'");
        if (std::count(p.mesh.elementRegion.begin(), p.mesh.elementRegion.end(),
                       p.mesh.regionIndex(s.target)) == 0)
          t.fail("region '" + s.target +
                 "' is empty (no elements): the body force would act on "
                 "nothing");
        s.kind = LoadKind::BodyForce;
        s.vector = l["body_force"].pair();
      }
      if (l.has("follower")) {
        if (s.kind != LoadKind::Pressure)
          l["follower"].fail("follower applies to pressures only (tractions, forces and body "
                             "forces are dead loads)");
        if (!p.model.geometricNonlinearity)
          l["follower"].fail("follower pressure needs model: geometric_nonlinearity: true");
        s.follower = l["follower"].boolean();
      }
      p.loads.push_back(s);
    }
  }

  if (top.has("contact")) {
    const Item list = top["contact"];
    list.requireSequence();
    if (p.model.formulation != Formulation::Displacement && !p.model.geometricNonlinearity)
      list.fail("contact with formulation: mixed needs geometric_nonlinearity: true (the "
                "iterating driver has the mixed model's finite kinematics only)");
    for (std::size_t i = 0; i < list.node.size(); ++i) {
      const Item c = list.at(i);
      ContactSpec s;
      s.line = c.line();
      s.type = c.required("type").choice({"rigid_circle", "rigid_half_plane", "node_to_segment"});
      if (s.type == "node_to_segment") {
        c.allowOnly({"type", "contactor", "target", "friction"});
        for (const char *key : {"contactor", "target"}) {
          const Item b = c.required(key);
          if (!p.mesh.hasBoundary(b.string()))
            b.fail("unknown boundary '" + b.string() + "' (mesh has: " + p.mesh.namedSets() + ")");
          checkNotEmpty(b, b.string());
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
      const Item b = c.required("boundary");
      s.boundary = b.string();
      if (!p.mesh.hasBoundary(s.boundary))
        b.fail("unknown boundary '" + s.boundary + "' (mesh has: " + p.mesh.namedSets() + ")");
      checkNotEmpty(b, s.boundary);
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
      if (c.has("drive")) {
        const Item d = c["drive"];
        d.requireMap();
        d.allowOnly({"displacement", "force"});
        // Per component either a displacement or a force (the other list holds null there).
        std::array<int, 2> given{0, 0};
        for (const char *key : {"displacement", "force"}) {
          if (!d.has(key))
            continue;
          const Item v = d[key];
          if (!v.node.IsSequence() || v.node.size() != 2)
            v.fail("expected a list of two entries [x, y] (numbers, or null for a component "
                   "given by the other list)");
          const bool force = std::string(key) == "force";
          for (int i = 0; i < 2; ++i) {
            if (v.at(i).node.IsNull())
              continue;
            ++given[i];
            (force ? s.driveForce : s.driveDisplacement)[i] = v.at(i).number();
            s.forceDriven[i] = force;
          }
        }
        for (int i = 0; i < 2; ++i)
          if (given[i] != 1)
            d.fail(std::string("component ") + (i == 0 ? "x" : "y") +
                   " of the drive must be given exactly once, as a displacement or as a force "
                   "(write null in the other list)");
      }
      p.contact.push_back(s);
    }
  }

  if (top.has("hybrid")) {
    const Item h = top["hybrid"];
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
    checkNotEmpty(h["boundary"], s.boundary);
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

  if (top.has("steps")) {
    const Item s = top["steps"];
    if (p.hybrid)
      for (const char *key : {"increments", "load_factors"})
        if (s.has(key))
          s[key].fail("the steps of a hybrid run come from its measurement file");
    s.allowOnly({"increments", "load_factors", "iteration", "tolerance", "residual_tolerance",
                 "max_iterations", "max_cuts", "tangent"});
    for (const char *key :
         {"iteration", "tolerance", "residual_tolerance", "max_iterations", "max_cuts", "tangent"})
      if (s.has(key) && !p.model.geometricNonlinearity && p.contact.empty() && !p.hybrid)
        s[key].fail(std::string(key) +
                    " applies to geometrically nonlinear or contact analyses (model: "
                    "geometric_nonlinearity: true, or a contact: section); linear steps are single "
                    "solves");
    auto &n = p.nonlinear;
    if (s.has("iteration")) {
      const std::string v = s["iteration"].choice({"newton", "modified_newton", "none"});
      n.method = v == "none"              ? IterationMethod::None
                 : v == "modified_newton" ? IterationMethod::ModifiedNewton
                                          : IterationMethod::Newton;
    }
    if (s.has("tangent")) {
      if (p.model.formulation != Formulation::Displacement)
        s["tangent"].fail("tangent applies to formulation: displacement (the mixed model always "
                          "iterates with its exact Jacobian)");
      p.tangent = s["tangent"].choice({"exact", "report"}) == "report" ? TangentKind::Report
                                                                       : TangentKind::Exact;
      if (p.tangent == TangentKind::Report &&
          p.model.elasticLaw == ElasticLaw::SaintVenantKirchhoff)
        s["tangent"].fail("tangent: report is the Almansi law's K^L + K^sigma; with elastic_law: "
                          "saint_venant_kirchhoff use the exact tangent");
    }
    if (s.has("tolerance"))
      n.tolerance = s["tolerance"].positive();
    if (s.has("residual_tolerance"))
      n.residualTolerance = s["residual_tolerance"].positive();
    if (s.has("max_iterations")) {
      n.maxIterations = s["max_iterations"].integer();
      if (n.maxIterations < 1)
        s["max_iterations"].fail("must be at least 1");
    }
    if (s.has("max_cuts")) {
      n.maxCuts = s["max_cuts"].integer();
      if (n.maxCuts < 0)
        s["max_cuts"].fail("must be 0 or more");
    }
    if (s.has("increments") && s.has("load_factors"))
      s.fail("give 'increments' or 'load_factors', not both");
    if (s.has("increments")) {
      const int n = s["increments"].integer();
      if (n < 1)
        s["increments"].fail("must be at least 1");
      if (n > kMaxIncrements)
        s["increments"].fail("at most " + std::to_string(kMaxIncrements) + " increments");
      p.loadFactors.clear();
      for (int k = 1; k <= n; ++k)
        p.loadFactors.push_back(static_cast<double>(k) / n);
    } else if (s.has("load_factors")) {
      const Item f = s["load_factors"];
      f.requireSequence();
      if (f.node.size() == 0)
        f.fail("needs at least one load factor");
      p.loadFactors.clear();
      for (std::size_t k = 0; k < f.node.size(); ++k)
        p.loadFactors.push_back(f.at(k).number());
    }
  }

  if (p.hybrid) {
    // One step per measured step; the measured values are prescribed as they are at each step.
    const std::size_t n = p.hybrid->steps.size();
    p.loadFactors.clear();
    for (std::size_t k = 1; k <= n; ++k)
      p.loadFactors.push_back(static_cast<double>(k) / n);
    if (p.model.formulation == Formulation::Mixed && !p.model.geometricNonlinearity)
      top["hybrid"].fail("a hybrid run with formulation: mixed needs geometric_nonlinearity: true "
                         "(the iterating driver has the mixed model's finite kinematics only)");
  }
  const bool nonlinearMixed =
      p.model.geometricNonlinearity && p.model.formulation == Formulation::Mixed;
  if (nonlinearMixed)
    p.solver.type = LinearSolverType::Direct;
  if (top.has("solver")) {
    const Item s = top["solver"];
    s.allowOnly({"type", "tolerance", "max_iterations", "strong_threshold", "aggressive_levels",
                 "print_level", "krylov", "preconditioner", "inner_tolerance",
                 "interpolation_max_elements", "nodal_coarsening", "method",
                 "stress_block_tolerance"});
    for (const char *key : {"method", "stress_block_tolerance"})
      if (s.has(key) && !nonlinearMixed)
        s[key].fail(std::string(key) +
                    " applies to the geometrically nonlinear mixed model's solver: amg only");
    if (s.has("method"))
      p.model.mixedNewton.method = s["method"].choice({"block_triangular", "schur"}) == "schur"
                                       ? MixedNewtonSolver::Schur
                                       : MixedNewtonSolver::BlockTriangular;
    if (s.has("stress_block_tolerance"))
      p.model.mixedNewton.preconditionerTolerance = s["stress_block_tolerance"].positive();
    for (const char *key : {"krylov", "preconditioner", "inner_tolerance"}) {
      if (s.has(key) && p.model.formulation != Formulation::Mixed)
        s[key].fail(std::string(key) + " applies to formulation: mixed only");
      if (s.has(key) && nonlinearMixed)
        s[key].fail(std::string(key) + " applies to the linear mixed model's Schur solver only");
    }
    if (s.has("krylov"))
      p.model.mixed.krylov =
          s["krylov"].choice({"cg", "gmres"}) == "gmres" ? KrylovMethod::Gmres : KrylovMethod::Cg;
    if (s.has("preconditioner")) {
      const std::string v = s["preconditioner"].choice({"auto", "lumped_schur", "stiffness"});
      p.model.mixed.preconditioner = v == "stiffness"      ? SchurPreconditioner::Stiffness
                                     : v == "lumped_schur" ? SchurPreconditioner::LumpedSchur
                                                           : SchurPreconditioner::Auto;
    }
    if (s.has("inner_tolerance"))
      p.model.mixed.innerTolerance = s["inner_tolerance"].positive();
    if (s.has("type")) {
      p.solver.type = s["type"].choice({"amg", "direct"}) == "direct" ? LinearSolverType::Direct
                                                                      : LinearSolverType::Amg;
    }
    if (s.has("tolerance"))
      p.solver.tolerance = s["tolerance"].positive();
    // Counts: an iteration limit below 1 would "converge" without iterating.
    auto count = [&](const char *key, int least) {
      const int v = s[key].integer();
      if (v < least)
        s[key].fail("must be at least " + std::to_string(least));
      return v;
    };
    if (s.has("max_iterations"))
      p.solver.maxIterations = count("max_iterations", 1);
    if (s.has("strong_threshold")) {
      p.solver.strongThreshold = s["strong_threshold"].number();
      if (!(p.solver.strongThreshold >= 0.0 && p.solver.strongThreshold < 1.0))
        s["strong_threshold"].fail("the AMG strength threshold must lie in [0, 1)");
    }
    if (s.has("aggressive_levels"))
      p.solver.aggressiveLevels = count("aggressive_levels", 0);
    if (s.has("print_level"))
      p.solver.printLevel = count("print_level", 0);
    if (s.has("interpolation_max_elements"))
      p.solver.interpolationMaxElements = count("interpolation_max_elements", 0);
    if (s.has("nodal_coarsening"))
      p.solver.nodalCoarsening = s["nodal_coarsening"].boolean();
  }

  if (!p.contact.empty() && p.model.formulation == Formulation::Mixed &&
      p.solver.type != LinearSolverType::Direct)
    top["solver"]["type"].fail("contact with the mixed model needs type: direct in this version");

  if (top.has("output")) {
    const Item o = top["output"];
    o.allowOnly({"directory", "hdf5"});
    if (o.has("directory"))
      p.outputDirectory = o["directory"].string();
    if (o.has("hdf5"))
      p.writeHdf5 = o["hdf5"].boolean();
  }

  if (top.has("verification")) {
    const Item v = top["verification"];
    v.requireMap();
    auto &s = p.verification;
    s.type = v.required("type").choice({"lame_cylinder", "cantilever"});
    if (v.has("tolerance"))
      s.tolerance = v["tolerance"].positive();
    if (s.type == "lame_cylinder") {
      v.allowOnly({"type", "tolerance", "inner_radius", "outer_radius", "inner_pressure",
                   "outer_pressure"});
      s.innerRadius = v.required("inner_radius").positive();
      s.outerRadius = v.required("outer_radius").positive();
      s.innerPressure = v.required("inner_pressure").number();
      s.outerPressure = v.has("outer_pressure") ? v["outer_pressure"].number() : 0.0;
    } else {
      v.allowOnly({"type", "tolerance", "length", "height", "load", "tip"});
      s.length = v.required("length").positive();
      s.height = v.required("height").positive();
      s.load = v.required("load").number();
      s.tipNodeSet = v.required("tip").string();
      checkTarget(v["tip"], s.tipNodeSet);
    }
    if (p.materials.size() != 1 || p.materials[0].type != "isotropic")
      v.fail("closed-form verification needs a single isotropic material");
    if (p.model.geometricNonlinearity)
      v.fail("the closed forms of verification are linear; run without geometric_nonlinearity "
             "(the nonlinear cantilever is checked by examples/cantilever_study.py and the "
             "validation tests)");
  }
  return p;
}

} // namespace

Problem parseProblem(const std::string &yamlText, const std::string &name,
                     const std::string &baseDirectory) {
  try {
    return parseDocument(yamlText, name, baseDirectory);
  } catch (const YAML::Exception &e) {
    // A node of an unexpected kind that a check above let through: still an input error.
    throw InputError(name + ":" + std::to_string(e.mark.line + 1) + ":" +
                     std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
}

Problem readProblem(const std::string &path) {
  // A problem file is a few kB; the cap keeps a mistaken argument (a mesh, a data dump) from being
  // read whole before YAML refuses it.
  constexpr std::size_t kMaxProblemBytes = std::size_t(64) << 20;
  const std::string text = readInputFile(path, "problem file", kMaxProblemBytes);
  const auto slash = path.find_last_of('/');
  const std::string base = slash == std::string::npos ? "" : path.substr(0, slash);
  return parseProblem(text, path, base);
}

} // namespace mixcon
