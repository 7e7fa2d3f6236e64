// The mixed (Hellinger-Reissner) model of the report (Eq. (29)-(32) with (9), (5b)) as a
// NonlinearModel: displacements and nodal stresses as unknowns, two forms (current, incremental),
// direct or iterative (block-triangular / Schur GMRES, solver/MixedNewtonSolvers.cpp) solves of
// its Jacobian. Layer: solver.
#pragma once

#include <kernels/MixedElasticity.hpp>
#include <kernels/MixedJacobianAction.hpp>
#include <solver/Krylov.hpp>
#include <solver/NonlinearModel.hpp>

#include <memory>
#include <string>
#include <vector>

namespace mixcon {

/// The mixed model (Eq. (29)-(32) with (9), (5b)): per increment from the last converged
/// configuration c1 with nodal Cauchy stress tau, unknowns the displacement increment u and the
/// incremental 2nd Piola-Kirchhoff stress S (5 per node, interleaved u, v, Sxx, Syy, Sxy); at
/// convergence tau <- F (tau + S) F^T / J at the nodes (see StressUpdate) and c1 <- c1 + u.
/// With small displacements (setSmallDisplacements, current form only) the residual is J0 x - f,
/// J0 the Jacobian at x = 0: the linear mixed model in contact and through stages.
class NonlinearMixedModel final : public NonlinearModel {
public:
  NonlinearMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                      const std::vector<PlaneMatrix> &stiffness, double thickness);
  ~NonlinearMixedModel() override;

  /// solver: direct — sparse LU of the 5-per-node Jacobian; amg — see MixedNewtonSolver (both
  /// use one BoomerAMG V-cycle on K^L of the current configuration and a block-Jacobi CG on the
  /// stress block M).
  void setup(const LinearSolverOptions &options, MPI_Comm comm) override;
  /// Which iterative solve (solver: amg); call before setup().
  void setIterativeSolver(const MixedNewtonSolverOptions &o) { mixedOptions_ = o; }
  /// Whether GMRES applies J matrix-free (MixedNewtonSolverOptions::jacobian: matrix-free, taken:
  /// solver amg, block-triangular, no follower loads, no contact); decided in setup().
  bool matrixFree() const { return matrixFree_; }
  /// Inner CG iterations on the stress block in the last correction (solver: amg).
  long innerIterations() const { return innerIterations_; }
  double evaluate(double lambda, bool tangent) override;
  LinearSolveStats correct(double lambda, double &increment) override;
  void commit() override;
  void rollback() override;
  void constraintsChanged() override; ///< the flags over all unknowns anew
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
  std::vector<double> residualVectorHost(const std::vector<LocalIndex> &nodes) const override {
    return toHostAt(g_, 5, nodes);
  }
  int unknownsPerNode() const override { return 5; }
  /// With contact (solver: direct), stick, slip and release are decided from the nodal
  /// stresses rotated to the contact surface, as in the report.
  std::vector<double> contactStressHost() const override;
  std::vector<double> contactStressHost(const std::vector<LocalIndex> &nodes) const override {
    return toHostAt(stressOnly(), 3, nodes);
  }
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
  void setupSchurPreconditioner();
  /// solveSchur() or solveBlockTriangular(), stronger AMG preconditioners while they fail.
  LinearSolveStats solveIterative();
  /// The fall back of solveIterative() once the AMG ladder is spent: the direct LU of the
  /// assembled Jacobian (one rank, assembled J, at most directFallbackUnknowns unknowns); kept.
  std::unique_ptr<LinearSolver> jacobianDirect_;
  MPI_Comm comm_ = MPI_COMM_SELF;
  LinearSolveStats solveSchur();
  LinearSolveStats solveBlockTriangular();
  /// y = J v (y overwritten), J the Jacobian at the last tangent evaluation (matrix-free: at
  /// jacobianState_); with small displacements J0, taken at the first evaluation.
  void applyJacobian(const Kokkos::View<const double *, Memory> &v,
                     const Kokkos::View<double *, Memory> &y) const;
  bool matrixFree_ = false;
  MixedElementColors<Memory> colors_;
  Kokkos::View<double *, Memory> jacobianState_; ///< x at the last tangent (matrix-free)
  MixedNewtonSolverOptions mixedOptions_;
  double stressRowScale_ = 1.0;              ///< s of solveBlockTriangular
  Kokkos::View<double *, Memory> precDiag5_; ///< D_c on 5 unknowns per node
  CsrMatrix<Memory> couplingBlock_;          ///< C = J_tau,u (solveBlockTriangular)
  KrylovWorkspace stressWork_, outerWork_;   ///< kept between solves (solver: amg)
  /// z = M^-1 w on the stress block of the Jacobian (nodal block-Jacobi CG) to `tolerance`,
  /// accepted at `acceptable` (stressBlockSolve); returns the CG iterations.
  long solveStressBlock(const Kokkos::View<const double *, Memory> &w,
                        const Kokkos::View<double *, Memory> &z, double tolerance,
                        double acceptable = 0.0);
  CsrMatrix<Memory> precMatrix_;
  Kokkos::View<double *, Memory> precDiag_;
  CsrMatrix<Memory> stressBlock_; ///< M = -J_tau,tau (solver: amg)
  /// Its 3 x 3 nodal diagonal blocks and their inverses.
  Kokkos::View<double * [ModelLayout::kNumStresses][ModelLayout::kNumStresses], Memory>
      stressNodalBlocks_, stressBlockInverse_;
  long innerIterations_ = 0;
  MixedElementData<Memory> reference_; ///< reference geometry (form Current)
  MixedElementData<Memory> current_;   ///< c1: last converged configuration (form Incremental)
  MixedForm form_ = MixedForm::Current;
  Kokkos::View<double *, Memory> committedState_; ///< x at the last commit (form Current)
  NodeGraph graph_;
  Kokkos::View<int ***, Kokkos::LayoutRight, Memory> map_;
  CsrMatrix<Memory> tangent_, work_, mass_;
  /// The Jacobian's LU estimated for LinearSolverOptions::directWhenCheaper (solveIterative).
  DirectCostEstimate jacobianCost_;
  Kokkos::View<double *, Memory> tau_, x_, g_, committed_, dx_, rhs_, target_, diag_;
  StressUpdate stressUpdate_ = StressUpdate::Projected;
  double stabilization_ = 0.0;
  double maxModulus_ = 0.0; ///< largest diagonal entry of the materials' [C]
  Kokkos::View<int *, Memory> constrained5_;
  std::unique_ptr<LinearSolver> solver_;
};

} // namespace mixcon
