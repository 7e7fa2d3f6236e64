// What the linear mixed model's tests compare between two solves of the same problem: the
// displacements, nodal stresses and reactions read back from a MixedModel after solve(), and the
// largest difference relative to the reference's largest entry. Tests only.
#pragma once

#include <solver/MixedModel.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace mixcon::test {

/// max_i |a_i - b_i| / max_i |b_i| (b the reference; a and b of the same size).
inline double maxRelativeDifference(const std::vector<double> &a, const std::vector<double> &b) {
  double d = 0.0, s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    s = std::max(s, std::abs(b[i]));
  }
  return d / s;
}

/// One solve of a set-up MixedModel and its fields on the host.
struct MixedSolution {
  std::vector<double> u, s, reaction; ///< displacements, nodal stresses, reactions
  LinearSolveStats stats;
};

/// Solves `model` (set up) at load factor `load` and reads its fields back.
inline MixedSolution solveMixed(MixedModel &model, double load = 1.0) {
  MixedSolution r;
  r.stats = model.solve(load);
  r.u = model.displacementHost();
  r.s = model.nodalStressHost();
  r.reaction = model.reactionHost(load);
  return r;
}

} // namespace mixcon::test
