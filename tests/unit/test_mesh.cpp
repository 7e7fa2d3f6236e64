// Mesh generators, Gmsh 4.1 reader and mesh validation.
#include <apps/Analysis.hpp>
#include <mesh/Generators.hpp>
#include <mesh/GmshReader.hpp>
#include <support/Reference.hpp>

#include <support/Params.hpp>

#include <gtest/gtest.h>

#include <limits>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

using namespace mixcon;

namespace {
double meshArea(const Mesh &m) {
  double area = 0.0;
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    const Eigen::MatrixXd xe = test::elementCoordinates(m, e);
    for (const auto &g : test::referenceGauss(m.nodesPerElement == 4 ? 2 : 3)) {
      Eigen::VectorXd sh;
      Eigen::MatrixXd dn;
      test::referenceShape(m.nodesPerElement, g[0], g[1], sh, dn);
      area += g[2] * (xe.transpose() * dn).determinant();
    }
  }
  return area;
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

class GeneratorTest : public ::testing::TestWithParam<ElementType> {};
INSTANTIATE_TEST_SUITE_P(Elements, GeneratorTest, test::bothElements(), test::elementName);

TEST_P(GeneratorTest, RectangleCountsAreaBoundariesAndCorners) {
  const Mesh m = rectangleMesh(4.0, 1.5, 8, 3, GetParam(), 1.0, -0.5);
  EXPECT_NO_THROW(validateMesh(m));
  EXPECT_EQ(m.numElements(), 24);
  EXPECT_EQ(m.numNodes(), GetParam() == ElementType::Quad8 ? 17 * 7 - 8 * 3 : 9 * 4);
  EXPECT_NEAR(meshArea(m), 6.0, 1e-12);
  EXPECT_EQ(m.boundaries.at("left").size(), 3u);
  EXPECT_EQ(m.boundaries.at("top").size(), 8u);
  for (LocalIndex n : m.nodesOf("right"))
    EXPECT_NEAR(m.x(n), 5.0, 1e-12);
  const LocalIndex tr = m.nodeSets.at("top_right").front();
  EXPECT_NEAR(m.x(tr), 5.0, 1e-12);
  EXPECT_NEAR(m.y(tr), 1.0, 1e-12);
}

TEST_P(GeneratorTest, CurvedGeneratorsConvergeToExactAreaAndShareNodes) {
  const bool q8 = GetParam() == ElementType::Quad8;
  // Chordal (Quad4) area error is O(h^2); parabolic edges (Quad8) O(h^4).
  const Mesh annulus = quarterAnnulusMesh(1.0, 2.0, 4, 16, GetParam());
  EXPECT_NEAR(meshArea(annulus), 3 * M_PI / 4, q8 ? 1e-5 : 1e-2);
  const Mesh disk = quarterDiskMesh(1.0, 6, 4, GetParam());
  EXPECT_NO_THROW(validateMesh(disk));
  EXPECT_NEAR(meshArea(disk), M_PI / 4, q8 ? 1e-5 : 1e-2);
  EXPECT_EQ(disk.numElements(), 36 + 2 * 24);
  // Merged O-grid: Euler's formula for a planar quad mesh, V - E + F = 1 (corner nodes only).
  const Mesh disk4 = quarterDiskMesh(1.0, 6, 4, ElementType::Quad4);
  const int v = disk4.numNodes(), f = disk4.numElements();
  const int boundaryEdges =
      static_cast<int>(disk4.boundaries.at("arc").size() + disk4.boundaries.at("bottom").size() +
                       disk4.boundaries.at("left").size());
  const int edges = (4 * f + boundaryEdges) / 2;
  EXPECT_EQ(v - edges + f, 1);
  const Mesh plate = plateWithHoleMesh(1.0, 5.0, 4.0, 6, 8, GetParam(), 1.2);
  EXPECT_NO_THROW(validateMesh(plate));
  EXPECT_NEAR(meshArea(plate), 20.0 - M_PI / 4, q8 ? 1e-4 : 2e-2);
  for (LocalIndex n : plate.nodesOf("hole"))
    EXPECT_NEAR(std::hypot(plate.x(n), plate.y(n)), 1.0, 1e-12);
  for (LocalIndex n : plate.nodesOf("top"))
    EXPECT_NEAR(plate.y(n), 4.0, 1e-12);
  for (LocalIndex n : disk.nodesOf("arc"))
    EXPECT_NEAR(std::hypot(disk.x(n), disk.y(n)), 1.0, 1e-12);
}

TEST_P(GeneratorTest, PinnedPlateHasTheReportsCountsAndEvenlySpacedHoleNodes) {
  const bool q8 = GetParam() == ElementType::Quad8;
  const Mesh m = pinnedPlateMesh(0.5, 2.0, 4.0, 8.0, 4, 6, 4, 9, GetParam(), 1.25);
  EXPECT_NO_THROW(validateMesh(m));
  // The report's wood plate: 124 elements, 156 nodes (Quad4).
  EXPECT_EQ(m.numElements(), 124);
  if (!q8) {
    EXPECT_EQ(m.numNodes(), 156);
  }
  EXPECT_NEAR(meshArea(m), 12.0 * 2.0 - M_PI * 0.25 / 2, q8 ? 1e-5 : 1e-2);
  EXPECT_EQ(m.boundaries.at("hole").size(), 12u);
  EXPECT_EQ(m.boundaries.at("end").size(), 4u);
  EXPECT_EQ(m.boundaries.at("far").size(), 4u);
  // Hole nodes on the circle, every 15 degrees (7.5 with the Quad8 mid-side nodes).
  std::vector<double> angles;
  for (LocalIndex n : m.nodesOf("hole")) {
    EXPECT_NEAR(std::hypot(m.x(n), m.y(n)), 0.5, 1e-12);
    angles.push_back(std::atan2(m.y(n), m.x(n)) * 180.0 / M_PI);
  }
  std::sort(angles.begin(), angles.end());
  ASSERT_EQ(angles.size(), q8 ? 25u : 13u);
  for (std::size_t k = 0; k < angles.size(); ++k)
    EXPECT_NEAR(angles[k], k * (q8 ? 7.5 : 15.0), 1e-9);
  for (LocalIndex n : m.nodesOf("bottom"))
    EXPECT_NEAR(m.y(n), 0.0, 1e-12);
  for (LocalIndex n : m.nodesOf("end"))
    EXPECT_NEAR(m.x(n), -4.0, 1e-12);
  const LocalIndex b = m.nodeSets.at("hole_bearing").front();
  EXPECT_NEAR(m.x(b), -0.5, 1e-12);
  EXPECT_NEAR(m.y(b), 0.0, 1e-12);
}

// The mesh's dimension comes from its element type; coordinates are dim() per node, read by
// coordinate(n, i) (x() and y() are its first two), and toDevice copies them to a MeshView of that
// dimension only.
TEST_P(GeneratorTest, DimensionCoordinateAccessorAndDeviceCopy) {
  const Mesh m = rectangleMesh(3.0, 2.0, 3, 2, GetParam(), 0.5, -1.0, 1.5, 1.0);
  EXPECT_EQ(spatialDimension(GetParam()), 2);
  ASSERT_EQ(m.dim(), 2);
  ASSERT_EQ(m.coordinates.size(), static_cast<std::size_t>(m.dim()) * m.numNodes());
  for (LocalIndex n = 0; n < m.numNodes(); ++n)
    for (int i = 0; i < m.dim(); ++i)
      EXPECT_EQ(m.coordinate(n, i), m.coordinates[static_cast<std::size_t>(m.dim()) * n + i]);
  for (LocalIndex n = 0; n < m.numNodes(); ++n) {
    EXPECT_EQ(m.x(n), m.coordinate(n, 0));
    EXPECT_EQ(m.y(n), m.coordinate(n, 1));
  }
  using Memory = Kokkos::DefaultExecutionSpace::memory_space;
  const auto view = toDevice<Memory, 2>(m);
  static_assert(decltype(view)::kDim == 2);
  ASSERT_EQ(view.coordinates.extent(0), static_cast<std::size_t>(m.numNodes()));
  ASSERT_EQ(view.connectivity.extent(0), static_cast<std::size_t>(m.numElements()));
  ASSERT_EQ(view.connectivity.extent(1), static_cast<std::size_t>(m.nodesPerElement));
  const auto hc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view.coordinates);
  const auto he = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view.connectivity);
  for (LocalIndex n = 0; n < m.numNodes(); ++n)
    for (int i = 0; i < 2; ++i)
      EXPECT_EQ(hc(n, i), m.coordinate(n, i));
  for (LocalIndex e = 0; e < m.numElements(); ++e)
    for (int a = 0; a < m.nodesPerElement; ++a)
      EXPECT_EQ(he(e, a), m.node(e, a));
}

