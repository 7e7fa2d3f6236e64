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
  const std::vector<Offset> rows(matrix.outerIndexPtr(), matrix.outerIndexPtr() + n + 1);
  impl_->n = n;
  return impl_->lu.factor(SparseDirect::Method::Lu,
                          HostCsr{n, rows.data(), matrix.innerIndexPtr(), matrix.valuePtr()}) ==
         SparseDirect::Outcome::Factored;
}

double HostSparseLu::solve(const std::vector<double> &b, std::vector<double> &x) const {
  x.assign(b.size(), 0.0);
  impl_->lu.solve(b.data(), x.data());
  std::vector<double> r(b.size()), dx(b.size()), xc(b.size()), rc(b.size());
  double rn = impl_->lu.residual(b.data(), x.data(), r.data());
  const double bn = Eigen::Map<const Eigen::VectorXd>(b.data(), impl_->n).norm();
  // Iterative refinement with the same factors while it gains (UMFPACK's own is off,
  // solver/SparseDirect.cpp): at most two steps.
  for (int step = 0; step < 2 && rn > 1e-14 * bn; ++step) {
    impl_->lu.solve(r.data(), dx.data());
    for (std::size_t i = 0; i < x.size(); ++i)
      xc[i] = x[i] + dx[i];
    const double cn = impl_->lu.residual(b.data(), xc.data(), rc.data());
    if (!(cn < rn))
      break;
    x.swap(xc);
    r.swap(rc);
    rn = cn;
  }
  return bn > 0 ? rn / bn : 0.0;
}

} // namespace mixcon
