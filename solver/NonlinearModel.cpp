// The nonlinear-problem interface's shared parts (solver/NonlinearModel.hpp): follower loads,
// the common end of an evaluation (contact, relative residual), the contact correction, and
// quadrature-point output. Layer: solver.
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/Krylov.hpp>
#include <solver/LoadStepper.hpp>
#include <solver/NonlinearModel.hpp>

#include <kernels/Nonlinear.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace mixcon {

using namespace fieldops;

const char *iterationMethodName(IterationMethod m) {
  switch (m) {
  case IterationMethod::ModifiedNewton:
    return "modified_newton";
  case IterationMethod::None:
    return "none";
  case IterationMethod::Newton:
  default:
    return "newton";
  }
}

// ---------------------------------------------------------------------------------------------
// NonlinearModel

void NonlinearModel::addFollowerPressure(const std::vector<BoundaryEdge> &edges, double pressure,
                                         double base) {
  for (const auto &e : edges) {
    followerEdges_.push_back(e);
    followerPressure_.push_back(pressure);
    followerBase_.push_back(base);
  }
}

void NonlinearModel::clearFollowerPressures() {
  followerEdges_.clear();
  followerPressure_.clear();
  followerBase_.clear();
}

void NonlinearModel::commitStage() {
  ModelBase::commitStage();
  follower_ = followerLoads();
  contactElimination_ = ConstraintElimination{};
}

std::pair<Kokkos::View<const double *, NonlinearModel::Memory>, double>
NonlinearModel::followerPressureAt(double lambda) const {
  if (follower_.base.extent(0) == 0)
    return {follower_.pressure, lambda};
  affine(follower_.base, lambda, follower_.pressure, follower_.applied);
  return {follower_.applied, 1.0};
}

NonlinearModel::FollowerLoads NonlinearModel::followerLoads() const {
  FollowerLoads f;
  f.edges = Kokkos::View<LocalIndex *[2], Memory>("mixcon::nonlinear::followerEdges",
                                                  followerEdges_.size());
  f.pressure = Kokkos::View<double *, Memory>("mixcon::nonlinear::followerPressure",
                                              followerPressure_.size());
  auto he = hostMirror(f.edges);
  auto hp = hostMirror(f.pressure);
  for (std::size_t k = 0; k < followerEdges_.size(); ++k) {
    he(k, 0) = followerEdges_[k].element;
    he(k, 1) = followerEdges_[k].edge;
    hp(k) = followerPressure_[k];
  }
  copyToDevice(f.edges, he);
  copyToDevice(f.pressure, hp);
  if (staged()) { // a stage: each pressure starts from its base
    f.base =
        Kokkos::View<double *, Memory>("mixcon::nonlinear::followerBase", followerBase_.size());
    f.applied =
        Kokkos::View<double *, Memory>("mixcon::nonlinear::followerApplied", followerBase_.size());
    copyToDevice(f.base, followerBase_);
  }
  return f;
}

Kokkos::View<const double *, Memory>
NonlinearModel::tangentState(const Kokkos::View<double *, Memory> &x) {
  if (!small_)
    return x;
  if (origin_.extent(0) != x.extent(0))
    origin_ = Kokkos::View<double *, Memory>("mixcon::nonlinear::origin", x.extent(0));
  return origin_;
}

