// 3D meshes of hexahedra and tetrahedra (issue 17): the box generator and the Gmsh 4.1 reader,
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
#include <limits>
#include <map>
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

/// VTK's (the internal) Hex20 mid-edge nodes: node 8 + k lies between corners kVtkEdge[k].
constexpr int kVtkEdge[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                 {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
/// Gmsh's Hex20 mid-edge nodes (Gmsh manual, "Node ordering": the hexahedron's edge list):
/// node 8 + k lies between corners kGmshEdge[k].
constexpr int kGmshEdge[12][2] = {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3},
                                  {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};
/// Natural coordinates of the Hex8 corners (the Gmsh/VTK order).
constexpr int kCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                               {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

/// Host reference: volume of a 20-node serendipity hexahedron (internal node order), the
/// integral of det(dx/dxi) by 3x3x3 Gauss, with the shape functions written out here: corner a,
/// N = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a)(xi xi_a + eta eta_a + zeta zeta_a - 2) / 8;
/// mid-edge node (zero natural coordinate along its edge, say xi), N = (1 - xi^2)(1 + eta
/// eta_a)(1 + zeta zeta_a) / 4.
double hex20Volume(const Mesh &m, LocalIndex e) {
  double xa[20][3];
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      xa[a][i] = kCorner[a][i];
  for (int k = 0; k < 12; ++k)
    for (int i = 0; i < 3; ++i)
      xa[8 + k][i] = 0.5 * (kCorner[kVtkEdge[k][0]][i] + kCorner[kVtkEdge[k][1]][i]);
  const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  double volume = 0.0;
  for (int q = 0; q < 27; ++q) {
    const double xi[3] = {g[q % 3], g[(q / 3) % 3], g[q / 9]};
    const double weight = w[q % 3] * w[(q / 3) % 3] * w[q / 9];
    double jac[3][3] = {};
    for (int a = 0; a < 20; ++a) {
      double p[3], dn[3];
      for (int i = 0; i < 3; ++i)
        p[i] = 1.0 + xi[i] * xa[a][i];
      if (a < 8) {
        const double s = xi[0] * xa[a][0] + xi[1] * xa[a][1] + xi[2] * xa[a][2] - 2.0;
        for (int i = 0; i < 3; ++i) // d/dxi_i of p0 p1 p2 s / 8
          dn[i] = 0.125 * p[(i + 1) % 3] * p[(i + 2) % 3] * xa[a][i] * (s + p[i]);
      } else {
        int along = 0;
        for (int i = 0; i < 3; ++i)
          if (xa[a][i] == 0.0)
            along = i;
        const int j = (along + 1) % 3, k = (along + 2) % 3;
        const double bubble = 1.0 - xi[along] * xi[along];
        dn[along] = -0.5 * xi[along] * p[j] * p[k];
        dn[j] = 0.25 * bubble * xa[a][j] * p[k];
        dn[k] = 0.25 * bubble * p[j] * xa[a][k];
      }
      const Vec3 x = point(m, m.node(e, a));
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          jac[i][j] += x[i] * dn[j];
    }
    volume += weight * (jac[0][0] * (jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1]) -
                        jac[0][1] * (jac[1][0] * jac[2][2] - jac[1][2] * jac[2][0]) +
                        jac[0][2] * (jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0]));
  }
  return volume;
}

/// Expects every mid-edge node of every element (and of every boundary face) of a Hex20 mesh at
/// the middle of its corners (kVtkEdge; face node 4 + m between face corners m and m + 1).
void expectMidEdgeNodesAtMidpoints(const Mesh &m) {
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    for (int k = 0; k < 12; ++k) {
      const Vec3 a = point(m, m.node(e, kVtkEdge[k][0])), b = point(m, m.node(e, kVtkEdge[k][1]));
      const Vec3 c = point(m, m.node(e, 8 + k));
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(c[i], 0.5 * (a[i] + b[i]), 1e-13) << "element " << e << " edge " << k;
    }
  for (const auto &[name, faces] : m.boundaries)
    for (const BoundaryEdge &f : faces)
      for (int k = 0; k < 4; ++k) {
        const Vec3 a = point(m, m.sideNode(f, k)), b = point(m, m.sideNode(f, (k + 1) % 4));
        const Vec3 c = point(m, m.sideNode(f, 4 + k));
        for (int i = 0; i < 3; ++i)
          EXPECT_NEAR(c[i], 0.5 * (a[i] + b[i]), 1e-13) << name << " face node " << 4 + k;
      }
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

TEST(SphereShellMesh, CountsSurfacesOrientationAndVolumeForEverySolid) {
  // The octant a = 1 <= r <= b = 2 of sphereShellMesh(n = 3, m = 2): three cubed-sphere patches
  // of n x n x m cells whose shared nodes are merged (inclusion-exclusion over the three interface
  // planes and their common line); every element valid; each boundary on its surface with
  // outward faces; the trilinear Hex8 volume close to pi / 6 (b^3 - a^3).
  const double a = 1.0, b = 2.0;
  const int n = 3, m = 2;
  for (ElementType type :
       {ElementType::Hex8, ElementType::Hex20, ElementType::Tet4, ElementType::Tet10}) {
    SCOPED_TRACE(elementTypeName(type));
    const Mesh mesh = sphereShellMesh(a, b, n, m, type);
    EXPECT_NO_THROW(validateMesh(mesh));
    const bool tet = type == ElementType::Tet4 || type == ElementType::Tet10;
    EXPECT_EQ(mesh.numElements(), 3 * n * n * m * (tet ? 6 : 1));
    if (type == ElementType::Hex8 || type == ElementType::Tet4) {
      EXPECT_EQ(mesh.numNodes(), 3 * (n + 1) * (n + 1) * (m + 1) - 3 * (n + 1) * (m + 1) + (m + 1));
    }
    for (LocalIndex k = 0; k < mesh.numNodes(); ++k) {
      const double r = norm(point(mesh, k));
      EXPECT_GE(r, a - 1e-12);
      EXPECT_LE(r, b + 1e-12);
      for (int i = 0; i < 3; ++i)
        EXPECT_GE(mesh.coordinate(k, i), -1e-12);
    }
    const int corners = tet ? 3 : 4, perCell = tet ? 2 : 1; // faces per cell face
    struct Side {
      const char *name;
      int faces;
      std::function<double(const Vec3 &)> level; // zero on the surface
      std::function<Vec3(const Vec3 &)> outward;
    };
    const auto radial = [](const Vec3 &x) {
      const double r = norm(x);
      return Vec3{x[0] / r, x[1] / r, x[2] / r};
    };
    const Side sides[] = {
        {"inner", 3 * n * n * perCell, [&](const Vec3 &x) { return norm(x) - a; },
         [&](const Vec3 &x) {
           const Vec3 e = radial(x);
           return Vec3{-e[0], -e[1], -e[2]};
         }},
        {"outer", 3 * n * n * perCell, [&](const Vec3 &x) { return norm(x) - b; }, radial},
        {"xmin", 2 * n * m * perCell, [](const Vec3 &x) { return x[0]; },
         [](const Vec3 &) {
           return Vec3{-1.0, 0.0, 0.0};
         }},
        {"ymin", 2 * n * m * perCell, [](const Vec3 &x) { return x[1]; },
         [](const Vec3 &) {
           return Vec3{0.0, -1.0, 0.0};
         }},
        {"zmin", 2 * n * m * perCell, [](const Vec3 &x) { return x[2]; },
         [](const Vec3 &) {
           return Vec3{0.0, 0.0, -1.0};
         }}};
    EXPECT_EQ(mesh.boundaries.size(), 5u);
    for (const Side &side : sides) {
      SCOPED_TRACE(side.name);
      ASSERT_TRUE(mesh.hasBoundary(side.name));
      const auto &faces = mesh.boundaries.at(side.name);
      EXPECT_EQ(static_cast<int>(faces.size()), side.faces);
      for (const BoundaryEdge &f : faces) {
        Vec3 centre{0.0, 0.0, 0.0};
        for (int k = 0; k < mesh.nodesPerSide(); ++k) {
          const Vec3 x = point(mesh, mesh.sideNode(f, k));
          EXPECT_NEAR(side.level(x), 0.0, 1e-12);
          if (k < corners)
            for (int i = 0; i < 3; ++i)
              centre[i] += x[i] / corners;
        }
        const Vec3 x0 = point(mesh, mesh.sideNode(f, 0));
        const Vec3 normal = cross(minus(point(mesh, mesh.sideNode(f, 1)), x0),
                                  minus(point(mesh, mesh.sideNode(f, corners - 1)), x0));
        const Vec3 want = side.outward(centre);
        EXPECT_GT(normal[0] * want[0] + normal[1] * want[1] + normal[2] * want[2],
                  0.5 * norm(normal));
      }
    }
    for (const char *surface : {"inner", "outer"})
      for (int i = 0; i < 3; ++i) {
        const std::string name = std::string(surface) + "_" + "xyz"[i];
        ASSERT_TRUE(mesh.hasNodeSet(name)) << name;
        const Vec3 x = point(mesh, mesh.nodeSets.at(name).front());
        for (int j = 0; j < 3; ++j)
          EXPECT_NEAR(x[j], j == i ? (surface[0] == 'i' ? a : b) : 0.0, 1e-12) << name;
      }
    if (type == ElementType::Hex8) {
      double volume = 0.0;
      for (LocalIndex e = 0; e < mesh.numElements(); ++e)
        volume += hexVolume(mesh, e);
      const double exact = M_PI / 6.0 * (b * b * b - a * a * a);
      EXPECT_NEAR(volume / exact, 1.0, 0.05); // flat faces cut the spheres' caps
      EXPECT_LT(volume, exact);
    }
  }
  EXPECT_THROW(sphereShellMesh(2.0, 1.0, 2, 2, ElementType::Hex8), GeneratorError);
  EXPECT_THROW(sphereShellMesh(1.0, 2.0, 0, 2, ElementType::Hex8), GeneratorError);
  EXPECT_THROW(sphereShellMesh(1.0, 2.0, 2, 2, ElementType::Quad4), GeneratorError);
}

TEST(ExtrudeMesh, SweepsQuadsIntoHexahedraWithTheirBoundariesAndNodeSets) {
  // A 3 x 2 rectangle (Quad4 and Quad8) extruded to z in [0, 1.5] in 3 layers graded by 1.5:
  // counts, positive volumes summing to the prism's, the swept boundaries on their planes with
  // outward normals, zmin / zmax, the regions, the node sets as lines along z; Hex20's vertical
  // mid-edge nodes half way between the grid lines.
  const double lx = 3.0, ly = 2.0, length = 1.5, grading = 1.5;
  const int nx = 3, ny = 2, layers = 3;
  for (ElementType section : {ElementType::Quad4, ElementType::Quad8}) {
    SCOPED_TRACE(elementTypeName(section));
    const Mesh plane = rectangleMesh(lx, ly, nx, ny, section);
    const Mesh m = extrudeMesh(plane, length, layers, grading);
    const bool quadratic = section == ElementType::Quad8;
    EXPECT_EQ(m.elementType, quadratic ? ElementType::Hex20 : ElementType::Hex8);
    EXPECT_NO_THROW(validateMesh(m));
    EXPECT_EQ(m.numElements(), nx * ny * layers);
    const LocalIndex corners = (nx + 1) * (ny + 1);
    EXPECT_EQ(m.numNodes(), (layers + 1) * plane.numNodes() + (quadratic ? layers * corners : 0));
    EXPECT_EQ(m.regionNames, plane.regionNames);
    double volume = 0.0;
    for (LocalIndex e = 0; e < m.numElements(); ++e) {
      const double v = hexVolume(m, e); // the corners: a straight-sided brick
      EXPECT_GT(v, 0.0);
      volume += v;
    }
    EXPECT_NEAR(volume, lx * ly * length, 1e-12 * lx * ly * length);
    // The first layer is length (1 / layers)^grading thick.
    double zmin1 = 1e300;
    for (LocalIndex k = 0; k < m.numNodes(); ++k)
      if (m.z(k) > 1e-12 && (!quadratic || k < (layers + 1) * plane.numNodes()))
        zmin1 = std::min(zmin1, m.z(k));
    EXPECT_NEAR(zmin1, length * std::pow(1.0 / layers, grading), 1e-12);
    const LocalIndex half = (layers + 1) * plane.numNodes(); // the first vertical mid-edge node
    if (quadratic) {
      for (LocalIndex k = half; k < half + corners; ++k)
        EXPECT_NEAR(m.z(k), 0.5 * zmin1, 1e-12);
    }
    struct Side {
      const char *name;
      int axis;
      double value, direction;
      int faces;
    };
    const Side sides[] = {{"left", 0, 0.0, -1.0, ny * layers},   {"right", 0, lx, 1.0, ny * layers},
                          {"bottom", 1, 0.0, -1.0, nx * layers}, {"top", 1, ly, 1.0, nx * layers},
                          {"zmin", 2, 0.0, -1.0, nx * ny},       {"zmax", 2, length, 1.0, nx * ny}};
    for (const Side &side : sides) {
      SCOPED_TRACE(side.name);
      ASSERT_TRUE(m.hasBoundary(side.name));
      EXPECT_EQ(static_cast<int>(m.boundaries.at(side.name).size()), side.faces);
      for (const BoundaryEdge &f : m.boundaries.at(side.name)) {
        for (int k = 0; k < m.nodesPerSide(); ++k)
          EXPECT_NEAR(m.coordinate(m.sideNode(f, k), side.axis), side.value, 1e-12);
        const Vec3 n = faceNormal(m, f);
        EXPECT_NEAR(n[side.axis], side.direction, 1e-12);
      }
    }
    for (const auto &[name, nodes] : plane.nodeSets) {
      SCOPED_TRACE(name);
      ASSERT_TRUE(m.hasNodeSet(name));
      const auto &line = m.nodeSets.at(name);
      EXPECT_EQ(line.size(), nodes.size() * (layers + 1 + (quadratic ? layers : 0)));
      for (LocalIndex k : line) {
        EXPECT_NEAR(m.x(k), plane.x(nodes.front()), 1e-12);
        EXPECT_NEAR(m.y(k), plane.y(nodes.front()), 1e-12);
      }
    }
  }
  const Mesh solid = boxMesh(1.0, 1.0, 1.0, 1, 1, 1, ElementType::Hex8);
  EXPECT_THROW(extrudeMesh(solid, 1.0, 2), GeneratorError);
  EXPECT_THROW(extrudeMesh(rectangleMesh(1.0, 1.0, 1, 1, ElementType::Quad4), 0.0, 2),
               GeneratorError);
}

// elementLayers = 2 V / (A h), h = (V / n)^(1/3) (a tetrahedron a sixth of a cube): N / 3 for a
// cube of N^3 elements of every solid type (the Tet meshes cut each cell into 6), k L / (L + 2 t)
// for a plate L x L x t of k layers of cubes, the same for the mesh moved anywhere.
TEST(ElementLayers, CountsTheElementsThroughAPart) {
  for (ElementType type :
       {ElementType::Hex8, ElementType::Hex20, ElementType::Tet4, ElementType::Tet10}) {
    EXPECT_NEAR(elementLayers(boxMesh(1.0, 1.0, 1.0, 6, 6, 6, type)), 2.0, 1e-12)
        << elementTypeName(type);
    EXPECT_NEAR(elementLayers(boxMesh(10.0, 10.0, 1.0, 20, 20, 2, type, 100.0, -50.0, 7.0)),
                2.0 * 10.0 / 12.0, 1e-12)
        << elementTypeName(type);
  }
  EXPECT_EQ(elementLayers(rectangleMesh(1.0, 1.0, 2, 2, ElementType::Quad4)), 0.0); // not a solid
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

TEST(BoxMesh, Hex20CountsVolumeMidEdgeNodesBoundariesAndNodeSets) {
  const double lx = 3.0, ly = 2.0, lz = 1.5, x0 = 1.0, y0 = -0.5, z0 = 2.0;
  const int nx = 4, ny = 3, nz = 2;
  const Mesh m = boxMesh(lx, ly, lz, nx, ny, nz, ElementType::Hex20, x0, y0, z0);
  EXPECT_EQ(m.elementType, ElementType::Hex20);
  EXPECT_EQ(m.dim(), 3);
  EXPECT_EQ(m.nodesPerElement, 20);
  EXPECT_EQ(m.nodesPerSide(), 8);
  const int corners = (nx + 1) * (ny + 1) * (nz + 1);
  const int edges = nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1) + (nx + 1) * (ny + 1) * nz;
  EXPECT_EQ(m.numNodes(), corners + edges);
  EXPECT_EQ(m.numElements(), nx * ny * nz);
  EXPECT_EQ(m.nodeIds.size(), static_cast<std::size_t>(m.numNodes()));
  EXPECT_EQ(m.elementIds.size(), static_cast<std::size_t>(m.numElements()));
  ASSERT_EQ(m.regionNames, std::vector<std::string>{"body"});
  EXPECT_EQ(m.elementRegion, std::vector<int>(m.numElements(), 0));
  EXPECT_NO_THROW(validateMesh(m));

  // Every node is used, each element has 20 distinct nodes, and no two nodes coincide.
  std::vector<int> uses(m.numNodes(), 0);
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    std::set<LocalIndex> own;
    for (int a = 0; a < 20; ++a) {
      own.insert(m.node(e, a));
      ++uses[m.node(e, a)];
    }
    EXPECT_EQ(own.size(), 20u) << "element " << e;
  }
  EXPECT_EQ(std::count(uses.begin(), uses.end(), 0), 0);
  std::set<std::array<long long, 3>> places;
  for (LocalIndex n = 0; n < m.numNodes(); ++n)
    places.insert(
        {std::llround(m.x(n) * 1e9), std::llround(m.y(n) * 1e9), std::llround(m.z(n) * 1e9)});
  EXPECT_EQ(places.size(), static_cast<std::size_t>(m.numNodes()));

  double volume = 0.0;
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    const double v = hex20Volume(m, e);
    EXPECT_NEAR(v, lx * ly * lz / (nx * ny * nz), 1e-12) << "element " << e;
    volume += v;
  }
  EXPECT_NEAR(volume, lx * ly * lz, 1e-12 * lx * ly * lz);
  expectMidEdgeNodesAtMidpoints(m);

  // Each boundary: its faces, their 8 nodes on its plane, the outward normal on its axis.
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
    for (const BoundaryEdge &f : faces) {
      std::set<LocalIndex> nodes;
      for (int k = 0; k < 8; ++k) {
        nodes.insert(m.sideNode(f, k));
        EXPECT_NEAR(m.coordinate(m.sideNode(f, k), s.axis), s.value, 1e-12);
      }
      EXPECT_EQ(nodes.size(), 8u);
      const Vec3 n = faceNormal(m, f);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(n[i], i == s.axis ? s.direction : 0.0, 1e-12);
    }
    // The boundary's nodes: the face's corner and mid-edge nodes of the lattice.
    const int a = (s.axis + 1) % 3, b = (s.axis + 2) % 3;
    const int n[3] = {nx, ny, nz};
    const int expected = (n[a] + 1) * (n[b] + 1) + n[a] * (n[b] + 1) + (n[a] + 1) * n[b];
    EXPECT_EQ(static_cast<int>(m.nodesOf(s.name).size()), expected);
  }

  for (int c = 0; c < 8; ++c) {
    const int cx = c & 1, cy = (c >> 1) & 1, cz = (c >> 2) & 1;
    const std::string name =
        "corner_" + std::to_string(cx) + std::to_string(cy) + std::to_string(cz);
    ASSERT_TRUE(m.hasNodeSet(name)) << name;
    ASSERT_EQ(m.nodeSets.at(name).size(), 1u) << name;
    const LocalIndex p = m.nodeSets.at(name).front();
    EXPECT_NEAR(m.x(p), x0 + cx * lx, 1e-12) << name;
    EXPECT_NEAR(m.y(p), y0 + cy * ly, 1e-12) << name;
    EXPECT_NEAR(m.z(p), z0 + cz * lz, 1e-12) << name;
  }
  // ny = 3: no grid line at mid-height, but a mid-edge node (nz = 2: a grid line at mid-depth),
  // so the face centre is a node.
  for (int side = 0; side < 2; ++side) {
    const std::string name = side == 0 ? "xmin_center" : "xmax_center";
    ASSERT_TRUE(m.hasNodeSet(name));
    ASSERT_EQ(m.nodeSets.at(name).size(), 1u);
    const LocalIndex c = m.nodeSets.at(name).front();
    EXPECT_NEAR(m.x(c), x0 + side * lx, 1e-12);
    EXPECT_NEAR(m.y(c), y0 + 0.5 * ly, 1e-12);
    EXPECT_NEAR(m.z(c), z0 + 0.5 * lz, 1e-12);
  }
}

