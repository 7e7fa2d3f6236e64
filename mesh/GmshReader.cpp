// Gmsh 4.1 ASCII reader ($MeshFormat, $PhysicalNames, $Entities, $Nodes, $Elements): meshes of
// quadrangles (2D) or of 8-node or 20-node hexahedra or 4-node or 10-node tetrahedra (3D).
// Layer: mesh.
#include <mesh/GmshReader.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <array>
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
  case 15:
    return "point";
  case 1:
    return "2-node line";
  case 8:
    return "3-node line";
  case 3:
    return "4-node quadrangle";
  case 16:
    return "8-node quadrangle";
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
  case 6:
    return "6-node prism";
  case 7:
    return "5-node pyramid";
  case 11:
    return "10-node tetrahedron";
  case 12:
    return "27-node hexahedron";
  case 17:
    return "20-node hexahedron";
  default:
    return "element";
  }
}

/// Gmsh element types of the volume elements mixcon reads: 8-node and 20-node hexahedra, 4-node
/// and 10-node tetrahedra; and of the triangles that are the tetrahedra's faces.
constexpr long kGmshHex8 = 5;
constexpr long kGmshHex20 = 17;
constexpr long kGmshTet4 = 4;
constexpr long kGmshTet10 = 11;
constexpr long kGmshTri3 = 2;
constexpr long kGmshTri6 = 9;

/// Internal (VTK, core/ElementTraits.hpp Tet10) node a of a 10-node tetrahedron is Gmsh's node
/// kTet10FromGmsh[a]. Gmsh numbers the mid-edge nodes by its edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1
/// (Gmsh manual, "High-order elements"), VTK by 0-1, 1-2, 2-0, 0-3, 1-3, 2-3: the last two swap.
constexpr int kTet10FromGmsh[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};

bool isGmshTet(long type) { return type == kGmshTet4 || type == kGmshTet10; }

/// Internal (VTK, core/ElementTraits.hpp Hex20) node a of a 20-node hexahedron is Gmsh's node
/// kHex20FromGmsh[a]. Both number the corners alike; Gmsh numbers the mid-edge nodes by its edge
/// list 0-1, 0-3, 0-4, 1-2, 1-5, 2-3, 2-6, 3-7, 4-5, 4-7, 5-6, 6-7 (Gmsh manual, "Node
/// ordering"), VTK by 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7, 7-4, 0-4, 1-5, 2-6, 3-7.
constexpr int kHex20FromGmsh[20] = {0,  1, 2,  3,  4,  5,  6,  7,  8,  11,
                                    13, 9, 16, 18, 19, 17, 10, 12, 14, 15};

/// Dimension of the supported element types (point, 2- and 3-node lines, quadrangles,
/// hexahedra).
int gmshDimension(long type) {
  return type == 15                                                   ? 0
         : type == 1 || type == 8                                     ? 1
         : type == kGmshHex8 || type == kGmshHex20 || isGmshTet(type) ? 3
                                                                      : 2;
}

int gmshNodesPerElement(long type) {
  switch (type) {
  case 15:
    return 1;
  case 1:
    return 2;
  case 8:
    return 3;
  case kGmshTri3:
    return 3;
  case 3:
  case kGmshTet4:
    return 4;
  case kGmshTri6:
    return 6;
  case kGmshTet10:
    return 10;
  case 16:
  case kGmshHex8:
    return 8;
  case kGmshHex20:
    return 20;
  default:
    return -1;
  }
}

struct LineElement {
  int entity;
  long id;
  std::vector<long> nodes;
  int line;
};
struct PointElement {
  int entity;
  long node;
};

/// What the sections of a file hold, before the mesh is assembled from it. The quadrangles are
/// read into the mesh's connectivity (they are its elements in 2D, its boundary faces in 3D).
struct GmshContent {
  std::map<std::pair<int, int>, std::string> physicalNames;        // (dim, tag) -> name
  std::map<std::pair<int, int>, std::vector<int>> entityPhysicals; // (dim, entity) -> tags
  std::unordered_map<long, LocalIndex> nodeIndex;
  std::vector<double> xyz; ///< 3 coordinates per node, as read
  std::vector<LineElement> lines;
  std::vector<PointElement> points;
  std::vector<int> elementEntity; ///< surface entity of each quadrangle
  std::vector<int> quadLine;      ///< file line of each quadrangle
  long quadType = 0; ///< Gmsh type of the 2D elements (quadrangles, or triangles as tet faces)
  long hexType = 0;  ///< Gmsh type of the volume elements: hexahedra or tetrahedra (0: none)
  std::vector<LocalIndex> hexConnectivity; ///< in the internal node order
  std::vector<long> hexIds;
  std::vector<int> hexEntity;
  int zLine = 0;  ///< line of the first node with z != 0 (0: none)
  long zNode = 0; ///< its tag

