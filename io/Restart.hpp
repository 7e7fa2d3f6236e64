// Reading a run back for `mixcon run --restart`: the steps it wrote up to its last converged one
// with a saved state, and that state (written by ResultsWriter with every converged step).
// Data flow: io (input side of the output files).
#pragma once

#include <io/Results.hpp>

#include <string>
#include <vector>

namespace mixcon {

/// Where a restarted run continues: the steps already written (up to the last converged one
/// with a saved state) and that state.
struct RestartPoint {
  std::vector<WrittenStep> steps; ///< steps 1..k as written (load factors, convergence)
  Checkpoint state;               ///< the committed state after step k
  std::string directory;          ///< the folder it was read from
  long numNodes = 0, numElements = 0;
  std::vector<double> nodes; ///< mesh coordinates, N x 2 (to check the problem's mesh)
  int lastStep() const { return steps.empty() ? 0 : steps.back().record.step; }
};

/// Reads the last converged step with a saved state from `directory`/results.h5; throws
/// InputError naming the file when there is none or the file cannot be read.
RestartPoint readRestart(const std::string &directory);

} // namespace mixcon
