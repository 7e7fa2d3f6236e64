// 3D meshes of Hex8 elements (issue 17): the box generator and the Gmsh 4.1 reader's hexahedra,
// checked against plain host references (trilinear Jacobians integrated by 2x2x2 Gauss, face
// normals from cross products). Layer under test: mesh.
#include <mesh/Generators.hpp>
#include <mesh/GmshReader.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iomanip>
#include <set>
#include <sstream>
#include <string>

using namespace mixcon;

namespace {

using Vec3 = std::array<double, 3>;

Vec3 point(const Mesh &m, LocalIndex n) { return {m.x(n), m.y(n), m.z(n)}; }
Vec3 minus(const Vec3 &a, const Vec3 &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3 &a, const Vec3 &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3 &a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/// Host reference: volume of a trilinear hexahedron (nodes in Gmsh/VTK order), the integral of
/// det(dx/dxi) by 2x2x2 Gauss, written out independently of core/ElementTraits.hpp.
double hexVolume(const Mesh &m, LocalIndex e) {
  static const int sign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                 {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double g = 1.0 / std::sqrt(3.0);
  double volume = 0.0;
  for (int q = 0; q < 8; ++q) {
    const double xi[3] = {q & 1 ? g : -g, q & 2 ? g : -g, q & 4 ? g : -g};
    double jac[3][3] = {};
    for (int a = 0; a < 8; ++a) {
      double dn[3];
      for (int j = 0; j < 3; ++j) {
        dn[j] = 0.125 * sign[a][j];
        for (int k = 0; k < 3; ++k)
          if (k != j)
            dn[j] *= 1.0 + sign[a][k] * xi[k];
      }
      const Vec3 x = point(m, m.node(e, a));
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          jac[i][j] += x[i] * dn[j];
    }
    volume += jac[0][0] * (jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1]) -
              jac[0][1] * (jac[1][0] * jac[2][2] - jac[1][2] * jac[2][0]) +
              jac[0][2] * (jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0]); // weights are 1
  }
  return volume;
}

/// Unit normal (x1 - x0) x (x3 - x0) of a boundary face from its corner nodes (Mesh::sideNode).
Vec3 faceNormal(const Mesh &m, const BoundaryEdge &f) {
  const Vec3 x0 = point(m, m.sideNode(f, 0));
  Vec3 n = cross(minus(point(m, m.sideNode(f, 1)), x0), minus(point(m, m.sideNode(f, 3)), x0));
  const double len = norm(n);
  for (double &c : n)
    c /= len;
  return n;
}

std::string expectInputError(const std::function<void()> &f) {
  try {
    f();
  } catch (const InputError &e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

/// `text` with the first `from` replaced by `to` (a test failure when there is none).
std::string replaced(std::string text, const std::string &from, const std::string &to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return pos == std::string::npos ? text : text.replace(pos, from.size(), to);
}

/// The 1-based line of `text` on which `needle` starts ("" when absent: the test fails).
int lineOf(const std::string &text, const std::string &needle) {
  const auto pos = text.find(needle);
  EXPECT_NE(pos, std::string::npos) << needle;
  return pos == std::string::npos
             ? 0
             : 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
}

} // namespace

TEST(BoxMesh, CountsVolumeBoundariesAndOrientation) {
  const double lx = 3.0, ly = 2.0, lz = 1.5, x0 = 1.0, y0 = -0.5, z0 = 2.0;
  const int nx = 4, ny = 3, nz = 2;
  const Mesh m = boxMesh(lx, ly, lz, nx, ny, nz, ElementType::Hex8, x0, y0, z0);
  EXPECT_EQ(m.elementType, ElementType::Hex8);
  EXPECT_EQ(m.dim(), 3);
  EXPECT_EQ(m.nodesPerElement, 8);
  EXPECT_EQ(m.numNodes(), (nx + 1) * (ny + 1) * (nz + 1));
  EXPECT_EQ(m.numElements(), nx * ny * nz);
  EXPECT_EQ(m.nodeIds.size(), static_cast<std::size_t>(m.numNodes()));
  EXPECT_EQ(m.elementIds.size(), static_cast<std::size_t>(m.numElements()));
  ASSERT_EQ(m.regionNames, std::vector<std::string>{"body"});
  EXPECT_EQ(m.elementRegion, std::vector<int>(m.numElements(), 0));
  EXPECT_NO_THROW(validateMesh(m));

  double volume = 0.0;
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    const double v = hexVolume(m, e);
    EXPECT_GT(v, 0.0) << "element " << e;
    volume += v;
  }
  EXPECT_NEAR(volume, lx * ly * lz, 1e-12 * lx * ly * lz);

  // Node numbering: x fastest, then y, then z.
  EXPECT_NEAR(m.x(1) - m.x(0), lx / nx, 1e-14);
  EXPECT_NEAR(m.y(nx + 1) - m.y(0), ly / ny, 1e-14);
  EXPECT_NEAR(m.z((nx + 1) * (ny + 1)) - m.z(0), lz / nz, 1e-14);

  // Each boundary: its number of faces, its nodes on its plane, the outward normal on its axis.
  struct Side {
    const char *name;
    int axis;
    double value, direction;
    int faces;
  };
  const Side sides[] = {{"xmin", 0, x0, -1.0, ny * nz}, {"xmax", 0, x0 + lx, 1.0, ny * nz},
                        {"ymin", 1, y0, -1.0, nx * nz}, {"ymax", 1, y0 + ly, 1.0, nx * nz},
                        {"zmin", 2, z0, -1.0, nx * ny}, {"zmax", 2, z0 + lz, 1.0, nx * ny}};
  EXPECT_EQ(m.boundaries.size(), 6u);
  for (const Side &s : sides) {
    SCOPED_TRACE(s.name);
    ASSERT_TRUE(m.hasBoundary(s.name));
    const auto &faces = m.boundaries.at(s.name);
    EXPECT_EQ(static_cast<int>(faces.size()), s.faces);
    std::set<LocalIndex> elements;
    for (const BoundaryEdge &f : faces) {
      elements.insert(f.element);
      for (int k = 0; k < m.nodesPerSide(); ++k)
        EXPECT_NEAR(m.coordinate(m.sideNode(f, k), s.axis), s.value, 1e-12);
      const Vec3 n = faceNormal(m, f);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(n[i], i == s.axis ? s.direction : 0.0, 1e-12);
    }
    EXPECT_EQ(static_cast<int>(elements.size()), s.faces); // one face per element
  }

  // Corners and face centres.
  for (int c = 0; c < 8; ++c) {
    const int cx = c & 1, cy = (c >> 1) & 1, cz = (c >> 2) & 1;
    const std::string name =
        "corner_" + std::to_string(cx) + std::to_string(cy) + std::to_string(cz);
    ASSERT_TRUE(m.hasNodeSet(name)) << name;
    ASSERT_EQ(m.nodeSets.at(name).size(), 1u) << name;
    const LocalIndex n = m.nodeSets.at(name).front();
    EXPECT_NEAR(m.x(n), x0 + cx * lx, 1e-12) << name;
    EXPECT_NEAR(m.y(n), y0 + cy * ly, 1e-12) << name;
    EXPECT_NEAR(m.z(n), z0 + cz * lz, 1e-12) << name;
  }
  for (int side = 0; side < 2; ++side) {
    const std::string name = side == 0 ? "xmin_center" : "xmax_center";
    ASSERT_TRUE(m.hasNodeSet(name));
    ASSERT_EQ(m.nodeSets.at(name).size(), 1u);
    const LocalIndex c = m.nodeSets.at(name).front();
    EXPECT_NEAR(m.x(c), x0 + side * lx, 1e-12);
    // ny = 3 has no node at mid-height: the closest grid line is one third of a division away;
    // nz = 2 has one at mid-depth.
    EXPECT_NEAR(std::abs(m.y(c) - (y0 + 0.5 * ly)), 0.5 * ly / ny, 1e-12);
    EXPECT_NEAR(m.z(c), z0 + 0.5 * lz, 1e-12);
    // No node of that face is closer (brute force over all nodes).
    const double d = std::hypot(m.y(c) - (y0 + 0.5 * ly), m.z(c) - (z0 + 0.5 * lz));
    for (LocalIndex n = 0; n < m.numNodes(); ++n) {
      if (std::abs(m.x(n) - (x0 + side * lx)) < 1e-12) {
        EXPECT_GE(std::hypot(m.y(n) - (y0 + 0.5 * ly), m.z(n) - (z0 + 0.5 * lz)), d - 1e-12);
      }
    }
  }
}

TEST(BoxMesh, GradingSetsTheFirstElementSize) {
  const double lx = 2.0, ly = 1.0, lz = 4.0, gx = 1.5, gy = 2.0, gz = 1.2;
  const int nx = 5, ny = 4, nz = 3;
  const Mesh m = boxMesh(lx, ly, lz, nx, ny, nz, ElementType::Hex8, 0.5, 0.0, -1.0, gx, gy, gz);
  EXPECT_NO_THROW(validateMesh(m));
  // Element 0 spans [x0, x0 + lx (1/nx)^gx] etc.: its nodes 0 -> 1 (x), 0 -> 3 (y), 0 -> 4 (z).
  const LocalIndex n0 = m.node(0, 0);
  EXPECT_NEAR(m.x(m.node(0, 1)) - m.x(n0), lx * std::pow(1.0 / nx, gx), 1e-14);
  EXPECT_NEAR(m.y(m.node(0, 3)) - m.y(n0), ly * std::pow(1.0 / ny, gy), 1e-14);
  EXPECT_NEAR(m.z(m.node(0, 4)) - m.z(n0), lz * std::pow(1.0 / nz, gz), 1e-14);
  // Sizes grow away from the origin, and the box is still the box.
  EXPECT_LT(m.x(m.node(0, 1)) - m.x(n0), lx / nx);
  double volume = 0.0;
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    volume += hexVolume(m, e);
  EXPECT_NEAR(volume, lx * ly * lz, 1e-12 * lx * ly * lz);
  for (LocalIndex n : m.nodesOf("xmax"))
    EXPECT_NEAR(m.x(n), 2.5, 1e-14);
  for (LocalIndex n : m.nodesOf("zmax"))
    EXPECT_NEAR(m.z(n), 3.0, 1e-14);
}

TEST(BoxMesh, RefusesBadArgumentsAndOtherElementTypes) {
  auto generatorError = [](const std::function<void()> &f) {
    try {
      f();
    } catch (const GeneratorError &e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "expected a GeneratorError";
    return std::string();
  };
  std::string msg = generatorError([] { boxMesh(1, 1, 1, 1, 1, 1, ElementType::Quad4); });
  EXPECT_NE(msg.find("mesh generator box"), std::string::npos) << msg;
  EXPECT_NE(msg.find("quad4"), std::string::npos) << msg;
  msg = generatorError([] { boxMesh(1, 1, 0.0, 1, 1, 1, ElementType::Hex8); });
  EXPECT_NE(msg.find("mesh generator box: size[2] must be positive"), std::string::npos) << msg;
  msg = generatorError([] { boxMesh(1, 1, 1, 1, 0, 1, ElementType::Hex8); });
  EXPECT_NE(msg.find("mesh generator box: divisions[1] must be positive"), std::string::npos)
      << msg;
  msg = generatorError([] { boxMesh(1, 1, 1, 1, 1, 1, ElementType::Hex8, 0, 0, 0, 1, 1, -2); });
  EXPECT_NE(msg.find("mesh generator box: grading[2] must be positive"), std::string::npos) << msg;
  msg = generatorError([] { boxMesh(1, 1, 1, 2000, 2000, 2000, ElementType::Hex8); });
  EXPECT_NE(msg.find("mesh generator box: divisions too large"), std::string::npos) << msg;
  // The 2D generators refuse a 3D element type instead of building a broken mesh.
  msg = generatorError([] { rectangleMesh(1, 1, 2, 2, ElementType::Hex8); });
  EXPECT_NE(msg.find("generator rectangle"), std::string::npos) << msg;
  EXPECT_NE(msg.find("hex8"), std::string::npos) << msg;
}

TEST(BoxMesh, MergeMeshesRefuses3DBodiesByName) {
  const Mesh box = boxMesh(1, 1, 1, 1, 1, 1, ElementType::Hex8);
  const Mesh plate = rectangleMesh(1, 1, 1, 1, ElementType::Quad4);
  std::string msg = expectInputError([&] { mergeMeshes({{"block", box, {0, 0}}}); });
  EXPECT_NE(msg.find("body 'block' is a 3D mesh"), std::string::npos) << msg;
  EXPECT_NE(msg.find("2D only"), std::string::npos) << msg;
  msg = expectInputError([&] { mergeMeshes({{"plate", plate, {0, 0}}, {"cube", box, {2, 0}}}); });
  EXPECT_NE(msg.find("body 'cube' is a 3D mesh"), std::string::npos) << msg;
  // 2D bodies still merge.
  const Mesh two = mergeMeshes({{"a", plate, {0, 0}}, {"b", plate, {2, 0}}});
  EXPECT_EQ(two.numElements(), 2);
  EXPECT_NEAR(two.x(two.nodeSets.at("b.bottom_left").front()), 2.0, 1e-15);
}

namespace {
// A 2 x 1 x 1 box of two hexahedra: node (i, j, k) at (i, j, k) has tag 101 + i + 3 j + 6 k.
// Physical groups: volume "body", surfaces "left" (x = 0) and "right" (x = 2) of one quadrangle
// each (the first turning like its element face, the second the other way), curve "edge" (y = z =
// 0, two lines), point "origin".
const char *kGmshHex = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
5
0 4 "origin"
1 5 "edge"
2 2 "left"
2 3 "right"
3 1 "body"
$EndPhysicalNames
$Entities
1 1 2 1
1 0 0 0 1 4
1 0 0 0 2 0 0 1 5 0
1 0 0 0 0 1 1 1 2 0
2 2 0 0 2 1 1 1 3 0
1 0 0 0 2 1 1 1 1 0
$EndEntities
$Nodes
1 12 101 112
3 1 0 12
101
102
103
104
105
106
107
108
109
110
111
112
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
0 0 1
1 0 1
2 0 1
0 1 1
1 1 1
2 1 1
$EndNodes
$Elements
5 7 1 22
0 1 15 1
1 101
1 1 1 2
2 101 102
3 102 103
2 1 3 1
4 101 107 110 104
2 2 3 1
5 103 109 112 106
3 1 5 2
21 101 102 105 104 107 108 111 110
22 102 103 106 105 108 109 112 111
$EndElements
)";

Mesh readText(const std::string &text, const std::string &name = "box.msh") {
  std::istringstream in(text);
  return readGmsh(in, name);
}

/// Mesh index of the node with Gmsh tag `tag`.
LocalIndex nodeOfTag(const Mesh &m, long tag) {
  const auto it = std::find(m.nodeIds.begin(), m.nodeIds.end(), tag);
  EXPECT_NE(it, m.nodeIds.end()) << tag;
  return static_cast<LocalIndex>(it - m.nodeIds.begin());
}
} // namespace

TEST(GmshReader3D, ReadsHexahedraWithRegionsBoundaryFacesAndNodeSets) {
  const Mesh m = readText(kGmshHex);
  EXPECT_EQ(m.elementType, ElementType::Hex8);
  EXPECT_EQ(m.dim(), 3);
  EXPECT_EQ(m.numNodes(), 12);
  EXPECT_EQ(m.numElements(), 2);
  EXPECT_EQ(m.elementIds, (std::vector<long>{21, 22}));
  EXPECT_EQ(m.nodeIds.front(), 101);
  // Coordinates interleaved x, y, z: tag 101 + i + 3 j + 6 k sits at (i, j, k).
  for (LocalIndex n = 0; n < m.numNodes(); ++n) {
    const long i = m.nodeIds[n] - 101;
    EXPECT_EQ(m.x(n), static_cast<double>(i % 3));
    EXPECT_EQ(m.y(n), static_cast<double>((i / 3) % 2));
    EXPECT_EQ(m.z(n), static_cast<double>(i / 6));
  }
  ASSERT_EQ(m.regionNames, std::vector<std::string>{"body"});
  EXPECT_EQ(m.elementRegion, (std::vector<int>{0, 0}));
  EXPECT_NO_THROW(validateMesh(m));
  double volume = 0.0;
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    volume += hexVolume(m, e);
  EXPECT_NEAR(volume, 2.0, 1e-14);

  // Boundaries: the quadrangle's element and face, the face's nodes those of the quadrangle, its
  // normal outward, whichever way the quadrangle turns.
  struct Expected {
    const char *name;
    LocalIndex element;
    int face;
    std::set<long> tags;
    double nx;
  };
  const Expected expected[] = {{"left", 0, 5, {101, 104, 107, 110}, -1.0},
                               {"right", 1, 3, {103, 109, 112, 106}, 1.0}};
  for (const Expected &x : expected) {
    SCOPED_TRACE(x.name);
    ASSERT_TRUE(m.hasBoundary(x.name));
    ASSERT_EQ(m.boundaries.at(x.name).size(), 1u);
    const BoundaryEdge f = m.boundaries.at(x.name).front();
    EXPECT_EQ(f.element, x.element);
    EXPECT_EQ(f.edge, x.face);
    std::set<long> tags;
    for (int k = 0; k < m.nodesPerSide(); ++k)
      tags.insert(m.nodeIds[m.sideNode(f, k)]);
    EXPECT_EQ(tags, x.tags);
    const Vec3 n = faceNormal(m, f);
    EXPECT_NEAR(n[0], x.nx, 1e-14);
    EXPECT_NEAR(n[1], 0.0, 1e-14);
    EXPECT_NEAR(n[2], 0.0, 1e-14);
  }
  // Node sets: the point's node, the curve's nodes (each once).
  ASSERT_TRUE(m.hasNodeSet("origin"));
  EXPECT_EQ(m.nodeSets.at("origin"), std::vector<LocalIndex>{nodeOfTag(m, 101)});
  ASSERT_TRUE(m.hasNodeSet("edge"));
  std::vector<LocalIndex> edge = {nodeOfTag(m, 101), nodeOfTag(m, 102), nodeOfTag(m, 103)};
  std::sort(edge.begin(), edge.end());
  EXPECT_EQ(m.nodeSets.at("edge"), edge);
  EXPECT_FALSE(m.hasBoundary("edge"));
  EXPECT_FALSE(m.hasBoundary("origin"));
  EXPECT_FALSE(m.hasNodeSet("left"));
}

namespace {
/// Writes a Hex8 mesh as Gmsh 4.1 ASCII: one volume (physical "body"), one surface per boundary
/// (physical groups of the same names) whose quadrangles are the boundary faces' corner nodes,
/// rotated by the face number and, for odd elements, in the other turning sense (the reader must
/// not depend on either), one point per node set. Node tags 5 + 2 n, element tags 1000 + e.
std::string toGmsh3D(const Mesh &m) {
  std::ostringstream s;
  std::vector<std::string> bnames, pnames;
  for (const auto &[name, faces] : m.boundaries)
    bnames.push_back(name);
  for (const auto &[name, nodes] : m.nodeSets)
    pnames.push_back(name);
  s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n"
    << 1 + bnames.size() + pnames.size() << "\n3 1 \"body\"\n";
  for (std::size_t i = 0; i < bnames.size(); ++i)
    s << "2 " << 10 + i << " \"" << bnames[i] << "\"\n";
  for (std::size_t i = 0; i < pnames.size(); ++i)
    s << "0 " << 100 + i << " \"" << pnames[i] << "\"\n";
  s << "$EndPhysicalNames\n$Entities\n" << pnames.size() << " 0 " << bnames.size() << " 1\n";
  for (std::size_t i = 0; i < pnames.size(); ++i)
    s << i + 1 << " 0 0 0 1 " << 100 + i << "\n";
  for (std::size_t i = 0; i < bnames.size(); ++i)
    s << i + 1 << " 0 0 0 1 1 1 1 " << 10 + i << " 0\n";
  s << "1 0 0 0 1 1 1 1 1 0\n$EndEntities\n";
  const LocalIndex nn = m.numNodes();
  auto tag = [](LocalIndex n) { return 5 + 2 * static_cast<long>(n); };
  s << "$Nodes\n1 " << nn << " 5 " << tag(nn - 1) << "\n3 1 0 " << nn << "\n";
  for (LocalIndex n = 0; n < nn; ++n)
    s << tag(n) << "\n";
  for (LocalIndex n = 0; n < nn; ++n)
    s << std::setprecision(17) << m.x(n) << " " << m.y(n) << " " << m.z(n) << "\n";
  s << "$EndNodes\n$Elements\n";
  std::size_t count = m.numElements();
  for (const auto &[name, faces] : m.boundaries)
    count += faces.size();
  for (const auto &[name, nodes] : m.nodeSets)
    count += nodes.size();
  s << 1 + bnames.size() + pnames.size() << " " << count << " 1 " << 1000 + m.numElements() << "\n";
  long id = 1;
  for (std::size_t i = 0; i < pnames.size(); ++i) {
    const auto &nodes = m.nodeSets.at(pnames[i]);
    s << "0 " << i + 1 << " 15 " << nodes.size() << "\n";
    for (LocalIndex n : nodes)
      s << id++ << " " << tag(n) << "\n";
  }
  for (std::size_t i = 0; i < bnames.size(); ++i) {
    const auto &faces = m.boundaries.at(bnames[i]);
    s << "2 " << i + 1 << " 3 " << faces.size() << "\n";
    for (const BoundaryEdge &f : faces) {
      s << id++;
      for (int k = 0; k < 4; ++k) {
        const int r = (k + f.edge) % 4;
        s << " " << tag(m.sideNode(f, f.element % 2 ? 3 - r : r));
      }
      s << "\n";
    }
  }
  s << "3 1 5 " << m.numElements() << "\n";
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    s << 1000 + e;
    for (int a = 0; a < 8; ++a)
      s << " " << tag(m.node(e, a));
    s << "\n";
  }
  s << "$EndElements\n";
  return s.str();
}
} // namespace

