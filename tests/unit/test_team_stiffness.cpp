// The team-per-element stiffness of the element driver (kernels/ElementDriver.hpp:
// teamElementStiffness, one team per element, the geometry shared in team scratch, one thread per
// node pair) against the SIMD-lanes kernel and, in 2D, the plain host reference (explicit B,
// Eigen): element matrices and the fused CSR assembly, for every element type, on distorted
// meshes with anisotropic materials, with teams of 1, 2 and 3 threads and the size the launch
// chooses. Teams of 2 and 3 threads on the OpenMP backend run the scratch sharing and barriers
// that the GPU relies on (a missing barrier fails with the threads racing). And the lanes
// kernel's assembly by element chunks without atomics (elementChunks) against the same assembly
// with atomics and a plain host assembly of the element matrices.
#include <kernels/LinearElasticity.hpp>
#include <support/KernelFixture.hpp>
#include <support/SolidMesh.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>

using namespace mixcon;
using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace team_stiffness_tests {

/// Team sizes to try: the launch's own choice (0), 1, 2 and 3, the last two only where the
/// execution space has that many threads (on CPUs a team cannot outnumber the pool).
std::vector<int> teamSizes() {
  std::set<int> sizes{0, 1};
  constexpr bool host = Kokkos::SpaceAccessibility<Exec, Kokkos::HostSpace>::accessible;
  for (int s : {2, 3})
    if (!host || s <= Exec().concurrency())
      sizes.insert(s);
  return {sizes.begin(), sizes.end()};
}

/// A distorted mesh of the element type with its element data: the 2D kernel fixture (two
/// anisotropic materials in a checkerboard, thickness 0.7) or the distorted 3D box with a rotated
/// orthotropic solid and a scaled copy of it on every other element.
template <int Dim> struct Case {
  Mesh mesh;
  ElementData<Memory, Dim> data;
};

Case<2> planeCase(ElementType type, int nx = 6, int ny = 5) {
  const test::Fixture f = test::makeFixture(type, nx, ny);
  return {f.mesh, f.data};
}

Case<3> solidCase(ElementType type, int n = 3) {
  Case<3> c;
  c.mesh = test::distortedBox(n, type);
  c.data.mesh = toDevice<Memory, 3>(c.mesh);
  c.data.material = Kokkos::View<int *, Memory>("material", c.mesh.numElements());
  c.data.stiffness = Kokkos::View<SolidMatrix *, Memory>("stiffness", 2);
  auto hm = Kokkos::create_mirror_view(c.data.material);
  for (LocalIndex e = 0; e < c.mesh.numElements(); ++e)
    hm(e) = e % 2;
  Kokkos::deep_copy(c.data.material, hm);
  auto hs = Kokkos::create_mirror_view(c.data.stiffness);
  hs(0) = test::rotatedOrthotropicSolid();
  for (int r = 0; r < 6; ++r)
    for (int s = 0; s < 6; ++s)
      hs(1).m[r][s] = 2.5 * hs(0).m[r][s];
  Kokkos::deep_copy(c.data.stiffness, hs);
  return c;
}

/// Largest |a - b| over all entries, and the largest |b|.
template <class A, class B> std::pair<double, double> difference(const A &a, const B &b) {
  double diff = 0.0, scale = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    diff = std::max(diff, std::abs(a.data()[k] - b.data()[k]));
    scale = std::max(scale, std::abs(b.data()[k]));
  }
  return {diff, scale};
}

