// The analysis driver behind `mixcon run`: problem -> model -> load steps -> results. Reusable by
// embedding codes and tests. Data flow: apps (uses mesh, kernels, solver, io).
#pragma once

#include <apps/Verification.hpp>
#include <io/Problem.hpp>
#include <io/Results.hpp>
#include <solver/Nonlinear.hpp>

#include <iosfwd>
#include <optional>
#include <vector>

namespace mixcon {

struct RunOptions {
  std::string outputDirectory; ///< overrides the problem's output.directory when not empty
  std::ostream *log = nullptr; ///< progress lines and warnings; nullptr: silent
  /// What goes to `log`: Normal (the model lines, one line per step, warnings, the files
  /// written), Quiet (warnings only) or Verbose (also every iteration and contact status change).
  Verbosity verbosity = Verbosity::Normal;
  /// Continue the run whose output folder this is from its last converged step (nonlinear or
  /// contact analyses; the results go on in outputDirectory, by default this folder).
  std::string restartDirectory;
};

struct RunResult {
  std::vector<StepRecord> steps;
  bool converged = false;
  std::optional<VerificationResult> verification;
  std::vector<double> displacement; ///< last step, N x 2
  std::vector<double> stress;       ///< last step, N x 3
  std::string outputDirectory;
  /// Contact corrections solved on a kept factorization of the stiffness (the direct solver,
  /// solver/CapacitanceSolve.hpp), and the factorizations they used.
  int keptFactorizationCorrections = 0, keptFactorizations = 0;
};

/// Runs the analysis a problem describes and writes its results. Non-convergence of a step is
/// reported in the result (converged = false, and in summary.json), not thrown.
RunResult runAnalysis(const Problem &problem, const RunOptions &options, MPI_Comm comm);

} // namespace mixcon
