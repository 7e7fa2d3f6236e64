// The element driver (kernels/ElementDriver.hpp) in 3D with the trilinear hexahedron
// (core/ElementTraits.hpp: Hex8) on a hand-built MeshView<Memory, 3> of two distorted
// hexahedra: Hex8 shape functions partition unity and reproduce linear fields; the driver's
// stiffness with LinearElasticPoint<3> (a rotated orthotropic solid) equals a plain host
// reference (explicit 6 x 24 B, its own shape functions and 2x2x2 Gauss loop, Eigen), is
// symmetric and has the six rigid-body modes in its null space; a linear displacement field gives
// the constant stress C eps at every quadrature point.
#include <kernels/ElementDriver.hpp>
#include <kernels/Material.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

using namespace mixcon;
using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace driver_3d_tests {

/// Every element gets the same linear solid point law.
struct SolidLaw {
  LinearElasticPoint<3> point;
  KOKKOS_INLINE_FUNCTION LinearElasticPoint<3> at(LocalIndex) const { return point; }
};

/// A rotated orthotropic solid (all 21 entries of C non-zero).
SolidMatrix rotatedOrthotropicSolid() {
  OrthotropicMaterial m{
      {1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.3, 0.35, 0.8e5, 0.6e5},
      matmul(rotationAboutZ(0.7), matmul(rotationAboutX(0.4), rotationAboutY(-0.3)))};
  return m.stiffness();
}

/// Corners of the reference cube in Gmsh/VTK order (written out here, not taken from the traits).
constexpr double kCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

/// Two distorted hexahedra (16 nodes, no shared node): a unit-ish brick with every node moved
/// by up to 0.15 and a stretched, sheared one.
std::vector<std::array<double, 3>> distortedNodes() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  std::vector<std::array<double, 3>> x;
  for (int e = 0; e < 2; ++e)
    for (int a = 0; a < 8; ++a) {
      const double X = 0.5 * (kCorner[a][0] + 1), Y = 0.5 * (kCorner[a][1] + 1),
                   Z = 0.5 * (kCorner[a][2] + 1);
      if (e == 0)
        x.push_back({X + u(rng), Y + u(rng), Z + u(rng)});
      else
        x.push_back({3.0 + 2.0 * X + 0.3 * Y + u(rng), 0.5 * Y + 0.2 * Z + u(rng),
                     1.5 * Z + 0.1 * X + u(rng)});
    }
  return x;
}

MeshView<Memory, 3> makeMesh(const std::vector<std::array<double, 3>> &x) {
  MeshView<Memory, 3> m;
  const LocalIndex nn = static_cast<LocalIndex>(x.size());
  m.coordinates = Kokkos::View<double *[3], Memory>("coordinates", nn);
  m.connectivity =
      Kokkos::View<LocalIndex **, Kokkos::LayoutRight, Memory>("connectivity", nn / 8, 8);
  auto hc = Kokkos::create_mirror_view(m.coordinates);
  auto he = Kokkos::create_mirror_view(m.connectivity);
  for (LocalIndex k = 0; k < nn; ++k)
    for (int i = 0; i < 3; ++i)
      hc(k, i) = x[k][i];
  for (LocalIndex e = 0; e < nn / 8; ++e)
    for (int a = 0; a < 8; ++a)
      he(e, a) = 8 * e + a;
  Kokkos::deep_copy(m.coordinates, hc);
  Kokkos::deep_copy(m.connectivity, he);
  return m;
}

/// Host reference stiffness int B^T C B dV of one hexahedron (nodes xe, 8 x 3): trilinear shape
/// functions and the 2x2x2 Gauss rule written here, B (6 x 24) in Voigt order xx, yy, zz, yz,
/// xz, xy with engineering shear.
Eigen::MatrixXd referenceHexStiffness(const Eigen::Matrix<double, 8, 3> &xe,
                                      const Eigen::Matrix<double, 6, 6> &c) {
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(24, 24);
  const double g = 1.0 / std::sqrt(3.0);
  for (int q = 0; q < 8; ++q) {
    const double xi[3] = {(q & 1) ? g : -g, (q & 2) ? g : -g, (q & 4) ? g : -g};
    Eigen::Matrix<double, 8, 3> dn;
    for (int a = 0; a < 8; ++a)
      for (int j = 0; j < 3; ++j) {
        double v = 0.125 * kCorner[a][j];
        for (int l = 0; l < 3; ++l)
          if (l != j)
            v *= 1.0 + xi[l] * kCorner[a][l];
        dn(a, j) = v;
      }
    const Eigen::Matrix3d jac = xe.transpose() * dn; // d x_i / d xi_j
    const Eigen::Matrix<double, 8, 3> gx = dn * jac.inverse();
    Eigen::Matrix<double, 6, 24> b = Eigen::Matrix<double, 6, 24>::Zero();
    for (int a = 0; a < 8; ++a) {
      b(0, 3 * a) = gx(a, 0);
      b(1, 3 * a + 1) = gx(a, 1);
      b(2, 3 * a + 2) = gx(a, 2);
      b(3, 3 * a + 1) = gx(a, 2); // yz
      b(3, 3 * a + 2) = gx(a, 1);
      b(4, 3 * a) = gx(a, 2); // xz
      b(4, 3 * a + 2) = gx(a, 0);
      b(5, 3 * a) = gx(a, 1); // xy
      b(5, 3 * a + 1) = gx(a, 0);
    }
    k += b.transpose() * c * b * jac.determinant(); // weights 1
  }
  return k;
}

