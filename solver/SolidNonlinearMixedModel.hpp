// The geometrically nonlinear mixed (Hellinger-Reissner) model on solids (issue 17): the 2D
// model's current-configuration form (NonlinearMixedModel, MixedForm::Current) on Hex8/Hex8,
// Hex20/Hex20, Tet4/Tet4 and Tet10/Tet10, 9 unknowns per node (u, v, w, then the Voigt Cauchy
// stresses xx, yy, zz, yz, xz, xy). Unknowns the total displacement and the nodal Cauchy stress;
// residual and exact Jacobian from the generic element driver (kernels/Nonlinear.hpp
// SolidMixedKernel with MixedCurrentLaw<Memory, 3>): G_u = int B(x)^T [(1 - a) tau + a C e(u)] da -
// f_ext, G_S = (1 - a) int psi (e(u) - D tau) da, e the Almansi strain, with the stabilization a
// (0: the report's model). Path independent, so no stress update between increments; load stepping,
// cutting, restart and follower face pressures as the displacement model. With
// setForm(MixedForm::Incremental) the report's literal scheme instead, as the 2D model's form
// (NonlinearMixedModel): per increment from the last converged configuration c1 with nodal
// Cauchy stress tau, unknowns the displacement increment and the incremental 2nd Piola-Kirchhoff
// stress S (MixedIncrementLaw<Memory, 3>), at convergence tau <- F (tau + S) F^T / J (projected or
// node-averaged, setStressUpdate) and c1 <- c1 + u. Solved with the direct
// solver (sparse LU) or the block-triangular AMG solve (solver/SolidMixedSolve.hpp). With small
// displacements (NonlinearModel::setSmallDisplacements) the residual is J0 x - f, J0 the Jacobian
// at x = 0 (the linear model's operator): the linear 3D mixed model through stages. Data flow:
// kernels -> solver (this) -> io.
#pragma once

#include <solver/NonlinearModel.hpp>
#include <solver/SolidMixedSolve.hpp>

#include <memory>
#include <string>
#include <vector>

namespace mixcon {

class SolidNonlinearMixedModel final : public NonlinearModel {
public:
  /// A 3D mesh (Hex8, Hex20, Tet4, Tet10; InputError for a 2D one), the 6 x 6 [C] of each material
  /// and the stabilization a in [0, 1).
  SolidNonlinearMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                           const std::vector<SolidMatrix> &stiffness, double stabilization);
  ~SolidNonlinearMixedModel() override;

  /// solver: direct — sparse LU of the Jacobian (not symmetric); amg — flexible GMRES on the
  /// Jacobian with the block-triangular preconditioner of SolidMixedSolve (one BoomerAMG V-cycle
  /// on K^L of the current configuration), falling back to the LU (reported) where it does not
  /// converge and the fall back is allowed. The Jacobian is assembled, or, where
  /// MixedNewtonSolverOptions::jacobian takes it (solidJacobianWithoutMatrix: matrix_free, or
  /// auto above kSolidMixedDirectFallback unknowns) and no follower pressures are applied,
  /// without its matrix (SolidMixedMatrixFree; no fall back then).
  void setup(const LinearSolverOptions &options, MPI_Comm comm) override;
  /// GMRES restart, the CG tolerance on M and the Jacobian's form of solver: amg (method is not
  /// used); call before setup().
  void setIterativeSolver(const MixedNewtonSolverOptions &o) { mixedOptions_ = o; }
  /// The form (Current, the default, or Incremental) and the incremental form's push-forward of
  /// the stress; call before setup().
  void setForm(MixedForm f) { form_ = f; }
  MixedForm form() const { return form_; }
  void setStressUpdate(StressUpdate u) { stressUpdate_ = u; }
  /// CG iterations on the stress block in the last correction (solver: amg).
  long innerIterations() const;
  double evaluate(double lambda, bool tangent) override;
  LinearSolveStats correct(double lambda, double &increment) override;
  void commit() override;
  void rollback() override;
  void constraintsChanged() override; ///< the flags over all unknowns anew
  void saveCommitted(Checkpoint &state) const override;
  void restoreCommitted(const Checkpoint &state) override;

