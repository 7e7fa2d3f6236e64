// The mixed element driver (kernels/ElementDriver.hpp: mixedElement with the point laws of
// kernels/MixedPointPhysics.hpp):
//  - mixedIncrementElement and mixedCurrentElement (now the driver) against the hand-written 2D
//    element loops they replaced (tests/support/MixedReference.hpp), residual and Jacobian, on
//    distorted Quad4 and Quad8 meshes with random u, S, tau, a = 0 and 0.3, to 1e-12 of the
//    largest entry;
//  - the row-block assembly (assembleMixed* with MixedJacobianBlocks::NodeRows: one test node's
//    rows at a time) against the whole-element assembly, residual and assembled Jacobian;
//  - the driver's 3D (Hex8) mixed Jacobian, both forms, against central differences of its
//    residual.
#include <kernels/Nonlinear.hpp>
#include <support/KernelFixture.hpp>
#include <support/MixedReference.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

using namespace mixcon;
using namespace mixcon::test;
using Exec = Kokkos::DefaultExecutionSpace;

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace mixed_driver_tests {

/// A rotated orthotropic solid: stiffness and compliance.
OrthotropicMaterial solid() {
  return {{1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.3, 0.35, 0.8e5, 0.6e5},
          matmul(rotationAboutZ(0.7), matmul(rotationAboutX(0.4), rotationAboutY(-0.3)))};
}

// ---------------------------------------------------------------------------------------------
// 2D: the driver against the hand-written element loops it replaced.

/// The fixture's element data with compliance, on the device and as a host copy built from the
/// host mesh (HostSpace views for the reference loops).
struct MixedSetup {
  Fixture f;
  MixedElementData<Memory> d;
  MixedElementData<Kokkos::HostSpace> hd;
};

MixedSetup makeSetup(ElementType type) {
  MixedSetup s;
  s.f = makeFixture(type, 4, 3);
  s.d = mixedElementData(s.f);
  s.hd.mesh = toDevice<Kokkos::HostSpace>(s.f.mesh);
  s.hd.thickness = s.d.thickness;
  s.hd.material = Kokkos::View<int *, Kokkos::HostSpace>("material", s.f.mesh.numElements());
  for (LocalIndex e = 0; e < s.f.mesh.numElements(); ++e)
    s.hd.material(e) = s.f.elementMaterial[e];
  const std::size_t materials = s.f.materials.size();
  s.hd.stiffness = Kokkos::View<PlaneMatrix *, Kokkos::HostSpace>("stiffness", materials);
  s.hd.compliance = Kokkos::View<PlaneMatrix *, Kokkos::HostSpace>("compliance", materials);
  for (std::size_t m = 0; m < materials; ++m) {
    s.hd.stiffness(m) = s.f.materials[m];
    invert3(s.f.materials[m], s.hd.compliance(m));
  }
  return s;
}

Kokkos::View<const double *, Kokkos::HostSpace> hostCopy(const Eigen::VectorXd &v) {
  Kokkos::View<double *, Kokkos::HostSpace> h("h", v.size());
  for (int i = 0; i < v.size(); ++i)
    h(i) = v(i);
  return h;
}

template <class Elem, bool Tangent>
void compareWithReference(const MixedSetup &s, bool incremental, double a) {
  constexpr int nd = 5 * Elem::kNumNodes;
  const LocalIndex ne = s.f.mesh.numElements();
  const int nn = s.f.mesh.numNodes();
  Eigen::VectorXd x = randomVector(5 * nn, 41);
  for (int k = 0; k < nn; ++k) {
    x.segment<2>(5 * k) *= 0.03;    // displacements: strains of a few percent
    x.segment<3>(5 * k + 2) *= 1e4; // stresses
  }
  const Eigen::VectorXd tau = 1e4 * randomVector(3 * nn, 43);
  const auto dx = Kokkos::View<const double *, Memory>(toView(x));
  const auto dtau = Kokkos::View<const double *, Memory>(toView(tau));
  Kokkos::View<double **, Memory> ge("ge", ne, nd);
  Kokkos::View<double ***, Memory> ke("ke", ne, nd, nd);
  Kokkos::View<int *, Memory> ok("ok", ne);
  const MixedElementData<Memory> d = s.d;
  Kokkos::parallel_for(
      "mixcon::test::mixedDriver", Kokkos::RangePolicy<Exec>(0, ne), KOKKOS_LAMBDA(LocalIndex e) {
        double g[nd], k[nd][nd];
        const bool v = incremental ? mixedIncrementElement<Elem, Tangent>(d, dtau, dx, a, e, g, k)
                                   : mixedCurrentElement<Elem, Tangent>(d, dx, a, e, g, k);
        ok(e) = v ? 1 : 0;
        for (int i = 0; i < nd; ++i) {
          ge(e, i) = g[i];
          if (Tangent)
            for (int j = 0; j < nd; ++j)
              ke(e, i, j) = k[i][j];
        }
      });
  auto hge = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ge);
  auto hke = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
  auto hok = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ok);
  const auto hx = hostCopy(x), htau = hostCopy(tau);
  double gErr = 0.0, gScale = 0.0, kErr = 0.0, kScale = 0.0;
  for (LocalIndex e = 0; e < ne; ++e) {
    double g[nd], k[nd][nd];
    const bool v = incremental
                       ? referenceMixedIncrementElement<Elem, Tangent>(s.hd, htau, hx, a, e, g, k)
                       : referenceMixedCurrentElement<Elem, Tangent>(s.hd, hx, a, e, g, k);
    EXPECT_EQ(hok(e), v ? 1 : 0) << "element " << e;
    EXPECT_TRUE(v) << "element " << e;
    for (int i = 0; i < nd; ++i) {
      gErr = std::max(gErr, std::abs(hge(e, i) - g[i]));
      gScale = std::max(gScale, std::abs(g[i]));
      if (Tangent)
        for (int j = 0; j < nd; ++j) {
          kErr = std::max(kErr, std::abs(hke(e, i, j) - k[i][j]));
          kScale = std::max(kScale, std::abs(k[i][j]));
        }
    }
  }
  EXPECT_GT(gScale, 0.0);
  EXPECT_LT(gErr, 1e-12 * gScale) << "residual";
  if (Tangent) {
    EXPECT_GT(kScale, 0.0);
    EXPECT_LT(kErr, 1e-12 * kScale) << "Jacobian";
  }
}

