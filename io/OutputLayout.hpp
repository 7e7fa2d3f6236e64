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
  /// XDMF AttributeType of the nodal stress: "Vector" in 2D (3 columns, what ParaView reads as
  /// one array), "Tensor6" in 3D. XDMF lists a Tensor6 as xx xy xz yy yz zz, so a reader labels
  /// the Voigt columns in that order; the `components` attribute names them.
  std::string stressAttribute;
};

/// Every row of the table: 2D quad4, quad8; 3D hex8, hex20, tet4, tet10.
const std::vector<OutputNames> &outputTable();

/// The row of `element` (traits' kName) in dimension `dim`; throws std::invalid_argument naming
/// both when the table has none.
const OutputNames &outputNames(const std::string &element, int dim);

/// The row of a mesh's element type and dimension.
const OutputNames &outputNames(const Mesh &mesh);

} // namespace mixcon
