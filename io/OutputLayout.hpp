// How the results files name an element type's cells and a dimension's geometry and field
// components: the XDMF topology and geometry types, the vector and Voigt stress component names,
// from one table keyed by element type (its traits' kName) and dimension, so that a new element
// type (the 3D ones) adds a row rather than a branch in the writer. Layer: io.
#pragma once

#include <mesh/Mesh.hpp>

#include <string>
#include <vector>

namespace mixcon {

/// One row of the output table: an element type in a dimension and the names its results use.
struct OutputNames {
  int dim = 0;                               ///< spatial dimension
  std::string element;                       ///< element traits' kName ("quad4", "hex8", ...)
  int nodesPerElement = 0;                   ///< nodes per cell, the connectivity's columns
  std::string topology;                      ///< XDMF 3 TopologyType of the cells
  std::string geometry;                      ///< XDMF 3 GeometryType of the node coordinates
  std::vector<std::string> vectorComponents; ///< x y (z): nodal vectors' components
  std::vector<std::string> stressComponents; ///< Voigt order of Voigt<dim>: xx yy (zz yz xz) xy
  /// The columns of results.xdmf's `stress` array, in the order ParaView labels them by position:
  /// X Y Z (= xx yy xy, the dataset's own order) in 2D; VTK's symmetric-tensor order
  /// XX YY ZZ XY YZ XZ (= xx yy zz xy yz xz) in 3D, which is not the Voigt order of the dataset.
  std::vector<std::string> xdmfStressComponents;
  /// The step's dataset that results.xdmf's `stress` attribute points at: "stress" itself where
  /// xdmfStressComponents is its order (2D), else "stress_vtk", a copy of its columns in
  /// xdmfStressComponents' order (3D). ParaView 5.11's Xdmf3 reader skips HyperSlab and Function
  /// data items, so the XDMF cannot reorder the columns of "stress" itself.
  std::string xdmfStressDataset;
  /// XDMF AttributeType of the `stress` attribute: "Vector" in 2D (3 columns, what ParaView reads
  /// as one array); "Matrix" in 3D, N x 6 read column by column. Not "Tensor6": XDMF orders a
  /// Tensor6 xx xy xz yy yz zz (ParaView's legacy Xdmf2 reader expands it into 3 x 3 in that
  /// order), which is neither the Voigt nor VTK's order; its Xdmf3 reader treats both alike.
  std::string stressAttribute;
};

/// Every row of the table: 2D quad4, quad8; 3D hex8, hex20, tet4, tet10.
const std::vector<OutputNames> &outputTable();

/// The row of `element` (traits' kName) in dimension `dim`; throws std::invalid_argument naming
/// both when the table has none.
const OutputNames &outputNames(const std::string &element, int dim);

/// The row of a mesh's element type and dimension.
const OutputNames &outputNames(const Mesh &mesh);

/// For each column of results.xdmf's `stress` array (row.xdmfStressComponents), the column of the
/// step's `stress` dataset (row.stressComponents) it holds: 0 1 2 in 2D, 0 1 2 5 3 4 in 3D.
std::vector<int> xdmfStressColumns(const OutputNames &row);

} // namespace mixcon
