// The Krylov methods of solver/Krylov.hpp against plain host references: the fused block
// operations of GMRES's classical Gram-Schmidt (dots, subtraction, solution update) against host
// loops, its second pass where the first one cancels, and flexible GMRES and CG against
// textbook host implementations (Eigen, modified Gram-Schmidt) and a dense LU solve.
#include <solver/Krylov.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace mixcon;

namespace {

Eigen::MatrixXd randomMatrix(int rows, int cols, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i)
      m(i, j) = u(gen);
  return m;
}

DeviceBlock toDevice(const Eigen::MatrixXd &m) {
  DeviceBlock b("block", m.rows(), m.cols());
  auto h = Kokkos::create_mirror_view(b);
  for (int j = 0; j < m.cols(); ++j)
    for (int i = 0; i < m.rows(); ++i)
      h(i, j) = m(i, j);
  Kokkos::deep_copy(b, h);
  return b;
}

DeviceVector toDevice(const Eigen::VectorXd &v) {
  DeviceVector d("vector", v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (int i = 0; i < v.size(); ++i)
    h(i) = v(i);
  Kokkos::deep_copy(d, h);
  return d;
}

Eigen::VectorXd toHost(const DeviceVector &d) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d);
  Eigen::VectorXd v(d.extent(0));
  for (int i = 0; i < v.size(); ++i)
    v(i) = h(i);
  return v;
}

std::vector<double> toStd(const Eigen::VectorXd &v) { return {v.data(), v.data() + v.size()}; }

} // namespace

TEST(KrylovBlockOps, DotsSubtractionAndUpdateMatchHostLoops) {
  const int n = 1003, columns = 40;
  const Eigen::MatrixXd vh = randomMatrix(n, columns, 1);
  const DeviceBlock v = toDevice(vh);
  detail::BlockOps ops;
  // 0 columns, one pass, a full pass of 15, one more than a pass, several passes
  for (int k : {0, 1, 7, 15, 16, 31, 40}) {
    const Eigen::VectorXd w = randomMatrix(n, 1, 2 + k).col(0);
    const Eigen::VectorXd c = randomMatrix(k > 0 ? k : 1, 1, 100 + k).col(0).head(k);
    const double scale = std::sqrt(double(n)) * std::sqrt(double(n)); // ~ ||v|| ||w||
    const double tol = 1e-13 * scale;

    std::vector<double> h(k);
    const double ww = ops.dots(v, k, toDevice(w), h);
    EXPECT_NEAR(ww, w.squaredNorm(), tol) << "k = " << k;
    for (int j = 0; j < k; ++j) {
      double ref = 0.0; // plain host loop
      for (int i = 0; i < n; ++i)
        ref += vh(i, j) * w(i);
      EXPECT_NEAR(h[j], ref, tol) << "k = " << k << ", column " << j;
    }

    const DeviceVector wd = toDevice(w);
    const double after = ops.subtract(v, k, toStd(c), wd);
    Eigen::VectorXd ref = w;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < n; ++i)
        ref(i) -= c(j) * vh(i, j);
    EXPECT_LT((toHost(wd) - ref).lpNorm<Eigen::Infinity>(), 1e-13 * (1.0 + c.lpNorm<1>()));
    EXPECT_NEAR(after, ref.squaredNorm(), 1e-12 * ref.squaredNorm());

    const DeviceVector xd = toDevice(w);
    ops.add(v, k, toStd(c), xd);
    Eigen::VectorXd xref = w;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < n; ++i)
        xref(i) += c(j) * vh(i, j);
    EXPECT_LT((toHost(xd) - xref).lpNorm<Eigen::Infinity>(), 1e-13 * (1.0 + c.lpNorm<1>()));
  }
}