TEST(BoxMesh, Hex20GradedMidEdgeNodesSitAtTheMiddleOfTheGradedEdges) {
  const double lx = 2.0, ly = 1.0, lz = 4.0, gx = 1.5, gy = 2.0, gz = 1.2;
  const int nx = 3, ny = 2, nz = 3;
  const Mesh m = boxMesh(lx, ly, lz, nx, ny, nz, ElementType::Hex20, 0.5, 0.0, -1.0, gx, gy, gz);
  EXPECT_NO_THROW(validateMesh(m));
  expectMidEdgeNodesAtMidpoints(m);
  // The corners are those of the Hex8 box with the same arguments, element by element.
  const Mesh hex8 = boxMesh(lx, ly, lz, nx, ny, nz, ElementType::Hex8, 0.5, 0.0, -1.0, gx, gy, gz);
  ASSERT_EQ(m.numElements(), hex8.numElements());
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i)
        EXPECT_EQ(m.coordinate(m.node(e, a), i), hex8.coordinate(hex8.node(e, a), i));
  for (const auto &[name, faces] : hex8.boundaries) {
    ASSERT_TRUE(m.hasBoundary(name));
    const auto &f20 = m.boundaries.at(name);
    ASSERT_EQ(f20.size(), faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i) {
      EXPECT_EQ(f20[i].element, faces[i].element);
      EXPECT_EQ(f20[i].edge, faces[i].edge);
    }
  }
  for (const char *corner : {"corner_000", "corner_111", "corner_101"})
    for (int i = 0; i < 3; ++i)
      EXPECT_EQ(m.coordinate(m.nodeSets.at(corner).front(), i),
                hex8.coordinate(hex8.nodeSets.at(corner).front(), i));
  double volume = 0.0;
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    const double v = hex20Volume(m, e);
    EXPECT_NEAR(v, hexVolume(hex8, e), 1e-12 * v) << "element " << e; // straight edges: a brick
    volume += v;
  }
  EXPECT_NEAR(volume, lx * ly * lz, 1e-12 * lx * ly * lz);
  // Numbering: the half-step lattice, I fastest: node 1 is the mid-edge node of element 0's
  // first x edge, node 2 the far end of that edge.
  EXPECT_EQ(m.node(0, 0), 0);
  EXPECT_EQ(m.node(0, 8), 1);
  EXPECT_EQ(m.node(0, 1), 2);
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
  // Hex20 counts 20 nodes per element: 500^3 Hex8 elements would fit, Hex20 ones do not.
  const double most = static_cast<double>(std::numeric_limits<LocalIndex>::max());
  EXPECT_LT(8.0 * 500 * 500 * 500, most);
  EXPECT_GT(20.0 * 500 * 500 * 500, most);
  msg = generatorError([] { boxMesh(1, 1, 1, 500, 500, 500, ElementType::Hex20); });
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

