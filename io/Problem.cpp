// YAML problem-file reader (yaml-cpp). Every map is checked against its allowed keys; every error
// names file:line:column and the key path (e.g. "materials[1].E").
// The sections are read in io/ProblemMesh.cpp, io/ProblemModel.cpp, io/ProblemContact.cpp and
// io/ProblemAnalysis.cpp (io/ProblemReader.hpp); this file holds the document's order and the
// boundary conditions and loads.
#include <io/Problem.hpp>
#include <io/ProblemChecks.hpp>
#include <io/ProblemReader.hpp>
#include <mesh/GmshReader.hpp>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <sstream>

namespace mixcon {

namespace detail {

ElementType elementType(const YamlItem &i) {
  const std::string v = i.string();
  if (v == "quad4")
    return ElementType::Quad4;
  if (v == "quad8")
    return ElementType::Quad8;
  if (v == "hex8")
    return ElementType::Hex8;
  if (v == "hex20")
    return ElementType::Hex20;
  if (v == "tet4")
    return ElementType::Tet4;
  if (v == "tet10")
    return ElementType::Tet10;
  i.fail("unsupported element '" + v + "' (supported: quad4, quad8, hex8, hex20, tet4, tet10)");
}

std::string joinPath(const std::string &base, const std::string &file) {
  if (file.empty() || file[0] == '/' || base.empty())
    return file;
  return base + "/" + file;
}

void checkNotEmpty(const Mesh &mesh, const YamlItem &i, const std::string &target) {
  if (mesh.nodesOf(target).empty())
    i.fail(std::string(mesh.hasBoundary(target) ? "boundary '" : "node set '") + target +
           "' is empty (" + (mesh.hasBoundary(target) ? "no edges" : "no nodes") +
           " in the mesh): it would act on nothing");
}

void checkTarget(const Mesh &mesh, const YamlItem &i, const std::string &target) {
  if (!mesh.hasBoundary(target) && !mesh.hasNodeSet(target)) {
    i.fail("unknown boundary or node set '" + target + "' (mesh has: " + mesh.namedSets() + ")");
  }
  checkNotEmpty(mesh, i, target);
}

DirichletSpec readDirichlet(const YamlItem &b, const Mesh &mesh, bool stage) {
  const int dim = mesh.dim();
  if (dim == 2 && b.has("uz"))
    b["uz"].fail("uz applies to 3D meshes; this mesh is 2D");
  std::vector<const char *> keys{"boundary", "node_set", "ux", "uy"};
  if (dim == 3)
    keys.push_back("uz");
  if (stage)
    keys.push_back("release");
  b.allowOnly(keys);
  if (b.has("boundary") == b.has("node_set"))
    b.fail("give exactly one of 'boundary' or 'node_set'");
  DirichletSpec d;
  d.line = b.line();
  const YamlItem t = b.has("boundary") ? b["boundary"] : b["node_set"];
  d.target = t.string();
  checkTarget(mesh, t, d.target);
  if (b.has("ux"))
    d.ux = b["ux"].number();
  if (b.has("uy"))
    d.uy = b["uy"].number();
  if (b.has("uz"))
    d.uz = b["uz"].number();
  if (b.has("release")) {
    // release: true (every component), or a list of component names
    const YamlItem r = b["release"];
    const char *names[3] = {"ux", "uy", "uz"};
    if (r.node.IsScalar()) {
      if (!r.boolean())
        r.fail("release: true frees every component; to keep a support, leave release out");
      for (int c = 0; c < dim; ++c)
        d.release[c] = true;
    } else {
      r.requireSequence();
      for (std::size_t k = 0; k < r.node.size(); ++k) {
        const std::string c =
            dim == 3 ? r.at(k).choice({"ux", "uy", "uz"}) : r.at(k).choice({"ux", "uy"});
        d.release[c == "ux" ? 0 : c == "uy" ? 1 : 2] = true;
      }
    }
    for (int c = 0; c < dim; ++c)
      if (d.release[c] && b.has(names[c]))
        b[names[c]].fail(std::string("component ") + names[c] +
                         " is both released and prescribed by this entry");
  }
  const bool released = d.release[0] || d.release[1] || d.release[2];
  if (!d.ux && !d.uy && !d.uz && !released)
    b.fail(std::string(dim == 2 ? "a boundary condition needs 'ux' and/or 'uy'"
                                : "a boundary condition needs one or more of 'ux', 'uy', 'uz'") +
           (stage ? " (or 'release')" : ""));
  return d;
}

LoadSpec readLoad(const YamlItem &l, const Problem &p) {
  l.allowOnly({"boundary", "node_set", "region", "traction", "pressure", "force", "body_force",
               "follower"});
  LoadSpec s;
  s.line = l.line();
  const int kinds = l.has("traction") + l.has("pressure") + l.has("force") + l.has("body_force");
  if (kinds != 1)
    l.fail("give exactly one of 'traction', 'pressure', 'force' or 'body_force'");
  if (l.has("traction") || l.has("pressure")) {
    const YamlItem t = l.required("boundary");
    s.target = t.string();
    if (!p.mesh.hasBoundary(s.target))
      t.fail("unknown boundary '" + s.target + "' (tractions and pressures act on boundaries)");
    checkNotEmpty(p.mesh, t, s.target);
    if (l.has("traction")) {
      s.kind = LoadKind::Traction;
      s.vector = l["traction"].vector(p.mesh.dim());
    } else {
      s.kind = LoadKind::Pressure;
      s.pressure = l["pressure"].number();
    }
  } else if (l.has("force")) {
    const YamlItem t = l.has("node_set") ? l["node_set"] : l.required("boundary");
    s.target = t.string();
    checkTarget(p.mesh, t, s.target);
    s.kind = LoadKind::Force;
    s.vector = l["force"].vector(p.mesh.dim());
  } else {
    const YamlItem t = l.required("region");
    s.target = t.string();
    if (p.mesh.regionIndex(s.target) < 0)
      t.fail("unknown region '" + s.target + "'");
    if (std::count(p.mesh.elementRegion.begin(), p.mesh.elementRegion.end(),
                   p.mesh.regionIndex(s.target)) == 0)
      t.fail("region '" + s.target +
             "' is empty (no elements): the body force would act on "
             "nothing");
    s.kind = LoadKind::BodyForce;
    s.vector = l["body_force"].vector(p.mesh.dim());
  }
  if (l.has("follower")) {
    if (s.kind != LoadKind::Pressure)
      l["follower"].fail("follower applies to pressures only (tractions, forces and body "
                         "forces are dead loads)");
    if (!p.model.geometricNonlinearity)
      l["follower"].fail("follower pressure needs model: geometric_nonlinearity: true");
    s.follower = l["follower"].boolean();
  }
  return s;
}

} // namespace detail

namespace {

using detail::YamlItem;

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
  const YamlItem top{root, "", &p.file};
  if (!root.IsMap())
    top.fail("a problem file is a YAML map with keys mesh, model, materials, ...");
  top.allowOnly({"mesh", "model", "materials", "boundary_conditions", "loads", "contact", "hybrid",
                 "steps", "stages", "solver", "output", "verification", "title"});