template <class Elem> void compareCase(ElementType type) {
  const MixedSetup s = makeSetup(type);
  for (bool incremental : {true, false})
    for (double a : {0.0, 0.3}) {
      SCOPED_TRACE(::testing::Message()
                   << Elem::kName << (incremental ? " incremental" : " current") << " a = " << a);
      compareWithReference<Elem, true>(s, incremental, a);
      compareWithReference<Elem, false>(s, incremental, a);
    }
}

TEST(MixedElementDriver, Quad4MatchesTheHandWrittenElementLoops) {
  compareCase<Quad4>(ElementType::Quad4);
}
TEST(MixedElementDriver, Quad8MatchesTheHandWrittenElementLoops) {
  compareCase<Quad8>(ElementType::Quad8);
}

/// g and the dense Jacobian of assembleMixedIncrement / assembleMixedCurrent with `blocks`.
template <class Elem>
std::pair<Eigen::VectorXd, Eigen::MatrixXd>
assembleMixed(const MixedSetup &s, bool incremental, double a, bool tangent,
              MixedJacobianBlocks blocks, const Eigen::VectorXd &x, const Eigen::VectorXd &tau) {
  const NodeGraph graph = buildNodeGraph(s.f.mesh);
  const auto map = elementScatterMap<Memory>(s.f.mesh, graph);
  CsrMatrix<Memory> mat;
  if (tangent)
    mat = expandGraph<Memory>(graph, 5);
  Kokkos::View<double *, Memory> g("g", x.size());
  const auto dx = Kokkos::View<const double *, Memory>(toView(x));
  const auto dtau = Kokkos::View<const double *, Memory>(toView(tau));
  const LocalIndex inverted =
      incremental ? assembleMixedIncrement<Elem>(Exec(), s.d, dtau, dx, a, map, mat, g, blocks)
                  : assembleMixedCurrent<Elem>(Exec(), s.d, dx, a, map, mat, g, blocks);
  EXPECT_EQ(inverted, -1);
  return {toEigen(g), tangent ? toDense(mat) : Eigen::MatrixXd()};
}

