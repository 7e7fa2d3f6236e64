// SolidNonlinearMixedModel (solver/SolidNonlinearMixedModel.hpp): host orchestration of device
// kernels. Layer: solver.
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/IncrementalUpdate.hpp>
#include <solver/Rules.hpp>
#include <solver/SolidMixedModel.hpp>
#include <solver/SolidNonlinearMixedModel.hpp>

#include <kernels/Nonlinear.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace mixcon {

using namespace fieldops;

namespace {
constexpr int kStresses = FieldLayout<3>::kNumStresses; // 6
constexpr int kStressOffset = FieldLayout<3>::kStressOffset;
} // namespace

SolidNonlinearMixedModel::SolidNonlinearMixedModel(const Mesh &mesh,
                                                   const std::vector<int> &elementMaterial,
                                                   const std::vector<SolidMatrix> &stiffness,
                                                   double stabilization)
    : NonlinearModel(mesh, elementMaterial, stiffness), stabilization_(stabilization) {
  detail::checkSolidMixedElement(mesh);
  if (const auto why = rules::stabilizationRange(stabilization))
    throw InputError("nonlinear mixed model: " + *why);
  compliance_ = detail::deviceMatrices(detail::solidCompliances(stiffness),
                                       "mixcon::nonlinear3d::compliance");
  for (const auto &c : stiffness)
    for (int i = 0; i < kStresses; ++i)
      maxModulus_ = std::max(maxModulus_, std::abs(c(i, i)));
  x_ = Vec("mixcon::nonlinear3d::unknowns", kUnknowns * mesh.numNodes());
  mixedOptions_.restart = kSolidMixedRestart;
}

SolidNonlinearMixedModel::~SolidNonlinearMixedModel() = default;

void SolidNonlinearMixedModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  if (contact_)
    throw InputError("nonlinear mixed model: contact is 2D only so far (issue 17)");
  if (incremental() && small_)
    throw std::logic_error("nonlinear mixed model: small displacements are solved in the current "
                           "form (the incremental form updates its configuration)");
  const auto start = std::chrono::steady_clock::now();
  // Form Incremental: c1 starts at the reference configuration; a later setup() keeps the state.
  if (incremental() && tau_.extent(0) == 0) {
    const LocalIndex nn = mesh_.numNodes();
    configuration_ = solid_;
    configuration_.mesh.coordinates =
        decltype(configuration_.mesh.coordinates)("mixcon::nonlinear3d::configuration", nn);
    Kokkos::deep_copy(configuration_.mesh.coordinates, solid_.mesh.coordinates);
    tau_ = Vec("mixcon::nonlinear3d::cauchyStress", kStresses * nn);
    displacement_ = Vec("mixcon::nonlinear3d::displacement", dim() * nn);
  }
  graph_ = buildNodeGraph(mesh_);
  map_ = elementScatterMap<Memory>(mesh_, graph_);
  setStiffnessScale(graph_, map_);
  work_ = CsrMatrix<Memory>{};
  mass_ = CsrMatrix<Memory>{}; // on graph_ (the projected stress update's, made when first used)
  commitStaged();
  follower_ = followerLoads();
  // jacobian: matrix_free serves the block-triangular GMRES without follower pressures (their
  // load stiffness is assembled).
  const bool withoutMatrix =
      options.type != LinearSolverType::Direct && follower_.edges.extent(0) == 0 &&
      solidJacobianWithoutMatrix(mixedOptions_.jacobian,
                                 static_cast<long>(kUnknowns) * mesh_.numNodes());
  tangent_ = withoutMatrix ? CsrMatrix<Memory>{} : expandGraph<Memory>(graph_, kUnknowns);
  iterative_.reset(); // holds the products of matrixFree_
  matrixFree_.reset();
  if (withoutMatrix)
    matrixFree_ = std::make_unique<SolidMixedMatrixFree>(
        mesh_, incremental() ? configuration_ : solid_, compliance_, stabilization_, !incremental(),
        incremental() ? ConstVec(tau_) : ConstVec());
  const LocalIndex n = kUnknowns * mesh_.numNodes();
  flags_ = Kokkos::View<int *, Memory>("mixcon::nonlinear3d::constrained", n);
  constraintsChanged();
  committed_ = Vec("mixcon::nonlinear3d::committed", n);
  g_ = Vec("mixcon::nonlinear3d::residual", n);
  originTaken_ = false;
  dx_ = Vec("mixcon::nonlinear3d::correction", n);
  rhs_ = Vec("mixcon::nonlinear3d::rhs", n);
  target_ = Vec("mixcon::nonlinear3d::target", n);
  diag_ = Vec("mixcon::nonlinear3d::diagonal", n);
  Kokkos::deep_copy(committed_, x_);
  linearOptions_ = options;
  // The exact Jacobian of the current form is not symmetric; the incremental form's is (without
  // follower pressures); both are saddle points: the LU.
  linearOptions_.symmetric = false;
  linearOptions_.indefinite = true;
  comm_ = comm;
  solver_.reset();
  iterative_.reset();
  if (options.type == LinearSolverType::Direct) {
    solver_ = makeLinearSolver(linearOptions_, DofMap::serial(mesh_.numNodes(), kUnknowns), comm);
  } else {
    positions_ =
        Kokkos::View<double **, Memory>("mixcon::nonlinear3d::positions", mesh_.numNodes(), dim());
    Kokkos::deep_copy(positions_, configurationCoordinates());
    iterative_ = std::make_unique<SolidMixedSolve>(
        graph_, options, mixedOptions_.preconditionerTolerance, mixedOptions_.restart, dofs_, comm,
        positions_, matrixFree_ == nullptr);
  }
  assemblySeconds_ = seconds(start);
}