/// Reads `text` as "bad.msh" and expects an InputError whose message holds
/// "bad.msh:<the line on which `marker` starts>: <message>"; returns the whole message.
std::string expectRefusedAt(const std::string &text, const std::string &marker,
                            const std::string &message) {
  const std::string msg = expectInputError([&] { readText(text, "bad.msh"); });
  EXPECT_NE(msg.find("bad.msh:" + std::to_string(lineOf(text, marker)) + ": " + message),
            std::string::npos)
      << msg;
  return msg;
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
/// Gmsh's node k of a 20-node hexahedron is internal node gmshToInternal()[k] (from the two edge
/// tables: the mid-edge node of the same two corners).
std::array<int, 20> gmshToInternal() {
  std::array<int, 20> p{};
  for (int a = 0; a < 8; ++a)
    p[a] = a;
  for (int k = 0; k < 12; ++k) {
    p[8 + k] = -1;
    for (int j = 0; j < 12; ++j)
      if (std::min(kVtkEdge[j][0], kVtkEdge[j][1]) == std::min(kGmshEdge[k][0], kGmshEdge[k][1]) &&
          std::max(kVtkEdge[j][0], kVtkEdge[j][1]) == std::max(kGmshEdge[k][0], kGmshEdge[k][1]))
        p[8 + k] = 8 + j;
    EXPECT_GE(p[8 + k], 8) << "Gmsh edge " << k;
  }
  return p;
}

/// How writeGmshSolid writes one element family: Gmsh's volume and face types, the corners per
/// face, node sets as points (type 15) or as curves of degenerate lines (type 1 or 8), and Gmsh's
/// node k as internal node order[k] (empty: the same numbering).
struct GmshSolidLayout {
  int volumeType = 5, faceType = 3, faceCorners = 4;
  bool nodeSetsAsCurves = false;
  int lineType = 1; ///< curves only: 1 (2-node) or 8 (3-node)
  std::vector<int> order;
};

/// Writes a 3D mesh as Gmsh 4.1 ASCII in Gmsh's node order: one volume (physical "body"), one
/// surface per boundary (physical groups of the same names) whose face elements are the boundary
/// faces' corner nodes, rotated by the face number and, for odd elements, in the other turning
/// sense (the reader must not depend on either), then for quadratic faces the mid-edge nodes of
/// the face element's edges in that order; one point or curve per node set. Node tags 5 + 2 n,
/// element tags 1000 + e.
std::string writeGmshSolid(const Mesh &m, const GmshSolidLayout &l) {
  const bool quadratic = m.nodesPerSide() > l.faceCorners;
  const int fc = l.faceCorners;
  std::ostringstream s;
  std::vector<std::string> bnames, snames;
  for (const auto &[name, faces] : m.boundaries)
    bnames.push_back(name);
  for (const auto &[name, nodes] : m.nodeSets)
    snames.push_back(name);
  const int setDim = l.nodeSetsAsCurves ? 1 : 0;
  s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n"
    << 1 + bnames.size() + snames.size() << "\n3 1 \"body\"\n";
  for (std::size_t i = 0; i < bnames.size(); ++i)
    s << "2 " << 10 + i << " \"" << bnames[i] << "\"\n";
  for (std::size_t i = 0; i < snames.size(); ++i)
    s << setDim << " " << 100 + i << " \"" << snames[i] << "\"\n";
  s << "$EndPhysicalNames\n$Entities\n";
  if (l.nodeSetsAsCurves)
    s << "0 " << snames.size() << " " << bnames.size() << " 1\n";
  else
    s << snames.size() << " 0 " << bnames.size() << " 1\n";
  for (std::size_t i = 0; i < snames.size(); ++i)
    s << i + 1 << (l.nodeSetsAsCurves ? " 0 0 0 1 1 1 1 " : " 0 0 0 1 ") << 100 + i
      << (l.nodeSetsAsCurves ? " 0\n" : "\n");
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
  s << 1 + bnames.size() + snames.size() << " " << count << " 1 " << 1000 + m.numElements() << "\n";
  long id = 1;
  for (std::size_t i = 0; i < snames.size(); ++i) {
    const auto &nodes = m.nodeSets.at(snames[i]);
    s << setDim << " " << i + 1 << " " << (l.nodeSetsAsCurves ? l.lineType : 15) << " "
      << nodes.size() << "\n";
    for (LocalIndex n : nodes) {
      s << id++ << " " << tag(n);
      if (l.nodeSetsAsCurves)
        s << " " << tag(n) << (l.lineType == 8 ? " " + std::to_string(tag(n)) : "");
      s << "\n";
    }
  }
  for (std::size_t i = 0; i < bnames.size(); ++i) {
    const auto &faces = m.boundaries.at(bnames[i]);
    s << "2 " << i + 1 << " " << l.faceType << " " << faces.size() << "\n";
    for (const BoundaryEdge &f : faces) {
      s << id++;
      std::vector<int> corner(fc); // the face corners in the face element's order
      for (int k = 0; k < fc; ++k) {
        const int r = (k + f.edge) % fc;
        corner[k] = f.element % 2 ? fc - 1 - r : r;
        s << " " << tag(m.sideNode(f, corner[k]));
      }
      // Face node fc + c lies between face corners c and c + 1.
      for (int k = 0; k < fc && quadratic; ++k) {
        const int c0 = corner[k], c1 = corner[(k + 1) % fc];
        s << " " << tag(m.sideNode(f, fc + (c1 == (c0 + 1) % fc ? c0 : c1)));
      }
      s << "\n";
    }
  }
  s << "3 1 " << l.volumeType << " " << m.numElements() << "\n";
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    s << 1000 + e;
    for (int a = 0; a < m.nodesPerElement; ++a)
      s << " " << tag(m.node(e, l.order.empty() ? a : l.order[a]));
    s << "\n";
  }
  s << "$EndElements\n";
  return s.str();
}