TEST(GmshReader3D, RoundTripOfAGradedBoxKeepsGeometryTopologyAndGroups) {
  const Mesh box = boxMesh(2.0, 1.0, 0.5, 3, 2, 2, ElementType::Hex8, -1.0, 0.0, 0.25, 1.3);
  const Mesh m = readText(toGmsh3D(box), "box.msh");
  EXPECT_EQ(m.elementType, ElementType::Hex8);
  EXPECT_EQ(m.coordinates, box.coordinates);
  EXPECT_EQ(m.connectivity, box.connectivity);
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    EXPECT_EQ(m.elementId(e), 1000 + e);
  for (LocalIndex n = 0; n < m.numNodes(); ++n)
    EXPECT_EQ(m.nodeId(n), 5 + 2 * n);
  EXPECT_EQ(m.regionNames, std::vector<std::string>{"body"});
  ASSERT_EQ(m.boundaries.size(), box.boundaries.size());
  for (const auto &[name, faces] : box.boundaries) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(m.hasBoundary(name));
    const auto &read = m.boundaries.at(name);
    ASSERT_EQ(read.size(), faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i) {
      EXPECT_EQ(read[i].element, faces[i].element);
      EXPECT_EQ(read[i].edge, faces[i].edge);
    }
  }
  EXPECT_EQ(m.nodeSets, box.nodeSets);
  EXPECT_NO_THROW(validateMesh(m));
}

