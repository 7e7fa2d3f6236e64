// Google Benchmark: the batched K^L kernel (element matrices, elements/s and GB/s of element-matrix
// output), fused compute + atomic CSR scatter (elements/s, GB/s of CSR traffic), the same kernel on
// Kokkos::Serial as the single-thread baseline, and the plain host reference implementation of the
// tests (tests/support/Reference.hpp: explicit B, Eigen dynamic matrices, one element at a time),
// against which bench/report gives the batched kernel's speed-up (the STREAM triad, the bandwidth
// roofline, is in bench_machine.cpp; bench/report runs both in one go). The 3D cases (issue 17):
// the Hex8 K^L of the generic element driver with LinearElasticPoint<3> on a distorted box mesh,
// element matrices and fused CSR assembly, checked against a plain host reference (explicit
// 6 x 24 B, Eigen) before they are timed.
#include <bench/BenchMain.hpp>
#include <kernels/GeometricStiffness.hpp>
#include <kernels/LinearElasticity.hpp>
#include <kernels/MixedElasticity.hpp>
#include <mesh/Generators.hpp>
#include <solver/LinearSolver.hpp>
#include <solver/RigidRotation.hpp>
#include <support/Reference.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace mixcon;
using Memory = Kokkos::DefaultExecutionSpace::memory_space;

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace linear_stiffness_bench {

struct Setup {
  Mesh mesh;
  ElementData<Memory> data;
};

Setup makeSetup(ElementType type, int n) {
  Setup s;
  s.mesh = rectangleMesh(1.0, 1.0, n, n, type);
  s.data.mesh = toDevice<Memory>(s.mesh);
  s.data.material = Kokkos::View<int *, Memory>("material", s.mesh.numElements());
  s.data.stiffness = Kokkos::View<PlaneMatrix *, Memory>("stiffness", 1);
  auto h = Kokkos::create_mirror_view(s.data.stiffness);
  h(0) = orthotropicStiffness({1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4},
                              PlaneAnalysis::PlaneStress, 0.3);
  Kokkos::deep_copy(s.data.stiffness, h);
  return s;
}

ElementType typeOf(const benchmark::State &state) {
  return state.range(0) == 8 ? ElementType::Quad8 : ElementType::Quad4;
}

/// Times `launch` (one batched element-matrix kernel over ne elements, fenced on `Exec`) and sets
/// the counters: elements/s, GB/s of the element matrices written (`bytes` per element) and
/// GFLOP/s (`flops` per element, counted from the kernel's code).
template <class Exec, class Launch>
void timeElementMatrices(benchmark::State &state, double ne, double bytes, double flops,
                         Launch &&launch) {
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    launch();
    Exec().fence();
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.counters["elem/s"] = benchmark::Counter(ne, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["GB/s"] =
      benchmark::Counter(ne * bytes / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["elements"] = ne;
  state.counters["GFLOP/s"] =
      benchmark::Counter(ne * flops / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

/// Times the host reference, one element after another on one thread: `element(e)` computes
/// element e's matrices and returns one of their entries, summed so that the work stays. Sets
/// elements/s.
template <class Element>
void timeHostReference(benchmark::State &state, LocalIndex numElements, Element &&element) {
  double sum = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    for (LocalIndex e = 0; e < numElements; ++e)
      sum += element(e);
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  benchmark::DoNotOptimize(sum);
  state.counters["elem/s"] = benchmark::Counter(static_cast<double>(numElements),
                                                benchmark::Counter::kIsIterationInvariantRate);
}

/// Floating-point operations of one K^L element (kernels/ElementStiffness.hpp, stiffnessLanes),
/// counted from the code, each multiply, add and divide one: per quadrature point the Jacobian
/// (8n), its inverse (8), the physical gradients (6n), the weight (2), the weighted gradients
/// (2n) and the gradient products of the node pairs a <= b (4 multiply-adds per pair, n(n+1)/2
/// pairs); per element the contraction of each pair's products with C (4 entries of 4
/// multiply-adds). Shape function evaluation and the mirror copy are not counted, so the rate is
/// a lower bound. Quad4: 936 per element (1,288 when each point formed B_a^T (C B_b)).
constexpr double stiffnessFlops(int n, int quadraturePoints) {
  return quadraturePoints * (4.0 * n * n + 20.0 * n + 10.0) + 16.0 * n * (n + 1);
}

/// Which stiffness kernel a benchmark times: the one the build chooses for the execution space
/// (computeElementStiffness: "threads"), SIMD lanes of elements per thread, or one team per
/// element (kernels/ElementStiffness.hpp; kTeamStiffness: the team form on GPUs for the 3D
/// elements of 24 or more unknowns).
enum class Kernel { Chosen, Lanes, Team };

template <Kernel K, class Elem, class Exec, class MeshV, class Law, class View>
void stiffnessWith(const Exec &exec, const MeshV &mesh, double thickness, const Law &law,
                   const View &ke) {
  if constexpr (K == Kernel::Lanes)
    computeElementStiffnessLanes<Elem>(exec, mesh, thickness, law, ke);
  else if constexpr (K == Kernel::Team)
    computeElementStiffnessTeam<Elem>(exec, mesh, thickness, law, ke);
  else
    computeElementStiffness<Elem>(exec, mesh, thickness, law, ke);
}

/// Skips a Kokkos::Serial baseline where the setup's memory is a GPU's (the CUDA build).
template <class Exec> bool baselineCanRun(benchmark::State &state) {
  if constexpr (Kokkos::SpaceAccessibility<Exec, Memory>::accessible) {
    return true;
  } else {
    state.SkipWithError("the Serial baseline needs host-accessible memory (not in this build)");
    return false;
  }
}

template <class Exec, Kernel K = Kernel::Chosen> void elementMatrices(benchmark::State &state) {
  if (!baselineCanRun<Exec>(state))
    return;
  const Setup s = makeSetup(typeOf(state), static_cast<int>(state.range(1)));
  dispatchPlaneElement(typeOf(state), "this 2D benchmark", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int nd = 2 * Elem::kNumNodes;
    Kokkos::View<double ***, Memory> ke("ke", s.mesh.numElements(), nd, nd);
    const auto law = linearElasticLaw(s.data);
    // Output dominates the traffic: nd^2 doubles per element, written once.
    timeElementMatrices<Exec>(
        state, s.mesh.numElements(), nd * nd * 8.0, stiffnessFlops(Elem::kNumNodes, Elem::kNumQp),
        [&] { stiffnessWith<K, Elem>(Exec(), s.data.mesh, s.data.thickness, law, ke); });
  });
}

/// The host reference implementation of the tests: K^L = t sum B^T C B w with B built
/// explicitly, Eigen dynamic matrices, one element after another on one thread.
void hostReference(benchmark::State &state) {
  const Setup s = makeSetup(typeOf(state), static_cast<int>(state.range(1)));
  auto hc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.data.stiffness);
  Eigen::Matrix3d c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c(i, j) = hc(0).m[i][j];
  timeHostReference(state, s.mesh.numElements(), [&](LocalIndex e) {
    return test::referenceStiffness(test::elementCoordinates(s.mesh, e), c, 1.0)(0, 0);
  });
}

/// Floating-point operations of one mixed element (kernels/MixedElasticity.hpp,
/// computeMixedElementMatrices), counted from the code: per quadrature point the Jacobian, its
/// inverse and the gradients (14n + 8), the weight (2) and the three scalar integrals gx, gy, m
/// (9 per node pair); then K22 = m D (9 per node pair), the lumped K22 (9 per node) and the
/// lumping (about n^2). Shape functions not counted.
constexpr double mixedFlops(int n, int quadraturePoints) {
  return quadraturePoints * (9.0 * n * n + 14.0 * n + 10.0) + 10.0 * n * n + 9.0 * n;
}

MixedElementData<Memory> mixedData(const Setup &s) {
  MixedElementData<Memory> m;
  static_cast<ElementData<Memory> &>(m) = s.data;
  m.compliance = Kokkos::View<PlaneMatrix *, Memory>("compliance", 1);
  auto hc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.data.stiffness);
  Eigen::Matrix3d c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c(i, j) = hc(0).m[i][j];
  const Eigen::Matrix3d d = c.inverse();
  auto h = Kokkos::create_mirror_view(m.compliance);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      h(0).m[i][j] = d(i, j);
  Kokkos::deep_copy(m.compliance, h);
  return m;
}

/// The mixed element matrices K12 (2n x 3n), K22 consistent and lumped (3n x 3n) of every
/// element, batched (the linear mixed model's kernel).
void mixedElementMatrices(benchmark::State &state) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const Setup s = makeSetup(typeOf(state), static_cast<int>(state.range(1)));
  const MixedElementData<Memory> md = mixedData(s);
  dispatchPlaneElement(typeOf(state), "this 2D benchmark", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int n = Elem::kNumNodes;
    const LocalIndex ne = s.mesh.numElements();
    Kokkos::View<double ***, Memory> k12("k12", ne, 2 * n, 3 * n), k22("k22", ne, 3 * n, 3 * n),
        k22l("k22l", ne, 3 * n, 3 * n);
    timeElementMatrices<Exec>(
        state, ne, 8.0 * (2 * n * 3 * n + 2 * 9 * n * n), mixedFlops(n, Elem::kNumQp),
        [&] { computeMixedElementMatrices<Elem>(Exec(), md, k12, k22, k22l); });
  });
}