TEST(MeshDimension, DeviceCopyOfAnotherDimensionIsRefusedByName) {
  Mesh m = rectangleMesh(1.0, 1.0, 1, 1, ElementType::Quad4);
  m.source = "plate.msh";
  using Memory = Kokkos::DefaultExecutionSpace::memory_space;
  try {
    (void)toDevice<Memory, 3>(m);
    FAIL() << "a 3D view of a 2D mesh was made";
  } catch (const std::invalid_argument &e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("plate.msh"), std::string::npos) << msg;
    EXPECT_NE(msg.find("2D"), std::string::npos) << msg;
    EXPECT_NE(msg.find("3D"), std::string::npos) << msg;
  }
}

TEST(MeshValidation, RejectsInvertedElementAndNamesIt) {
  Mesh m = rectangleMesh(2.0, 1.0, 2, 1, ElementType::Quad4);
  // Swap two nodes of element 2 so it becomes clockwise.
  std::swap(m.connectivity[4 + 1], m.connectivity[4 + 3]);
  const std::string msg = expectInputError([&] { validateMesh(m); });
  EXPECT_NE(msg.find("element 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Jacobian"), std::string::npos) << msg;
}

// Coordinates that are not finite, or whose Jacobian overflows a double, are input errors naming
// the node or element (f4b0a44: a size of 1e200 crashed in the minimum-Jacobian reduction, which
// never saw a finite value and indexed with its initial location).
TEST(MeshValidation, NonFiniteCoordinatesAndOverflowingJacobiansAreNamed) {
  for (const ElementType type : {ElementType::Quad4, ElementType::Quad8}) {
    Mesh huge = rectangleMesh(1e200, 1e200, 2, 2, type);
    std::string msg = expectInputError([&] { validateMesh(huge); });
    EXPECT_NE(msg.find("element 1: its Jacobian determinant is not a finite number"),
              std::string::npos)
        << msg;
    Mesh nan = rectangleMesh(2.0, 1.0, 2, 1, type);
    nan.coordinates[2 * 3 + 1] = std::numeric_limits<double>::quiet_NaN();
    msg = expectInputError([&] { validateMesh(nan); });
    EXPECT_NE(msg.find("node " + std::to_string(nan.nodeId(3)) +
                       " has a coordinate that is not a finite number"),
              std::string::npos)
        << msg;
    Mesh inf = rectangleMesh(2.0, 1.0, 2, 1, type);
    inf.coordinates[0] = std::numeric_limits<double>::infinity();
    msg = expectInputError([&] { validateMesh(inf); });
    EXPECT_NE(msg.find("node " + std::to_string(inf.nodeId(0))), std::string::npos) << msg;
  }
}

