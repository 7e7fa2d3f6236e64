// The iterative solves of the mixed model's Jacobian J = [A B; C -M] (solver: amg): flexible
// GMRES right-preconditioned by the block lower-triangular [S~ 0; C -M~], or on the Schur
// complement A + B M^-1 C; the block-Jacobi CG on the stress block M. Layer: solver.
#include <solver/BlockTriangular.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/Krylov.hpp>
#include <solver/MixedModel.hpp>
#include <solver/NonlinearMixedModel.hpp>

#include <kernels/Nonlinear.hpp>

#include <algorithm>
#include <cmath>

namespace mixcon {

using namespace fieldops;

void NonlinearMixedModel::setupSchurPreconditioner() {
  // K^L on the current configuration (c1 + increment, or X + total displacement), constrained;
  // one BoomerAMG V-cycle on it preconditions the Schur complement.
  const auto start = std::chrono::steady_clock::now();
  const bool current = form_ == MixedForm::Current;
  ElementData<Memory> d = current ? static_cast<ElementData<Memory>>(reference_)
                                  : static_cast<ElementData<Memory>>(current_);
  const auto base = d.mesh.coordinates;
  d.mesh.coordinates = positions_; // also the AMG's rigid-body modes
  movedCoordinates(base, tangentState(x_), kMixed, d.mesh.coordinates);
  Kokkos::deep_copy(precMatrix_.values, 0.0);
  dispatchPlaneElement(mesh_.elementType, "the nonlinear mixed model", [&](auto elem) {
    assembleLinearStiffness<decltype(elem)>(Exec(), d, map_, precMatrix_);
  });
  Vec zero("mixcon::nonlinear::zero", precDiag_.extent(0)),
      scratch("mixcon::nonlinear::scratch", precDiag_.extent(0));
  applyDirichlet(Exec(), precMatrix_, Kokkos::View<const int *, Memory>(isConstrained_),
                 ConstVec(zero), scratch);
  constrainedDiagonal(Exec(), precMatrix_, Kokkos::View<const int *, Memory>(isConstrained_),
                      precDiag_);
  // The stress block M = -J_tau,tau and its nodal kStress x kStress inverses for the inner CG.
  if (!matrixFree_) // matrix-free: assembled on its own in evaluate()
    extractFieldBlock(tangent_, kMixed, kStressAt, kStress, kStressAt, kStress, stressBlock_, -1.0);
  nodalDiagonalBlocks(stressBlock_, stressNodalBlocks_);
  invertNodalBlocks(Exec(), stressNodalBlocks_, stressBlockInverse_);
  Exec().fence();
  solver_->setup(precMatrix_);
  solverSetupSeconds_ += seconds(start);
}

long NonlinearMixedModel::solveStressBlock(const ConstVec &w, const Vec &z, double tolerance,
                                           double acceptable) {
  // M z = w with M = -J_tau,tau, extracted from J once per tangent (setupSchurPreconditioner;
  // a product with it reads 9/25 of J), CG preconditioned by the inverses of M's kStress x kStress
  // nodal blocks (the stress components coupled at a node: anisotropic compliances).
  const LinearMap apply = [&](const ConstDeviceVector &a, const DeviceVector &y) {
    multiply(Exec(), stressBlock_, a, y);
  };
  const LinearMap jacobi = [&](const ConstDeviceVector &a, const DeviceVector &y) {
    applyNodalBlocks(Exec(), stressBlockInverse_, a, y);
  };
  return stressBlockSolve(apply, jacobi, w, z, tolerance, stressWork_, "nonlinear mixed model",
                          acceptable);
}

LinearSolveStats NonlinearMixedModel::solveSchur() {
  // J [du; dtau] = -G with J = [A B; C -M]: dtau = M^-1 (C du + G_S) and
  // (A + B M^-1 C) du = -G_u - B M^-1 G_S, prescribed du applied as P S P + D_c.
  const auto start = std::chrono::steady_clock::now();
  if (fresh_)
    setupSchurPreconditioner();
  const LocalIndex nn = mesh_.numNodes();
  Vec in5("mixcon::nonlinear::in5", kMixed * nn), w("mixcon::nonlinear::w", kStress * nn),
      z("mixcon::nonlinear::z", kStress * nn), masked("mixcon::nonlinear::masked", kDisp * nn);
  const auto flags = Kokkos::View<const int *, Memory>(isConstrained_);
  // Inner solves two orders tighter than the outer tolerance, so the outer Krylov sees a fixed
  // operator to its own accuracy.
  const double innerTol = std::clamp(1e-2 * linearOptions_.tolerance, 1e-14, 1e-8);
  long inner = 0;
  // y = (A + B M^-1 C) v for a displacement vector v (kDisp per node).
  const auto schur = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    scatter<double>(v, kMixed, 0, kDisp, in5, true);
    multiplyFieldRows(tangent_, kMixed, kStressAt, kStress, ConstVec(in5), w); // tau rows: C v
    inner += solveStressBlock(w, z, innerTol);
    scatter<double>(z, kMixed, kStressAt, kStress, in5, false);
    multiplyFieldRows(tangent_, kMixed, 0, kDisp, ConstVec(in5), y); // u rows: A v + B z
  };
  const LinearMap constrainedSchur = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    maskConstrained(Exec(), flags, v, masked);
    schur(ConstVec(masked), y);
    finishConstrained(Exec(), flags, ConstVec(precDiag_), v, y);
  };
  const LinearMap amg = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    solver_->precondition(r, y);
  };
  // Right-hand side: f = -G_u - B M^-1 G_S, then b = P (f - S g) + D_c g.
  Vec mgs("mixcon::nonlinear::mgs", kStress * nn), f("mixcon::nonlinear::schurRhs", kDisp * nn),
      gc("mixcon::nonlinear::prescribedStep", kDisp * nn),
      sg("mixcon::nonlinear::schurG", kDisp * nn), b("mixcon::nonlinear::schurB", kDisp * nn),
      du("mixcon::nonlinear::du", kDisp * nn);
  gather(g_, kMixed, kStressAt, kStress, w);
  inner += solveStressBlock(w, mgs, innerTol);
  scatter<double>(mgs, kMixed, kStressAt, kStress, in5, true);
  multiplyFieldRows(tangent_, kMixed, 0, kDisp, ConstVec(in5), f); // u rows: B M^-1 G_S
  gather(g_, kMixed, 0, kDisp, sg);
  axpby(-1.0, sg, -1.0, f);
  gather(target_, kMixed, 0, kDisp, gc);
  schur(ConstVec(gc), sg);
  constrainedRhs(Exec(), flags, ConstVec(precDiag_), ConstVec(f), ConstVec(gc), ConstVec(sg), b);
  KrylovOptions ko;
  ko.method = KrylovMethod::Gmres;
  ko.tolerance = linearOptions_.tolerance;
  ko.backwardErrorFloor = true; // slender parts: the relative residual has a floor
  ko.maxIterations = solver_->iterationsPerAttempt(linearOptions_.maxIterations);
  const KrylovStats ks = krylovSolve(ko, constrainedSchur, amg, ConstVec(b), du);
  // dtau = M^-1 (C du + G_S).
  scatter<double>(du, kMixed, 0, kDisp, in5, true);
  multiplyFieldRows(tangent_, kMixed, kStressAt, kStress, ConstVec(in5), w);
  gather(g_, kMixed, kStressAt, kStress, mgs);
  axpby(1.0, mgs, 1.0, w);
  inner += solveStressBlock(w, z, innerTol);
  scatter<double>(du, kMixed, 0, kDisp, dx_, true);
  scatter<double>(z, kMixed, kStressAt, kStress, dx_, false);
  innerIterations_ = inner;
  return statsOf(ks, start);
}