/// The tests' host reference of the mixed blocks (explicit B and Psi, Eigen dynamic matrices).
void mixedHostReference(benchmark::State &state) {
  const Setup s = makeSetup(typeOf(state), static_cast<int>(state.range(1)));
  const MixedElementData<Memory> md = mixedData(s);
  auto hd = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), md.compliance);
  Eigen::Matrix3d d;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      d(i, j) = hd(0).m[i][j];
  Eigen::MatrixXd k12, k22;
  timeHostReference(state, s.mesh.numElements(), [&](LocalIndex e) {
    test::referenceMixed(test::elementCoordinates(s.mesh, e), d, 1.0, k12, k22);
    return k12(0, 0) + k22(0, 0);
  });
}

/// Floating-point operations of one K^sigma element (kernels/GeometricStiffness.hpp,
/// geometricStiffness with nodal stresses), counted from the code: per quadrature point the
/// Jacobian, its inverse, the gradients and the weight (14n + 10, as for K^L), tau interpolated
/// from the nodes (6n), tau g_a for every node (8n) and the scalar products g_a^T tau g_b for
/// a <= b added to both diagonal entries of the 2 x 2 block (5 per node pair, n(n+1)/2 pairs).
/// Shape functions and the mirror copy not counted.
constexpr double geometricFlops(int n, int quadraturePoints) {
  return quadraturePoints * (2.5 * n * (n + 1.0) + 28.0 * n + 10.0);
}