template <class Elem> void rowBlocksCase(ElementType type) {
  const MixedSetup s = makeSetup(type);
  const int nn = s.f.mesh.numNodes();
  Eigen::VectorXd x = randomVector(5 * nn, 61);
  for (int k = 0; k < nn; ++k) {
    x.segment<2>(5 * k) *= 0.03;
    x.segment<3>(5 * k + 2) *= 1e4;
  }
  const Eigen::VectorXd tau = 1e4 * randomVector(3 * nn, 63);
  for (bool incremental : {true, false})
    for (double a : {0.0, 0.3})
      for (bool tangent : {true, false}) {
        SCOPED_TRACE(::testing::Message()
                     << Elem::kName << (incremental ? " incremental" : " current") << " a = " << a
                     << (tangent ? " tangent" : " residual"));
        const auto whole =
            assembleMixed<Elem>(s, incremental, a, tangent, MixedJacobianBlocks::Element, x, tau);
        const auto rows =
            assembleMixed<Elem>(s, incremental, a, tangent, MixedJacobianBlocks::NodeRows, x, tau);
        EXPECT_GT(whole.first.cwiseAbs().maxCoeff(), 0.0);
        EXPECT_LT(relativeError(rows.first, whole.first), 1e-12);
        if (tangent) {
          EXPECT_GT(whole.second.cwiseAbs().maxCoeff(), 0.0);
          EXPECT_LT(relativeError(rows.second, whole.second), 1e-12);
        }
      }
}

TEST(MixedElementDriver, Quad4RowBlockAssemblyEqualsElementAssembly) {
  rowBlocksCase<Quad4>(ElementType::Quad4);
}
TEST(MixedElementDriver, Quad8RowBlockAssemblyEqualsElementAssembly) {
  rowBlocksCase<Quad8>(ElementType::Quad8);
}

// ---------------------------------------------------------------------------------------------
// 3D: the Hex8 mixed Jacobian against central differences of the residual.

template <class Point> struct UniformLaw {
  Point point;
  KOKKOS_INLINE_FUNCTION Point at(LocalIndex) const { return point; }
};

MeshView<Memory, 3> distortedHex() {
  constexpr double corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                   {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.12, 0.12);
  MeshView<Memory, 3> m;
  m.coordinates = Kokkos::View<double *[3], Memory>("coordinates", 8);
  m.connectivity = Kokkos::View<LocalIndex **, Kokkos::LayoutRight, Memory>("connectivity", 1, 8);
  auto hc = Kokkos::create_mirror_view(m.coordinates);
  auto he = Kokkos::create_mirror_view(m.connectivity);
  for (int a = 0; a < 8; ++a) {
    hc(a, 0) = 0.6 * (corner[a][0] + 1) + 0.1 * corner[a][1] + u(rng);
    hc(a, 1) = 0.5 * (corner[a][1] + 1) + u(rng);
    hc(a, 2) = 0.4 * (corner[a][2] + 1) + 0.05 * corner[a][0] + u(rng);
    he(0, a) = a;
  }
  Kokkos::deep_copy(m.coordinates, hc);
  Kokkos::deep_copy(m.connectivity, he);
  return m;
}

template <bool Tangent, class Law>
Eigen::MatrixXd hexElement(const MeshView<Memory, 3> &mesh, const Law &law,
                           const Eigen::VectorXd &x, const Eigen::VectorXd &tau,
                           Eigen::VectorXd &g) {
  constexpr int nd = 9 * 8;
  const auto dx = Kokkos::View<const double *, Memory>(toView(x));
  const auto dtau = Kokkos::View<const double *, Memory>(toView(tau));
  Kokkos::View<double *, Memory> ge("ge", nd);
  Kokkos::View<double **, Memory> ke("ke", nd, nd);
  Kokkos::View<int *, Memory> ok("ok", 1);
  Kokkos::parallel_for(
      "mixcon::test::hexMixed", Kokkos::RangePolicy<Exec>(0, 1), KOKKOS_LAMBDA(LocalIndex e) {
        double gl[nd], kl[nd][nd];
        ok(0) = mixedElement<Hex8, Tangent>(mesh, 1.0, law, dx, dtau, e, gl, kl) ? 1 : 0;
        for (int i = 0; i < nd; ++i) {
          ge(i) = gl[i];
          if (Tangent)
            for (int j = 0; j < nd; ++j)
              ke(i, j) = kl[i][j];
        }
      });
  auto hg = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ge);
  auto hk = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
  auto hok = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ok);
  EXPECT_EQ(hok(0), 1);
  g.resize(nd);
  Eigen::MatrixXd k(nd, nd);
  for (int i = 0; i < nd; ++i) {
    g(i) = hg(i);
    for (int j = 0; j < nd; ++j)
      k(i, j) = hk(i, j);
  }
  return k;
}

