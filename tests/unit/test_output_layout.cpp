// The output table (io/OutputLayout.hpp): XDMF topology and geometry names and component names by
// element type and dimension, 3D rows included, and the results writer taking its names from it;
// the XDMF's stress array in the column order ParaView labels (3D: a copy of the Voigt dataset).
#include <io/OutputLayout.hpp>
#include <io/Results.hpp>
#include <mesh/Generators.hpp>
#include <support/Program.hpp>

#include <gtest/gtest.h>

#include <hdf5.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

using namespace mixcon;

namespace {

const char kAxis[3] = {'x', 'y', 'z'};

/// The Voigt component names of Voigt<Dim>, from its (row, column) map.
template <int Dim> std::vector<std::string> voigtNames() {
  std::vector<std::string> names;
  for (int k = 0; k < Voigt<Dim>::kSize; ++k)
    names.push_back(std::string{kAxis[Voigt<Dim>::row(k)], kAxis[Voigt<Dim>::col(k)]});
  return names;
}

/// VTK's order of a symmetric tensor's 6 components, in which ParaView labels a 6-column array
/// XX YY ZZ XY YZ XZ (vtkMath::TensorFromSymmetricTensor; ParaView's default component names).
const std::vector<std::string> kVtkSymmetricOrder = {"xx", "yy", "zz", "xy", "yz", "xz"};

/// The string list attribute `name` of the dataset `path` (the `components` of a stress dataset).
std::vector<std::string> readStringList(hid_t file, const std::string &path, const char *name) {
  const hid_t set = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (set < 0)
    return {};
  const hid_t a = H5Aopen(set, name, H5P_DEFAULT);
  const hid_t stringType = H5Aget_type(a);
  const std::size_t width = H5Tget_size(stringType);
  const hid_t aspace = H5Aget_space(a);
  const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(aspace));
  std::string packed(width * count, '\0');
  H5Aread(a, stringType, packed.data());
  std::vector<std::string> names;
  for (std::size_t i = 0; i < count; ++i) {
    std::string s = packed.substr(i * width, width);
    names.push_back(s.substr(0, s.find('\0')));
  }
  H5Sclose(aspace);
  H5Tclose(stringType);
  H5Aclose(a);
  H5Dclose(set);
  return names;
}

/// A 2-D float64 dataset's values (row-major) and its (rows, columns); empty when there is none.
std::vector<double> readMatrix(hid_t file, const std::string &path, hsize_t (&dims)[2]) {
  dims[0] = dims[1] = 0;
  if (H5Lexists(file, path.c_str(), H5P_DEFAULT) <= 0)
    return {};
  const hid_t set = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(set);
  H5Sget_simple_extent_dims(space, dims, nullptr);
  H5Sclose(space);
  std::vector<double> values(static_cast<std::size_t>(dims[0] * dims[1]));
  H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Dclose(set);
  return values;
}

/// The `stress` node attribute of an XDMF grid: its AttributeType, its DataItem's Dimensions and
/// the HDF5 path it points at (after "results.h5:").
struct XdmfStress {
  std::string type, dimensions, path;
};

/// The `stress` attributes of every grid (step) of an XDMF text, in order.
std::vector<XdmfStress> xdmfStress(const std::string &xdmf) {
  static const std::regex attribute(
      "<Attribute Name=\"stress\" AttributeType=\"([^\"]*)\"[^>]*>\\s*"
      "<DataItem Dimensions=\"([^\"]*)\"[^>]*>results\\.h5:([^<]*)</DataItem>");
  std::vector<XdmfStress> found;
  for (auto it = std::sregex_iterator(xdmf.begin(), xdmf.end(), attribute);
       it != std::sregex_iterator(); ++it)
    found.push_back({(*it)[1], (*it)[2], (*it)[3]});
  return found;
}