  /// Names of the physical groups of entity (dim, entity): their names, or their tags where
  /// $PhysicalNames names none.
  std::vector<std::string> groupNames(int dim, int entity) const {
    std::vector<std::string> names;
    auto it = entityPhysicals.find({dim, entity});
    if (it == entityPhysicals.end())
      return names;
    for (int tag : it->second) {
      auto pn = physicalNames.find({dim, tag});
      names.push_back(pn != physicalNames.end() ? pn->second : std::to_string(tag));
    }
    return names;
  }
};

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

namespace {

/// The message prefix "file:line: ".
std::string at(const std::string &name, int line) {
  return name + ":" + std::to_string(line) + ": ";
}

/// A 2D mesh: the quadrangles are the elements, 1D groups boundaries (their line elements matched
/// to element edges), 0D groups node sets.
/// The nodes of the point elements (0D physical groups) as node sets, in both dimensions.
void addPointNodeSets(Mesh &mesh, const GmshContent &c, const std::string &name) {
  for (const auto &p : c.points) {
    auto names = c.groupNames(0, p.entity);
    auto it = c.nodeIndex.find(p.node);
    if (it == c.nodeIndex.end())
      throw InputError(name + ": point element references unknown node " + std::to_string(p.node));
    for (const auto &nm : names)
      mesh.nodeSets[nm].push_back(it->second);
  }
}

void assemblePlane(Mesh &mesh, GmshContent &c, const std::string &name) {
  mesh.elementType = c.quadType == 16 ? ElementType::Quad8 : ElementType::Quad4;
  mesh.nodesPerElement = c.quadType == 16 ? 8 : 4;
  mesh.coordinates.reserve(2 * (c.xyz.size() / 3));
  for (std::size_t n = 0; n < c.xyz.size() / 3; ++n) {
    mesh.coordinates.push_back(c.xyz[3 * n]);
    mesh.coordinates.push_back(c.xyz[3 * n + 1]);
  }
  std::vector<double>().swap(c.xyz); // the z column is not needed

  // Gmsh orients a plane surface's elements by its curve loop: a surface drawn clockwise gives
  // clockwise quadrangles. Planar elements have one right orientation, so reorder them (before
  // boundary edges are taken from the elements); inverted or folded ones stay for validateMesh.
  if (const LocalIndex flipped = orientCounterClockwise(mesh); flipped > 0)
    mesh.warnings.push_back(name + ": " + std::to_string(flipped) + " of " +
                            std::to_string(mesh.numElements()) +
                            " quadrangles had clockwise nodes (a surface whose curve loop runs "
                            "clockwise); their nodes were reordered to counter-clockwise");

  // Regions: the first physical group of each element's surface (or "surface_<tag>").
  for (std::size_t e = 0; e < c.elementEntity.size(); ++e) {
    auto names = c.groupNames(2, c.elementEntity[e]);
    const std::string region =
        names.empty() ? "surface_" + std::to_string(c.elementEntity[e]) : names.front();
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
  for (const auto &l : c.lines) {
    auto names = c.groupNames(1, l.entity);
    if (names.empty())
      continue;
    if (static_cast<int>(l.nodes.size()) != lineNodes)
      throw InputError(at(name, l.line) + "line element " + std::to_string(l.id) + " has " +
                       std::to_string(l.nodes.size()) + " nodes but the quadrangles need " +
                       std::to_string(lineNodes) + "-node edges");
    LocalIndex ends[2];
    for (int k = 0; k < 2; ++k) {
      auto it = c.nodeIndex.find(l.nodes[k]);
      if (it == c.nodeIndex.end())
        throw InputError(at(name, l.line) + "line element " + std::to_string(l.id) +
                         " references unknown node " + std::to_string(l.nodes[k]));
      ends[k] = it->second;
    }
    auto it = edgeOf.find({std::min(ends[0], ends[1]), std::max(ends[0], ends[1])});
    if (it == edgeOf.end())
      throw InputError(at(name, l.line) + "line element " + std::to_string(l.id) +
                       " of boundary '" + names.front() + "' is not an edge of any quadrangle");
    for (const auto &nm : names)
      mesh.boundaries[nm].push_back(it->second);
  }
  addPointNodeSets(mesh, c, name);
  // A named physical group without elements is kept, empty: a problem that uses it is then told
  // that it is empty rather than that it does not exist.
  for (const auto &[key, nm] : c.physicalNames) {
    if (key.first == 1 && !mesh.boundaries.count(nm))
      mesh.boundaries[nm];
    else if (key.first == 0 && !mesh.nodeSets.count(nm))
      mesh.nodeSets[nm];
  }
}

/// One face of a hexahedron or tetrahedron, keyed by its sorted corner nodes (a triangle's
/// padded with -1; the search table of the boundary faces).
struct SolidFace {
  std::array<LocalIndex, 4> key;
  BoundaryEdge side;
  bool operator<(const SolidFace &o) const { return key < o.key; }
};

/// True when the `n` corner nodes `q` run around the face in the same direction as the element's
/// side `s` (one is the other rotated), i.e. the face's normal points out of that element.
bool sameTurn(const Mesh &mesh, const BoundaryEdge &s, const std::array<LocalIndex, 4> &q, int n) {
  for (int shift = 0; shift < n; ++shift) {
    bool all = true;
    for (int k = 0; k < n && all; ++k)
      all = mesh.sideNode(s, k) == q[(k + shift) % n];
    if (all)
      return true;
  }
  return false;
}

/// The mid-edge node of side `s` (n corners) between its corners a and b (-1 when a-b is no
/// edge of it): the side's node n + m lies between its corners m and m + 1 (Hex20::sideNode,
/// Tet10::sideNode).
LocalIndex sideMidEdgeNode(const Mesh &mesh, const BoundaryEdge &s, int n, LocalIndex a,
                           LocalIndex b) {
  for (int m = 0; m < n; ++m) {
    const LocalIndex p = mesh.sideNode(s, m), q = mesh.sideNode(s, (m + 1) % n);
    if ((p == a && q == b) || (p == b && q == a))
      return mesh.sideNode(s, n + m);
  }
  return -1;
}

/// What a mesh of one volume element type takes: its element type, the Gmsh types of its faces
/// and edges, and the words for messages.
struct SolidKind {
  ElementType type;
  long faceType, lineType;
  const char *element, *elements, *face, *faces;
};

SolidKind solidKind(long gmshType) {
  switch (gmshType) {
  case kGmshHex20:
    return {ElementType::Hex20,
            16,
            8,
            "hexahedron",
            "20-node hexahedra",
            "quadrangle",
            "8-node quadrangles (type 16)"};
  case kGmshTet4:
    return {
        ElementType::Tet4,          kGmshTri3, 1, "tetrahedron", "4-node tetrahedra", "triangle",
        "3-node triangles (type 2)"};
  case kGmshTet10:
    return {
        ElementType::Tet10,         kGmshTri6, 8, "tetrahedron", "10-node tetrahedra", "triangle",
        "6-node triangles (type 9)"};
  default:
    return {ElementType::Hex8,
            3,
            1,
            "hexahedron",
            "8-node hexahedra",
            "quadrangle",
            "4-node quadrangles (type 3)"};
  }
}

/// A 3D mesh: the hexahedra or tetrahedra are the elements (volume groups are regions), the
/// quadrangles or triangles of surface groups are boundaries (each matched to the element face
/// with the same corner nodes; for 20-node hexahedra and 10-node tetrahedra, 8-node quadrangles
/// and 6-node triangles whose mid-edge nodes must be the face's), curve and point groups are node
/// sets (their nodes). Faces of surfaces without a physical group must still be element faces:
/// a mesh of volume elements takes no 2D elements.
void assembleSolid(Mesh &mesh, GmshContent &c, const std::string &name) {
  const SolidKind kind = solidKind(c.hexType);
  const bool quadratic = kind.type == ElementType::Hex20 || kind.type == ElementType::Tet10;
  if (c.quadType != 0 && c.quadType != kind.faceType && !c.quadLine.empty())
    throw InputError(at(name, c.quadLine.front()) + gmshTypeName(c.quadType) + "s (type " +
                     std::to_string(c.quadType) + ") in a mesh of " + kind.elements +
                     "; the faces of " + kind.elements + " are " + kind.faces);
  // Curves: 3-node lines with quadratic elements, 2-node lines with linear ones (one order).
  const std::size_t lineNodes = quadratic ? 3 : 2;
  for (const auto &l : c.lines)
    if (l.nodes.size() != lineNodes)
      throw InputError(at(name, l.line) + "line element " + std::to_string(l.id) + " has " +
                       std::to_string(l.nodes.size()) + " nodes in a mesh of " + kind.elements +
                       ", whose edges are " +
                       (quadratic ? "3-node lines (type 8)" : "2-node lines (type 1)") +
                       " (use one element order per mesh)");
  // The 2D elements read so far are faces: move them out of the element arrays.
  const std::vector<LocalIndex> quads = std::move(mesh.connectivity);
  const std::vector<long> quadIds = std::move(mesh.elementIds);
  const bool tet = kind.type == ElementType::Tet4 || kind.type == ElementType::Tet10;
  const int corners = tet ? 3 : 4; // of a face
  const std::size_t quadNodes = static_cast<std::size_t>(gmshNodesPerElement(kind.faceType));
  mesh.elementType = kind.type;
  mesh.nodesPerElement = dispatchElement(kind.type, [](auto t) { return decltype(t)::kNumNodes; });
  mesh.connectivity = std::move(c.hexConnectivity);
  mesh.elementIds = std::move(c.hexIds);
  mesh.coordinates = std::move(c.xyz);
  // No reorientation: a hexahedron has no single fix for a wrong node order (a mirrored one
  // differs from a twisted one); validateMesh names the element whose Jacobian is not positive.

  // Regions: the first physical group of each element's volume (or "volume_<tag>").
  for (int entity : c.hexEntity) {
    auto names = c.groupNames(3, entity);
    const std::string region = names.empty() ? "volume_" + std::to_string(entity) : names.front();
    int idx = mesh.regionIndex(region);
    if (idx < 0) {
      idx = static_cast<int>(mesh.regionNames.size());
      mesh.regionNames.push_back(region);
    }
    mesh.elementRegion.push_back(idx);
  }

  // Boundaries: each face element matched to the element faces with its corner nodes. A face
  // between two elements matches both; the one whose side turns like the face element is taken.
  if (!quads.empty()) {
    const int sides = dispatchElement(kind.type, [](auto t) { return decltype(t)::kNumSides; });
    std::vector<SolidFace> faces;
    faces.reserve(static_cast<std::size_t>(mesh.numElements()) * sides);
    for (LocalIndex e = 0; e < mesh.numElements(); ++e)
      for (int f = 0; f < sides; ++f) {
        SolidFace face{{-1, -1, -1, -1}, {e, f}};
        for (int k = 0; k < corners; ++k)
          face.key[k] = mesh.sideNode({e, f}, k);
        std::sort(face.key.begin(), face.key.end());
        faces.push_back(face);
      }
    std::sort(faces.begin(), faces.end());
    for (std::size_t q = 0; q < quadIds.size(); ++q) {
      const auto names = c.groupNames(2, c.elementEntity[q]);
      std::array<LocalIndex, 4> nodes{-1, -1, -1, -1}; // the corners
      const auto quad = quads.begin() + static_cast<std::ptrdiff_t>(quadNodes * q);
      std::copy(quad, quad + corners, nodes.begin());
      SolidFace probe{nodes, {0, 0}};
      std::sort(probe.key.begin(), probe.key.end());
      const auto [first, last] = std::equal_range(faces.begin(), faces.end(), probe);
      const std::string what =
          std::string(kind.face) + " element " + std::to_string(quadIds[q]) +
          (names.empty() ? " (surface " + std::to_string(c.elementEntity[q]) + ")"
                         : " of boundary '" + names.front() + "'");
      if (first == last) {
        const std::string noFace = " is not a face of any " + std::string(kind.element);
        if (!names.empty())
          throw InputError(at(name, c.quadLine[q]) + what + noFace);
        throw InputError(at(name, c.quadLine[q]) + what + noFace + "; in a mesh of " +
                         kind.elements + " " + kind.face +
                         "s are boundary faces only (mixed 2D and 3D elements are not supported)");
      }
      auto match = first;
      for (auto it = first; it != last; ++it)
        if (sameTurn(mesh, it->side, nodes, corners)) {
          match = it;
          break;
        }
      // A quadratic face's node n + m lies between its corners m and m + 1 (Gmsh's order, as
      // the internal one): it must be the element's mid-edge node of that edge.
      if (quadratic)
        for (int m = 0; m < corners; ++m) {
          const LocalIndex a = quad[m], b = quad[(m + 1) % corners], mid = quad[corners + m];
          const LocalIndex expected = sideMidEdgeNode(mesh, match->side, corners, a, b);
          if (mid != expected)
            throw InputError(at(name, c.quadLine[q]) + what + ": its mid-edge node " +
                             std::to_string(mesh.nodeId(mid)) + " (between nodes " +
                             std::to_string(mesh.nodeId(a)) + " and " +
                             std::to_string(mesh.nodeId(b)) + ") is not the " + kind.element +
                             "'s mid-edge node of that edge, " +
                             std::to_string(mesh.nodeId(expected)));
        }
      for (const auto &nm : names)
        mesh.boundaries[nm].push_back(match->side);
    }
  }

  // Node sets: the nodes of the curve and point groups, sorted.
  for (const auto &l : c.lines) {
    for (const auto &nm : c.groupNames(1, l.entity))
      for (long tag : l.nodes) {
        auto it = c.nodeIndex.find(tag);
        if (it == c.nodeIndex.end())
          throw InputError(at(name, l.line) + "line element " + std::to_string(l.id) +
                           " references unknown node " + std::to_string(tag));
        mesh.nodeSets[nm].push_back(it->second);
      }
  }
  addPointNodeSets(mesh, c, name);
  for (auto &[nm, nodes] : mesh.nodeSets) {
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  }
  // Named groups without elements are kept, empty (as in 2D).
  for (const auto &[key, nm] : c.physicalNames) {
    if (key.first == 2 && !mesh.boundaries.count(nm))
      mesh.boundaries[nm];
    else if ((key.first == 1 || key.first == 0) && !mesh.nodeSets.count(nm))
      mesh.nodeSets[nm];
  }
}

} // namespace

Mesh readGmsh(std::istream &in, const std::string &name) {
  Lexer lex(in, name);
  Mesh mesh;
  mesh.source = name;
  GmshContent c;
  bool sawFormat = false, sawNodes = false, sawElements = false;

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
        c.physicalNames[{lex.toInt(p[0]), lex.toInt(p[1])}] = nm;
      }
    } else if (section == "$Entities") {
      auto e0 = lex.expectLine("$Entities");
      lex.need(e0, 4, "$Entities counts");
      long counts[4];
      for (int d = 0; d < 4; ++d)
        counts[d] = lex.toCount(e0[d], kMaxCount, "number of entities");
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
            c.entityPhysicals[{d, tag}].push_back(std::abs(lex.toInt(e[physAt + 1 + k])));
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
        const long n = lex.toCount(bh[3], kMaxCount - static_cast<long>(mesh.nodeIds.size()),
                                   "number of nodes");
        std::vector<long> tags; // grown as read: the header's count drives no allocation
        for (long i = 0; i < n; ++i)
          tags.push_back(lex.toLong(lex.expectLine("$Nodes tags")[0]));
        for (long i = 0; i < n; ++i) {
          auto xyz = lex.expectLine("$Nodes coordinates");
          lex.need(xyz, parametric ? 4 : 3, "node coordinates");
          const double x = lex.toDouble(xyz[0]), y = lex.toDouble(xyz[1]), z = lex.toDouble(xyz[2]);
          // z != 0 is refused once the mesh turns out to be 2D (no hexahedra), at this line.
          if (std::abs(z) > 0.0 && c.zLine == 0) {
            c.zLine = lex.line();
            c.zNode = tags[i];
          }
          if (!c.nodeIndex.emplace(tags[i], static_cast<LocalIndex>(mesh.nodeIds.size())).second)
            lex.fail("duplicate node tag " + std::to_string(tags[i]));
          c.xyz.insert(c.xyz.end(), {x, y, z});
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
        if (dim == 3 && c.hexType != 0 && type != c.hexType)
          lex.fail("mixed volume element types: element type " + std::to_string(type) + " (" +
                   gmshTypeName(type) + ") after element type " + std::to_string(c.hexType) + " (" +
                   gmshTypeName(c.hexType) +
                   "); mixcon reads one volume element type per mesh, 8-node (type 5) or 20-node "
                   "(type 17) hexahedra or 4-node (type 4) or 10-node (type 11) tetrahedra");
        if (npe < 0)
          lex.fail(std::string("unsupported element type ") + std::to_string(type) + " (" +
                   gmshTypeName(type) +
                   "); mixcon reads 4-node (type 3) and 8-node (type 16) quadrangles, 8-node "
                   "(type 5) and 20-node (type 17) hexahedra and 4-node (type 4) and 10-node "
                   "(type 11) tetrahedra with 3-node (type 2) and 6-node (type 9) triangles "
                   "as their faces");
        if (gmshDimension(type) != dim)
          lex.fail("element type " + std::to_string(type) + " in a block of dimension " +
                   std::to_string(dim));
        if (dim == 2) {
          if (c.quadType != 0 && c.quadType != type)
            lex.fail(std::string("mixed 2D element types: ") + gmshTypeName(type) + "s after " +
                     gmshTypeName(c.quadType) +
                     "s (mixed 4-node and 8-node quadrangles, or quadrangles and triangles); use "
                     "one element type per mesh");
          c.quadType = type;
        } else if (dim == 3) {
          c.hexType = type;
        }
        for (long i = 0; i < n; ++i) {
          auto e = lex.expectLine("$Elements entry");
          lex.need(e, 1 + npe, "element");
          const long id = lex.toLong(e[0]);
          std::vector<long> nodes(npe);
          for (int a = 0; a < npe; ++a)
            nodes[a] = lex.toLong(e[1 + a]);
          if (dim >= 2) {
            std::vector<LocalIndex> &conn = dim == 2 ? mesh.connectivity : c.hexConnectivity;
            if (static_cast<long>(conn.size()) > kMaxCount - npe)
              lex.fail("too many elements (connectivity indices are " +
                       std::to_string(sizeof(LocalIndex) * 8) + "-bit)");
            for (int a = 0; a < npe; ++a) {
              // 20-node hexahedra and 10-node tetrahedra from Gmsh's node order to the internal
              // one.
              const long nt = nodes[type == kGmshHex20   ? kHex20FromGmsh[a]
                                    : type == kGmshTet10 ? kTet10FromGmsh[a]
                                                         : a];
              auto it = c.nodeIndex.find(nt);
              if (it == c.nodeIndex.end())
                lex.fail("element " + std::to_string(id) + " references unknown node " +
                         std::to_string(nt));
              conn.push_back(it->second);
            }
            if (dim == 2) {
              mesh.elementIds.push_back(id);
              c.elementEntity.push_back(entity);
              c.quadLine.push_back(lex.line());
            } else {
              c.hexIds.push_back(id);
              c.hexEntity.push_back(entity);
            }
          } else if (dim == 1) {
            c.lines.push_back({entity, id, nodes, lex.line()});
          } else {
            c.points.push_back({entity, nodes[0]});
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
  // The mesh's dimension is the highest element dimension present: 3 with volume elements.
  const bool solid = !c.hexIds.empty();
  // Triangles are faces of tetrahedra only (no triangle elements in 2D).
  if (!solid && (c.quadType == kGmshTri3 || c.quadType == kGmshTri6) && !c.quadLine.empty())
    throw InputError(at(name, c.quadLine.front()) + "unsupported element type " +
                     std::to_string(c.quadType) + " (" + gmshTypeName(c.quadType) +
                     ") in a mesh without tetrahedra; mixcon reads triangles only as the faces "
                     "of 4-node (type 4) or 10-node (type 11) tetrahedra");
  if (!solid && c.zLine > 0)
    throw InputError(at(name, c.zLine) + "node " + std::to_string(c.zNode) +
                     " has a non-zero z coordinate; mixcon meshes are planar (z = 0) unless "
                     "they are made of 8-node (type 5) or 20-node (type 17) hexahedra or 4-node "
                     "(type 4) or 10-node (type 11) tetrahedra");
  if (!sawFormat)
    throw InputError(name + ": not a Gmsh file (no $MeshFormat section)");
  if (!sawNodes || !sawElements)
    throw InputError(name + ": missing $Nodes or $Elements section");
  if (c.quadType == 0 && !solid)
    throw InputError(name + ": no quadrilateral elements (2D elements of type 3 or 16) and no "
                            "hexahedra or tetrahedra (3D elements of type 5, 17, 4 or 11)");
  if (solid)
    assembleSolid(mesh, c, name);
  else
    assemblePlane(mesh, c, name);
  mesh.finalizeIds();
  return mesh;
}

} // namespace mixcon
