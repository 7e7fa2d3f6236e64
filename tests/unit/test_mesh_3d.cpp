// 3D meshes of Hex8 elements (issue 17): the box generator, checked against plain host
// references (trilinear Jacobians integrated by 2x2x2 Gauss, face normals from cross products).
// Layer under test: mesh.
#include <mesh/Generators.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
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