std::string SolidNonlinearMixedModel::solverName() const {
  std::ostringstream o;
  o << "mixed "
    << (incremental()
            ? std::string("incremental form (3D, stress update ") +
                  (stressUpdate_ == StressUpdate::Projected ? "projected" : "nodal average") + ")"
            : std::string("current-configuration form (3D)"))
    << ", a = " << stabilization_ << ", "
    << (solver_      ? solver_->name()
        : iterative_ ? iterative_->name()
                     : std::string("none"));
  return o.str();
}

long SolidNonlinearMixedModel::innerIterations() const {
  return iterative_ ? iterative_->innerIterations() : 0;
}

void SolidNonlinearMixedModel::setUnknowns(const std::vector<double> &x) {
  if (x.size() != x_.extent(0))
    throw std::invalid_argument("nonlinear mixed model: " + std::to_string(x.size()) +
                                " unknowns given, " + std::to_string(x_.extent(0)) + " expected");
  fromHost(x, x_);
  updateDisplacement();
}

void SolidNonlinearMixedModel::setPrestress(const std::vector<double> &tau) {
  if (!incremental() || tau_.extent(0) == 0)
    throw std::logic_error("nonlinear mixed model: a prestress needs the incremental form, set up");
  if (tau.size() != tau_.extent(0))
    throw std::invalid_argument("nonlinear mixed model: " + std::to_string(tau.size()) +
                                " prestress values given, " + std::to_string(tau_.extent(0)) +
                                " expected");
  fromHost(tau, tau_);
}

void SolidNonlinearMixedModel::updateDisplacement() {
  gather(x_, kUnknowns, 0, dim(), u_);
  if (incremental() && displacement_.extent(0) == u_.extent(0))
    axpby(1.0, displacement_, 1.0, u_);
}

Kokkos::View<const double **, SolidNonlinearMixedModel::Memory>
SolidNonlinearMixedModel::configurationCoordinates() const {
  if (incremental() && configuration_.mesh.coordinates.extent(0) > 0)
    return configuration_.mesh.coordinates;
  return referenceCoordinates();
}

