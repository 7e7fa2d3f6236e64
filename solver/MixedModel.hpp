// The mixed (Hellinger-Reissner) model of the report, Eq. (29)-(32): displacements and stresses
// are nodal unknowns (u, v, Sxx, Syy, Sxy per node, equal-order interpolation). The system
//   [K11 + a Kd    (1-a) K12 ] [u]   [f]
//   [(1-a) K12^T  -(1-a) M   ] [S] = [0]
// is the report's model for a = 0; a > 0 adds the consistent stabilization of DESIGN-NOTES
// section 2 (Schur complement S_a = K11 + a Kd + (1-a) K12 M^-1 K12^T, stresses still
// S = M^-1 K12^T u). M is the consistent compliance mass or its lumped 3x3 nodal blocks.
// Solvers:
//   direct - the full saddle-point system, sparse LU (small problems, reference in tests);
//   amg    - method Schur: Krylov on the Schur complement preconditioned by one BoomerAMG
//            V-cycle on the assembled lumped S_a (or on Kd): with lumped M the operator is that
//            assembled matrix; with consistent M it is applied matrix-free with an inner CG on M;
//            method BlockTriangular: flexible GMRES on the whole saddle point, right
//            preconditioned by [S~ 0; K12^T -M~] (the same V-cycle, a loose CG on M,
//            tighter on slender parts;
//            solver/BlockTriangular.hpp).
// K12, K12^T and M are applied through the assembled node-block operators or element by element
// (partial assembly or fully matrix-free, kernels/MixedMatrixFree.hpp; MixedOptions::operators).
// Data flow: mesh -> kernels -> solver (this) -> io.
#pragma once

#include <kernels/MixedElasticity.hpp>
#include <kernels/MixedMatrixFree.hpp>
#include <solver/MixedOptions.hpp>
#include <solver/ModelBase.hpp>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace mixcon {

/// Element data plus the compliance D = C^-1 of every material; throws InputError when a [C] is
/// not positive definite.
MixedElementData<DeviceSpace> withCompliance(const ElementData<DeviceSpace> &d,
                                             const std::vector<PlaneMatrix> &stiffness);

/// The operator form of `requested`, Auto resolved by the rule measured with
/// bench/bench_mixed_operators.cpp (docs/performance.md, one thread, best of 3): the model's
/// Schur solve with partial assembly took 0.92 of the assembled time on 1e4 Quad8 elements (the
/// inner CG's M products dominate; M s by partial assembly is 0.6-1.0 of assembled from 1e4
/// Quad8 elements on), 1.07 on 1e3; on Quad4 it took 1.2-1.6 of it, and fully matrix-free 1.1-2.3
/// everywhere. So: partial assembly for Quad8 from 1e4 elements, the assembled operators otherwise.
MixedOperatorForm resolveOperatorForm(MixedOperatorForm requested, ElementType type,
                                      LocalIndex numElements);

/// The method of the iterative solve, Auto resolved by the rule measured with
/// bench/bench_mixed_solver.cpp at about 1e6 unknowns (docs/performance.md, "The linear mixed
/// solve (issue 20)", 2 threads, strip at about 1e6 displacement unknowns): consistent M ->
/// BlockTriangular (0.33-0.64 of the Schur method's solve time, Quad4 and Quad8); lumped M ->
/// Schur (its operator is then the assembled S_a,L: 17 iterations, 0.8-0.9 of the
/// block-triangular time).
MixedLinearMethod resolveLinearMethod(MixedLinearMethod requested, ComplianceMass compliance);

