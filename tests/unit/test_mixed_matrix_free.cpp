// Matrix-free mixed blocks (kernels/MixedMatrixFree.hpp): K12 s, K12^T u and M s by partial
// assembly and fully matrix-free against the assembled node-block operators (MixedOperators) and
// a plain host loop over the reference element matrices (tests/support/Reference.hpp), on
// distorted Quad4 and Quad8 meshes with three materials, with the OpenMP threads of the run
// (atomic scatter races would show as differences between repeated applies), with the atomic and
// the colored scatter; and the element coloring itself.
#include <kernels/MixedMatrixFree.hpp>
#include <solver/MixedModel.hpp>
#include <support/KernelFixture.hpp>
#include <support/Params.hpp>

#include <gtest/gtest.h>

using namespace mixcon;
using namespace mixcon::test;
using Exec = Kokkos::DefaultExecutionSpace;

namespace {

/// The kernel fixture with a third material (isotropic, plane stress) on every third element.
Fixture threeMaterialFixture(ElementType type, int nx, int ny) {
  Fixture f = makeFixture(type, nx, ny);
  f.materials.push_back(isotropicStiffness(7.0e4, 0.25, PlaneAnalysis::PlaneStress));
  f.data.stiffness = Kokkos::View<PlaneMatrix *, Memory>("stiffness", f.materials.size());
  auto hs = Kokkos::create_mirror_view(f.data.stiffness);
  for (std::size_t i = 0; i < f.materials.size(); ++i)
    hs(i) = f.materials[i];
  Kokkos::deep_copy(f.data.stiffness, hs);
  auto hm = Kokkos::create_mirror_view(f.data.material);
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e)
    hm(e) = f.elementMaterial[e] = e % 3;
  Kokkos::deep_copy(f.data.material, hm);
  return f;
}

MixedOperators<Memory> assembled(const Fixture &f, const MixedElementData<Memory> &d) {
  const NodeGraph g = buildNodeGraph(f.mesh);
  const auto map = elementScatterMap<Memory>(f.mesh, g);
  return dispatchPlaneElement(f.mesh.elementType, "this 2D test", [&](auto elem) {
    return assembleMixedOperators<decltype(elem)>(Exec(), d, toDevice<Memory>(g), map);
  });
}

/// Plain host loop: r = K12^T u, k = K12 s, m = M s from the reference element matrices.
struct HostProducts {
  Eigen::VectorXd r, k, m;
};
HostProducts hostProducts(const Fixture &f, const Eigen::VectorXd &u, const Eigen::VectorXd &s) {
  const Mesh &mesh = f.mesh;
  const int nn = mesh.numNodes(), n = mesh.nodesPerElement;
  HostProducts p{Eigen::VectorXd::Zero(3 * nn), Eigen::VectorXd::Zero(2 * nn),
                 Eigen::VectorXd::Zero(3 * nn)};
  for (LocalIndex e = 0; e < mesh.numElements(); ++e) {
    Eigen::MatrixXd k12, k22;
    const Eigen::Matrix3d d = toEigen(f.materials[f.elementMaterial[e]]).inverse();
    referenceMixed(elementCoordinates(mesh, e), d, f.data.thickness, k12, k22);
    Eigen::VectorXd ue(2 * n), se(3 * n);
    for (int a = 0; a < n; ++a) {
      const int k = mesh.node(e, a);
      ue.segment<2>(2 * a) = u.segment<2>(2 * k);
      se.segment<3>(3 * a) = s.segment<3>(3 * k);
    }
    const Eigen::VectorXd re = k12.transpose() * ue, ke = k12 * se, me = k22 * se;
    for (int a = 0; a < n; ++a) {
      const int k = mesh.node(e, a);
      p.r.segment<3>(3 * k) += re.segment<3>(3 * a);
      p.k.segment<2>(2 * k) += ke.segment<2>(2 * a);
      p.m.segment<3>(3 * k) += me.segment<3>(3 * a);
    }
  }
  return p;
}