/// A Hex8 or Hex20 mesh as Gmsh (type 5 or 17, quadrangle faces 3 or 16), node sets as points.
std::string toGmsh3D(const Mesh &m) {
  const bool hex20 = m.elementType == ElementType::Hex20;
  GmshSolidLayout l;
  l.volumeType = hex20 ? 17 : 5;
  l.faceType = hex20 ? 16 : 3;
  if (hex20) {
    const std::array<int, 20> order = gmshToInternal();
    l.order.assign(order.begin(), order.end());
  }
  return writeGmshSolid(m, l);
}
} // namespace

namespace {
/// A mesh read back from toGmsh3D(box) (element tags 1000 + e, node tags 5 + 2 n) is the box.
void expectSameAsWritten(const Mesh &m, const Mesh &box) {
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
} // namespace

TEST(GmshReader3D, RoundTripOfAGradedBoxKeepsGeometryTopologyAndGroups) {
  const Mesh box = boxMesh(2.0, 1.0, 0.5, 3, 2, 2, ElementType::Hex8, -1.0, 0.0, 0.25, 1.3);
  const Mesh m = readText(toGmsh3D(box), "box.msh");
  EXPECT_EQ(m.elementType, ElementType::Hex8);
  expectSameAsWritten(m, box);
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
  std::string msg =
      expectRefusedAt(bad, "5 103 109 111 105",
                      "quadrangle element 5 of boundary 'right' is not a face of any hexahedron");
  // The same quadrangle in a surface without a physical group: a 2D element among the 3D ones.
  bad = t;
  bad = replaced(bad, "2 2 0 0 2 1 1 1 3 0", "2 2 0 0 2 1 1 0 0");
  bad = replaced(bad, "5 103 109 112 106", "5 103 109 111 105");
  msg = expectRefusedAt(bad, "5 103 109 111 105",
                        "quadrangle element 5 (surface 2) is not a face of any hexahedron");
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
  msg = expectRefusedAt(bad, "3 1 4 1",
                        "mixed volume element types: element type 4 (4-node tetrahedron)");
  // A prism block is an unsupported type.
  bad = t;
  bad = replaced(bad, "3 1 5 2\n", "3 1 6 2\n");
  msg = expectRefusedAt(bad, "3 1 6 2", "unsupported element type 6 (6-node prism)");
  EXPECT_NE(msg.find("8-node (type 5) and 20-node (type 17) hexahedra"), std::string::npos) << msg;
  // 8-node quadrangles next to hexahedra.
  bad = t;
  bad = replaced(bad, "2 1 3 1\n4 101 107 110 104", "2 1 16 1\n4 101 107 110 104 101 107 110 104");
  bad = replaced(bad, "2 2 3 1\n5 103 109 112 106", "2 2 16 1\n5 103 109 112 106 103 109 112 106");
  msg = expectRefusedAt(bad, "4 101 107 110 104",
                        "8-node quadrangles (type 16) in a mesh of 8-node hexahedra");
  // A hexahedron that references a node that does not exist.
  bad = t;
  bad = replaced(bad, "22 102 103", "22 102 999");
  msg = expectRefusedAt(bad, "22 102 999", "element 22 references unknown node 999");
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
  const std::string msg = expectRefusedAt(
      bad, "1 1 0.5", "node 3 has a non-zero z coordinate; mixcon meshes are planar (z = 0)");
}

TEST(GmshReader3D, RoundTripOfAGradedHex20BoxKeepsGeometryTopologyAndGroups) {
  const Mesh box =
      boxMesh(2.0, 1.0, 0.5, 3, 2, 2, ElementType::Hex20, -1.0, 0.0, 0.25, 1.3, 1.0, 1.6);
  const std::string text = toGmsh3D(box);
  ASSERT_NE(text.find("\n3 1 17 12\n"), std::string::npos); // 20-node hexahedra
  ASSERT_NE(text.find("\n2 1 16 "), std::string::npos);     // 8-node quadrangles
  const Mesh m = readText(text, "box20.msh");
  EXPECT_EQ(m.elementType, ElementType::Hex20);
  EXPECT_EQ(m.nodesPerElement, 20);
  expectSameAsWritten(m, box);
}

namespace {
/// A 2 x 1 x 1 box of two 20-node hexahedra written by hand in Gmsh's node order. Its nodes are
/// the points (I, J, K) / 2, 0 <= I <= 4, 0 <= J, K <= 2, with at most one odd index, tagged
/// 1 + I + 5 J + 15 K. Groups: volume "body"; surface "right" (x = 2), one 8-node quadrangle;
/// curve "edge" (y = z = 0), two 3-node lines; point "origin".
struct Hex20File {
  using P = std::array<int, 3>;
  static long tag(const P &p) { return 1 + p[0] + 5 * p[1] + 15 * p[2]; }
  /// " t1 t2 ..." of the points.
  static std::string tags(const std::vector<P> &points) {
    std::string s;
    for (const P &p : points)
      s += " " + std::to_string(tag(p));
    return s;
  }
  /// Lattice point of corner c of element e.
  static P corner(int e, int c) {
    return {2 * e + kCorner[c][0] + 1, kCorner[c][1] + 1, kCorner[c][2] + 1};
  }
  static P middle(const P &a, const P &b) {
    return {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
  }
  /// Element e's nodes by an edge table (Gmsh's or VTK's).
  static std::vector<P> nodes(int e, const int (&edges)[12][2]) {
    std::vector<P> v;
    for (int c = 0; c < 8; ++c)
      v.push_back(corner(e, c));
    for (int k = 0; k < 12; ++k)
      v.push_back(middle(corner(e, edges[k][0]), corner(e, edges[k][1])));
    return v;
  }
  /// The quadrangle of x = 2, turning counter-clockwise seen from +x, in Gmsh's (Quad8's) order.
  static std::vector<P> rightQuad() {
    const std::vector<P> c = {{4, 0, 0}, {4, 2, 0}, {4, 2, 2}, {4, 0, 2}};
    std::vector<P> q = c;
    for (int k = 0; k < 4; ++k)
      q.push_back(middle(c[k], c[(k + 1) % 4]));
    return q;
  }
  static std::string text() {
    std::vector<P> points;
    for (int K = 0; K <= 2; ++K)
      for (int J = 0; J <= 2; ++J)
        for (int I = 0; I <= 4; ++I)
          if (I % 2 + J % 2 + K % 2 <= 1)
            points.push_back({I, J, K});
    std::ostringstream s;
    s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n0 4 \"origin\"\n1 5 "
         "\"edge\"\n2 3 \"right\"\n3 1 \"body\"\n$EndPhysicalNames\n$Entities\n1 1 1 1\n1 0 0 0 1 "
         "4\n1 0 0 0 2 0 0 1 5 0\n2 2 0 0 2 1 1 1 3 0\n1 0 0 0 2 1 1 1 1 0\n$EndEntities\n";
    s << "$Nodes\n1 " << points.size() << " 1 " << tag({4, 2, 2}) << "\n3 1 0 " << points.size()
      << "\n";
    for (const P &p : points)
      s << tag(p) << "\n";
    for (const P &p : points)
      s << 0.5 * p[0] << " " << 0.5 * p[1] << " " << 0.5 * p[2] << "\n";
    s << "$EndNodes\n$Elements\n4 6 1 22\n0 1 15 1\n1" << tags({{0, 0, 0}}) << "\n1 1 8 2\n2"
      << tags({{0, 0, 0}, {2, 0, 0}, {1, 0, 0}}) << "\n3" << tags({{2, 0, 0}, {4, 0, 0}, {3, 0, 0}})
      << "\n2 2 16 1\n5" << tags(rightQuad()) << "\n3 1 17 2\n21" << tags(nodes(0, kGmshEdge))
      << "\n22" << tags(nodes(1, kGmshEdge)) << "\n$EndElements\n";
    return s.str();
  }
};
} // namespace

TEST(GmshReader3D, ReadsHex20InGmshOrderIntoTheInternalOrder) {
  using F = Hex20File;
  const std::string text = F::text();
  const Mesh m = readText(text, "two20.msh");
  EXPECT_EQ(m.elementType, ElementType::Hex20);
  EXPECT_EQ(m.nodesPerElement, 20);
  EXPECT_EQ(m.numNodes(), 12 + 8 + 6 + 6); // corners, x, y and z edges
  EXPECT_EQ(m.numElements(), 2);
  EXPECT_EQ(m.elementIds, (std::vector<long>{21, 22}));
  // The connectivity in VTK's order, node by node (by tag).
  for (int e = 0; e < 2; ++e) {
    const std::vector<F::P> expected = F::nodes(e, kVtkEdge);
    for (int a = 0; a < 20; ++a)
      EXPECT_EQ(m.nodeId(m.node(e, a)), F::tag(expected[a])) << "element " << e << " node " << a;
  }
  EXPECT_NO_THROW(validateMesh(m));
  EXPECT_NEAR(hex20Volume(m, 0) + hex20Volume(m, 1), 2.0, 1e-14);
  expectMidEdgeNodesAtMidpoints(m);
  ASSERT_EQ(m.regionNames, std::vector<std::string>{"body"});
  // The 8-node quadrangle is face x+ (3) of element 22, all eight nodes.
  ASSERT_TRUE(m.hasBoundary("right"));
  ASSERT_EQ(m.boundaries.at("right").size(), 1u);
  const BoundaryEdge f = m.boundaries.at("right").front();
  EXPECT_EQ(f.element, 1);
  EXPECT_EQ(f.edge, 3);
  std::set<long> tags, quad;
  for (int k = 0; k < m.nodesPerSide(); ++k)
    tags.insert(m.nodeId(m.sideNode(f, k)));
  for (const F::P &p : F::rightQuad())
    quad.insert(F::tag(p));
  EXPECT_EQ(tags, quad);
  EXPECT_NEAR(faceNormal(m, f)[0], 1.0, 1e-14);
  // Node sets: the 3-node lines' five nodes, the point's node.
  std::vector<LocalIndex> edge;
  for (int i = 0; i <= 4; ++i)
    edge.push_back(nodeOfTag(m, F::tag({i, 0, 0})));
  std::sort(edge.begin(), edge.end());
  EXPECT_EQ(m.nodeSets.at("edge"), edge);
  EXPECT_EQ(m.nodeSets.at("origin"), std::vector<LocalIndex>{nodeOfTag(m, 1)});
}

TEST(GmshReader3D, Hex20RefusesQuadranglesThatAreNoFaceMidEdgeMismatchesAndMixedOrders) {
  using F = Hex20File;
  using P = F::P;
  const std::string t = F::text();
  const std::string quad = "5" + F::tags(F::rightQuad());
  // An 8-node quadrangle whose corners are no face (a diagonal plane).
  const std::string diagonal =
      "5" +
      F::tags(
          {{4, 0, 0}, {4, 2, 0}, {2, 2, 2}, {2, 0, 2}, {4, 1, 0}, {4, 2, 1}, {4, 1, 2}, {4, 0, 1}});
  std::string bad = replaced(t, quad, diagonal);
  std::string msg = expectRefusedAt(
      bad, diagonal, "quadrangle element 5 of boundary 'right' is not a face of any hexahedron");
  // The right corners, but the mid-edge nodes of edges 1-2 and 2-3 swapped.
  std::vector<P> q = F::rightQuad();
  std::swap(q[5], q[6]);
  const std::string swapped = "5" + F::tags(q);
  bad = replaced(t, quad, swapped);
  msg = expectRefusedAt(bad, swapped,
                        "quadrangle element 5 of boundary 'right': its mid-edge node " +
                            std::to_string(F::tag(q[5])) + " (between nodes " +
                            std::to_string(F::tag(q[1])) + " and " + std::to_string(F::tag(q[2])) +
                            ") is not the hexahedron's mid-edge node of that edge, " +
                            std::to_string(F::tag(q[6])));
  // A 4-node quadrangle on a 20-node hexahedron.
  const std::string corners = "5" + F::tags({q[0], q[1], q[2], q[3]});
  bad = replaced(replaced(t, quad, corners), "2 2 16 1", "2 2 3 1");
  msg = expectRefusedAt(bad, corners, "4-node quadrangles (type 3) in a mesh of 20-node hexahedra");
  // A 2-node line (a curve of the other order).
  const std::string line2 = "3" + F::tags({{2, 0, 0}, {4, 0, 0}});
  bad = replaced(t,
                 "1 1 8 2\n2" + F::tags({{0, 0, 0}, {2, 0, 0}, {1, 0, 0}}) + "\n3" +
                     F::tags({{2, 0, 0}, {4, 0, 0}, {3, 0, 0}}),
                 "1 1 1 1\n" + line2);
  bad = replaced(bad, "4 6 1 22", "4 5 1 22");
  msg = expectRefusedAt(bad, line2, "line element 3 has 2 nodes in a mesh of 20-node hexahedra");
  // 20-node hexahedra followed by 8-node ones: mixed orders, at the second block's line.
  bad = replaced(t, "4 6 1 22", "5 7 1 23");
  std::vector<P> hex8;
  for (int c = 0; c < 8; ++c)
    hex8.push_back(F::corner(0, c));
  bad = replaced(bad, "$EndElements", "3 1 5 1\n23" + F::tags(hex8) + "\n$EndElements");
  msg = expectRefusedAt(bad, "3 1 5 1",
                        "mixed volume element types: element type 5 (8-node hexahedron) after "
                        "element type 17 (20-node hexahedron)");
  // ... and the other way round, in the 8-node file: a 20-node block after the 8-node one.
  bad = replaced(kGmshHex, "5 7 1 22", "6 8 1 23");
  bad = replaced(bad, "$EndElements",
                 "3 1 17 1\n23 101 102 105 104 107 108 111 110 101 102 105 104 107 108 111 110 "
                 "101 102 105 104\n$EndElements");
  msg = expectRefusedAt(bad, "3 1 17 1",
                        "mixed volume element types: element type 17 (20-node hexahedron) after "
                        "element type 5 (8-node hexahedron)");
  // A 3-node line in the 8-node file.
  bad = replaced(kGmshHex, "1 1 1 2\n2 101 102\n3 102 103", "1 1 8 1\n2 101 103 102");
  bad = replaced(bad, "5 7 1 22", "5 6 1 22");
  msg = expectRefusedAt(bad, "2 101 103 102",
                        "line element 2 has 3 nodes in a mesh of 8-node hexahedra");
}

// ---- Tetrahedra: the box split into 6 tetrahedra per cell (Tet4, Tet10) ----

namespace {

/// Host reference: signed volume of the straight tetrahedron of an element's first four nodes,
/// det(x1 - x0, x2 - x0, x3 - x0) / 6.
double tetVolume(const Mesh &m, LocalIndex e) {
  const Vec3 x0 = point(m, m.node(e, 0));
  const Vec3 a = minus(point(m, m.node(e, 1)), x0), b = minus(point(m, m.node(e, 2)), x0),
             c = minus(point(m, m.node(e, 3)), x0);
  const Vec3 n = cross(a, b);
  return (n[0] * c[0] + n[1] * c[1] + n[2] * c[2]) / 6.0;
}

/// The internal (VTK) Tet10 edges: mid-edge node 4 + k lies between corners kTetEdge[k].
constexpr int kTetEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

/// Checks a box of tetrahedra against host references: node and element counts, positive
/// volumes adding up to the box, validateMesh, the boundary triangles on their planes with
/// outward normals and the face areas, conformity (every triangle shared by two tetrahedra
/// unless it is a boundary face), Tet10 mid-edge nodes (of elements and faces) at the midpoints,
/// and the node sets at the coordinates of the Hex8 box's.
void expectTetBox(const Mesh &m, const double (&l)[3], const int (&n)[3], const double (&o)[3],
                  const double (&g)[3]) {
  const bool quadratic = m.elementType == ElementType::Tet10;
  const int step = quadratic ? 2 : 1;
  EXPECT_EQ(m.nodesPerElement, quadratic ? 10 : 4);
  EXPECT_EQ(m.numElements(), 6 * n[0] * n[1] * n[2]);
  EXPECT_EQ(m.numNodes(), (step * n[0] + 1) * (step * n[1] + 1) * (step * n[2] + 1));
  EXPECT_NO_THROW(validateMesh(m));
  double volume = 0.0;
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    const double v = tetVolume(m, e);
    EXPECT_GT(v, 0.0) << "element " << e;
    volume += v;
  }
  EXPECT_NEAR(volume, l[0] * l[1] * l[2], 1e-12 * l[0] * l[1] * l[2]);
  if (quadratic) {
    for (LocalIndex e = 0; e < m.numElements(); ++e)
      for (int k = 0; k < 6; ++k) {
        const Vec3 a = point(m, m.node(e, kTetEdge[k][0])), b = point(m, m.node(e, kTetEdge[k][1]));
        const Vec3 c = point(m, m.node(e, 4 + k));
        for (int i = 0; i < 3; ++i)
          EXPECT_NEAR(c[i], 0.5 * (a[i] + b[i]), 1e-13) << "element " << e << " edge " << k;
      }
    // No two nodes coincide.
    std::set<Vec3> distinct;
    for (LocalIndex p = 0; p < m.numNodes(); ++p)
      distinct.insert(point(m, p));
    EXPECT_EQ(static_cast<LocalIndex>(distinct.size()), m.numNodes());
  }
  // Conformity: count the tetrahedra on each corner triangle.
  std::map<std::array<LocalIndex, 3>, int> shared;
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    for (int f = 0; f < 4; ++f) {
      std::array<LocalIndex, 3> key{};
      for (int k = 0; k < 3; ++k)
        key[k] = m.node(e, Tet4::sideNode(f, k));
      std::sort(key.begin(), key.end());
      ++shared[key];
    }
  std::set<std::array<LocalIndex, 3>> boundary;
  const char *names[3][2] = {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}};
  for (int d = 0; d < 3; ++d)
    for (int end = 0; end < 2; ++end) {
      const std::string name = names[d][end];
      ASSERT_EQ(m.boundaries.count(name), 1u) << name;
      const auto &faces = m.boundaries.at(name);
      const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
      EXPECT_EQ(faces.size(), static_cast<std::size_t>(2 * n[d1] * n[d2])) << name;
      const double plane = o[d] + end * l[d];
      double area = 0.0;
      for (const BoundaryEdge &f : faces) {
        EXPECT_EQ(m.nodesPerSide(), quadratic ? 6 : 3);
        const Vec3 x0 = point(m, m.sideNode(f, 0));
        const Vec3 x1 = point(m, m.sideNode(f, 1)), x2 = point(m, m.sideNode(f, 2));
        for (int k = 0; k < m.nodesPerSide(); ++k)
          EXPECT_NEAR(point(m, m.sideNode(f, k))[d], plane, 1e-12) << name << " node " << k;
        const Vec3 nrm = cross(minus(x1, x0), minus(x2, x0));
        EXPECT_GT(end == 0 ? -nrm[d] : nrm[d], 0.0) << name << ": the normal points inward";
        EXPECT_NEAR(std::abs(nrm[d]), norm(nrm), 1e-12 * norm(nrm)) << name;
        area += 0.5 * norm(nrm);
        if (quadratic)
          for (int k = 0; k < 3; ++k) {
            const Vec3 a = point(m, m.sideNode(f, k)), b = point(m, m.sideNode(f, (k + 1) % 3));
            const Vec3 c = point(m, m.sideNode(f, 3 + k));
            for (int i = 0; i < 3; ++i)
              EXPECT_NEAR(c[i], 0.5 * (a[i] + b[i]), 1e-13) << name << " face node " << 3 + k;
          }
        std::array<LocalIndex, 3> key{m.sideNode(f, 0), m.sideNode(f, 1), m.sideNode(f, 2)};
        std::sort(key.begin(), key.end());
        EXPECT_TRUE(boundary.insert(key).second) << name << ": a face listed twice";
      }
      EXPECT_NEAR(area, l[d1] * l[d2], 1e-12 * l[d1] * l[d2]) << name;
    }
  for (const auto &[key, count] : shared)
    EXPECT_EQ(count, boundary.count(key) ? 1 : 2)
        << "triangle " << key[0] << " " << key[1] << " " << key[2];
  // Node sets: the corners at the coordinates of the hexahedral box's; the face centres the node
  // of the face closest to its centre (Tet10 has face-centre nodes that Hex20 has not).
  const Mesh hex = boxMesh(l[0], l[1], l[2], n[0], n[1], n[2],
                           quadratic ? ElementType::Hex20 : ElementType::Hex8, o[0], o[1], o[2],
                           g[0], g[1], g[2]);
  ASSERT_EQ(m.nodeSets.size(), hex.nodeSets.size());
  for (const auto &[name, nodes] : hex.nodeSets) {
    ASSERT_EQ(m.nodeSets.count(name), 1u) << name;
    ASSERT_EQ(m.nodeSets.at(name).size(), nodes.size()) << name;
    const Vec3 got = point(m, m.nodeSets.at(name).front());
    if (name.find("_center") == std::string::npos) {
      EXPECT_EQ(got, point(hex, nodes.front())) << name;
      continue;
    }
    const double x = name == "xmin_center" ? o[0] : o[0] + l[0];
    const Vec3 centre{x, o[1] + 0.5 * l[1], o[2] + 0.5 * l[2]};
    EXPECT_EQ(got[0], x) << name;
    double best = std::numeric_limits<double>::infinity();
    for (LocalIndex p = 0; p < m.numNodes(); ++p)
      if (m.x(p) == x)
        best = std::min(best, norm(minus(point(m, p), centre)));
    EXPECT_EQ(norm(minus(got, centre)), best) << name;
  }
}

} // namespace