double NonlinearModel::finishEvaluate(double lambda, bool tangent, LocalIndex inverted, double fint,
                                      const Kokkos::View<double *, Memory> &g, int stride,
                                      const Kokkos::View<const int *, Memory> &flags,
                                      const Kokkos::View<const double **, Memory> &coordinates,
                                      const Kokkos::View<const double *, Memory> &x,
                                      std::chrono::steady_clock::time_point start) {
  // Contact detection at the positions coordinates + x, the friction forces of slip nodes (on
  // the body), and the relative residual over the free displacement unknowns.
  double free = 0.0;
  if (contact_) {
    contact_->locate(Kokkos::View<const double *[kDisp], Memory>(coordinates), x, stride, flags);
    contact_->subtractForces(g, stride);
    free = contact_->freeResidualNorm(g, flags, stride);
  } else {
    free = strideNorm(g, stride, 0, dim(), flags, 0);
  }
  double fext = std::max(appliedLoadNorm(lambda), followerNorm_);
  followerNorm_ = 0.0;
  if (contact_)
    fext = contact_->externalForceNorm(fext);
  last_[kForceScale] = std::max(fint, fext);
  const double r = relative(free, std::max({fint, fext, forceFloor(strideNorm(u_, 1, 0, 1, {}, 0)),
                                            kHistoryFraction * history_[kForceScale]}));
  fresh_ = tangent;
  assemblySeconds_ += seconds(start);
  invertedElement_ = inverted;
  return inverted >= 0 ? std::numeric_limits<double>::infinity() : r;
}

void NonlinearModel::setStiffnessScale(
    const NodeGraph &graph, const Kokkos::View<int ***, Kokkos::LayoutRight, Memory> &map) {
  // RMS diagonal of K^L on the reference configuration, on the model's own pattern: the force a
  // unit displacement of one node produces.
  auto k = expandGraph<Memory>(graph, dim());
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    assembleLinearStiffness<Elem>(Exec(), elementData<Elem::kDim>(), map, k);
  });
  Vec d("mixcon::nonlinear::stiffnessDiagonal", k.numRows);
  fieldDiagonal(k, 1, 0, 1, d, 1.0);
  stiffnessScale_ = strideNorm(d, 1, 0, 1, {}, 0) / std::sqrt(std::max<double>(1.0, k.numRows));
}

Kokkos::View<double *, NonlinearModel::Memory>
NonlinearModel::followerForce(const Kokkos::View<double *, Memory> &g) {
  if (followerForce_.extent(0) != g.extent(0))
    followerForce_ = Vec("mixcon::nonlinear::followerForce", g.extent(0));
  else
    Kokkos::deep_copy(followerForce_, 0.0);
  return followerForce_;
}

void NonlinearModel::addFollowerForce(const Kokkos::View<double *, Memory> &g, int stride) {
  axpby(1.0, followerForce_, 1.0, g);
  followerNorm_ = strideNorm(followerForce_, stride, 0, dim(), {}, 0);
}

void NonlinearModel::noteCommitted() {
  for (int k = 0; k < 3; ++k)
    history_[k] = std::max(history_[k], last_[k]);
}

void NonlinearModel::setHistoryScales(const std::vector<double> &scales) {
  for (std::size_t k = 0; k < 3 && k < scales.size(); ++k)
    history_[k] = scales[k];
}

double NonlinearModel::relativeToHistory(double change, double norm, Scale scale) {
  last_[scale] = norm;
  return relative(change, std::max(norm, kHistoryFraction * history_[scale]));
}

double NonlinearModel::forceFloor(double displacementNorm) const {
  // 1e-8 of the stiffness scale times ||u|| is round-off level for internal forces: the
  // reference left when a motion is (nearly) rigid and no force acts.
  return 1e-8 * stiffnessScale_ * displacementNorm;
}

std::string NonlinearModel::invertedElementMessage() const {
  if (invertedElement_ < 0)
    return "no element is inverted";
  return "element " + std::to_string(mesh_.elementId(invertedElement_)) +
         " is inverted (non-positive Jacobian in the deformed configuration)";
}

LinearSolveStats NonlinearModel::solve(double loadFactor) {
  LoadStepper stepper(*this, NonlinearOptions{});
  const IncrementOutcome o = stepper.advance(loadFactor);
  LinearSolveStats s;
  s.converged = o.converged;
  s.iterations = o.linearIterations;
  s.relativeResidual = o.history.empty() ? o.initialResidual : o.history.back().residual;
  s.solveSeconds = o.solveSeconds;
  return s;
}

