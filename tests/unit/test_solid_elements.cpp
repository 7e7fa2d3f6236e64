// The 3D element traits (core/ElementTraits.hpp), Hex8 and Hex20, against their definitions:
// shape functions are 1 at their own node and 0 at the others, sum to one, their derivatives
// equal central differences, they reproduce every polynomial of their space (Hex8: trilinear;
// Hex20: all quadratics and the serendipity cubic terms) exactly; the quadrature rule integrates
// the monomials it should exactly; the faces (sideNode) lie on their natural plane, run
// counter-clockwise seen from outside and, for Hex20, carry the mid-edge nodes of their edges in
// Quad8 order. The element stiffness of the generic driver (K^L with a rotated orthotropic solid)
// on a distorted Hex20 is symmetric with exactly the six rigid-body modes in its null space.
#include <kernels/ElementDriver.hpp>
#include <kernels/LinearElasticity.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

using namespace mixcon;

namespace {

template <class Elem> std::vector<std::array<double, 3>> naturalNodes() {
  std::vector<std::array<double, 3>> x(Elem::kNumNodes);
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    double xi[3];
    Elem::nodeNatural(a, xi);
    x[a] = {xi[0], xi[1], xi[2]};
  }
  return x;
}

/// Interpolation of f through the nodes, evaluated at xi.
template <class Elem>
double interpolate(const std::function<double(double, double, double)> &f, const double (&xi)[3]) {
  double n[Elem::kNumNodes], dn[Elem::kNumNodes][3];
  Elem::shape(xi, n, dn);
  double v = 0.0;
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    double xa[3];
    Elem::nodeNatural(a, xa);
    v += n[a] * f(xa[0], xa[1], xa[2]);
  }
  return v;
}

template <class Elem> class SolidElementTest : public ::testing::Test {};
using SolidElements = ::testing::Types<Hex8, Hex20>;
class SolidElementNames {
public:
  template <class T> static std::string GetName(int) { return T::kName; }
};
TYPED_TEST_SUITE(SolidElementTest, SolidElements, SolidElementNames);

} // namespace

TYPED_TEST(SolidElementTest, ShapeFunctionsAreNodalPartitionOfUnityWithExactDerivatives) {
  using Elem = TypeParam;
  constexpr int n = Elem::kNumNodes;
  const auto nodes = naturalNodes<Elem>();
  for (int b = 0; b < n; ++b) {
    const double xi[3] = {nodes[b][0], nodes[b][1], nodes[b][2]};
    double sh[n], dn[n][3];
    Elem::shape(xi, sh, dn);
    for (int a = 0; a < n; ++a)
      EXPECT_NEAR(sh[a], a == b ? 1.0 : 0.0, 1e-14) << "N_" << a << " at node " << b;
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const double xi[3] = {u(rng), u(rng), u(rng)};
    double sh[n], dn[n][3];
    Elem::shape(xi, sh, dn);
    double sum = 0.0, dsum[3] = {};
    for (int a = 0; a < n; ++a) {
      sum += sh[a];
      for (int i = 0; i < 3; ++i)
        dsum[i] += dn[a][i];
    }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(dsum[i], 0.0, 1e-13);
      const double h = 1e-6;
      double xp[3] = {xi[0], xi[1], xi[2]}, xm[3] = {xi[0], xi[1], xi[2]};
      xp[i] += h;
      xm[i] -= h;
      double np[n], nm[n], unused[n][3];
      Elem::shape(xp, np, unused);
      Elem::shape(xm, nm, unused);
      for (int a = 0; a < n; ++a)
        EXPECT_NEAR(dn[a][i], (np[a] - nm[a]) / (2 * h), 1e-8) << "dN_" << a << "/dxi_" << i;
    }
  }
}

