// Reader for Gmsh 4.1 ASCII meshes (.msh) of 4-node and 8-node quadrilaterals. Physical groups
// name things: 2D groups are regions, 1D groups are boundaries (their line elements are matched
// to element edges), 0D groups are node sets. First stage of the data flow.
#pragma once

#include <mesh/Mesh.hpp>

#include <cstddef>
#include <fstream>
#include <istream>
#include <string>

namespace mixcon {

/// Reads a Gmsh 4.1 ASCII file. Throws InputError naming the file and line on malformed or
/// unsupported content (binary files, other element types, mixed element orders).
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
