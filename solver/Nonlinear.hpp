// Geometrically nonlinear (updated-Lagrangian) analysis: the two models of the report with exact
// tangents, and the load stepping that drives them (Eq. (27)-(28)): full Newton-Raphson, modified
// Newton-Raphson (tangent formed once per increment) or no equilibrium iterations; convergence
// on the report's relative increment norm epsilon plus a relative force-residual norm; automatic
// step cutting when an increment fails. Prescribed displacements and loads scale with the load
// factor; follower pressures act normal to the deformed boundary. Theory: docs/theory.md.
// Data flow: mesh -> kernels -> solver (this) -> io.
#pragma once

#include <kernels/MixedElasticity.hpp>
#include <solver/Checkpoint.hpp>
#include <solver/Krylov.hpp>
#include <solver/ModelBase.hpp>

#include <chrono>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace mixcon {

class RigidContact;
class SurfaceContact;
class ContactIterations;
struct MultiPointConstraints;

enum class IterationMethod { Newton, ModifiedNewton, None };

/// "newton" | "modified_newton" | "none".
const char *iterationMethodName(IterationMethod m);

struct NonlinearOptions {
  IterationMethod method = IterationMethod::Newton;
  /// epsilon: ||delta u|| / ||u|| (mixed: also ||delta S|| / ||tau + S||), the report's measure.
  double tolerance = 1e-3;
  /// ||G|| / max(||internal force||, ||external force||) over the free displacement unknowns.
  double residualTolerance = 1e-6;
  int maxIterations = 30;
  /// Halvings of a failed increment before the analysis stops.
  int maxCuts = 8;
  /// Contact status updates (each followed by equilibrium iterations) per increment.
  int maxContactIterations = 30;
};

/// A geometrically nonlinear model: iterate (evaluate, correct), then commit or roll back.
/// Host-side interface (virtual, never called on the device).
class NonlinearModel : public ModelBase {
public:
  using ModelBase::ModelBase;

  /// A follower pressure p (reference value, scaled by the load factor; positive pushes into the
  /// body) on the current, deformed position of `edges`.
  void addFollowerPressure(const std::vector<BoundaryEdge> &edges, double pressure);

  /// Builds the sparsity pattern and the linear solver. Call after loads and constraints.
  virtual void setup(const LinearSolverOptions &options, MPI_Comm comm) = 0;
  /// Residual G (internal minus external force) at the current iterate for load factor lambda,
  /// and the tangent when `tangent`. Returns ||G|| / max(||f_int||, ||f_ext||) over the free
  /// displacement unknowns; infinity when an element is inverted.
  virtual double evaluate(double lambda, bool tangent) = 0;
  /// Solves the last tangent for the correction (prescribed values reach lambda g), applies it,
  /// and returns the solver statistics; `increment` receives the relative increment norm.
  virtual LinearSolveStats correct(double lambda, double &increment) = 0;
  /// Accepts the current state as converged (configuration and stress update).
  virtual void commit() = 0;
  /// Returns to the last committed state.
  virtual void rollback() = 0;
  /// The committed state (what commit() accepted) into `state` under "model/..." names;
  /// restoreCommitted makes a saved state the committed and the current one (call after
  /// setup()), so that a restarted run continues as the uninterrupted one would. Throws
  /// std::runtime_error when `state` does not fit this model (another mesh or formulation).
  virtual void saveCommitted(Checkpoint &state) const = 0;
  virtual void restoreCommitted(const Checkpoint &state) = 0;

