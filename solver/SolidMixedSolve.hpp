// The iterative solve of the 3D mixed models' Jacobian J = [A B; C -M] (9 unknowns per node: 3
// displacements, then the 6 Voigt stresses), `solver: amg`: flexible GMRES right-preconditioned
// by the block lower-triangular [S~ 0; C -M~] (solver/BlockTriangular.hpp, as the 2D models),
// with S~^-1 one BoomerAMG V-cycle on K^L (3 functions per node, the rigid-body modes of the node
// positions as interpolation vectors) and M~^-1 a loose CG on M (tighter on slender parts)
// preconditioned by its nodal 6 x 6 blocks. J is either assembled (its blocks C and M extracted) or
// never stored (SolidMixedMatrixFree, `solver: {jacobian: matrix_free}`): J applied at the
// quadrature points, C and M by partial assembly; only K^L, its AMG hierarchy and per-point and
// per-node data are kept. Shared by SolidMixedModel (K^L and J of the reference configuration,
// once) and SolidNonlinearMixedModel (of the current configuration, at every tangent). Layer:
// solver.
#pragma once

#include <solver/Krylov.hpp>
#include <solver/LinearSolver.hpp>
#include <solver/ModelBase.hpp>

#include <kernels/MixedJacobianAction.hpp>

#include <memory>
#include <string>

namespace mixcon {

/// The inverses of the nodal 6 x 6 diagonal blocks of m (6 unknowns per node, node-interleaved:
/// rows and columns 6 p .. 6 p + 5): inverse(p) = (block p)^-1, or the inverse of its diagonal
/// where invertConstitutive refuses the block (not positive definite; a zero diagonal entry gives
/// 0). The CG on M's preconditioner.
void invertStressBlocks(const CsrMatrix<DeviceSpace> &m,
                        const Kokkos::View<SolidMatrix *, DeviceSpace> &inverse);
/// inverse(p) = blocks(p)^-1 (the inverse of its diagonal where invertConstitutive refuses it).
void invertStressBlocks(const Kokkos::View<const SolidMatrix *, DeviceSpace> &blocks,
                        const Kokkos::View<SolidMatrix *, DeviceSpace> &inverse);
/// y = diag(inverse(0), inverse(1), ...) a (6 per node).
void applyStressBlocks(const Kokkos::View<const SolidMatrix *, DeviceSpace> &inverse,
                       const Kokkos::View<const double *, DeviceSpace> &a,
                       const Kokkos::View<double *, DeviceSpace> &y);

/// The products with a 3D mixed Jacobian J = [A B; C -M] that the block-triangular solve needs,
/// for a J that is not assembled (DeviceSpace vectors).
struct SolidMixedOperators {
  LinearMap jacobian;    ///< y = J v (9 unknowns per node)
  LinearMap coupling;    ///< w = C v (v: 3 displacements per node, w: 6 stresses per node)
  LinearMap stressBlock; ///< y = M z (6 stresses per node)
  Kokkos::View<const SolidMatrix *, DeviceSpace> stressBlocks; ///< M's nodal 6 x 6 blocks
};

/// The 3D mixed Jacobian applied without its matrix: y = J v at the quadrature points
/// (kernels/MixedJacobianAction.hpp applyMixedJacobian, the point law re-evaluated at every
/// product), w = C v and M z by partial assembly (C's 6 x 9 and M's 6 x 6 matrix at every
/// quadrature point, 720 bytes per point, the gradients recomputed; M's nodal 6 x 6 blocks; all
/// from update()), on the rules of core/ElementTraits.hpp MixedRule. Scattered per element color
/// on host spaces, with atomics on devices. Stored: the state (9 doubles per node), the point
/// matrices and the nodal blocks; nothing per node pair. The incremental law at x = 0 (no
/// prestress) is the linear model's operator (SolidMixedModel), the current law the
/// geometrically nonlinear model's exact Jacobian (SolidNonlinearMixedModel), the incremental law
/// with a prestress on c1 the Jacobian of that model's incremental form.
class SolidMixedMatrixFree {
public:
  using Memory = DeviceSpace;
  /// `solid`: the mesh and materials (for the incremental law: the configuration c1, whose
  /// coordinates may move in place between update() calls); compliance: D = C^-1 per material;
  /// a: the stabilization; currentForm: MixedCurrentLaw, else MixedIncrementLaw with the nodal
  /// prestress `prestress` (6 per node, kept as a handle: read at every product; empty: zero).
  SolidMixedMatrixFree(const Mesh &mesh, const ElementData<Memory, 3> &solid,
                       const Kokkos::View<SolidMatrix *, Memory> &compliance, double stabilization,
                       bool currentForm,
                       const Kokkos::View<const double *, Memory> &prestress = {});
  /// The products capture this object: not copied or moved.
  SolidMixedMatrixFree(const SolidMixedMatrixFree &) = delete;
  SolidMixedMatrixFree &operator=(const SolidMixedMatrixFree &) = delete;
  /// Takes the state of the products (x: 9 unknowns per node, copied) and computes C's and M's
  /// point matrices and M's nodal blocks there.
  void update(const Kokkos::View<const double *, Memory> &x);
  /// The products at the state of the last update() (valid while this object lives: its owner
  /// destroys the SolidMixedSolve that keeps them first).
  SolidMixedOperators operators() const;
  void applyJacobian(const Kokkos::View<const double *, Memory> &v,
                     const Kokkos::View<double *, Memory> &y) const;
  void applyCoupling(const Kokkos::View<const double *, Memory> &v,
                     const Kokkos::View<double *, Memory> &w) const;
  void applyStressBlock(const Kokkos::View<const double *, Memory> &z,
                        const Kokkos::View<double *, Memory> &y) const;

private:
  /// f(MixedRule<Elem>{}, law) for the mesh's element type and the model's point law.
  template <class F> void dispatch(const F &f) const;
  ElementType type_;
  ElementData<Memory, 3> solid_;
  Kokkos::View<SolidMatrix *, Memory> compliance_;
  double stabilization_;
  bool current_;
  MixedElementColors<Memory> colors_;
  Kokkos::View<double *, Memory> x_;                           ///< the state
  Kokkos::View<const double *, Memory> tau_;                   ///< the prestress (incremental law)
  Kokkos::View<double ***, Memory> pointCoupling_, pointMass_; ///< (elements, points, 54 / 36)
  Kokkos::View<SolidMatrix *, Memory> blocks_;
};

class SolidMixedSolve {
public:
  using Memory = DeviceSpace;
  /// The patterns on the model's node graph, and the AMG (options: the problem's amg settings;
  /// `preconditionerTolerance` the relative tolerance of the CG on M, `restart` GMRES's);
  /// positions (N x 3): where K^L is built, for the AMG's rigid-body modes (may be moved in place
  /// between refresh() calls).
  /// assembledJacobian: refresh() takes J as a matrix (false: as SolidMixedOperators; the
  /// patterns of C and M are then not allocated).
  SolidMixedSolve(const NodeGraph &graph, const LinearSolverOptions &options,
                  double preconditionerTolerance, int restart, const DofMap &dofs, MPI_Comm comm,
                  const Kokkos::View<const double **, Memory> &positions,
                  bool assembledJacobian = true);
  ~SolidMixedSolve();