double SolidNonlinearMixedModel::evaluate(double lambda, bool tangent) {
  const auto start = std::chrono::steady_clock::now();
  Kokkos::deep_copy(g_, 0.0);
  // Small displacements: J0, the Jacobian at the origin (assembled, or the matrix-free products'
  // state), is taken once; the residual is J0 x - f.
  const bool withJacobian = small_ ? !originTaken_ : tangent;
  const bool assembled = withJacobian && !matrixFree_;
  if (assembled)
    Kokkos::deep_copy(tangent_.values, 0.0);
  if (small_ && withJacobian && matrixFree_)
    matrixFree_->update(tangentState(x_)); // the products stay at the origin
  const CsrMatrix<Memory> none;
  const CsrMatrix<Memory> &a = assembled ? tangent_ : none; // else at the solve
  LocalIndex inverted = -1;
  double fint = 0.0;
  // Form Incremental: on c1 with the prestress tau, x the increment.
  const MeshView<Memory, 3> &mesh = incremental() ? configuration_.mesh : solid_.mesh;
  const auto assemble = [&](auto elem) {
    using Elem = decltype(elem);
    // One test node's row block at a time: the whole Hex20 Jacobian (180 x 180) does not fit a
    // thread.
    const auto rows = [&](const auto &law) {
      using Law = std::decay_t<decltype(law)>;
      return assembleNonlinearRows<kUnknowns, Elem>(
          Exec(), mesh,
          SolidMixedKernel<Elem, Memory, Law>{mesh, law, tangentState(x_), ConstVec(tau_)}, map_, a,
          g_);
    };
    if (assembled || !small_)
      inverted = incremental()
                     ? rows(MixedIncrementLaw<Memory, 3>{solid_.material, solid_.stiffness,
                                                         compliance_, stabilization_})
                     : rows(MixedCurrentLaw<Memory, 3>{solid_.material, solid_.stiffness,
                                                       compliance_, stabilization_});
    if (small_) { // g = J0 x
      originTaken_ = true;
      if (matrixFree_)
        matrixFree_->applyJacobian(ConstVec(x_), g_);
      else
        multiply(Exec(), tangent_, ConstVec(x_), g_);
    }
    fint = strideNorm(g_, kUnknowns, 0, dim(), {}, 0);
    subtractLoad(g_, kUnknowns, lambda);
    if (follower_.edges.extent(0) > 0) {
      const auto [pressure, factor] = followerPressureAt(lambda);
      assembleFollowerFacePressure<kUnknowns, Elem>(Exec(), mesh, ConstVec(x_), follower_.edges,
                                                    pressure, factor, map_, a, followerForce(g_));
      addFollowerForce(g_, kUnknowns);
    }
  };
  dispatchSolidElement(mesh_.elementType, "the 3D mixed model", assemble);
  return finishEvaluate(lambda, tangent, inverted, fint, g_, kUnknowns, flags_,
                        configurationCoordinates(), x_, start);
}

LinearSolveStats SolidNonlinearMixedModel::correct(double lambda, double &increment) {
  prescribedStep(flags_, prescribed_, u_, lambda, kUnknowns, dim(), target_, prescribedBase_);
  const LinearSolveStats s =
      iterative_ ? solveIterative()
                 : constrainedSolve(tangent_, fresh_, work_, flags_, g_, target_, rhs_, diag_,
                                    *solver_, dx_, solverSetupSeconds_);
  fresh_ = false;
  axpby(1.0, dx_, 1.0, x_);
  updateDisplacement();
  const double du = relativeToHistory(strideNorm(dx_, kUnknowns, 0, dim(), {}, 0),
                                      strideNorm(u_, 1, 0, 1, {}, 0), kDisplacementScale);
  // Stresses below 1e-8 of the largest modulus count as zero (a rigid motion has none).
  const double stressFloor = 1e-8 * maxModulus_ * std::sqrt(static_cast<double>(mesh_.numNodes()));
  const double stress = incremental() ? strideNorm(totalStress(), 1, 0, 1, {}, 0)
                                      : strideNorm(x_, kUnknowns, kStressOffset, kStresses, {}, 0);
  const double ds = relativeToHistory(strideNorm(dx_, kUnknowns, kStressOffset, kStresses, {}, 0),
                                      std::max(stress, stressFloor), kStressScale);
  increment = std::max(du, ds);
  return s;
}