TEST(GmshReader3D, AnInteriorFaceTakesTheElementItsQuadrangleFacesOutOf) {
  // A named quadrangle on the interface x = 1 matches a face of both hexahedra: the element whose
  // face turns like the quadrangle is taken. 102 105 111 108 turns counter-clockwise seen from
  // +x, the face x+ (3) of element 21; reversed it is the face x- (5) of element 22.
  for (const bool reversed : {false, true}) {
    SCOPED_TRACE(reversed ? "reversed" : "as is");
    std::string t = kGmshHex;
    t = replaced(t, "5 103 109 112 106", reversed ? "5 102 108 111 105" : "5 102 105 111 108");
    const Mesh m = readText(t);
    ASSERT_EQ(m.boundaries.at("right").size(), 1u);
    const BoundaryEdge f = m.boundaries.at("right").front();
    EXPECT_EQ(f.element, reversed ? 1 : 0);
    EXPECT_EQ(f.edge, reversed ? 5 : 3);
    EXPECT_NEAR(faceNormal(m, f)[0], reversed ? -1.0 : 1.0, 1e-14);
  }
}

TEST(GmshReader3D, RefusesQuadranglesThatAreNoFaceAndMixedElements) {
  const std::string t = kGmshHex;
  // A boundary quadrangle whose corners are no face of a hexahedron.
  std::string bad = t;
  bad = replaced(bad, "5 103 109 112 106", "5 103 109 111 105");
  std::string msg = expectInputError([&] { readText(bad, "bad.msh"); });
  EXPECT_NE(msg.find("bad.msh:" + std::to_string(lineOf(bad, "5 103 109 111 105")) +
                     ": quadrangle element 5 of boundary 'right' is not a face of any hexahedron"),
            std::string::npos)
      << msg;
  // The same quadrangle in a surface without a physical group: a 2D element among the 3D ones.
  bad = t;
  bad = replaced(bad, "2 2 0 0 2 1 1 1 3 0", "2 2 0 0 2 1 1 0 0");
  bad = replaced(bad, "5 103 109 112 106", "5 103 109 111 105");
  msg = expectInputError([&] { readText(bad, "bad.msh"); });
  EXPECT_NE(msg.find("bad.msh:" + std::to_string(lineOf(bad, "5 103 109 111 105")) +
                     ": quadrangle element 5 (surface 2) is not a face of any hexahedron"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("mixed 2D and 3D elements"), std::string::npos) << msg;
  // ... while an unnamed quadrangle that is a face is accepted (and names nothing).
  bad = t;
  bad = replaced(bad, "2 2 0 0 2 1 1 1 3 0", "2 2 0 0 2 1 1 0 0");
  const Mesh unnamed = readText(bad);
  ASSERT_TRUE(unnamed.hasBoundary("right")); // named in $PhysicalNames, so kept, empty
  EXPECT_TRUE(unnamed.boundaries.at("right").empty());
  EXPECT_EQ(unnamed.boundaries.at("left").size(), 1u);

  // Hexahedra followed by a tetrahedron block: mixed volume types, at the block's line.
  bad = t;
  bad = replaced(bad, "5 7 1 22", "6 8 1 23");
  bad = replaced(bad, "$EndElements", "3 1 4 1\n23 101 102 104 107\n$EndElements");
  msg = expectInputError([&] { readText(bad, "bad.msh"); });
  EXPECT_NE(msg.find("bad.msh:" + std::to_string(lineOf(bad, "3 1 4 1")) +
                     ": mixed volume element types: element type 4 (4-node tetrahedron)"),
            std::string::npos)
      << msg;
  // A tetrahedron block alone is an unsupported type.
  bad = t;
  bad = replaced(bad, "3 1 5 2\n", "3 1 4 2\n");
  msg = expectInputError([&] { readText(bad, "bad.msh"); });
  EXPECT_NE(msg.find("bad.msh:" + std::to_string(lineOf(bad, "3 1 4 2")) +
                     ": unsupported element type 4 (4-node tetrahedron)"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("8-node hexahedra (type 5)"), std::string::npos) << msg;
  // 8-node quadrangles next to hexahedra.
  bad = t;
  bad = replaced(bad, "2 1 3 1\n4 101 107 110 104", "2 1 16 1\n4 101 107 110 104 101 107 110 104");
  bad = replaced(bad, "2 2 3 1\n5 103 109 112 106", "2 2 16 1\n5 103 109 112 106 103 109 112 106");
  msg = expectInputError([&] { readText(bad, "bad.msh"); });
  EXPECT_NE(msg.find("bad.msh:" + std::to_string(lineOf(bad, "4 101 107 110 104")) +
                     ": 8-node quadrangles (type 16) in a mesh of 8-node hexahedra"),
            std::string::npos)
      << msg;
  // A hexahedron that references a node that does not exist.
  bad = t;
  bad = replaced(bad, "22 102 103", "22 102 999");
  msg = expectInputError([&] { readText(bad, "bad.msh"); });
  EXPECT_NE(msg.find("bad.msh:" + std::to_string(lineOf(bad, "22 102 999")) +
                     ": element 22 references unknown node 999"),
            std::string::npos)
      << msg;
}

TEST(GmshReader3D, InvertedHexahedronIsRefusedByValidation) {
  // Element 22 with its bottom and top faces swapped: mirrored, negative Jacobian everywhere.
  std::string t = kGmshHex;
  t = replaced(t, "22 102 103 106 105 108 109 112 111", "22 108 109 112 111 102 103 106 105");
  const Mesh m = readText(t, "inverted.msh");
  EXPECT_LT(hexVolume(m, 1), 0.0);
  const std::string msg = expectInputError([&] { validateMesh(m); });
  EXPECT_NE(msg.find("inverted.msh: element 22 has a non-positive Jacobian"), std::string::npos)
      << msg;
}

TEST(GmshReader3D, PlanarMeshesKeepTheir2DRules) {
  // One quadrangle with its nodes at z = 0 is a 2D mesh; a node off the plane is refused at its
  // line, as before hexahedra were read.
  const std::string t = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 4 1 4
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
1 1 1 1
2 1 3 1
1 1 2 3 4
$EndElements
)";
  const Mesh m = readText(t, "flat.msh");
  EXPECT_EQ(m.elementType, ElementType::Quad4);
  EXPECT_EQ(m.dim(), 2);
  EXPECT_EQ(m.coordinates, (std::vector<double>{0, 0, 1, 0, 1, 1, 0, 1}));
  EXPECT_EQ(m.regionNames, std::vector<std::string>{"surface_1"});
  std::string bad = t;
  bad = replaced(bad, "1 1 0\n", "1 1 0.5\n");
  const std::string msg = expectInputError([&] { readText(bad, "bad.msh"); });
  EXPECT_NE(msg.find("bad.msh:" + std::to_string(lineOf(bad, "1 1 0.5")) +
                     ": node 3 has a non-zero z coordinate; mixcon meshes are planar (z = 0)"),
            std::string::npos)
      << msg;
}