  std::string solverName() const override;
  /// The nodal Cauchy stress (6 per node, Voigt<3> order): the stress unknowns (form Current),
  /// tau + S (form Incremental).
  std::vector<double> nodalStressHost() const override;
  /// The displacement rows of the last residual (internal minus external force, 3 per node).
  std::vector<double> reactionHost(double loadFactor) const override;
  std::vector<double> residualVectorHost() const override { return toHost(g_); }
  std::vector<double> residualVectorHost(const std::vector<LocalIndex> &nodes) const override {
    return toHostAt(g_, kUnknowns, nodes);
  }
  int unknownsPerNode() const override { return kUnknowns; }

  /// Whether the Jacobian is applied without its matrix (set by setup()).
  bool matrixFree() const { return matrixFree_ != nullptr; }
  /// Test access: the unknowns (9 per node: the total state, or the increment of form
  /// Incremental), the prestress tau of form Incremental (6 per node; after setup()), and the
  /// last Jacobian (empty when matrix-free) and residual.
  void setUnknowns(const std::vector<double> &x);
  void setPrestress(const std::vector<double> &tau);
  const CsrMatrix<Memory> &tangent() const { return tangent_; }
  Kokkos::View<const double *, Memory> residual() const { return g_; }

private:
  static constexpr int kUnknowns = FieldLayout<3>::kMixedUnknowns; // 9
  void updateDisplacement();
  bool incremental() const { return form_ == MixedForm::Incremental; }
  /// Where the element kernels integrate: c1 (form Incremental), else the reference geometry.
  Kokkos::View<const double **, Memory> configurationCoordinates() const;
  /// The nodal Cauchy stress, 6 per node (see nodalStressHost).
  Kokkos::View<double *, Memory> totalStress() const;
  /// Form Incremental: tau pushed forward and c1 moved by the increment, which is added to the
  /// total displacement and zeroed.
  void commitIncrement();
  /// The correction by the iterative solve (K^L of the current configuration and the AMG
  /// refreshed with a fresh Jacobian), or by the LU it fell back to.
  LinearSolveStats solveIterative();

  double stabilization_;
  double maxModulus_ = 0.0; ///< largest diagonal entry of the materials' [C]
  Kokkos::View<SolidMatrix *, Memory> compliance_;
  NodeGraph graph_;
  Kokkos::View<int ***, Kokkos::LayoutRight, Memory> map_;
  CsrMatrix<Memory> tangent_, work_;
  /// The Jacobian's LU estimated for LinearSolverOptions::directWhenCheaper.
  DirectCostEstimate jacobianCost_;
  Kokkos::View<int *, Memory> flags_; ///< constrained unknowns, 9 per node
  /// The unknowns, the last committed ones, the residual and the correction's work vectors.
  Kokkos::View<double *, Memory> x_, committed_, g_, dx_, rhs_, target_, diag_;
  std::unique_ptr<LinearSolver> solver_; ///< solver: direct, or the fall back of solver: amg
  MixedNewtonSolverOptions mixedOptions_;
  /// jacobian: matrix_free; declared before iterative_, which keeps its products, so that it is
  /// destroyed after it.
  std::unique_ptr<SolidMixedMatrixFree> matrixFree_;
  std::unique_ptr<SolidMixedSolve> iterative_; ///< solver: amg
  MPI_Comm comm_ = MPI_COMM_SELF;
  MixedForm form_ = MixedForm::Current;
  StressUpdate stressUpdate_ = StressUpdate::Projected;
  /// Form Incremental (allocated by the first setup()): c1, the last converged configuration (the
  /// materials of solid_, its own coordinates), the nodal Cauchy stress tau there and the total
  /// displacement to c1 (3 per node); the scalar mass of the projected stress update (made at
  /// the first commit).
  ElementData<Memory, 3> configuration_;
  Kokkos::View<double *, Memory> tau_, displacement_;
  CsrMatrix<Memory> mass_;
};

} // namespace mixcon
