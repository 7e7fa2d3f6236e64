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
  /// z = M~^-1 w on the stresses: a solve with M to the relative `tolerance` that
  /// blockTriangularSolve asks for (stressSolveTolerance); returns its inner iterations.
  std::function<long(const ConstDeviceVector &w, const DeviceVector &z, double tolerance)>
      stressSolve;
  /// The loosest relative tolerance of stressSolve (`stress_block_tolerance`).
  double stressTolerance = 1e-2;
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

/// The relative tolerance of the solve with M inside the preconditioner, for a preconditioner input
/// whose displacement part has the norm `displacementResidual` and whose stress solve's right-hand
/// side w = C S~^-1 r_u - r_tau / s has the norm `stressRhs`, with s the stress-row scale:
/// min(`loosest`, kStressToleranceMargin displacementResidual / (s stressRhs)), at least
/// kTightestStressTolerance.
/// Why: the solve's error e enters the displacement rows as B e. On a slender part a bending
/// displacement has stresses (L/h)^2 times larger than the forces that they leave, so a relative
/// error tau of M^-1 w perturbs those rows by about tau s ||w||, which is (L/h)^2 times ||r_u||:
/// with a fixed 1e-2 the flexible GMRES stalled near a residual of 1 on the Quad8 strip of
/// L/h = 1000 (docs/performance.md, issue 20 section 6). On compact parts the ratio is larger, so
/// the tolerance is tightened little (4-7 % more inner iterations on the 4 x 1 strip).
double stressSolveTolerance(double loosest, double displacementResidual, double stressRhs,
                            double stressRowScale);
/// Measured on the Quad8 strips (L/h = 10, 100, 1000): 0.1, 0.01 and 0.001 gave the same outer
/// iterations, 1 gave 2.1-2.3x as many at L/h = 1000; on the compact 4 x 1 strip at 1e6 unknowns
/// 0.1 cost 4 % (Quad4) and 7 % (Quad8) more inner iterations per application, no outer ones.
inline constexpr double kStressToleranceMargin = 0.1;
inline constexpr double kTightestStressTolerance = 1e-12;

/// A Krylov solve's figures as the mixed models report them: its iterations, residual and
/// convergence, `setupSeconds`, and the seconds since `start` as the solve time.
LinearSolveStats statsOf(const KrylovStats &ks, std::chrono::steady_clock::time_point start,
                         double setupSeconds = 0.0);

/// z = M^-1 w by CG from z = 0 to the relative `tolerance` (at most 2000 iterations), `apply`
/// the product with the SPD stress block M and `precondition` its preconditioner; returns the
/// iterations. Throws std::runtime_error, naming `who`, when the CG misses the relative
/// residual max(tolerance, `acceptable`) (the preconditioner's loosest tolerance where
/// stressSolveTolerance asked for a tighter one).
long stressBlockSolve(const LinearMap &apply, const LinearMap &precondition,
                      const ConstDeviceVector &w, const DeviceVector &z, double tolerance,
                      KrylovWorkspace &workspace, const std::string &who, double acceptable = 0.0);

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