  /// Contact with rigid obstacles enforced in the corrections (not owned; nullptr: none).
  /// Displacement model only in this version.
  virtual void setContact(RigidContact *contact);
  RigidContact *contact() const { return contact_; }
  /// Elastic-elastic node-to-segment contact (not owned; nullptr: none); both models (the mixed
  /// one with solver: direct). Not together with rigid obstacles in this version.
  void setSurfaceContact(SurfaceContact *contact) { surface_ = contact; }
  SurfaceContact *surfaceContact() const { return surface_; }
  /// The contact enforcement the load stepper iterates (rigid or surface; nullptr: none).
  ContactIterations *contactIterations() const;
  /// Host copy of the last residual G = f_int - f_ext (unknowns per node as the model's, the
  /// displacements first) and that count per node.
  virtual std::vector<double> residualVectorHost() const = 0;
  virtual int unknownsPerNode() const = 0;
  /// Nodal Cauchy stresses (3 per node) that decide stick, slip and release, or empty when the
  /// contact forces decide (displacement model).
  virtual std::vector<double> contactStressHost() const { return {}; }
  /// True when the residual is linear in the unknowns (small displacements, dead loads): an
  /// increment has then converged once the residual criterion holds, whatever |du|/|u|.
  virtual bool linearResponse() const { return false; }

  /// One increment from the committed state straight to lambda with default NonlinearOptions.
  LinearSolveStats solve(double loadFactor) override;
  double assemblySeconds() const override { return assemblySeconds_; }
  double solverSetupSeconds() const override { return solverSetupSeconds_; }
  /// The first element found inverted by the last evaluate() (-1: none), and a message naming it
  /// by its mesh id.
  LocalIndex invertedElement() const { return invertedElement_; }
  std::string invertedElementMessage() const;

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
  };
  /// Device copy of the staged follower pressures (empty views when none).
  FollowerLoads followerLoads() const;
  LinearSolverOptions linearOptions_;
  double assemblySeconds_ = 0.0, solverSetupSeconds_ = 0.0;
  /// Contact helpers shared by both models (`stride` unknowns per node, displacements first):
  /// whether any node is held in its local frame, the friction forces (2 per node) subtracted
  /// from G, the
  /// residual norm over the unknowns held by neither Dirichlet nor contact conditions, and the
  /// correction solved in local frames with the contact conditions prescribed.
  bool contactFramed() const;
  void subtractFrictionForces(const Kokkos::View<double *, Memory> &g, int stride,
                              const std::vector<double> &force);
  double contactFreeResidualNorm(const Kokkos::View<const double *, Memory> &g,
                                 const Kokkos::View<const int *, Memory> &flags, int stride) const;
  LinearSolveStats correctWithContact(
      double lambda, int stride, const CsrMatrix<Memory> &tangent, CsrMatrix<Memory> &work,
      const Kokkos::View<const int *, Memory> &flags, const Kokkos::View<const double *, Memory> &g,
      const Kokkos::View<double *, Memory> &rhs, const Kokkos::View<double *, Memory> &target,
      LinearSolver &solver, const Kokkos::View<double *, Memory> &dx);
  /// Node-to-segment contact: the constraints of the closed pairs (`flags`: the Dirichlet flags,
  /// `stride` per node), and the correction with them eliminated (x = T y + s).
  void surfaceConstraints(int stride, const std::vector<int> &flags,
                          MultiPointConstraints &c) const;
  LinearSolveStats correctWithSurfaceContact(
      double lambda, int stride, const CsrMatrix<Memory> &tangent,
      const Kokkos::View<const int *, Memory> &flags, const Kokkos::View<const double *, Memory> &g,
      const Kokkos::View<double *, Memory> &rhs, const Kokkos::View<double *, Memory> &target,
      LinearSolver &solver, const Kokkos::View<double *, Memory> &dx);
  bool surfaceClosed() const;
  /// The common end of evaluate(): contact detection at coordinates + x (`stride` unknowns per
  /// node), friction forces, and the relative residual of g over the free displacement unknowns
  /// (reference max(f_int, f_ext, force floor)); infinity when an element is inverted.
  double finishEvaluate(double lambda, bool tangent, LocalIndex inverted, double fint,
                        const Kokkos::View<double *, Memory> &g, int stride,
                        const Kokkos::View<const int *, Memory> &flags,
                        const Kokkos::View<double *[2], Memory> &coordinates,
                        const Kokkos::View<const double *, Memory> &x,
                        std::chrono::steady_clock::time_point start);
  /// Round-off floor of the force norm for a displacement norm (relative residuals of nearly
  /// rigid motions under no load).
  double forceFloor(double displacementNorm) const;
  /// Sets the stiffness scale of forceFloor from K^L assembled on the model's node graph.
  void setStiffnessScale(const NodeGraph &graph,
                         const Kokkos::View<int ***, Kokkos::LayoutRight, Memory> &map);
  double stiffnessScale_ = 0.0;
  bool fresh_ = false; ///< the last evaluate() assembled a tangent not yet given to the solver
  LocalIndex invertedElement_ = -1;
  RigidContact *contact_ = nullptr;
  SurfaceContact *surface_ = nullptr;
  CsrMatrix<Memory> surfaceWork_;        ///< the eliminated system (its own pattern)
  ElasticLaw law_ = ElasticLaw::Almansi; ///< the displacement model's law (output stresses)
  bool small_ = false; ///< small-displacement kinematics (displacement model; linear law)