TEST(Hex8, ShapeFunctionsPartitionUnityAndReproduceLinearFields) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // A linear field x(xi) = A xi + b sampled at the nodes.
  double a[3][3], b[3], xn[8][3];
  for (int i = 0; i < 3; ++i) {
    b[i] = u(rng);
    for (int j = 0; j < 3; ++j)
      a[i][j] = u(rng);
  }
  for (int n = 0; n < 8; ++n) {
    double xa[3];
    Hex8::nodeNatural(n, xa);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(xa[i], kCorner[n][i]) << "node " << n;
      xn[n][i] = b[i] + a[i][0] * xa[0] + a[i][1] * xa[1] + a[i][2] * xa[2];
    }
  }
  for (int trial = 0; trial < 20; ++trial) {
    const double xi[3] = {u(rng), u(rng), u(rng)};
    double sh[8], dn[8][3];
    Hex8::shape(xi, sh, dn);
    double sum = 0.0, dsum[3] = {};
    for (int n = 0; n < 8; ++n) {
      sum += sh[n];
      for (int j = 0; j < 3; ++j)
        dsum[j] += dn[n][j];
    }
    EXPECT_NEAR(sum, 1.0, 1e-15);
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(dsum[j], 0.0, 1e-15);
    for (int i = 0; i < 3; ++i) {
      double v = 0.0, dv[3] = {};
      for (int n = 0; n < 8; ++n) {
        v += sh[n] * xn[n][i];
        for (int j = 0; j < 3; ++j)
          dv[j] += dn[n][j] * xn[n][i];
      }
      EXPECT_NEAR(v, b[i] + a[i][0] * xi[0] + a[i][1] * xi[1] + a[i][2] * xi[2], 1e-14);
      for (int j = 0; j < 3; ++j)
        EXPECT_NEAR(dv[j], a[i][j], 1e-14);
    }
  }
  // Kronecker property at the nodes and the quadrature rule's weights sum to the volume 8.
  for (int n = 0; n < 8; ++n) {
    double sh[8], dn[8][3];
    Hex8::shape(kCorner[n], sh, dn);
    for (int m = 0; m < 8; ++m)
      EXPECT_NEAR(sh[m], m == n ? 1.0 : 0.0, 1e-15);
  }
  double wsum = 0.0;
  for (int q = 0; q < Hex8::kNumQp; ++q) {
    double xi[3], w;
    Hex8::quadraturePoint(q, xi, w);
    wsum += w;
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(std::abs(xi[j]), 1.0 / std::sqrt(3.0), 1e-15);
  }
  EXPECT_NEAR(wsum, 8.0, 1e-14);
}

namespace {
// The single-element path, one element per thread (a free function: nvcc refuses device lambdas in
// a TEST body).
template <class Law>
void singleElementStiffness(const MeshView<Memory, 3> &mesh, const Law &law,
                            const Kokkos::View<double ***, Memory> &single) {
  Kokkos::parallel_for(
      "mixcon::test::hexSingle", Kokkos::RangePolicy<Exec>(0, single.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int nd = 24;
        double k[nd][nd];
        elementStiffness<Hex8>(mesh, 1.0, law, e, k);
        for (int i = 0; i < nd; ++i)
          for (int j = 0; j < nd; ++j)
            single(e, i, j) = k[i][j];
      });
}
} // namespace

