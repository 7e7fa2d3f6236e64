// Small fixed-size tensor algebra (core/Tensor.hpp): products and inverses against Eigen (the host
// reference), the Voigt maps of 2D and 3D against the tensor definitions, the field layouts, and
// the same functions run inside a Kokkos kernel against the host call.
#include <core/ElementTraits.hpp>
#include <core/Tensor.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <type_traits>
#include <vector>

using namespace mixcon;

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace tensor_tests {

using Exec = Kokkos::DefaultExecutionSpace;

template <int R, int C> Mat<R, C> randomMat(std::mt19937 &g) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat<R, C> a{};
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j)
      a.m[i][j] = u(g);
  return a;
}

template <int R, int C> Eigen::Matrix<double, R, C> toEigen(const Mat<R, C> &a) {
  Eigen::Matrix<double, R, C> e;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j)
      e(i, j) = a.m[i][j];
  return e;
}

template <int R, int C>
void expectNear(const Mat<R, C> &a, const Eigen::Matrix<double, R, C> &b, double relTol) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j)
      EXPECT_NEAR(a.m[i][j], b(i, j), relTol * scale) << "(" << i << "," << j << ")";
}

/// A random symmetric positive-definite N x N matrix, condition number about 10^3.
template <int N> Mat<N, N> randomSpd(std::mt19937 &g) {
  const Mat<N, N> b = randomMat<N, N>(g);
  Mat<N, N> a = matmulTN(b, b);
  for (int i = 0; i < N; ++i)
    a.m[i][i] += 1e-3 + 0.1 * i;
  return a;
}

template <int N> void checkSpdInverse(std::mt19937 &g) {
  for (int trial = 0; trial < 20; ++trial) {
    const Mat<N, N> a = randomSpd<N>(g);
    Mat<N, N> inv{};
    ASSERT_TRUE(spdInverse(a, inv)) << "N = " << N;
    const Eigen::Matrix<double, N, N> ref = toEigen(a).inverse();
    expectNear(inv, ref, 1e-10 * ref.norm());
    // L L^T reproduces A.
    Mat<N, N> l{};
    ASSERT_TRUE(cholesky(a, l));
    expectNear(matmulNT(l, l), toEigen(a), 1e-14);
    for (int i = 0; i < N; ++i)
      for (int j = i + 1; j < N; ++j)
        EXPECT_EQ(l.m[i][j], 0.0);
  }
  // Indefinite (one negative eigenvalue) and singular matrices are refused, inv untouched.
  Mat<N, N> bad = identity<N>();
  bad.m[N - 1][N - 1] = -1.0;
  Mat<N, N> inv = identity<N>();
  inv.m[0][0] = 42.0;
  EXPECT_FALSE(spdInverse(bad, inv)) << "N = " << N;
  EXPECT_EQ(inv.m[0][0], 42.0);
  EXPECT_FALSE(isSymmetricPositiveDefinite(bad));
  if (N > 1) {
    Mat<N, N> singular{}; // rank one: v v^T
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j)
        singular.m[i][j] = (i + 1.0) * (j + 1.0);
    EXPECT_FALSE(isSymmetricPositiveDefinite(singular)) << "N = " << N;
  }
  EXPECT_TRUE(isSymmetricPositiveDefinite(identity<N>()));
}

/// Tensor contraction sigma : eps with the full tensors.
template <int Dim> double contraction(const Mat<Dim, Dim> &s, const Mat<Dim, Dim> &e) {
  double w = 0.0;
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j)
      w += s.m[i][j] * e.m[i][j];
  return w;
}

template <int Dim> Mat<Dim, Dim> randomSymmetric(std::mt19937 &g) {
  Mat<Dim, Dim> a = randomMat<Dim, Dim>(g);
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < i; ++j)
      a.m[i][j] = a.m[j][i];
  return a;
}

template <int Dim> void checkVoigt(std::mt19937 &g) {
  using V = Voigt<Dim>;
  for (int k = 0; k < V::kSize; ++k) {
    EXPECT_EQ(V::index(V::row(k), V::col(k)), k);
    EXPECT_EQ(V::index(V::col(k), V::row(k)), k);
    EXPECT_EQ(V::isShear(k), V::row(k) != V::col(k));
    EXPECT_LE(V::row(k), V::col(k));
  }
  const Mat<Dim, Dim> s = randomSymmetric<Dim>(g), e = randomSymmetric<Dim>(g);
  const auto sv = stressToVoigt(s);
  const auto ev = strainToVoigt(e);
  expectNear(voigtToStress<Dim>(sv), toEigen(s), 0.0);
  expectNear(voigtToStrain<Dim>(ev), toEigen(e), 1e-16);
  for (int k = 0; k < V::kSize; ++k) {
    EXPECT_EQ(sv[k], s.m[V::row(k)][V::col(k)]);
    EXPECT_EQ(ev[k], (V::isShear(k) ? 2.0 : 1.0) * e.m[V::row(k)][V::col(k)]);
  }
  // Engineering shear makes the Voigt inner product the work density sigma : eps.
  EXPECT_NEAR(inner(sv, ev), contraction(s, e), 1e-14);
}

} // namespace tensor_tests
using namespace tensor_tests;

