// The device constraint set of a linear system (solver/ConstraintSet.hpp) and the tangent basis of
// local frames (solver/LocalFrames.hpp: tangentBasis<Dim>):
//  - tangentBasis, evaluated on the device for random and axis-aligned normals: in 2D exactly
//    (-n_y, n_x); in 3D two unit tangents orthogonal to n and to each other, with (n, t0, t1)
//    right-handed (n x t0 = t1), checked on the host by dot and cross products;
//  - solveConstrained with local frames, multipoint rows and prescribed unknowns together against
//    the dense host solution of the same constrained problem (x = R (T y + s), y prescribed at
//    the flagged unknowns, the rest minimizing the energy: P^T T^T R^T A R T P z = ...), and
//    constrainedFreeNorm against T^T R^T g computed densely (and zero at that solution).
#include <core/Transfer.hpp>
#include <solver/ConstraintSet.hpp>
#include <solver/DofMap.hpp>
#include <solver/LocalFrames.hpp>
#include <support/KernelFixture.hpp>
#include <support/MultiPointReference.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <random>
#include <vector>

using namespace mixcon;

namespace constraint_set_tests {

using Memory = Kokkos::DefaultExecutionSpace::memory_space;

/// Random unit normals in Dim dimensions, then the axis directions (both signs) and directions
/// between two axes, where a choice of helper axis could degenerate.
template <int Dim> std::vector<std::array<double, Dim>> normals(int count) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::array<double, Dim>> out;
  for (int k = 0; k < count; ++k) {
    std::array<double, Dim> n{};
    double l = 0.0;
    for (double &v : n) {
      v = g(rng);
      l += v * v;
    }
    for (double &v : n)
      v /= std::sqrt(l);
    out.push_back(n);
  }
  for (int a = 0; a < Dim; ++a)
    for (double s : {1.0, -1.0}) {
      std::array<double, Dim> n{};
      n[a] = s;
      out.push_back(n);
      std::array<double, Dim> m{};
      m[a] = s * std::sqrt(0.5);
      m[(a + 1) % Dim] = std::sqrt(0.5);
      out.push_back(m);
    }
  return out;
}

/// tangentBasis<Dim> of every normal, computed on the device.
template <int Dim>
std::vector<double> deviceTangents(const std::vector<std::array<double, Dim>> &n) {
  const int m = static_cast<int>(n.size());
  Kokkos::View<double **, Memory> nv("n", m, Dim), tv("t", m, (Dim - 1) * Dim);
  auto hn = Kokkos::create_mirror_view(nv);
  for (int k = 0; k < m; ++k)
    for (int i = 0; i < Dim; ++i)
      hn(k, i) = n[k][i];
  Kokkos::deep_copy(nv, hn);
  Kokkos::parallel_for(
      "tangents", Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, m), KOKKOS_LAMBDA(int k) {
        double nk[Dim], t[Dim - 1][Dim];
        for (int i = 0; i < Dim; ++i)
          nk[i] = nv(k, i);
        tangentBasis<Dim>(nk, t);
        for (int a = 0; a < Dim - 1; ++a)
          for (int i = 0; i < Dim; ++i)
            tv(k, a * Dim + i) = t[a][i];
      });
  return toHostVector(tv); // row-major whatever the layout (CUDA's is column-major)
}

} // namespace constraint_set_tests
using namespace constraint_set_tests;

TEST(TangentBasis, TwoDimensionsIsTheRotatedNormal) {
  const auto n = normals<2>(50);
  const auto t = deviceTangents<2>(n);
  for (std::size_t k = 0; k < n.size(); ++k) {
    EXPECT_EQ(t[2 * k], -n[k][1]) << k;
    EXPECT_EQ(t[2 * k + 1], n[k][0]) << k;
  }
}

