// Geometrically nonlinear (updated-Lagrangian) analysis, the problem interface: a model that
// evaluates its residual G (internal minus external force) and tangent at the current iterate,
// corrects, commits or rolls back (solver/LoadStepper.hpp drives it through the load factors;
// the two models of the report are solver/NonlinearDisplacementModel.hpp and
// solver/NonlinearMixedModel.hpp). Prescribed displacements and loads scale with the load factor;
// follower pressures act normal to the deformed boundary; contact enters through one
// ContactIterations (solver/ContactIterations.hpp). Theory: docs/theory.md. Layer: solver.
#pragma once

#include <solver/CapacitanceSolve.hpp>
#include <solver/Checkpoint.hpp>
#include <solver/ContactIterations.hpp>
#include <solver/ModelBase.hpp>
#include <solver/NonlinearOptions.hpp>

#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mixcon {

/// Thrown by NonlinearModel::commit() where the converged state cannot be accepted (the mixed
/// models' stress projection onto the moved configuration fails); the committed state is then
/// unchanged, and the load stepper cuts the increment as for a failed Newton iteration.
class CommitFailure : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// A geometrically nonlinear model: iterate (evaluate, correct), then commit or roll back.
/// Host-side interface (virtual, never called on the device).
class NonlinearModel : public ModelBase {
public:
  using ModelBase::ModelBase;

  /// A follower pressure p (reference value, scaled by the load factor; positive pushes into the
  /// body) on the current, deformed position of `edges` (element edges in 2D, faces in 3D).
  /// Stages: `base` is the pressure the stage starts from, `pressure` its change over the stage.
  void addFollowerPressure(const std::vector<BoundaryEdge> &edges, double pressure,
                           double base = 0.0);
  /// Removes every follower pressure (a new stage gives them again with their base).
  void clearFollowerPressures();
  /// Load histories (solver/ModelBase.hpp): what the stage driver (apps/Stages.cpp) calls.
  using ModelBase::beginStage;
  using ModelBase::loadsToBase;
  using ModelBase::release;
  using ModelBase::restoreLoading;
  using ModelBase::saveLoading;
  using ModelBase::staged;
  /// ModelBase::commitStage, and the follower pressures and contact work copied anew.
  void commitStage() override;

  /// Builds the sparsity pattern and the linear solver. Call after loads and constraints.
  virtual void setup(const LinearSolverOptions &options, MPI_Comm comm) = 0;
  /// Residual G (internal minus external force) at the current iterate for load factor lambda,
  /// and the tangent when `tangent`. Returns ||G|| / max(||f_int||, ||f_ext||) over the free
  /// displacement unknowns; infinity when an element is inverted.
  virtual double evaluate(double lambda, bool tangent) = 0;
  /// Solves the last tangent for the correction (prescribed values reach lambda g), applies it,
  /// and returns the solver statistics; `increment` receives the relative increment norm.
  virtual LinearSolveStats correct(double lambda, double &increment) = 0;
  /// Accepts the current state as converged (configuration and stress update). Throws
  /// CommitFailure, with the committed state unchanged, where it cannot.
  virtual void commit() = 0;
  /// Returns to the last committed state.
  virtual void rollback() = 0;
  /// The committed state (what commit() accepted) into `state` under "model/..." names;
  /// restoreCommitted makes a saved state the committed and the current one (call after
  /// setup()), so that a restarted run continues as the uninterrupted one would. Throws
  /// std::runtime_error when `state` does not fit this model (another mesh or formulation).
  virtual void saveCommitted(Checkpoint &state) const = 0;
  virtual void restoreCommitted(const Checkpoint &state) = 0;

  /// The contact enforcement (not owned; nullptr: none): rigid obstacles or elastic-elastic
  /// node-to-segment contact (contact/), one per model in this version; the mixed model needs
  /// solver: direct with contact. The models ask it for detection, contact forces and the
  /// constrained corrections; the load stepper for its status iterations.
  void setContact(ContactIterations *contact) { contact_ = contact; }
  ContactIterations *contactIterations() const { return contact_; }
  /// The contact corrections solved on a kept factorization (the direct solver, the stiffness
  /// unchanged between corrections: solver/CapacitanceSolve.hpp), for the run's summary.
  const CapacitanceSolve &keptFactorization() const { return capacitance_; }
  /// Host copy of the last residual G = f_int - f_ext (unknowns per node as the model's, the
  /// displacements first) and that count per node.
  virtual std::vector<double> residualVectorHost() const = 0;
  virtual int unknownsPerNode() const = 0;
  /// Nodal Cauchy stresses (3 per node) that decide stick, slip and release, or empty when the
  /// contact forces decide (displacement model).
  virtual std::vector<double> contactStressHost() const { return {}; }
  /// The two above with only the values at `nodes` copied (0 elsewhere): what a contact status
  /// update reads, O(contact candidates) per contact iteration.
  virtual std::vector<double> residualVectorHost(const std::vector<LocalIndex> &nodes) const = 0;
  virtual std::vector<double> contactStressHost(const std::vector<LocalIndex> &) const {
    return {};
  }
  /// Small-displacement kinematics: the residual is the linear model's, J0 x - f, with J0 the
  /// operator on the reference configuration (the displacement model's K^L; the mixed models'
  /// Jacobian at x = 0, their linear Hellinger-Reissner operator). The nonlinear machinery then
  /// serves contact and load histories on a linear body. Call before setup().
  void setSmallDisplacements(bool on) { small_ = on; }
  /// True when the residual is linear in the unknowns (small displacements, dead loads): an
  /// increment has then converged once the residual criterion holds, whatever |du|/|u|.
  bool linearResponse() const { return small_ && follower_.edges.extent(0) == 0; }

