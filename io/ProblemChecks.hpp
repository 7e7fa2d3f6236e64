// Strictness checks of the problem reader (io/Problem.cpp) that look at the document or the read
// problem as a whole: repeated keys, conflicting boundary conditions, clipped echoes of values.
// Internal to the reader. Data flow: io (input side).
#pragma once

#include <io/Problem.hpp>

#include <string>
#include <vector>

namespace YAML {
class Node;
} // namespace YAML

namespace mixcon::detail {

/// Refuses a map anywhere in the document (block or flow style) that gives a key twice (yaml-cpp
/// keeps both pairs; a lookup would silently take the first): InputError
/// "file:line:column: path: key 'E' given twice (first at line 8)".
void checkDuplicateKeys(const YAML::Node &root, const std::string &file);

/// Refuses two boundary_conditions entries that prescribe the same component of a node (the same
/// set, or two sets sharing the node) with different values, naming both entries with their
/// lines and the node. Two entries on the same set that prescribe a component with the same value
/// pass, with a warning appended to `warnings`.
void checkDirichletConflicts(const Mesh &mesh, const std::vector<DirichletSpec> &dirichlet,
                             const std::string &file, std::vector<std::string> &warnings);

/// `message` with every quoted value ('...') longer than about 80 characters cut with "...".
std::string clipQuoted(const std::string &message);

} // namespace mixcon::detail
