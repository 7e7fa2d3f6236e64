// The load-step / Newton driver (solver/LoadStepper.hpp). Layer: solver.
#include <solver/FieldOps.hpp>
#include <solver/LoadStepper.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>
#include <set>
#include <sstream>

namespace mixcon {

using namespace fieldops;

LoadStepper::LoadStepper(NonlinearModel &model, const NonlinearOptions &options, std::ostream *log,
                         Verbosity verbosity)
    : model_(model), options_(options), log_(log),
      detail_(verbosity == Verbosity::Verbose ? log : nullptr) {}

std::string LoadStepper::contactHint() const {
  return model_.contactIterations()
             ? "; with contact, a body held only by obstacles has rigid-body modes "
               "until it touches them: start it touching (gap 0) or hold it by a "
               "displacement condition"
             : "";
}

bool LoadStepper::attempt(double lambda, IncrementOutcome &out, std::string &why) {
  out.history.clear();
  ContactIterations *contact = model_.contactIterations();
  if (contact)
    contact->setLoadFactor(lambda);
  double r0 = model_.evaluate(lambda, true);
  // A force-driven obstacle without support first moves along its force onto the body.
  const bool seated = contact && contact->seatForceDriven() > 0;
  if (seated)
    r0 = model_.evaluate(lambda, true);
  if (contact && (!contactStarted_ || seated)) {
    // Nodes touching an obstacle in the initial state close before the first correction, so a
    // body resting on an obstacle is supported from the start.
    contactStarted_ = true;
    if (contact->closeTouching(1e-12) > 0)
      r0 = model_.evaluate(lambda, true);
  }
  out.initialResidual = r0;
  if (!std::isfinite(r0)) {
    why = model_.invertedElementMessage() + " at the start of the increment";
    return false;
  }
  // A linear body against flat obstacles (or none): the first converged solve is the answer and
  // the residual criterion alone decides (|du|/|u| is then the whole step, not an error).
  const bool linear = model_.linearResponse() && (!contact || contact->linearConstraints());
  for (int it = 1; it <= options_.maxIterations; ++it) {
    double inc = 0.0;
    LinearSolveStats s;
    try {
      s = model_.correct(lambda, inc);
    } catch (const InputError &) {
      throw; // a modelling error, not a failed increment
    } catch (const std::runtime_error &e) {
      why = std::string("the linear solve failed: ") + e.what() + contactHint();
      return false;
    }
    ++out.iterations;
    out.linearIterations += s.iterations;
    if (!s.note.empty() && log_)
      *log_ << "    load factor " << lambda << ", iteration " << it << ": " << s.note << "\n";
    out.solveSeconds += s.solveSeconds;
    if (!s.converged) {
      std::ostringstream m;
      m << "the linear solver did not converge (relative residual " << s.relativeResidual
        << " after " << s.iterations << " iterations)";
      why = m.str() + contactHint();
      return false;
    }
    const bool tangent = options_.method == IterationMethod::Newton;
    const double r = model_.evaluate(lambda, tangent);
    out.history.push_back({inc, r, s.iterations});
    if (detail_) {
      char line[200];
      std::snprintf(line, sizeof line,
                    "    load factor %.5g  iteration %d  |du|/|u| %.3e  residual %.3e  linear its "
                    "%d\n",
                    lambda, it, inc, r, s.iterations);
      *detail_ << line << std::flush;
    }
    if (!std::isfinite(r) || !std::isfinite(inc)) {
      why = model_.invertedElement() >= 0 ? model_.invertedElementMessage()
                                          : std::string("the residual is not finite");
      return false;
    }
    if (options_.method == IterationMethod::None)
      return true;
    if ((inc <= options_.tolerance || linear) && r <= options_.residualTolerance)
      return true;
    if (it >= 3 && r > 1e3 * std::max(r0, options_.residualTolerance)) {
      why = "the iteration diverges (residual " + std::to_string(r) + ")";
      return false;
    }
  }
  std::ostringstream m;
  m << "no convergence in " << options_.maxIterations
    << " iterations (|du|/|u| = " << out.history.back().increment
    << ", residual = " << out.history.back().residual << ")";
  why = m.str();
  return false;
}

bool LoadStepper::settleContact(double lambda, IncrementOutcome &out, std::string &why) {
  // The report's nested iterations: after equilibrium, update the contact statuses from the
  // positions and contact forces; while any changed, iterate equilibrium again at this load.
  ContactIterations *contact = model_.contactIterations();
  if (!contact)
    return true;
  std::string previous = contact->signature();
  std::set<std::string> seen{previous};
  bool frozen = false;
  for (int it = 0; it < options_.maxContactIterations; ++it) {
    std::string changesLog;
    // The residual and stresses where the status update reads them (the candidate nodes of
    // rigid contact: O(candidates) copied), or everywhere.
    const std::vector<LocalIndex> *nodes = contact->statusNodes();
    const auto stress = nodes ? model_.contactStressHost(*nodes) : model_.contactStressHost();
    const auto g = nodes ? model_.residualVectorHost(*nodes) : model_.residualVectorHost();
    const int changes = contact->updateStatus(g, model_.unknownsPerNode(), changesLog,
                                              stress.empty() ? nullptr : &stress, frozen);
    ++out.contactIterations;
    if (detail_ && !changesLog.empty())
      *detail_ << changesLog;
    if (changes == 0) {
      std::string where;
      if (!contact->penetrationWithin(1e-6, where)) {
        why = "penetration above 1e-6 of the obstacle size after convergence: " + where;
        return false;
      }
      return true;
    }
    // Only status changes can cycle; friction-force updates alone keep the signature.
    const std::string signature = contact->signature();
    const bool statusChanged = signature != previous;
    previous = signature;
    if (statusChanged && !seen.insert(signature).second) {
      // A status pattern came back: the active set cycles. Resolve it by keeping the current
      // pattern and iterating only the friction forces to mu N, and report it.
      out.contactCycled = true;
      frozen = true;
      if (log_)
        *log_ << "    contact: the active set cycles at load factor " << lambda
              << "; keeping the current pattern\n";
    }
    if (!attempt(lambda, out, why))
      return false;
  }
  why = "the contact statuses did not settle in " + std::to_string(options_.maxContactIterations) +
        " contact iterations";
  return false;
}

bool LoadStepper::commitModel(std::string &why) {
  try {
    model_.commit();
  } catch (const CommitFailure &e) { // the committed state is unchanged: cut as for a divergence
    why = e.what();
    return false;
  }
  return true;
}

IncrementOutcome LoadStepper::advance(double target) {
  IncrementOutcome out;
  double step = target - lambda_;
  while (std::abs(target - lambda_) > 1e-14 * std::max(1.0, std::abs(target))) {
    const double next =
        std::abs(target - lambda_) <= std::abs(step) * (1 + 1e-12) ? target : lambda_ + step;
    std::string why;
    if (attempt(next, out, why) && settleContact(next, out, why) && commitModel(why)) {
      model_.noteCommitted();
      if (model_.contactIterations())
        model_.contactIterations()->commit();
      lambda_ = next;
      ++out.subincrements;
      continue;
    }
    model_.rollback();
    if (model_.contactIterations())
      model_.contactIterations()->rollback();
    if (out.subincrements == 0 && lambda_ == 0.0 && !resumed_)
      contactStarted_ = false; // back at the initial state: close the touching nodes again
    if (++out.cuts > options_.maxCuts) {
      std::ostringstream m;
      m << "load factor " << next << ": " << why << "; gave up after " << options_.maxCuts
        << " increment cuts (last increment " << step << ")";
      out.message = m.str();
      return out;
    }
    if (log_)
      *log_ << "    load factor " << next << ": " << why << "; cutting the increment to "
            << step / 2 << "\n";
    step *= 0.5;
  }
  out.converged = true;
  return out;
}

std::vector<double> convergenceOrders(const std::vector<double> &r) {
  std::vector<double> q;
  for (std::size_t k = 2; k < r.size(); ++k)
    if (r[k] > 0 && r[k - 1] > 0 && r[k - 2] > 0 && r[k - 1] != r[k - 2])
      q.push_back(std::log(r[k] / r[k - 1]) / std::log(r[k - 1] / r[k - 2]));
  return q;
}

} // namespace mixcon
