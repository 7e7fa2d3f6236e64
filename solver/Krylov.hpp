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
  /// CG only (GMRES ignores it): the operator is applied exactly (an assembled or partially
  /// assembled matrix, no inner iterations), so convergence is judged on CG's recursive residual,
  /// without the final product that recomputes the true one; and a zero start x gives r = b without
  /// a product. For short inner solves (the stress block's CG on M: 3-8 iterations) these are two
  /// of every 5-10 products.
  bool exactOperator = false;
};

struct KrylovStats {
  int iterations = 0;
  /// The true residual recomputed at the end; CG's recursive one with exactOperator.
  double relativeResidual = 0.0;
  bool converged = false;
};

/// Krylov basis vectors as the columns of one block (n rows, LayoutLeft: each column contiguous),
/// so that GMRES's orthogonalization and its solution update read all of them in one pass.
using DeviceBlock = Kokkos::View<double **, Kokkos::LayoutLeft, DeviceSpace>;

namespace detail {

/// The fused block operations of GMRES (classical Gram-Schmidt and the solution update), each
/// one pass over the block's columns, with the few coefficients on the host. Against the
/// 2 (k + 1) + 1 dot and axpy kernels (5 (k + 1) + 1 vector passes) of modified Gram-Schmidt
/// per GMRES iteration: 2 reductions and 2k + 5 passes, twice that where the second pass runs,
/// and one more reduction per 15 columns past the first 15.
class BlockOps {
public:
  /// h[j] = V(:, j) . w for j < k; returns w . w (the same pass). h has at least k entries.
  double dots(const DeviceBlock &v, int k, const ConstDeviceVector &w, std::vector<double> &h);
  /// w -= V(:, 0:k) c; returns w . w after the update (the same pass).
  double subtract(const DeviceBlock &v, int k, const std::vector<double> &c, const DeviceVector &w);
  /// x += V(:, 0:k) c.
  void add(const DeviceBlock &v, int k, const std::vector<double> &c, const DeviceVector &x);
  /// Orthogonalizes w against the orthonormal columns V(:, 0:k) by classical Gram-Schmidt,
  /// repeated once where the first pass left less than 1/sqrt(2) of ||w|| (Daniel, Gragg,
  /// Kaufman, Stewart 1976; "twice is enough": Giraud et al. 2005, Numer. Math. 101); h[0:k]
  /// receives the coefficients. Returns ||w||.
  double orthogonalize(const DeviceBlock &v, int k, const DeviceVector &w, std::vector<double> &h);
  /// How many second passes orthogonalize() took so far.
  long reorthogonalizations() const { return reorthogonalizations_; }

private:
  Kokkos::View<double *, DeviceSpace> coefficients(const std::vector<double> &c, int k);

  Kokkos::View<double *, DeviceSpace> coefficients_;
  std::vector<double> second_;
  long reorthogonalizations_ = 0;
};

} // namespace detail

/// Work vectors kept from one solve to the next. A Krylov method called many times (an inner
/// solve inside a preconditioner) otherwise allocates its vectors on every call, and the
/// operating system zero-fills every fresh page: at 1e6 elements that was a fifth of the time.
class KrylovWorkspace {
public:
  /// The i-th work vector, of length n (reallocated when n changes).
  DeviceVector get(std::size_t i, std::size_t n);
  /// The i-th block of n rows with at least `columns` columns (at most `limit`: a block grows by
  /// doubling, so its memory follows the iterations taken, within 2x). Growing keeps the contents
  /// of its first `keep` columns; a new n discards them.
  DeviceBlock block(std::size_t i, std::size_t n, std::size_t columns, std::size_t limit,
                    std::size_t keep);
  /// The block operations with their coefficient buffer, kept like the vectors.
  detail::BlockOps &blockOps() { return blockOps_; }

private:
  std::vector<DeviceVector> vectors_;
  std::vector<DeviceBlock> blocks_;
  detail::BlockOps blockOps_;
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
