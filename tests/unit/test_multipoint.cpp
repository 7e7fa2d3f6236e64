// Master-slave elimination of linear multi-point constraints (solver/MultiPointConstraints.hpp)
// against the host reference: the dense saddle-point (Lagrange multiplier) system
// [A C^T; C 0] [x; lambda] = [b; d] solved with Eigen. Both give the same x, the condensed
// residual T^T (A x - b) vanishes, and the eliminated matrix stays symmetric positive definite.
#include <solver/MultiPointConstraints.hpp>
#include <support/KernelFixture.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

using namespace mixcon;

namespace multipoint_tests {

using Memory = Kokkos::DefaultExecutionSpace::memory_space;

CsrMatrix<Memory> toCsr(const Eigen::MatrixXd &a) {
  const LocalIndex n = static_cast<LocalIndex>(a.rows());
  CsrMatrix<Memory> m;
  m.numRows = m.numColumns = n;
  m.rowOffsets = Kokkos::View<Offset *, Memory>("ro", n + 1);
  m.columns = Kokkos::View<LocalIndex *, Memory>("co", n * n);
  m.values = Kokkos::View<double *, Memory>("va", n * n);
  auto ro = Kokkos::create_mirror_view(m.rowOffsets);
  auto co = Kokkos::create_mirror_view(m.columns);
  auto va = Kokkos::create_mirror_view(m.values);
  for (LocalIndex i = 0; i <= n; ++i)
    ro(i) = static_cast<Offset>(i) * n;
  for (LocalIndex i = 0; i < n; ++i)
    for (LocalIndex j = 0; j < n; ++j) {
      co(i * n + j) = j;
      va(i * n + j) = a(i, j);
    }
  Kokkos::deep_copy(m.rowOffsets, ro);
  Kokkos::deep_copy(m.columns, co);
  Kokkos::deep_copy(m.values, va);
  return m;
}

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

  Kokkos::View<double *, Memory> bv("b", n);
  auto hb = Kokkos::create_mirror_view(bv);
  for (int i = 0; i < n; ++i)
    hb(i) = b(i);
  Kokkos::deep_copy(bv, hb);
  const auto reduced = eliminateConstraints(toCsr(a), c, 3.0, bv);
  const Eigen::MatrixXd ad = test::toDense(reduced);
  EXPECT_LT((ad - ad.transpose()).norm(), 1e-12 * ad.norm());        // symmetric
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(ad).info(), Eigen::Success); // positive definite
  EXPECT_DOUBLE_EQ(ad(2, 2), 3.0);
  EXPECT_DOUBLE_EQ(ad(5, 5), 3.0);
  auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), bv);
  Eigen::VectorXd rb(n);
  for (int i = 0; i < n; ++i)
    rb(i) = hr(i);
  const Eigen::VectorXd y = ad.ldlt().solve(rb);
  EXPECT_NEAR(y(2), 0.0, 1e-14);
  EXPECT_NEAR(y(5), 0.0, 1e-14);
  Kokkos::View<double *, Memory> xv("x", n);
  auto hx = Kokkos::create_mirror_view(xv);
  for (int i = 0; i < n; ++i)
    hx(i) = y(i);
  Kokkos::deep_copy(xv, hx);
  expandConstrained(c, xv);
  Kokkos::deep_copy(hx, xv);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i)
    x(i) = hx(i);
  EXPECT_LT((x - ref.head(n)).norm(), 1e-12 * ref.head(n).norm());
  EXPECT_LT((cm * x - dv).norm(), 1e-13);
  // Condensed residual zero; the slaves' residuals are the multipliers' forces: A x - b = -C^T l.
  const Eigen::VectorXd res = a * x - b;
  std::vector<double> cond(res.data(), res.data() + n);
  condenseVector(c, cond);
  for (int i = 0; i < n; ++i)
    EXPECT_NEAR(cond[i], 0.0, 1e-12) << i;
  EXPECT_LT((res + cm.transpose() * ref.tail(2)).norm(), 1e-12 * res.norm());
}
