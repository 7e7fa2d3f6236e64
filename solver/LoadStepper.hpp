// The load-step / Newton driver of the report (Eq. (27)-(28)): full Newton-Raphson, modified
// Newton-Raphson (tangent formed once per increment) or no equilibrium iterations on a
// NonlinearModel; convergence on the report's relative increment norm epsilon plus a relative
// force-residual norm; the nested contact status iterations; automatic step cutting when an
// increment fails. Layer: solver.
#pragma once

#include <solver/NonlinearModel.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace mixcon {

/// One iteration's record.
struct IterationRecord {
  double increment = 0.0; ///< relative increment norm after the correction
  double residual = 0.0;  ///< relative residual after the correction
  int linearIterations = 0;
};

/// Outcome of advancing to one requested load factor (possibly in cut sub-increments).
struct IncrementOutcome {
  bool converged = false;
  int iterations = 0; ///< corrections over all sub-increments
  int linearIterations = 0;
  int cuts = 0;
  int subincrements = 0;
  int contactIterations = 0;            ///< status updates over all sub-increments
  bool contactCycled = false;           ///< a repeated status pattern was detected (and frozen)
  double initialResidual = 0.0;         ///< of the last sub-increment, before its first correction
  std::vector<IterationRecord> history; ///< of the last (converged) sub-increment
  std::string message;                  ///< why it failed
  double solveSeconds = 0.0;
};

/// Drives a NonlinearModel through load factors. Writes to `log` (nullptr: nothing) its warnings
/// (cycling, cuts) always and, with Verbosity::Verbose, a line per iteration and per contact
/// status change.
class LoadStepper {
public:
  LoadStepper(NonlinearModel &model, const NonlinearOptions &options, std::ostream *log = nullptr,
              Verbosity verbosity = Verbosity::Verbose);
  /// Advances from the committed load factor to `target`, cutting the increment on failure.
  IncrementOutcome advance(double target);
  double loadFactor() const { return lambda_; }
  /// Continues from a restored state at load factor `lambda` (restart): the model's and the
  /// contact's committed states must have been restored before (restoreCommitted).
  void resume(double lambda) {
    lambda_ = lambda;
    contactStarted_ = model_.contactIterations() != nullptr;
    resumed_ = true;
  }
  /// The iteration settings from the next increment on (a stage's own).
  void setOptions(const NonlinearOptions &options) { options_ = options; }

private:
  bool attempt(double lambda, IncrementOutcome &out, std::string &why);
  bool settleContact(double lambda, IncrementOutcome &out, std::string &why);
  /// model_.commit(); false, with why, where it throws CommitFailure.
  bool commitModel(std::string &why);
  std::string contactHint() const;
  NonlinearModel &model_;
  NonlinearOptions options_;
  std::ostream *log_;
  std::ostream *detail_; ///< log_ with Verbosity::Verbose, else nullptr
  double lambda_ = 0.0;
  bool contactStarted_ = false;
  bool resumed_ = false; ///< continued from a committed state (restart, a later stage)
};

/// Convergence orders log(r_k+1 / r_k) / log(r_k / r_k-1) of a residual history (2: quadratic).
std::vector<double> convergenceOrders(const std::vector<double> &residuals);

} // namespace mixcon
