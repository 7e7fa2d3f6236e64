// The linear mixed (Hellinger-Reissner) model on solids (issue 17, first step of the 3D mixed
// model): displacements and the six Voigt stresses as nodal unknowns of equal order (9 per node:
// u, v, w, then xx, yy, zz, yz, xz, xy): Hex8/Hex8, Hex20/Hex20, Tet4/Tet4 and Tet10/Tet10 (the
// tetrahedra with the rules of core/ElementTraits.hpp MixedRule). Its operator is the Jacobian
// of the mixed residual at the undeformed, unstressed state, assembled by the generic element
// driver (kernels/Nonlinear.hpp SolidMixedKernel): [a K^L, (1 - a) K12; (1 - a) K12^T,
// -(1 - a) M] with the consistent stabilization a (0: the report's model), and solved with the
// direct solver or the block-triangular AMG solve (solver/SolidMixedSolve.hpp). Data flow:
// kernels -> solver (this) -> io.
#pragma once

#include <solver/ModelBase.hpp>
#include <solver/NonlinearOptions.hpp>

#include <memory>
#include <string>

namespace mixcon {

class SolidMixedSolve;
class SolidMixedMatrixFree;

namespace detail {
/// Refuses (InputError) a mesh the 3D mixed models do not take: a 2D one.
void checkSolidMixedElement(const Mesh &mesh);
/// The compliance D = C^-1 of each material (InputError naming a material whose stiffness is
/// not positive definite).
std::vector<SolidMatrix> solidCompliances(const std::vector<SolidMatrix> &stiffness);
/// Device copy of per-material 6 x 6 matrices.
Kokkos::View<SolidMatrix *, DeviceSpace> deviceMatrices(const std::vector<SolidMatrix> &m,
                                                        const char *label);
} // namespace detail

class SolidMixedModel final : public ModelBase {
public:
  /// A 3D mesh (Hex8, Hex20, Tet4, Tet10; InputError for a 2D one) and the 6 x 6 [C] of
  /// each material; a in [0, 1) is the stabilization.
  SolidMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                  const std::vector<SolidMatrix> &stiffness, double stabilization);

  ~SolidMixedModel() override;
  /// Assembles the operator and, with solver: direct, applies the constraints and factorizes it;
  /// with solver: amg, sets up the block-triangular solve (solver/SolidMixedSolve.hpp). Call
  /// after all loads and constraints are given.
  void setup(const LinearSolverOptions &options, MPI_Comm comm);
  /// solver: amg: the relative tolerance of the CG on the stress block inside the preconditioner,
  /// the GMRES restart, and whether the operator is applied without its matrix
  /// (SolidMixedMatrixFree; no fall back to the LU then): solidJacobianWithoutMatrix of
  /// `jacobian` (automatic: above kSolidMixedDirectFallback unknowns); call before setup().
  void setIterativeSolver(double preconditionerTolerance, int restart,
                          JacobianForm jacobian = JacobianForm::Automatic) {
    preconditionerTolerance_ = preconditionerTolerance;
    restart_ = restart;
    jacobian_ = jacobian;
  }
  /// Whether the operator is applied without its matrix (set by setup()).
  bool matrixFree() const { return matrixFree_ != nullptr; }
  /// Solves for load factor lambda: loads lambda F, u = lambda g on constrained unknowns (solver:
  /// amg falls back to the direct LU, reported in the note, where it does not converge and the
  /// system has at most min(directFallbackUnknowns, kSolidMixedDirectFallback) unknowns).
  LinearSolveStats solve(double loadFactor) override;

  double assemblySeconds() const override { return assemblySeconds_; }
  double solverSetupSeconds() const override;
  std::string solverName() const override;
  /// The stress unknowns (6 per node, Voigt<3> order).
  std::vector<double> nodalStressHost() const override;
  /// The displacement rows of the operator times the solution, minus lambda F (3 per node).
  std::vector<double> reactionHost(double loadFactor) const override;
  /// The solution vector (9 per node).
  Kokkos::View<const double *, Memory> unknowns() const { return x_; }

private:
  double stabilization_;
  std::vector<SolidMatrix> compliance_; ///< D = C^-1 per material (host)
  CsrMatrix<Memory> operator_, constrained_;
  /// The operator's LU estimated for LinearSolverOptions::directWhenCheaper (solve()).
  DirectCostEstimate operatorCost_;
  Kokkos::View<int *, Memory> flags_; ///< constrained unknowns, 9 per node
  Kokkos::View<double *, Memory> x_;  ///< the unknowns, 9 per node
  /// The LU of the constrained operator and its right-hand side for lambda = 1 (solver: direct,
  /// or the fall back of amg).
  void setupDirect();
  /// For lambda = 1: F on the displacement rows, the prescribed values g, and the constrained
  /// right-hand side of the direct solve.
  Kokkos::View<double *, Memory> rhs_, target_, constrainedRhs_;
  std::unique_ptr<LinearSolver> solver_; ///< solver: direct, or the fall back of amg
  /// jacobian: matrix_free; declared before iterative_, which keeps its products, so that it is
  /// destroyed after it.
  std::unique_ptr<SolidMixedMatrixFree> matrixFree_;
  std::unique_ptr<SolidMixedSolve> iterative_; ///< solver: amg
  JacobianForm jacobian_ = JacobianForm::Automatic;
  LinearSolverOptions options_;
  MPI_Comm comm_ = MPI_COMM_SELF;
  double preconditionerTolerance_ = 1e-2;
  int restart_ = kSolidMixedRestart;
  double assemblySeconds_ = 0.0;
};

} // namespace mixcon