/// A smooth nodal stress field (3 per node), the same for the kernel and the reference.
Kokkos::View<double *, Memory> nodalStress(const Mesh &mesh) {
  Kokkos::View<double *, Memory> s("stress", 3 * mesh.numNodes());
  auto h = Kokkos::create_mirror_view(s);
  for (LocalIndex k = 0; k < mesh.numNodes(); ++k) {
    h(3 * k) = 1e3 * (1.0 + mesh.x(k));
    h(3 * k + 1) = -2e3 * mesh.y(k);
    h(3 * k + 2) = 5e2 * mesh.x(k) * mesh.y(k);
  }
  Kokkos::deep_copy(s, h);
  return s;
}

/// The geometric stiffness K^sigma (2n x 2n) of every element from nodal stresses, batched (the
/// mixed model's K11 and, with stresses at the quadrature points, the displacement model's).
void geometricElementMatrices(benchmark::State &state) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const Setup s = makeSetup(typeOf(state), static_cast<int>(state.range(1)));
  const NodalStressField<Memory> field{s.data.mesh, nodalStress(s.mesh)};
  dispatchPlaneElement(typeOf(state), "this 2D benchmark", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int nd = 2 * Elem::kNumNodes;
    const LocalIndex ne = s.mesh.numElements();
    Kokkos::View<double ***, Memory> kg("kg", ne, nd, nd);
    timeElementMatrices<Exec>(state, ne, nd * nd * 8.0,
                              geometricFlops(Elem::kNumNodes, Elem::kNumQp),
                              [&] { computeGeometricStiffness<Elem>(Exec(), s.data, field, kg); });
  });
}

/// The tests' host reference of K^sigma (the 4 x 2n [B^sigma] and 4 x 4 [tau] of Eq. (25)
/// multiplied as matrices, Eigen dynamic matrices, one element at a time). It also forms the
/// stress force F^sigma (2n entries, a small part of its work).
void geometricHostReference(benchmark::State &state) {
  const Setup s = makeSetup(typeOf(state), static_cast<int>(state.range(1)));
  const auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), nodalStress(s.mesh));
  const int n = s.mesh.nodesPerElement;
  Eigen::MatrixXd kg;
  Eigen::VectorXd fnl;
  timeHostReference(state, s.mesh.numElements(), [&](LocalIndex e) {
    const auto tauAt = [&](int, const Eigen::VectorXd &sh) {
      Eigen::Vector3d tau = Eigen::Vector3d::Zero();
      for (int b = 0; b < n; ++b)
        for (int c = 0; c < 3; ++c)
          tau(c) += sh(b) * hs(3 * s.mesh.node(e, b) + c);
      return tau;
    };
    test::referenceGeometricAt(test::elementCoordinates(s.mesh, e), tauAt, 1.0, kg, fnl);
    return kg(0, 0);
  });
}