TEST(KrylovBlockOps, OrthogonalizeTakesASecondPassWhereTheFirstCancels) {
  const int n = 500, k = 12;
  const Eigen::MatrixXd q =
      Eigen::HouseholderQR<Eigen::MatrixXd>(randomMatrix(n, k, 7)).householderQ() *
      Eigen::MatrixXd::Identity(n, k); // orthonormal columns
  const DeviceBlock v = toDevice(q);
  const Eigen::VectorXd c = randomMatrix(k, 1, 8).col(0);
  const Eigen::VectorXd r = randomMatrix(n, 1, 9).col(0);

  // Almost in the span of V: one classical pass leaves w far from orthogonal to it (about
  // eps ||w|| / ||w - V V^T w|| = 1e-16 / 1e-9), which the host reference shows first.
  const Eigen::VectorXd w = q * c + 1e-9 * r;
  const Eigen::VectorXd onePass = w - q * (q.transpose() * w);
  const double lossOfOnePass = (q.transpose() * onePass).lpNorm<Eigen::Infinity>() / onePass.norm();
  ASSERT_GT(lossOfOnePass, 1e-10);

  detail::BlockOps ops;
  const DeviceVector wd = toDevice(w);
  std::vector<double> h(k);
  const double norm = ops.orthogonalize(v, k, wd, h);
  const Eigen::VectorXd out = toHost(wd);
  EXPECT_EQ(ops.reorthogonalizations(), 1);
  EXPECT_NEAR(norm, out.norm(), 1e-14 * out.norm());
  EXPECT_LT((q.transpose() * out).lpNorm<Eigen::Infinity>() / out.norm(), 1e-13);
  const Eigen::VectorXd projection = q.transpose() * w; // the coefficients: V^T w
  for (int j = 0; j < k; ++j)
    EXPECT_NEAR(h[j], projection(j), 1e-14 * w.norm());
  // The part of w outside the span is 1e-9 (I - V V^T) r.
  EXPECT_NEAR(norm, 1e-9 * (r - q * (q.transpose() * r)).norm(), 1e-15);

  // A w with a few percent outside the span still takes the second pass (less than 1/sqrt(2)
  // of it is left); one far from the span (97 % of it left) does not. Both come out
  // orthogonal to the basis.
  const struct {
    double outside;
    long passesAfter;
  } cases[] = {{0.01, 2}, {1.0, 2}};
  for (const auto &cs : cases) {
    const Eigen::VectorXd wf = (1.0 - cs.outside) * q * c + cs.outside * r;
    const DeviceVector far = toDevice(wf);
    ops.orthogonalize(v, k, far, h);
    EXPECT_EQ(ops.reorthogonalizations(), cs.passesAfter) << cs.outside;
    const Eigen::VectorXd farOut = toHost(far);
    EXPECT_LT((q.transpose() * farOut).lpNorm<Eigen::Infinity>() / farOut.norm(), 1e-14)
        << cs.outside;
  }
}

TEST(KrylovBlockOps, ArnoldiBasisStaysOrthogonal) {
  // 40 Arnoldi steps on a diagonal operator whose 400 eigenvalues lie in 8 clusters of relative
  // width 1e-6: after 8 steps the Krylov space is nearly invariant and each new vector almost in
  // the basis, where one classical pass per step (the host reference below) loses orthogonality
  // entirely and the fused one with its second pass keeps it to working precision.
  const int n = 400, steps = 40;
  Eigen::VectorXd eigenvalues(n);
  for (int i = 0; i < n; ++i)
    eigenvalues(i) = (1.0 + 9.0 * (i % 8) / 7.0) * (1.0 + 1e-6 * std::sin(1.0 + i));
  const Eigen::MatrixXd a = eigenvalues.asDiagonal();
  const Eigen::VectorXd start = Eigen::VectorXd::Ones(n);

  Eigen::MatrixXd onePass(n, steps + 1); // host reference: classical Gram-Schmidt, one pass
  onePass.col(0) = start.normalized();
  for (int k = 0; k < steps; ++k) {
    Eigen::VectorXd w = a * onePass.col(k);
    w -= onePass.leftCols(k + 1) * (onePass.leftCols(k + 1).transpose() * w);
    onePass.col(k + 1) = w.normalized();
  }
  const auto loss = [&](const Eigen::MatrixXd &basis) {
    return (basis.transpose() * basis - Eigen::MatrixXd::Identity(basis.cols(), basis.cols()))
        .lpNorm<Eigen::Infinity>();
  };
  ASSERT_GT(loss(onePass), 0.1);

  DeviceBlock v("mixcon::test::basis", n, steps + 1);
  const Eigen::VectorXd v0 = start.normalized();
  Kokkos::deep_copy(Kokkos::subview(v, Kokkos::ALL, 0), toDevice(v0));
  detail::BlockOps ops;
  std::vector<double> h(steps + 1);
  Eigen::MatrixXd basis(n, steps + 1);
  basis.col(0) = v0;
  for (int k = 0; k < steps; ++k) {
    const DeviceVector w = toDevice(Eigen::VectorXd(a * basis.col(k)));
    const double norm = ops.orthogonalize(v, k + 1, w, h);
    ASSERT_GT(norm, 0.0);
    axpby(0.0, w, 1.0 / norm, w);
    Kokkos::deep_copy(Kokkos::subview(v, Kokkos::ALL, k + 1), w);
    basis.col(k + 1) = toHost(w);
  }
  EXPECT_LT(loss(basis), 1e-13);
  EXPECT_GT(ops.reorthogonalizations(), 0);
}

