// Gmsh 4.1 ASCII reader: $MeshFormat, $PhysicalNames, $Entities, $Nodes, $Elements.
#include <mesh/GmshReader.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

namespace mixcon {

namespace {

/// Largest count a header may announce: node and connectivity indices are LocalIndex.
constexpr long kMaxCount = std::numeric_limits<LocalIndex>::max();

/// Line-oriented tokenizer that remembers the line number for messages.
class Lexer {
public:
  Lexer(std::istream &in, std::string name) : in_(in), name_(std::move(name)) {}

  /// Next non-empty line split into tokens; false at end of file.
  bool next(std::vector<std::string> &tokens) {
    std::string line;
    while (readInputLine(in_, line, name_, line_ + 1)) {
      ++line_;
      if (!line.empty() && line.back() == '\r')
        line.pop_back();
      std::istringstream s(line);
      tokens.clear();
      std::string t;
      while (s >> t)
        tokens.push_back(t);
      if (!tokens.empty())
        return true;
    }
    return false;
  }
  std::vector<std::string> expectLine(const char *what) {
    std::vector<std::string> t;
    if (!next(t))
      fail(std::string("unexpected end of file while reading ") + what);
    return t;
  }
  [[noreturn]] void fail(const std::string &msg) const {
    throw InputError(name_ + ":" + std::to_string(line_) + ": " + msg);
  }
  long toLong(const std::string &s) const {
    try {
      std::size_t pos = 0;
      long v = std::stol(s, &pos);
      if (pos != s.size())
        throw std::invalid_argument(s);
      return v;
    } catch (const std::exception &) {
      fail("expected an integer, found '" + clipValue(s) + "'");
    }
  }
  /// An integer within +-INT_MAX (entity and physical tags, dimensions; |v| is an int too).
  int toInt(const std::string &s) const {
    const long v = toLong(s);
    if (v < -std::numeric_limits<int>::max() || v > std::numeric_limits<int>::max())
      fail("integer " + s + " out of range");
    return static_cast<int>(v);
  }
  /// A count from a section header: 0 <= n <= most (the header drives allocation).
  long toCount(const std::string &s, long most, const char *what) const {
    const long v = toLong(s);
    if (v < 0 || v > most)
      fail(std::string(what) + " " + s + " out of range (0 to " + std::to_string(most) + ")");
    return v;
  }
  double toDouble(const std::string &s) const {
    try {
      std::size_t pos = 0;
      double v = std::stod(s, &pos);
      if (pos != s.size() || !std::isfinite(v))
        throw std::invalid_argument(s);
      return v;
    } catch (const std::exception &) {
      fail("expected a finite number, found '" + clipValue(s) + "'");
    }
  }
  void need(const std::vector<std::string> &t, std::size_t n, const char *what) const {
    if (t.size() < n)
      fail(std::string("too few fields in ") + what + " (expected " + std::to_string(n) + ")");
  }
  int line() const { return line_; }

private:
  std::istream &in_;
  std::string name_;
  int line_ = 0;
};

const char *gmshTypeName(long type) {
  switch (type) {
  case 2:
    return "3-node triangle";
  case 9:
    return "6-node triangle";
  case 10:
    return "9-node quadrangle";
  case 4:
    return "4-node tetrahedron";
  case 5:
    return "8-node hexahedron";
  default:
    return "element";
  }
}

/// Dimension of the supported element types (point, 2- and 3-node lines, quadrangles).
int gmshDimension(long type) { return type == 15 ? 0 : type == 1 || type == 8 ? 1 : 2; }

int gmshNodesPerElement(long type) {
  switch (type) {
  case 15:
    return 1;
  case 1:
    return 2;
  case 8:
    return 3;
  case 3:
    return 4;
  case 16:
    return 8;
  default:
    return -1;
  }
}

} // namespace

std::ifstream openInputFile(const std::string &path, const std::string &what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(path + ": cannot open the " + what + " (" + std::strerror(errno) + ")");
  if (!S_ISREG(st.st_mode)) {
    const char *kind = S_ISDIR(st.st_mode)                          ? "a directory"
                       : S_ISFIFO(st.st_mode)                       ? "a FIFO"
                       : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                       : S_ISSOCK(st.st_mode)                       ? "a socket"
                                                                    : "a special file";
    throw InputError(path + ": the " + what + " is " + kind + ", not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(path + ": cannot open the " + what);
  return in;
}

bool readInputLine(std::istream &in, std::string &line, const std::string &name, int lineNumber) {
  line.clear();
  std::istream::sentry ok(in, true);
  if (!ok)
    return false;
  std::streambuf *buf = in.rdbuf();
  for (;;) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return !line.empty();
    }
    if (c == '\n')
      return true;
    if (line.size() >= kMaxInputLine)
      throw InputError(name + ":" + std::to_string(lineNumber) + ": line longer than " +
                       std::to_string(kMaxInputLine) + " characters (not a text input file?)");
    line.push_back(static_cast<char>(c));
  }
}

std::string readInputFile(const std::string &path, const std::string &what, std::size_t maxBytes) {
  std::ifstream in = openInputFile(path, what);
  std::string text, line;
  for (int n = 1; readInputLine(in, line, path, n); ++n) {
    text += line;
    text += '\n';
    if (text.size() > maxBytes)
      throw InputError(path + ":" + std::to_string(n) + ": the " + what + " is larger than " +
                       std::to_string(maxBytes) + " bytes");
  }
  return text;
}

std::string clipValue(const std::string &value) {
  constexpr std::size_t kKeep = 77;
  return value.size() <= kKeep + 3 ? value : value.substr(0, kKeep) + "...";
}

Mesh readGmsh(const std::string &path) {
  std::ifstream in = openInputFile(path, "mesh file");
  return readGmsh(in, path);
}

Mesh readGmsh(std::istream &in, const std::string &name) {
  Lexer lex(in, name);
  Mesh mesh;
  mesh.source = name;

  std::map<std::pair<int, int>, std::string> physicalNames;        // (dim, tag) -> name
  std::map<std::pair<int, int>, std::vector<int>> entityPhysicals; // (dim, entity) -> tags
  std::unordered_map<long, LocalIndex> nodeIndex;
  struct LineElement {
    int entity;
    long id;
    std::vector<long> nodes;
    int line;
  };
  std::vector<LineElement> lines;
  struct PointElement {
    int entity;
    long node;
  };
  std::vector<PointElement> points;
  std::vector<int> elementEntity;
  bool sawFormat = false, sawNodes = false, sawElements = false;
  long quadType = 0;

  std::vector<std::string> t;
  // The header first: a file that does not start with $MeshFormat is refused at its first line
  // instead of being scanned to its end for one.
  if (!lex.next(t))
    throw InputError(name + ": empty file, not a Gmsh mesh (expected $MeshFormat first)");
  if (t[0] != "$MeshFormat")
    lex.fail("not a Gmsh file: expected $MeshFormat first, found '" + clipValue(t[0]) + "'");
  do {
    const std::string &section = t[0];
    if (section == "$MeshFormat") {
      auto f = lex.expectLine("$MeshFormat");
      lex.need(f, 3, "$MeshFormat");
      if (f[0] != "4.1")
        lex.fail("unsupported Gmsh format version " + f[0] + " (mixcon reads 4.1)");
      if (f[1] != "0")
        lex.fail("binary Gmsh files are not supported; save as ASCII (Mesh.Binary = 0)");
      sawFormat = true;
    } else if (section == "$PhysicalNames") {
      const long n =
          lex.toCount(lex.expectLine("$PhysicalNames")[0], kMaxCount, "number of physical names");
      for (long i = 0; i < n; ++i) {
        auto p = lex.expectLine("$PhysicalNames");
        lex.need(p, 3, "$PhysicalNames entry");
        std::string nm = p[2];
        for (std::size_t k = 3; k < p.size(); ++k)
          nm += " " + p[k];
        if (nm.size() >= 2 && nm.front() == '"' && nm.back() == '"')
          nm = nm.substr(1, nm.size() - 2);
        physicalNames[{lex.toInt(p[0]), lex.toInt(p[1])}] = nm;
      }
    } else if (section == "$Entities") {
      auto c = lex.expectLine("$Entities");
      lex.need(c, 4, "$Entities counts");
      long counts[4];
      for (int d = 0; d < 4; ++d)
        counts[d] = lex.toCount(c[d], kMaxCount, "number of entities");
      for (int d = 0; d < 4; ++d)
        for (long i = 0; i < counts[d]; ++i) {
          auto e = lex.expectLine("$Entities");
          // point: tag x y z nphys tags...; curve/surface/volume: tag 6 bbox nphys tags... nbound
          const std::size_t physAt = d == 0 ? 4 : 7;
          lex.need(e, physAt + 1, "$Entities entry");
          const int tag = lex.toInt(e[0]);
          const long np = lex.toCount(e[physAt], kMaxCount, "number of physical tags");
          lex.need(e, physAt + 1 + np, "$Entities entry");
          for (long k = 0; k < np; ++k)
            entityPhysicals[{d, tag}].push_back(std::abs(lex.toInt(e[physAt + 1 + k])));
        }
    } else if (section == "$Nodes") {
      auto h = lex.expectLine("$Nodes");
      lex.need(h, 4, "$Nodes header");
      const long blocks = lex.toCount(h[0], kMaxCount, "number of node blocks");
      for (long b = 0; b < blocks; ++b) {
        auto bh = lex.expectLine("$Nodes block");
        lex.need(bh, 4, "$Nodes block header");
        const bool parametric = lex.toLong(bh[2]) != 0;
        // Node indices are LocalIndex: the mesh holds at most kMaxCount nodes.
        const long n = lex.toCount(bh[3], kMaxCount - mesh.numNodes(), "number of nodes");
        std::vector<long> tags; // grown as read: the header's count drives no allocation
        for (long i = 0; i < n; ++i)
          tags.push_back(lex.toLong(lex.expectLine("$Nodes tags")[0]));
        for (long i = 0; i < n; ++i) {
          auto xyz = lex.expectLine("$Nodes coordinates");
          lex.need(xyz, parametric ? 4 : 3, "node coordinates");
          if (std::abs(lex.toDouble(xyz[2])) > 0.0)
            lex.fail("node " + std::to_string(tags[i]) +
                     " has a non-zero z coordinate; mixcon meshes are planar (z = 0)");
          if (!nodeIndex.emplace(tags[i], mesh.numNodes()).second)
            lex.fail("duplicate node tag " + std::to_string(tags[i]));
          mesh.coordinates.push_back(lex.toDouble(xyz[0]));
          mesh.coordinates.push_back(lex.toDouble(xyz[1]));
          mesh.nodeIds.push_back(tags[i]);
        }
      }
      sawNodes = true;
    } else if (section == "$Elements") {
      auto h = lex.expectLine("$Elements");
      lex.need(h, 4, "$Elements header");
      const long blocks = lex.toCount(h[0], kMaxCount, "number of element blocks");
      for (long b = 0; b < blocks; ++b) {
        auto bh = lex.expectLine("$Elements block");
        lex.need(bh, 4, "$Elements block header");
        const int dim = lex.toInt(bh[0]);
        const int entity = lex.toInt(bh[1]);
        const long type = lex.toLong(bh[2]);
        const long n = lex.toCount(bh[3], kMaxCount, "number of elements");
        const int npe = gmshNodesPerElement(type);
        if (npe < 0 || dim < 0 || dim > 2)
          lex.fail(std::string("unsupported element type ") + std::to_string(type) + " (" +
                   gmshTypeName(type) +
                   "); mixcon reads 4-node (type 3) and 8-node (type 16) quadrangles");
        if (gmshDimension(type) != dim)
          lex.fail("element type " + std::to_string(type) + " in a block of dimension " +
                   std::to_string(dim));
        if (dim == 2) {
          if (quadType != 0 && quadType != type)
            lex.fail("mixed 4-node and 8-node quadrangles; use one element order per mesh");
          quadType = type;
        }
        for (long i = 0; i < n; ++i) {
          auto e = lex.expectLine("$Elements entry");
          lex.need(e, 1 + npe, "element");
          const long id = lex.toLong(e[0]);
          std::vector<long> nodes(npe);
          for (int a = 0; a < npe; ++a)
            nodes[a] = lex.toLong(e[1 + a]);
          if (dim == 2) {
            if (static_cast<long>(mesh.connectivity.size()) > kMaxCount - npe)
              lex.fail("too many elements (connectivity indices are " +
                       std::to_string(sizeof(LocalIndex) * 8) + "-bit)");
            for (long nt : nodes) {
              auto it = nodeIndex.find(nt);
              if (it == nodeIndex.end())
                lex.fail("element " + std::to_string(id) + " references unknown node " +
                         std::to_string(nt));
              mesh.connectivity.push_back(it->second);
            }
            mesh.elementIds.push_back(id);
            elementEntity.push_back(entity);
          } else if (dim == 1) {
            lines.push_back({entity, id, nodes, lex.line()});
          } else {
            points.push_back({entity, nodes[0]});
          }
        }
      }
      sawElements = true;
    } else if (section.size() > 1 && section[0] == '$' && section.rfind("$End", 0) != 0) {
      // Skip sections mixcon does not use ($Periodic, $NodeData, ...).
      const std::string end = "$End" + section.substr(1);
      std::vector<std::string> s;
      while (lex.next(s) && s[0] != end) {
      }
    }
  } while (lex.next(t));
  if (!sawFormat)
    throw InputError(name + ": not a Gmsh file (no $MeshFormat section)");
  if (!sawNodes || !sawElements)
    throw InputError(name + ": missing $Nodes or $Elements section");
  if (quadType == 0)
    throw InputError(name + ": no quadrilateral elements (2D elements of type 3 or 16)");
  mesh.elementType = quadType == 16 ? ElementType::Quad8 : ElementType::Quad4;
  mesh.nodesPerElement = quadType == 16 ? 8 : 4;

  // Gmsh orients a plane surface's elements by its curve loop: a surface drawn clockwise gives
  // clockwise quadrangles. Planar elements have one right orientation, so reorder them (before
  // boundary edges are taken from the elements); inverted or folded ones stay for validateMesh.
  if (const LocalIndex flipped = orientCounterClockwise(mesh); flipped > 0)
    mesh.warnings.push_back(name + ": " + std::to_string(flipped) + " of " +
                            std::to_string(mesh.numElements()) +
                            " quadrangles had clockwise nodes (a surface whose curve loop runs "
                            "clockwise); their nodes were reordered to counter-clockwise");

  auto groupNames = [&](int dim, int entity) {
    std::vector<std::string> names;
    auto it = entityPhysicals.find({dim, entity});
    if (it == entityPhysicals.end())
      return names;
    for (int tag : it->second) {
      auto pn = physicalNames.find({dim, tag});
      names.push_back(pn != physicalNames.end() ? pn->second : std::to_string(tag));
    }
    return names;
  };

  // Regions: the first physical group of each element's surface (or "surface_<tag>").
  for (std::size_t e = 0; e < elementEntity.size(); ++e) {
    auto names = groupNames(2, elementEntity[e]);
    const std::string region =
        names.empty() ? "surface_" + std::to_string(elementEntity[e]) : names.front();
    int idx = mesh.regionIndex(region);
    if (idx < 0) {
      idx = static_cast<int>(mesh.regionNames.size());
      mesh.regionNames.push_back(region);
    }
    mesh.elementRegion.push_back(idx);
  }

  // Boundaries: match each physical line element to the element edge with the same end nodes.
  std::map<std::pair<LocalIndex, LocalIndex>, BoundaryEdge> edgeOf;
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int k = 0; k < 4; ++k) {
      const LocalIndex a = mesh.node(e, k), b = mesh.node(e, (k + 1) % 4);
      edgeOf[{std::min(a, b), std::max(a, b)}] = {e, k};
    }
  const int lineNodes = mesh.nodesPerEdge();
  for (const auto &l : lines) {
    auto names = groupNames(1, l.entity);
    if (names.empty())
      continue;
    if (static_cast<int>(l.nodes.size()) != lineNodes)
      throw InputError(name + ":" + std::to_string(l.line) + ": line element " +
                       std::to_string(l.id) + " has " + std::to_string(l.nodes.size()) +
                       " nodes but the quadrangles need " + std::to_string(lineNodes) +
                       "-node edges");
    LocalIndex ends[2];
    for (int k = 0; k < 2; ++k) {
      auto it = nodeIndex.find(l.nodes[k]);
      if (it == nodeIndex.end())
        throw InputError(name + ":" + std::to_string(l.line) + ": line element " +
                         std::to_string(l.id) + " references unknown node " +
                         std::to_string(l.nodes[k]));
      ends[k] = it->second;
    }
    auto it = edgeOf.find({std::min(ends[0], ends[1]), std::max(ends[0], ends[1])});
    if (it == edgeOf.end())
      throw InputError(name + ":" + std::to_string(l.line) + ": line element " +
                       std::to_string(l.id) + " of boundary '" + names.front() +
                       "' is not an edge of any quadrangle");
    for (const auto &nm : names)
      mesh.boundaries[nm].push_back(it->second);
  }
  for (const auto &p : points) {
    auto names = groupNames(0, p.entity);
    auto it = nodeIndex.find(p.node);
    if (it == nodeIndex.end())
      throw InputError(name + ": point element references unknown node " + std::to_string(p.node));
    for (const auto &nm : names)
      mesh.nodeSets[nm].push_back(it->second);
  }
  // A named physical group without elements is kept, empty: a problem that uses it is then told
  // that it is empty rather than that it does not exist.
  for (const auto &[key, nm] : physicalNames) {
    if (key.first == 1 && !mesh.boundaries.count(nm))
      mesh.boundaries[nm];
    else if (key.first == 0 && !mesh.nodeSets.count(nm))
      mesh.nodeSets[nm];
  }
  mesh.finalizeIds();
  return mesh;
}

} // namespace mixcon
