// Batched element kernels (kernels/LinearElasticity.hpp) and CSR assembly against the host
// reference implementation (tests/support/Reference.hpp), with tolerance ~10 eps * scale.
#include <kernels/LinearElasticity.hpp>
#include <mesh/Generators.hpp>
#include <support/KernelFixture.hpp>
#include <support/Reference.hpp>

#include <support/Params.hpp>

#include <gtest/gtest.h>

#include <set>
#include <utility>
#include <vector>

using namespace mixcon;
using namespace mixcon::test;
using Exec = Kokkos::DefaultExecutionSpace;

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace kernel_tests {

/// Body force f = (x + 2y, 3 - x) at the quadrature points xq, on the device. A named function
/// template, so that the device lambda is not defined inside a generic lambda (nvcc rejects that).
template <class Elem>
void fillBodyForce(const Kokkos::View<double **[2], Memory> &xq,
                   const Kokkos::View<double **[2], Memory> &fq) {
  Kokkos::parallel_for(
      "mixcon::test::fillBodyForce", Kokkos::RangePolicy<Exec>(0, xq.extent(0)),
      KOKKOS_LAMBDA(int e) {
        for (int q = 0; q < Elem::kNumQp; ++q) {
          fq(e, q, 0) = xq(e, q, 0) + 2 * xq(e, q, 1);
          fq(e, q, 1) = 3 - xq(e, q, 0);
        }
      });
}

Eigen::MatrixXd referenceElement(const Fixture &f, LocalIndex e) {
  return test::referenceStiffness(test::elementCoordinates(f.mesh, e),
                                  test::toEigen(f.materials[f.elementMaterial[e]]),
                                  f.data.thickness);
}

/// Element matrices of all elements from the batched kernel, copied to the host.
template <class Elem> auto kernelElementMatrices(const Fixture &f) {
  constexpr int nd = 2 * Elem::kNumNodes;
  Kokkos::View<double ***, Memory> ke("ke", f.mesh.numElements(), nd, nd);
  computeLinearStiffness<Elem>(Exec(), f.data, ke);
  return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
}

} // namespace kernel_tests
using namespace kernel_tests;

class KernelTest : public ::testing::TestWithParam<ElementType> {};
INSTANTIATE_TEST_SUITE_P(Elements, KernelTest, test::bothElements(), test::elementName);

TEST_P(KernelTest, ElementStiffnessMatchesHostReference) {
  const Fixture f = makeFixture(GetParam());
  dispatchPlaneElement(GetParam(), "this 2D test", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int nd = 2 * Elem::kNumNodes;
    const auto h = kernelElementMatrices<Elem>(f);
    for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
      const Eigen::MatrixXd ref = referenceElement(f, e);
      const double scale = ref.cwiseAbs().maxCoeff();
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j)
          ASSERT_NEAR(h(e, i, j), ref(i, j), 10 * 2.2e-16 * scale * nd)
              << "element " << e << " entry " << i << "," << j;
    }
  });
}

TEST_P(KernelTest, ElementStiffnessHasExactlyThreeRigidBodyModes) {
  const Fixture f = makeFixture(GetParam());
  dispatchPlaneElement(GetParam(), "this 2D test", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int nd = 2 * Elem::kNumNodes;
    const auto h = kernelElementMatrices<Elem>(f);
    Eigen::MatrixXd m(nd, nd);
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j)
        m(i, j) = h(3, i, j);
    EXPECT_NEAR((m - m.transpose()).norm(), 0.0, 1e-12 * m.norm());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
    const auto ev = eig.eigenvalues();
    const double top = ev.maxCoeff();
    int zero = 0;
    for (int i = 0; i < nd; ++i)
      zero += std::abs(ev(i)) < 1e-10 * top;
    EXPECT_EQ(zero, 3) << "two translations and one rotation, no spurious modes";
  });
}