class MixedModel final : public ModelBase {
public:
  /// Throws InputError for an unsupported (displacement, stress) pairing or a material whose [C]
  /// is not positive definite (no compliance).
  MixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
             const std::vector<PlaneMatrix> &stiffness, double thickness,
             ElementType stressElement);
  MixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
             const std::vector<PlaneMatrix> &stiffness, double thickness)
      : MixedModel(mesh, elementMaterial, stiffness, thickness, mesh.elementType) {}
  ~MixedModel() override;

  /// A nodal stress field tau (3 per node) whose geometric stiffness K11 (Eq. (31)) joins the
  /// operator: the prestressed tangent of the updated-Lagrangian iteration. Call before setup().
  void setInitialStress(const std::vector<double> &tau);

  /// Assembles the blocks and sets the chosen solver up. Call after loads and constraints.
  void setup(const MixedOptions &options, MPI_Comm comm);
  LinearSolveStats solve(double loadFactor) override;

  double assemblySeconds() const override { return assemblySeconds_; }
  double solverSetupSeconds() const override { return solverSetupSeconds_; }
  std::string solverName() const override;
  /// The iterative method (the options' choice, Auto resolved); after setup().
  MixedLinearMethod method() const { return method_; }
  /// Inner CG iterations on M in the last solve (Schur: in its products; BlockTriangular: in its
  /// preconditioner).
  long innerIterations() const { return innerIterations_; }
  /// Operator applications in the last solve.
  long operatorApplications() const { return operatorApplications_; }

  Kokkos::View<double *, Memory> stress() const { return s_; } ///< 3 per node, interleaved
  std::vector<double> nodalStressHost() const override;        ///< the stress unknowns
  std::vector<double> reactionHost(double loadFactor) const override;

  /// The assembled operators: the lumped blocks always; graph, coupling and compliance only when
  /// the solve uses them (operatorForm() Assembled, or the lumped-Schur preconditioner).
  const MixedOperators<Memory> &operators() const { return ops_; }
  /// How K12, K12^T and M are applied (the options' choice, Auto resolved); after setup().
  MixedOperatorForm operatorForm() const { return form_; }
  const MixedElementData<Memory> &elementData() const { return mixed_; }
  /// y = S_a u, unconstrained (with the options' M; consistent M through the inner CG).
  void applySchur(const ConstDeviceVector &u, const DeviceVector &y);
  /// s = M^-1 r (consistent: inner CG to inner_tolerance; lumped: nodal blocks).
  void applyComplianceInverse(const ConstDeviceVector &r, const DeviceVector &s);
  /// Every Kokkos view the model holds after setup(), by name, with its bytes (the device-memory
  /// budget; hypre's copy of the preconditioner matrix and its AMG hierarchy, the Krylov vectors
  /// of solve() and setup's temporaries are not views held here).
  std::vector<std::pair<std::string, std::size_t>> deviceViewBytes() const;
  /// The assembled preconditioner matrix (lumped S_a without K11, or Kd), constrained rows.
  const CsrMatrix<Memory> &preconditionerMatrix() const { return precMatrix_; }

private:
  struct Direct;
  Kokkos::View<double *, Memory> initialStressOnDevice() const; ///< zero when none was given
  void setupDirect();
  void setupBlockTriangular();
  /// s = M^-1 r to `tolerance` (consistent M: inner CG; lumped: nodal blocks); returns the
  /// inner iterations. Throws when the CG misses max(tolerance, `acceptable`).
  long solveCompliance(const ConstDeviceVector &r, const DeviceVector &s, double tolerance,
                       double acceptable = 0.0);
  LinearSolveStats solveDirect(double loadFactor);
  LinearSolveStats solveSchur(double loadFactor);
  LinearSolveStats solveBlockTriangular(double loadFactor);
  /// y = J v for the saddle point with its stress rows divided by 1 - a,
  ///   J = [a Kd + K11, (1-a) K12; K12^T, -M], v and y 5 per node (u, v, Sxx, Syy, Sxy).
  void applySaddlePoint(const ConstDeviceVector &v, const DeviceVector &y);
  /// r = K12^T u, f = beta f + alpha K12 s and y = M x by the chosen operator form.
  void applyCouplingTransposeBlock(const ConstDeviceVector &u, const DeviceVector &r) const;
  void applyCouplingBlock(double alpha, const ConstDeviceVector &s, double beta,
                          const DeviceVector &f) const;
  void applyComplianceBlock(const ConstDeviceVector &x, const DeviceVector &y) const;

  MixedOptions options_;
  MixedElementData<Memory> mixed_;
  NodeGraph graph_;
  MixedOperators<Memory> ops_;
  MixedMatrixFreeOperators<Memory> matrixFree_; ///< used unless form_ is Assembled
  MixedOperatorForm form_ = MixedOperatorForm::Assembled;
  MixedLinearMethod method_ = MixedLinearMethod::Schur;
  CsrMatrix<Memory> stiffness_; ///< a Kd (+ K11) on the node graph, unconstrained
  CsrMatrix<Memory> precMatrix_;
  std::vector<double> initialStress_;
  Kokkos::View<double *, Memory> s_;
  Kokkos::View<double *, Memory> constrainedDiagonal_;
  DeviceVector workStressRhs_, workStress_; ///< K12^T u and M^-1 K12^T u inside applySchur
  /// BlockTriangular: constraint flags and D_c on 5 unknowns per node, the stress-row scale, the
  /// displacement and stress parts of v and J v inside applySaddlePoint.
  Kokkos::View<int *, Memory> constrained5_;
  Kokkos::View<double *, Memory> constrainedDiagonal5_;
  double stressRowScale_ = 1.0;
  DeviceVector splitU_, splitJu_, splitS_, splitJs_;
  KrylovWorkspace outerWork_, complianceWork_; ///< Krylov vectors kept between solves
  std::unique_ptr<LinearSolver> amg_;
  std::unique_ptr<Direct> direct_;
  double assemblySeconds_ = 0.0, solverSetupSeconds_ = 0.0;
  long innerIterations_ = 0, operatorApplications_ = 0;
};

} // namespace mixcon