namespace {

/// The 1D convection-diffusion operator -u'' + beta u' on n interior points of (0, 1), central
/// differences (nonsymmetric; cell Peclet number beta h / 2), u = 0 at both ends.
struct ConvectionDiffusion {
  int n;
  double beta;
  double lower() const { return -1.0 - 0.5 * beta / (n + 1); }
  double diagonal() const { return 2.0; }
  double upper() const { return -1.0 + 0.5 * beta / (n + 1); }

  Eigen::MatrixXd dense() const {
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
      a(i, i) = diagonal();
      if (i > 0)
        a(i, i - 1) = lower();
      if (i + 1 < n)
        a(i, i + 1) = upper();
    }
    return a;
  }

  LinearMap map() const {
    const double l = lower(), d = diagonal(), u = upper();
    const int size = n;
    return [=](const ConstDeviceVector &x, const DeviceVector &y) {
      Kokkos::parallel_for(
          "test::tridiagonal", Kokkos::RangePolicy<>(0, size), KOKKOS_LAMBDA(int i) {
            y(i) = d * x(i) + (i > 0 ? l * x(i - 1) : 0.0) + (i + 1 < size ? u * x(i + 1) : 0.0);
          });
    };
  }
};

/// Right-preconditioned flexible GMRES(m) as in Saad's "Iterative Methods for Sparse Linear
/// Systems" (2003), Algorithm 9.6, with modified Gram-Schmidt and Givens rotations; the same
/// stopping rule as krylovSolve (the recursive residual within a cycle, the true one at its end).
int hostGmres(const Eigen::MatrixXd &a, const Eigen::VectorXd &pinv, const Eigen::VectorXd &b,
              Eigen::VectorXd &x, int m, double tol, int maxIterations) {
  const double bnorm = b.norm();
  int its = 0;
  Eigen::VectorXd r = b - a * x;
  double rnorm = r.norm();
  while (rnorm > tol * bnorm && its < maxIterations) {
    Eigen::MatrixXd v = Eigen::MatrixXd::Zero(b.size(), m + 1), z(b.size(), m);
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m + 1, m);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(m + 1), cs(m), sn(m);
    v.col(0) = r / rnorm;
    g(0) = rnorm;
    int k = 0;
    for (; k < m && its < maxIterations; ++k) {
      z.col(k) = pinv.cwiseProduct(v.col(k));
      Eigen::VectorXd w = a * z.col(k);
      for (int i = 0; i <= k; ++i) {
        h(i, k) = w.dot(v.col(i));
        w -= h(i, k) * v.col(i);
      }
      h(k + 1, k) = w.norm();
      v.col(k + 1) = w / h(k + 1, k);
      for (int i = 0; i < k; ++i) {
        const double t = cs(i) * h(i, k) + sn(i) * h(i + 1, k);
        h(i + 1, k) = -sn(i) * h(i, k) + cs(i) * h(i + 1, k);
        h(i, k) = t;
      }
      const double den = std::hypot(h(k, k), h(k + 1, k));
      cs(k) = h(k, k) / den;
      sn(k) = h(k + 1, k) / den;
      h(k, k) = den;
      h(k + 1, k) = 0.0;
      g(k + 1) = -sn(k) * g(k);
      g(k) = cs(k) * g(k);
      ++its;
      if (std::fabs(g(k + 1)) <= tol * bnorm) {
        ++k;
        break;
      }
    }
    const Eigen::VectorXd y = h.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
    x += z.leftCols(k) * y;
    r = b - a * x;
    rnorm = r.norm();
  }
  return its;
}

} // namespace