  /// K^L's matrix (3 unknowns per node): the caller assembles K^L into it (zeroed here) before
  /// refresh().
  CsrMatrix<Memory> &stiffness() { return stiffness_; }
  void zeroStiffness();
  /// Takes a new Jacobian: constrains K^L (flags3: the constrained displacements, 3 per node) and
  /// builds a new AMG hierarchy on it (with the rigid-body modes of `positions` as they are
  /// now), extracts C and M from J, and the stress-row scale.
  /// J is kept (a shallow copy of the handle) for solve().
  void refresh(const CsrMatrix<Memory> &jacobian, const Kokkos::View<const int *, Memory> &flags3);
  /// The same for a J that is not assembled: its products (kept for solve()) and M's nodal blocks.
  void refresh(const SolidMixedOperators &jacobian,
               const Kokkos::View<const int *, Memory> &flags3);
  /// J x = f for the J of the last refresh(), with x = target on the constrained unknowns (flags9,
  /// flags3: 9 and 3 per node), from x = 0 (f's constrained entries are ignored). Where the AMG's
  /// ladder would step, `directInstead` (if given) may stop it for the caller's LU (solveOnLadder).
  LinearSolveStats solve(const Kokkos::View<const int *, Memory> &flags9,
                         const Kokkos::View<const int *, Memory> &flags3,
                         const Kokkos::View<const double *, Memory> &f,
                         const Kokkos::View<const double *, Memory> &target,
                         const Kokkos::View<double *, Memory> &x,
                         const DirectInstead &directInstead = {});
  std::string name() const;
  double setupSeconds() const { return setupSeconds_; }
  /// CG iterations on M in the last solve().
  long innerIterations() const { return inner_; }

private:
  /// K^L constrained, M's nodal blocks inverted, the stress-row scale, the AMG set up.
  void finishRefresh(const Kokkos::View<const int *, Memory> &flags3);
  LinearSolverOptions options_;
  double preconditionerTolerance_;
  int restart_;
  bool assembled_;
  SolidMixedOperators jacobian_; ///< of the last refresh()
  std::unique_ptr<LinearSolver> amg_;
  CsrMatrix<Memory> stiffness_, coupling_, stressBlock_;
  Kokkos::View<double *, Memory> diag3_, diag9_, stressDiagonal_;
  Kokkos::View<SolidMatrix *, Memory> stressBlocks_, stressBlockInverse_; ///< M's nodal blocks
  double stressRowScale_ = 1.0;
  KrylovWorkspace outerWork_, stressWork_;
  double setupSeconds_ = 0.0;
  long inner_ = 0;
};

} // namespace mixcon