std::string readText(const std::filesystem::path &path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Writes one step of `mesh` with a stress that differs in every node and column (100 node +
/// column) into `dir`; returns that stress.
std::vector<double> writeOneStep(const Mesh &mesh, const std::filesystem::path &dir) {
  const OutputNames &row = outputNames(mesh);
  const auto nn = static_cast<std::size_t>(mesh.numNodes());
  const std::size_t ns = row.stressComponents.size(), q = row.dim == 2 ? 4 : 8;
  const std::size_t nq = static_cast<std::size_t>(mesh.numElements()) * q;
  StepFields f;
  f.displacement.assign(nn * row.dim, 0.5);
  f.stress.resize(nn * ns);
  for (std::size_t i = 0; i < nn; ++i)
    for (std::size_t c = 0; c < ns; ++c)
      f.stress[ns * i + c] = 100.0 * static_cast<double>(i) + static_cast<double>(c);
  f.gaussCoordinates.assign(nq * row.dim, 0.0);
  f.gaussStress.assign(nq * ns, 2.0);
  f.pointsPerElement = static_cast<int>(q);
  StepRecord r;
  r.step = 1;
  r.loadFactor = 1.0;
  r.converged = true;
  ResultsWriter w(dir.string(), mesh, true, "problem.yaml");
  w.writeStep(r, f);
  w.finish(true, "");
  return f.stress;
}

} // namespace

// Every row: vectors have dim components named x, y (, z), the geometry type spells them, and
// the stress components follow Voigt<dim>'s order; (element, dim) keys are unique.
TEST(OutputTable, ComponentsFollowTheDimensionAndVoigtOrder) {
  std::set<std::pair<std::string, int>> keys;
  for (const OutputNames &row : outputTable()) {
    SCOPED_TRACE(row.element);
    EXPECT_TRUE(keys.insert({row.element, row.dim}).second) << "duplicate row";
    ASSERT_TRUE(row.dim == 2 || row.dim == 3);
    ASSERT_EQ(row.vectorComponents.size(), static_cast<std::size_t>(row.dim));
    std::string geometry;
    for (int i = 0; i < row.dim; ++i) {
      EXPECT_EQ(row.vectorComponents[i], std::string(1, kAxis[i]));
      geometry += static_cast<char>(std::toupper(kAxis[i]));
    }
    EXPECT_EQ(row.geometry, geometry);
    EXPECT_EQ(row.stressComponents, row.dim == 2 ? voigtNames<2>() : voigtNames<3>());
    // 3 columns are a vector to ParaView; 6 a matrix read column by column (not an XDMF Tensor6,
    // whose order xx xy xz yy yz zz is neither Voigt's nor VTK's).
    EXPECT_EQ(row.stressAttribute, row.stressComponents.size() == 3 ? "Vector" : "Matrix");
    // The XDMF presents the stress in the order ParaView labels: the dataset's own in 2D (X Y Z
    // = xx yy xy), VTK's symmetric-tensor order in 3D, from a copy of the dataset.
    EXPECT_EQ(row.xdmfStressComponents, row.dim == 2 ? voigtNames<2>() : kVtkSymmetricOrder);
    EXPECT_EQ(row.xdmfStressDataset, row.dim == 2 ? "stress" : "stress_vtk");
    const std::vector<int> columns = xdmfStressColumns(row);
    ASSERT_EQ(columns.size(), row.stressComponents.size());
    std::set<int> distinct(columns.begin(), columns.end());
    EXPECT_EQ(distinct.size(), columns.size()) << "not a permutation";
    for (std::size_t j = 0; j < columns.size(); ++j)
      EXPECT_EQ(row.stressComponents.at(static_cast<std::size_t>(columns[j])),
                row.xdmfStressComponents[j]);
    EXPECT_EQ(&outputNames(row.element, row.dim), &row);
  }
  EXPECT_EQ(keys.size(), 6u);
}

// The 2D rows are the element types' own (name, dimension, node count) and the names the writer
// has always written.
TEST(OutputTable, TwoDimensionalRowsMatchTheElementTraits) {
  for (ElementType type : {ElementType::Quad4, ElementType::Quad8})
    dispatchElement(type, [](auto elem) {
      using Elem = decltype(elem);
      const OutputNames &row = outputNames(Elem::kName, Elem::kDim);
      EXPECT_EQ(row.nodesPerElement, Elem::kNumNodes);
      EXPECT_EQ(row.topology, Elem::kNumNodes == 4 ? "Quadrilateral" : "Quadrilateral_8");
      EXPECT_EQ(row.geometry, "XY");
      const Mesh mesh = rectangleMesh(2.0, 1.0, 2, 1, Elem::kType);
      EXPECT_EQ(&outputNames(mesh), &row);
    });
}

// The 3D rows use the XDMF 3 topology names (XdmfTopologyType) with their node counts.
TEST(OutputTable, ThreeDimensionalRowsUseTheXdmfNames) {
  const struct {
    const char *element;
    int nodes;
    const char *topology;
  } expected[] = {{"hex8", 8, "Hexahedron"},
                  {"hex20", 20, "Hexahedron_20"},
                  {"tet4", 4, "Tetrahedron"},
                  {"tet10", 10, "Tetrahedron_10"}};
  for (const auto &e : expected) {
    const OutputNames &row = outputNames(e.element, 3);
    EXPECT_EQ(row.nodesPerElement, e.nodes) << e.element;
    EXPECT_EQ(row.topology, e.topology) << e.element;
    EXPECT_EQ(row.geometry, "XYZ") << e.element;
    EXPECT_EQ(row.stressComponents.size(), 6u) << e.element;
  }
}

TEST(OutputTable, MissingRowsAreRefusedByName) {
  for (const auto &[element, dim] :
       {std::pair<std::string, int>{"quad4", 3}, {"hex8", 2}, {"pyramid5", 3}}) {
    try {
      (void)outputNames(element, dim);
      ADD_FAILURE() << element << " in " << dim << "D has a row";
    } catch (const std::invalid_argument &e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(element), std::string::npos) << msg;
      EXPECT_NE(msg.find(std::to_string(dim) + "D"), std::string::npos) << msg;
    }
  }
}

