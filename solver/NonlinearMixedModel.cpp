// The mixed model (solver/NonlinearMixedModel.hpp): setup, evaluation, correction, stress
// update, commit and roll back; the iterative solves of its Jacobian are in
// solver/MixedNewtonSolvers.cpp. Layer: solver.
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/IncrementalUpdate.hpp>
#include <solver/Krylov.hpp>
#include <solver/MixedModel.hpp>
#include <solver/NonlinearMixedModel.hpp>
#include <solver/Rules.hpp>

#include <kernels/Nonlinear.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace mixcon {

using namespace fieldops;

NonlinearMixedModel::NonlinearMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                                         const std::vector<PlaneMatrix> &stiffness,
                                         double thickness)
    : NonlinearModel(mesh, elementMaterial, stiffness, thickness) {
  checkMixedPairing(mesh.elementType, mesh.elementType);
  reference_ = withCompliance(data_, stiffness);
  for (const auto &c : stiffness) // PlaneMatrix: the 2D-only 3 x 3 plane [C]
    for (int i = 0; i < 3; ++i)
      maxModulus_ = std::max(maxModulus_, std::abs(c.m[i][i]));
  current_ = reference_;
  current_.mesh.coordinates =
      Kokkos::View<double *[kDisp], Memory>("mixcon::nonlinear::configuration", mesh.numNodes());
  Kokkos::deep_copy(current_.mesh.coordinates, data_.mesh.coordinates);
  const LocalIndex nn = mesh.numNodes();
  tau_ = Vec("mixcon::nonlinear::cauchyStress", kStress * nn);
  x_ = Vec("mixcon::nonlinear::increment", kMixed * nn);
}

NonlinearMixedModel::~NonlinearMixedModel() = default;

void NonlinearMixedModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  if (const auto why = rules::mixedContactSolver(true, contact_ != nullptr, options.type))
    throw InputError("nonlinear mixed model: " + *why);
  if (const auto why = rules::stabilizationRange(stabilization_))
    throw InputError("nonlinear mixed model: " + *why);
  if (small_ && form_ != MixedForm::Current)
    throw std::logic_error("nonlinear mixed model: small displacements are solved in the current "
                           "form (the incremental form updates its configuration)");
  const auto start = std::chrono::steady_clock::now();
  graph_ = buildNodeGraph(mesh_);
  map_ = elementScatterMap<Memory>(mesh_, graph_);
  setStiffnessScale(graph_, map_);
  commitStaged();
  follower_ = followerLoads();
  matrixFree_ = options.type != LinearSolverType::Direct &&
                mixedOptions_.method == MixedNewtonSolver::BlockTriangular &&
                mixedOptions_.jacobian == JacobianForm::MatrixFree &&
                follower_.edges.extent(0) == 0 && contact_ == nullptr;
  tangent_ = matrixFree_ ? CsrMatrix<Memory>{} : expandGraph<Memory>(graph_, kMixed);
  const LocalIndex nn = mesh_.numNodes();
  if (matrixFree_) {
    colors_ = mixedElementColors<Memory>(mesh_, kDefaultMixedScatter<Exec>);
    jacobianState_ = Vec("mixcon::nonlinear::jacobianState", kMixed * nn);
    couplingBlock_ = expandGraph<Memory>(graph_, kStress, kDisp);
    precDiag5_ = Vec("mixcon::nonlinear::precDiagonal5", kMixed * nn);
  }
  g_ = Vec("mixcon::nonlinear::residual", kMixed * nn);
  originTaken_ = false;
  committed_ = Vec("mixcon::nonlinear::committed", kDisp * nn);
  dx_ = Vec("mixcon::nonlinear::correction", kMixed * nn);
  rhs_ = Vec("mixcon::nonlinear::rhs", kMixed * nn);
  target_ = Vec("mixcon::nonlinear::target", kMixed * nn);
  diag_ = Vec("mixcon::nonlinear::diagonal", kMixed * nn);
  work_ = CsrMatrix<Memory>{};
  constrained5_ = Kokkos::View<int *, Memory>("mixcon::nonlinear::constrained5", kMixed * nn);
  constraintsChanged();
  Kokkos::deep_copy(committed_, u_);
  committedState_ = Vec("mixcon::nonlinear::committedState", kMixed * nn);
  Kokkos::deep_copy(committedState_, x_);
  linearOptions_ = options;
  comm_ = comm;
  jacobianDirect_.reset();
  if (options.type == LinearSolverType::Direct) {
    linearOptions_.symmetric = false; // indefinite (Incremental) or nonsymmetric (Current): LU
    linearOptions_.indefinite = true;
    solver_ = makeLinearSolver(linearOptions_, DofMap::serial(nn, kMixed), comm);
  } else {
    // Schur complement on the displacements, BoomerAMG on K^L of the current configuration.
    precMatrix_ = expandGraph<Memory>(graph_, kDisp);
    precDiag_ = Vec("mixcon::nonlinear::precDiagonal", kDisp * nn);
    stressBlock_ = expandGraph<Memory>(graph_, kStress);
    stressNodalBlocks_ = Kokkos::View<double *[kStress][kStress], Memory>(
        "mixcon::nonlinear::stressNodalBlocks", nn);
    stressBlockInverse_ =
        Kokkos::View<double *[kStress][kStress], Memory>("mixcon::nonlinear::blockInverse", nn);
    LinearSolverOptions amg = options;
    amg.symmetric = true;
    solver_ = makeLinearSolver(amg, dofs_, comm);
    positions_ = Kokkos::View<double *[kDisp], Memory>("mixcon::nonlinear::positions", nn);
    solver_->setNearNullSpace(positions_);
  }
  assemblySeconds_ = seconds(start);
}

