// RigidCoarseSpace: aggregates, the smoothed rigid-body prolongator and its Galerkin operator.
#include <core/Transfer.hpp>
#include <solver/RigidCoarseSpace.hpp>
#include <solver/RigidRotation.hpp>
#include <solver/SparseDirect.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>

namespace mixcon {

namespace {
using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
/// Below this fraction of its norm before the projection a mode of an aggregate depends on the
/// ones kept (a rotation of a single free node, of collinear nodes) and is dropped.
constexpr double kDependentMode = 1e-8;
/// Power iterations for the largest eigenvalue of D^-1 A (the Jacobi smoothing's damping).
constexpr int kPowerIterations = 20;
} // namespace

std::vector<int> aggregateNodes(const std::vector<Offset> &rowOffsets,
                                const std::vector<LocalIndex> &columns) {
  const LocalIndex n = static_cast<LocalIndex>(rowOffsets.size()) - 1;
  std::vector<int> agg(n, -1);
  int count = 0;
  for (LocalIndex k = 0; k < n; ++k) { // 1: nodes whose neighbourhood is wholly free
    bool free = agg[k] < 0;
    for (Offset j = rowOffsets[k]; j < rowOffsets[k + 1] && free; ++j)
      free = agg[columns[j]] < 0;
    if (!free)
      continue;
    agg[k] = count;
    for (Offset j = rowOffsets[k]; j < rowOffsets[k + 1]; ++j)
      agg[columns[j]] = count;
    ++count;
  }
  const std::vector<int> first = agg;
  for (LocalIndex k = 0; k < n; ++k) // 2: the rest join a neighbouring aggregate of step 1
    for (Offset j = rowOffsets[k]; j < rowOffsets[k + 1] && agg[k] < 0; ++j)
      agg[k] = first[columns[j]];
  for (LocalIndex k = 0; k < n; ++k) { // 3: none next to them: their own, with free neighbours
    if (agg[k] >= 0)
      continue;
    agg[k] = count;
    for (Offset j = rowOffsets[k]; j < rowOffsets[k + 1]; ++j)
      if (agg[columns[j]] < 0)
        agg[columns[j]] = count;
    ++count;
  }
  return agg;
}

struct RigidCoarseSpace::Factors {
  RowMatrix p;
  SparseDirect coarse; ///< Cholesky of P^T A P for a symmetric A, LU otherwise (an exact tangent)
};

RigidCoarseSpace::RigidCoarseSpace(const CsrMatrix<DeviceSpace> &a,
                                   const Kokkos::View<const double **, DeviceSpace> &positions,
                                   long maxSize, bool symmetric)
    : factors_(std::make_unique<Factors>()) {
  const int dim = static_cast<int>(positions.extent(1));
  const LocalIndex nodes = static_cast<LocalIndex>(positions.extent(0));
  const LocalIndex n = a.numRows;
  if ((dim != 2 && dim != 3) || static_cast<long>(nodes) * dim != n) {
    why_ = "the rigid-body coarse space needs 2 or 3 displacement unknowns per node";
    return;
  }
  const auto ro = hostReadable(a.rowOffsets);
  const auto co = hostReadable(a.columns);
  const auto va = hostReadable(a.values);
  const auto x = hostReadable(positions);

  // Which rows are prescribed (no off-diagonal value left, solver/Dirichlet.hpp).
  std::vector<char> prescribed(n, 1);
  for (LocalIndex i = 0; i < n; ++i)
    for (Offset k = ro(i); k < ro(i + 1) && prescribed[i]; ++k)
      if (co(k) != i && va(k) != 0.0)
        prescribed[i] = 0;

  // Aggregates of the node graph (the blocks of the first unknown of each node).
  std::vector<Offset> graphRows(nodes + 1, 0);
  std::vector<LocalIndex> graphColumns;
  for (LocalIndex k = 0; k < nodes; ++k) {
    for (Offset j = ro(dim * k); j < ro(dim * k + 1); ++j)
      if (co(j) % dim == 0 && co(j) / dim != k)
        graphColumns.push_back(co(j) / dim);
    graphRows[k + 1] = static_cast<Offset>(graphColumns.size());
  }
  const std::vector<int> agg = aggregateNodes(graphRows, graphColumns);
  aggregates_ = agg.empty() ? 0 : *std::max_element(agg.begin(), agg.end()) + 1;
  std::vector<std::vector<LocalIndex>> members(aggregates_);
  for (LocalIndex k = 0; k < nodes; ++k)
    members[agg[k]].push_back(k);

  // The tentative prolongator: per aggregate, its free unknowns' rigid-body modes about its
  // centroid (translations; rotations: 2D about z, 3D about x, y, z), orthonormalized.
  const int modes = dim + rigidRotations(dim);
  std::vector<Eigen::Triplet<double>> t;
  for (const auto &m : members) {
    double c[3] = {0.0, 0.0, 0.0};
    for (LocalIndex k : m)
      for (int d = 0; d < dim; ++d)
        c[d] += x(k, d) / static_cast<double>(m.size());
    std::vector<LocalIndex> rows;
    for (LocalIndex k : m)
      for (int d = 0; d < dim; ++d)
        if (!prescribed[dim * k + d])
          rows.push_back(dim * k + d);
    if (rows.empty())
      continue;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), modes);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const LocalIndex k = rows[r] / dim;
      const int d = rows[r] % dim;
      const double p[3] = {x(k, 0) - c[0], x(k, 1) - c[1], dim == 3 ? x(k, 2) - c[2] : 0.0};
      b(r, d) = 1.0;
      for (int rot = 0; rot < rigidRotations(dim); ++rot)
        b(r, dim + rot) = rigidRotation(dim, rot, d, p);
    }
    for (int j = 0; j < modes; ++j) { // modified Gram-Schmidt, dependent modes dropped
      const double before = b.col(j).norm();
      for (int i = 0; i < j; ++i)
        if (b.col(i).squaredNorm() > 0.0)
          b.col(j) -= b.col(i).dot(b.col(j)) * b.col(i);
      const double after = b.col(j).norm();
      if (!(before > 0.0) || after <= kDependentMode * before) {
        b.col(j).setZero();
        continue;
      }
      b.col(j) /= after;
      for (std::size_t r = 0; r < rows.size(); ++r)
        t.emplace_back(rows[r], size_, b(r, j));
      ++size_;
    }
  }
  if (size_ > maxSize) {
    why_ = "the rigid-body coarse space would have " + std::to_string(size_) +
           " unknowns, more than " + std::to_string(maxSize);
    return;
  }
  RowMatrix pt(n, size_);
  pt.setFromTriplets(t.begin(), t.end());
  t.clear();
  t.reserve(static_cast<std::size_t>(ro(n))); // the matrix for Eigen, past the size check
  for (LocalIndex i = 0; i < n; ++i)
    for (Offset k = ro(i); k < ro(i + 1); ++k)
      t.emplace_back(i, co(k), va(k));
  RowMatrix am(n, n);
  am.setFromTriplets(t.begin(), t.end());

  // One damped Jacobi step: P = (I - omega D^-1 A) P_t, omega = 4 / (3 lambda_max(D^-1 A)).
  const Eigen::VectorXd dinv = am.diagonal().cwiseInverse();
  Eigen::VectorXd v(n);
  for (LocalIndex i = 0; i < n; ++i)
    v(i) = 1.0 + 0.5 * std::sin(1.0 + i); // deterministic, rich in every mode
  double lambda = 1.0;
  for (int it = 0; it < kPowerIterations; ++it) {
    Eigen::VectorXd w = dinv.cwiseProduct(am * v);
    lambda = w.norm() / v.norm();
    v = w / w.norm();
  }
  const double omega = 4.0 / (3.0 * lambda);
  const Eigen::VectorXd scale = omega * dinv;
  const RowMatrix ap = scale.asDiagonal() * (am * pt);
  factors_->p = pt - ap;
  factors_->p.prune(0.0);
  RowMatrix ac = factors_->p.transpose() * (am * factors_->p);
  ac.makeCompressed();
  bool singular = size_ == 0;
  if (!singular) {
    std::vector<Offset> acRows;
    const HostCsr csr = hostCsr(ac, acRows);
    const auto method = symmetric ? SparseDirect::Method::Cholesky : SparseDirect::Method::Lu;
    // Symmetric: a pivot <= 0 or at round-off relative to the largest is not definite.
    singular = factors_->coarse.factor(method, csr) != SparseDirect::Outcome::Factored ||
               (symmetric && !(factors_->coarse.pivotRatio() > 1e-14));
  }
  if (singular)
    why_ = symmetric ? "the rigid-body coarse operator is not positive definite (a part without "
                       "supports, or a compressive prestress)"
                     : "the rigid-body coarse operator is singular (a part without supports?)";
}

RigidCoarseSpace::~RigidCoarseSpace() = default;

void RigidCoarseSpace::apply(const double *r, double *z) const {
  const auto n = factors_->p.rows();
  const Eigen::Map<const Eigen::VectorXd> er(r, n);
  const Eigen::VectorXd pr = factors_->p.transpose() * er;
  Eigen::VectorXd c(pr.size());
  factors_->coarse.solve(pr.data(), c.data());
  Eigen::Map<Eigen::VectorXd>(z, n) = factors_->p * c;
}

void RigidCoarseSpace::prolongator(std::vector<Offset> &rowOffsets,
                                   std::vector<LocalIndex> &columns,
                                   std::vector<double> &values) const {
  const RowMatrix &p = factors_->p;
  rowOffsets.assign(p.rows() + 1, 0);
  columns.clear();
  values.clear();
  for (Eigen::Index i = 0; i < p.rows(); ++i) {
    for (RowMatrix::InnerIterator it(p, i); it; ++it) {
      columns.push_back(static_cast<LocalIndex>(it.col()));
      values.push_back(it.value());
    }
    rowOffsets[i + 1] = static_cast<Offset>(columns.size());
  }
}

} // namespace mixcon
