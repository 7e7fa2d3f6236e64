// The mesh section of the problem file: a Gmsh file, a generator, or several bodies moved by their
// offsets and checked not to overlap (io/ProblemReader.hpp). Data flow: io (input side).
#include <io/ProblemReader.hpp>
#include <mesh/Generators.hpp>
#include <mesh/GmshReader.hpp>

#include <unistd.h>

#include <algorithm>
#include <limits>
#include <sstream>

namespace mixcon::detail {

namespace {

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
void checkGeneratedSize(const YamlItem &divisions, double elements) {
  const double limit = maxGeneratedElements();
  if (elements > limit) {
    std::ostringstream s;
    s << "these divisions make " << elements << " elements, more than the " << limit
      << " a generated mesh may have (index range and memory)";
    divisions.fail(s.str());
  }
}

/// How far a node of one body may lie inside an element of another at the start, as a fraction
/// of that element's diameter: straight edges cut a circle of the other body as chords, by
/// (chord length) x (angle in radians) / 8, about 0.03 of the chord at 15 degrees, while a
/// misplaced body goes deep.
constexpr double kOverlapTolerance = 0.1;

/// Refuses bodies that overlap at the start: a node of one body strictly inside an element of
/// another (touching along a contact interface is fine).
void checkBodiesApart(const YamlItem &list, const std::vector<MeshBody> &bodies, const Mesh &mesh) {
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

} // namespace

Mesh readMesh(const YamlItem &m, const std::string &baseDir, bool body) {
  if (!body && m.has("bodies")) {
    // Several bodies, each a mesh of its own (file or generator) moved by its offset.
    m.allowOnly({"bodies"});
    const YamlItem list = m["bodies"];
    list.requireSequence();
    if (list.node.size() == 0)
      list.fail("expected at least one body");
    std::vector<MeshBody> bodies;
    for (std::size_t i = 0; i < list.node.size(); ++i) {
      const YamlItem b = list.at(i);
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
      if (mb.mesh.dim() != 2)
        b.fail("several bodies are 2D only so far (contact between bodies is 2D; issue 17); "
               "body '" +
               mb.name + "' is a 3D mesh");
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
        m["element"].fail(std::string("the mesh file has ") + elementTypeName(mesh.elementType) +
                          " elements but the problem asks for " + m["element"].string());
    }
  } else {
    if (m.has("element"))
      m["element"].fail("for a generator, give 'element' inside 'generator'");
    const YamlItem g = m["generator"];
    g.requireMap();
    const std::string type = g.required("type").choice(
        {"rectangle", "quarter_annulus", "plate_with_hole", "quarter_disk", "half_disk",
         "pinned_plate", "box", "sphere_shell"});
    const bool solid = type == "box" || type == "sphere_shell";
    ElementType et = g.has("element") ? elementType(g["element"])
                     : solid          ? ElementType::Hex8
                                      : ElementType::Quad4;
    // A 2D generator with `extrude` makes hexahedra from its quadrilaterals: the element names the
    // result (hex8 from quad4, hex20 from quad8).
    const bool extruded = !solid && g.has("extrude");
    if (extruded) {
      if (g.has("element") && et != ElementType::Hex8 && et != ElementType::Hex20)
        g["element"].fail("an extruded mesh is made of hex8 (from quad4) or hex20 (from quad8) "
                          "elements");
      et = et == ElementType::Hex20 ? ElementType::Quad8 : ElementType::Quad4;
    }
    const auto allow = [&](std::initializer_list<const char *> keys) {
      std::vector<const char *> k(keys);
      if (!solid)
        k.push_back("extrude");
      g.allowOnly(k);
    };
    try {
      if (type == "box") {
        allow({"type", "element", "size", "divisions", "origin", "grading"});
        const auto size = g.required("size").vector(3);
        const YamlItem d = g.required("divisions");
        if (!d.node.IsSequence() || d.node.size() != 3)
          d.fail("expected a list of three integers [nx, ny, nz]");
        const std::array<int, 3> div{d.at(0).integer(), d.at(1).integer(), d.at(2).integer()};
        checkGeneratedSize(d, 1.0 * div[0] * div[1] * div[2]);
        const auto origin =
            g.has("origin") ? g["origin"].vector(3) : std::array<double, 3>{0.0, 0.0, 0.0};
        const auto grading =
            g.has("grading") ? g["grading"].vector(3) : std::array<double, 3>{1.0, 1.0, 1.0};
        mesh = boxMesh(size[0], size[1], size[2], div[0], div[1], div[2], et, origin[0], origin[1],
                       origin[2], grading[0], grading[1], grading[2]);
      } else if (type == "rectangle") {
        allow({"type", "element", "size", "divisions", "origin", "grading"});
        const auto size = g.required("size").pair();
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 1.0 * div[0] * div[1]);
        const auto origin = g.has("origin") ? g["origin"].pair() : std::array<double, 2>{0, 0};
        const auto grading =
            g.has("grading") ? g["grading"].pair() : std::array<double, 2>{1.0, 1.0};
        mesh = rectangleMesh(size[0], size[1], div[0], div[1], et, origin[0], origin[1], grading[0],
                             grading[1]);
      } else if (type == "sphere_shell") {
        allow({"type", "element", "inner_radius", "outer_radius", "divisions", "grading"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 3.0 * div[0] * div[0] * div[1]);
        mesh = sphereShellMesh(g.required("inner_radius").number(),
                               g.required("outer_radius").number(), div[0], div[1], et,
                               g.has("grading") ? g["grading"].number() : 1.0);
      } else if (type == "quarter_annulus") {
        allow({"type", "element", "inner_radius", "outer_radius", "divisions", "grading"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 1.0 * div[0] * div[1]);
        mesh = quarterAnnulusMesh(g.required("inner_radius").number(),
                                  g.required("outer_radius").number(), div[0], div[1], et,
                                  g.has("grading") ? g["grading"].number() : 1.0);
      } else if (type == "plate_with_hole") {
        allow({"type", "element", "hole_radius", "width", "height", "divisions", "grading"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 2.0 * div[0] * div[1]);
        mesh = plateWithHoleMesh(g.required("hole_radius").number(), g.required("width").number(),
                                 g.required("height").number(), div[0], div[1], et,
                                 g.has("grading") ? g["grading"].number() : 1.0);
      } else if (type == "half_disk") {
        allow({"type", "element", "radius", "divisions", "grading"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 2.0 * div[0] * div[0] + 4.0 * div[0] * div[1]);
        const auto grading =
            g.has("grading") ? g["grading"].pair() : std::array<double, 2>{1.0, 1.0};
        mesh = halfDiskMesh(g.required("radius").number(), div[0], div[1], et, grading[0],
                            grading[1]);
      } else if (type == "pinned_plate") {
        allow({"type", "element", "hole_radius", "half_width", "end_distance", "length",
               "divisions", "grading"});
        const YamlItem d = g.required("divisions");
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
        allow({"type", "element", "radius", "divisions", "grading"});
        const auto div = g.required("divisions").intPair();
        checkGeneratedSize(g["divisions"], 1.0 * div[0] * div[0] + 2.0 * div[0] * div[1]);
        const auto grading =
            g.has("grading") ? g["grading"].pair() : std::array<double, 2>{1.0, 1.0};
        mesh = quarterDiskMesh(g.required("radius").number(), div[0], div[1], et, grading[0],
                               grading[1]);
      }
      if (extruded) {
        const YamlItem x = g["extrude"];
        x.requireMap();
        x.allowOnly({"length", "divisions", "grading"});
        const int layers = x.required("divisions").integer();
        checkGeneratedSize(x["divisions"], 1.0 * mesh.numElements() * layers);
        mesh = extrudeMesh(mesh, x.required("length").positive(), layers,
                           x.has("grading") ? x["grading"].positive() : 1.0);
      }
    } catch (const GeneratorError &e) { // the keys' own errors above carry their location already
      g.fail(e.what());
    }
  }
  validateMesh(mesh);
  return mesh;
}
} // namespace mixcon::detail
