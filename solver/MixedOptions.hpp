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

struct MixedOptions {
  ComplianceMass compliance = ComplianceMass::Consistent;
  double stabilization = 0.05; ///< a in [0, 1); 0 is the report's model
  /// type (amg | direct), tolerance, max iterations and BoomerAMG settings of the outer solve.
  LinearSolverOptions linear;
  KrylovMethod krylov = KrylovMethod::Cg; ///< outer method; GMRES when K11 makes S indefinite
  SchurPreconditioner preconditioner = SchurPreconditioner::Auto;
  double innerTolerance = 1e-10; ///< relative, inner CG on M (consistent M only)
  int innerMaxIterations = 500;
  MixedOperatorForm operators = MixedOperatorForm::Auto;
};

} // namespace mixcon