/// Residuals of the element at every column of xs (one kernel launch, one column per work item).
template <class Law>
Eigen::MatrixXd hexResiduals(const MeshView<Memory, 3> &mesh, const Law &law,
                             const Eigen::MatrixXd &xs, const Eigen::VectorXd &tau) {
  constexpr int nd = 9 * 8;
  const int cols = static_cast<int>(xs.cols());
  Kokkos::View<double **, Kokkos::LayoutRight, Memory> dxs("xs", cols, nd);
  auto hx = Kokkos::create_mirror_view(dxs);
  for (int c = 0; c < cols; ++c)
    for (int i = 0; i < nd; ++i)
      hx(c, i) = xs(i, c);
  Kokkos::deep_copy(dxs, hx);
  const auto dtau = Kokkos::View<const double *, Memory>(toView(tau));
  Kokkos::View<double **, Kokkos::LayoutRight, Memory> ge("ge", cols, nd);
  Kokkos::View<int *, Memory> ok("ok", cols);
  Kokkos::parallel_for(
      "mixcon::test::hexResiduals", Kokkos::RangePolicy<Exec>(0, cols), KOKKOS_LAMBDA(int c) {
        const Kokkos::View<const double *, Memory> x(&dxs(c, 0), nd);
        double gl[nd], kl[nd][nd];
        ok(c) = mixedElement<Hex8, false>(mesh, 1.0, law, x, dtau, 0, gl, kl) ? 1 : 0;
        for (int i = 0; i < nd; ++i)
          ge(c, i) = gl[i];
      });
  auto hg = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ge);
  auto hok = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ok);
  Eigen::MatrixXd g(nd, cols);
  for (int c = 0; c < cols; ++c) {
    EXPECT_EQ(hok(c), 1);
    for (int i = 0; i < nd; ++i)
      g(i, c) = hg(c, i);
  }
  return g;
}

template <class Point> void hexJacobianCase(double a) {
  using L = FieldLayout<3>;
  const MeshView<Memory, 3> mesh = distortedHex();
  const UniformLaw<Point> law{Point{solid().stiffness(), solid().compliance(), a}};
  Eigen::VectorXd x = randomVector(9 * 8, 51), tau = 1e4 * randomVector(6 * 8, 53);
  for (int k = 0; k < 8; ++k) {
    x.segment<3>(L::mixedDisplacementDof(k, 0)) *= 0.03;
    x.segment<6>(L::mixedStressDof(k, 0)) *= 1e4;
  }
  Eigen::VectorXd g;
  const Eigen::MatrixXd k = hexElement<true>(mesh, law, x, tau, g);
  // Columns: x, then x + step e_j and x - step e_j for every unknown j.
  const int nd = static_cast<int>(x.size());
  Eigen::MatrixXd xs(nd, 1 + 2 * nd);
  Eigen::VectorXd steps(nd);
  xs.col(0) = x;
  for (int j = 0; j < nd; ++j) {
    steps(j) = j % 9 >= 3 ? 1e-2 : 1e-7; // stresses of order 1e4, coordinates of order 1
    xs.col(1 + 2 * j) = x;
    xs.col(2 + 2 * j) = x;
    xs(j, 1 + 2 * j) += steps(j);
    xs(j, 2 + 2 * j) -= steps(j);
  }
  const Eigen::MatrixXd gs = hexResiduals(mesh, law, xs, tau);
  EXPECT_LT((g - gs.col(0)).cwiseAbs().maxCoeff(), 1e-14 * g.cwiseAbs().maxCoeff());
  Eigen::MatrixXd fd(nd, nd);
  for (int j = 0; j < nd; ++j)
    fd.col(j) = (gs.col(1 + 2 * j) - gs.col(2 + 2 * j)) / (2 * steps(j));
  // Column blocks of very different scales: compare each (row block, column block) against its
  // own largest entry.
  for (int rb = 0; rb < 2; ++rb)
    for (int cb = 0; cb < 2; ++cb) {
      double err = 0.0, scale = 0.0;
      for (int i = 0; i < k.rows(); ++i)
        for (int j = 0; j < k.cols(); ++j)
          if ((i % 9 >= 3) == (rb == 1) && (j % 9 >= 3) == (cb == 1)) {
            err = std::max(err, std::abs(k(i, j) - fd(i, j)));
            scale = std::max(scale, std::abs(k(i, j)));
          }
      EXPECT_GT(scale, 0.0) << "block " << rb << cb;
      EXPECT_LT(err, 1e-6 * scale) << "block " << rb << cb;
    }
}

TEST(MixedElementDriver, Hex8IncrementJacobianMatchesFiniteDifferences) {
  hexJacobianCase<MixedIncrementPoint<3>>(0.0);
  hexJacobianCase<MixedIncrementPoint<3>>(0.3);
}
TEST(MixedElementDriver, Hex8CurrentJacobianMatchesFiniteDifferences) {
  hexJacobianCase<MixedCurrentPoint<3>>(0.0);
  hexJacobianCase<MixedCurrentPoint<3>>(0.3);
}

} // namespace mixed_driver_tests