TEST(BoxMesh, Tet4SplitsEachCellIntoSixConformingPositiveTetrahedra) {
  const double l[3] = {2.0, 1.0, 0.5}, o[3] = {-1.0, 0.5, 0.25}, g[3] = {1.0, 1.0, 1.0};
  const int n[3] = {3, 2, 2};
  const Mesh m = boxMesh(l[0], l[1], l[2], n[0], n[1], n[2], ElementType::Tet4, o[0], o[1], o[2]);
  EXPECT_EQ(m.elementType, ElementType::Tet4);
  expectTetBox(m, l, n, o, g);
  // Tet4 nodes are the Hex8 box's nodes.
  const Mesh hex = boxMesh(l[0], l[1], l[2], n[0], n[1], n[2], ElementType::Hex8, o[0], o[1], o[2]);
  EXPECT_EQ(m.coordinates, hex.coordinates);
  // The six tetrahedra of a cell share its main diagonal (Hex8 corners 0 and 6).
  for (LocalIndex c = 0; c < hex.numElements(); ++c)
    for (int t = 0; t < 6; ++t) {
      std::set<LocalIndex> corners;
      for (int a = 0; a < 4; ++a)
        corners.insert(m.node(6 * c + t, a));
      EXPECT_EQ(corners.count(hex.node(c, 0)), 1u) << "cell " << c;
      EXPECT_EQ(corners.count(hex.node(c, 6)), 1u) << "cell " << c;
    }
}