namespace {
// Two Quad4 elements on [0,2]x[0,1], a physical curve "left" (x = 0), a physical point "tip".
const char *kGmshQuad4 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
0 3 "tip"
1 1 "left"
2 2 "plate"
$EndPhysicalNames
$Entities
1 1 1 0
1 2 1 0 1 3
1 0 0 0 0 1 0 1 1 2 1 -1
1 0 0 0 2 1 0 1 2 0
$EndEntities
$Nodes
3 6 1 6
0 1 0 1
6
2 1 0
1 1 0 2
1
2
0 0 0
0 1 0
2 1 0 3
3
4
5
1 0 0
1 1 0
2 0 0
$EndNodes
$Elements
3 4 1 4
0 1 15 1
1 6
1 1 1 1
2 1 2
2 1 3 2
3 1 3 4 2
4 3 5 6 4
$EndElements
)";
} // namespace

TEST(GmshReader, ReadsQuad4WithPhysicalGroups) {
  std::istringstream in(kGmshQuad4);
  const Mesh m = readGmsh(in, "two.msh");
  EXPECT_EQ(m.elementType, ElementType::Quad4);
  EXPECT_EQ(m.numNodes(), 6);
  EXPECT_EQ(m.numElements(), 2);
  ASSERT_EQ(m.regionNames.size(), 1u);
  EXPECT_EQ(m.regionNames[0], "plate");
  ASSERT_TRUE(m.hasBoundary("left"));
  const auto left = m.nodesOf("left");
  ASSERT_EQ(left.size(), 2u);
  for (LocalIndex n : left)
    EXPECT_NEAR(m.x(n), 0.0, 1e-15);
  ASSERT_TRUE(m.hasNodeSet("tip"));
  EXPECT_NEAR(m.x(m.nodeSets.at("tip")[0]), 2.0, 1e-15);
  EXPECT_EQ(m.elementIds[1], 4);
  EXPECT_NO_THROW(validateMesh(m));
}

