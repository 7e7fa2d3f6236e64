// blockTriangularSolve: flexible GMRES on a mixed saddle-point system with the block
// lower-triangular preconditioner (solver/BlockTriangular.hpp). Layer: solver.
#include <solver/BlockTriangular.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>

#include <cmath>
#include <string>

namespace mixcon {

using namespace fieldops;

double blockTriangularScale(const ConstDeviceVector &diagonalSchur,
                            const ConstDeviceVector &diagonalStress) {
  const double na = std::sqrt(dot(diagonalSchur, diagonalSchur));
  const double nm = std::sqrt(dot(diagonalStress, diagonalStress));
  // rms over kDisp and kStress entries per node: the norms' ratio times sqrt(kStress / kDisp)
  const double perNode = std::sqrt(static_cast<double>(kStress) / kDisp);
  return nm > 0.0 ? std::sqrt(na / nm * perNode) : 1.0;
}

KrylovStats blockTriangularSolve(const SaddlePointSystem &system, const KrylovOptions &options,
                                 const ConstDeviceVector &f, const ConstDeviceVector &target,
                                 const DeviceVector &x, long &inner, KrylovWorkspace *workspace) {
  // With M~ = M, J P^-1 = [S S~^-1, -B M^-1; 0, I] and the iterations are those of the Schur
  // solve; a loose M~ costs a few more outer iterations but no tight inner solve per product.
  const std::size_t nn = x.extent(0) / kMixed;
  const double scale = system.stressRowScale;
  const auto work = [](const char *label, std::size_t n) {
    return Vec(Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string(label)), n);
  };
  // Work vectors, each fully written before it is read.
  Vec masked = work("mixcon::blockTriangular::masked5", kMixed * nn),
      r2 = work("mixcon::blockTriangular::r2", kDisp * nn),
      y2 = work("mixcon::blockTriangular::y2", kDisp * nn),
      w = work("mixcon::blockTriangular::w", kStress * nn),
      t = work("mixcon::blockTriangular::t", kStress * nn),
      z = work("mixcon::blockTriangular::z", kStress * nn);
  const auto &flags = system.constrained;
  const auto &diag = system.constrainedDiagonal;
  // y = D (P J P + D_c) v, D scaling the stress rows.
  const LinearMap op = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    maskConstrained(Exec(), flags, v, masked);
    system.jacobian(ConstVec(masked), y);
    finishConstrained(Exec(), flags, diag, v, y);
    scaleField(y, kMixed, kStressAt, kStress, scale);
  };
  // y = P^-1 D^-1 r: y_u = S~^-1 r_u, y_tau = M~^-1 (C P y_u - r_tau / s).
  const LinearMap prec = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    gather(r, kMixed, 0, kDisp, r2);
    system.schurPreconditioner(r2, y2);
    scatter<double>(y2, kMixed, 0, kDisp, y, true);
    maskConstrained(Exec(), system.constrainedDisplacement, ConstVec(y2), r2);
    system.coupling(ConstVec(r2), w);
    gather(r, kMixed, kStressAt, kStress, t, 1.0 / scale);
    axpby(-1.0, t, 1.0, w);
    inner += system.stressSolve(w, z);
    scatter<double>(z, kMixed, kStressAt, kStress, y, false);
  };
  // b = D (P (f - J g) + D_c g), g the prescribed values.
  Vec jg = work("mixcon::blockTriangular::jg", kMixed * nn),
      b = work("mixcon::blockTriangular::rhs5", kMixed * nn);
  system.jacobian(target, jg);
  constrainedRhs(Exec(), flags, diag, f, target, ConstVec(jg), b);
  scaleField(b, kMixed, kStressAt, kStress, scale);
  KrylovOptions ko = options;
  ko.method = KrylovMethod::Gmres;
  Kokkos::deep_copy(x, 0.0);
  return krylovSolve(ko, op, prec, ConstVec(b), x, workspace);
}

} // namespace mixcon
