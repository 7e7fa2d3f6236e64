// The linear displacement model of the report (Eq. (24)-(25) without K^sigma): assembles K^L and
// F^L with the batched kernels, applies prescribed displacements, solves with hypre AMG or the
// direct solver, and recovers stresses and reactions. Loads and prescribed values form a reference
// load that a load factor scales. Device-resident throughout; host copies only on request.
// Data flow: mesh -> kernels -> solver (this) -> io.
#pragma once

#include <solver/Dirichlet.hpp>
#include <solver/ModelBase.hpp>

#include <memory>

namespace mixcon {

class LinearDisplacementModel final : public ModelBase {
public:
  using ModelBase::ModelBase;

  /// Assembles K^L, applies the constraints and sets the linear solver up (AMG hierarchy or
  /// factorization). Call after all loads and constraints are given.
  void setup(const LinearSolverOptions &options, MPI_Comm comm);
  /// Solves K u = lambda F with u = lambda g on constrained unknowns; result in displacement().
  LinearSolveStats solve(double loadFactor) override;

  /// A fresh K^L without constraints (the model keeps only its constrained one).
  CsrMatrix<Memory> assembleStiffness() const;
  double assemblySeconds() const override { return assemblySeconds_; }
  double solverSetupSeconds() const override { return solver_ ? solver_->setupSeconds() : 0.0; }
  std::string solverName() const override { return solver_ ? solver_->name() : std::string(); }

  std::vector<double> nodalStressHost() const override; ///< recovered from 2x2 Gauss points
  std::vector<double> reactionHost(double loadFactor) const override; ///< K u - lambda F

private:
  NodeGraph graph_;
  CsrMatrix<Memory> stiffness_;        ///< K^L with identity-like constrained rows
  Kokkos::View<double *, Memory> rhs_; ///< constrained right-hand side for lambda = 1
  std::unique_ptr<LinearSolver> solver_;
  double assemblySeconds_ = 0.0;
};

} // namespace mixcon
