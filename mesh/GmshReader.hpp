// Reader for Gmsh 4.1 ASCII meshes (.msh) of 4-node and 8-node quadrilaterals. Physical groups
// name things: 2D groups are regions, 1D groups are boundaries (their line elements are matched
// to element edges), 0D groups are node sets. First stage of the data flow.
#pragma once

#include <mesh/Mesh.hpp>

#include <istream>
#include <string>

namespace mixcon {

/// Reads a Gmsh 4.1 ASCII file. Throws InputError naming the file and line on malformed or
/// unsupported content (binary files, other element types, mixed element orders).
Mesh readGmsh(const std::string &path);

/// Same, from a stream; `name` is used in messages.
Mesh readGmsh(std::istream &in, const std::string &name);

} // namespace mixcon