TEST(GmshReader, RejectsBadFilesWithFileAndLine) {
  auto read = [](std::string text) {
    std::istringstream in(text);
    return readGmsh(in, "bad.msh");
  };
  std::string t = kGmshQuad4;
  auto msg =
      expectInputError([&] { read(std::string(t).replace(t.find("4.1 0 8"), 7, "2.2 0 8")); });
  EXPECT_NE(msg.find("bad.msh:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("version"), std::string::npos) << msg;
  msg = expectInputError([&] { read(std::string(t).replace(t.find("4.1 0 8"), 7, "4.1 1 8")); });
  EXPECT_NE(msg.find("binary"), std::string::npos) << msg;
  // A triangle block (type 2) is unsupported.
  msg = expectInputError([&] { read(std::string(t).replace(t.find("2 1 3 2"), 7, "2 1 2 2")); });
  EXPECT_NE(msg.find("unsupported element type 2"), std::string::npos) << msg;
  // An element that references a node that does not exist.
  msg =
      expectInputError([&] { read(std::string(t).replace(t.find("4 3 5 6 4"), 9, "4 3 5 6 9")); });
  EXPECT_NE(msg.find("unknown node 9"), std::string::npos) << msg;
  msg = expectInputError([&] { read("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n"); });
  EXPECT_NE(msg.find("end of file"), std::string::npos) << msg;
  msg = expectInputError([&] { read("hello\n"); });
  EXPECT_NE(msg.find("not a Gmsh file"), std::string::npos) << msg;
}

// Files that are not Gmsh meshes are refused after a bounded read: a device, a directory or a
// FIFO by stat before opening; a first line other than $MeshFormat at that line (it used to be
// scanned to the end for one); a line over kMaxInputLine characters when it passes that length.
TEST(GmshReader, RefusesNonRegularFilesWrongHeadersAndEndlessLines) {
  EXPECT_NE(expectInputError([] {
              readGmsh("/dev/zero");
            }).find("/dev/zero: the mesh file is a device, not a regular file"),
            std::string::npos);
  const auto dir =
      std::filesystem::temp_directory_path() / ("mixcon-gmsh-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  EXPECT_NE(expectInputError([&] { readGmsh(dir.string()); }).find("the mesh file is a directory"),
            std::string::npos);
  const auto fifo = dir / "fifo.msh";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(expectInputError([&] { readGmsh(fifo.string()); }).find("the mesh file is a FIFO"),
            std::string::npos);
  EXPECT_NE(expectInputError([&] {
              readGmsh((dir / "none.msh").string());
            }).find("none.msh: cannot open the mesh file"),
            std::string::npos);
  std::filesystem::remove_all(dir);

  auto read = [](std::string text) {
    std::istringstream in(text);
    return readGmsh(in, "bad.msh");
  };
  const std::string t = kGmshQuad4;
  auto msg = expectInputError([&] { read("# exported\n" + t); });
  EXPECT_NE(msg.find("bad.msh:1: not a Gmsh file: expected $MeshFormat first, found '#'"),
            std::string::npos)
      << msg;
  msg = expectInputError([&] { read("\n\n$Nodes\n" + t); });
  EXPECT_NE(msg.find("bad.msh:3: not a Gmsh file"), std::string::npos) << msg;
  // One endless line (a 1 GB file of one line is refused after its first MiB).
  msg = expectInputError([&] { read(std::string(kMaxInputLine + 10, '1')); });
  EXPECT_NE(msg.find("bad.msh:1: line longer than 1048576 characters"), std::string::npos) << msg;
  msg = expectInputError(
      [&] { read("$MeshFormat\n4.1 0 8 " + std::string(kMaxInputLine, ' ') + "\n"); });
  EXPECT_NE(msg.find("bad.msh:2: line longer than"), std::string::npos) << msg;
  // A long token is echoed cut to 80 characters.
  msg = expectInputError([&] {
    read("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n" + std::string(500, '7') + "x 1 1 1\n");
  });
  EXPECT_NE(msg.find("found '" + std::string(77, '7') + "...'"), std::string::npos) << msg;
  EXPECT_LT(msg.size(), 200u) << msg;
}

// Reproducers found by fuzz/fuzz_gmsh.cpp: header counts, numbers and element blocks that used to
// escape as std::length_error or allocate what the header claimed; each is now an InputError
// naming file:line.
TEST(GmshReader, FuzzedHeadersAndNumbersAreInputErrorsWithLine) {
  auto read = [](std::string text) {
    std::istringstream in(text);
    return readGmsh(in, "bad.msh");
  };
  const std::string t = kGmshQuad4;
  const std::string head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  // A negative node count in a block header (was: std::length_error from vector(n)).
  auto msg = expectInputError([&] { read(head + "$Nodes\n1 6 1 6\n2 1 0 -1\n1\n"); });
  EXPECT_NE(msg.find("bad.msh:6: number of nodes -1 out of range"), std::string::npos) << msg;
  // A huge count allocates nothing up front: the file simply ends.
  msg = expectInputError([&] { read(head + "$Nodes\n1 6 1 6\n2 1 0 2000000000\n1\n"); });
  EXPECT_NE(msg.find("end of file"), std::string::npos) << msg;
  msg = expectInputError([&] { read(head + "$Nodes\n1 6 1 6\n2 1 0 99999999999\n1\n"); });
  EXPECT_NE(msg.find("bad.msh:6: number of nodes 99999999999 out of range"), std::string::npos)
      << msg;
  // Non-finite coordinates are refused where they are read.
  msg =
      expectInputError([&] { read(std::string(t).replace(t.find("1 0 0\n1 1 0"), 5, "nan 0 0")); });
  EXPECT_NE(msg.find("bad.msh:30: expected a finite number, found 'nan'"), std::string::npos)
      << msg;
  msg =
      expectInputError([&] { read(std::string(t).replace(t.find("1 0 0\n1 1 0"), 5, "1 inf 0")); });
  EXPECT_NE(msg.find("found 'inf'"), std::string::npos) << msg;
  // A line type in a block of dimension 2 (was: a Quad4 mesh with 2-node connectivity).
  msg = expectInputError([&] { read(std::string(t).replace(t.find("2 1 3 2"), 7, "2 1 1 2")); });
  EXPECT_NE(msg.find("element type 1 in a block of dimension 2"), std::string::npos) << msg;
  // A physical tag (the surface's) whose absolute value does not fit an int.
  msg = expectInputError(
      [&] { read(std::string(t).replace(t.find("0 1 2 0\n"), 7, "0 1 -2147483648 0")); });
  EXPECT_NE(msg.find("bad.msh:14: integer -2147483648 out of range"), std::string::npos) << msg;
  EXPECT_NO_THROW(read(t));
}

namespace {
/// Local node k of an element written clockwise: its natural coordinates mirrored (xi -> -xi),
/// so that corner 0 takes (1,-1) and the mid-side nodes follow their edges.
constexpr int kMirrored[8] = {1, 0, 3, 2, 4, 7, 6, 5};

/// Writes a mesh as Gmsh 4.1 ASCII: one surface (physical "body"), one curve entity per boundary
/// (physical groups of the same names, 2- or 3-node lines), one point per node set. Elements
/// for which `clockwise` holds are written with their nodes in clockwise order (kMirrored), as
/// Gmsh writes a surface whose curve loop runs clockwise.
std::string toGmsh(const Mesh &m, const std::function<bool(LocalIndex)> &clockwise = {}) {
  std::ostringstream s;
  const int lineType = m.nodesPerElement == 8 ? 8 : 1, quadType = m.nodesPerElement == 8 ? 16 : 3;
  std::vector<std::string> bnames, pnames;
  for (const auto &[name, edges] : m.boundaries)
    bnames.push_back(name);
  for (const auto &[name, nodes] : m.nodeSets)
    pnames.push_back(name);
  s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n"
    << 1 + bnames.size() + pnames.size() << "\n2 1 \"body\"\n";
  for (std::size_t i = 0; i < bnames.size(); ++i)
    s << "1 " << 10 + i << " \"" << bnames[i] << "\"\n";
  for (std::size_t i = 0; i < pnames.size(); ++i)
    s << "0 " << 100 + i << " \"" << pnames[i] << "\"\n";
  s << "$EndPhysicalNames\n$Entities\n" << pnames.size() << " " << bnames.size() << " 1 0\n";
  for (std::size_t i = 0; i < pnames.size(); ++i)
    s << i + 1 << " 0 0 0 1 " << 100 + i << "\n";
  for (std::size_t i = 0; i < bnames.size(); ++i)
    s << i + 1 << " 0 0 0 1 1 0 1 " << 10 + i << " 0\n";
  s << "1 0 0 0 1 1 0 1 1 0\n$EndEntities\n";
  // All nodes in the surface block, tags 1-based and shuffled by a stride to test the tag map.
  const LocalIndex nn = m.numNodes();
  auto tag = [&](LocalIndex n) { return 5 + 2 * n; };
  s << "$Nodes\n1 " << nn << " 5 " << tag(nn - 1) << "\n2 1 0 " << nn << "\n";
  for (LocalIndex n = 0; n < nn; ++n)
    s << tag(n) << "\n";
  for (LocalIndex n = 0; n < nn; ++n)
    s << std::setprecision(17) << m.x(n) << " " << m.y(n) << " 0\n";
  s << "$EndNodes\n$Elements\n";
  std::size_t count = m.numElements(), blocks = 1 + bnames.size() + pnames.size();
  for (const auto &[name, edges] : m.boundaries)
    count += edges.size();
  for (const auto &[name, nodes] : m.nodeSets)
    count += nodes.size();
  s << blocks << " " << count << " 1 " << count << "\n";
  long id = 1;
  for (std::size_t i = 0; i < pnames.size(); ++i) {
    const auto &nodes = m.nodeSets.at(pnames[i]);
    s << "0 " << i + 1 << " 15 " << nodes.size() << "\n";
    for (LocalIndex n : nodes)
      s << id++ << " " << tag(n) << "\n";
  }
  for (std::size_t i = 0; i < bnames.size(); ++i) {
    const auto &edges = m.boundaries.at(bnames[i]);
    s << "1 " << i + 1 << " " << lineType << " " << edges.size() << "\n";
    for (const auto &e : edges) {
      s << id++;
      for (int k = 0; k < m.nodesPerEdge(); ++k)
        s << " " << tag(m.edgeNode(e, k));
      s << "\n";
    }
  }
  s << "2 1 " << quadType << " " << m.numElements() << "\n";
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    s << id++;
    const bool cw = clockwise && clockwise(e);
    for (int a = 0; a < m.nodesPerElement; ++a)
      s << " " << tag(m.node(e, cw ? kMirrored[a] : a));
    s << "\n";
  }
  s << "$EndElements\n";
  return s.str();
}
} // namespace

TEST_P(GeneratorTest, GmshRoundTripKeepsGeometryTopologyAndGroups) {
  const Mesh m = plateWithHoleMesh(1.0, 4.0, 3.0, 4, 5, GetParam(), 1.1);
  std::istringstream in(toGmsh(m));
  const Mesh r = readGmsh(in, "roundtrip.msh");
  ASSERT_EQ(r.elementType, m.elementType);
  ASSERT_EQ(r.numNodes(), m.numNodes());
  ASSERT_EQ(r.numElements(), m.numElements());
  for (LocalIndex n = 0; n < m.numNodes(); ++n) {
    EXPECT_DOUBLE_EQ(r.x(n), m.x(n));
    EXPECT_DOUBLE_EQ(r.y(n), m.y(n));
    EXPECT_EQ(r.nodeIds[n], 5 + 2 * n);
  }
  EXPECT_EQ(r.connectivity, m.connectivity);
  EXPECT_EQ(r.regionNames, std::vector<std::string>{"body"});
  for (const auto &[name, edges] : m.boundaries) {
    ASSERT_TRUE(r.hasBoundary(name)) << name;
    EXPECT_EQ(r.nodesOf(name), m.nodesOf(name)) << name;
    ASSERT_EQ(r.boundaries.at(name).size(), edges.size());
    for (std::size_t k = 0; k < edges.size(); ++k) { // matched to the same element edge
      EXPECT_EQ(r.boundaries.at(name)[k].element, edges[k].element);
      EXPECT_EQ(r.boundaries.at(name)[k].edge, edges[k].edge);
    }
  }
  EXPECT_NO_THROW(validateMesh(r));
}

TEST_P(GeneratorTest, HalfDiskAndMergedBodies) {
  const bool q8 = GetParam() == ElementType::Quad8;
  const Mesh pin = halfDiskMesh(0.5, 3, 2, GetParam());
  EXPECT_NO_THROW(validateMesh(pin));
  EXPECT_EQ(pin.numElements(), 2 * 3 * 3 + 4 * 3 * 2);
  EXPECT_NEAR(meshArea(pin), M_PI * 0.25 / 2, q8 ? 1e-4 : 2e-2);
  EXPECT_EQ(pin.boundaries.at("arc").size(), 12u); // every 15 degrees, like the report's hole
  std::vector<double> angles;
  for (LocalIndex n : pin.nodesOf("arc")) {
    EXPECT_NEAR(std::hypot(pin.x(n), pin.y(n)), 0.5, 1e-12);
    angles.push_back(std::atan2(pin.y(n), pin.x(n)) * 180.0 / M_PI);
  }
  std::sort(angles.begin(), angles.end());
  ASSERT_EQ(angles.size(), q8 ? 25u : 13u);
  for (std::size_t k = 0; k < angles.size(); ++k)
    EXPECT_NEAR(angles[k], k * (q8 ? 7.5 : 15.0), 1e-9);
  for (LocalIndex n : pin.nodesOf("bottom"))
    EXPECT_NEAR(pin.y(n), 0.0, 1e-12);
  // Two bodies: nodes and elements concatenated, names prefixed, the second body moved.
  const Mesh block = rectangleMesh(2.0, 1.0, 4, 2, GetParam(), 0.0, 0.0, 1.5, 2.0);
  const Mesh merged = mergeMeshes({{"pin", pin, {0.0, 0.0}}, {"block", block, {-1.0, 0.5}}});
  EXPECT_NO_THROW(validateMesh(merged));
  EXPECT_EQ(merged.numNodes(), pin.numNodes() + block.numNodes());
  EXPECT_EQ(merged.numElements(), pin.numElements() + block.numElements());
  EXPECT_NEAR(meshArea(merged), meshArea(pin) + 2.0, 1e-10);
  EXPECT_EQ(merged.regionNames, (std::vector<std::string>{"pin", "block"}));
  EXPECT_EQ(merged.boundaries.at("block.top").size(), 4u);
  for (LocalIndex n : merged.nodesOf("block.top"))
    EXPECT_NEAR(merged.y(n), 1.5, 1e-14);
  for (LocalIndex n : merged.nodesOf("pin.arc"))
    EXPECT_LT(n, pin.numNodes());
  // Grading 1.5 along x: the first column is (1/4)^1.5 of the width.
  const LocalIndex corner = merged.nodeSets.at("block.bottom_left").front();
  EXPECT_NEAR(merged.x(corner), -1.0, 1e-14);
  double next = 1e9;
  for (LocalIndex n : merged.nodesOf("block.bottom"))
    if (merged.x(n) > -1.0 + 1e-12)
      next = std::min(next, merged.x(n) + 1.0);
  // (the Quad8 mid-side node halfway)
  EXPECT_NEAR(next, (q8 ? 0.5 : 1.0) * 2.0 * std::pow(0.25, 1.5), 1e-12);
  EXPECT_NE(expectInputError([&] {
              mergeMeshes({{"a", pin, {0, 0}}, {"a", block, {0, 0}}});
            }).find("used twice"),
            std::string::npos);
  const Mesh other = rectangleMesh(1, 1, 1, 1, q8 ? ElementType::Quad4 : ElementType::Quad8);
  EXPECT_NE(expectInputError([&] {
              mergeMeshes({{"a", pin, {0, 0}}, {"b", other, {0, 0}}});
            }).find("element type"),
            std::string::npos);
}

TEST_P(GeneratorTest, ClockwiseGmshQuadranglesAreReorientedToTheSameElements) {
  const Mesh m = plateWithHoleMesh(1.0, 4.0, 3.0, 4, 5, GetParam(), 1.1);
  // Every other element clockwise (a mesh of surfaces drawn both ways).
  std::istringstream in(toGmsh(m, [](LocalIndex e) { return e % 2 == 0; }));
  const Mesh r = readGmsh(in, "clockwise.msh");
  ASSERT_EQ(r.numElements(), m.numElements());
  const int corners = 4, npe = m.nodesPerElement;
  for (LocalIndex e = 0; e < m.numElements(); ++e) {
    // The same element up to where it starts: a cyclic shift s of the corners, the mid-side
    // nodes shifted with their edges.
    int shift = -1;
    for (int s = 0; s < corners; ++s)
      if (r.node(e, 0) == m.node(e, s))
        shift = s;
    ASSERT_GE(shift, 0) << "element " << e;
    for (int k = 0; k < corners; ++k) {
      EXPECT_EQ(r.node(e, k), m.node(e, (k + shift) % corners)) << "element " << e;
      if (npe == 8) {
        EXPECT_EQ(r.node(e, 4 + k), m.node(e, 4 + (k + shift) % corners)) << "element " << e;
      }
    }
    // Counter-clockwise at every Gauss point, with the original element's area.
    const Eigen::MatrixXd xe = test::elementCoordinates(r, e), x0 = test::elementCoordinates(m, e);
    double area = 0.0, area0 = 0.0;
    for (const auto &g : test::referenceGauss(npe == 4 ? 2 : 3)) {
      Eigen::VectorXd sh;
      Eigen::MatrixXd dn;
      test::referenceShape(npe, g[0], g[1], sh, dn);
      const double det = (xe.transpose() * dn).determinant();
      EXPECT_GT(det, 0.0) << "element " << e;
      area += g[2] * det;
      area0 += g[2] * (x0.transpose() * dn).determinant();
    }
    EXPECT_NEAR(area, area0, 1e-13 * area0) << "element " << e;
  }
  EXPECT_NO_THROW(validateMesh(r));
  // Boundaries taken from the reoriented elements: the same nodes, the outward normal on the
  // right of each edge (the edge runs counter-clockwise around the body).
  for (const auto &[name, edges] : m.boundaries) {
    EXPECT_EQ(r.nodesOf(name), m.nodesOf(name)) << name;
    for (const auto &be : r.boundaries.at(name)) {
      const LocalIndex a = r.edgeNode(be, 0), b = r.edgeNode(be, 1);
      double cx = 0, cy = 0; // element centre: on the left of the edge
      for (int k = 0; k < corners; ++k) {
        cx += r.x(r.node(be.element, k)) / corners;
        cy += r.y(r.node(be.element, k)) / corners;
      }
      const double cross = (r.x(b) - r.x(a)) * (cy - r.y(a)) - (r.y(b) - r.y(a)) * (cx - r.x(a));
      EXPECT_GT(cross, 0.0) << name;
    }
  }
  // Said once, with the count.
  ASSERT_EQ(r.warnings.size(), 1u);
  const std::string count = std::to_string((m.numElements() + 1) / 2) + " of " +
                            std::to_string(m.numElements()) + " quadrangles";
  EXPECT_NE(r.warnings[0].find(count), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("clockwise.msh"), std::string::npos) << r.warnings[0];
  // A counter-clockwise file says nothing.
  std::istringstream ccw(toGmsh(m));
  EXPECT_TRUE(readGmsh(ccw, "ccw.msh").warnings.empty());
}

TEST_P(GeneratorTest, ClockwiseGmshMeshGivesTheSameDisplacements) {
  const Mesh m = plateWithHoleMesh(1.0, 4.0, 3.0, 3, 4, GetParam(), 1.1);
  const auto dir =
      std::filesystem::temp_directory_path() / ("mixcon-test-cw-" + std::to_string(::getpid()) +
                                                "-" + std::to_string(static_cast<int>(GetParam())));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "ccw.msh") << toGmsh(m);
  std::ofstream(dir / "cw.msh") << toGmsh(m, [](LocalIndex) { return true; });
  auto run = [&](const std::string &file) {
    const std::string yaml = "mesh: {file: " + file + R"(}
model: {formulation: displacement, analysis: plane_stress}
materials:
  - {region: body, type: isotropic, E: 1000, nu: 0.3}
boundary_conditions:
  - {boundary: left, ux: 0}
  - {boundary: bottom, uy: 0}
loads:
  - {boundary: right, traction: [1, 0]}
  - {boundary: hole, pressure: 0.5}
solver: {type: direct}
output: {hdf5: false}
)";
    const Problem p = parseProblem(yaml, file + ".yaml", dir.string());
    RunOptions o;
    o.outputDirectory = (dir / ("out-" + file)).string();
    return runAnalysis(p, o, MPI_COMM_WORLD).displacement;
  };
  const auto u0 = run("ccw.msh"), u1 = run("cw.msh");
  std::filesystem::remove_all(dir);
  ASSERT_EQ(u0.size(), 2u * m.numNodes());
  ASSERT_EQ(u1.size(), u0.size());
  double umax = 0.0;
  for (double v : u0)
    umax = std::max(umax, std::abs(v));
  EXPECT_GT(umax, 1e-4);
  for (std::size_t i = 0; i < u0.size(); ++i)
    EXPECT_NEAR(u1[i], u0[i], 1e-10 * umax) << i;
}

