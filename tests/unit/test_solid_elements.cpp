// The 3D element traits (core/ElementTraits.hpp), Hex8 and Hex20, against their definitions:
// shape functions are 1 at their own node and 0 at the others, sum to one, their derivatives
// equal central differences, they reproduce every polynomial of their space (Hex8: trilinear;
// Hex20: all quadratics and the serendipity cubic terms) exactly; the quadrature rule integrates
// the monomials it should exactly; the faces (sideNode) lie on their natural plane, run
// counter-clockwise seen from outside and, for Hex20, carry the mid-edge nodes of their edges in
// Quad8 order. The element stiffness of the generic driver (K^L with a rotated orthotropic solid)
// on a distorted Hex20 and Tet10 is symmetric with exactly the six rigid-body modes in its null
// space. Tet4 and Tet10: nodal, partition of unity, derivatives, their complete polynomial degree
// reproduced and integrated exactly by their rules, outward faces with their mid-edge nodes.
#include <kernels/ElementDriver.hpp>
#include <kernels/LinearElasticity.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <type_traits>
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

/// (b - a) x (c - a): the normal of the plane through a, b and c, pointing to the side from
/// which a, b, c run counter-clockwise.
std::array<double, 3> planeNormal(const std::array<double, 3> &a, const std::array<double, 3> &b,
                                  const std::array<double, 3> &c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
               v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
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
template <class Elem> class AnySolidElementTest : public ::testing::Test {};
template <class Elem> class TetElementTest : public ::testing::Test {};
using SolidElements = ::testing::Types<Hex8, Hex20>;
using AnySolidElements = ::testing::Types<Hex8, Hex20, Tet4, Tet10>;
using TetElements = ::testing::Types<Tet4, Tet10>;
class SolidElementNames {
public:
  template <class T> static std::string GetName(int) { return T::kName; }
};
TYPED_TEST_SUITE(SolidElementTest, SolidElements, SolidElementNames);
TYPED_TEST_SUITE(AnySolidElementTest, AnySolidElements, SolidElementNames);
TYPED_TEST_SUITE(TetElementTest, TetElements, SolidElementNames);

} // namespace

TYPED_TEST(AnySolidElementTest, ShapeFunctionsAreNodalPartitionOfUnityWithExactDerivatives) {
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
    const auto nrm =
        planeNormal(x[Elem::sideNode(f, 0)], x[Elem::sideNode(f, 1)], x[Elem::sideNode(f, 3)]);
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

TYPED_TEST(TetElementTest, ReproducesItsPolynomialSpaceAndIntegratesIt) {
  using Elem = TypeParam;
  using F = std::function<double(double, double, double)>;
  // Monomials with their integrals over the unit tetrahedron (x^a y^b z^c: a! b! c! / (a+b+c+3)!).
  struct Monomial {
    F f;
    double integral;
    int degree;
  };
  const std::vector<Monomial> space = {
      {[](double, double, double) { return 1.0; }, 1.0 / 6.0, 0},
      {[](double x, double, double) { return x; }, 1.0 / 24.0, 1},
      {[](double, double y, double) { return y; }, 1.0 / 24.0, 1},
      {[](double, double, double z) { return z; }, 1.0 / 24.0, 1},
      {[](double x, double, double) { return x * x; }, 2.0 / 120.0, 2},
      {[](double x, double y, double) { return x * y; }, 1.0 / 120.0, 2},
      {[](double, double y, double z) { return y * z; }, 1.0 / 120.0, 2},
      {[](double, double, double z) { return z * z; }, 2.0 / 120.0, 2},
  };
  const int order = Elem::kNumNodes == 4 ? 1 : 2; // the element's complete polynomial degree
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 0.33);
  for (const auto &m : space) {
    if (m.degree > order)
      continue;
    for (int trial = 0; trial < 5; ++trial) {
      const double xi[3] = {u(rng), u(rng), u(rng)};
      EXPECT_NEAR(interpolate<Elem>(m.f, xi), m.f(xi[0], xi[1], xi[2]), 1e-14);
    }
    double q = 0.0;
    for (int k = 0; k < Elem::kNumQp; ++k) {
      double xi[3], w;
      Elem::quadraturePoint(k, xi, w);
      q += w * m.f(xi[0], xi[1], xi[2]);
    }
    EXPECT_NEAR(q, m.integral, 1e-15) << "degree " << m.degree;
  }
  // A Tet4 does not reproduce x^2: the test can fail.
  if (Elem::kNumNodes == 4) {
    const double xi[3] = {0.3, 0.1, 0.2};
    EXPECT_GT(std::abs(interpolate<Elem>(space[4].f, xi) - 0.09), 0.05);
  }
}

