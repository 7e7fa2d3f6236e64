// Master-slave elimination of linear multi-point constraints (solver/MultiPointConstraints.hpp)
// against the host reference: the dense saddle-point (Lagrange multiplier) system
// [A C^T; C 0] [x; lambda] = [b; d] solved with Eigen. Both give the same x, the condensed
// residual T^T (A x - b) vanishes, and the eliminated matrix stays symmetric positive definite.
// The device elimination (T^T A T + D, T^T (b - A s), T y + s, T^T v, the condensed free norm)
// against the Eigen sparse host reference (tests/support/MultiPointReference.hpp) on random SPD
// matrices with random contact-like constraint rows (framed slip rows, stick and single slaves),
// and the reuse of its symbolic phase.
#include <solver/MultiPointConstraints.hpp>
#include <support/KernelFixture.hpp>
#include <support/MultiPointReference.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

using namespace mixcon;

namespace multipoint_tests {

using Memory = Kokkos::DefaultExecutionSpace::memory_space;

using test::toEigen;
using test::toView;

} // namespace multipoint_tests
using namespace multipoint_tests;

TEST(MultiPointConstraints, EliminationEqualsTheLagrangeMultiplierSolution) {
  const int n = 12;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd r(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      r(i, j) = u(rng);
  const Eigen::MatrixXd a = r * r.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i)
    b(i) = u(rng);
  // Unknowns 2, 3 are a "framed node": x2 = n0 (0.4 x7 + 0.6 x9 + 0.1) + t0 y3, x3 = n1 (...) +
  // t1 y3 (its normal component slaved to the target unknowns 7 and 9, y3 its free tangential
  // component); unknown 5 is a plain slave x5 = -0.3 x1 + 0.2 x11 + 0.05.
  const double nn[2] = {0.6, 0.8}, tt[2] = {-0.8, 0.6};
  MultiPointConstraints c;
  for (int d = 0; d < 2; ++d)
    c.addRow(2 + d, {{7, 0.4 * nn[d]}, {9, 0.6 * nn[d]}, {3, tt[d]}}, 0.1 * nn[d]);
  c.slaves.push_back(2);
  c.addRow(5, {{1, -0.3}, {11, 0.2}}, 0.05);
  c.slaves.push_back(5);
  // The same constraints as rows of C x = d: n . (x2, x3) - 0.4 x7 - 0.6 x9 = 0.1, and
  // x5 + 0.3 x1 - 0.2 x11 = 0.05.
  Eigen::MatrixXd cm = Eigen::MatrixXd::Zero(2, n);
  cm(0, 2) = nn[0];
  cm(0, 3) = nn[1];
  cm(0, 7) = -0.4;
  cm(0, 9) = -0.6;
  cm(1, 5) = 1.0;
  cm(1, 1) = 0.3;
  cm(1, 11) = -0.2;
  const Eigen::Vector2d dv(0.1, 0.05);
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n + 2, n + 2);
  kkt.topLeftCorner(n, n) = a;
  kkt.topRightCorner(n, 2) = cm.transpose();
  kkt.bottomLeftCorner(2, n) = cm;
  Eigen::VectorXd rhs(n + 2);
  rhs << b, dv;
  const Eigen::VectorXd ref = kkt.fullPivLu().solve(rhs);

  const auto bv = toView(b);
  ConstraintElimination elimination;
  const auto t = toDevice(c, n);
  const auto reduced = elimination.eliminate(test::denseToCsr(a), t, 3.0, bv);
  const Eigen::MatrixXd ad = test::toDense(reduced);
  EXPECT_LT((ad - ad.transpose()).norm(), 1e-12 * ad.norm());        // symmetric
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(ad).info(), Eigen::Success); // positive definite
  EXPECT_DOUBLE_EQ(ad(2, 2), 3.0);
  EXPECT_DOUBLE_EQ(ad(5, 5), 3.0);
  const Eigen::VectorXd rb = toEigen(bv);
  const Eigen::VectorXd y = ad.ldlt().solve(rb);
  EXPECT_NEAR(y(2), 0.0, 1e-14);
  EXPECT_NEAR(y(5), 0.0, 1e-14);
  const auto xv = toView(y);
  expandConstrained(t, xv);
  const Eigen::VectorXd x = toEigen(xv);
  EXPECT_LT((x - ref.head(n)).norm(), 1e-12 * ref.head(n).norm());
  EXPECT_LT((cm * x - dv).norm(), 1e-13);
  // Condensed residual zero; the slaves' residuals are the multipliers' forces: A x - b = -C^T l.
  const Eigen::VectorXd res = a * x - b;
  const auto rv = toView(res);
  condenseVector(t, rv);
  const Eigen::VectorXd condensed = toEigen(rv);
  for (int i = 0; i < n; ++i)
    EXPECT_NEAR(condensed(i), 0.0, 1e-12) << i;
  EXPECT_LT((res + cm.transpose() * ref.tail(2)).norm(), 1e-12 * res.norm());
}