TEST(Hex8, DriverStiffnessMatchesHostReferenceIsSymmetricWithRigidBodyNullSpace) {
  const auto nodes = distortedNodes();
  const MeshView<Memory, 3> mesh = makeMesh(nodes);
  const SolidMatrix c = rotatedOrthotropicSolid();
  const SolidLaw law{LinearElasticPoint<3>{c}};
  constexpr int nd = 24;
  // The batched (lanes) path and the single-element path.
  Kokkos::View<double ***, Memory> lanes("lanes", 2, nd, nd), single("single", 2, nd, nd);
  computeElementStiffness<Hex8>(Exec(), mesh, 1.0, law, lanes);
  singleElementStiffness(mesh, law, single);
  auto hl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), lanes);
  auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), single);
  Eigen::Matrix<double, 6, 6> ce;
  for (int r = 0; r < 6; ++r)
    for (int s = 0; s < 6; ++s)
      ce(r, s) = c.m[r][s];
  for (int e = 0; e < 2; ++e) {
    Eigen::Matrix<double, 8, 3> xe;
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i)
        xe(a, i) = nodes[8 * e + a][i];
    const Eigen::MatrixXd ref = referenceHexStiffness(xe, ce);
    const double scale = ref.cwiseAbs().maxCoeff();
    double err = 0.0, errSingle = 0.0, asym = 0.0;
    Eigen::MatrixXd k(nd, nd);
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) {
        k(i, j) = hl(e, i, j);
        err = std::max(err, std::abs(hl(e, i, j) - ref(i, j)));
        errSingle = std::max(errSingle, std::abs(hs(e, i, j) - ref(i, j)));
        asym = std::max(asym, std::abs(hl(e, i, j) - hl(e, j, i)));
      }
    EXPECT_LT(err, 1e-12 * scale) << "element " << e;
    EXPECT_LT(errSingle, 1e-12 * scale) << "element " << e;
    EXPECT_LT(asym, 1e-13 * scale) << "element " << e;
    // Rigid-body modes: translations e_i and rotations omega x x.
    for (int mode = 0; mode < 6; ++mode) {
      Eigen::VectorXd v(nd);
      for (int a = 0; a < 8; ++a) {
        const Eigen::Vector3d x = xe.row(a).transpose();
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        if (mode < 3)
          d(mode) = 1.0;
        else
          d = Eigen::Vector3d::Unit(mode - 3).cross(x);
        v.segment<3>(3 * a) = d;
      }
      EXPECT_LT((k * v).norm(), 1e-12 * scale * v.norm()) << "element " << e << " mode " << mode;
    }
    // ...and nothing else: a pure stretch is not in the null space.
    Eigen::VectorXd stretch = Eigen::VectorXd::Zero(nd);
    for (int a = 0; a < 8; ++a)
      stretch(3 * a) = xe(a, 0);
    EXPECT_GT((k * stretch).norm(), 1e-3 * scale * stretch.norm());
  }
}

TEST(Hex8, LinearDisplacementGivesConstantStress) {
  const auto nodes = distortedNodes();
  const MeshView<Memory, 3> mesh = makeMesh(nodes);
  const SolidMatrix c = rotatedOrthotropicSolid();
  const SolidLaw law{LinearElasticPoint<3>{c}};
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Mat<3, 3> grad{};
  double shift[3];
  for (int i = 0; i < 3; ++i) {
    shift[i] = u(rng);
    for (int j = 0; j < 3; ++j)
      grad.m[i][j] = u(rng);
  }
  Kokkos::View<double *, Memory> disp("u", 3 * nodes.size());
  auto hu = Kokkos::create_mirror_view(disp);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int i = 0; i < 3; ++i)
      hu(3 * k + i) = shift[i] + grad.m[i][0] * nodes[k][0] + grad.m[i][1] * nodes[k][1] +
                      grad.m[i][2] * nodes[k][2];
  Kokkos::deep_copy(disp, hu);
  Kokkos::View<double ***, Memory> stress("stress", 2, Hex8::kNumQp, 6);
  quadraturePointStress<Hex8>(Exec(), mesh, law, Kokkos::View<const double *, Memory>(disp),
                              stress);
  auto hsig = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), stress);
  // C eps with eps written out here (engineering shear, Voigt xx, yy, zz, yz, xz, xy).
  const double eps[6] = {grad.m[0][0],
                         grad.m[1][1],
                         grad.m[2][2],
                         grad.m[1][2] + grad.m[2][1],
                         grad.m[0][2] + grad.m[2][0],
                         grad.m[0][1] + grad.m[1][0]};
  double exact[6], scale = 0.0;
  for (int r = 0; r < 6; ++r) {
    exact[r] = 0.0;
    for (int s = 0; s < 6; ++s)
      exact[r] += c.m[r][s] * eps[s];
    scale = std::max(scale, std::abs(exact[r]));
  }
  for (int e = 0; e < 2; ++e)
    for (int q = 0; q < Hex8::kNumQp; ++q)
      for (int r = 0; r < 6; ++r)
        EXPECT_NEAR(hsig(e, q, r), exact[r], 1e-12 * scale)
            << "element " << e << " point " << q << " component " << r;
}

} // namespace driver_3d_tests