void assembleCsr(benchmark::State &state) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const Setup s = makeSetup(typeOf(state), static_cast<int>(state.range(1)));
  const NodeGraph g = buildNodeGraph(s.mesh);
  auto a = expandGraph<Memory>(g, 2);
  const auto map = elementScatterMap<Memory>(s.mesh, g);
  dispatchPlaneElement(typeOf(state), "this 2D benchmark", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int nd = 2 * Elem::kNumNodes;
    for (auto _ : state) {
      const auto t0 = std::chrono::steady_clock::now();
      Kokkos::deep_copy(Exec(), a.values, 0.0);
      assembleLinearStiffness<Elem>(Exec(), s.data, map, a);
      Exec().fence();
      state.SetIterationTime(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    const double ne = s.mesh.numElements();
    // Bytes: zeroing the CSR values (write), then nd^2 atomic read-modify-writes per element
    // (16 B each) plus the scatter map (nodes^2 ints) and connectivity.
    const double bytes =
        a.numNonzeros() * 8.0 + ne * (nd * nd * 16.0 + Elem::kNumNodes * Elem::kNumNodes * 4.0);
    state.counters["elem/s"] =
        benchmark::Counter(ne, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["GB/s"] =
        benchmark::Counter(bytes / 1e9, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["nnz"] = static_cast<double>(a.numNonzeros());
    state.counters["DOF"] = 2.0 * s.mesh.numNodes();
  });
}

// ---------------------------------------------------------------------------------------------
// 3D (issue 17): Hex8 against a plain host reference; Hex20, Tet4 and Tet10 against the
// properties every K^L has (symmetry, the six rigid-body modes in its null space).

struct SolidSetup {
  Mesh mesh;
  ElementData<Memory, 3> data;
};

/// `nodes` of a 3D benchmark's first argument: 8 (Hex8), 20 (Hex20), 4 (Tet4), 10 (Tet10).
ElementType solidTypeOf(const benchmark::State &state) {
  switch (state.range(0)) {
  case 20:
    return ElementType::Hex20;
  case 4:
    return ElementType::Tet4;
  case 10:
    return ElementType::Tet10;
  default:
    return ElementType::Hex8;
  }
}

/// The unit cube of n^3 cells (Hex8 or Hex20 elements, or 6 tetrahedra per cell) with every node
/// moved by up to 0.15 h in each direction (fixed seed: general, non-affine elements), one
/// rotated orthotropic material (a full 6 x 6 [C]: the kernel does the same arithmetic for any
/// [C]).
SolidSetup makeSolidSetup(int n, ElementType type = ElementType::Hex8) {
  SolidSetup s;
  s.mesh = boxMesh(1.0, 1.0, 1.0, n, n, n, type);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> shift(-0.15 / n, 0.15 / n);
  for (double &x : s.mesh.coordinates)
    x += shift(rng);
  s.data.mesh = toDevice<Memory, 3>(s.mesh);
  s.data.material = Kokkos::View<int *, Memory>("material", s.mesh.numElements());
  s.data.stiffness = Kokkos::View<SolidMatrix *, Memory>("stiffness", 1);
  auto h = Kokkos::create_mirror_view(s.data.stiffness);
  const OrthotropicMaterial m{{1.6e6, 1.1e5, 1.2e5, 1.0e5, 0.3, 0.25, 0.35, 0.9e5, 0.4e5},
                              matmul(rotationAboutZ(0.3), rotationAboutX(0.2))};
  h(0) = m.stiffness();
  Kokkos::deep_copy(s.data.stiffness, h);
  return s;
}

/// Plain host reference of one Hex8 K^L = int B^T C B dV: its own trilinear shape functions and
/// 2 x 2 x 2 Gauss rule, the 6 x 24 B (Voigt xx, yy, zz, yz, xz, xy; engineering shears) built
/// explicitly, Eigen dynamic matrices.
Eigen::MatrixXd referenceHexStiffness(const Mesh &mesh, LocalIndex e, const Eigen::MatrixXd &c) {
  static const double corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                      {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  Eigen::MatrixXd xe(8, 3);
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      xe(a, i) = mesh.coordinate(mesh.node(e, a), i);
  const double g = 1.0 / std::sqrt(3.0);
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(24, 24);
  for (int q = 0; q < 8; ++q) {
    const double xi[3] = {q % 2 ? g : -g, (q / 2) % 2 ? g : -g, q / 4 ? g : -g};
    Eigen::MatrixXd dn(8, 3);
    for (int a = 0; a < 8; ++a)
      for (int j = 0; j < 3; ++j) {
        double v = 0.125 * corner[a][j];
        for (int m = 0; m < 3; ++m)
          if (m != j)
            v *= 1.0 + corner[a][m] * xi[m];
        dn(a, j) = v;
      }
    const Eigen::MatrixXd jac = xe.transpose() * dn; // d x_i / d xi_j
    const Eigen::MatrixXd dx = dn * jac.inverse();   // d N_a / d x_i
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(6, 24);
    for (int a = 0; a < 8; ++a) {
      for (int i = 0; i < 3; ++i)
        b(i, 3 * a + i) = dx(a, i);
      b(3, 3 * a + 1) = dx(a, 2), b(3, 3 * a + 2) = dx(a, 1);
      b(4, 3 * a + 0) = dx(a, 2), b(4, 3 * a + 2) = dx(a, 0);
      b(5, 3 * a + 0) = dx(a, 1), b(5, 3 * a + 1) = dx(a, 0);
    }
    k += b.transpose() * c * b * jac.determinant();
  }
  return k;
}

Eigen::MatrixXd solidStiffnessMatrix(const SolidSetup &s) {
  auto hc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.data.stiffness);
  Eigen::MatrixXd c(6, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      c(i, j) = hc(0).m[i][j];
  return c;
}

/// Largest |K_kernel - K_reference| / max |K_reference| over the first, a middle and the last
/// element (the check before the timing).
template <class View> double solidMismatch(const SolidSetup &s, const View &ke) {
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
  const Eigen::MatrixXd c = solidStiffnessMatrix(s);
  const LocalIndex ne = s.mesh.numElements();
  double worst = 0.0;
  for (const LocalIndex e : {LocalIndex(0), ne / 2, ne - 1}) {
    const Eigen::MatrixXd ref = referenceHexStiffness(s.mesh, e, c);
    double diff = 0.0;
    for (int i = 0; i < 24; ++i)
      for (int j = 0; j < 24; ++j)
        diff = std::max(diff, std::abs(h(e, i, j) - ref(i, j)));
    worst = std::max(worst, diff / ref.cwiseAbs().maxCoeff());
  }
  return worst;
}

/// Floating-point operations of one 3D K^L element (stiffnessLanes with Dim = 3), counted from the
/// code as stiffnessFlops (each multiply, add and divide one): per quadrature point the Jacobian
/// (18n), its adjugate inverse (42: 9 cofactor terms of 3, det 5, 1 divide, 24 for the scaled
/// entries), the physical gradients (15n), the weight (2), the weighted gradients (3n) and the
/// gradient products of the node pairs a <= b (9 multiply-adds per pair, n(n+1)/2 pairs); per
/// element the contraction of each pair's products with the tangent tensor (9 entries of 9
/// multiply-adds). Shape functions and the mirror copy are not counted: a lower bound. Hex8:
/// 13,672 per element (24,928 when each point formed B_a^T (f D B_b)). The same loops serve
/// Hex20, Tet4 and Tet10 with their n and rule.
constexpr double solidStiffnessFlops(int n, int quadraturePoints) {
  return quadraturePoints * (9.0 * n * n + 45.0 * n + 44.0) + 81.0 * n * (n + 1);
}

/// Largest violation, over the first, a middle and the last element, of two properties every
/// K^L has: symmetry (|K - K^T| / max |K|) and the six rigid-body modes in its null space
/// (|K r| / (max |K| |r|) for the three translations and the three rotations about the element's
/// first node). The check of the elements without a plain host reference here (Hex20, Tet4,
/// Tet10; tests/unit compares them with references): a scrambled layout or a missing term fails it.
template <class View> double solidPropertyViolation(const Mesh &mesh, const View &ke) {
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ke);
  const LocalIndex ne = mesh.numElements();
  const int nn = static_cast<int>(h.extent(1)) / 3;
  double worst = 0.0;
  for (const LocalIndex e : {LocalIndex(0), ne / 2, ne - 1}) {
    double scale = 0.0, diff = 0.0;
    for (int i = 0; i < 3 * nn; ++i)
      for (int j = 0; j < 3 * nn; ++j) {
        scale = std::max(scale, std::abs(h(e, i, j)));
        diff = std::max(diff, std::abs(h(e, i, j) - h(e, j, i)));
      }
    for (int mode = 0; mode < 6; ++mode) {
      std::vector<double> r(3 * nn);
      double rmax = 0.0;
      for (int a = 0; a < nn; ++a) {
        double d[3];
        for (int i = 0; i < 3; ++i)
          d[i] = mesh.coordinate(mesh.node(e, a), i) - mesh.coordinate(mesh.node(e, 0), i);
        for (int i = 0; i < 3; ++i) {
          // Translation along `mode`, or the rotation about axis mode - 3.
          r[3 * a + i] = mode < 3 ? (i == mode ? 1.0 : 0.0) : rigidRotation(3, mode - 3, i, d);
          rmax = std::max(rmax, std::abs(r[3 * a + i]));
        }
      }
      for (int i = 0; i < 3 * nn; ++i) {
        double kr = 0.0;
        for (int j = 0; j < 3 * nn; ++j)
          kr += h(e, i, j) * r[j];
        diff = std::max(diff, std::abs(kr) / rmax);
      }
    }
    worst = std::max(worst, diff / scale);
  }
  return worst;
}

template <class Exec, Kernel K = Kernel::Chosen>
void solidElementMatrices(benchmark::State &state) {
  if (!baselineCanRun<Exec>(state))
    return;
  const ElementType type = solidTypeOf(state);
  const SolidSetup s = makeSolidSetup(static_cast<int>(state.range(1)), type);
  dispatchSolidElement(type, "this 3D benchmark", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int nd = 3 * Elem::kNumNodes;
    const LocalIndex ne = s.mesh.numElements();
    Kokkos::View<double ***, Memory> ke("ke", ne, nd, nd);
    const auto law = linearElasticLaw(s.data);
    stiffnessWith<K, Elem>(Exec(), s.data.mesh, s.data.thickness, law, ke);
    Exec().fence();
    const bool hex8 = type == ElementType::Hex8;
    const double m = hex8 ? solidMismatch(s, ke) : solidPropertyViolation(s.mesh, ke);
    if (!(m < (hex8 ? 1e-12 : 1e-9))) {
      state.SkipWithError((std::string(hex8 ? "Hex8 K^L differs from the host reference by "
                                            : "K^L breaks symmetry or a rigid-body mode by ") +
                           std::to_string(m) + " (relative)")
                              .c_str());
      return;
    }
    timeElementMatrices<Exec>(
        state, ne, nd * nd * 8.0, solidStiffnessFlops(Elem::kNumNodes, Elem::kNumQp),
        [&] { stiffnessWith<K, Elem>(Exec(), s.data.mesh, s.data.thickness, law, ke); });
  });
}

/// The plain host reference above, one element after another on one thread.
void solidHostReference(benchmark::State &state) {
  const SolidSetup s = makeSolidSetup(static_cast<int>(state.range(1)));
  const Eigen::MatrixXd c = solidStiffnessMatrix(s);
  timeHostReference(state, s.mesh.numElements(),
                    [&](LocalIndex e) { return referenceHexStiffness(s.mesh, e, c)(0, 0); });
}

/// Fused compute + atomic CSR scatter of the Hex8 K^L (3 unknowns per node), checked first: the
/// assembled matrix times a smooth displacement field equals the sum of the element matrices
/// (host reference) times it.
template <Kernel K = Kernel::Chosen> void solidAssembleCsr(benchmark::State &state) {
  using Exec = Kokkos::DefaultExecutionSpace;
  const auto assemble = [](const SolidSetup &s, const auto &map, const auto &a) {
    const auto law = linearElasticLaw(s.data);
    if constexpr (K == Kernel::Lanes)
      assembleElementStiffnessLanes<Hex8>(Exec(), s.data.mesh, 1.0, law, map, a);
    else if constexpr (K == Kernel::Team)
      assembleElementStiffnessTeam<Hex8>(Exec(), s.data.mesh, 1.0, law, map, a);
    else
      assembleLinearStiffness<Hex8>(Exec(), s.data, map, a);
  };
  const SolidSetup s = makeSolidSetup(static_cast<int>(state.range(1)));
  const NodeGraph g = buildNodeGraph(s.mesh);
  auto a = expandGraph<Memory>(g, 3);
  const auto map = elementScatterMap<Memory>(s.mesh, g);
  constexpr int nd = 3 * Hex8::kNumNodes;
  const LocalIndex nn = s.mesh.numNodes(), ne = s.mesh.numElements();
  {
    Kokkos::deep_copy(a.values, 0.0);
    assemble(s, map, a);
    Exec().fence();
    // K u for u = (sin 3x + yz, cos 2y + x^2, x z^2 + y) (not in the null space or constant
    // stress, so interior rows count too): the kernel's CSR against the reference's elements.
    const auto u = [&](LocalIndex k, int i) {
      const double x = s.mesh.x(k), y = s.mesh.y(k), z = s.mesh.z(k);
      return i == 0   ? std::sin(3.0 * x) + y * z
             : i == 1 ? std::cos(2.0 * y) + x * x
                      : x * z * z + y;
    };
    const auto ro = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.rowOffsets);
    const auto ci = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.columns);
    const auto va = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.values);
    std::vector<double> ku(3 * nn, 0.0), ref(3 * nn, 0.0);
    for (LocalIndex r = 0; r < 3 * nn; ++r)
      for (auto k = ro(r); k < ro(r + 1); ++k)
        ku[r] += va(k) * u(ci(k) / 3, ci(k) % 3);
    const Eigen::MatrixXd c = solidStiffnessMatrix(s);
    for (LocalIndex e = 0; e < ne; ++e) {
      const Eigen::MatrixXd k = referenceHexStiffness(s.mesh, e, c);
      for (int p = 0; p < nd; ++p)
        for (int q = 0; q < nd; ++q)
          ref[3 * s.mesh.node(e, p / 3) + p % 3] += k(p, q) * u(s.mesh.node(e, q / 3), q % 3);
    }
    double diff = 0.0, scale = 0.0;
    for (LocalIndex r = 0; r < 3 * nn; ++r) {
      diff = std::max(diff, std::abs(ku[r] - ref[r]));
      scale = std::max(scale, std::abs(ref[r]));
    }
    if (!(diff <= 1e-11 * scale)) {
      state.SkipWithError("Hex8 CSR assembly differs from the host reference");
      return;
    }
  }
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    Kokkos::deep_copy(Exec(), a.values, 0.0);
    assemble(s, map, a);
    Exec().fence();
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  // Bytes as for 2D: zeroing the values, nd^2 atomic read-modify-writes (16 B) and the scatter
  // map (nodes^2 ints) per element.
  const double bytes =
      a.numNonzeros() * 8.0 + ne * (nd * nd * 16.0 + Hex8::kNumNodes * Hex8::kNumNodes * 4.0);
  state.counters["elem/s"] =
      benchmark::Counter(static_cast<double>(ne), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["GB/s"] =
      benchmark::Counter(bytes / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["GFLOP/s"] =
      benchmark::Counter(ne * solidStiffnessFlops(Hex8::kNumNodes, Hex8::kNumQp) / 1e9,
                         benchmark::Counter::kIsIterationInvariantRate);
  state.counters["nnz"] = static_cast<double>(a.numNonzeros());
  state.counters["DOF"] = 3.0 * nn;
}

/// Mesh sizes of the threaded kernels: on a GPU (memory the host cannot address), or with
/// MIXCON_BENCH_FULL=1 for the CPU figure beside it, one more of about 1e6 elements (2D n = 1024:
/// up to 2 GB of Quad8 matrices; 3D n = 96: 4 GB).
const bool kLarge = !Kokkos::SpaceAccessibility<Kokkos::HostSpace, Memory>::accessible ||
                    std::getenv("MIXCON_BENCH_FULL") != nullptr;
std::vector<int64_t> planeSizes() {
  return kLarge ? std::vector<int64_t>{64, 256, 512, 1024} : std::vector<int64_t>{64, 256, 512};
}
std::vector<int64_t> solidSizes() {
  return kLarge ? std::vector<int64_t>{16, 32, 48, 96} : std::vector<int64_t>{16, 32, 48};
}
/// Hex20 (3.6 kB of matrix per element), Tet4 (6 per cell) and Tet10 (6 per cell, 0.9 kB each):
/// the large size about 4-6 GB of element matrices.
std::vector<int64_t> solidSizesOf(int nodes) {
  std::vector<int64_t> n{8, 16, 32};
  if (kLarge)
    n.push_back(nodes == 4 ? 96 : 48);
  return n;
}

} // namespace linear_stiffness_bench
using namespace linear_stiffness_bench;