namespace multipoint_tests {

/// A random sparse SPD matrix on `nodes` nodes with `stride` unknowns each: a random symmetric
/// node graph (each node coupled to `degree` random others), dense blocks, diagonally dominant.
test::MpcSparse randomSpd(int nodes, int stride, int degree, std::mt19937 &rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, nodes - 1);
  std::vector<Eigen::Triplet<double, long>> t;
  const auto block = [&](int p, int q) {
    for (int a = 0; a < stride; ++a)
      for (int b = 0; b < stride; ++b) {
        const double v = u(rng);
        t.emplace_back(stride * p + a, stride * q + b, v);
        t.emplace_back(stride * q + b, stride * p + a, v);
      }
  };
  for (int p = 0; p < nodes; ++p)
    for (int k = 0; k < degree; ++k) {
      const int q = pick(rng);
      if (q != p)
        block(p, q);
    }
  test::MpcSparse m(stride * nodes, stride * nodes);
  m.setFromTriplets(t.begin(), t.end());
  // Diagonal dominance: diag = 1 + sum |off-diagonal| of the row.
  std::vector<Eigen::Triplet<double, long>> d;
  for (long i = 0; i < m.rows(); ++i)
    d.emplace_back(i, i, 1.0 + m.row(i).cwiseAbs().sum());
  test::MpcSparse dm(m.rows(), m.cols());
  dm.setFromTriplets(d.begin(), d.end());
  m += dm;
  m.makeCompressed();
  return m;
}

/// Contact-like constraints on `stride` unknowns per node: `count` contactor nodes (distinct,
/// never masters), each on 2 or 3 random target nodes with random weights and a random unit
/// normal n, t = (-n_y, n_x): a framed slip node (rows at both components, slave at the first,
/// the free tangential component y_{i0+1}), a stick node (both components slaves) or a node with
/// one component held (one slave row, the held component as an entry).
MultiPointConstraints randomConstraints(int nodes, int stride, int count, std::mt19937 &rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.1, 1.0);
  std::vector<int> order(nodes);
  for (int p = 0; p < nodes; ++p)
    order[p] = p;
  std::shuffle(order.begin(), order.end(), rng);
  const std::vector<int> contactors(order.begin(), order.begin() + count);
  const std::vector<int> masters(order.begin() + count, order.end());
  std::uniform_int_distribution<int> pickMaster(0, static_cast<int>(masters.size()) - 1);
  MultiPointConstraints c;
  for (int k = 0; k < count; ++k) {
    const LocalIndex i0 = stride * contactors[k];
    const double angle = 3.14159 * u(rng);
    const double n[2] = {std::cos(angle), std::sin(angle)}, t[2] = {-n[1], n[0]};
    const int targets = 2 + k % 2;
    std::vector<std::pair<LocalIndex, double>> normalRow, tangentRow;
    for (int a = 0; a < targets; ++a) {
      const int q = masters[pickMaster(rng)];
      const double wa = w(rng), wt = w(rng);
      for (int d = 0; d < 2; ++d) {
        normalRow.emplace_back(stride * q + d, wa * n[d]);
        tangentRow.emplace_back(stride * q + d, wt * t[d]);
      }
    }
    const double step = 0.01 * u(rng), tangentStep = 0.01 * u(rng);
    const int kind = k % 3;
    if (kind == 2) { // one component held (here the first): a single slave row
      auto row = normalRow;
      row.emplace_back(i0, 0.3 * u(rng));
      c.addRow(i0 + 1, row, step);
      c.slaves.push_back(i0 + 1);
      continue;
    }
    for (int d = 0; d < 2; ++d) {
      std::vector<std::pair<LocalIndex, double>> row;
      for (const auto &e : normalRow)
        row.emplace_back(e.first, n[d] * e.second);
      double offset = n[d] * step;
      if (kind == 1) {
        for (const auto &e : tangentRow)
          row.emplace_back(e.first, t[d] * e.second);
        offset += t[d] * tangentStep;
      } else {
        row.emplace_back(i0 + 1, t[d]);
      }
      c.addRow(i0 + d, row, offset);
    }
    c.slaves.push_back(i0);
    if (kind == 1)
      c.slaves.push_back(i0 + 1);
  }
  return c;
}

double maxAbs(const test::MpcSparse &m) {
  double v = 0.0;
  for (long k = 0; k < m.nonZeros(); ++k)
    v = std::max(v, std::abs(m.valuePtr()[k]));
  return v;
}

} // namespace multipoint_tests

