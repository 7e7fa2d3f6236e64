// Internals of the problem reader (io/Problem.cpp and the section readers io/ProblemMesh.cpp,
// io/ProblemModel.cpp, io/ProblemContact.cpp, io/ProblemAnalysis.cpp): a YAML node with its key
// path for "file:line:column: path: what" messages, and one reader per section of the problem file.
// Not part of the public API (it needs yaml-cpp). Data flow: io (input side).
#pragma once

#include <io/Problem.hpp>
#include <io/ProblemChecks.hpp>

#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

namespace mixcon::detail {

/// A YAML node with its path in the document, for messages.
struct YamlItem {
  YAML::Node node;
  std::string path;
  const std::string *file;

  [[noreturn]] void fail(const std::string &msg) const {
    std::ostringstream s;
    s << *file;
    const auto m = node.Mark();
    if (m.line >= 0)
      s << ":" << m.line + 1 << ":" << m.column + 1;
    s << ": " << (path.empty() ? "" : path + ": ") << clipQuoted(msg);
    throw InputError(s.str());
  }
  int line() const { return node.Mark().line + 1; }
  bool has(const char *key) const { return node.IsMap() && node[key]; }
  YamlItem operator[](const char *key) const {
    return YamlItem{node[key], path.empty() ? key : path + "." + key, file};
  }
  YamlItem at(std::size_t i) const {
    return YamlItem{node[i], path + "[" + std::to_string(i) + "]", file};
  }
  YamlItem required(const char *key) const {
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
    allowOnly(std::vector<const char *>(allowed));
  }
  void allowOnly(const std::vector<const char *> &allowed) const {
    requireMap();
    for (auto it = node.begin(); it != node.end(); ++it) {
      if (!it->first.IsScalar())
        YamlItem{it->first, path, file}.fail("a key must be a plain word, not a list or a map");
      const std::string key = it->first.Scalar();
      bool ok = false;
      for (const char *a : allowed)
        ok = ok || key == a;
      if (!ok) {
        std::string list;
        for (const char *a : allowed)
          list += std::string(list.empty() ? "" : ", ") + a;
        YamlItem{it->first, path, file}.fail("unknown key '" + key + "' (allowed: " + list + ")");
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
  /// A list of `dim` numbers (2: [x, y], 3: [x, y, z]) as three components (z = 0 in 2D).
  std::array<double, 3> vector(int dim) const {
    if (!node.IsSequence() || static_cast<int>(node.size()) != dim)
      fail(dim == 2 ? "expected a list of two numbers [x, y]"
                    : "expected a list of three numbers [x, y, z] (the mesh is 3D)");
    return {at(0).number(), at(1).number(), dim == 3 ? at(2).number() : 0.0};
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

/// The element type a key names (quad4 | quad8).
ElementType elementType(const YamlItem &i);

/// `file` resolved against the problem file's folder `base` (absolute paths stay).
std::string joinPath(const std::string &base, const std::string &file);

/// Refuses a named set that exists but holds nothing (an empty Gmsh physical group): what acts on
/// it would act on nothing.
void checkNotEmpty(const Mesh &mesh, const YamlItem &i, const std::string &target);

/// Refuses a name that is neither a boundary nor a node set of the mesh, or an empty one.
void checkTarget(const Mesh &mesh, const YamlItem &i, const std::string &target);

/// One boundary_conditions entry (`stage`: of a stage, where `release` is allowed).
DirichletSpec readDirichlet(const YamlItem &b, const Mesh &mesh, bool stage);

/// One loads entry.
LoadSpec readLoad(const YamlItem &l, const Problem &p);

/// A rigid obstacle's `drive` map: per component a displacement or a force.
void readDrive(const YamlItem &d, std::array<double, 2> &displacement, std::array<double, 2> &force,
               std::array<bool, 2> &forceDriven);

/// stages: the load history (io/ProblemStages.cpp); after steps and contact.
void readStages(const YamlItem &top, Problem &p);

/// mesh: one mesh from a file or a generator, or several bodies (io/ProblemMesh.cpp).
Mesh readMesh(const YamlItem &m, const std::string &baseDir, bool body = false);

/// model: the formulation and its options, with the mixed model's element checks against the
/// mesh's element type (io/ProblemModel.cpp).
ModelSpec readModel(const YamlItem &m, ElementType meshElement);
/// The mixed model runs in the iterating driver: geometrically nonlinear, or linear (small
/// displacements) with contact or stages (io/ProblemAnalysis.cpp).
bool mixedInIteratingDriver(const Problem &p);
/// Fails at the first of the linear mixed model's own operator keys (compliance, stress_element,
/// operators) that `m` has, with the message key + why.
void refuseLinearMixedKeys(const YamlItem &m, const std::string &why);

/// materials: one per region, every region covered (io/ProblemModel.cpp).
void readMaterials(const YamlItem &top, Problem &p);

/// contact: rigid obstacles or node-to-segment pairs (io/ProblemContact.cpp).
void readContact(const YamlItem &list, Problem &p);

/// hybrid: measured displacements on a boundary (io/ProblemContact.cpp).
void readHybrid(const YamlItem &top, Problem &p, const std::string &baseDirectory);

/// The iteration keys of `steps` (and of a stage) into `n`: iteration, tolerance,
/// residual_tolerance, max_iterations, max_cuts.
void readIterationKeys(const YamlItem &s, NonlinearOptions &n);

/// steps: load factors and the equilibrium iterations (io/ProblemAnalysis.cpp).
void readSteps(const YamlItem &top, Problem &p);

/// solver: the linear solver and the mixed model's solve settings (io/ProblemAnalysis.cpp).
void readSolver(const YamlItem &top, Problem &p);

/// verification: the closed form a run is checked against (io/ProblemAnalysis.cpp).
void readVerification(const YamlItem &v, Problem &p);

} // namespace mixcon::detail