TEST(GmshReader, InvertedAndBowTieQuadranglesAreStillRefusedByTheirId) {
  // kGmshQuad4's second element (id 4: nodes 3 5 6 4) made a bow-tie (3 5 4 6: two edges
  // cross) and degenerate (3 5 5 4: a repeated node, zero area at a corner).
  for (const char *bad : {"4 3 5 4 6", "4 3 5 5 4", "4 3 3 3 3"}) {
    std::string t = kGmshQuad4;
    t.replace(t.find("4 3 5 6 4"), 9, bad);
    std::istringstream in(t);
    const Mesh m = readGmsh(in, "bad.msh");
    const std::string msg = expectInputError([&] { validateMesh(m); });
    EXPECT_NE(msg.find("bad.msh: element 4 has a non-positive Jacobian"), std::string::npos)
        << bad << ": " << msg;
  }
  // A Quad8 whose mid-side node sits beyond the opposite edge folds the element: its signed area
  // stays positive, so it is not reoriented, and the fold is refused.
  Mesh q = rectangleMesh(1.0, 1.0, 1, 1, ElementType::Quad8);
  const LocalIndex mid = q.node(0, 4); // mid-side of the bottom edge
  q.coordinates[2 * mid + 1] = 1.4;
  std::istringstream in(toGmsh(q));
  Mesh r = readGmsh(in, "fold.msh");
  EXPECT_TRUE(r.warnings.empty());
  const std::string msg = expectInputError([&] { validateMesh(r); });
  EXPECT_NE(msg.find("fold.msh: element"), std::string::npos) << msg;
  EXPECT_NE(msg.find("non-positive Jacobian"), std::string::npos) << msg;
}