private:
  std::vector<BoundaryEdge> followerEdges_;
  std::vector<double> followerPressure_;
};

/// Which tangent the displacement model iterates with.
enum class TangentKind {
  Exact, ///< the derivative of the residual (quadratic Newton convergence; not symmetric)
  Report ///< the report's K^L + K^sigma of Eq. (24)-(25) on the current configuration
};

/// The displacement model (Eq. (24)-(28)): Cauchy stress from the Almansi strain of the total
/// displacement, integrals over the current configuration, exact (nonsymmetric) tangent or the
/// report's symmetric K^L + K^sigma.
class NonlinearDisplacementModel final : public NonlinearModel {
public:
  using NonlinearModel::NonlinearModel;
  ~NonlinearDisplacementModel() override;

  void setup(const LinearSolverOptions &options, MPI_Comm comm) override;
  double evaluate(double lambda, bool tangent) override;
  LinearSolveStats correct(double lambda, double &increment) override;
  void commit() override;
  void rollback() override;
  void saveCommitted(Checkpoint &state) const override;
  void restoreCommitted(const Checkpoint &state) override;

  std::string solverName() const override;
  std::vector<double> nodalStressHost() const override; ///< the law's, recovered at nodes
  std::vector<double> reactionHost(double loadFactor) const override;
  /// The last assembled tangent (unconstrained) and residual, for tests.
  const CsrMatrix<Memory> &tangent() const { return tangent_; }
  Kokkos::View<const double *, Memory> residual() const { return g_; }
  void setDisplacement(const std::vector<double> &u);
  void setTangent(TangentKind t) { tangentKind_ = t; }
  /// Small-displacement kinematics (linear elasticity on the reference configuration, residual
  /// K u - f): the nonlinear machinery then serves contact on a linear body. Call before setup().
  void setSmallDisplacements(bool on) { small_ = on; }
  bool linearResponse() const override { return small_ && follower_.edges.extent(0) == 0; }
  /// Elastic law (default Almansi; St. Venant-Kirchhoff needs the exact tangent).
  void setElasticLaw(ElasticLaw law) { law_ = law; }
  std::vector<double> residualVectorHost() const override { return toHost(g_); }
  int unknownsPerNode() const override { return 2; }

private:
  template <class Elem> void assembleReportTangent();
  TangentKind tangentKind_ = TangentKind::Exact;
  CsrMatrix<Memory> linearStiffness_; ///< K^L on the reference configuration (small_)
  NodeGraph graph_;
  Kokkos::View<int ***, Kokkos::LayoutRight, Memory> map_;
  CsrMatrix<Memory> tangent_, constrained_;
  Kokkos::View<double *, Memory> g_, committed_, du_, rhs_, target_, diag_;
  FollowerLoads follower_;
  std::unique_ptr<LinearSolver> solver_;
};

/// How the mixed model turns tau + S into the Cauchy stress of the new configuration (Eq. (5b)).
enum class StressUpdate {
  /// L2 projection onto the nodal stress space of c2 of F (tau + S) F^T / J evaluated at the
  /// quadrature points (default: consistent, no node-to-node error pattern accumulates).
  Projected,
  /// The report's literal form: F averaged over the elements at each node, tau <- F Sigma F^T / J
  /// node by node. Its error pattern accumulates over increments (docs/theory.md).
  NodalAverage
};