/// Element matrices and CSR assembly of the team kernel against the lanes kernel, for every team
/// size, and the dispatching entry point's matrices; the lanes matrices are returned for the
/// caller's reference check.
template <class Elem, int Dim> auto compareTeamWithLanes(const Case<Dim> &c) {
  constexpr int nd = Dim * Elem::kNumNodes;
  const LocalIndex ne = c.mesh.numElements();
  const auto law = linearElasticLaw(c.data);
  Kokkos::View<double ***, Memory> lanes("lanes", ne, nd, nd), team("team", ne, nd, nd);
  computeElementStiffnessLanes<Elem>(Exec(), c.data.mesh, c.data.thickness, law, lanes);
  const auto hl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), lanes);

  const NodeGraph graph = buildNodeGraph(c.mesh);
  const auto map = elementScatterMap<Memory>(c.mesh, graph);
  auto a = expandGraph<Memory>(graph, Dim), b = expandGraph<Memory>(graph, Dim);
  Kokkos::deep_copy(a.values, 0.0);
  assembleElementStiffnessLanes<Elem>(Exec(), c.data.mesh, c.data.thickness, law, map, a, 0.7);
  const auto ha = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.values);

  // The dispatching entry point gives the matrices of the kernel it chooses.
  computeElementStiffness<Elem>(Exec(), c.data.mesh, c.data.thickness, law, team);
  const auto [d, s] =
      difference(Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), team), hl);
  EXPECT_LE(d, 1e-13 * s) << Elem::kName << " (" << (kTeamStiffness<Exec, Elem> ? "team" : "lanes")
                          << " chosen)";

  for (const int size : teamSizes()) {
    Kokkos::deep_copy(team, -1.0);
    computeElementStiffnessTeam<Elem>(Exec(), c.data.mesh, c.data.thickness, law, team, size);
    const auto ht = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), team);
    const auto [dk, sk] = difference(ht, hl);
    EXPECT_LE(dk, 1e-13 * sk) << Elem::kName << ", element matrices, team size " << size;

    // Non-zero start values: the assembly adds.
    Kokkos::deep_copy(b.values, 1.0);
    assembleElementStiffnessTeam<Elem>(Exec(), c.data.mesh, c.data.thickness, law, map, b, 0.7,
                                       size);
    auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.values);
    for (std::size_t k = 0; k < hb.size(); ++k)
      hb(k) -= 1.0;
    const auto [da, sa] = difference(hb, ha);
    EXPECT_LE(da, 1e-13 * sa) << Elem::kName << ", CSR assembly, team size " << size;
  }
  return hl;
}

} // namespace team_stiffness_tests
using namespace team_stiffness_tests;

class TeamStiffness : public ::testing::TestWithParam<ElementType> {};

TEST_P(TeamStiffness, EqualsTheLanesKernelAndTheHostReference) {
  const ElementType type = GetParam();
  dispatchElement(type, [&](auto elem) {
    using Elem = decltype(elem);
    if constexpr (Elem::kDim == 2) {
      const Case<2> c = planeCase(type);
      const auto hl = compareTeamWithLanes<Elem>(c);
      // The lanes matrices (equal to the team's above) against the plain host reference.
      const test::Fixture f = test::makeFixture(type);
      for (LocalIndex e = 0; e < c.mesh.numElements(); ++e) {
        const Eigen::MatrixXd ref =
            test::referenceStiffness(test::elementCoordinates(c.mesh, e),
                                     test::toEigen(f.materials[f.elementMaterial[e]]), 0.7);
        double diff = 0.0;
        for (int i = 0; i < ref.rows(); ++i)
          for (int j = 0; j < ref.cols(); ++j)
            diff = std::max(diff, std::abs(hl(e, i, j) - ref(i, j)));
        ASSERT_LE(diff, 1e-10 * ref.cwiseAbs().maxCoeff()) << Elem::kName << ", element " << e;
      }
    } else {
      const Case<3> c = solidCase(type);
      compareTeamWithLanes<Elem>(c);
    }
  });
}

INSTANTIATE_TEST_SUITE_P(Elements, TeamStiffness,
                         ::testing::Values(ElementType::Quad4, ElementType::Quad8,
                                           ElementType::Hex8, ElementType::Hex20, ElementType::Tet4,
                                           ElementType::Tet10),
                         [](const auto &info) { return elementTypeName(info.param); });

