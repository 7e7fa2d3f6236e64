// Krylov methods on device vectors for operators that are not (only) assembled matrices: the
// matrix-free Schur complement of the mixed model, preconditioned by one BoomerAMG V-cycle on an
// assembled approximation. Flexible CG (Notay's Polak-Ribiere beta, robust to a slightly variable
// preconditioner or an operator applied with inner iterations) for symmetric positive definite
// operators, and right-preconditioned flexible GMRES(m) for indefinite or nonsymmetric ones
// (K11 of a compressive prestress). Operators are host-side callables that launch device kernels.
// Data flow: solver.
#pragma once

#include <solver/LinearSolver.hpp>

#include <functional>
#include <vector>

namespace mixcon {

using DeviceVector = Kokkos::View<double *, DeviceSpace>;
using ConstDeviceVector = Kokkos::View<const double *, DeviceSpace>;
/// y = Op(x); y must be fully overwritten.
using LinearMap = std::function<void(const ConstDeviceVector &x, const DeviceVector &y)>;

enum class KrylovMethod { Cg, Gmres };

struct KrylovOptions {
  KrylovMethod method = KrylovMethod::Cg;
  double tolerance = 1e-8;  ///< relative residual ||b - A x|| / ||b||
  int maxIterations = 1000; ///< at least 1; krylovSolve throws std::invalid_argument
  int restart = 60;         ///< GMRES restart length
  /// Also stop (converged) at the accuracy floor of floating point: the backward error
  /// ||b - A x|| / (||A|| ||x|| + ||b||) at most kBackwardErrorFloor (LinearSolver.hpp), with ||A||
  /// estimated by ||A w|| / ||w|| for a vector w of pseudo-random signs (one more product per
  /// solve; an underestimate makes the test stricter). For outer solves of systems whose relative
  /// residual cannot reach the tolerance (slender parts, cond(A) ~ (L/h)^4).
  bool backwardErrorFloor = false;
};

struct KrylovStats {
  int iterations = 0;
  double relativeResidual = 0.0; ///< true residual recomputed at the end
  bool converged = false;
};

/// Work vectors kept from one solve to the next. A Krylov method called many times (an inner
/// solve inside a preconditioner) otherwise allocates its vectors on every call, and the
/// operating system zero-fills every fresh page: at 1e6 elements that was a fifth of the time.
class KrylovWorkspace {
public:
  /// The i-th work vector, of length n (reallocated when n changes).
  DeviceVector get(std::size_t i, std::size_t n);

private:
  std::vector<DeviceVector> vectors_;
};

/// Solves A x = b with preconditioner P, starting from the given x; work vectors from
/// `workspace` when given.
KrylovStats krylovSolve(const KrylovOptions &options, const LinearMap &a, const LinearMap &p,
                        const ConstDeviceVector &b, const DeviceVector &x,
                        KrylovWorkspace *workspace = nullptr);

double dot(const ConstDeviceVector &a, const ConstDeviceVector &b);
/// y = A x on the default execution space (compiled here, so that host-library translation
/// units such as the hypre and Eigen solvers launch no kernel of their own).
void multiply(const CsrMatrix<DeviceSpace> &a, const ConstDeviceVector &x, const DeviceVector &y);
/// y = alpha x + beta y
void axpby(double alpha, const ConstDeviceVector &x, double beta, const DeviceVector &y);

} // namespace mixcon