/// The two forms of the geometrically nonlinear mixed model (docs/theory.md).
enum class MixedForm {
  /// Default: unknowns the total displacement and the nodal Cauchy stress in the current
  /// configuration; Almansi law imposed weakly (the displacement model's law), path independent.
  Current,
  /// The report's literal scheme: per increment from c1 the incremental 2nd Piola-Kirchhoff
  /// stress with S = C E(u) (incremental St. Venant-Kirchhoff), pushed forward at convergence.
  /// Hypoelastic: its stress is carried from increment to increment.
  Incremental
};

/// The iterative solve of the mixed Jacobian J = [A B; C -M] (solver: amg).
enum class MixedNewtonSolver {
  /// Default: flexible GMRES on J, right preconditioned by the block lower-triangular
  /// [S~ 0; C -M~] (one BoomerAMG V-cycle on K^L; a loose block-Jacobi CG on M).
  BlockTriangular,
  /// Flexible GMRES on the Schur complement A + B M^-1 C, each product with a tight inner CG on M.
  Schur
};

struct MixedNewtonSolverOptions {
  MixedNewtonSolver method = MixedNewtonSolver::BlockTriangular;
  /// BlockTriangular: relative tolerance of the CG on M inside the preconditioner (1e-2: 4-5
  /// CG iterations; 1e-1 and 1e-3 measured slower, docs/performance.md).
  double preconditionerTolerance = 1e-2;
  /// BlockTriangular: GMRES restart (vectors of 5 unknowns per node: 2 x restart are stored).
  int restart = 30;
};

/// The mixed model (Eq. (29)-(32) with (9), (5b)): per increment from the last converged
/// configuration c1 with nodal Cauchy stress tau, unknowns the displacement increment u and the
/// incremental 2nd Piola-Kirchhoff stress S (5 per node, interleaved u, v, Sxx, Syy, Sxy); at
/// convergence tau <- F (tau + S) F^T / J at the nodes (see StressUpdate) and c1 <- c1 + u.
class NonlinearMixedModel final : public NonlinearModel {
public:
  NonlinearMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                      const std::vector<PlaneMatrix> &stiffness, double thickness);
  ~NonlinearMixedModel() override;

  /// solver: direct — sparse LU of the 5-per-node Jacobian; amg — see MixedNewtonSolver (both
  /// use one BoomerAMG V-cycle on K^L of the current configuration and a block-Jacobi CG on the
  /// stress block M).
  void setup(const LinearSolverOptions &options, MPI_Comm comm) override;
  /// Which iterative solve (solver: amg); call before the first correction.
  void setIterativeSolver(const MixedNewtonSolverOptions &o) { mixedOptions_ = o; }
  /// Inner CG iterations on the stress block in the last correction (solver: amg).
  long innerIterations() const { return innerIterations_; }
  double evaluate(double lambda, bool tangent) override;
  LinearSolveStats correct(double lambda, double &increment) override;
  void commit() override;
  void rollback() override;
  void saveCommitted(Checkpoint &state) const override;
  void restoreCommitted(const Checkpoint &state) override;
  void setStressUpdate(StressUpdate u) { stressUpdate_ = u; }
  /// Call before setup().
  void setForm(MixedForm f) { form_ = f; }
  MixedForm form() const { return form_; }
  /// Stabilization a in [0, 1) (0: the report's model; see mixedIncrementElement).
  void setStabilization(double a) { stabilization_ = a; }

  std::string solverName() const override;
  std::vector<double> nodalStressHost() const override; ///< tau (+ S during an increment)
  std::vector<double> reactionHost(double loadFactor) const override;
  std::vector<double> residualVectorHost() const override { return toHost(g_); }
  int unknownsPerNode() const override { return 5; }
  /// Contact with rigid obstacles (solver: direct): stick, slip and release decided from the
  /// nodal stresses rotated to the obstacle surface, as in the report.
  void setContact(RigidContact *contact) override;
  std::vector<double> contactStressHost() const override;
  /// Nodal stresses interpolated at the quadrature points (the report's way to get Cauchy stress
  /// in the mixed model), (E * nq) x 3.
  std::vector<double> interpolatedGaussStressHost() const;

  /// Test access: prestress tau (form Incremental), the unknowns x (5 per node: the increment
  /// for Incremental, the total state for Current), the last Jacobian and residual.
  void setPrestress(const std::vector<double> &tau);
  void setIncrement(const std::vector<double> &x);
  const CsrMatrix<Memory> &tangent() const { return tangent_; }
  Kokkos::View<const double *, Memory> residual() const { return g_; }
  Kokkos::View<const double *, Memory> prestress() const { return tau_; }