TEST(BoxMesh, GradedTet4AndTet10BoxesKeepPositiveConformingElements) {
  const double l[3] = {1.5, 2.0, 1.0}, o[3] = {0.5, 0.0, -1.0}, g[3] = {1.4, 1.0, 1.7};
  const int n[3] = {2, 3, 2};
  for (ElementType type : {ElementType::Tet4, ElementType::Tet10}) {
    SCOPED_TRACE(elementTypeName(type));
    expectTetBox(
        boxMesh(l[0], l[1], l[2], n[0], n[1], n[2], type, o[0], o[1], o[2], g[0], g[1], g[2]), l, n,
        o, g);
  }
}

TEST(BoxMesh, Tet10HasAMidEdgeNodeOnEveryEdgeIncludingTheDiagonals) {
  const double l[3] = {1.0, 2.0, 3.0}, o[3] = {0.0, 0.0, 0.0}, g[3] = {1.0, 1.0, 1.0};
  const int n[3] = {2, 2, 3};
  const Mesh m = boxMesh(l[0], l[1], l[2], n[0], n[1], n[2], ElementType::Tet10);
  expectTetBox(m, l, n, o, g);
  // Its corners are the Tet4 box's corners, element by element.
  const Mesh t4 = boxMesh(l[0], l[1], l[2], n[0], n[1], n[2], ElementType::Tet4);
  ASSERT_EQ(m.numElements(), t4.numElements());
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    for (int a = 0; a < 4; ++a)
      EXPECT_EQ(point(m, m.node(e, a)), point(t4, t4.node(e, a))) << e;
  // Every edge (distinct corner pair) has exactly one mid-edge node, shared by all its elements.
  std::map<std::pair<LocalIndex, LocalIndex>, std::set<LocalIndex>> middles;
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    for (int k = 0; k < 6; ++k) {
      LocalIndex a = m.node(e, kTetEdge[k][0]), b = m.node(e, kTetEdge[k][1]);
      middles[{std::min(a, b), std::max(a, b)}].insert(m.node(e, 4 + k));
    }
  for (const auto &[edge, nodes] : middles)
    EXPECT_EQ(nodes.size(), 1u) << edge.first << "-" << edge.second;
  // Vertices + edges of the split: every lattice point is a corner or one edge's middle.
  EXPECT_EQ(static_cast<LocalIndex>(t4.numNodes() + middles.size()), m.numNodes());
}