std::string NonlinearMixedModel::solverName() const {
  std::ostringstream o;
  o << "mixed " << (form_ == MixedForm::Current ? "current-configuration" : "incremental")
    << " form, a = " << stabilization_ << ", ";
  if (linearOptions_.type == LinearSolverType::Direct)
    o << (solver_ ? solver_->name() : std::string("none"));
  else if (mixedOptions_.method == MixedNewtonSolver::Schur)
    o << "flexible GMRES on the Schur complement (inner block-Jacobi CG on the stress block), one "
         "BoomerAMG V-cycle on K^L of the current configuration"
      << coarseSpacePhrase(solver_.get());
  else
    o << "flexible GMRES(" << mixedOptions_.restart << ") on the Jacobian"
      << (matrixFree_ ? " (applied matrix-free, not assembled)" : "")
      << ", block-triangular preconditioner: one BoomerAMG V-cycle on K^L of the "
         "current configuration"
      << coarseSpacePhrase(solver_.get()) << ", block-Jacobi CG on the stress block to "
      << mixedOptions_.preconditionerTolerance << " or tighter";
  return o.str();
}

LinearSolveStats NonlinearMixedModel::solveIterative() {
  const auto direct = [&] {
    return constrainedSolve(tangent_, true, work_, constrained5_, g_, target_, rhs_, diag_,
                            *jacobianDirect_, dx_, solverSetupSeconds_);
  };
  if (jacobianDirect_)
    return direct();
  const auto once = [&] {
    return mixedOptions_.method == MixedNewtonSolver::Schur ? solveSchur() : solveBlockTriangular();
  };
  const long unknowns = static_cast<long>(kMixed) * mesh_.numNodes();
  const bool fallback =
      !matrixFree_ && directFallbackFits(comm_, unknowns, linearOptions_.directFallbackUnknowns);
  // The AMG on K^L is a preconditioner here: where the method around it fails, the solver's
  // escalation ladder (its coarse space, a larger coarsest level, then the direct solver) is
  // taken step by step; before each step, the LU of the Jacobian where it is estimated to take
  // less time than this solve has so far (LinearSolverOptions::directWhenCheaper).
  LinearSolveStats s = solveOnLadder(
      *solver_, once,
      luWhenCheaper(fallback && linearOptions_.directWhenCheaper, jacobianCost_, tangent_,
                    std::chrono::steady_clock::now(), "the iterative solve"));
  std::string note = s.note;
  int iterations = s.iterations;
  if (!s.converged && fallback) {
    LinearSolverOptions o = linearOptions_;
    o.type = LinearSolverType::Direct;
    o.symmetric = false;
    o.indefinite = true;
    jacobianDirect_ = makeLinearSolver(o, DofMap::serial(mesh_.numNodes(), kMixed), comm_);
    appendNote(note, "the iterative solve did not converge (relative residual " +
                         std::to_string(s.relativeResidual) +
                         "): falling back to the direct LU of the Jacobian (" +
                         std::to_string(unknowns) + " unknowns)");
    s = direct();
    iterations += s.iterations;
  }
  s.iterations = iterations;
  s.note = note;
  return s;
}

void NonlinearMixedModel::setPrestress(const std::vector<double> &tau) { fromHost(tau, tau_); }

void NonlinearMixedModel::setIncrement(const std::vector<double> &x) {
  fromHost(x, x_);
  updateTotalDisplacement();
}

void NonlinearMixedModel::updateTotalDisplacement() {
  gather(x_, kMixed, 0, kDisp, u_);
  if (form_ == MixedForm::Incremental && committed_.extent(0) == u_.extent(0))
    axpby(1.0, committed_, 1.0, u_);
}

