// Options of the mixed model's solve (see MixedModel.hpp), separate so that problem-file parsing
// does not pull in the kernels. Data flow: solver.
#pragma once

#include <solver/Krylov.hpp>

namespace mixcon {

enum class ComplianceMass { Consistent, Lumped };
/// What BoomerAMG is built on for the Schur solve. Auto (measured, docs/mixed-model.md):
/// consistent M -> Kd (iteration counts flat from 1e3 to 1e6 unknowns on the strip and the Lame
/// cylinder, for Quad4 and Quad8, and the cheapest setup); lumped M -> the assembled S_a,L, which
/// is then also the operator.
enum class SchurPreconditioner { Auto, LumpedSchur, Stiffness };

/// How the Schur operator applies K12, K12^T and the consistent M (kernels/MixedMatrixFree.hpp):
/// the assembled node-block operators, partial assembly (geometric factors per quadrature point),
/// or fully matrix-free (geometry recomputed). The lumped blocks and the preconditioner matrix
/// stay assembled on every path. Auto (measured, docs/performance.md): partial assembly for Quad8
/// meshes of 1e4 elements or more, the assembled operators otherwise.
enum class MixedOperatorForm { Auto, Assembled, PartialAssembly, MatrixFree };

/// The iterative method of the solve (solver: amg; `solver: {method: ...}`):
///   Schur           - Krylov on the displacement Schur complement S_a, each product with an
///                     inner CG on M (consistent M) or the assembled S_a,L (lumped M);
///   BlockTriangular - flexible GMRES on the whole saddle point [A B; K12^T -M] (stress rows
///                     divided by 1 - a), right preconditioned by [S~ 0; K12^T -M~]: one BoomerAMG
///                     V-cycle for S~ and a loose CG on M for M~ (tighter on slender parts)
///                     (solver/BlockTriangular.hpp, the nonlinear model's method).
/// Auto (measured, docs/performance.md): block-triangular for consistent M, Schur for lumped M
/// (resolveLinearMethod, solver/MixedModel.hpp).
enum class MixedLinearMethod { Auto, Schur, BlockTriangular };

struct MixedOptions {
  ComplianceMass compliance = ComplianceMass::Consistent;
  double stabilization = 0.05; ///< a in [0, 1); 0 is the report's model
  /// type (amg | direct), tolerance, max iterations and BoomerAMG settings of the outer solve.
  LinearSolverOptions linear;
  /// Schur: the outer method; GMRES when K11 makes S indefinite (BlockTriangular: always GMRES).
  KrylovMethod krylov = KrylovMethod::Cg;
  SchurPreconditioner preconditioner = SchurPreconditioner::Auto;
  double innerTolerance = 1e-10; ///< Schur: relative, inner CG on M (consistent M only)
  int innerMaxIterations = 500;
  MixedOperatorForm operators = MixedOperatorForm::Auto;
  MixedLinearMethod method = MixedLinearMethod::Auto;
  /// BlockTriangular: relative tolerance of the CG on M inside the preconditioner (consistent M).
  double preconditionerTolerance = 1e-2;
  int restart = 30; ///< BlockTriangular: GMRES restart (vectors of 5 unknowns per node)
};

} // namespace mixcon