void NonlinearModel::gaussPointStressHost(std::vector<double> &coordinates,
                                          std::vector<double> &stress,
                                          int &pointsPerElement) const {
  std::vector<double> gradient, current;
  gaussPointFieldsHost(coordinates, stress, pointsPerElement, gradient, current);
}

void NonlinearModel::gaussPointFieldsHost(std::vector<double> &coordinates,
                                          std::vector<double> &stress, int &pointsPerElement,
                                          std::vector<double> &gradient,
                                          std::vector<double> &currentCoordinates) const {
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    const auto &d = elementData<Elem::kDim>();
    const LocalIndex ne = mesh_.numElements();
    // Extents spelled from Elem (nvcc 13 gives a local constexpr extent the wrong value).
    Kokkos::View<double * * [Elem::kDim], Memory> xq("mixcon::nonlinear::qpCoordinates", ne,
                                                     Elem::kNumQp);
    Kokkos::View<double * * [Elem::kDim], Memory> xc("mixcon::nonlinear::qpCurrent", ne,
                                                     Elem::kNumQp);
    Kokkos::View<double * * [Voigt<Elem::kDim>::kSize], Memory> sq("mixcon::nonlinear::qpStress",
                                                                   ne, Elem::kNumQp);
    Kokkos::View<double * * [Elem::kDim * Elem::kDim], Memory> gq("mixcon::nonlinear::qpGradient",
                                                                  ne, Elem::kNumQp);
    quadraturePointCoordinates<Elem>(Exec(), d.mesh, xq);
    almansiGaussPointStress<Elem>(Exec(), d, ConstVec(u_), sq, gq, xc, law_);
    if (small_) // linear law on the reference configuration
      gaussPointStress<Elem>(Exec(), d, ConstVec(u_), sq);
    pointsPerElement = Elem::kNumQp;
    coordinates = toHostVector(xq);
    stress = toHostVector(sq);
    gradient = toHostVector(gq);
    currentCoordinates = toHostVector(xc);
  });
}

LinearSolveStats NonlinearModel::correctWithContact(
    double lambda, int stride, const CsrMatrix<Memory> &tangent, CsrMatrix<Memory> &work,
    const Kokkos::View<const int *, Memory> &flags, const Kokkos::View<const double *, Memory> &g,
    const Kokkos::View<double *, Memory> &rhs, const Kokkos::View<double *, Memory> &target,
    LinearSolver &solver, const Kokkos::View<double *, Memory> &dx) {
  ContactCorrection system;
  system.lambda = lambda;
  system.stride = stride;
  system.tangent = &tangent;
  system.work = &work;
  system.flags = flags;
  system.g = g;
  system.prescribed = prescribed_;
  system.prescribedBase = prescribedBase_;
  system.displacement = u_;
  system.rhs = rhs;
  system.target = target;
  system.solver = &solver;
  system.stiffnessScale = stiffnessScale_;
  system.setupSeconds = &solverSetupSeconds_;
  // Contact as a provider of constraints: the model solves through its constraint set; only a
  // correction with unknowns of its own (force-driven obstacles) is left to the provider.
  const auto start = std::chrono::steady_clock::now();
  const ConstraintSet *set = contact_->constraintSet(system);
  if (!set)
    return contact_->correct(system, dx);
  axpby(-1.0, g, 0.0, rhs);
  solverSetupSeconds_ += seconds(start);
  // The same matrix as in the last correction, only the contact conditions changed: solved on
  // one kept factorization (solver/CapacitanceSolve.hpp) where the solver allows it.
  LinearSolveStats kept;
  if (capacitance_.solve(*set, flags, tangent, rhs, solver, dx, kept, &solverSetupSeconds_))
    return kept;
  // Frames and Dirichlet rows keep the tangent's pattern (the model's `work`, as its own
  // corrections); multipoint rows make a reduced matrix of another pattern (its own storage).
  return solveConstrained(*set, tangent, set->hasMultipoint() ? contactWork_ : work,
                          contactElimination_, rhs, solver, dx, &solverSetupSeconds_);
}

