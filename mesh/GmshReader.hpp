// Reader for Gmsh 4.1 ASCII meshes (.msh) of 4-node or 8-node quadrilaterals (2D) or of 8-node
// or 20-node hexahedra or 4-node or 10-node tetrahedra (3D, Gmsh types 5, 17, 4 and 11, one of
// them per mesh). The mesh's dimension is the highest element dimension in the file. Physical
// groups name things. In 2D: surface groups are regions, curve groups are boundaries (their line
// elements are matched to element edges), point groups are node sets; all nodes must have z = 0;
// clockwise quadrangles are reordered. In 3D: volume groups are regions, surface groups of faces
// are boundaries (4-node quadrangles with 8-node hexahedra, 8-node ones with 20-node hexahedra,
// 3-node triangles with 4-node tetrahedra, 6-node ones with 10-node tetrahedra; each face is
// matched to the element face with the same corner nodes, whatever their order; it must be one,
// and a quadratic face's mid-edge nodes must be that face's), curve groups (2-node lines with
// linear elements, 3-node lines with quadratic ones) and point groups are node sets (their
// nodes). The 20-node hexahedra and 10-node tetrahedra are reordered from Gmsh's node order to
// the internal (VTK) one of core/ElementTraits.hpp. Volume elements are not reoriented
// (validateMesh refuses inverted ones), and other volume types, mixed volume types, 2D elements
// that are not faces, faces or lines of the other order and triangles without tetrahedra are
// refused. Layer: mesh, the first stage of the data flow.
#pragma once

#include <mesh/Mesh.hpp>

#include <cstddef>
#include <fstream>
#include <istream>
#include <string>

namespace mixcon {

/// Reads a Gmsh 4.1 ASCII file. Throws InputError naming the file and line on malformed or
/// unsupported content (binary files, other element types, mixed element types or orders, mixed
/// dimensions, a boundary quadrangle or triangle that is no face of the volume elements or whose
/// mid-edge nodes are not the face's).
Mesh readGmsh(const std::string &path);

/// Same, from a stream; `name` is used in messages.
Mesh readGmsh(std::istream &in, const std::string &name);

/// Longest line an input file (problem, mesh, measurements) may have.
constexpr std::size_t kMaxInputLine = std::size_t(1) << 20;

/// Opens an input file (`what`: "mesh file", ...) after checking by stat that it is a regular
/// file, so that a directory, a device (/dev/zero) or a FIFO is refused before anything is read;
/// throws InputError naming the file.
std::ifstream openInputFile(const std::string &path, const std::string &what);

/// Next line of `in` (without its '\n'), reading at most kMaxInputLine characters of it; false at
/// end of file; throws InputError naming `name` and the line number `line` when longer.
bool readInputLine(std::istream &in, std::string &line, const std::string &name, int lineNumber);

/// The whole text of an input file, through openInputFile and readInputLine; refused (InputError)
/// once it passes `maxBytes`.
std::string readInputFile(const std::string &path, const std::string &what,
                          std::size_t maxBytes = std::string::npos);

/// `value` for an error message: cut to about 80 characters with "..." when longer.
std::string clipValue(const std::string &value);

} // namespace mixcon
