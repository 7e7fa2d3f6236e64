// Host direct solves with Eigen (solver/HostAlgebra.hpp).
#include <solver/HostAlgebra.hpp>
#include <solver/SparseDirect.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace mixcon {

bool solveSmallDense(const std::vector<double> &a, std::size_t n, const std::vector<double> &b,
                     std::vector<double> &x, double threshold) {
  const auto size = static_cast<Eigen::Index>(n);
  const Eigen::MatrixXd m =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          a.data(), size, size);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(m);
  lu.setThreshold(threshold);
  if (!lu.isInvertible())
    return false;
  const Eigen::VectorXd solution = lu.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), size));
  x.assign(solution.data(), solution.data() + size);
  return true;
}

bool invertSmallDense(const std::vector<double> &a, std::size_t n, std::vector<double> &inverse,
                      double threshold) {
  const auto size = static_cast<Eigen::Index>(n);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::PartialPivLU<RowMajor> lu(Eigen::Map<const RowMajor>(a.data(), size, size));
  if (size > 0) {
    const Eigen::VectorXd pivots = lu.matrixLU().diagonal().cwiseAbs();
    if (!(pivots.minCoeff() > threshold * pivots.maxCoeff()))
      return false;
  }
  inverse.resize(n * n);
  Eigen::Map<RowMajor>(inverse.data(), size, size) = lu.inverse();
  return true;
}

struct HostSparseLu::Impl {
  SparseDirect lu;
  Eigen::Index n = 0;
};

HostSparseLu::HostSparseLu() : impl_(std::make_unique<Impl>()) {}
HostSparseLu::~HostSparseLu() = default;

bool HostSparseLu::factor(std::int64_t n, const std::vector<SparseEntry> &entries) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(entries.size());
  for (const SparseEntry &e : entries)
    t.emplace_back(e.row, e.column, e.value);
  Eigen::SparseMatrix<double, Eigen::RowMajor> matrix(n, n);
  matrix.setFromTriplets(t.begin(), t.end()); // sums duplicates
  matrix.makeCompressed();
  std::vector<Offset> rows;
  impl_->n = n;
  return impl_->lu.factor(SparseDirect::Method::Lu, hostCsr(matrix, rows)) ==
         SparseDirect::Outcome::Factored;
}

double HostSparseLu::solve(const std::vector<double> &b, std::vector<double> &x) const {
  x.assign(b.size(), 0.0);
  const double bn = Eigen::Map<const Eigen::VectorXd>(b.data(), impl_->n).norm();
  // Iterative refinement with the same factors while it gains (UMFPACK's own is off,
  // solver/SparseDirect.cpp): at most two steps.
  const double rn = impl_->lu.solveRefined(b.data(), x.data(), 2, 1e-14 * bn);
  return bn > 0 ? rn / bn : 0.0;
}

} // namespace mixcon