double NonlinearMixedModel::evaluate(double lambda, bool tangent) {
  const auto start = std::chrono::steady_clock::now();
  // Small displacements: J0, the Jacobian at the origin (assembled, or its stress rows and state
  // for the matrix-free products), is taken once; the residual is J0 x - f.
  const bool withJacobian = small_ ? !originTaken_ : tangent;
  const ConstVec state = tangentState(x_);
  Kokkos::deep_copy(g_, 0.0);
  if (withJacobian && !matrixFree_)
    Kokkos::deep_copy(tangent_.values, 0.0);
  const CsrMatrix<Memory> none;
  const CsrMatrix<Memory> &a = withJacobian && !matrixFree_ ? tangent_ : none;
  if (withJacobian && matrixFree_) {
    // J stays unassembled: its state, and the stress rows C and M the preconditioner needs.
    Kokkos::deep_copy(jacobianState_, state);
    Kokkos::deep_copy(couplingBlock_.values, 0.0);
    Kokkos::deep_copy(stressBlock_.values, 0.0);
    dispatchPlaneElement(mesh_.elementType, "the geometrically nonlinear mixed model",
                         [&](auto elem) {
                           using Elem = decltype(elem);
                           if (form_ == MixedForm::Current)
                             assembleMixedStressRows<Elem>(
                                 Exec(), reference_.mesh, reference_.thickness,
                                 MixedCurrentLaw<Memory>{reference_.material, reference_.stiffness,
                                                         reference_.compliance, stabilization_},
                                 state, ConstVec(), map_, couplingBlock_, stressBlock_);
                           else
                             assembleMixedStressRows<Elem>(
                                 Exec(), current_.mesh, current_.thickness,
                                 MixedIncrementLaw<Memory>{current_.material, current_.stiffness,
                                                           current_.compliance, stabilization_},
                                 ConstVec(x_), ConstVec(tau_), map_, couplingBlock_, stressBlock_);
                         });
  }
  LocalIndex inverted = -1;
  double fint = 0.0;
  dispatchPlaneElement(
      mesh_.elementType, "the geometrically nonlinear mixed model", [&](auto elem) {
        using Elem = decltype(elem);
        const bool current = form_ == MixedForm::Current;
        if (current && (withJacobian || !small_))
          inverted =
              assembleMixedCurrent<Elem>(Exec(), reference_, state, stabilization_, map_, a, g_);
        else if (!current)
          inverted = assembleMixedIncrement<Elem>(Exec(), current_, ConstVec(tau_), ConstVec(x_),
                                                  stabilization_, map_, a, g_);
        if (small_) { // g = J0 x
          originTaken_ = true;
          applyJacobian(ConstVec(x_), g_);
        }
        fint = strideNorm(g_, kMixed, 0, kDisp, {}, 0);
        subtractLoad(g_, kMixed, lambda);
        if (follower_.edges.extent(0) > 0) {
          const auto [pressure, factor] = followerPressureAt(lambda);
          assembleFollowerPressure<kMixed, Elem>(Exec(), current ? reference_.mesh : current_.mesh,
                                                 ConstVec(x_), follower_.edges, pressure, factor,
                                                 data_.thickness, map_, a, followerForce(g_));
          addFollowerForce(g_, kMixed);
        }
      });
  return finishEvaluate(lambda, tangent, inverted, fint, g_, kMixed, constrained5_,
                        form_ == MixedForm::Current ? reference_.mesh.coordinates
                                                    : current_.mesh.coordinates,
                        x_, start);
}

void NonlinearMixedModel::applyJacobian(const ConstVec &v, const Vec &y) const {
  if (!matrixFree_) {
    multiply(Exec(), tangent_, v, y);
    return;
  }
  const ConstVec state(jacobianState_);
  dispatchPlaneElement(
      mesh_.elementType, "the geometrically nonlinear mixed model", [&](auto elem) {
        using Elem = decltype(elem);
        if (form_ == MixedForm::Current)
          applyMixedCurrentJacobian<Elem>(Exec(), reference_, state, stabilization_, v, y, colors_);
        else
          applyMixedIncrementJacobian<Elem>(Exec(), current_, ConstVec(tau_), state, stabilization_,
                                            v, y, colors_);
      });
}

