// Sparse direct factorizations on the host with SuiteSparse: CHOLMOD's Cholesky (supernodal
// where the factor is dense enough, the choice CHOLMOD makes) for symmetric positive definite
// matrices and UMFPACK's LU for any square one. Behind a plain interface: SuiteSparse's headers
// stay in SparseDirect.cpp. Host memory and host code only (never called from a kernel). Data
// flow: the direct solver (LinearSolver.cpp), the rigid-body coarse space (RigidCoarseSpace.cpp)
// and HostSparseLu (HostAlgebra.cpp) -> SparseDirect -> SuiteSparse.
#pragma once

#include <core/Compat.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace mixcon {

/// A square matrix in compressed rows on the host (0-based; columns within a row in any order,
/// no duplicates), borrowed for the duration of one call.
struct HostCsr {
  std::int64_t size = 0;
  const Offset *rowOffsets = nullptr; ///< size + 1
  const LocalIndex *columns = nullptr;
  const double *values = nullptr;
};

/// A compressed row-major matrix with int row offsets (an Eigen::SparseMatrix<double,
/// Eigen::RowMajor> after makeCompressed(): anything with rows(), outerIndexPtr(),
/// innerIndexPtr() and valuePtr()) as a HostCsr: the offsets are widened to Offset in `rows`,
/// which, like `m`, must outlive the result.
template <class RowMajorSparse>
HostCsr hostCsr(const RowMajorSparse &m, std::vector<Offset> &rows) {
  rows.assign(m.outerIndexPtr(), m.outerIndexPtr() + m.rows() + 1);
  return HostCsr{static_cast<std::int64_t>(m.rows()), rows.data(), m.innerIndexPtr(), m.valuePtr()};
}

class SparseDirect {
public:
  enum class Method { Cholesky, Lu };
  enum class Outcome {
    Factored,
    NotPositiveDefinite, ///< Cholesky only: a pivot was not positive (indefinite or singular)
    Singular             ///< LU only: an exactly zero pivot
  };

  SparseDirect();
  ~SparseDirect();
  SparseDirect(const SparseDirect &) = delete;
  SparseDirect &operator=(const SparseDirect &) = delete;

  /// Factors `a` (copied). Cholesky reads one triangle of it (give the whole symmetric matrix:
  /// residual() multiplies with every entry given). The fill-
  /// reducing ordering and symbolic analysis are kept and reused by the next factor() with the
  /// same method and the same pattern (a Newton or contact correction), only the numbers are
  /// factored again. Throws std::runtime_error when SuiteSparse fails otherwise (out of memory).
  Outcome factor(Method method, const HostCsr &a);
  /// x = A^-1 b for the last matrix factored (b and x `size` long, distinct). Not reentrant:
  /// the solves share one workspace (one thread at a time per SparseDirect).
  void solve(const double *b, double *x) const;
  /// r = b - A x with the last matrix factored; returns ||r||_2.
  double residual(const double *b, const double *x, double *r) const;
  /// x = A^-1 b, then up to `steps` steps of iterative refinement with the same factors while
  /// ||b - A x||_2 > `target`, each kept only if it lowers that residual. Returns ||b - A x||_2
  /// of the x returned. Not reentrant, as solve().
  double solveRefined(const double *b, double *x, int steps, double target) const;
  /// The smallest pivot magnitude over the largest of the last factorization: Cholesky
  /// (min L_ii / max L_ii)^2 (min |D_ii| / max |D_ii| for its LDL^T form), LU UMFPACK's
  /// min |U_ii| / max |U_ii|. Near round-off: singular to working precision.
  double pivotRatio() const;
  Method method() const { return method_; }
  /// How many factorizations reused the kept analysis (for the notes and tests).
  int analysisReuses() const { return reuses_; }
  /// Whether the BLAS SuiteSparse calls is an OpenBLAS whose threads factor() and solve() hold
  /// to one for their duration (and restore after), see SparseDirect.cpp.
  static bool controlsBlasThreads();
  /// "CHOLMOD Cholesky" or "UMFPACK LU".
  static const char *name(Method method);
  /// Whether `a` is symmetric to round-off: every |a_ij - a_ji| at most `relative` times the
  /// larger of the two, or at most `absolute` (an absent entry counts as 0). Stops at the first
  /// pair that is not; binary search in rows whose columns are sorted.
  static bool isSymmetric(const HostCsr &a, double relative, double absolute);

  /// What a Cholesky factorization of a matrix of `a`'s pattern would cost, from CHOLMOD's
  /// symbolic analysis with AMD's ordering (the values are not read; the pattern is taken as
  /// symmetric, its lower triangle read): the floating-point operations of the numeric
  /// factorization and the entries of the factor L. The analysis is not kept. Throws
  /// std::runtime_error when CHOLMOD fails (out of memory).
  struct Estimate {
    double flops = 0.0;
    double factorEntries = 0.0;
  };
  static Estimate estimateCholesky(const HostCsr &a);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Method method_ = Method::Cholesky;
  int reuses_ = 0;
};

} // namespace mixcon