  /// One increment from the committed state straight to lambda with default NonlinearOptions.
  LinearSolveStats solve(double loadFactor) override;
  double assemblySeconds() const override { return assemblySeconds_; }
  double solverSetupSeconds() const override { return solverSetupSeconds_; }
  /// The first element found inverted by the last evaluate() (-1: none), and a message naming it
  /// by its mesh id.
  LocalIndex invertedElement() const { return invertedElement_; }
  std::string invertedElementMessage() const;

  /// The largest force, displacement and stress norms of the committed states so far (3
  /// values): below kHistoryFraction of them, a norm no longer scales the convergence criteria,
  /// so that a body unloaded to zero converges (its forces and displacements go to round-off).
  /// The load stepper calls noteCommitted() after every commit; a restart restores them.
  void noteCommitted();
  std::vector<double> historyScales() const { return {history_[0], history_[1], history_[2]}; }
  void setHistoryScales(const std::vector<double> &scales);
  static constexpr double kHistoryFraction = 1e-3;

  /// Quadrature-point output of the current state, in one kernel pass: coordinates (reference),
  /// the Cauchy stress of the Almansi law from the displacements, the spatial displacement
  /// gradient du/dx (4 per point), and the current coordinates.
  void gaussPointStressHost(std::vector<double> &coordinates, std::vector<double> &stress,
                            int &pointsPerElement) const override;
  void gaussPointFieldsHost(std::vector<double> &coordinates, std::vector<double> &stress,
                            int &pointsPerElement, std::vector<double> &gradient,
                            std::vector<double> &currentCoordinates) const;

protected:
  struct FollowerLoads {
    Kokkos::View<LocalIndex *[2], Memory> edges;
    Kokkos::View<double *, Memory> pressure;
    Kokkos::View<double *, Memory> base;    ///< stages: the start of each pressure (else empty)
    Kokkos::View<double *, Memory> applied; ///< stages: base + lambda pressure (work)
  };
  /// Device copy of the staged follower pressures (empty views when none).
  FollowerLoads followerLoads() const;
  /// The follower pressures at lambda and the factor the kernels scale them by: (pressure,
  /// lambda), or in a stage (base + lambda pressure, 1).
  std::pair<Kokkos::View<const double *, Memory>, double> followerPressureAt(double lambda) const;
  FollowerLoads follower_; ///< the device copy setup() and commitStage() make
  /// The follower pressures' forces are assembled into followerForce(g) (zeroed, g's length) and
  /// then added to g by addFollowerForce(g, stride), which notes their norm: the residual's
  /// reference force includes them (a body loaded only by follower pressures starts at u = 0
  /// with no internal force and no dead load).
  Kokkos::View<double *, Memory> followerForce(const Kokkos::View<double *, Memory> &g);
  void addFollowerForce(const Kokkos::View<double *, Memory> &g, int stride);
  LinearSolverOptions linearOptions_;
  double assemblySeconds_ = 0.0, solverSetupSeconds_ = 0.0;
  /// The correction `dx` with the contact constraints enforced (contact_ constrains()): solved
  /// through contact_->constraintSet(), or by contact_->correct() where that gives none.
  LinearSolveStats correctWithContact(
      double lambda, int stride, const CsrMatrix<Memory> &tangent, CsrMatrix<Memory> &work,
      const Kokkos::View<const int *, Memory> &flags, const Kokkos::View<const double *, Memory> &g,
      const Kokkos::View<double *, Memory> &rhs, const Kokkos::View<double *, Memory> &target,
      LinearSolver &solver, const Kokkos::View<double *, Memory> &dx);
  /// The common end of evaluate(): contact detection at coordinates + x (`stride` unknowns per
  /// node), friction forces, and the relative residual of g over the free displacement unknowns
  /// (reference max(f_int, f_ext, force floor)); infinity when an element is inverted.
  double finishEvaluate(double lambda, bool tangent, LocalIndex inverted, double fint,
                        const Kokkos::View<double *, Memory> &g, int stride,
                        const Kokkos::View<const int *, Memory> &flags,
                        const Kokkos::View<const double **, Memory> &coordinates,
                        const Kokkos::View<const double *, Memory> &x,
                        std::chrono::steady_clock::time_point start);
  /// Round-off floor of the force norm for a displacement norm (relative residuals of nearly
  /// rigid motions under no load).
  double forceFloor(double displacementNorm) const;
  /// Sets the stiffness scale of forceFloor from K^L assembled on the model's node graph.
  void setStiffnessScale(const NodeGraph &graph,
                         const Kokkos::View<int ***, Kokkos::LayoutRight, Memory> &map);
  double stiffnessScale_ = 0.0;
  /// The norms that scale the convergence criteria, in history_ and last_.
  enum Scale { kForceScale = 0, kDisplacementScale = 1, kStressScale = 2 };
  /// change / max(norm, kHistoryFraction times the largest committed `scale` norm); notes norm
  /// as the current iterate's.
  double relativeToHistory(double change, double norm, Scale scale);
  bool fresh_ = false; ///< the last evaluate() assembled a tangent not yet given to the solver
  LocalIndex invertedElement_ = -1;
  ContactIterations *contact_ = nullptr;
  CsrMatrix<Memory> contactWork_;            ///< the reduced system of multipoint constraints
  ConstraintElimination contactElimination_; ///< its symbolic phase, kept between corrections
  CapacitanceSolve capacitance_; ///< contact corrections on one factorization (direct solver)
  ElasticLaw law_ = ElasticLaw::Almansi; ///< the displacement model's law (output stresses)
  bool small_ = false;                   ///< small-displacement kinematics (setSmallDisplacements)
  /// Where a mixed model takes its Jacobian: its unknowns x, or with small displacements the
  /// origin (zeros of x's length, allocated on first use), where the Jacobian is J0, the linear
  /// operator, and the residual J0 x - f.
  Kokkos::View<const double *, Memory> tangentState(const Kokkos::View<double *, Memory> &x);
  /// Small displacements: J0 has been taken (assembled, or the matrix-free products' state set)
  /// since the last setup(); it is taken once.
  bool originTaken_ = false;
  /// The node positions of the last tangent handed to the AMG solver, whose rigid-body modes
  /// it interpolates (LinearSolver::setNearNullSpace); moved in place with every tangent
  /// (N x dim()).
  Kokkos::View<double **, Memory> positions_;

private:
  Kokkos::View<double *, Memory> origin_; ///< zeros (tangentState with small displacements)
  double history_[3] = {0.0, 0.0, 0.0}, last_[3] = {0.0, 0.0, 0.0};
  Kokkos::View<double *, Memory> followerForce_;
  double followerNorm_ = 0.0; ///< of the last addFollowerForce, until finishEvaluate
  std::vector<BoundaryEdge> followerEdges_;
  std::vector<double> followerPressure_, followerBase_;
};