// ---- Gmsh 4.1 tetrahedra (types 4 and 11) with triangle faces (types 2 and 9) ----

namespace {
// Two tetrahedra sharing the face 2 3 4: 1 2 3 4 (the corner of the unit cube) and 2 3 4 5 with
// node 5 at (1, 1, 1). Physical groups: volume "body"; surfaces "bottom" (z = 0, triangle 1 3 2
// turning like the element's face, outward -z) and "back" (x = 0, triangle 1 3 4 turning the
// other way); curve "edge" (the line 1-2); point "origin" (node 1).
const char *kGmshTet = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
5
0 4 "origin"
1 5 "edge"
2 2 "bottom"
2 3 "back"
3 1 "body"
$EndPhysicalNames
$Entities
1 1 2 1
1 0 0 0 1 4
1 0 0 0 1 0 0 1 5 0
1 0 0 0 1 1 0 1 2 0
2 0 0 0 0 1 1 1 3 0
1 0 0 0 1 1 1 1 1 0
$EndEntities
$Nodes
1 5 1 5
3 1 0 5
1
2
3
4
5
0 0 0
1 0 0
0 1 0
0 0 1
1 1 1
$EndNodes
$Elements
5 6 1 32
0 1 15 1
1 1
1 1 1 1
2 1 2
2 1 2 1
10 1 3 2
2 2 2 1
11 1 3 4
3 1 4 2
31 1 2 3 4
32 2 3 4 5
$EndElements
)";

/// Gmsh's node k of a 10-node tetrahedron is internal node gmshToInternalTet()[k]: Gmsh's
/// mid-edge nodes 4..9 lie on its edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1 (Gmsh manual, "High-order
/// elements"), matched to the internal edges kTetEdge by their corners.
std::array<int, 10> gmshToInternalTet() {
  constexpr int gmshEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  std::array<int, 10> p{0, 1, 2, 3, -1, -1, -1, -1, -1, -1};
  for (int k = 0; k < 6; ++k) {
    for (int j = 0; j < 6; ++j)
      if (std::min(kTetEdge[j][0], kTetEdge[j][1]) == std::min(gmshEdge[k][0], gmshEdge[k][1]) &&
          std::max(kTetEdge[j][0], kTetEdge[j][1]) == std::max(gmshEdge[k][0], gmshEdge[k][1]))
        p[4 + k] = 4 + j;
    EXPECT_GE(p[4 + k], 4) << "Gmsh edge " << k;
  }
  return p;
}

/// A Tet4 or Tet10 mesh as Gmsh (type 4 or 11, triangle faces 2 or 9), node sets as curves of
/// degenerate lines (type 1 or 8).
std::string toGmshTet(const Mesh &m) {
  const bool tet10 = m.elementType == ElementType::Tet10;
  GmshSolidLayout l;
  l.volumeType = tet10 ? 11 : 4;
  l.faceType = tet10 ? 9 : 2;
  l.faceCorners = 3;
  l.nodeSetsAsCurves = true;
  l.lineType = tet10 ? 8 : 1;
  if (tet10) {
    const std::array<int, 10> order = gmshToInternalTet();
    l.order.assign(order.begin(), order.end());
  }
  return writeGmshSolid(m, l);
}
} // namespace