TEST(KrylovGmres, MatchesAHostReferenceOnANonsymmetricSystem) {
  // Cell Peclet number 0.8: strongly nonsymmetric, still a stable discretization. The restart
  // (15) is reached several times, so the basis blocks are reused and grown.
  const ConvectionDiffusion op{400, 640.0};
  const Eigen::MatrixXd a = op.dense();
  Eigen::VectorXd b(op.n);
  for (int i = 0; i < op.n; ++i)
    b(i) = std::sin(3.0 * (i + 1) / (op.n + 1)) + 0.5;
  const Eigen::VectorXd exact = a.partialPivLu().solve(b);
  const double tol = 1e-10;

  Eigen::VectorXd xRef = Eigen::VectorXd::Zero(op.n);
  const Eigen::VectorXd pinv = Eigen::VectorXd::Constant(op.n, 1.0 / op.diagonal());
  const int refIts = hostGmres(a, pinv, b, xRef, 15, tol, 5000);

  for (int restart : {15, 60}) {
    KrylovOptions o;
    o.method = KrylovMethod::Gmres;
    o.tolerance = tol;
    o.restart = restart;
    o.maxIterations = 5000;
    const double dinv = 1.0 / op.diagonal();
    const LinearMap jacobi = [dinv](const ConstDeviceVector &x, const DeviceVector &y) {
      axpby(dinv, x, 0.0, y);
    };
    KrylovWorkspace workspace;
    for (int call = 0; call < 2; ++call) { // the second call reuses the grown blocks
      const DeviceVector x("x", op.n);
      const KrylovStats s = krylovSolve(o, op.map(), jacobi, toDevice(b), x, &workspace);
      ASSERT_TRUE(s.converged) << "restart " << restart;
      EXPECT_LE(s.relativeResidual, tol);
      const Eigen::VectorXd xd = toHost(x);
      EXPECT_LE((b - a * xd).norm() / b.norm(), tol);
      EXPECT_LT((xd - exact).norm() / exact.norm(), 1e-7);
      if (restart == 15) { // the same algorithm as the reference, up to rounding
        EXPECT_NEAR(s.iterations, refIts, 2) << "host reference took " << refIts;
      }
    }
  }
  ASSERT_GT(refIts, 30); // several restart cycles of 15
}