namespace detail {
/// Refuses a saved state of another formulation (0 displacement, 1 and 2 the mixed model's forms
/// Current and Incremental), naming both (std::runtime_error).
void checkFormulation(const Checkpoint &state, double expected);
/// The state of a mixed model's incremental form in a checkpoint (formulation 2, 2D and 3D): the
/// total displacement, the nodal stress tau and the configuration c1 (saved itself: X + u differs
/// from it by rounding; node by node, whatever the view's layout).
void saveIncrementalState(Checkpoint &state,
                          const Kokkos::View<const double *, DeviceSpace> &displacement,
                          const Kokkos::View<const double *, DeviceSpace> &tau,
                          const Kokkos::View<const double **, DeviceSpace> &configuration);
/// Reads what saveIncrementalState wrote into views of the same sizes.
void restoreIncrementalState(const Checkpoint &state,
                             const Kokkos::View<double *, DeviceSpace> &displacement,
                             const Kokkos::View<double *, DeviceSpace> &tau,
                             const Kokkos::View<double **, DeviceSpace> &configuration);
/// field <- mass^-1 load for `components` interleaved values per node (mass: a scalar matrix,
/// one row per node), component by component by Jacobi-CG to 1e-13 from field's values: the L2
/// projection of the incremental form's stress update, accepted at the backward-error floor of
/// floating point. CommitFailure when a component does not converge (field may then hold the
/// components before it projected).
void projectNodalComponents(const CsrMatrix<DeviceSpace> &mass,
                            const Kokkos::View<const double *, DeviceSpace> &load, int components,
                            const Kokkos::View<double *, DeviceSpace> &field);
} // namespace detail

} // namespace mixcon
