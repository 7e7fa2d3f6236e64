// The output table (io/OutputLayout.hpp). Layer: io.
#include <io/OutputLayout.hpp>

#include <algorithm>
#include <stdexcept>

namespace mixcon {

namespace {

/// XDMF 3 names (XdmfTopologyType, XdmfGeometryType); component names in the order of the
/// datasets' columns (Voigt<Dim>: xx yy xy in 2D, xx yy zz yz xz xy in 3D) and of the XDMF's
/// stress array (VTK's symmetric-tensor order in 3D, io/OutputLayout.hpp).
std::vector<OutputNames> makeTable() {
  const std::vector<std::string> v2 = {"x", "y"}, v3 = {"x", "y", "z"};
  const std::vector<std::string> s2 = {"xx", "yy", "xy"}, s3 = {"xx", "yy", "zz", "yz", "xz", "xy"};
  const std::vector<std::string> vtk3 = {"xx", "yy", "zz", "xy", "yz", "xz"};
  return {
      {2, "quad4", 4, "Quadrilateral", "XY", v2, s2, s2, "stress", "Vector"},
      {2, "quad8", 8, "Quadrilateral_8", "XY", v2, s2, s2, "stress", "Vector"},
      {3, "hex8", 8, "Hexahedron", "XYZ", v3, s3, vtk3, "stress_vtk", "Matrix"},
      {3, "hex20", 20, "Hexahedron_20", "XYZ", v3, s3, vtk3, "stress_vtk", "Matrix"},
      {3, "tet4", 4, "Tetrahedron", "XYZ", v3, s3, vtk3, "stress_vtk", "Matrix"},
      {3, "tet10", 10, "Tetrahedron_10", "XYZ", v3, s3, vtk3, "stress_vtk", "Matrix"},
  };
}

} // namespace

const std::vector<OutputNames> &outputTable() {
  static const std::vector<OutputNames> table = makeTable();
  return table;
}

const OutputNames &outputNames(const std::string &element, int dim) {
  for (const OutputNames &row : outputTable())
    if (row.element == element && row.dim == dim)
      return row;
  throw std::invalid_argument("output: no XDMF names for element type '" + element + "' in " +
                              std::to_string(dim) + "D");
}

std::vector<int> xdmfStressColumns(const OutputNames &row) {
  std::vector<int> columns;
  for (const std::string &name : row.xdmfStressComponents) {
    const auto at = std::find(row.stressComponents.begin(), row.stressComponents.end(), name);
    if (at == row.stressComponents.end())
      throw std::logic_error("output table: XDMF stress component '" + name + "' of " +
                             row.element + " is not a column of the stress dataset");
    columns.push_back(static_cast<int>(at - row.stressComponents.begin()));
  }
  return columns;
}

const OutputNames &outputNames(const Mesh &mesh) {
  return outputNames(elementTypeName(mesh.elementType), mesh.dim());
}

} // namespace mixcon