namespace team_stiffness_tests {

/// A mesh of the element type whose consecutive elements are neighbours (the generators'
/// numbering): a distorted 16 x 13 rectangle in 2D, the distorted box of 6 x 7 x 6 cells in 3D.
template <int Dim> Case<Dim> chunkCase(ElementType type) {
  if constexpr (Dim == 2)
    return planeCase(type, 16, 13);
  else
    return solidCase(type, 6);
}

/// The nodes of elements [first, end) of the mesh.
std::set<LocalIndex> chunkNodes(const Mesh &mesh, LocalIndex first, LocalIndex end) {
  std::set<LocalIndex> nodes;
  for (LocalIndex e = first; e < std::min(end, mesh.numElements()); ++e)
    for (int a = 0; a < mesh.nodesPerElement; ++a)
      nodes.insert(mesh.node(e, a));
  return nodes;
}

/// The CSR values of the element matrices ke (checked against the host reference by the test
/// above) added one element after the other on the host, times `scale`, onto `start`.
template <int Dim, class Ke>
std::vector<double> hostAssembly(const Mesh &mesh, const CsrMatrix<Memory> &pattern, const Ke &ke,
                                 double scale, double start) {
  const auto ro = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pattern.rowOffsets);
  const auto co = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pattern.columns);
  std::vector<double> v(co.extent(0), start);
  const int n = mesh.nodesPerElement;
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < Dim; ++i) {
        const LocalIndex row = Dim * mesh.node(e, a) + i;
        for (int b = 0; b < n; ++b)
          for (int j = 0; j < Dim; ++j) {
            const LocalIndex col = Dim * mesh.node(e, b) + j;
            Offset k = ro(row);
            while (k < ro(row + 1) && co(k) != col)
              ++k;
            if (k == ro(row + 1)) {
              ADD_FAILURE() << "the pattern lacks (" << row << ", " << col << ")";
              return v;
            }
            v[k] += scale * ke(e, Dim * a + i, Dim * b + j);
          }
      }
  return v;
}

/// The assembly by chunks (those elementChunks finds with chunks of `base` elements) against the
/// atomic one and the host assembly, adding onto 1.
template <class Elem, int Dim>
void compareChunkedAssembly(const Case<Dim> &c, const ElementChunks &chunks, const char *what) {
  constexpr int nd = Dim * Elem::kNumNodes;
  const auto law = linearElasticLaw(c.data);
  const NodeGraph graph = buildNodeGraph(c.mesh);
  const auto map = elementScatterMap<Memory>(c.mesh, graph);
  auto chunked = expandGraph<Memory>(graph, Dim), atomic = expandGraph<Memory>(graph, Dim);
  Kokkos::deep_copy(chunked.values, 1.0);
  Kokkos::deep_copy(atomic.values, 1.0);
  assembleElementStiffnessLanes<Elem>(Exec(), c.data.mesh, c.data.thickness, law, map, chunked, 0.7,
                                      chunks);
  assembleElementStiffnessLanes<Elem>(Exec(), c.data.mesh, c.data.thickness, law, map, atomic, 0.7,
                                      ElementChunks{});
  Kokkos::View<double ***, Memory> ke("ke", c.mesh.numElements(), nd, nd);
  computeElementStiffnessLanes<Elem>(Exec(), c.data.mesh, c.data.thickness, law, ke);
  const auto hke = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
  const std::vector<double> host = hostAssembly<Dim>(c.mesh, chunked, hke, 0.7, 1.0);
  const auto hc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), chunked.values);
  const auto ha = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), atomic.values);
  ASSERT_EQ(hc.extent(0), host.size());
  const auto [dc, s] = difference(hc, host);
  const auto [da, sa] = difference(ha, host);
  EXPECT_LE(dc, 1e-13 * s) << Elem::kName << ", " << what << ", by chunks";
  EXPECT_LE(da, 1e-13 * sa) << Elem::kName << ", " << what << ", with atomics";
}

} // namespace team_stiffness_tests

class ElementChunksTest : public ::testing::TestWithParam<ElementType> {};