TEST(KrylovCg, MatchesAHostReferenceOnTheLaplacian) {
  const ConvectionDiffusion op{300, 0.0}; // symmetric positive definite
  const Eigen::MatrixXd a = op.dense();
  Eigen::VectorXd b(op.n);
  for (int i = 0; i < op.n; ++i)
    b(i) = 1.0 + 0.1 * i;
  const Eigen::VectorXd exact = a.llt().solve(b);
  const double tol = 1e-10;

  // Textbook preconditioned CG (Saad, Algorithm 9.1) with a Jacobi preconditioner.
  Eigen::VectorXd xr = Eigen::VectorXd::Zero(op.n), r = b, z = r / op.diagonal(), p = z;
  double rz = r.dot(z);
  int refIts = 0;
  while (r.norm() > tol * b.norm()) {
    const Eigen::VectorXd q = a * p;
    const double alpha = rz / p.dot(q);
    xr += alpha * p;
    r -= alpha * q;
    z = r / op.diagonal();
    const double rzNew = r.dot(z);
    p = z + (rzNew / rz) * p;
    rz = rzNew;
    ++refIts;
  }

  KrylovOptions o;
  o.method = KrylovMethod::Cg;
  o.tolerance = tol;
  o.maxIterations = 5000;
  const double dinv = 1.0 / op.diagonal();
  const DeviceVector x("x", op.n);
  const KrylovStats s = krylovSolve(
      o, op.map(),
      [dinv](const ConstDeviceVector &in, const DeviceVector &out) { axpby(dinv, in, 0.0, out); },
      toDevice(b), x);
  ASSERT_TRUE(s.converged);
  EXPECT_NEAR(s.iterations, refIts, 2) << "host reference took " << refIts;
  const Eigen::VectorXd xd = toHost(x);
  EXPECT_LE((b - a * xd).norm() / b.norm(), tol);
  EXPECT_LT((xd - exact).norm() / exact.norm(), 1e-7);

  // An exactly applied operator from x = 0: one product per iteration, none for the first
  // residual or for the final check, and the same answer.
  int products = 0;
  const LinearMap base = op.map();
  const LinearMap counted = [&](const ConstDeviceVector &in, const DeviceVector &out) {
    ++products;
    base(in, out);
  };
  const LinearMap jacobi = [dinv](const ConstDeviceVector &in, const DeviceVector &out) {
    axpby(dinv, in, 0.0, out);
  };
  for (bool exactOperator : {false, true}) {
    o.exactOperator = exactOperator;
    products = 0;
    const DeviceVector xe("x", op.n);
    const KrylovStats se = krylovSolve(o, counted, jacobi, toDevice(b), xe);
    ASSERT_TRUE(se.converged);
    EXPECT_EQ(se.iterations, s.iterations);
    EXPECT_EQ(products, se.iterations + (exactOperator ? 0 : 2)) << exactOperator;
    const Eigen::VectorXd xeh = toHost(xe);
    EXPECT_LE((b - a * xeh).norm() / b.norm(), 1.01 * tol);
  }
  // A nonzero start still takes its true residual first (one product more), and stopping at
  // the iteration limit reports the recursive residual, not converged.
  products = 0;
  const Eigen::VectorXd half = Eigen::VectorXd::Constant(op.n, 0.5);
  const DeviceVector start = toDevice(half);
  const KrylovStats fromHalf = krylovSolve(o, counted, jacobi, toDevice(b), start);
  ASSERT_TRUE(fromHalf.converged);
  EXPECT_EQ(products, fromHalf.iterations + 1);
  EXPECT_LE((b - a * toHost(start)).norm() / b.norm(), 1.01 * tol);
  o.maxIterations = 3;
  products = 0;
  const DeviceVector limited("x", op.n);
  const KrylovStats three = krylovSolve(o, counted, jacobi, toDevice(b), limited);
  EXPECT_FALSE(three.converged);
  EXPECT_EQ(three.iterations, 3);
  EXPECT_EQ(products, 3);
  const double trueResidual = (b - a * toHost(limited)).norm() / b.norm();
  EXPECT_GT(three.relativeResidual, tol);
  EXPECT_NEAR(three.relativeResidual, trueResidual, 1e-10 * trueResidual);
}

TEST(KrylovGmres, RestartBelowOneIsRefused) {
  KrylovOptions o;
  o.method = KrylovMethod::Gmres;
  o.restart = 0;
  DeviceVector b("b", 3), x("x", 3);
  Kokkos::deep_copy(b, 1.0);
  const LinearMap identity = [](const ConstDeviceVector &in, const DeviceVector &out) {
    Kokkos::deep_copy(out, in);
  };
  EXPECT_THROW(krylovSolve(o, identity, identity, b, x), std::invalid_argument);
  o.restart = 1; // GMRES(1) still solves the identity
  EXPECT_TRUE(krylovSolve(o, identity, identity, b, x).converged);
}
