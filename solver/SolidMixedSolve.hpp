// The iterative solve of the 3D mixed models' assembled Jacobian J = [A B; C -M] (9 unknowns per
// node: 3 displacements, then the 6 Voigt stresses), `solver: amg`: flexible GMRES right-
// preconditioned by the block lower-triangular [S~ 0; C -M~] (solver/BlockTriangular.hpp, as the
// 2D models), with S~^-1 one BoomerAMG V-cycle on K^L (3 functions per node, the rigid-body modes
// of the node positions as interpolation vectors) and M~^-1 a loose CG on M preconditioned by
// its nodal 6 x 6 blocks. Shared by
// SolidMixedModel (K^L and J of the reference configuration, once) and SolidNonlinearMixedModel
// (of the current configuration, at every tangent). Layer: solver.
#pragma once

#include <solver/Krylov.hpp>
#include <solver/LinearSolver.hpp>
#include <solver/ModelBase.hpp>

#include <memory>
#include <string>

namespace mixcon {

/// The inverses of the nodal 6 x 6 diagonal blocks of m (6 unknowns per node, node-interleaved:
/// rows and columns 6 p .. 6 p + 5): inverse(p) = (block p)^-1, or the inverse of its diagonal
/// where invertConstitutive refuses the block (not positive definite; a zero diagonal entry gives
/// 0). The CG on M's preconditioner.
void invertStressBlocks(const CsrMatrix<DeviceSpace> &m,
                        const Kokkos::View<SolidMatrix *, DeviceSpace> &inverse);
/// y = diag(inverse(0), inverse(1), ...) a (6 per node).
void applyStressBlocks(const Kokkos::View<const SolidMatrix *, DeviceSpace> &inverse,
                       const Kokkos::View<const double *, DeviceSpace> &a,
                       const Kokkos::View<double *, DeviceSpace> &y);

class SolidMixedSolve {
public:
  using Memory = DeviceSpace;
  /// The patterns on the model's node graph, and the AMG (options: the problem's amg settings;
  /// `preconditionerTolerance` the relative tolerance of the CG on M, `restart` GMRES's);
  /// positions (N x 3): where K^L is built, for the AMG's rigid-body modes (may be moved in place
  /// between refresh() calls).
  SolidMixedSolve(const NodeGraph &graph, const LinearSolverOptions &options,
                  double preconditionerTolerance, int restart, const DofMap &dofs, MPI_Comm comm,
                  const Kokkos::View<const double **, Memory> &positions);
  ~SolidMixedSolve();

  /// K^L's matrix (3 unknowns per node): the caller assembles K^L into it (zeroed here) before
  /// refresh().
  CsrMatrix<Memory> &stiffness() { return stiffness_; }
  void zeroStiffness();
  /// Takes a new Jacobian: constrains K^L (flags3: the constrained displacements, 3 per node) and
  /// builds a new AMG hierarchy on it (with the rigid-body modes of `positions` as they are
  /// now), extracts C and M from J, and the stress-row scale.
  void refresh(const CsrMatrix<Memory> &jacobian, const Kokkos::View<const int *, Memory> &flags3);
  /// J x = f with x = target on the constrained unknowns (flags9, flags3: 9 and 3 per node),
  /// from x = 0 (f's constrained entries are ignored).
  LinearSolveStats solve(const CsrMatrix<Memory> &jacobian,
                         const Kokkos::View<const int *, Memory> &flags9,
                         const Kokkos::View<const int *, Memory> &flags3,
                         const Kokkos::View<const double *, Memory> &f,
                         const Kokkos::View<const double *, Memory> &target,
                         const Kokkos::View<double *, Memory> &x);
  std::string name() const;
  double setupSeconds() const { return setupSeconds_; }
  /// CG iterations on M in the last solve().
  long innerIterations() const { return inner_; }

private:
  LinearSolverOptions options_;
  double preconditionerTolerance_;
  int restart_;
  std::unique_ptr<LinearSolver> amg_;
  CsrMatrix<Memory> stiffness_, coupling_, stressBlock_;
  Kokkos::View<double *, Memory> diag3_, diag9_, stressDiagonal_;
  Kokkos::View<SolidMatrix *, Memory> stressBlockInverse_; ///< of M's nodal 6 x 6 blocks
  double stressRowScale_ = 1.0;
  KrylovWorkspace outerWork_, stressWork_;
  double setupSeconds_ = 0.0;
  long inner_ = 0;
};

} // namespace mixcon
