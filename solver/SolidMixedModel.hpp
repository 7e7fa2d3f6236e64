// The linear mixed (Hellinger-Reissner) model on solids (issue 17, first step of the 3D mixed
// model): displacements and the six Voigt stresses as nodal unknowns of equal order (9 per node:
// u, v, w, then xx, yy, zz, yz, xz, xy), Hex8/Hex8 and Hex20/Hex20. Its operator is the Jacobian
// of the mixed residual at the undeformed, unstressed state, assembled by the generic element
// driver (kernels/Nonlinear.hpp SolidMixedKernel): [a K^L, (1 - a) K12; (1 - a) K12^T,
// -(1 - a) M] with the consistent stabilization a (0: the report's model), and solved with the
// direct solver (the block-triangular AMG solve of the 2D model is the next step). Data flow:
// kernels -> solver (this) -> io.
#pragma once

#include <solver/ModelBase.hpp>

#include <memory>

namespace mixcon {

class SolidMixedModel final : public ModelBase {
public:
  /// A 3D mesh of Hex8 or Hex20 (throws InputError for other element types) and the 6 x 6 [C] of
  /// each material; a in [0, 1) is the stabilization.
  SolidMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                  const std::vector<SolidMatrix> &stiffness, double stabilization);

  /// Assembles the operator, applies the constraints and factorizes it (options.type must be
  /// direct). Call after all loads and constraints are given.
  void setup(const LinearSolverOptions &options, MPI_Comm comm);
  /// Solves for load factor lambda: loads lambda F, u = lambda g on constrained unknowns.
  LinearSolveStats solve(double loadFactor) override;

  double assemblySeconds() const override { return assemblySeconds_; }
  double solverSetupSeconds() const override { return solver_ ? solver_->setupSeconds() : 0.0; }
  std::string solverName() const override { return solver_ ? solver_->name() : std::string(); }
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
  Kokkos::View<int *, Memory> flags_;  ///< constrained unknowns, 9 per node
  Kokkos::View<double *, Memory> x_;   ///< the unknowns, 9 per node
  Kokkos::View<double *, Memory> rhs_; ///< constrained right-hand side for lambda = 1
  std::unique_ptr<LinearSolver> solver_;
  double assemblySeconds_ = 0.0;
};

} // namespace mixcon