TEST(MultiPointConstraints, DeviceEliminationMatchesTheEigenReference) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const int stride : {2, 3, 5})
    for (const int count : {1, 4, 13}) {
      SCOPED_TRACE("stride " + std::to_string(stride) + ", " + std::to_string(count) + " nodes");
      const int nodes = 40;
      const test::MpcSparse a = randomSpd(nodes, stride, 3, rng);
      const LocalIndex n = static_cast<LocalIndex>(a.rows());
      const MultiPointConstraints c = randomConstraints(nodes, stride, count, rng);
      Eigen::VectorXd b(n);
      for (LocalIndex i = 0; i < n; ++i)
        b(i) = u(rng);
      Eigen::VectorXd rb = b;
      const test::MpcSparse ref = test::referenceElimination(a, c, 2.5, rb);

      const auto t = toDevice(c, n);
      ConstraintElimination elimination;
      const auto bv = toView(b);
      const auto reduced = elimination.eliminate(test::sparseToCsr(a), t, 2.5, bv);
      EXPECT_FALSE(elimination.reusedPattern());
      // Same pattern as Eigen's (structural) product, same entries to 1e-14 of the largest.
      const auto ro = toHostVector(reduced.rowOffsets);
      const auto co = toHostVector(reduced.columns);
      const auto va = toHostVector(reduced.values);
      ASSERT_EQ(static_cast<long>(co.size()), ref.nonZeros());
      const double scale = maxAbs(ref);
      for (LocalIndex i = 0; i < n; ++i) {
        ASSERT_EQ(ro[i + 1], ref.outerIndexPtr()[i + 1]) << i;
        for (Offset k = ro[i]; k < ro[i + 1]; ++k) {
          ASSERT_EQ(co[k], ref.innerIndexPtr()[k]) << i;
          EXPECT_NEAR(va[k], ref.valuePtr()[k], 1e-14 * scale) << i << ", " << co[k];
        }
      }
      EXPECT_LT((toEigen(bv) - rb).norm(), 1e-14 * rb.norm() + 1e-300);

      // The symbolic phase reused when only values change, redone when T's pattern changes.
      test::MpcSparse a2 = a;
      for (long k = 0; k < a2.nonZeros(); ++k)
        a2.valuePtr()[k] *= 1.0 + 0.1 * u(rng);
      a2 = test::MpcSparse(0.5 * (a2 + test::MpcSparse(a2.transpose())));
      a2.makeCompressed();
      ASSERT_EQ(a2.nonZeros(), a.nonZeros());
      auto csr = test::sparseToCsr(a);
      Kokkos::deep_copy(csr.values,
                        toView(Eigen::Map<const Eigen::VectorXd>(a2.valuePtr(), a2.nonZeros())));
      ConstraintElimination again;
      again.eliminate(csr, t, 2.5, toView(b));
      Eigen::VectorXd rb2 = b;
      const test::MpcSparse ref2 = test::referenceElimination(a2, c, 2.5, rb2);
      const auto bv2 = toView(b);
      const auto reduced2 = again.eliminate(csr, toDevice(c, n), 2.5, bv2);
      EXPECT_TRUE(again.reusedPattern());
      const Eigen::MatrixXd d2 = test::toDense(reduced2);
      EXPECT_LT((d2 - ref2.toDense()).cwiseAbs().maxCoeff(), 1e-14 * maxAbs(ref2));
      EXPECT_LT((toEigen(bv2) - rb2).norm(), 1e-14 * rb2.norm());
      const MultiPointConstraints other = randomConstraints(nodes, stride, count, rng);
      const auto bv3 = toView(b);
      const auto reduced3 = again.eliminate(csr, toDevice(other, n), 2.5, bv3);
      EXPECT_FALSE(again.reusedPattern());
      Eigen::VectorXd rb3 = b;
      const test::MpcSparse ref3 = test::referenceElimination(a2, other, 2.5, rb3);
      EXPECT_LT((test::toDense(reduced3) - ref3.toDense()).cwiseAbs().maxCoeff(),
                1e-14 * maxAbs(ref3));

      // T y + s, T^T v and the condensed free norm against the reference.
      Eigen::VectorXd y(n), g(n);
      for (LocalIndex i = 0; i < n; ++i) {
        y(i) = u(rng);
        g(i) = u(rng);
      }
      const auto xv = toView(y);
      expandConstrained(t, xv);
      const Eigen::VectorXd xr = test::referenceExpand(c, y);
      EXPECT_LT((toEigen(xv) - xr).norm(), 1e-15 * xr.norm());
      const auto gv = toView(g);
      condenseVector(t, gv);
      const Eigen::VectorXd gr = test::referenceCondense(c, g);
      EXPECT_LT((toEigen(gv) - gr).norm(), 1e-15 * gr.norm());
      std::vector<int> flags(n, 0);
      for (LocalIndex i = 0; i < n; i += 7)
        flags[i] = 1;
      Kokkos::View<int *, Memory> fv("flags", n);
      copyToDevice(fv, flags);
      double free = 0.0;
      for (LocalIndex i = 0; i < n; ++i)
        if (i % stride < 2 && !flags[i])
          free += gr(i) * gr(i); // gr is zero at the slaves
      EXPECT_NEAR(condensedFreeNorm(t, Kokkos::View<const double *, Memory>(toView(g)),
                                    Kokkos::View<const int *, Memory>(fv), stride),
                  std::sqrt(free), 1e-14 * std::sqrt(free));
    }
}
