// One numbering in every message and file (issue 25 item 5): nodes and elements by the mesh's own
// ids (Gmsh tags), obstacles and contact pairs by their 1-based place in the problem's `contact:`
// list with their boundary name, the same on screen, in contact.csv and in HDF5; one location
// prefix in the problem reader's generator errors. The meshes are Gmsh files whose tags are not
// index + 1, so that an index printed anywhere shows.
#include <io/Problem.hpp>
#include <mesh/GmshReader.hpp>
#include <solver/Nonlinear.hpp>
#include <support/Program.hpp>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using namespace mixcon;
using mixcon::test::runMixcon;
using mixcon::test::ScratchDir;

namespace {

constexpr long kNodeTag0 = 1001;    ///< tag of the first node (index 0)
constexpr long kElementTag0 = 5001; ///< tag of the first quadrangle

/// A Gmsh 4.1 file of the rectangle [0, lx] x [0, ly] with nx x ny Quad4 elements, node tags
/// kNodeTag0 + index and element tags kElementTag0 + index; physical curves "bottom", "right",
/// "top", "left" and the physical surface "body".
std::string offsetRectangleMsh(double lx, double ly, int nx, int ny) {
  auto node = [&](int i, int j) { return kNodeTag0 + j * (nx + 1) + i; };
  std::ostringstream s;
  s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    << "$PhysicalNames\n5\n1 1 \"bottom\"\n1 2 \"right\"\n1 3 \"top\"\n1 4 \"left\"\n"
    << "2 5 \"body\"\n$EndPhysicalNames\n"
    << "$Entities\n0 4 1 0\n"
    << "1 0 0 0 " << lx << " 0 0 1 1 0\n"
    << "2 " << lx << " 0 0 " << lx << " " << ly << " 0 1 2 0\n"
    << "3 0 " << ly << " 0 " << lx << " " << ly << " 0 1 3 0\n"
    << "4 0 0 0 0 " << ly << " 0 1 4 0\n"
    << "1 0 0 0 " << lx << " " << ly << " 0 1 5 0\n$EndEntities\n";
  const int numNodes = (nx + 1) * (ny + 1);
  s << "$Nodes\n1 " << numNodes << " " << kNodeTag0 << " " << kNodeTag0 + numNodes - 1 << "\n"
    << "2 1 0 " << numNodes << "\n";
  for (int k = 0; k < numNodes; ++k)
    s << kNodeTag0 + k << "\n";
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      s << lx * i / nx << " " << ly * j / ny << " 0\n";
  s << "$EndNodes\n";
  // The sides counter-clockwise (bottom, right, top, left), then the quadrangles.
  std::vector<std::vector<std::array<long, 2>>> sides(4);
  for (int i = 0; i < nx; ++i) {
    sides[0].push_back({node(i, 0), node(i + 1, 0)});
    sides[2].push_back({node(nx - i, ny), node(nx - i - 1, ny)});
  }
  for (int j = 0; j < ny; ++j) {
    sides[1].push_back({node(nx, j), node(nx, j + 1)});
    sides[3].push_back({node(0, ny - j), node(0, ny - j - 1)});
  }
  const long lines = 2 * (nx + ny), quads = static_cast<long>(nx) * ny;
  long tag = 9001;
  s << "$Elements\n5 " << lines + quads << " " << kElementTag0 << " " << tag + lines - 1 << "\n";
  for (int c = 0; c < 4; ++c) {
    s << "1 " << c + 1 << " 1 " << sides[c].size() << "\n";
    for (const auto &l : sides[c])
      s << tag++ << " " << l[0] << " " << l[1] << "\n";
  }
  s << "2 1 3 " << quads << "\n";
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      s << kElementTag0 + j * nx + i << " " << node(i, j) << " " << node(i + 1, j) << " "
        << node(i + 1, j + 1) << " " << node(i, j + 1) << "\n";
  s << "$EndElements\n";
  return s.str();
}

/// contact.csv rows as maps column -> value.
std::vector<std::map<std::string, std::string>> readCsv(const fs::path &file) {
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string &l) {
    std::vector<std::string> f;
    std::stringstream s(l);
    std::string x;
    while (std::getline(s, x, ','))
      f.push_back(x);
    return f;
  };
  if (std::getline(in, line))
    header = split(line);
  while (std::getline(in, line)) {
    const auto f = split(line);
    std::map<std::string, std::string> r;
    for (std::size_t i = 0; i < f.size() && i < header.size(); ++i)
      r[header[i]] = f[i];
    rows.push_back(r);
  }
  return rows;
}

/// An int dataset of results.h5 (empty when absent).
std::vector<long> readIntegers(const fs::path &file, const std::string &name) {
  std::vector<long> v;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0)
    return v;
  if (H5Lexists(f, name.c_str(), H5P_DEFAULT) > 0) {
    const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    const hid_t sp = H5Dget_space(d);
    v.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(sp)));
    H5Dread(d, H5T_NATIVE_LONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(sp);
    H5Dclose(d);
  }
  H5Fclose(f);
  return v;
}

} // namespace