private:
  void updateTotalDisplacement();
  /// Nodal Cauchy stress tau + S (3 per node).
  Kokkos::View<double *, Memory> stressOnly() const;
  /// tau <- M(c2)^-1 load, component by component (the L2 projection of the stress update).
  void projectStress(const Kokkos::View<double *, Memory> &load);
  void setupSchurPreconditioner();
  LinearSolveStats solveSchur();
  LinearSolveStats solveBlockTriangular();
  MixedNewtonSolverOptions mixedOptions_;
  double stressRowScale_ = 1.0;              ///< s of solveBlockTriangular
  Kokkos::View<double *, Memory> precDiag5_; ///< D_c on 5 unknowns per node
  CsrMatrix<Memory> couplingBlock_;          ///< C = J_tau,u (solveBlockTriangular)
  KrylovWorkspace stressWork_, outerWork_;   ///< kept between solves (solver: amg)
  /// z = M^-1 w on the stress block of the Jacobian (nodal block-Jacobi CG); returns the CG
  /// iterations.
  long solveStressBlock(const Kokkos::View<const double *, Memory> &w,
                        const Kokkos::View<double *, Memory> &z, double tolerance);
  CsrMatrix<Memory> precMatrix_;
  Kokkos::View<double *, Memory> precDiag_;
  CsrMatrix<Memory> stressBlock_;                        ///< M = -J_tau,tau (solver: amg)
  Kokkos::View<double *[9], Memory> stressBlockInverse_; ///< its 3 x 3 nodal inverses
  long innerIterations_ = 0;
  MixedElementData<Memory> reference_; ///< reference geometry (form Current)
  MixedElementData<Memory> current_;   ///< c1: last converged configuration (form Incremental)
  MixedForm form_ = MixedForm::Current;
  Kokkos::View<double *, Memory> committedState_; ///< x at the last commit (form Current)
  NodeGraph graph_;
  Kokkos::View<int ***, Kokkos::LayoutRight, Memory> map_;
  CsrMatrix<Memory> tangent_, work_, mass_;
  Kokkos::View<double *, Memory> tau_, x_, g_, committed_, dx_, rhs_, target_, diag_;
  StressUpdate stressUpdate_ = StressUpdate::Projected;
  double stabilization_ = 0.0;
  double maxModulus_ = 0.0; ///< largest diagonal entry of the materials' [C]
  Kokkos::View<int *, Memory> constrained5_;
  FollowerLoads follower_;
  std::unique_ptr<LinearSolver> solver_;
};

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

/// How much progress is printed. Quiet: warnings only (active-set cycling, increment cuts,
/// failures); Normal: also the driver's start-up lines and one line per step; Verbose: also every
/// equilibrium iteration and every contact status change.
enum class Verbosity { Quiet, Normal, Verbose };

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
  }

private:
  bool attempt(double lambda, IncrementOutcome &out, std::string &why);
  bool settleContact(double lambda, IncrementOutcome &out, std::string &why);
  std::string contactHint() const;
  NonlinearModel &model_;
  NonlinearOptions options_;
  std::ostream *log_;
  std::ostream *detail_; ///< log_ with Verbosity::Verbose, else nullptr
  double lambda_ = 0.0;
  bool contactStarted_ = false;
};

/// Convergence orders log(r_k+1 / r_k) / log(r_k / r_k-1) of a residual history (2: quadratic).
std::vector<double> convergenceOrders(const std::vector<double> &residuals);

} // namespace mixcon
