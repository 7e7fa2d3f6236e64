// Strictness checks of the problem reader on the whole document or problem: repeated keys,
// conflicting boundary conditions, clipped echoes of long values (io/ProblemChecks.hpp).
#include <io/ProblemChecks.hpp>
#include <mesh/GmshReader.hpp>

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>

namespace mixcon::detail {

namespace {

std::string location(const std::string &file, const YAML::Mark &m) {
  return file + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

void checkNode(const YAML::Node &node, const std::string &path, const std::string &file,
               std::set<std::pair<int, int>> &visited) {
  if (!node.IsMap() && !node.IsSequence())
    return;
  // An alias is the anchored node again (same mark): check it once, so that nested aliases do not
  // multiply the work.
  const YAML::Mark mark = node.Mark();
  if (!visited.insert({mark.line, mark.column}).second)
    return;
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      checkNode(node[i], path + "[" + std::to_string(i) + "]", file, visited);
    return;
  }
  std::map<std::string, YAML::Mark> seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    if (!it->first.IsScalar())
      continue; // the reader refuses non-scalar keys where it reads the map
    const std::string key = it->first.Scalar();
    const YAML::Mark at = it->first.Mark();
    const auto [first, inserted] = seen.emplace(key, at);
    if (!inserted) {
      const YAML::Mark f = first->second;
      std::string msg = location(file, at) + ": " + (path.empty() ? "" : path + ": ") + "key '" +
                        clipValue(key) + "' given twice (first at line " +
                        std::to_string(f.line + 1);
      if (f.line == at.line)
        msg += ", column " + std::to_string(f.column + 1);
      throw InputError(msg + ")");
    }
    checkNode(it->second, path.empty() ? key : path + "." + key, file, visited);
  }
}

/// The shortest decimal that reads back as `v` (0.1, not 0.10000000000000001).
std::string formatValue(double v) {
  std::ostringstream s;
  for (int digits = 6; digits <= 17; ++digits) {
    s.str("");
    s.precision(digits);
    s << v;
    if (std::stod(s.str()) == v)
      break;
  }
  return s.str();
}

} // namespace

void checkDuplicateKeys(const YAML::Node &root, const std::string &file) {
  std::set<std::pair<int, int>> visited;
  checkNode(root, "", file, visited);
}

void checkDirichletConflicts(const Mesh &mesh, const std::vector<DirichletSpec> &dirichlet,
                             const std::string &file, std::vector<std::string> &warnings) {
  const char *names[3] = {"ux", "uy", "uz"};
  const auto component = [](const DirichletSpec &d, int c) -> const std::optional<double> & {
    return c == 0 ? d.ux : (c == 1 ? d.uy : d.uz);
  };
  auto entry = [&](std::size_t k) {
    return "boundary_conditions[" + std::to_string(k) + "] (line " +
           std::to_string(dirichlet[k].line) + ", on '" + dirichlet[k].target + "')";
  };
  for (int c = 0; c < mesh.dim(); ++c) {
    std::map<LocalIndex, std::size_t> owner; // node -> first entry prescribing component c
    std::set<std::pair<std::size_t, std::size_t>> warned;
    for (std::size_t k = 0; k < dirichlet.size(); ++k) {
      const auto &value = component(dirichlet[k], c);
      if (!value)
        continue;
      for (LocalIndex n : mesh.nodesOf(dirichlet[k].target)) {
        const auto [it, inserted] = owner.emplace(n, k);
        if (inserted)
          continue;
        const std::size_t j = it->second;
        const double other = *component(dirichlet[j], c);
        if (other != *value)
          throw InputError(file + ":" + std::to_string(dirichlet[k].line) + ": " + entry(k) +
                           " prescribes " + names[c] + " = " + formatValue(*value) + " at node " +
                           std::to_string(mesh.nodeIds[n]) + " but " + entry(j) + " prescribes " +
                           names[c] + " = " + formatValue(other) +
                           " there: conflicting boundary conditions (give each node one value)");
        if (dirichlet[j].target == dirichlet[k].target && warned.insert({j, k}).second)
          warnings.push_back(file + ":" + std::to_string(dirichlet[k].line) + ": " + entry(k) +
                             " repeats " + names[c] + " = " + formatValue(*value) + " of " +
                             entry(j));
      }
    }
  }
}

std::string clipQuoted(const std::string &message) {
  // A quote opens where no letter or digit precedes it and closes where none follows it, so that
  // the apostrophe of "model's" is text, not a quote.
  auto word = [&](std::size_t k) {
    return k < message.size() && std::isalnum(static_cast<unsigned char>(message[k]));
  };
  std::string out;
  std::size_t i = 0;
  while (i < message.size()) {
    std::size_t open = message.find('\'', i);
    while (open != std::string::npos && open > 0 && word(open - 1))
      open = message.find('\'', open + 1);
    if (open == std::string::npos)
      break;
    std::size_t close = message.find('\'', open + 1);
    while (close != std::string::npos && word(close + 1))
      close = message.find('\'', close + 1);
    if (close == std::string::npos)
      break;
    out += message.substr(i, open + 1 - i);
    out += clipValue(message.substr(open + 1, close - open - 1));
    out += '\'';
    i = close + 1;
  }
  return out + (i < message.size() ? message.substr(i) : "");
}

} // namespace mixcon::detail