// A block on a Gmsh mesh with tags from 1001 pushed up against a rigid plane (the second
// obstacle; the first, beside the body, never touches): every status-change line of --verbose
// names a node by an id in contact.csv's node_id column, and the obstacle by the number that
// contact.csv and HDF5 give the rows of that node, with the boundary's name.
TEST(Numbering, RigidContactLinesUseTheFilesNodeIdsAndObstacleNumbers) {
  ScratchDir dir("numbering");
  std::ofstream(dir.path() / "block.msh") << offsetRectangleMsh(2.0, 1.0, 4, 2);
  std::ofstream(dir.path() / "block.yaml") << R"(mesh: {file: block.msh}
model: {formulation: displacement, analysis: plane_strain, thickness: 1.0}
materials: [{region: body, type: isotropic, E: 1000, nu: 0.3}]
boundary_conditions: [{boundary: left, ux: 0}, {boundary: bottom, uy: 0.02}]
contact:
  - {type: rigid_half_plane, boundary: right, point: [3, 0], normal: [-1, 0]}
  - {type: rigid_half_plane, boundary: top, point: [0, 1.005], normal: [0, -1], friction: 0.3}
steps: {increments: 2}
solver: {type: direct}
)";
  std::string out;
  ASSERT_EQ(runMixcon("run --verbose -o " + (dir.path() / "out").string() + " " +
                          (dir.path() / "block.yaml").string(),
                      out, dir.path()),
            0)
      << out;

  const auto rows = readCsv(dir.path() / "out" / "contact.csv");
  ASSERT_FALSE(rows.empty());
  std::map<std::string, std::set<std::string>> obstaclesOfNode; // node_id -> obstacle numbers
  for (const auto &r : rows)
    obstaclesOfNode[r.at("node_id")].insert(r.at("obstacle"));
  const std::set<std::string> topIds = [&] {
    std::set<std::string> ids;
    for (int i = 0; i <= 4; ++i)
      ids.insert(std::to_string(kNodeTag0 + 2 * 5 + i)); // the row j = 2
    return ids;
  }();
  for (const auto &id : topIds)
    EXPECT_EQ(obstaclesOfNode.count(id), 1u) << "top node " << id << " not in contact.csv";

  const std::regex status(R"(contact: node (\d+) on obstacle (\d+) \('([^']*)'\): )");
  const char *names[] = {"right", "top"};
  int lines = 0;
  std::istringstream log(out);
  for (std::string line; std::getline(log, line);) {
    std::smatch m;
    if (line.find("contact: node") == std::string::npos)
      continue;
    ASSERT_TRUE(std::regex_search(line, m, status)) << line;
    ++lines;
    const std::string node = m[1], obstacle = m[2];
    ASSERT_TRUE(obstaclesOfNode.count(node))
        << "node " << node << " is not in contact.csv: " << line;
    EXPECT_TRUE(obstaclesOfNode[node].count(obstacle))
        << "contact.csv has no row of node " << node << " on obstacle " << obstacle;
    EXPECT_EQ(obstacle, "2") << line; // only the top closes
    EXPECT_EQ(m[3].str(), names[std::stoi(obstacle) - 1]) << line;
    EXPECT_TRUE(topIds.count(node)) << line;
  }
  EXPECT_GE(lines, 5) << out; // every top node closes

  // HDF5: the same node ids and obstacle numbers, row by row, as contact.csv's last step.
  const auto h5obstacle =
      readIntegers(dir.path() / "out" / "results.h5", "/steps/2/contact/obstacle");
  const auto h5node = readIntegers(dir.path() / "out" / "results.h5", "/steps/2/contact/node_id");
  std::vector<std::pair<std::string, std::string>> lastCsv, lastH5;
  for (const auto &r : rows)
    if (r.at("step") == "2")
      lastCsv.emplace_back(r.at("obstacle"), r.at("node_id"));
  for (std::size_t k = 0; k < h5obstacle.size() && k < h5node.size(); ++k)
    lastH5.emplace_back(std::to_string(h5obstacle[k]), std::to_string(h5node[k]));
  EXPECT_EQ(lastH5, lastCsv);
  EXPECT_EQ(std::set<std::string>({"1", "2"}), [&] {
    std::set<std::string> s;
    for (const auto &r : lastCsv)
      s.insert(r.first);
    return s;
  }()) << "obstacles numbered from 1 as in the problem's contact: list";
}