  p.mesh = detail::readMesh(top.required("mesh"), baseDirectory);
  if (top.has("model"))
    p.model = detail::readModel(top["model"], p.mesh.elementType);
  if (p.mesh.dim() == 3) // 3D runs so far: the displacement model without contact (issue 17)
    for (const char *key : {"contact", "hybrid"})
      if (top.has(key))
        top[key].fail(std::string(key) + " is 2D only so far; 3D meshes run the displacement "
                                         "model without contact (issue 17)");
  detail::readMaterials(top, p);

  const YamlItem bcs = top.required("boundary_conditions");
  if (!bcs.node.IsNull())
    bcs.requireSequence();
  for (std::size_t i = 0; i < bcs.node.size(); ++i)
    p.dirichlet.push_back(detail::readDirichlet(bcs.at(i), p.mesh, false));
  if (p.dirichlet.empty())
    bcs.fail("no Dirichlet condition anywhere: the body is free to move as a rigid body");
  detail::checkDirichletConflicts(p.mesh, p.dirichlet, p.file, p.mesh.warnings);

  if (top.has("loads")) {
    const YamlItem loads = top["loads"];
    loads.requireSequence();
    for (std::size_t i = 0; i < loads.node.size(); ++i)
      p.loads.push_back(detail::readLoad(loads.at(i), p));
  }

  if (top.has("contact"))
    detail::readContact(top["contact"], p);
  if (top.has("hybrid"))
    detail::readHybrid(top, p, baseDirectory);
  detail::readSteps(top, p);
  detail::readStages(top, p);
  if (detail::mixedInIteratingDriver(p) && !p.model.geometricNonlinearity && top.has("model")) {
    // The linear mixed model with contact or stages runs in the iterating driver with small
    // displacements: the consistent M and equal-order stresses; its own operator keys do not
    // apply there.
    detail::refuseLinearMixedKeys(
        top["model"], " applies to the linear mixed model without contact or stages; with them "
                      "it runs in the iterating driver (consistent M, equal-order stresses, "
                      "solver keys as the geometrically nonlinear mixed model's)");
  }
  detail::readSolver(top, p);

  if (top.has("output")) {
    const YamlItem o = top["output"];
    o.allowOnly({"directory", "hdf5"});
    if (o.has("directory"))
      p.outputDirectory = o["directory"].string();
    if (o.has("hdf5"))
      p.writeHdf5 = o["hdf5"].boolean();
  }

  if (top.has("verification"))
    detail::readVerification(top["verification"], p);
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