LinearSolveStats NonlinearMixedModel::correct(double lambda, double &increment) {
  if (matrixFree_ && mixedOptions_.method != MixedNewtonSolver::BlockTriangular)
    throw std::logic_error("nonlinear mixed model: the matrix-free Jacobian was set up for the "
                           "block-triangular solve");
  prescribedStep(constrained5_, prescribed_, u_, lambda, kMixed, kDisp, target_, prescribedBase_);
  const LinearSolveStats s =
      contact_ && contact_->constrains()
          ? correctWithContact(lambda, kMixed, tangent_, work_, constrained5_, g_, rhs_, target_,
                               *solver_, dx_)
      : linearOptions_.type == LinearSolverType::Direct
          ? constrainedSolve(tangent_, fresh_ || contactIterations() != nullptr, work_,
                             constrained5_, g_, target_, rhs_, diag_, *solver_, dx_,
                             solverSetupSeconds_)
          : solveIterative();
  fresh_ = false;
  axpby(1.0, dx_, 1.0, x_);
  updateTotalDisplacement();
  const double du = relativeToHistory(strideNorm(dx_, kMixed, 0, kDisp, {}, 0),
                                      strideNorm(u_, 1, 0, 1, {}, 0), kDisplacementScale);
  // Stresses below 1e-8 of the largest modulus count as zero (a rigid motion has none).
  const double stressFloor = 1e-8 * maxModulus_ * std::sqrt(static_cast<double>(mesh_.numNodes()));
  const double ds = relativeToHistory(
      strideNorm(dx_, kMixed, kStressAt, kStress, {}, 0),
      std::max(strideNorm(stressOnly(), 1, 0, 1, {}, 0), stressFloor), kStressScale);
  increment = std::max(du, ds);
  return s;
}

void NonlinearMixedModel::commit() {
  if (form_ == MixedForm::Current) {
    Kokkos::deep_copy(committedState_, x_);
    return;
  }
  detail::commitIncrementalState<kDisp>(
      [&](const auto &f) {
        dispatchPlaneElement(mesh_.elementType, "the geometrically nonlinear mixed model", f);
      },
      current_.mesh, current_.thickness, stressUpdate_, graph_, map_, mass_, x_, tau_, committed_);
  updateTotalDisplacement();
}

void NonlinearMixedModel::rollback() {
  if (form_ == MixedForm::Current)
    Kokkos::deep_copy(x_, committedState_);
  else
    Kokkos::deep_copy(x_, 0.0);
  updateTotalDisplacement();
}

// Form Current: the committed unknowns (total displacement and nodal Cauchy stress). Form
// Incremental: the total displacement, the stress tau and the configuration c1 carried from
// increment to increment (detail::saveIncrementalState).
void NonlinearMixedModel::saveCommitted(Checkpoint &state) const {
  if (form_ == MixedForm::Current) {
    state.putScalar("model/formulation", 1.0);
    state.put("model/unknowns", toHost(committedState_));
    return;
  }
  detail::saveIncrementalState(state, committed_, tau_, current_.mesh.coordinates);
}

void NonlinearMixedModel::restoreCommitted(const Checkpoint &state) {
  if (form_ == MixedForm::Current) {
    detail::checkFormulation(state, 1.0);
    fromHost(state.get("model/unknowns", committedState_.extent(0)), committedState_);
  } else {
    detail::restoreIncrementalState(state, committed_, tau_, current_.mesh.coordinates);
  }
  rollback();
}

std::vector<double> NonlinearMixedModel::nodalStressHost() const { return toHost(stressOnly()); }

std::vector<double> NonlinearMixedModel::reactionHost(double) const {
  const auto g = toHost(g_);
  std::vector<double> r(kDisp * (g.size() / kMixed));
  for (std::size_t k = 0; k < r.size() / kDisp; ++k)
    for (int i = 0; i < kDisp; ++i)
      r[kDisp * k + i] = g[kMixed * k + i];
  return r;
}

Kokkos::View<double *, Memory> NonlinearMixedModel::stressOnly() const {
  Vec t("mixcon::nonlinear::nodalStress", tau_.extent(0));
  gather(x_, kMixed, kStressAt, kStress, t);
  axpby(1.0, tau_, 1.0, t);
  return t;
}

std::vector<double> NonlinearMixedModel::interpolatedGaussStressHost() const {
  std::vector<double> out;
  dispatchPlaneElement(
      mesh_.elementType, "the geometrically nonlinear mixed model", [&](auto elem) {
        using Elem = decltype(elem);
        const LocalIndex ne = mesh_.numElements();
        Kokkos::View<double **[kStress], Memory> sq("mixcon::nonlinear::qpInterpolated", ne,
                                                    Elem::kNumQp);
        interpolateNodalStress<Elem>(Exec(), current_.mesh, ConstVec(stressOnly()), sq);
        out = toHostVector(sq);
      });
  return out;
}

std::vector<double> NonlinearMixedModel::contactStressHost() const { return toHost(stressOnly()); }

void NonlinearMixedModel::constraintsChanged() {
  if (constrained5_.extent(0) > 0)
    scatter<int>(isConstrained_, kMixed, 0, kDisp, constrained5_, true);
}

} // namespace mixcon