TYPED_TEST(SolidElementTest, ReproducesItsPolynomialSpace) {
  using Elem = TypeParam;
  using F = std::function<double(double, double, double)>;
  std::vector<F> space = {
      [](double, double, double) { return 1.0; },
      [](double x, double, double) { return x; },
      [](double, double y, double) { return y; },
      [](double, double, double z) { return z; },
      [](double x, double y, double) { return x * y; },
      [](double, double y, double z) { return y * z; },
      [](double x, double, double z) { return x * z; },
      [](double x, double y, double z) { return x * y * z; },
  };
  if (Elem::kNumNodes == 20) { // the serendipity space: the quadratics and x^2 y, x y^2, ...
    space.push_back([](double x, double, double) { return x * x; });
    space.push_back([](double, double y, double) { return y * y; });
    space.push_back([](double, double, double z) { return z * z; });
    space.push_back([](double x, double y, double) { return x * x * y; });
    space.push_back([](double x, double y, double z) { return x * y * y * z; });
    space.push_back([](double x, double, double z) { return x * z * z; });
  }
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t k = 0; k < space.size(); ++k)
    for (int trial = 0; trial < 10; ++trial) {
      const double xi[3] = {u(rng), u(rng), u(rng)};
      EXPECT_NEAR(interpolate<Elem>(space[k], xi), space[k](xi[0], xi[1], xi[2]), 1e-13)
          << "monomial " << k;
    }
  // Not in the space: a Hex8 does not reproduce x^2 (a check that the test can fail).
  if (Elem::kNumNodes == 8) {
    const double xi[3] = {0.3, 0.1, -0.2};
    EXPECT_GT(
        std::abs(interpolate<Elem>([](double x, double, double) { return x * x; }, xi) - 0.09),
        0.5);
  }
}

TYPED_TEST(SolidElementTest, QuadratureIsExactToItsDegree) {
  using Elem = TypeParam;
  const int degree = 2 * Elem::kGaussOrder - 1; // per direction
  double sum = 0.0, mono = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double xi[3], w;
    Elem::quadraturePoint(q, xi, w);
    sum += w;
    mono += w * std::pow(xi[0], degree - 1) * std::pow(xi[1], degree - 1) * xi[2] * xi[2];
  }
  EXPECT_NEAR(sum, 8.0, 1e-14);
  EXPECT_NEAR(mono, (2.0 / degree) * (2.0 / degree) * (2.0 / 3.0), 1e-14);
}

TYPED_TEST(SolidElementTest, FacesLieOnTheirPlaneAndRunCounterClockwiseFromOutside) {
  using Elem = TypeParam;
  using Side = typename Elem::Side;
  static_assert(Side::kNumNodes == Elem::kNodesPerSide, "a face is its Side element");
  const auto x = naturalNodes<Elem>();
  std::vector<int> seen(Elem::kNumNodes, 0);
  for (int f = 0; f < Elem::kNumSides; ++f) {
    // Corners 0, 1, 3 of the face: (x1 - x0) x (x3 - x0) is its outward normal.
    const auto &p0 = x[Elem::sideNode(f, 0)], &p1 = x[Elem::sideNode(f, 1)],
               &p3 = x[Elem::sideNode(f, 3)];
    const double a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]},
                 b[3] = {p3[0] - p0[0], p3[1] - p0[1], p3[2] - p0[2]};
    const double nrm[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]};
    int axis = 0;
    for (int i = 1; i < 3; ++i)
      if (std::abs(nrm[i]) > std::abs(nrm[axis]))
        axis = i;
    const double side = nrm[axis] > 0 ? 1.0 : -1.0;
    for (int i = 0; i < 3; ++i) {
      if (i != axis) {
        EXPECT_NEAR(nrm[i], 0.0, 1e-14) << "face " << f;
      }
    }
    for (int k = 0; k < Elem::kNodesPerSide; ++k) {
      const int a = Elem::sideNode(f, k);
      ASSERT_GE(a, 0);
      ASSERT_LT(a, Elem::kNumNodes);
      ++seen[a];
      EXPECT_EQ(x[a][axis], side) << "face " << f << " node " << a << ": on the outward side";
    }
    // Quad8 order: node 4 + k is the middle of corners k and k + 1.
    for (int k = 4; k < Elem::kNodesPerSide; ++k) {
      const auto &m = x[Elem::sideNode(f, k)], &c0 = x[Elem::sideNode(f, k - 4)],
                 &c1 = x[Elem::sideNode(f, (k - 3) % 4)];
      for (int i = 0; i < 3; ++i)
        EXPECT_EQ(m[i], 0.5 * (c0[i] + c1[i])) << "face " << f << " node " << k;
    }
  }
  // Every node is on some face: corners on three, mid-edge nodes on two.
  for (int a = 0; a < Elem::kNumNodes; ++a)
    EXPECT_EQ(seen[a], a < 8 ? 3 : 2) << "node " << a;
}

