// Linear solvers for assembled systems: hypre BoomerAMG-preconditioned CG on a ParCSR matrix built
// through the IJ interface with global row numbering (ownership ranges from the DofMap), and a
// direct sparse Cholesky or LU (SuiteSparse, solver/SparseDirect.hpp) for small and medium
// problems and as the reference in tests. Data flow:
// kernels -> solver (this) -> contact -> io.
#pragma once

#include <kernels/SparseMatrix.hpp>
#include <solver/DofMap.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mpi.h>
#include <string>
#include <vector>

namespace mixcon {

using DeviceSpace = Kokkos::DefaultExecutionSpace::memory_space;

enum class LinearSolverType { Amg, Direct };

/// BoomerAMG's smoother on every level but the coarsest (hypre's relax types 8, 18, 16): the
/// l1-scaled symmetric hybrid Gauss-Seidel (DESIGN-NOTES section 3), l1-Jacobi, or Chebyshev of
/// order 2 (the last two: only matrix-vector products, no sweep order). Automatic picks, from
/// the hypre mixcon runs on, the one whose result does not depend on hypre's thread count
/// (resolvedSmoother).
enum class AmgSmoother { Automatic, L1GaussSeidel, L1Jacobi, Chebyshev };

/// Who applies BoomerAMG's V-cycle (LinearSolverOptions::cycle).
enum class AmgCycleKind { Automatic, Hypre, MixconDouble, MixconSingle };

/// When the AMG solver adds its rigid-body coarse space (LinearSolverOptions::coarseSpace).
enum class CoarseSpace {
  None,     ///< never
  OnStall,  ///< as the first step of the escalation ladder (`coarse_space: auto`)
  RigidBody ///< from the first setup on (`coarse_space: rigid_body`)
};

/// Options; defaults are DESIGN-NOTES section 3 (HMIS, ext+i, l1-GS; Chebyshev with a threaded
/// hypre: resolvedSmoother) with the interpolation truncation measured for mixcon's operators.
struct LinearSolverOptions {
  LinearSolverType type = LinearSolverType::Amg;
  /// Relative residual ||b - A x|| / ||b|| (two-norm). Every solve checks it on the true residual
  /// of the system as posed (up to 10x over when the method itself reported success; 100x for
  /// the direct solver, whose residual is about eps * cond(A)).
  double tolerance = 1e-8;
  int maxIterations = 1000; ///< at least 1; makeLinearSolver throws std::invalid_argument

