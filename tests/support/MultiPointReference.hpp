// Plain host reference of the multipoint-constraint elimination (solver/MultiPointConstraints.hpp):
// T assembled as an Eigen sparse matrix from the host description, T^T A T + D and T^T (b - A s)
// by Eigen sparse products, x = T y + s and T^T v. This was the library's own implementation
// before the elimination moved to the device; the device kernels are compared against it.
// Tests only.
#pragma once

#include <solver/MultiPointConstraints.hpp>

#include <Eigen/SparseCore>

#include <vector>

namespace mixcon::test {

using MpcSparse = Eigen::SparseMatrix<double, Eigen::RowMajor, long>;

/// T (n x n): the listed rows, the identity elsewhere.
inline MpcSparse referenceTransformation(const MultiPointConstraints &c, LocalIndex n) {
  std::vector<char> listed(n, 0);
  std::vector<Eigen::Triplet<double, long>> t;
  for (std::size_t r = 0; r < c.rows.size(); ++r) {
    listed[c.rows[r]] = 1;
    for (const auto &[col, v] : c.entries[r])
      t.emplace_back(c.rows[r], col, v);
  }
  for (LocalIndex i = 0; i < n; ++i)
    if (!listed[i])
      t.emplace_back(i, i, 1.0);
  MpcSparse m(n, n);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

/// s (n): the offsets at the listed rows, zero elsewhere.
inline Eigen::VectorXd referenceOffsets(const MultiPointConstraints &c, LocalIndex n) {
  Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
  for (std::size_t r = 0; r < c.rows.size(); ++r)
    s(c.rows[r]) = c.offset[r];
  return s;
}

/// T^T A T + D (every diagonal entry present, D = slaveDiagonal at the slaves) and
/// b <- T^T (b - A s), zero at the slaves.
inline MpcSparse referenceElimination(const MpcSparse &a, const MultiPointConstraints &c,
                                      double slaveDiagonal, Eigen::VectorXd &b) {
  const LocalIndex n = static_cast<LocalIndex>(a.rows());
  const MpcSparse t = referenceTransformation(c, n);
  std::vector<char> slave(n, 0);
  for (LocalIndex s : c.slaves)
    slave[s] = 1;
  std::vector<Eigen::Triplet<double, long>> dt;
  for (LocalIndex i = 0; i < n; ++i)
    dt.emplace_back(i, i, slave[i] ? slaveDiagonal : 0.0);
  MpcSparse d(n, n);
  d.setFromTriplets(dt.begin(), dt.end());
  const MpcSparse at = a * t;
  MpcSparse reduced = MpcSparse(t.transpose()) * at;
  reduced += d;
  reduced.makeCompressed();
  const Eigen::VectorXd shifted = b - a * referenceOffsets(c, n);
  b = t.transpose() * shifted;
  for (LocalIndex s : c.slaves)
    b(s) = 0.0;
  return reduced;
}

/// x = T y + s.
inline Eigen::VectorXd referenceExpand(const MultiPointConstraints &c, const Eigen::VectorXd &y) {
  const LocalIndex n = static_cast<LocalIndex>(y.size());
  return referenceTransformation(c, n) * y + referenceOffsets(c, n);
}

/// T^T v, zero at the slaves.
inline Eigen::VectorXd referenceCondense(const MultiPointConstraints &c, const Eigen::VectorXd &v) {
  Eigen::VectorXd out =
      referenceTransformation(c, static_cast<LocalIndex>(v.size())).transpose() * v;
  for (LocalIndex s : c.slaves)
    out(s) = 0.0;
  return out;
}

} // namespace mixcon::test