// The writer's XDMF topology and geometry types, the node coordinates' columns and the stress
// datasets' `components` attribute are the mesh's row of the table.
TEST(OutputTable, ResultsWriterTakesItsNamesFromTheTable) {
  for (ElementType type : {ElementType::Quad4, ElementType::Quad8}) {
    const Mesh mesh = rectangleMesh(2.0, 1.0, 2, 1, type);
    const OutputNames &row = outputNames(mesh);
    SCOPED_TRACE(row.element);
    test::ScratchDir dir("output-table");
    const auto nn = static_cast<std::size_t>(mesh.numNodes());
    const std::size_t nq = static_cast<std::size_t>(mesh.numElements()) * 4;
    StepFields f;
    f.displacement.assign(nn * row.dim, 0.5);
    f.stress.assign(nn * row.stressComponents.size(), 1.0);
    f.gaussCoordinates.assign(nq * row.dim, 0.0);
    f.gaussStress.assign(nq * row.stressComponents.size(), 2.0);
    f.pointsPerElement = 4;
    StepRecord r;
    r.step = 1;
    r.loadFactor = 1.0;
    r.converged = true;
    {
      ResultsWriter w(dir.path().string(), mesh, true, "problem.yaml");
      w.writeStep(r, f);
      w.finish(true, "");
    }
    std::ifstream in(dir.path() / "results.xdmf");
    std::stringstream xdmf;
    xdmf << in.rdbuf();
    EXPECT_NE(xdmf.str().find("TopologyType=\"" + row.topology + "\""), std::string::npos);
    EXPECT_NE(xdmf.str().find("GeometryType=\"" + row.geometry + "\""), std::string::npos);

    const hid_t file = H5Fopen((dir.path() / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hid_t nodes = H5Dopen2(file, "/mesh/nodes", H5P_DEFAULT);
    hsize_t dims[2] = {0, 0};
    const hid_t space = H5Dget_space(nodes);
    H5Sget_simple_extent_dims(space, dims, nullptr);
    H5Sclose(space);
    H5Dclose(nodes);
    EXPECT_EQ(dims[0], nn);
    EXPECT_EQ(dims[1], row.vectorComponents.size());
    const std::vector<std::string> names = readStringList(file, "/steps/1/stress", "components");
    // 2D: the XDMF's stress is the dataset itself, a Vector of its 3 columns; no copy is written.
    const std::vector<XdmfStress> attr = xdmfStress(xdmf.str());
    ASSERT_EQ(attr.size(), 1u);
    EXPECT_EQ(attr[0].type, "Vector");
    EXPECT_EQ(attr[0].path, "/steps/1/stress");
    EXPECT_EQ(attr[0].dimensions, std::to_string(nn) + " 3");
    EXPECT_EQ(H5Lexists(file, "/steps/1/stress_vtk", H5P_DEFAULT), 0);
    H5Fclose(file);
    EXPECT_EQ(names, row.stressComponents);
  }
}

// 3D: results.h5 keeps the Voigt order (xx yy zz yz xz xy) in /steps/<k>/stress; the XDMF's
// stress attribute points at a copy whose columns are in the order ParaView labels them (XX YY
// ZZ XY YZ XZ), so that each label shows its own component: stress_XY is the dataset's column 5
// (xy), stress_YZ column 3, stress_XZ column 4. The Gauss-point stress, which the XDMF does not
// reference, stays as it was, without a copy.
TEST(OutputTable, ThreeDimensionalXdmfStressIsInParaViewsLabelOrder) {
  const Mesh mesh = boxMesh(2.0, 1.0, 1.0, 2, 1, 1, ElementType::Hex8);
  test::ScratchDir dir("output-table-3d");
  const std::vector<double> stress = writeOneStep(mesh, dir.path());
  const auto nn = static_cast<std::size_t>(mesh.numNodes());
  const std::vector<std::string> voigt = voigtNames<3>();

  const hid_t file = H5Fopen((dir.path() / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  hsize_t dims[2];
  EXPECT_EQ(readMatrix(file, "/steps/1/stress", dims), stress) << "the Voigt dataset changed";
  EXPECT_EQ(dims[1], 6u);
  EXPECT_EQ(readStringList(file, "/steps/1/stress", "components"), voigt);

  const std::vector<XdmfStress> attr = xdmfStress(readText(dir.path() / "results.xdmf"));
  ASSERT_EQ(attr.size(), 1u);
  EXPECT_EQ(attr[0].type, "Matrix");
  EXPECT_EQ(attr[0].dimensions, std::to_string(nn) + " 6");
  const std::vector<double> shown = readMatrix(file, attr[0].path, dims);
  ASSERT_EQ(dims[0], nn);
  ASSERT_EQ(dims[1], 6u);
  const std::vector<std::string> names = readStringList(file, attr[0].path, "components");
  EXPECT_EQ(names, kVtkSymmetricOrder);
  // ParaView's label of column j is kVtkSymmetricOrder[j]; its values must be the Voigt column of
  // that name (found in Voigt<3>'s own map, not in the output table).
  for (std::size_t j = 0; j < 6; ++j) {
    const auto k = static_cast<std::size_t>(
        std::find(voigt.begin(), voigt.end(), kVtkSymmetricOrder[j]) - voigt.begin());
    ASSERT_LT(k, 6u);
    for (std::size_t i = 0; i < nn; ++i)
      ASSERT_EQ(shown[6 * i + j], stress[6 * i + k])
          << "node " << i << ": ParaView's " << kVtkSymmetricOrder[j] << " shows Voigt column " << k
          << "'s value?";
  }
  EXPECT_EQ(readStringList(file, "/steps/1/gauss_points/stress", "components"), voigt);
  EXPECT_EQ(H5Lexists(file, "/steps/1/gauss_points/stress_vtk", H5P_DEFAULT), 0);
  H5Fclose(file);
}
