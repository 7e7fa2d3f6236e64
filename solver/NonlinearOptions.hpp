// The options of the geometrically nonlinear analysis as plain data (enums and structs, no
// behaviour): iteration method and tolerances, the displacement model's tangent, the mixed
// model's forms, stress update and iterative solve, the driver's verbosity. What the problem
// reader (io/) fills in without the models' headers. Layer: solver.
#pragma once

namespace mixcon {

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

/// Which tangent the displacement model iterates with.
enum class TangentKind {
  Exact, ///< the derivative of the residual (quadratic Newton convergence; not symmetric)
  Report ///< the report's K^L + K^sigma of Eq. (24)-(25) on the current configuration
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

/// The GMRES restart of the 3D mixed models' block-triangular solve (solver/SolidMixedSolve.hpp):
/// the 2D models' 30 measured 2.5x the iterations of 100 on the Hex20 cantilever of
/// tests/unit/test_solid_mixed_solve.cpp (240 against 95; Hex8: 80 against 56,
/// docs/performance.md).
inline constexpr int kSolidMixedRestart = 100;
/// The largest 3D mixed system the block-triangular solve falls back to the direct LU for (its
/// fill grows fast: with UMFPACK 62 s and 3.7 GiB for the Lame sphere's 54,873 unknowns; Eigen's
/// sparse LU before took 185 s and 10.7 GiB there, and the bound was 30,000; docs/performance.md
/// issue 20 section 7).
inline constexpr long kSolidMixedDirectFallback = 55000;

/// How the block-triangular GMRES applies the mixed Jacobian J (MixedNewtonSolverOptions::jacobian;
/// `solver: {jacobian: ...}`).
enum class JacobianForm {
  /// The 3D mixed models: without its matrix where the system has more than
  /// kSolidMixedDirectFallback unknowns (and it can be taken: solver: amg, no follower pressures),
  /// as fast or faster and 2.5-3.2x less memory at 1e6 unknowns (docs/performance.md, "The 3D
  /// mixed Jacobian without its matrix"); assembled below, where the direct LU is the fall back.
  /// The 2D mixed models: assembled (matrix-free measured 1.4-1.5x slower there).
  Automatic,
  Assembled, ///< always assembled
  MatrixFree ///< without its matrix wherever it can be taken (refused elsewhere by the input)
};

/// Whether the 3D mixed models apply J without its matrix for `form` on `unknowns` unknowns,
/// where it can be taken.
inline bool solidJacobianWithoutMatrix(JacobianForm form, long unknowns) {
  return form == JacobianForm::MatrixFree ||
         (form == JacobianForm::Automatic && unknowns > kSolidMixedDirectFallback);
}

struct MixedNewtonSolverOptions {
  MixedNewtonSolver method = MixedNewtonSolver::BlockTriangular;
  /// BlockTriangular: relative tolerance of the CG on M inside the preconditioner (1e-2: 4-5
  /// CG iterations; 1e-1 and 1e-3 measured slower, docs/performance.md).
  double preconditionerTolerance = 1e-2;
  /// BlockTriangular: GMRES restart (vectors of 5 unknowns per node: 2 x restart are stored);
  /// the 3D mixed models' default is kSolidMixedRestart.
  int restart = 30;
  /// BlockTriangular: whether GMRES applies the Jacobian matrix-free at the quadrature points
  /// (kernels/MixedJacobianAction.hpp) at the state of the last tangent evaluation, J not
  /// assembled (2D: its stress rows C and M, and K^L, are assembled on their own; 3D: C and M by
  /// partial assembly, solver/SolidMixedSolve.hpp). Without follower loads only (their Jacobian is
  /// assembled); otherwise assembled. 2D: per Newton step measured slower than the assembled J on
  /// one thread, but J's CSR (2.7 KB per Quad4, 14 KB per Quad8 element) is not stored
  /// (docs/performance.md).
  JacobianForm jacobian = JacobianForm::Automatic;
};

/// How much progress is printed. Quiet: warnings only (active-set cycling, increment cuts,
/// failures); Normal: also the driver's start-up lines and one line per step; Verbose: also every
/// equilibrium iteration and every contact status change.
enum class Verbosity { Quiet, Normal, Verbose };

} // namespace mixcon