LinearSolveStats NonlinearMixedModel::solveBlockTriangular() {
  // Flexible GMRES on the whole Jacobian J = [A B; C -M] (prescribed du as P J P + D_c), right
  // preconditioned by the block lower-triangular P = [S~ 0; C -M~]: S~^-1 one BoomerAMG V-cycle
  // on K^L of the current configuration (as for the Schur complement A + B M^-1 C), M~^-1 a
  // loose block-Jacobi CG on M. With M~ = M, J P^-1 = [S S~^-1, -B M^-1; 0, I] and the
  // iterations are those of the Schur solve; a loose M~ costs a few more outer iterations but
  // no tight inner solve per product. The stress rows are scaled by s = sqrt(rms diag K^L /
  // rms diag M), which balances the two off-diagonal blocks of J P^-1 (s (I - M M~^-1) C S~^-1
  // against B M^-1 / s): with |diag K^L| / |diag M| itself the residual of the loose M~ swamped
  // the iteration (no convergence in 1000 iterations).
  const auto start = std::chrono::steady_clock::now();
  const LocalIndex nn = mesh_.numNodes();
  if (fresh_) {
    setupSchurPreconditioner();
    Vec da("mixcon::nonlinear::diagA", kDisp * nn), dm("mixcon::nonlinear::diagM", kStress * nn);
    fieldDiagonal(precMatrix_, 1, 0, 1, da, 1.0); // K^L: A alone is 0 at a = 0 without stress
    if (matrixFree_)
      fieldDiagonal(stressBlock_, kStress, 0, kStress, dm, 1.0);
    else
      fieldDiagonal(tangent_, kMixed, kStressAt, kStress, dm, -1.0);
    stressRowScale_ = blockTriangularScale(ConstVec(da), ConstVec(dm));
    // C = J_tau,u on its own (6/25 of J's entries; the tau rows of J hold 15/25).
    if (couplingBlock_.numRows == 0) {
      couplingBlock_ = expandGraph<Memory>(graph_, kStress, kDisp);
      precDiag5_ = Vec("mixcon::nonlinear::precDiagonal5", kMixed * nn);
    }
    scatter<double>(ConstVec(precDiag_), kMixed, 0, kDisp, precDiag5_, true);
    if (!matrixFree_) // matrix-free: assembled on its own in evaluate()
      extractFieldBlock(tangent_, kMixed, kStressAt, kStress, 0, kDisp, couplingBlock_, 1.0);
  }
  SaddlePointSystem system;
  system.jacobian = [&](const ConstDeviceVector &v, const DeviceVector &y) { applyJacobian(v, y); };
  system.schurPreconditioner = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    solver_->precondition(r, y);
  };
  system.coupling = [&](const ConstDeviceVector &v, const DeviceVector &w) {
    multiply(Exec(), couplingBlock_, v, w);
  };
  system.stressSolve = [&](const ConstDeviceVector &w, const DeviceVector &z, double tolerance) {
    return solveStressBlock(w, z, tolerance, mixedOptions_.preconditionerTolerance);
  };
  system.stressTolerance = mixedOptions_.preconditionerTolerance;
  system.constrained = constrained5_;
  system.constrainedDisplacement = isConstrained_;
  system.constrainedDiagonal = precDiag5_;
  system.stressRowScale = stressRowScale_;
  // f = -G; the prescribed rows reach target_, the remaining prescribed step.
  Vec f(Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::nonlinear::negativeResidual"),
        kMixed * nn);
  axpby(-1.0, g_, 0.0, f);
  KrylovOptions ko;
  ko.tolerance = linearOptions_.tolerance;
  ko.backwardErrorFloor = true; // slender parts: the relative residual has a floor
  ko.maxIterations = solver_->iterationsPerAttempt(linearOptions_.maxIterations);
  ko.restart = mixedOptions_.restart;
  long inner = 0;
  const KrylovStats ks =
      blockTriangularSolve(system, ko, ConstVec(f), ConstVec(target_), dx_, inner, &outerWork_);
  innerIterations_ = inner;
  return statsOf(ks, start);
}

} // namespace mixcon
