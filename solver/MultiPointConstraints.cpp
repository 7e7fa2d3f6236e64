#include <core/Transfer.hpp>
#include <solver/MultiPointConstraints.hpp>

#include <Eigen/SparseCore>

namespace mixcon {

namespace {

using Memory = Kokkos::DefaultExecutionSpace::memory_space;
using SpMat = Eigen::SparseMatrix<double, Eigen::RowMajor, long>;

SpMat transformation(const MultiPointConstraints &c, LocalIndex n) {
  std::vector<char> listed(n, 0);
  std::vector<Eigen::Triplet<double, long>> t;
  t.reserve(n);
  for (std::size_t r = 0; r < c.rows.size(); ++r) {
    listed[c.rows[r]] = 1;
    for (const auto &[col, v] : c.entries[r])
      t.emplace_back(c.rows[r], col, v);
  }
  for (LocalIndex i = 0; i < n; ++i)
    if (!listed[i])
      t.emplace_back(i, i, 1.0);
  SpMat m(n, n);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

SpMat toEigen(const CsrMatrix<Memory> &a) {
  const auto ro = copyToHost(a.rowOffsets);
  const auto co = copyToHost(a.columns);
  const auto va = copyToHost(a.values);
  std::vector<Eigen::Triplet<double, long>> t;
  t.reserve(co.extent(0));
  for (LocalIndex i = 0; i < a.numRows; ++i)
    for (Offset k = ro(i); k < ro(i + 1); ++k)
      t.emplace_back(i, co(k), va(k));
  SpMat m(a.numRows, a.numColumns);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

Eigen::VectorXd offsets(const MultiPointConstraints &c, LocalIndex n) {
  Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
  for (std::size_t r = 0; r < c.rows.size(); ++r)
    s(c.rows[r]) = c.offset[r];
  return s;
}

} // namespace

CsrMatrix<Memory> eliminateConstraints(const CsrMatrix<Memory> &a, const MultiPointConstraints &c,
                                       double slaveDiagonal,
                                       const Kokkos::View<double *, Memory> &rhs) {
  const LocalIndex n = a.numRows;
  const SpMat t = transformation(c, n);
  const SpMat am = toEigen(a);
  // Every diagonal entry present (Dirichlet rows need it), the slaves' set to slaveDiagonal.
  std::vector<Eigen::Triplet<double, long>> dt;
  dt.reserve(n);
  std::vector<char> slave(n, 0);
  for (LocalIndex s : c.slaves)
    slave[s] = 1;
  for (LocalIndex i = 0; i < n; ++i)
    dt.emplace_back(i, i, slave[i] ? slaveDiagonal : 0.0);
  SpMat d(n, n);
  d.setFromTriplets(dt.begin(), dt.end());
  SpMat at = am * t;
  SpMat reduced = SpMat(t.transpose()) * at;
  reduced += d;
  reduced.makeCompressed();

  auto hb = copyToHost(rhs);
  Eigen::Map<Eigen::VectorXd> b(hb.data(), n);
  const Eigen::VectorXd shifted = b - am * offsets(c, n);
  b = t.transpose() * shifted;
  for (LocalIndex s : c.slaves)
    b(s) = 0.0;
  copyToDevice(rhs, hb);

  CsrMatrix<Memory> r;
  r.numRows = r.numColumns = n;
  const Offset nnz = reduced.nonZeros();
  r.rowOffsets = Kokkos::View<Offset *, Memory>("mixcon::mpc::rowOffsets", n + 1);
  r.columns = Kokkos::View<LocalIndex *, Memory>("mixcon::mpc::columns", nnz);
  r.values = Kokkos::View<double *, Memory>("mixcon::mpc::values", nnz);
  auto hr = hostMirror(r.rowOffsets);
  auto hc = hostMirror(r.columns);
  auto hv = hostMirror(r.values);
  for (LocalIndex i = 0; i <= n; ++i)
    hr(i) = reduced.outerIndexPtr()[i];
  for (Offset k = 0; k < nnz; ++k) {
    hc(k) = static_cast<LocalIndex>(reduced.innerIndexPtr()[k]);
    hv(k) = reduced.valuePtr()[k];
  }
  copyToDevice(r.rowOffsets, hr);
  copyToDevice(r.columns, hc);
  copyToDevice(r.values, hv);
  return r;
}

void expandConstrained(const MultiPointConstraints &c, const Kokkos::View<double *, Memory> &x) {
  auto h = copyToHost(x);
  std::vector<double> y(h.data(), h.data() + h.extent(0));
  for (std::size_t r = 0; r < c.rows.size(); ++r) {
    double v = c.offset[r];
    for (const auto &[col, a] : c.entries[r])
      v += a * y[col];
    h(c.rows[r]) = v;
  }
  copyToDevice(x, h);
}

void condenseVector(const MultiPointConstraints &c, std::vector<double> &v) {
  // v <- T^T v: listed rows send their value to their entries' columns, others keep theirs.
  std::vector<double> out(v);
  for (LocalIndex r : c.rows)
    out[r] = 0.0;
  for (std::size_t r = 0; r < c.rows.size(); ++r)
    for (const auto &[col, a] : c.entries[r])
      out[col] += a * v[c.rows[r]];
  for (LocalIndex s : c.slaves)
    out[s] = 0.0;
  v.swap(out);
}

} // namespace mixcon
