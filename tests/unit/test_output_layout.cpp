// The output table (io/OutputLayout.hpp): XDMF topology and geometry names and component names by
// element type and dimension, 3D rows included, and the results writer taking its names from it.
#include <io/OutputLayout.hpp>
#include <io/Results.hpp>
#include <mesh/Generators.hpp>
#include <support/Program.hpp>

#include <gtest/gtest.h>

#include <hdf5.h>

#include <cctype>
#include <fstream>
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
    // 3 columns are a vector to ParaView; 6 a symmetric tensor.
    EXPECT_EQ(row.stressAttribute, row.stressComponents.size() == 3 ? "Vector" : "Tensor6");
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
    const hid_t stress = H5Dopen2(file, "/steps/1/stress", H5P_DEFAULT);
    const hid_t a = H5Aopen(stress, "components", H5P_DEFAULT);
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
    H5Dclose(stress);
    H5Fclose(file);
    EXPECT_EQ(names, row.stressComponents);
  }
}