TEST(Tensor, ProductsMatchEigen) {
  std::mt19937 g(7);
  const auto a = randomMat<3, 4>(g);
  const auto b = randomMat<4, 2>(g);
  const auto c = randomMat<3, 2>(g);
  const auto d = randomMat<5, 4>(g);
  expectNear(matmul(a, b), Eigen::Matrix<double, 3, 2>(toEigen(a) * toEigen(b)), 1e-15);
  expectNear(matmulTN(a, c), Eigen::Matrix<double, 4, 2>(toEigen(a).transpose() * toEigen(c)),
             1e-15);
  expectNear(matmulNT(a, d), Eigen::Matrix<double, 3, 5>(toEigen(a) * toEigen(d).transpose()),
             1e-15);
  expectNear(transpose(a), Eigen::Matrix<double, 4, 3>(toEigen(a).transpose()), 0.0);
  expectNear(identity<4>(), Eigen::Matrix<double, 4, 4>(Eigen::Matrix4d::Identity()), 0.0);
  const Vector<4> x{{0.3, -1.2, 2.0, 0.7}};
  const Vector<3> y{{1.5, -0.4, 0.9}};
  const Eigen::Vector4d xe(0.3, -1.2, 2.0, 0.7);
  const Eigen::Vector3d ye(1.5, -0.4, 0.9);
  const Eigen::Vector3d ax = toEigen(a) * xe;
  const Eigen::Vector4d aty = toEigen(a).transpose() * ye;
  const Vector<3> axm = matvec(a, x);
  const Vector<4> atym = matvecT(a, y);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(axm[i], ax(i), 1e-15);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(atym[i], aty(i), 1e-15);
  EXPECT_NEAR(inner(x, x), xe.squaredNorm(), 1e-15);
}

TEST(Tensor, SmallInversesMatchEigen) {
  std::mt19937 g(11);
  for (int trial = 0; trial < 20; ++trial) {
    const auto a2 = randomMat<2, 2>(g);
    const auto a3 = randomMat<3, 3>(g);
    Mat<2, 2> i2{};
    Mat<3, 3> i3{};
    EXPECT_NEAR(inverse(a2, i2), toEigen(a2).determinant(), 1e-14);
    EXPECT_NEAR(inverse(a3, i3), toEigen(a3).determinant(), 1e-14);
    EXPECT_NEAR(determinant(a3), toEigen(a3).determinant(), 1e-14);
    const Eigen::Matrix2d r2 = toEigen(a2).inverse();
    const Eigen::Matrix3d r3 = toEigen(a3).inverse();
    expectNear(i2, r2, 1e-12 * r2.norm());
    expectNear(i3, r3, 1e-12 * r3.norm());
  }
  // Singular: determinant 0, the output left as it was.
  const Mat<3, 3> s{{{1, 2, 3}, {2, 4, 6}, {0, 1, 1}}};
  Mat<3, 3> out = identity<3>();
  EXPECT_EQ(inverse(s, out), 0.0);
  expectNear(out, Eigen::Matrix3d(Eigen::Matrix3d::Identity()), 0.0);
  const Mat<2, 2> s2{{{1, 2}, {2, 4}}};
  Mat<2, 2> out2 = identity<2>();
  EXPECT_EQ(inverse(s2, out2), 0.0);
  expectNear(out2, Eigen::Matrix2d(Eigen::Matrix2d::Identity()), 0.0);
}

TEST(Tensor, SpdInverseMatchesEigenAndRefusesIndefinite) {
  std::mt19937 g(13);
  checkSpdInverse<1>(g);
  checkSpdInverse<2>(g);
  checkSpdInverse<3>(g);
  checkSpdInverse<4>(g);
  checkSpdInverse<5>(g);
  checkSpdInverse<6>(g);
}

TEST(Tensor, VoigtMapsRoundTripAndGiveTheWorkDensity) {
  std::mt19937 g(17);
  checkVoigt<2>(g);
  checkVoigt<3>(g);
  // The documented orders: xx, yy, xy and xx, yy, zz, yz, xz, xy.
  EXPECT_EQ(Voigt<2>::kSize, 3);
  EXPECT_EQ(Voigt<3>::kSize, 6);
  EXPECT_EQ(Voigt<2>::index(0, 1), 2);
  const int rows[6] = {0, 1, 2, 1, 0, 0}, cols[6] = {0, 1, 2, 2, 2, 1};
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(Voigt<3>::row(k), rows[k]) << k;
    EXPECT_EQ(Voigt<3>::col(k), cols[k]) << k;
  }
}