TEST_P(KernelTest, AssembledMatrixMatchesDenseReferenceAssembly) {
  const Fixture f = makeFixture(GetParam(), 4, 3);
  const NodeGraph g = buildNodeGraph(f.mesh);
  auto a = expandGraph<Memory>(g, 2);
  const auto map = elementScatterMap<Memory>(f.mesh, g);
  dispatchPlaneElement(GetParam(), "this 2D test", [&](auto elem) {
    assembleLinearStiffness<decltype(elem)>(Exec(), f.data, map, a);
  });
  const int n = 2 * f.mesh.numNodes();
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
    const Eigen::MatrixXd k = referenceElement(f, e);
    for (int p = 0; p < f.mesh.nodesPerElement; ++p)
      for (int q = 0; q < f.mesh.nodesPerElement; ++q)
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j)
            dense(2 * f.mesh.node(e, p) + i, 2 * f.mesh.node(e, q) + j) += k(2 * p + i, 2 * q + j);
  }
  auto ro = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.rowOffsets);
  auto co = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.columns);
  auto va = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.values);
  Eigen::MatrixXd fromCsr = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (Offset k = ro(i); k < ro(i + 1); ++k) {
      fromCsr(i, co(k)) += va(k);
      if (k > ro(i)) {
        ASSERT_LT(co(k - 1), co(k)) << "columns sorted and unique";
      }
    }
  }
  const double scale = dense.cwiseAbs().maxCoeff();
  EXPECT_LT((fromCsr - dense).cwiseAbs().maxCoeff(), 100 * 2.2e-16 * scale);
  // The pattern is exactly the pairs of unknowns whose nodes share an element, computed by brute
  // force from the connectivity: nothing dropped, nothing extra.
  std::set<std::pair<int, int>> coupled, pattern;
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e)
    for (int p = 0; p < f.mesh.nodesPerElement; ++p)
      for (int q = 0; q < f.mesh.nodesPerElement; ++q)
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j)
            coupled.insert({2 * f.mesh.node(e, p) + i, 2 * f.mesh.node(e, q) + j});
  for (int i = 0; i < n; ++i)
    for (Offset k = ro(i); k < ro(i + 1); ++k)
      pattern.insert({i, static_cast<int>(co(k))});
  EXPECT_EQ(ro(n), a.numNonzeros());
  EXPECT_EQ(a.numNonzeros(), static_cast<Offset>(coupled.size()));
  EXPECT_TRUE(pattern == coupled) << pattern.size() << " pattern entries, " << coupled.size()
                                  << " coupled pairs of unknowns";
}

TEST_P(KernelTest, BodyForceAndInternalForceMatchReference) {
  const Fixture f = makeFixture(GetParam());
  const int n = 2 * f.mesh.numNodes();
  dispatchPlaneElement(GetParam(), "this 2D test", [&](auto elem) {
    using Elem = decltype(elem);
    // Body force f = (x + 2y, 3 - x) at the quadrature points.
    Kokkos::View<double **[2], Memory> xq("xq", f.mesh.numElements(), Elem::kNumQp);
    quadraturePointCoordinates<Elem>(Exec(), f.data.mesh, xq);
    Kokkos::View<double **[2], Memory> fq("fq", f.mesh.numElements(), Elem::kNumQp);
    fillBodyForce<Elem>(xq, fq);
    Kokkos::View<double *, Memory> rhs("rhs", n);
    assembleBodyForce<Elem>(Exec(), f.data, Kokkos::View<const double **[2], Memory>(fq), rhs);
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), rhs);
    Eigen::VectorXd ref = Eigen::VectorXd::Zero(n);
    for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
      const Eigen::MatrixXd xe = test::elementCoordinates(f.mesh, e);
      for (const auto &g : test::referenceGauss(Elem::kGaussOrder)) {
        Eigen::VectorXd sh;
        Eigen::MatrixXd dn;
        test::referenceShape(Elem::kNumNodes, g[0], g[1], sh, dn);
        const Eigen::Matrix2d j = xe.transpose() * dn;
        const Eigen::Vector2d x = xe.transpose() * sh;
        for (int a = 0; a < Elem::kNumNodes; ++a) {
          const double w = sh(a) * g[2] * j.determinant() * f.data.thickness;
          ref(2 * f.mesh.node(e, a)) += w * (x(0) + 2 * x(1));
          ref(2 * f.mesh.node(e, a) + 1) += w * (3 - x(0));
        }
      }
    }
    for (int i = 0; i < n; ++i)
      EXPECT_NEAR(h(i), ref(i), 1e-13 * ref.cwiseAbs().maxCoeff());

    // Internal force K u for a random u equals the assembled reference product.
    Kokkos::View<double *, Memory> u("u", n), fi("fi", n);
    auto hu = Kokkos::create_mirror_view(u);
    Eigen::VectorXd eu(n);
    for (int i = 0; i < n; ++i)
      hu(i) = eu(i) = std::sin(1.7 * i + 0.3);
    Kokkos::deep_copy(u, hu);
    assembleInternalForce<Elem>(Exec(), f.data, Kokkos::View<const double *, Memory>(u), fi);
    auto hf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fi);
    Eigen::VectorXd rf = Eigen::VectorXd::Zero(n);
    for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
      const Eigen::MatrixXd k = referenceElement(f, e);
      Eigen::VectorXd ue(2 * Elem::kNumNodes);
      for (int a = 0; a < Elem::kNumNodes; ++a)
        for (int c = 0; c < 2; ++c)
          ue(2 * a + c) = eu(2 * f.mesh.node(e, a) + c);
      const Eigen::VectorXd fe = k * ue;
      for (int a = 0; a < Elem::kNumNodes; ++a)
        for (int c = 0; c < 2; ++c)
          rf(2 * f.mesh.node(e, a) + c) += fe(2 * a + c);
    }
    for (int i = 0; i < n; ++i)
      EXPECT_NEAR(hf(i), rf(i), 1e-12 * rf.cwiseAbs().maxCoeff());
  });
}

