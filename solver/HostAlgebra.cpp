// Host direct solves with Eigen (solver/HostAlgebra.hpp).
#include <solver/HostAlgebra.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

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

struct HostSparseLu::Impl {
  Eigen::SparseMatrix<double> matrix;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
};

HostSparseLu::HostSparseLu() : impl_(std::make_unique<Impl>()) {}
HostSparseLu::~HostSparseLu() = default;

bool HostSparseLu::factor(std::int64_t n, const std::vector<SparseEntry> &entries) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(entries.size());
  for (const SparseEntry &e : entries)
    t.emplace_back(e.row, e.column, e.value);
  impl_->matrix.resize(n, n);
  impl_->matrix.setFromTriplets(t.begin(), t.end());
  impl_->lu.analyzePattern(impl_->matrix);
  impl_->lu.factorize(impl_->matrix);
  return impl_->lu.info() == Eigen::Success;
}

double HostSparseLu::solve(const std::vector<double> &b, std::vector<double> &x) const {
  const Eigen::Map<const Eigen::VectorXd> rhs(b.data(), static_cast<Eigen::Index>(b.size()));
  const Eigen::VectorXd solution = impl_->lu.solve(rhs);
  x.assign(solution.data(), solution.data() + solution.size());
  const double bn = rhs.norm();
  return bn > 0 ? (impl_->matrix * solution - rhs).norm() / bn : 0.0;
}

} // namespace mixcon
