// Linear solvers for assembled systems: hypre BoomerAMG-preconditioned CG on a ParCSR matrix built
// through the IJ interface with global row numbering (ownership ranges from the DofMap), and a
// direct sparse Cholesky (Eigen) for small problems and as the reference in tests. Data flow:
// kernels -> solver (this) -> contact -> io.
#pragma once

#include <kernels/SparseMatrix.hpp>
#include <solver/DofMap.hpp>

#include <memory>
#include <mpi.h>
#include <string>

namespace mixcon {

using DeviceSpace = Kokkos::DefaultExecutionSpace::memory_space;

enum class LinearSolverType { Amg, Direct };

/// Options; defaults are DESIGN-NOTES section 3 (HMIS, ext+i, l1-GS) with the interpolation
/// truncation measured for mixcon's operators.
struct LinearSolverOptions {
  LinearSolverType type = LinearSolverType::Amg;
  /// Relative residual ||b - A x|| / ||b|| (two-norm). Every solve checks it on the true residual
  /// of the system as posed (up to 10x over when the method itself reported success; 100x for
  /// the direct solver, whose residual is about eps * cond(A)).
  double tolerance = 1e-8;
  int maxIterations = 1000; ///< at least 1; makeLinearSolver throws std::invalid_argument

  double strongThreshold = 0.5; ///< BoomerAMG strength threshold
  int aggressiveLevels = 0;     ///< BoomerAMG levels of aggressive coarsening
  /// Interpolation truncation (PMaxElmts); 0 keeps all entries. 0 measured best for both the
  /// displacement model and the mixed preconditioners (docs/mixed-model.md); 4 is hypre's usual.
  int interpolationMaxElements = 0;
  /// Nodal coarsening (SetNodal 1, CPU only in hypre): 2x cheaper V-cycles on the Quad4 lumped
  /// Schur operator of the strip, but more iterations on the Lame cylinder and on Quad8
  /// (docs/mixed-model.md); off unless asked for.
  bool nodalCoarsening = false;
  int printLevel = 0; ///< hypre's own print level
  /// false for a nonsymmetric matrix (the exact tangent of the geometrically nonlinear
  /// displacement model): hypre GMRES(kDim) + BoomerAMG instead of PCG, LU instead of LDL^T.
  bool symmetric = true;
  int gmresRestart = 50;
};

struct LinearSolveStats {
  int iterations = 0;
  /// True relative residual ||b - A x|| / ||b|| of the solved system, recomputed after the solve
  /// (0 for b = 0, where x = 0 exactly); `converged` is decided from it, never for a NaN or for
  /// x = 0 with b != 0.
  double relativeResidual = 0.0;
  double setupSeconds = 0.0;
  double solveSeconds = 0.0;
  bool converged = false;
};

/// A solver bound to one matrix: setup() once (factorization or AMG hierarchy), then any number
/// of solve() calls with different right-hand sides.
class LinearSolver {
public:
  virtual ~LinearSolver() = default;
  /// Takes the owned rows of the matrix (rows numbered as in the DofMap); keeps what it needs.
  virtual void setup(const CsrMatrix<DeviceSpace> &a) = 0;
  /// Solves A x = b; x is overwritten (the initial guess is zero).
  virtual LinearSolveStats solve(const Kokkos::View<const double *, DeviceSpace> &b,
                                 const Kokkos::View<double *, DeviceSpace> &x) = 0;
  /// x = P^-1 b for use inside another Krylov method: one BoomerAMG V-cycle (amg) or the exact
  /// solve (direct), from a zero initial guess.
  virtual void precondition(const Kokkos::View<const double *, DeviceSpace> &b,
                            const Kokkos::View<double *, DeviceSpace> &x) = 0;
  virtual std::string name() const = 0;
  virtual double setupSeconds() const = 0;
};

/// Creates the solver chosen in the options. `comm` must outlive the solver. Throws
/// std::invalid_argument for maxIterations < 1; the direct solver's setup() throws
/// std::runtime_error for a matrix singular to working precision (a zero pivot).
std::unique_ptr<LinearSolver> makeLinearSolver(const LinearSolverOptions &options,
                                               const DofMap &dofs, MPI_Comm comm);

/// "hypre X.Y.Z" for benchmark contexts and summaries.
std::string hypreVersion();

} // namespace mixcon