namespace detail {
/// Refuses a saved state of another formulation (0 displacement, 1 and 2 the mixed model's
/// forms Current and Incremental), naming both.
void checkFormulation(const Checkpoint &state, double expected) {
  const auto name = [](double f) -> std::string {
    return f == 0.0   ? "the displacement model"
           : f == 1.0 ? "the mixed model (form current)"
           : f == 2.0 ? "the mixed model (form incremental)"
                      : "an unknown formulation";
  };
  const double saved = state.getScalar("model/formulation");
  if (saved != expected)
    throw std::runtime_error("the saved state is of " + name(saved) + ", this problem uses " +
                             name(expected));
}

void saveIncrementalState(Checkpoint &state, const ConstVec &displacement, const ConstVec &tau,
                          const Kokkos::View<const double **, Memory> &configuration) {
  state.putScalar("model/formulation", 2.0);
  state.put("model/displacement", ModelBase::toHost(displacement));
  state.put("model/stress", ModelBase::toHost(tau));
  const auto c = copyToHost(configuration);
  const std::size_t dim = c.extent(1);
  std::vector<double> rows(dim * c.extent(0));
  for (std::size_t i = 0; i < c.extent(0); ++i)
    for (std::size_t d = 0; d < dim; ++d)
      rows[dim * i + d] = c(i, d);
  state.put("model/configuration", std::move(rows));
}

void restoreIncrementalState(const Checkpoint &state, const Vec &displacement, const Vec &tau,
                             const Kokkos::View<double **, Memory> &configuration) {
  checkFormulation(state, 2.0);
  ModelBase::fromHost(state.get("model/displacement", displacement.extent(0)), displacement);
  ModelBase::fromHost(state.get("model/stress", tau.extent(0)), tau);
  const auto &rows = state.get("model/configuration", configuration.size());
  auto c = hostMirror(configuration);
  const std::size_t dim = c.extent(1);
  for (std::size_t i = 0; i < c.extent(0); ++i)
    for (std::size_t d = 0; d < dim; ++d)
      c(i, d) = rows[dim * i + d];
  copyToDevice(configuration, c);
}

void projectNodalComponents(const CsrMatrix<Memory> &mass, const ConstVec &load, int components,
                            const Vec &field) {
  const LocalIndex nn = mass.numRows;
  Vec diag("mixcon::nonlinear::massDiagonal", nn), b("mixcon::nonlinear::projectionRhs", nn),
      t("mixcon::nonlinear::projected", nn);
  fieldDiagonal(mass, 1, 0, 1, diag, 1.0);
  const LinearMap apply = [&](const ConstDeviceVector &x, const DeviceVector &y) {
    multiply(Exec(), mass, x, y);
  };
  const LinearMap jacobi = [&](const ConstDeviceVector &x, const DeviceVector &y) {
    divide(x, diag, y);
  };
  KrylovOptions o;
  o.tolerance = 1e-13;
  o.maxIterations = 500;
  o.backwardErrorFloor = true; // 1e-13 can be below what rounding allows on a large mesh
  for (int c = 0; c < components; ++c) {
    gather(load, components, c, 1, b);
    gather(field, components, c, 1, t); // the previous values as the initial guess
    const KrylovStats s = krylovSolve(o, apply, jacobi, b, t);
    if (!s.converged) {
      std::ostringstream m;
      m << "the stress update's mass projection (stress component " << c << ") did not converge"
        << " (relative residual " << s.relativeResidual << " after " << s.iterations
        << " iterations)";
      throw CommitFailure(m.str());
    }
    scatter<double>(t, components, c, 1, field, false);
  }
}
} // namespace detail

} // namespace mixcon