// On a mesh numbered as the generators number it, elementChunks cuts the elements into chunks
// whose same-parity members share no node (checked node by node here), and the assembly by them
// without atomics is the assembly with atomics and the host's assembly of the element matrices,
// also with chunks one element longer (an odd size: the SIMD lanes' last batch of every chunk is
// short); with the elements shuffled (every chunk spans the whole mesh) it finds no cut. Skipped
// where the kernels run off the host, which keeps the atomics.
TEST_P(ElementChunksTest, AssembleWithoutAtomicsAsWithThem) {
  if (!Kokkos::SpaceAccessibility<Exec, Kokkos::HostSpace>::accessible || !kHostAccessible<Memory>)
    GTEST_SKIP() << "the assembly by chunks runs on the host's threads only";
  const ElementType type = GetParam();
  dispatchElement(type, [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int dim = Elem::kDim;
    Case<dim> c = chunkCase<dim>(type);
    const LocalIndex ne = c.mesh.numElements();
    const ElementChunks chunks = elementChunks<Elem>(Exec(), c.data.mesh, 3, 4);
    ASSERT_GT(chunks.size, 0) << Elem::kName << ": no chunks on " << ne << " elements";
    EXPECT_EQ(chunks.size % 4, 0);
    EXPECT_EQ(chunks.count, (ne + chunks.size - 1) / chunks.size);
    EXPECT_GE(chunks.count, 3);
    const auto shareNode = [&](LocalIndex size) {
      for (LocalIndex first = 0; first < ne; first += size)
        for (LocalIndex other = first + 2 * size; other < ne; other += 2 * size) {
          const auto a = chunkNodes(c.mesh, first, first + size);
          for (const LocalIndex node : chunkNodes(c.mesh, other, other + size))
            if (a.count(node))
              return true;
        }
      return false;
    };
    EXPECT_FALSE(shareNode(chunks.size)) << Elem::kName;
    compareChunkedAssembly<Elem>(c, chunks, "generator's numbering");
    const LocalIndex odd = chunks.size + 1;
    ASSERT_FALSE(shareNode(odd)) << Elem::kName;
    compareChunkedAssembly<Elem>(c, ElementChunks{odd, (ne + odd - 1) / odd}, "odd chunks");

    // Shuffled: element k takes element (k * 7919) % ne's nodes (7919 prime, not a factor of ne).
    ASSERT_NE(ne % 7919, 0);
    const Mesh ordered = c.mesh;
    const int n = c.mesh.nodesPerElement;
    for (LocalIndex e = 0; e < ne; ++e)
      for (int a = 0; a < n; ++a)
        c.mesh.connectivity[static_cast<std::size_t>(e) * n + a] =
            ordered.node(static_cast<LocalIndex>((static_cast<std::int64_t>(e) * 7919) % ne), a);
    c.data.mesh = toDevice<Memory, dim>(c.mesh);
    EXPECT_EQ(elementChunks<Elem>(Exec(), c.data.mesh, 3, 4).size, 0) << Elem::kName;
    compareChunkedAssembly<Elem>(c, ElementChunks{}, "shuffled elements");
  });
}

INSTANTIATE_TEST_SUITE_P(Elements, ElementChunksTest,
                         ::testing::Values(ElementType::Quad4, ElementType::Quad8,
                                           ElementType::Hex8, ElementType::Hex20, ElementType::Tet4,
                                           ElementType::Tet10),
                         [](const auto &info) { return elementTypeName(info.param); });

// The entry point without chunks finds its own (chunks of 2,048 elements, at least one per thread
// and parity) on a mesh large enough for them, and assembles the matrix of the atomic path.
TEST(ElementChunks, EntryPointTakesTheChunksOfALargeMesh) {
  if (!Kokkos::SpaceAccessibility<Exec, Kokkos::HostSpace>::accessible || !kHostAccessible<Memory>)
    GTEST_SKIP() << "the assembly by chunks runs on the host's threads only";
  const test::Fixture f = test::makeFixture(ElementType::Quad4, 256, 128); // 32,768 elements
  const auto law = linearElasticLaw(f.data);
  const LocalIndex threads = static_cast<LocalIndex>(Exec().concurrency());
  const ElementChunks chunks = elementChunks<Quad4>(Exec(), f.data.mesh, 2 * threads);
  if (threads <= 8) { // 16 blocks of 2,048 elements
    EXPECT_GT(chunks.size, 0) << threads << " threads";
  }
  const NodeGraph graph = buildNodeGraph(f.mesh);
  const auto map = elementScatterMap<Memory>(f.mesh, graph);
  auto own = expandGraph<Memory>(graph, 2), atomic = expandGraph<Memory>(graph, 2);
  Kokkos::deep_copy(own.values, 0.0);
  Kokkos::deep_copy(atomic.values, 0.0);
  assembleElementStiffnessLanes<Quad4>(Exec(), f.data.mesh, f.data.thickness, law, map, own);
  assembleElementStiffnessLanes<Quad4>(Exec(), f.data.mesh, f.data.thickness, law, map, atomic, 1.0,
                                       ElementChunks{});
  const auto ho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), own.values);
  const auto ha = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), atomic.values);
  const auto [d, s] = difference(ho, ha);
  EXPECT_GT(s, 0.0);
  EXPECT_LE(d, 1e-13 * s);
}