TEST_P(KernelTest, EdgeLoadsIntegrateTractionAndPressure) {
  // Quarter annulus, pressure p on the inner arc plus a uniform traction (0.25, -0.5). The
  // pressure acts against the body's outward normal, which on the inner arc points towards the
  // origin, so its resultant p a t (1, 1) points away from it.
  const double a = 1.0, p = 3.0, t = 0.5;
  Mesh mesh = quarterAnnulusMesh(a, 2.0, 2, 32, GetParam());
  const auto dev = toDevice<Memory>(mesh);
  const auto &edges = mesh.boundaries.at("inner");
  const auto batch = uniformEdgeLoads<Memory>(edges, 0.25, -0.5, p);
  Kokkos::View<double *, Memory> rhs("rhs", 2 * mesh.numNodes());
  dispatchPlaneElement(GetParam(), "this 2D test", [&](auto elem) {
    assembleEdgeLoads<decltype(elem)>(Exec(), dev, batch.edges, batch.load, t, rhs);
  });
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), rhs);
  double fx = 0, fy = 0;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
    fx += h(2 * n);
    fy += h(2 * n + 1);
  }
  // Exact: pressure resultant p a t on each axis; traction times the arc length pi a / 2 times t.
  // The arc is approximated by the element edges: straight chords (Quad4) or parabolas (Quad8).
  const double tol = GetParam() == ElementType::Quad8 ? 1e-5 : 2e-3;
  EXPECT_NEAR(fx, p * a * t + 0.25 * M_PI * a / 2 * t, tol);
  EXPECT_NEAR(fy, p * a * t - 0.5 * M_PI * a / 2 * t, tol);
}