TEST(Hex20Stiffness, SymmetricWithTheSixRigidBodyModesAsItsNullSpace) {
  using Exec = Kokkos::DefaultExecutionSpace;
  using Memory = Exec::memory_space;
  // One distorted Hex20: the mid-edge nodes off the straight edges.
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.08, 0.08);
  Kokkos::View<double *[3], Memory> xs("x", 20);
  Kokkos::View<LocalIndex **, Kokkos::LayoutRight, Memory> conn("conn", 1, 20);
  auto hx = Kokkos::create_mirror_view(xs);
  auto hc = Kokkos::create_mirror_view(conn);
  for (int a = 0; a < 20; ++a) {
    double xi[3];
    Hex20::nodeNatural(a, xi);
    hx(a, 0) = 1.0 + 0.7 * xi[0] + 0.1 * xi[1] + u(rng);
    hx(a, 1) = 0.5 * xi[1] + 0.05 * xi[2] + u(rng);
    hx(a, 2) = 0.8 * xi[2] + 0.1 * xi[0] + u(rng);
    hc(0, a) = a;
  }
  Kokkos::deep_copy(xs, hx);
  Kokkos::deep_copy(conn, hc);
  ElementData<Memory, 3> d;
  d.mesh.coordinates = xs;
  d.mesh.connectivity = conn;
  d.material = Kokkos::View<int *, Memory>("material", 1);
  d.stiffness = Kokkos::View<SolidMatrix *, Memory>("stiffness", 1);
  auto hs = Kokkos::create_mirror_view(d.stiffness);
  hs(0) = OrthotropicMaterial{{1.6e3, 1.1e2, 0.9e2, 1.0e2, 0.4, 0.3, 0.35, 0.8e2, 0.6e2},
                              matmul(rotationAboutZ(0.7), rotationAboutX(0.4))}
              .stiffness();
  Kokkos::deep_copy(d.stiffness, hs);
  Kokkos::View<double ***, Memory> ke("ke", 1, 60, 60);
  computeLinearStiffness<Hex20>(Exec(), d, ke);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
  Eigen::MatrixXd k(60, 60);
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j)
      k(i, j) = h(0, i, j);
  EXPECT_LT((k - k.transpose()).norm(), 1e-12 * k.norm());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(k);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  for (int i = 0; i < 6; ++i)
    EXPECT_LT(std::abs(lambda(i)), 1e-10 * lambda(59)) << i;
  EXPECT_GT(lambda(6), 1e-6 * lambda(59)); // no spurious zero-energy mode (full 3x3x3 rule)
  // The rigid-body modes are in the null space: translations and rotations about the origin.
  for (int mode = 0; mode < 6; ++mode) {
    Eigen::VectorXd v(60);
    for (int a = 0; a < 20; ++a) {
      const double p[3] = {hx(a, 0), hx(a, 1), hx(a, 2)};
      for (int c = 0; c < 3; ++c)
        v(3 * a + c) = mode < 3 ? (c == mode ? 1.0 : 0.0)
                                : (c == (mode - 3 + 1) % 3   ? -p[(mode - 3 + 2) % 3]
                                   : c == (mode - 3 + 2) % 3 ? p[(mode - 3 + 1) % 3]
                                                             : 0.0);
    }
    EXPECT_LT((k * v).norm(), 1e-10 * k.norm() * v.norm()) << "mode " << mode;
  }
}