BENCHMARK(elementMatrices<Kokkos::DefaultExecutionSpace, Kernel::Chosen>)
    ->Name("KL/elementMatrices/threads")
    ->ArgsProduct({{4, 8}, planeSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
#ifdef KOKKOS_ENABLE_SERIAL
BENCHMARK(elementMatrices<Kokkos::Serial, Kernel::Chosen>)
    ->Name("KL/elementMatrices/serial-baseline")
    ->ArgsProduct({{4, 8}, {64, 256, 512}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
#endif
BENCHMARK(hostReference)
    ->Name("KL/elementMatrices/host-reference")
    ->ArgsProduct({{4, 8}, {64, 256}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(mixedElementMatrices)
    ->Name("mixed/elementMatrices/threads")
    ->ArgsProduct({{4, 8}, planeSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(mixedHostReference)
    ->Name("mixed/elementMatrices/host-reference")
    ->ArgsProduct({{4, 8}, {64, 256}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(geometricElementMatrices)
    ->Name("Ksigma/elementMatrices/threads")
    ->ArgsProduct({{4, 8}, planeSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(geometricHostReference)
    ->Name("Ksigma/elementMatrices/host-reference")
    ->ArgsProduct({{4, 8}, {64, 256}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(assembleCsr)
    ->Name("KL/assembleCsr/threads")
    ->ArgsProduct({{4, 8}, planeSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
// 3D (issue 17): `nodes` is 8 (Hex8), 20 (Hex20), 4 (Tet4) or 10 (Tet10), n the divisions of
// the cube (n^3 hexahedra, 6 n^3 tetrahedra).
BENCHMARK(solidElementMatrices<Kokkos::DefaultExecutionSpace, Kernel::Chosen>)
    ->Name("KL3D/elementMatrices/threads")
    ->ArgsProduct({{8}, solidSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(solidElementMatrices<Kokkos::DefaultExecutionSpace, Kernel::Chosen>)
    ->Name("KL3D/elementMatrices/threads")
    ->ArgsProduct({{20}, solidSizesOf(20)})
    ->ArgsProduct({{4}, solidSizesOf(4)})
    ->ArgsProduct({{10}, solidSizesOf(10)})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
#ifdef KOKKOS_ENABLE_SERIAL
BENCHMARK(solidElementMatrices<Kokkos::Serial, Kernel::Chosen>)
    ->Name("KL3D/elementMatrices/serial-baseline")
    ->ArgsProduct({{8}, {16, 32, 48}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
#endif
BENCHMARK(solidHostReference)
    ->Name("KL3D/elementMatrices/host-reference")
    ->ArgsProduct({{8}, {16, 32}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(solidAssembleCsr<>)
    ->Name("KL3D/assembleCsr/threads")
    ->ArgsProduct({{8}, solidSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
// The two stiffness kernels side by side (the "threads" cases above run the one the build
// chooses): SIMD lanes of elements per thread, and one team per element (docs/gpu.md).
BENCHMARK(elementMatrices<Kokkos::DefaultExecutionSpace, Kernel::Lanes>)
    ->Name("KL/elementMatrices/lanes")
    ->ArgsProduct({{4, 8}, planeSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(elementMatrices<Kokkos::DefaultExecutionSpace, Kernel::Team>)
    ->Name("KL/elementMatrices/team")
    ->ArgsProduct({{4, 8}, planeSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(solidElementMatrices<Kokkos::DefaultExecutionSpace, Kernel::Lanes>)
    ->Name("KL3D/elementMatrices/lanes")
    ->ArgsProduct({{8}, solidSizes()})
    ->ArgsProduct({{20}, solidSizesOf(20)})
    ->ArgsProduct({{4}, solidSizesOf(4)})
    ->ArgsProduct({{10}, solidSizesOf(10)})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(solidElementMatrices<Kokkos::DefaultExecutionSpace, Kernel::Team>)
    ->Name("KL3D/elementMatrices/team")
    ->ArgsProduct({{8}, solidSizes()})
    ->ArgsProduct({{20}, solidSizesOf(20)})
    ->ArgsProduct({{4}, solidSizesOf(4)})
    ->ArgsProduct({{10}, solidSizesOf(10)})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(solidAssembleCsr<Kernel::Lanes>)
    ->Name("KL3D/assembleCsr/lanes")
    ->ArgsProduct({{8}, solidSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(solidAssembleCsr<Kernel::Team>)
    ->Name("KL3D/assembleCsr/team")
    ->ArgsProduct({{8}, solidSizes()})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
int main(int argc, char **argv) { return mixcon::runBenchmarks(argc, argv); }