TEST(GmshReaderTet, ReadsTetrahedraWithRegionsTriangleFacesAndNodeSets) {
  const Mesh m = readText(kGmshTet);
  EXPECT_EQ(m.elementType, ElementType::Tet4);
  EXPECT_EQ(m.dim(), 3);
  EXPECT_EQ(m.nodesPerElement, 4);
  EXPECT_EQ(m.numNodes(), 5);
  EXPECT_EQ(m.elementIds, (std::vector<long>{31, 32}));
  ASSERT_EQ(m.regionNames, std::vector<std::string>{"body"});
  EXPECT_EQ(m.elementRegion, (std::vector<int>{0, 0}));
  EXPECT_NO_THROW(validateMesh(m));
  EXPECT_NEAR(tetVolume(m, 0), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(tetVolume(m, 1), 1.0 / 3.0, 1e-15);
  // Boundaries: element 31's faces, nodes those of the triangle, normal outward.
  struct Expected {
    const char *name;
    std::set<long> tags;
    int axis;
    double sign;
  };
  const Expected expected[] = {{"bottom", {1, 2, 3}, 2, -1.0}, {"back", {1, 3, 4}, 0, -1.0}};
  for (const Expected &x : expected) {
    SCOPED_TRACE(x.name);
    ASSERT_TRUE(m.hasBoundary(x.name));
    ASSERT_EQ(m.boundaries.at(x.name).size(), 1u);
    const BoundaryEdge f = m.boundaries.at(x.name).front();
    EXPECT_EQ(f.element, 0);
    EXPECT_EQ(m.nodesPerSide(), 3);
    std::set<long> tags;
    for (int k = 0; k < 3; ++k)
      tags.insert(m.nodeIds[m.sideNode(f, k)]);
    EXPECT_EQ(tags, x.tags);
    const Vec3 x0 = point(m, m.sideNode(f, 0));
    const Vec3 n =
        cross(minus(point(m, m.sideNode(f, 1)), x0), minus(point(m, m.sideNode(f, 2)), x0));
    EXPECT_NEAR(n[x.axis] / norm(n), x.sign, 1e-14);
  }
  EXPECT_EQ(m.nodeSets.at("origin"), std::vector<LocalIndex>{nodeOfTag(m, 1)});
  std::vector<LocalIndex> edge = {nodeOfTag(m, 1), nodeOfTag(m, 2)};
  std::sort(edge.begin(), edge.end());
  EXPECT_EQ(m.nodeSets.at("edge"), edge);
  // A triangle on the shared face 2 3 4 matches the element its turn points out of.
  for (const bool reversed : {false, true}) {
    const Mesh i = readText(replaced(kGmshTet, "11 1 3 4", reversed ? "11 2 4 3" : "11 2 3 4"));
    const BoundaryEdge f = i.boundaries.at("back").front();
    EXPECT_EQ(f.element, reversed ? 1 : 0) << reversed;
    const Vec3 x0 = point(i, i.sideNode(f, 0));
    const Vec3 n =
        cross(minus(point(i, i.sideNode(f, 1)), x0), minus(point(i, i.sideNode(f, 2)), x0));
    // The face x + y + z = 1 of the corner tetrahedron points to +(1, 1, 1).
    EXPECT_GT(reversed ? -n[0] : n[0], 0.0) << reversed;
  }
}

TEST(GmshReaderTet, ReadsTet10InGmshOrderIntoTheInternalOrder) {
  // One 10-node tetrahedron, corners as kGmshTet's first; mid-edge node tags 10 + Gmsh's number,
  // each at the middle of Gmsh's edge (0-1, 1-2, 2-0, 3-0, 3-2, 3-1), written in Gmsh's order.
  const double corner[4][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
  constexpr int gmshEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  std::ostringstream s;
  s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 2 \"bottom\"\n3 1 \"body\"\n"
       "$EndPhysicalNames\n$Entities\n0 0 1 1\n1 0 0 0 2 2 0 1 2 0\n1 0 0 0 2 2 2 1 1 0\n"
       "$EndEntities\n$Nodes\n1 10 1 19\n3 1 0 10\n";
  for (int a = 0; a < 4; ++a)
    s << a + 1 << "\n";
  for (int k = 0; k < 6; ++k)
    s << 14 + k << "\n";
  for (int a = 0; a < 4; ++a)
    s << corner[a][0] << " " << corner[a][1] << " " << corner[a][2] << "\n";
  for (int k = 0; k < 6; ++k)
    for (int i = 0; i < 3; ++i)
      s << 0.5 * (corner[gmshEdge[k][0]][i] + corner[gmshEdge[k][1]][i]) << (i < 2 ? " " : "\n");
  // The bottom face 1 3 2 (Tri6: corners, then the middles of 1-3, 3-2, 2-1: tags 16, 15, 14).
  s << "$EndNodes\n$Elements\n2 2 1 7\n2 1 9 1\n7 1 3 2 16 15 14\n3 1 11 1\n"
       "6 1 2 3 4 14 15 16 17 18 19\n$EndElements\n";
  const std::string text = s.str();
  const Mesh m = readText(text, "tet10.msh");
  EXPECT_EQ(m.elementType, ElementType::Tet10);
  ASSERT_EQ(m.nodesPerElement, 10);
  EXPECT_NO_THROW(validateMesh(m));
  for (int k = 0; k < 6; ++k) {
    const Vec3 a = point(m, m.node(0, kTetEdge[k][0])), b = point(m, m.node(0, kTetEdge[k][1]));
    const Vec3 c = point(m, m.node(0, 4 + k));
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(c[i], 0.5 * (a[i] + b[i]), 1e-15) << "internal mid-edge node " << 4 + k;
  }
  // Internal nodes 8 (1-3) and 9 (2-3) are Gmsh's 9 (3-1) and 8 (3-2): tags 19 and 18.
  EXPECT_EQ(m.nodeId(m.node(0, 8)), 19);
  EXPECT_EQ(m.nodeId(m.node(0, 9)), 18);
  ASSERT_EQ(m.boundaries.at("bottom").size(), 1u);
  const BoundaryEdge f = m.boundaries.at("bottom").front();
  EXPECT_EQ(f.edge, 0);
  EXPECT_EQ(m.nodesPerSide(), 6);
  // A mid-edge node of the triangle that is not the tetrahedron's is refused.
  const std::string bad = replaced(text, "7 1 3 2 16 15 14", "7 1 3 2 16 14 15");
  const std::string msg = expectRefusedAt(
      bad, "7 1 3 2 16 14 15", "triangle element 7 of boundary 'bottom': its mid-edge node 14");
  EXPECT_NE(msg.find("is not the tetrahedron's mid-edge node of that edge, 15"), std::string::npos)
      << msg;
}

TEST(GmshReaderTet, RoundTripOfTet4AndTet10BoxesKeepsGeometryTopologyAndGroups) {
  for (ElementType type : {ElementType::Tet4, ElementType::Tet10}) {
    SCOPED_TRACE(elementTypeName(type));
    const Mesh box = boxMesh(2.0, 1.0, 0.5, 3, 2, 2, type, -1.0, 0.0, 0.25, 1.3, 1.0, 1.6);
    const std::string text = toGmshTet(box);
    const Mesh m = readText(text, "box.msh");
    EXPECT_EQ(m.elementType, type);
    expectSameAsWritten(m, box);
  }
}

TEST(GmshReaderTet, RefusesMixedTypesTrianglesThatAreNoFaceAndTrianglesWithoutTetrahedra) {
  const std::string t = kGmshTet;
  // A triangle whose corners are no face of a tetrahedron.
  std::string bad = replaced(t, "10 1 3 2", "10 1 3 5");
  std::string msg = expectRefusedAt(
      bad, "10 1 3 5", "triangle element 10 of boundary 'bottom' is not a face of any tetrahedron");
  // 4-node and 10-node tetrahedra in one mesh.
  bad = replaced(t, "5 6 1 32", "6 7 1 33");
  bad = replaced(bad, "$EndElements", "3 1 11 1\n33 1 2 3 4 1 2 3 4 1 2\n$EndElements");
  msg = expectRefusedAt(bad, "3 1 11 1",
                        "mixed volume element types: element type 11 (10-node tetrahedron) after "
                        "element type 4 (4-node tetrahedron)");
  // Quadrangles next to tetrahedra.
  bad = replaced(t, "2 1 2 1\n10 1 3 2", "2 1 3 1\n10 1 3 2 4");
  bad = replaced(bad, "2 2 2 1\n11 1 3 4", "2 2 3 1\n11 1 3 4 2");
  msg = expectRefusedAt(bad, "10 1 3 2 4",
                        "4-node quadrangles (type 3) in a mesh of 4-node tetrahedra; the faces of "
                        "4-node tetrahedra are 3-node triangles (type 2)");
  // Triangles and quadrangles mixed among the 2D elements.
  bad = replaced(t, "2 2 2 1\n11 1 3 4", "2 2 3 1\n11 1 3 4 2");
  msg = expectRefusedAt(bad, "2 2 3 1", "mixed 2D element types");
  // 3-node lines with 4-node tetrahedra.
  bad = replaced(t, "1 1 1 1\n2 1 2", "1 1 8 1\n2 1 2 1");
  msg =
      expectRefusedAt(bad, "2 1 2 1", "line element 2 has 3 nodes in a mesh of 4-node tetrahedra");
  // Triangles without tetrahedra: no 2D mesh of triangles.
  bad = replaced(t, "5 6 1 32", "4 4 1 11");
  bad = replaced(bad, "3 1 4 2\n31 1 2 3 4\n32 2 3 4 5\n", "");
  bad = replaced(bad, "0 0 1\n1 1 1\n", "0 0 0\n1 1 0\n"); // planar nodes
  msg = expectRefusedAt(bad, "10 1 3 2",
                        "unsupported element type 2 (3-node triangle) in a mesh without "
                        "tetrahedra");
  // An inverted tetrahedron is refused by validation (not reoriented).
  const Mesh inverted = readText(replaced(t, "31 1 2 3 4", "31 1 3 2 4"));
  msg = expectInputError([&] { validateMesh(inverted); });
  EXPECT_FALSE(msg.empty());
}