  double strongThreshold = 0.5; ///< BoomerAMG strength threshold
  AmgSmoother smoother = AmgSmoother::Automatic;
  int aggressiveLevels = 0; ///< BoomerAMG levels of aggressive coarsening
  /// Interpolation truncation (PMaxElmts); 0 keeps all entries. 0 measured best for both the
  /// displacement model and the mixed preconditioners (docs/mixed-model.md); 4 is hypre's usual.
  int interpolationMaxElements = 0;
  /// Nodal coarsening (SetNodal 1, CPU only in hypre): 2x cheaper V-cycles on the Quad4 lumped
  /// Schur operator of the strip, but more iterations on the Lame cylinder and on Quad8
  /// (docs/mixed-model.md); off unless asked for.
  bool nodalCoarsening = false;
  /// BoomerAMG built on the separate displacement components: only the entries of A that couple
  /// a component with the same component of a node (row and column equal modulo the unknowns
  /// per node), about 1/3 of A's in 3D and 1/2 in 2D. The Krylov method still runs on A; the
  /// hierarchy and every V-cycle (its smoothing too) use the filtered matrix, with no
  /// interpolation vectors (the rotations couple components). Cheaper setups and V-cycles, more
  /// iterations; for compact bodies (the 3D cube: docs/performance.md), not for slender parts,
  /// whose bending couples the components (Korn's inequality degrades with L/h).
  bool separateComponents = false;
  /// Who runs BoomerAMG's V-cycle (problem key `amg_cycle`). Hypre: hypre's own cycle and
  /// Krylov method. MixconDouble, MixconSingle: mixcon's kernels on a copy of the hierarchy hypre
  /// built (solver/AmgCycle.hpp: the same levels, Chebyshev smoothing and coarsest solve, one
  /// product fewer per level, in double or single precision) inside mixcon's flexible CG (GMRES
  /// for a nonsymmetric matrix); where the copy does not apply (more than one rank, a smoother
  /// other than Chebyshev, one level) hypre's cycle runs and the solver's name says why.
  /// Automatic: MixconSingle where it applies, else hypre's, silently (docs/performance.md,
  /// issue 17 table 3h: the same iterations and a 1.3-1.7x faster solve on the 3D cube).
  AmgCycleKind cycle = AmgCycleKind::Automatic;
  /// The Chebyshev smoother's polynomial order (problem key `chebyshev_order`, 1 to 4; hypre's
  /// ChebyOrder, hypre's default 2): the smoothing applies a polynomial of degree order - 1 in
  /// D^-1 A, order products with the level's matrix per sweep. Order 1 is one scaled Jacobi step
  /// with hypre's Chebyshev damping: half the products of a V-cycle for more iterations (the
  /// problem files' default for the 3D displacement model: docs/performance.md, issue 17 table
  /// 3n). Used where the smoother is Chebyshev.
  int chebyshevOrder = 2;
  int printLevel = 0; ///< hypre's own print level
  /// false for a nonsymmetric matrix (the exact tangent of the geometrically nonlinear
  /// displacement model): hypre GMRES(kDim) + BoomerAMG instead of PCG, LU instead of Cholesky
  /// (unless the direct solver finds the matrix symmetric to round-off).
  bool symmetric = true;
  /// A symmetric but indefinite matrix (a saddle point: the mixed models): the direct solver
  /// takes the LU from the start instead of trying the Cholesky on a matrix it finds symmetric.
  bool indefinite = false;
  int gmresRestart = 50;
  /// BoomerAMG interpolation fitted to the rigid-body rotations of the node positions given by
  /// setNearNullSpace() (hypre's systems AMG with interpolation vectors, nodal coarsening), so
  /// that bending is seen on the coarse levels of slender parts (docs/performance.md).
  bool rigidBodyModes = true;
  /// hypre's InterpVecVariant: 1, 2 the global-matrix approaches GM1, GM2; 3 local neighbourhood
  /// (LN). GM2 measured fewest iterations on slender strips (docs/performance.md).
  int interpolationVectorVariant = 2;
  /// Largest coarsest level of BoomerAMG (solved by Gaussian elimination); hypre's default 9.
  int coarsestSize = 9;
  /// Robustness ladder of the AMG solver, in this order, whenever a solve does not converge within
  /// `escalationIterations` (or, for the AMG used as a preconditioner, when the method around it
  /// asks through strengthen()): within solve(), first the direct solver where it is estimated
  /// cheaper (`directWhenCheaper`, below); the rigid-body coarse space (`coarseSpace` OnStall,
  /// where it can be built: slender parts, whose bending the hierarchy loses, are what makes
  /// BoomerAMG stall); then a rebuild with the next coarsest size of `escalationCoarsestSizes`
  /// (coarse levels of long, thin elements lock in bending, so the hierarchy must stop while the
  /// elements are still short: L/h = 100 needs about 400, L/h = 1000 about 3000 unknowns; the
  /// ladder stops at 2000: the coarsest level is a dense inverse), then the direct solver where the
  /// system has at most `directFallbackUnknowns` unknowns on one rank. A step whose coarsest size
  /// is not below the system's unknowns goes to that direct solver instead (hypre would still
  /// coarsen once; the dense coarsest level would be no cheaper). Every step is taken both when a
  /// solve fails and when it converges slowly (more than half of `escalationIterations`; then from
  /// the next setup on). Each step is reported (LinearSolveStats::note) and kept for the run.
  int escalationIterations = 200;
  std::vector<int> escalationCoarsestSizes = {500, 2000};
  long directFallbackUnknowns = 200000; ///< 0: never fall back to the direct solver
  /// Within a solve(), before each step of the ladder (a stall, or a slow convergence): where the
  /// direct fall back is allowed and the direct solver's factorization is estimated to take less
  /// time than the AMG has spent on this solve, its hierarchy's setup included, the direct solver
  /// instead (at once after a stall, from the next setup after a slow convergence). The estimate
  /// comes from a symbolic analysis of the pattern, once per pattern (detail::
  /// estimatedDirectSeconds). Small and slender parts, the ones BoomerAMG stalls on, have almost
  /// banded factors: measured on examples/cantilever_3d_large_deflection.yaml with `solver: amg`
  /// (Hex20, 1,464 unknowns) 10.9-12.3 s with the ladder against 1.6 s (docs/performance.md,
  /// issue 20 section 9). False: the ladder's steps as listed above.
  bool directWhenCheaper = true;
  /// Keep the AMG hierarchy of an earlier matrix of the same sparsity pattern (Newton and contact
  /// corrections): only the fine-level values are updated, until a solve takes more than
  /// `reuseIterationGrowth` times the iterations the fresh hierarchy took (then it is rebuilt at
  /// the next setup; a solve that fails with a kept hierarchy is redone with a fresh one).
  bool reuseHierarchy = true;
  double reuseIterationGrowth = 2.0;
  /// The direct solver's factorization may be kept across contact corrections while the matrix
  /// stays and only the contact conditions change (solver/CapacitanceSolve.hpp).
  bool reuseFactorization = true;
  /// A second level around the BoomerAMG V-cycle: the rigid-body modes of small node aggregates
  /// with their Galerkin operator factorized (solver/RigidCoarseSpace.hpp), applied by the
  /// balancing method in mixcon's CG (GMRES where not symmetric). For slender parts, whose
  /// bending the classical hierarchy loses (docs/performance.md); one rank, node positions
  /// given (setNearNullSpace), at most rigidCoarseSpaceLimit() coarse unknowns. It costs 2 more
  /// products with A and 2 coarse solves per iteration, and its setup grows as the square of its
  /// size on compact 3D meshes: by default (OnStall) it is the escalation ladder's first step,
  /// taken only where BoomerAMG alone stalls or converges slowly.
  CoarseSpace coarseSpace = CoarseSpace::OnStall;
};

/// Every solver also accepts a solution at the accuracy floor of floating point: normwise
/// backward error ||b - A x|| / (||A|| ||x|| + ||b||) at most this. Slender parts need it: a strip
/// of L/h = 100 cannot get below ||r|| / ||b|| = 4e-7, one of L/h = 1000 below 4e-3, by any
/// solver (backward error 4e-17: the exact solution in double precision; cond(A) ~ (L/h)^4).
/// Only while ||A|| ||x|| <= kGrowthLimit ||b||: a singular system (a floating body) solved
/// anyway has a tiny backward error too, but an x of 1e16 ||b|| / ||A||; the L/h = 100 strip
/// has 1e10, L/h = 300 about 1e12 (L/h = 1000, 1e14, is past double precision: loosen the
/// tolerance there).
inline constexpr double kBackwardErrorFloor = 1e-14;
inline constexpr double kGrowthLimit = 1e13;

struct LinearSolveStats {
  int iterations = 0;
  /// True relative residual ||b - A x|| / ||b|| of the solved system, recomputed after the solve
  /// (0 for b = 0, where x = 0 exactly); `converged` is decided from it, never for a NaN or for
  /// x = 0 with b != 0.
  double relativeResidual = 0.0;
  double setupSeconds = 0.0;
  double solveSeconds = 0.0;
  bool converged = false;
  /// What the solver changed to get there (a stronger AMG, the direct fall back, a rebuilt
  /// hierarchy), for the log; empty when nothing changed.
  std::string note;
};

/// A solver bound to one matrix: setup() once (factorization or AMG hierarchy), then any number
/// of solve() calls with different right-hand sides.
class LinearSolver {
public:
  virtual ~LinearSolver() = default;
  /// Takes the owned rows of the matrix (rows numbered as in the DofMap); keeps what it needs.
  /// The solver keeps the matrix's views (not a copy of its values) until the next setup(): the
  /// arrays must live and keep their values until then. The AMG solver on one rank in host memory
  /// reads the matrix's own arrays while it builds a hierarchy, each row's diagonal swapped to its
  /// front, and swaps them back before the call returns (the entries are then bit for bit what
  /// they were, also where the call throws): nothing may read them during setup(), nor during a
  /// solve() or strengthen() that rebuilds the hierarchy on them (a kept hierarchy that stopped
  /// converging, the escalation ladder).
  virtual void setup(const CsrMatrix<DeviceSpace> &a) = 0;
  /// Solves A x = b; x is overwritten (the initial guess is zero).
  virtual LinearSolveStats solve(const Kokkos::View<const double *, DeviceSpace> &b,
                                 const Kokkos::View<double *, DeviceSpace> &x) = 0;
  /// x = P^-1 b for use inside another Krylov method: one BoomerAMG V-cycle (amg) or the exact
  /// solve (direct), from a zero initial guess.
  virtual void precondition(const Kokkos::View<const double *, DeviceSpace> &b,
                            const Kokkos::View<double *, DeviceSpace> &x) = 0;
  /// The node positions (one row per local node, one column per displacement component) the
  /// matrices handed to setup() are built on: the AMG solver derives the rigid-body modes from
  /// them at each setup(), so the view may be updated in place between setups (an
  /// updated-Lagrangian model moves it with the deformation). Ignored by the direct solver and
  /// where the unknowns per node are not the positions' components.
  virtual void setNearNullSpace(const Kokkos::View<const double **, DeviceSpace> &) {}
  /// Makes the preconditioner stronger for every later setup() and solve (the AMG's escalation
  /// ladder, see LinearSolverOptions) and rebuilds it on the matrix of the last setup(), for a
  /// method that applies precondition() and did not converge. False when nothing stronger is
  /// left. `note` says what was done.
  virtual bool strengthen(std::string &note) {
    (void)note;
    return false;
  }
  /// The iterations a method around precondition() should give one attempt before it asks for
  /// strengthen(): `maxIterations`, or fewer while the AMG's cheapest step, its coarse space
  /// (CoarseSpace::OnStall), is still to be taken, so that a stall is found in
  /// LinearSolverOptions::escalationIterations, not in `maxIterations`.
  virtual int iterationsPerAttempt(int maxIterations) const { return maxIterations; }
  virtual std::string name() const = 0;
  virtual double setupSeconds() const = 0;
  /// Full setups (hierarchies built or factorizations) and setups that kept the hierarchy.
  virtual int builds() const { return 0; }
  virtual int reuses() const { return 0; }
  /// True where solve() is exact to round-off on a factorization kept until the next setup()
  /// (the direct solver) and the options allow a caller to keep one for other constraints
  /// (LinearSolverOptions::reuseFactorization); builds() then counts the factorizations.
  virtual bool keepsFactorization() const { return false; }
  /// A new solver of the same kind and options, nothing set up (the direct solver: for a
  /// caller that keeps a factorization of its own beside this one's); nullptr where not offered.
  virtual std::unique_ptr<LinearSolver> another() const { return nullptr; }
};

/// Creates the solver chosen in the options. `comm` must outlive the solver. Throws
/// std::invalid_argument for maxIterations < 1; the direct solver's setup() throws
/// std::runtime_error for a matrix singular to working precision (a zero pivot).
std::unique_ptr<LinearSolver> makeLinearSolver(const LinearSolverOptions &options,
                                               const DofMap &dofs, MPI_Comm comm);

/// " with a rigid-body coarse space" (" of N unknowns" once built) when `solver`, which may be
/// null, has or asks for one (LinearSolverOptions::coarseSpace), else "": for the names of the
/// mixed models, which use its V-cycle through precondition().
std::string coarseSpacePhrase(const LinearSolver *solver);

/// Appends `more` (if any) to a LinearSolveStats::note, "; "-separated.
void appendNote(std::string &note, const std::string &more);

/// Whether the caller's direct solver should take over a system now, or has taken it over itself
/// (filling `why` when so, or with why a direct solver it tried refused the system); see
/// solveOnLadder and DirectCostEstimate.
using DirectInstead = std::function<bool(std::string &why)>;

/// The escalation ladder around a solve whose method only calls precondition() (or the AMG's own
/// Krylov solve): while `s`, the last attempt, has not converged and solver.strengthen() takes a
/// step, `attempt` runs again. Returns the last attempt; every step taken, or why none was left,
/// is appended to `note`, and `total` accumulates the iterations of the attempts after `s`.
/// Where `directInstead` is given, it is asked before each step (a non-empty `why` goes to the
/// note whatever it answers); when it says so the ladder stops there and the last attempt, not
/// converged, is returned for the caller's direct fall back (or the one it took itself).
LinearSolveStats climbLadder(LinearSolver &solver, LinearSolveStats s,
                             const std::function<LinearSolveStats()> &attempt, std::string &note,
                             int &total, const DirectInstead &directInstead = {});

/// A solve whose method only calls solver.precondition(): attempt() and, while it has not
/// converged, the solver's escalation ladder (climbLadder, with `directInstead`). Returns the last
/// attempt with the iterations of all of them and the steps taken as its note.
LinearSolveStats solveOnLadder(LinearSolver &solver,
                               const std::function<LinearSolveStats()> &attempt,
                               const DirectInstead &directInstead = {});

/// LinearSolverOptions::directWhenCheaper's estimate of a direct factorization, kept for the last
/// matrix pattern it was asked about (another pattern is analysed anew).
class DirectCostEstimate {
public:
  /// When the factorization of `a` (an LU where `symmetric` is false) is estimated
  /// (detail::estimatedDirectSeconds) to take less than `spentSeconds`: true, with both figures in
  /// `why` ("<spent> s; the direct solver's factorization is estimated at <t> s"). One rank.
  /// Where the analysis fails (out of memory), false.
  bool cheaperThan(const CsrMatrix<DeviceSpace> &a, bool symmetric, double spentSeconds,
                   std::string &why);

private:
  double flops_ = 0.0;
  std::uint64_t pattern_ = 0; ///< a hash of the pattern analysed
  bool analysed_ = false;
};

/// The direct fall back's own conditions (LinearSolverOptions::directFallbackUnknowns): one rank
/// and at most `limit` unknowns.
bool directFallbackFits(MPI_Comm comm, long unknowns, long limit);

/// The mixed models' DirectInstead (none where `allowed`, their LU fall back's conditions and
/// LinearSolverOptions::directWhenCheaper, is false): the LU of `matrix` (the Jacobian) where
/// `cost` estimates it below the seconds since `start`; the note says "<what> stalled (...)".
/// `cost` and `matrix` are referenced: they must outlive the result.
DirectInstead luWhenCheaper(bool allowed, DirectCostEstimate &cost,
                            const CsrMatrix<DeviceSpace> &matrix,
                            std::chrono::steady_clock::time_point start, const std::string &what);

/// "hypre X.Y.Z" for benchmark contexts and summaries.
std::string hypreVersion();

/// The smoother that AmgSmoother::Automatic stands for; any other is returned as is. Hybrid
/// Gauss-Seidel is Gauss-Seidel within each of hypre's threads and Jacobi between them, so with
/// a threaded (OpenMP or GPU) hypre its convergence depends on the thread count: the slender
/// strip of L/h = 100 took 30, 44, 101 and 130 PCG iterations with 1, 4, 8 and 16 threads,
/// Chebyshev 31-35 with any (docs/performance.md, "The threaded hypre with more threads").
/// Automatic is therefore Chebyshev with a threaded hypre and l1-Gauss-Seidel (a true Gauss-
/// Seidel there) with a sequential one: chosen by the build, never by the thread count.
AmgSmoother resolvedSmoother(AmgSmoother smoother);

/// "l1-Gauss-Seidel", "l1-Jacobi" or "Chebyshev" (Automatic resolved first).
std::string smootherName(AmgSmoother smoother);

namespace detail {
/// Whether the loaded libHYPRE has cmake/patches/hypre-2.26.0-chebyshev-estimate.patch (the
/// build of cmake/build-hypre.sh): probed once, by scaling a 1 x 1 zero matrix by its diagonal
/// on the host (the fixed hypre gives 0, the unfixed 1/sqrt(0) = inf; the error it may flag is
/// cleared). False for a GPU-enabled hypre, whose device estimate the patch does not touch. With
/// it `smoother: chebyshev` takes its eigenvalue bound from hypre's Lanczos estimate; without it
/// from Gershgorin's discs (that estimate can loop forever there, hypre issue #531).
bool hypreChebyshevEstimateIsSafe();

/// The seconds a direct factorization of a matrix with `nonzeros` entries and `choleskyFlops`
/// (SparseDirect::estimateCholesky: AMD's ordering) is expected to take on one rank:
/// kDirectSecondsPerNonzero per entry (the analysis and the per-column work, which dominate
/// small and slender patterns) plus the flops at kDirectFlopsPerSecond, twice those for an LU
/// (`symmetric` false: the matrix may take UMFPACK's LU, about twice the Cholesky's flops).
double estimatedDirectSeconds(std::int64_t nonzeros, double choleskyFlops, bool symmetric);
/// Fitted to the direct solver's setups (SuiteSparse 5.12, the sequential OpenBLAS, 2 cores;
/// docs/performance.md issue 20 section 9): small and slender matrices (2D and 3D, 141k-6.5M
/// entries, under 0.6 GFlop) took 0.7-1.6e-7 s per entry; on 2D grids of 0.1-1M unknowns the
/// flops went at 9-18 GFlop/s; 3D cubes of 15k-182k unknowns, ordered by METIS in the
/// factorization, took 3.3-24x less time than the model says: there it errs towards the dearer.
inline constexpr double kDirectSecondsPerNonzero = 1e-7;
inline constexpr double kDirectFlopsPerSecond = 1e10;
} // namespace detail

} // namespace mixcon