TEST(TangentBasis, ThreeDimensionsIsARightHandedOrthonormalFrame) {
  const auto n = normals<3>(200);
  const auto t = deviceTangents<3>(n);
  const auto dot = [](const double *a, const double *b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  for (std::size_t k = 0; k < n.size(); ++k) {
    const double *nk = n[k].data(), *t0 = &t[6 * k], *t1 = &t[6 * k + 3];
    EXPECT_NEAR(dot(t0, t0), 1.0, 1e-15) << k;
    EXPECT_NEAR(dot(t1, t1), 1.0, 1e-15) << k;
    EXPECT_NEAR(dot(t0, nk), 0.0, 1e-15) << k;
    EXPECT_NEAR(dot(t1, nk), 0.0, 1e-15) << k;
    EXPECT_NEAR(dot(t0, t1), 0.0, 1e-15) << k;
    const double cross[3] = {nk[1] * t0[2] - nk[2] * t0[1], nk[2] * t0[0] - nk[0] * t0[2],
                             nk[0] * t0[1] - nk[1] * t0[0]};
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(cross[i], t1[i], 1e-15) << k; // n x t0 = t1: right-handed
  }
}

TEST(ConstraintSet, FramesMultipointRowsAndDirichletSolveTheConstrainedProblem) {
  const int nodes = 12, stride = 3, n = nodes * stride;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd r0(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      r0(i, j) = u(rng);
  const Eigen::MatrixXd a = r0 * r0.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd b(n), g(n);
  for (int i = 0; i < n; ++i) {
    b(i) = u(rng);
    g(i) = u(rng);
  }
  // Frames at nodes 1, 4, 7, 10 (random normals); R = [n t] on their displacement pairs.
  std::vector<int> framed(nodes, 0);
  std::vector<double> normal(2 * nodes, 0.0);
  Eigen::MatrixXd rot = Eigen::MatrixXd::Identity(n, n);
  for (int p = 1; p < nodes; p += 3) {
    const double angle = 3.0 * u(rng), nn[2] = {std::cos(angle), std::sin(angle)};
    double t[1][2];
    tangentBasis<2>(nn, t);
    framed[p] = 1;
    normal[2 * p] = nn[0];
    normal[2 * p + 1] = nn[1];
    for (int i = 0; i < 2; ++i) {
      rot(stride * p + i, stride * p) = nn[i];
      rot(stride * p + i, stride * p + 1) = t[0][i];
    }
  }
  // Multipoint rows (in local components at framed nodes): a framed contactor at node 4 whose
  // normal component follows nodes 0 and 2, a plain slave at node 5's x following nodes 8, 9.
  MultiPointConstraints c;
  c.addRow(stride * 4, {{0, 0.3}, {1, -0.2}, {stride * 2 + 1, 0.5}}, 0.01);
  c.slaves.push_back(stride * 4);
  c.addRow(stride * 5, {{stride * 8, 0.6}, {stride * 9 + 1, 0.4}, {stride * 9 + 2, 0.1}}, -0.02);
  c.slaves.push_back(stride * 5);
  // Prescribed: node 0 fully (displacements), node 7's normal component, node 3's stress-like
  // third unknown.
  std::vector<int> flags(n, 0);
  std::vector<double> values(n, 0.0);
  for (int i : {0, 1, stride * 7, stride * 3 + 2}) {
    flags[i] = 1;
    values[i] = 0.05 * u(rng);
  }

  // Host reference: x = R (T (P z + v) + s), z the free unknowns minimizing the energy.
  const Eigen::MatrixXd t = Eigen::MatrixXd(test::referenceTransformation(c, n));
  const Eigen::VectorXd s = test::referenceOffsets(c, n);
  std::vector<int> held(flags);
  for (LocalIndex sl : c.slaves)
    held[sl] = 1;
  std::vector<int> free;
  for (int i = 0; i < n; ++i)
    if (!held[i])
      free.push_back(i);
  Eigen::MatrixXd pm = Eigen::MatrixXd::Zero(n, static_cast<long>(free.size()));
  for (std::size_t k = 0; k < free.size(); ++k)
    pm(free[k], static_cast<long>(k)) = 1.0;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i)
    if (flags[i])
      v(i) = values[i];
  const Eigen::MatrixXd map = rot * t * pm;
  const Eigen::VectorXd shift = rot * (t * v + s);
  const Eigen::VectorXd z =
      (map.transpose() * a * map).llt().solve(map.transpose() * (b - a * shift));
  const Eigen::VectorXd xRef = map * z + shift;

  // Device: one constraint set.
  const auto fv = Kokkos::View<int *, Memory>("flags", n);
  const auto vv = Kokkos::View<double *, Memory>("values", n);
  const auto frv = Kokkos::View<int *, Memory>("framed", nodes);
  const auto nv = Kokkos::View<double *[2], Memory>("normal", nodes);
  copyToDevice(fv, flags);
  copyToDevice(vv, values);
  copyToDevice(frv, framed);
  auto hn = hostMirror(nv);
  for (int p = 0; p < nodes; ++p)
    for (int i = 0; i < 2; ++i)
      hn(p, i) = normal[2 * p + i];
  copyToDevice(nv, hn);
  const auto mp = toDevice(c, n);
  ConstraintSet set;
  set.stride = stride;
  set.flags = fv;
  set.values = vv;
  set.framed = frv;
  set.normal = nv;
  set.multipoint = &mp;
  set.slaveDiagonal = 2.0;
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  auto solver = makeLinearSolver(o, DofMap::serial(nodes, stride), MPI_COMM_WORLD);
  const auto am = test::denseToCsr(a);
  CsrMatrix<Memory> work;
  ConstraintElimination elimination;
  const auto bv = test::toView(b);
  Kokkos::View<double *, Memory> xv("x", n);
  double setup = 0.0;
  solveConstrained(set, am, work, elimination, bv, *solver, xv, &setup);
  const Eigen::VectorXd x = test::toEigen(xv);
  EXPECT_LT((x - xRef).norm(), 1e-10 * xRef.norm());
  EXPECT_GT(setup, 0.0);

  // The free residual: T^T R^T g over displacement unknowns neither prescribed nor slaves.
  const Eigen::VectorXd cond = t.transpose() * rot.transpose() * g;
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    if (i % stride < 2 && !held[i])
      sum += cond(i) * cond(i);
  const double norm =
      constrainedFreeNorm(set, Kokkos::View<const double *, Memory>(test::toView(g)));
  EXPECT_NEAR(norm, std::sqrt(sum), 1e-13 * std::sqrt(sum));
  // At the constrained solution the residual it balances vanishes.
  const Eigen::VectorXd res = a * x - b;
  EXPECT_LT(constrainedFreeNorm(set, Kokkos::View<const double *, Memory>(test::toView(res))),
            1e-10 * b.norm());
}