/// (partial assembly?, scatter) of every variant.
const std::pair<bool, MixedScatter> kVariants[] = {{true, MixedScatter::Atomic},
                                                   {true, MixedScatter::Colored},
                                                   {false, MixedScatter::Atomic},
                                                   {false, MixedScatter::Colored}};

struct Products {
  Eigen::VectorXd r, k, m;
};

/// The three products through an operator set (assembled or matrix-free), K12 s as
/// f = beta f0 + alpha K12 s.
template <class Ops>
Products apply(const Ops &ops, const Eigen::VectorXd &u, const Eigen::VectorXd &s,
               const Eigen::VectorXd &f0, double alpha, double beta) {
  auto du = toView(u), ds = toView(s), df = toView(f0);
  Kokkos::View<double *, Memory> r("r", s.size()), y("y", s.size());
  applyCouplingTranspose(Exec(), ops, ConstDeviceVector(du), r);
  applyCoupling(Exec(), ops, alpha, ConstDeviceVector(ds), beta, df);
  applyCompliance(Exec(), ops, ConstDeviceVector(ds), y);
  return {toEigen(r), toEigen(df), toEigen(y)};
}

} // namespace

class MixedMatrixFreeTest : public ::testing::TestWithParam<ElementType> {};
INSTANTIATE_TEST_SUITE_P(Elements, MixedMatrixFreeTest, bothElements(), elementName);

TEST_P(MixedMatrixFreeTest, AppliesMatchAssembledAndHostLoop) {
  const Fixture f = threeMaterialFixture(GetParam(), 7, 5);
  const auto d = mixedElementData(f);
  const int nn = f.mesh.numNodes();
  const Eigen::VectorXd u = randomVector(2 * nn, 11), s = 1e3 * randomVector(3 * nn, 12),
                        f0 = randomVector(2 * nn, 13);
  const HostProducts host = hostProducts(f, u, s);
  const Products ref = apply(assembled(f, d), u, s, f0, 1.0, 0.0);
  // The assembled operators are the ones the model used so far: they match the host loop too.
  ASSERT_LT(relativeError(ref.r, host.r), 1e-12);
  ASSERT_LT(relativeError(ref.k, host.k), 1e-12);
  ASSERT_LT(relativeError(ref.m, host.m), 1e-12);
  for (const auto &[partial, scatter] : kVariants) {
    SCOPED_TRACE(std::string(partial ? "partial assembly" : "fully matrix-free") +
                 (scatter == MixedScatter::Atomic ? ", atomic" : ", colored"));
    const auto mf = makeMixedMatrixFree(Exec(), d, f.mesh, partial, scatter);
    EXPECT_EQ(mf.scatter, scatter);
    EXPECT_EQ(mf.geometry.weight.extent(0), partial ? f.mesh.numElements() : 0u);
    const Products p = apply(mf, u, s, f0, 1.0, 0.0);
    EXPECT_LT(relativeError(p.r, ref.r), 1e-12);
    EXPECT_LT(relativeError(p.r, host.r), 1e-12);
    EXPECT_LT(relativeError(p.k, ref.k), 1e-12);
    EXPECT_LT(relativeError(p.k, host.k), 1e-12);
    EXPECT_LT(relativeError(p.m, ref.m), 1e-12);
    EXPECT_LT(relativeError(p.m, host.m), 1e-12);
    // f = beta f + alpha K12 s, as the assembled applyCoupling (beta = 0, 1 and other values).
    for (const double beta : {1.0, -2.0}) {
      const Products a = apply(assembled(f, d), u, s, f0, 0.7, beta);
      const Products b = apply(mf, u, s, f0, 0.7, beta);
      EXPECT_LT(relativeError(b.k, a.k), 1e-12) << "beta " << beta;
      EXPECT_LT(relativeError(b.k, 0.7 * host.k + beta * f0), 1e-12) << "beta " << beta;
    }
  }
}

