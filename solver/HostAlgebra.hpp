// Dense and sparse direct solves on the host (Eigen's dense LU and SuiteSparse's UMFPACK behind a
// plain interface), for the small systems of the force-driven obstacles, the mixed model's
// direct saddle-point solve and the coarsest level of mixcon's AMG V-cycle. Eigen
// stays in HostAlgebra.cpp, out of every translation unit with device code (ctest
// repo.eigen_host_only): under nvcc it would be compiled as device code too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace mixcon {

/// x = a^-1 b for a small dense n x n `a` (row-major), LU with full pivoting. Returns false, x
/// untouched, when `a` is singular by Eigen's FullPivLU rank test with `threshold` (relative to
/// the largest pivot).
bool solveSmallDense(const std::vector<double> &a, std::size_t n, const std::vector<double> &b,
                     std::vector<double> &x, double threshold = 1e-10);

/// The inverse of a dense n x n `a` (row-major, into `inverse`, row-major), LU with partial
/// pivoting (up to a few thousand rows: the coarsest AMG level of solver/AmgCycle.hpp). Returns
/// false, `inverse` untouched, where a pivot is at most `threshold` times the largest.
bool invertSmallDense(const std::vector<double> &a, std::size_t n, std::vector<double> &inverse,
                      double threshold);

/// One entry of a sparse matrix given by coordinates; entries at the same place are summed.
struct SparseEntry {
  std::int64_t row, column;
  double value;
};

/// Sparse LU (UMFPACK, solver/SparseDirect.hpp) of an n x n matrix given by its entries.
class HostSparseLu {
public:
  HostSparseLu();
  ~HostSparseLu();
  HostSparseLu(const HostSparseLu &) = delete;
  HostSparseLu &operator=(const HostSparseLu &) = delete;

  /// Factors the matrix; false when it is singular.
  bool factor(std::int64_t n, const std::vector<SparseEntry> &entries);
  /// x = A^-1 b; returns ||A x - b|| / ||b|| (0 for b = 0).
  double solve(const std::vector<double> &b, std::vector<double> &x) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace mixcon