// Node-to-segment pairs: the status lines name the pair by its 1-based number (contact.csv's
// `obstacle`) and its surfaces, and the node by an id of contact.csv's rows of that pair.
TEST(Numbering, SurfaceContactLinesUseTheFilesNumbers) {
  ScratchDir dir("numbering");
  std::ofstream(dir.path() / "pair.yaml") << R"(mesh:
  bodies:
    - {name: base, generator: {type: rectangle, size: [2, 0.5], origin: [-0.5, 0], divisions: [8, 2], element: quad4}}
    - {name: block, generator: {type: rectangle, size: [1, 0.5], origin: [0, 0.5], divisions: [5, 2], element: quad4}}
model: {formulation: displacement, analysis: plane_strain, thickness: 1.0}
materials: [{region: base, type: isotropic, E: 1000, nu: 0.3}, {region: block, type: isotropic, E: 1000, nu: 0.3}]
boundary_conditions: [{boundary: base.bottom, ux: 0, uy: 0}, {boundary: block.top, ux: 0, uy: -0.01}]
contact: [{type: node_to_segment, contactor: block.bottom, target: base.top, friction: 0.2}]
steps: {increments: 2}
solver: {type: direct}
)";
  std::string out;
  ASSERT_EQ(runMixcon("run --verbose -o " + (dir.path() / "out").string() + " " +
                          (dir.path() / "pair.yaml").string(),
                      out, dir.path()),
            0)
      << out;
  std::set<std::string> ids;
  for (const auto &r : readCsv(dir.path() / "out" / "contact.csv")) {
    EXPECT_EQ(r.at("obstacle"), "1");
    ids.insert(r.at("node_id"));
  }
  const std::regex status(R"(contact: node (\d+) on contact 1 \('block\.bottom -> base\.top'\): )");
  int lines = 0;
  std::istringstream log(out);
  for (std::string line; std::getline(log, line);) {
    if (line.find("contact: node") == std::string::npos)
      continue;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(line, m, status)) << line;
    EXPECT_TRUE(ids.count(m[1])) << line;
    ++lines;
  }
  EXPECT_GE(lines, 1) << out;
}

// A generator's errors, its own and those of its keys, carry one file:line:column prefix.
TEST(Numbering, GeneratorErrorsHaveOneLocation) {
  const std::string rest = R"(
model: {formulation: displacement, analysis: plane_stress}
materials: [{region: body, type: isotropic, E: 1000, nu: 0.3}]
solver: {type: direct}
)";
  const char *generators[] = {
      "{type: rectangle, size: [1, 1], divisions: [0, 2]}",        // the generator refuses
      "{type: quarter_disk, radius: -1, divisions: [2, 2]}",       // the generator refuses
      "{type: rectangle, size: [1, 1], divisions: [a, 2]}",        // the key's reader refuses
      "{type: quarter_annulus, inner_radius: 1, outer_radius: 2}", // a missing key
      "{type: pinned_plate, hole_radius: 1, half_width: 4, end_distance: 3, length: 9, "
      "divisions: [1, 1, 1]}",                                              // three, not four
      "{type: rectangle, size: [1, 1], divisions: [100000000, 100000000]}", // too many elements
  };
  for (const char *g : generators) {
    const std::string yaml = std::string("mesh:\n  generator: ") + g + rest;
    try {
      parseProblem(yaml, "gen.yaml", "");
      ADD_FAILURE() << "accepted " << g;
    } catch (const InputError &e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("gen.yaml:2:", 0), 0u) << msg;
      EXPECT_EQ(msg.find("gen.yaml", 1), std::string::npos) << "two locations: " << msg;
    }
  }
}

// The inverted-element message names the element by its Gmsh tag and by nothing else.
TEST(Numbering, InvertedElementNamedByItsTag) {
  std::istringstream in(offsetRectangleMsh(3.0, 2.0, 3, 2));
  const Mesh mesh = readGmsh(in, "plate.msh");
  ASSERT_EQ(mesh.elementIds.size(), 6u);
  const std::vector<PlaneMatrix> materials{
      isotropicStiffness(2.0e5, 0.3, PlaneAnalysis::PlaneStrain)};
  const std::vector<int> elementMaterial(mesh.numElements(), 0);
  NonlinearDisplacementModel model(mesh, elementMaterial, materials, 1.0);
  model.prescribe(0, 0, 0.0);
  LinearSolverOptions direct;
  direct.type = LinearSolverType::Direct;
  model.setup(direct, MPI_COMM_WORLD);
  // Push the third corner of element 4 (index) through its first corner.
  const LocalIndex e = 4, a = mesh.node(e, 0), c = mesh.node(e, 2);
  std::vector<double> u(2 * mesh.numNodes(), 0.0);
  u[2 * c] = 1.5 * (mesh.x(a) - mesh.x(c));
  u[2 * c + 1] = 1.5 * (mesh.y(a) - mesh.y(c));
  model.setDisplacement(u);
  EXPECT_FALSE(std::isfinite(model.evaluate(1.0, false)));
  ASSERT_GE(model.invertedElement(), 0);
  const std::string msg = model.invertedElementMessage();
  const long tag = mesh.elementIds[static_cast<std::size_t>(model.invertedElement())];
  EXPECT_GE(tag, kElementTag0);
  EXPECT_EQ(msg.rfind("element " + std::to_string(tag) + " is inverted", 0), 0u) << msg;
  EXPECT_EQ(msg.find("index"), std::string::npos) << msg;
}
