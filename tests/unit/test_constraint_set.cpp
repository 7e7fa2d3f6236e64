// The device constraint set of a linear system (solver/ConstraintSet.hpp) and the tangent basis of
// local frames (solver/LocalFrames.hpp: tangentBasis<Dim>):
//  - tangentBasis, evaluated on the device for random and axis-aligned normals: in 2D exactly
//    (-n_y, n_x); in 3D two unit tangents orthogonal to n and to each other, with (n, t0, t1)
//    right-handed (n x t0 = t1), checked on the host by dot and cross products.
#include <solver/LocalFrames.hpp>

#include <gtest/gtest.h>

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
  auto ht = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tv);
  std::vector<double> out(ht.data(), ht.data() + ht.size());
  return out;
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