/// The partial assembly's stored factors: the weights sum to t times the mesh area and the
/// weighted gradients to zero per point (sum_a dpsi_a/dx = 0), as the recomputed geometry.
TEST_P(MixedMatrixFreeTest, PartialAssemblyFactorsAreTheGeometry) {
  const Fixture f = threeMaterialFixture(GetParam(), 5, 4);
  const auto d = mixedElementData(f);
  const auto mf = makeMixedMatrixFree(Exec(), d, f.mesh, true);
  auto w = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mf.geometry.weight);
  auto g = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mf.geometry.gradient);
  double area = 0.0, worst = 0.0;
  for (std::size_t e = 0; e < w.extent(0); ++e)
    for (std::size_t q = 0; q < w.extent(1); ++q) {
      area += w(e, q);
      for (int i = 0; i < 2; ++i) {
        double sum = 0.0;
        for (int a = 0; a < f.mesh.nodesPerElement; ++a)
          sum += g(e, q, 2 * a + i);
        worst = std::max(worst, std::abs(sum) / std::abs(w(e, q)));
      }
    }
  EXPECT_NEAR(area, f.data.thickness * 3.0 * 2.0, 1e-12); // the fixture's 3 x 2 rectangle
  EXPECT_LT(worst, 1e-12);
}

/// Repeated applies on a larger mesh with every thread of the run scatter atomically into shared
/// nodes; each result matches the host loop (a lost update would not).
TEST_P(MixedMatrixFreeTest, ScatterIsRaceFreeWithThreads) {
  const Fixture f = threeMaterialFixture(GetParam(), 60, 40);
  const auto d = mixedElementData(f);
  const int nn = f.mesh.numNodes();
  const Eigen::VectorXd u = randomVector(2 * nn, 21), s = randomVector(3 * nn, 22),
                        f0 = Eigen::VectorXd::Zero(2 * nn);
  const HostProducts host = hostProducts(f, u, s);
  RecordProperty("threads", Exec().concurrency());
  for (const auto &[partial, scatter] : kVariants) {
    const auto mf = makeMixedMatrixFree(Exec(), d, f.mesh, partial, scatter);
    for (int repeat = 0; repeat < 10; ++repeat) {
      const Products p = apply(mf, u, s, f0, 1.0, 0.0);
      SCOPED_TRACE(::testing::Message()
                   << "partial " << partial << " atomic " << (scatter == MixedScatter::Atomic)
                   << " repeat " << repeat);
      ASSERT_LT(relativeError(p.r, host.r), 1e-12);
      ASSERT_LT(relativeError(p.k, host.k), 1e-12);
      ASSERT_LT(relativeError(p.m, host.m), 1e-12);
    }
  }
}

/// The element colors: every element once, no two elements of a color sharing a node, and few
/// colors on these quadrilateral meshes.
TEST_P(MixedMatrixFreeTest, ElementColorsShareNoNode) {
  const Fixture f = threeMaterialFixture(GetParam(), 9, 7);
  const auto mf =
      makeMixedMatrixFree(Exec(), mixedElementData(f), f.mesh, false, MixedScatter::Colored);
  ASSERT_EQ(mf.scatter, MixedScatter::Colored);
  EXPECT_LE(mf.numColors, 8);
  auto list = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mf.coloredElements);
  std::vector<int> seen(f.mesh.numElements(), 0);
  for (int c = 0; c < mf.numColors; ++c) {
    std::vector<int> nodeUsed(f.mesh.numNodes(), 0);
    for (LocalIndex i = mf.colorOffsets[c]; i < mf.colorOffsets[c + 1]; ++i) {
      const LocalIndex e = list(i);
      ++seen[e];
      for (int a = 0; a < f.mesh.nodesPerElement; ++a)
        EXPECT_EQ(nodeUsed[f.mesh.node(e, a)]++, 0) << "color " << c << " element " << e;
    }
  }
  EXPECT_EQ(mf.colorOffsets[mf.numColors], f.mesh.numElements());
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e)
    EXPECT_EQ(seen[e], 1) << "element " << e;
}