TEST_P(KernelTest, StressRecoveryIsExactForLinearDisplacement) {
  const Fixture f = makeFixture(GetParam());
  const int n = 2 * f.mesh.numNodes();
  Kokkos::View<double *, Memory> u("u", n);
  auto hu = Kokkos::create_mirror_view(u);
  // u = (1e-3 x + 2e-3 y, -5e-4 x + 4e-4 y): eps = (1e-3, 4e-4, 1.5e-3).
  for (LocalIndex i = 0; i < f.mesh.numNodes(); ++i) {
    hu(2 * i) = 1e-3 * f.mesh.x(i) + 2e-3 * f.mesh.y(i);
    hu(2 * i + 1) = -5e-4 * f.mesh.x(i) + 4e-4 * f.mesh.y(i);
  }
  Kokkos::deep_copy(u, hu);
  const double eps[3] = {1e-3, 4e-4, 1.5e-3};
  Kokkos::View<double *[3], Memory> nodal("nodal", f.mesh.numNodes());
  dispatchPlaneElement(GetParam(), "this 2D test", [&](auto elem) {
    using Elem = decltype(elem);
    Kokkos::View<double **[3], Memory> gp("gp", f.mesh.numElements(), Elem::kNumQp);
    gaussPointStress<Elem>(Exec(), f.data, Kokkos::View<const double *, Memory>(u), gp);
    auto hg = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), gp);
    for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
      double sig[3];
      applyStiffness(f.materials[f.elementMaterial[e]], eps, sig);
      for (int q = 0; q < Elem::kNumQp; ++q)
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(hg(e, q, c), sig[c], 1e-9 * std::abs(sig[0]));
    }
  });
  // Single material, so that the nodal average of a constant stress is that stress.
  ElementData<Memory> one = f.data;
  one.material = Kokkos::View<int *, Memory>("zero", f.mesh.numElements());
  dispatchPlaneElement(GetParam(), "this 2D test", [&](auto elem) {
    nodalStressRecovery<decltype(elem)>(Exec(), one, Kokkos::View<const double *, Memory>(u),
                                        nodal);
  });
  auto hn = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), nodal);
  double sig[3];
  applyStiffness(f.materials[0], eps, sig);
  for (LocalIndex i = 0; i < f.mesh.numNodes(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(hn(i, c), sig[c], 1e-9 * std::abs(sig[0])) << "node " << i;
}

// The node graph, its expansion and the element scatter map are built on the host's threads, a
// node graph row by chunks of nodes: on a mesh of several chunks (9,261 nodes of Hex8, and Tet10's
// 9,261 with 6 tetrahedra per cell) against the connectivity by brute force (each node's
// neighbours as a set), the second-neighbour graph against the neighbours' neighbours (every 7th
// node), the expansion against its definition (node I's rows (I, c) list, for each
// neighbour J in order, J's columnDofs unknowns) and the map against the graph's own rows.
TEST(NodeGraph, ThreadedBuildMatchesTheConnectivityAcrossChunks) {
  for (ElementType type : {ElementType::Hex8, ElementType::Tet10}) {
    const int n = type == ElementType::Hex8 ? 20 : 10;
    const Mesh mesh = boxMesh(1.0, 1.0, 1.0, n, n, n, type);
    ASSERT_GT(mesh.numNodes(), 2 * 4096);
    std::vector<std::set<LocalIndex>> neighbours(mesh.numNodes());
    for (LocalIndex i = 0; i < mesh.numNodes(); ++i)
      neighbours[i].insert(i);
    for (LocalIndex e = 0; e < mesh.numElements(); ++e)
      for (int a = 0; a < mesh.nodesPerElement; ++a)
        for (int b = 0; b < mesh.nodesPerElement; ++b)
          neighbours[mesh.node(e, a)].insert(mesh.node(e, b));
    const NodeGraph g = buildNodeGraph(mesh);
    ASSERT_EQ(g.numNodes(), mesh.numNodes());
    for (LocalIndex i = 0; i < mesh.numNodes(); ++i)
      ASSERT_EQ(std::vector<LocalIndex>(g.columns.begin() + g.rowOffsets[i],
                                        g.columns.begin() + g.rowOffsets[i + 1]),
                std::vector<LocalIndex>(neighbours[i].begin(), neighbours[i].end()))
          << "node " << i;
    EXPECT_EQ(g.rowOffsets.back(), static_cast<Offset>(g.columns.size()));

    // the second neighbours (the lumped Schur complement's pattern), by the same chunks
    const NodeGraph g2 = secondNeighbourGraph(g);
    ASSERT_EQ(g2.numNodes(), mesh.numNodes());
    for (LocalIndex i = 0; i < mesh.numNodes(); i += 7) {
      std::set<LocalIndex> two;
      for (LocalIndex j : neighbours[i])
        two.insert(neighbours[j].begin(), neighbours[j].end());
      ASSERT_EQ(std::vector<LocalIndex>(g2.columns.begin() + g2.rowOffsets[i],
                                        g2.columns.begin() + g2.rowOffsets[i + 1]),
                std::vector<LocalIndex>(two.begin(), two.end()))
          << "node " << i;
    }
    EXPECT_EQ(g2.rowOffsets.back(), static_cast<Offset>(g2.columns.size()));

    const int rowDofs = 3, columnDofs = 2; // rectangular: rows and columns expand differently
    const CsrMatrix<Memory> a = expandGraph<Memory>(g, rowDofs, columnDofs);
    auto ro = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.rowOffsets);
    auto co = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.columns);
    ASSERT_EQ(a.numRows, rowDofs * mesh.numNodes());
    ASSERT_EQ(a.numColumns, columnDofs * mesh.numNodes());
    Offset k = 0;
    for (LocalIndex i = 0; i < mesh.numNodes(); ++i)
      for (int c = 0; c < rowDofs; ++c) {
        ASSERT_EQ(ro(rowDofs * i + c), k) << "row " << rowDofs * i + c;
        for (LocalIndex j : neighbours[i])
          for (int d = 0; d < columnDofs; ++d)
            ASSERT_EQ(co(k++), columnDofs * j + d) << "row " << rowDofs * i + c;
      }
    EXPECT_EQ(ro(a.numRows), k);
    EXPECT_EQ(a.numNonzeros(), k);

    const auto map = elementScatterMap<Memory>(mesh, g);
    auto hm = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), map);
    for (LocalIndex e = 0; e < mesh.numElements(); ++e)
      for (int p = 0; p < mesh.nodesPerElement; ++p)
        for (int q = 0; q < mesh.nodesPerElement; ++q)
          ASSERT_EQ(g.columns[g.rowOffsets[mesh.node(e, p)] + hm(e, p, q)], mesh.node(e, q))
              << "element " << e;
  }
}