// The mixed models' tetrahedron rules (core/ElementTraits.hpp MixedRule) integrate every monomial
// x^a y^b z^c over the unit tetrahedron exactly (a! b! c! / (a + b + c + 3)!) up to their degree,
// twice the shape functions' (the compliance mass of equal-order stresses): Tet4Mixed degree 2,
// Tet10Mixed degree 5. The displacement rules do not reach it (the check can fail).
TEST(MixedTetRule, IntegratesTwiceTheShapeFunctionsDegreeExactly) {
  const auto factorial = [](int n) { return std::tgamma(n + 1.0); };
  const auto error = [&](auto elem, int degree) {
    using Elem = decltype(elem);
    double worst = 0.0;
    for (int a = 0; a <= degree; ++a)
      for (int b = 0; a + b <= degree; ++b)
        for (int c = 0; a + b + c <= degree; ++c) {
          double q = 0.0;
          for (int k = 0; k < Elem::kNumQp; ++k) {
            double xi[3], w;
            Elem::quadraturePoint(k, xi, w);
            q += w * std::pow(xi[0], a) * std::pow(xi[1], b) * std::pow(xi[2], c);
          }
          const double exact =
              factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
          worst = std::max(worst, std::abs(q / exact - 1.0));
        }
    return worst;
  };
  EXPECT_LT(error(MixedRule<Tet4>{}, 2), 1e-14);
  EXPECT_LT(error(MixedRule<Tet10>{}, 4), 1e-14);
  EXPECT_LT(error(MixedRule<Tet10>{}, 5), 1e-14);
  EXPECT_GT(error(Tet4{}, 2), 0.1);
  EXPECT_GT(error(Tet10{}, 4), 0.01);
  static_assert(std::is_same_v<MixedRule<Hex8>, Hex8> && std::is_same_v<MixedRule<Hex20>, Hex20>,
                "the hexahedra's tensor rules integrate M exactly already");
}

TYPED_TEST(TetElementTest, FacesAreOutwardAndCarryTheirEdgesMidNodes) {
  using Elem = TypeParam;
  static_assert(Elem::Side::kNumNodes == Elem::kNodesPerSide, "a face is its Side element");
  const auto x = naturalNodes<Elem>();
  const double centre[3] = {0.25, 0.25, 0.25};
  for (int f = 0; f < Elem::kNumSides; ++f) {
    const auto &p0 = x[Elem::sideNode(f, 0)];
    const auto nrm = planeNormal(p0, x[Elem::sideNode(f, 1)], x[Elem::sideNode(f, 2)]);
    // Outward: the normal points away from the centroid.
    double out = 0.0;
    for (int i = 0; i < 3; ++i)
      out += nrm[i] * (p0[i] - centre[i]);
    EXPECT_GT(out, 0.0) << "face " << f;
    for (int k = 0; k < Elem::kNodesPerSide; ++k) { // every face node on the face's plane
      const auto &pk = x[Elem::sideNode(f, k)];
      double d = 0.0;
      for (int i = 0; i < 3; ++i)
        d += nrm[i] * (pk[i] - p0[i]);
      EXPECT_NEAR(d, 0.0, 1e-15) << "face " << f << " node " << k;
    }
    for (int k = 3; k < Elem::kNodesPerSide; ++k) { // Tri6 order: node 3 + k between k, k + 1
      const auto &m = x[Elem::sideNode(f, k)], &c0 = x[Elem::sideNode(f, k - 3)],
                 &c1 = x[Elem::sideNode(f, (k - 2) % 3)];
      for (int i = 0; i < 3; ++i)
        EXPECT_EQ(m[i], 0.5 * (c0[i] + c1[i])) << "face " << f << " node " << k;
    }
  }
}

template <class Elem> class QuadraticSolidTest : public ::testing::Test {};
using QuadraticSolids = ::testing::Types<Hex20, Tet10>;
TYPED_TEST_SUITE(QuadraticSolidTest, QuadraticSolids, SolidElementNames);

TYPED_TEST(QuadraticSolidTest, StiffnessIsSymmetricWithTheSixRigidBodyModesAsItsNullSpace) {
  using Elem = TypeParam;
  constexpr int nn = Elem::kNumNodes, nd = 3 * nn;
  using Exec = Kokkos::DefaultExecutionSpace;
  using Memory = Exec::memory_space;
  // One distorted element: the mid-edge nodes off the straight edges.
  std::mt19937 rng(13);
  const double amplitude = Elem::kSimplex ? 0.03 : 0.08;
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Kokkos::View<double *[3], Memory> xs("x", nn);
  Kokkos::View<LocalIndex **, Kokkos::LayoutRight, Memory> conn("conn", 1, nn);
  auto hx = Kokkos::create_mirror_view(xs);
  auto hc = Kokkos::create_mirror_view(conn);
  for (int a = 0; a < nn; ++a) {
    double xi[3];
    Elem::nodeNatural(a, xi);
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
  Kokkos::View<double ***, Memory> ke("ke", 1, nd, nd);
  computeLinearStiffness<Elem>(Exec(), d, ke);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
  Eigen::MatrixXd k(nd, nd);
  for (int i = 0; i < nd; ++i)
    for (int j = 0; j < nd; ++j)
      k(i, j) = h(0, i, j);
  EXPECT_LT((k - k.transpose()).norm(), 1e-12 * k.norm());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(k);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  for (int i = 0; i < 6; ++i)
    EXPECT_LT(std::abs(lambda(i)), 1e-10 * lambda(nd - 1)) << i;
  EXPECT_GT(lambda(6), 1e-6 * lambda(nd - 1)); // no spurious zero-energy mode (full rules: 3x3x3
                                               // Gauss, the 4-point tetrahedron rule)
  // The rigid-body modes are in the null space: translations and rotations about the origin.
  for (int mode = 0; mode < 6; ++mode) {
    Eigen::VectorXd v(nd);
    for (int a = 0; a < nn; ++a) {
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