LinearSolveStats SolidNonlinearMixedModel::solveIterative() {
  if (solver_) // the iterative solve failed before: the LU it fell back to stays
    return constrainedSolve(tangent_, fresh_, work_, flags_, g_, target_, rhs_, diag_, *solver_,
                            dx_, solverSetupSeconds_);
  if (fresh_) {
    // K^L on the current configuration x = X + u (or c1 + u; also the AMG's rigid-body modes).
    movedCoordinates(configurationCoordinates(), tangentState(x_), kUnknowns, positions_);
    ElementData<Memory, 3> d = solid_;
    d.mesh.coordinates = positions_;
    iterative_->zeroStiffness();
    dispatchSolidElement(mesh_.elementType, "the 3D mixed model", [&](auto elem) {
      assembleLinearStiffness<decltype(elem)>(Exec(), d, map_, iterative_->stiffness());
    });
    const double before = iterative_->setupSeconds();
    if (matrixFree_) { // J at this state: M's point matrices and nodal blocks
      const auto start = std::chrono::steady_clock::now();
      if (!small_) // else kept at the origin since evaluate() took J0
        matrixFree_->update(ConstVec(x_));
      solverSetupSeconds_ += seconds(start);
      iterative_->refresh(matrixFree_->operators(), isConstrained_);
    } else {
      iterative_->refresh(tangent_, isConstrained_);
    }
    solverSetupSeconds_ += iterative_->setupSeconds() - before;
  }
  Vec f(Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::nonlinear3d::negativeResidual"),
        g_.extent(0));
  axpby(-1.0, g_, 0.0, f);
  const long unknowns = static_cast<long>(kUnknowns) * mesh_.numNodes();
  const bool fallback =
      !matrixFree_ && directFallbackFits(comm_, unknowns,
                                         std::min(linearOptions_.directFallbackUnknowns,
                                                  kSolidMixedDirectFallback));
  LinearSolveStats s = iterative_->solve(
      flags_, isConstrained_, ConstVec(f), ConstVec(target_), dx_,
      luWhenCheaper(fallback && linearOptions_.directWhenCheaper, jacobianCost_, tangent_,
                    std::chrono::steady_clock::now(), "the block-triangular solve"));
  if (!s.converged && fallback) {
    LinearSolverOptions o = linearOptions_;
    o.type = LinearSolverType::Direct;
    solver_ = makeLinearSolver(o, DofMap::serial(mesh_.numNodes(), kUnknowns), comm_);
    const int iterations = s.iterations;
    std::string note = s.note; // the AMG's ladder steps
    appendNote(note, "the block-triangular solve did not converge (relative residual " +
                         std::to_string(s.relativeResidual) +
                         "): falling back to the direct LU of the Jacobian (" +
                         std::to_string(unknowns) + " unknowns)");
    s = constrainedSolve(tangent_, true, work_, flags_, g_, target_, rhs_, diag_, *solver_, dx_,
                         solverSetupSeconds_);
    s.iterations += iterations;
    appendNote(note, s.note);
    s.note = note;
  }
  return s;
}

void SolidNonlinearMixedModel::commit() {
  if (incremental())
    commitIncrement();
  else
    Kokkos::deep_copy(committed_, x_);
}

void SolidNonlinearMixedModel::commitIncrement() {
  detail::commitIncrementalState<3>(
      [&](const auto &f) { dispatchSolidElement(mesh_.elementType, "the 3D mixed model", f); },
      configuration_.mesh, 1.0, stressUpdate_, graph_, map_, mass_, x_, tau_, displacement_);
  updateDisplacement();
}

void SolidNonlinearMixedModel::rollback() {
  if (incremental())
    Kokkos::deep_copy(x_, 0.0);
  else
    Kokkos::deep_copy(x_, committed_);
  updateDisplacement();
}

// Form Current: the committed unknowns (total displacement and nodal Cauchy stress), as the 2D
// model's current form saves them; the sizes tell a 2D state from a 3D one. Form Incremental: the
// total displacement, tau and c1, as the 2D model's incremental form
// (detail::saveIncrementalState).
void SolidNonlinearMixedModel::saveCommitted(Checkpoint &state) const {
  if (incremental()) {
    detail::saveIncrementalState(state, displacement_, tau_, configuration_.mesh.coordinates);
    return;
  }
  state.putScalar("model/formulation", 1.0);
  state.put("model/unknowns", toHost(committed_));
}

void SolidNonlinearMixedModel::restoreCommitted(const Checkpoint &state) {
  if (incremental()) {
    detail::restoreIncrementalState(state, displacement_, tau_, configuration_.mesh.coordinates);
  } else {
    detail::checkFormulation(state, 1.0);
    fromHost(state.get("model/unknowns", committed_.extent(0)), committed_);
  }
  rollback();
}

Kokkos::View<double *, SolidNonlinearMixedModel::Memory>
SolidNonlinearMixedModel::totalStress() const {
  Vec s("mixcon::nonlinear3d::stress", kStresses * mesh_.numNodes());
  gather(x_, kUnknowns, kStressOffset, kStresses, s);
  if (incremental() && tau_.extent(0) == s.extent(0))
    axpby(1.0, tau_, 1.0, s);
  return s;
}

std::vector<double> SolidNonlinearMixedModel::nodalStressHost() const {
  return toHost(totalStress());
}

std::vector<double> SolidNonlinearMixedModel::reactionHost(double) const {
  Vec r("mixcon::nonlinear3d::reaction", dim() * mesh_.numNodes());
  gather(g_, kUnknowns, 0, dim(), r);
  return toHost(r);
}

void SolidNonlinearMixedModel::constraintsChanged() {
  if (flags_.extent(0) > 0)
    scatter<int>(isConstrained_, kUnknowns, 0, dim(), flags_, true);
}

} // namespace mixcon