TEST(Tensor, FieldLayoutsOfBothDimensions) {
  using L2 = FieldLayout<2>;
  using L3 = FieldLayout<3>;
  EXPECT_EQ(L2::kNumDisplacements, 2);
  EXPECT_EQ(L2::kNumStresses, 3);
  EXPECT_EQ(L2::kDisplacementUnknowns, 2);
  EXPECT_EQ(L2::kMixedUnknowns, 5);
  EXPECT_EQ(L3::kNumDisplacements, 3);
  EXPECT_EQ(L3::kNumStresses, 6);
  EXPECT_EQ(L3::kDisplacementUnknowns, 3);
  EXPECT_EQ(L3::kMixedUnknowns, 9);
  // 2D interleaving of the mixed model: u, v, Sxx, Syy, Sxy per node (x(5 k + 2 + c) today).
  for (int node = 0; node < 4; ++node) {
    for (int c = 0; c < 2; ++c) {
      EXPECT_EQ(L2::mixedDisplacementDof(node, c), 5 * node + c);
      EXPECT_EQ(L2::displacementDof(node, c), 2 * node + c);
    }
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(L2::mixedStressDof(node, c), 5 * node + 2 + c);
    for (int c = 0; c < 6; ++c)
      EXPECT_EQ(L3::mixedStressDof(node, c), 9 * node + 3 + c);
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(L3::displacementDof(node, c), 3 * node + c);
  }
  static_assert(std::is_same<Quad4::Layout, L2>::value, "Quad4 is a 2D element");
  static_assert(std::is_same<LayoutOf<Quad8>, L2>::value, "Quad8 is a 2D element");
}

namespace tensor_tests {
/// Runs the device-callable algebra once inside a Kokkos kernel; out receives, in order, the
/// 6x6 SPD inverse, the 3x3 inverse, the 2x2 inverse, the 3D stress and strain Voigt vectors, the
/// tensors back from them, matmulTN of 3x3s and its determinant.
void runOnDevice(const Mat<6, 6> &spd, const Mat<3, 3> &a3, const Mat<2, 2> &a2,
                 const Mat<3, 3> &sym, const Kokkos::View<double *, Exec::memory_space> &out) {
  Kokkos::parallel_for(
      "mixcon::test::tensorOnDevice", Kokkos::RangePolicy<Exec>(0, 1), KOKKOS_LAMBDA(int) {
        int n = 0;
        Mat<6, 6> i6{};
        out(n++) = spdInverse(spd, i6) ? 1.0 : 0.0;
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j)
            out(n++) = i6.m[i][j];
        Mat<3, 3> i3{};
        out(n++) = inverse(a3, i3);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            out(n++) = i3.m[i][j];
        Mat<2, 2> i2{};
        out(n++) = inverse(a2, i2);
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j)
            out(n++) = i2.m[i][j];
        const Vector<6> sv = stressToVoigt(sym), ev = strainToVoigt(sym);
        for (int k = 0; k < 6; ++k) {
          out(n++) = sv[k];
          out(n++) = ev[k];
        }
        const Mat<3, 3> back = voigtToStrain<3>(ev);
        const Mat<3, 3> p = matmulTN(a3, back);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            out(n++) = p.m[i][j];
        out(n++) = determinant(p);
      });
}
} // namespace tensor_tests

TEST(Tensor, DeviceCallsMatchHostCalls) {
  std::mt19937 g(19);
  const Mat<6, 6> spd = randomSpd<6>(g);
  const auto a3 = randomMat<3, 3>(g);
  const auto a2 = randomMat<2, 2>(g);
  const auto sym = randomSymmetric<3>(g);
  // Host reference: the same calls in plain host code.
  std::vector<double> ref;
  Mat<6, 6> i6{};
  ref.push_back(spdInverse(spd, i6) ? 1.0 : 0.0);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      ref.push_back(i6.m[i][j]);
  Mat<3, 3> i3{};
  ref.push_back(inverse(a3, i3));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      ref.push_back(i3.m[i][j]);
  Mat<2, 2> i2{};
  ref.push_back(inverse(a2, i2));
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      ref.push_back(i2.m[i][j]);
  const Vector<6> sv = stressToVoigt(sym), ev = strainToVoigt(sym);
  for (int k = 0; k < 6; ++k) {
    ref.push_back(sv[k]);
    ref.push_back(ev[k]);
  }
  const Mat<3, 3> p = matmulTN(a3, voigtToStrain<3>(ev));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      ref.push_back(p.m[i][j]);
  ref.push_back(determinant(p));

  Kokkos::View<double *, Exec::memory_space> out("out", ref.size());
  runOnDevice(spd, a3, a2, sym, out);
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  ASSERT_EQ(ref[0], 1.0);
  for (std::size_t k = 0; k < ref.size(); ++k)
    EXPECT_NEAR(h(k), ref[k], 1e-13 * std::max(1.0, std::abs(ref[k]))) << "entry " << k;
}
