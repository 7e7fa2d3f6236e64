// blockTriangularSolve: flexible GMRES on a mixed saddle-point system with the block
// lower-triangular preconditioner (solver/BlockTriangular.hpp). Layer: solver.
#include <solver/BlockTriangular.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mixcon {

using namespace fieldops;

double blockTriangularScale(const ConstDeviceVector &diagonalSchur,
                            const ConstDeviceVector &diagonalStress) {
  const double na = std::sqrt(dot(diagonalSchur, diagonalSchur));
  const double nm = std::sqrt(dot(diagonalStress, diagonalStress));
  // the ratio of the rms values: the norms' ratio times sqrt(stress entries / displacement ones)
  const double entries = static_cast<double>(diagonalStress.extent(0)) /
                         static_cast<double>(std::max<std::size_t>(1, diagonalSchur.extent(0)));
  return nm > 0.0 ? std::sqrt(na / nm * std::sqrt(entries)) : 1.0;
}

double stressSolveTolerance(double loosest, double displacementResidual, double stressRhs,
                            double stressRowScale) {
  const double ratio = displacementResidual / (stressRowScale * stressRhs);
  if (!(ratio >= 0.0) || !std::isfinite(ratio))
    return loosest; // w = 0 (the solve returns z = 0 at any tolerance), or not a number
  return std::max(std::min(kTightestStressTolerance, loosest),
                  std::min(loosest, kStressToleranceMargin * ratio));
}

LinearSolveStats statsOf(const KrylovStats &ks, std::chrono::steady_clock::time_point start,
                         double setupSeconds) {
  LinearSolveStats s;
  s.iterations = ks.iterations;
  s.relativeResidual = ks.relativeResidual;
  s.converged = ks.converged;
  s.setupSeconds = setupSeconds;
  s.solveSeconds = seconds(start);
  return s;
}

long stressBlockSolve(const LinearMap &apply, const LinearMap &precondition,
                      const ConstDeviceVector &w, const DeviceVector &z, double tolerance,
                      KrylovWorkspace &workspace, const std::string &who, double acceptable) {
  KrylovOptions o;
  o.tolerance = tolerance;
  o.maxIterations = 2000;
  o.exactOperator = true; // M applied exactly: no true-residual product at start and end
  Kokkos::deep_copy(z, 0.0);
  const KrylovStats st = krylovSolve(o, apply, precondition, w, z, &workspace);
  if (!st.converged && !(st.relativeResidual <= acceptable))
    throw std::runtime_error(who +
                             ": the CG on the stress block did not converge (relative "
                             "residual " +
                             std::to_string(st.relativeResidual) + ")");
  return st.iterations;
}

KrylovStats blockTriangularSolve(const SaddlePointSystem &system, const KrylovOptions &options,
                                 const ConstDeviceVector &f, const ConstDeviceVector &target,
                                 const DeviceVector &x, long &inner, KrylovWorkspace *workspace) {
  // With M~ = M, J P^-1 = [S S~^-1, -B M^-1; 0, I] and the iterations are those of the Schur
  // solve; a loose M~ costs a few more outer iterations but no tight inner solve per product.
  const int nd = system.displacements, ns = system.stresses, nu = nd + ns;
  const std::size_t nn = x.extent(0) / nu;
  const double scale = system.stressRowScale;
  const auto work = [](const char *label, std::size_t n) {
    return Vec(Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string(label)), n);
  };
  // Work vectors, each fully written before it is read.
  Vec masked = work("mixcon::blockTriangular::masked", nu * nn),
      r2 = work("mixcon::blockTriangular::r2", nd * nn),
      y2 = work("mixcon::blockTriangular::y2", nd * nn),
      w = work("mixcon::blockTriangular::w", ns * nn),
      t = work("mixcon::blockTriangular::t", ns * nn),
      z = work("mixcon::blockTriangular::z", ns * nn);
  const auto &flags = system.constrained;
  const auto &diag = system.constrainedDiagonal;
  // y = D (P J P + D_c) v, D scaling the stress rows.
  const LinearMap op = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    maskConstrained(Exec(), flags, v, masked);
    system.jacobian(ConstVec(masked), y);
    finishConstrained(Exec(), flags, diag, v, y);
    scaleField(y, nu, nd, ns, scale);
  };
  // y = P^-1 D^-1 r: y_u = S~^-1 r_u, y_tau = M~^-1 (C P y_u - r_tau / s).
  const LinearMap prec = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    gather(r, nu, 0, nd, r2);
    const double displacementResidual = std::sqrt(dot(ConstVec(r2), ConstVec(r2)));
    system.schurPreconditioner(r2, y2);
    scatter<double>(y2, nu, 0, nd, y, true);
    maskConstrained(Exec(), system.constrainedDisplacement, ConstVec(y2), r2);
    system.coupling(ConstVec(r2), w);
    gather(r, nu, nd, ns, t, 1.0 / scale);
    axpby(-1.0, t, 1.0, w);
    const double tolerance = stressSolveTolerance(system.stressTolerance, displacementResidual,
                                                  std::sqrt(dot(ConstVec(w), ConstVec(w))), scale);
    inner += system.stressSolve(w, z, tolerance);
    scatter<double>(z, nu, nd, ns, y, false);
  };
  // b = D (P (f - J g) + D_c g), g the prescribed values.
  Vec jg = work("mixcon::blockTriangular::jg", nu * nn),
      b = work("mixcon::blockTriangular::rhs", nu * nn);
  system.jacobian(target, jg);
  constrainedRhs(Exec(), flags, diag, f, target, ConstVec(jg), b);
  scaleField(b, nu, nd, ns, scale);
  KrylovOptions ko = options;
  ko.method = KrylovMethod::Gmres;
  Kokkos::deep_copy(x, 0.0);
  return krylovSolve(ko, op, prec, ConstVec(b), x, workspace);
}

} // namespace mixcon
