// The block-triangular preconditioned Krylov solve of a mixed saddle-point system
// J = [A B; C -M] on vectors of interleaved unknowns per node (the displacements, then the
// stresses: 2 + 3 in 2D, 3 + 6 in 3D), shared by the linear mixed model (solver/MixedModel.cpp,
// C = K12^T), the nonlinear one's Jacobian (solver/MixedNewtonSolvers.cpp) and the 3D mixed
// models (solver/SolidMixedSolve.cpp): flexible GMRES on the constrained J with its stress rows
// scaled, right preconditioned by [S~ 0; C -M~]. Layer: solver.
#pragma once

#include <solver/Krylov.hpp>
#include <solver/LinearSolver.hpp>

#include <chrono>
#include <functional>
#include <string>

namespace mixcon {

/// What a model supplies to blockTriangularSolve. Vectors are DeviceSpace views; "per node" is
/// the model's interleaving: `displacements` then `stresses` unknowns per node (2D: fieldops::
/// kDisp and kStress, kMixed in all; 3D: 3 and 6).
struct SaddlePointSystem {
  int displacements = ModelLayout::kNumDisplacements;
  int stresses = ModelLayout::kNumStresses;
  /// y = J v, all unknowns, unconstrained (the solve masks and completes constrained rows).
  LinearMap jacobian;
  /// y = S~^-1 r on the displacements: one AMG V-cycle on an SPD approximation
  /// of the Schur complement A + B M^-1 C, with the constraints' identity rows.
  LinearMap schurPreconditioner;
  /// w = C v: the stress rows' displacement block (v displacements, w stresses).
  LinearMap coupling;
  /// z = M~^-1 w on the stresses (a loose solve with M); returns its inner iterations.
  std::function<long(const ConstDeviceVector &w, const DeviceVector &z)> stressSolve;
  /// Constrained unknowns, of all unknowns and of the displacements (the stresses never are).
  Kokkos::View<const int *, DeviceSpace> constrained, constrainedDisplacement;
  /// D_c: the preconditioner matrix's diagonal on constrained rows (all unknowns, 0 elsewhere).
  ConstDeviceVector constrainedDiagonal;
  /// s multiplying the stress rows of J (blockTriangularScale).
  double stressRowScale = 1.0;
};

/// s = sqrt(rms diag(S~) / rms diag(M)), the stress-row scale that balances the two off-diagonal
/// blocks of J P^-1, from the diagonals of S~ (displacements per node) and M (stresses per node);
/// 1 when M's diagonal is zero.
double blockTriangularScale(const ConstDeviceVector &diagonalSchur,
                            const ConstDeviceVector &diagonalStress);

/// A Krylov solve's figures as the mixed models report them: its iterations, residual and
/// convergence, `setupSeconds`, and the seconds since `start` as the solve time.
LinearSolveStats statsOf(const KrylovStats &ks, std::chrono::steady_clock::time_point start,
                         double setupSeconds = 0.0);

/// z = M^-1 w by CG from z = 0 to the relative `tolerance` (at most 2000 iterations), `apply`
/// the product with the SPD stress block M and `precondition` its preconditioner; returns the
/// iterations. Throws std::runtime_error, naming `who`, when the CG does not converge.
long stressBlockSolve(const LinearMap &apply, const LinearMap &precondition,
                      const ConstDeviceVector &w, const DeviceVector &z, double tolerance,
                      KrylovWorkspace &workspace, const std::string &who);

/// Solves J x = f with x = target on the constrained unknowns (all unknowns per node; f's
/// constrained entries are ignored), starting from x = 0: flexible GMRES (options.method is
/// ignored) on D (P J P + D_c), D scaling the stress rows by s, right preconditioned by
/// P^-1 = [S~ 0; C -M~]^-1 D^-1. Adds the stress solves' iterations to `inner`; Krylov vectors
/// from `workspace` when given.
KrylovStats blockTriangularSolve(const SaddlePointSystem &system, const KrylovOptions &options,
                                 const ConstDeviceVector &f, const ConstDeviceVector &target,
                                 const DeviceVector &x, long &inner,
                                 KrylovWorkspace *workspace = nullptr);

} // namespace mixcon
