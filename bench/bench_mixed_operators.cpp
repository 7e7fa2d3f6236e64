// Google Benchmark: the linear mixed model's blocks applied three ways (issue 16, item 3) on a
// square of Quad4 or Quad8 elements, two materials:
//   assembled - MixedOperators: node-graph coupling (Gx, Gy) and 3x3 compliance blocks per graph
//               entry (kernels/MixedElasticity.hpp; the baseline, measured in the same run);
//   partial   - partial assembly: t w det J and the weighted gradients per quadrature point
//               (kernels/MixedMatrixFree.hpp);
//   matfree   - fully matrix-free: geometry recomputed from the coordinates at every apply;
// both with the colored scatter (methods 1, 2; no atomics, one launch per element color, the
// CPU default) and the atomic one (methods 3, 4; the GPU default).
// Benchmarks: apply/<op> for op = K12^T u (0), K12 s (1) and M s (2), and setup (assembly of the
// operators, given the node graph and its scatter map, versus the partial assembly's precompute,
// versus the element coloring for matfree). Real time, a Kokkos fence before the clock stops;
// every apply case is first checked against the assembled apply (SkipWithError on a mismatch).
// Counters: elements/s and bytes/element, the operator storage the apply reads (graph + blocks, or
// the stored factors) plus the mesh (coordinates, connectivity, material) that every path reads.
// And solve: the model's Schur solve with each form (what the default is chosen by).
// Sizes 1e3, 1e4 and 1e5 elements by default (solve: 1e3, 1e4); `--mixcon_large` adds 1e6
// (solve: 1e5).
#include <bench/BenchMain.hpp>
#include <kernels/MixedMatrixFree.hpp>
#include <mesh/Generators.hpp>
#include <solver/MixedModel.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

using namespace mixcon;
using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;
using ConstVector = Kokkos::View<const double *, Memory>;
using Layout = FieldLayout<2>; // the plane problems: displacements and stresses per node

namespace {

enum Method { Assembled = 0, Partial = 1, MatrixFree = 2, PartialAtomic = 3, MatrixFreeAtomic = 4 };
enum Op { CouplingTranspose = 0, Coupling = 1, Compliance = 2 };

/// One problem, kept between the cases of the same size (only the latest, to bound memory).
struct Problem {
  ElementType type;
  int n = 0;
  Mesh mesh;
  MixedElementData<Memory> data;
  NodeGraph graph;
  DeviceNodeGraph<Memory> dgraph;
  Kokkos::View<int ***, Kokkos::LayoutRight, Memory> map;
  MixedOperators<Memory> assembled;
  MixedMatrixFreeOperators<Memory> partial, matrixFree, partialAtomic, matrixFreeAtomic;
  Kokkos::View<double *, Memory> u, s, f, r, y;
};

std::unique_ptr<Problem> current;

const Problem &problem(ElementType type, int n) {
  if (current && current->type == type && current->n == n)
    return *current;
  current.reset(); // free the previous size first
  auto p = std::make_unique<Problem>();
  p->type = type;
  p->n = n;
  p->mesh = rectangleMesh(1.0, 1.0, n, n, type);
  const LocalIndex ne = p->mesh.numElements(), nn = p->mesh.numNodes();
  p->data.mesh = toDevice<Memory>(p->mesh);
  p->data.thickness = 1.0;
  p->data.material = Kokkos::View<int *, Memory>("material", ne);
  p->data.stiffness = Kokkos::View<PlaneMatrix *, Memory>("stiffness", 2);
  p->data.compliance = Kokkos::View<PlaneMatrix *, Memory>("compliance", 2);
  auto hm = Kokkos::create_mirror_view(p->data.material);
  for (LocalIndex e = 0; e < ne; ++e)
    hm(e) = e % 2;
  Kokkos::deep_copy(p->data.material, hm);
  auto hs = Kokkos::create_mirror_view(p->data.stiffness);
  auto hc = Kokkos::create_mirror_view(p->data.compliance);
  hs(0) = orthotropicStiffness({1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4},
                               PlaneAnalysis::PlaneStress, 0.3);
  hs(1) = isotropicStiffness(2.0e5, 0.3, PlaneAnalysis::PlaneStrain);
  for (int i = 0; i < 2; ++i)
    invert3(hs(i), hc(i));
  Kokkos::deep_copy(p->data.stiffness, hs);
  Kokkos::deep_copy(p->data.compliance, hc);
  p->graph = buildNodeGraph(p->mesh);
  p->dgraph = toDevice<Memory>(p->graph);
  p->map = elementScatterMap<Memory>(p->mesh, p->graph);
  dispatchPlaneElement(type, "this 2D benchmark", [&](auto elem) {
    p->assembled = assembleMixedOperators<decltype(elem)>(Exec(), p->data, p->dgraph, p->map);
  });
  p->partial = makeMixedMatrixFree(Exec(), p->data, p->mesh, true, MixedScatter::Colored);
  p->matrixFree = makeMixedMatrixFree(Exec(), p->data, p->mesh, false, MixedScatter::Colored);
  p->partialAtomic = p->partial;
  p->partialAtomic.scatter = MixedScatter::Atomic;
  p->matrixFreeAtomic = p->matrixFree;
  p->matrixFreeAtomic.scatter = MixedScatter::Atomic;
  p->u = Kokkos::View<double *, Memory>("u", Layout::kNumDisplacements * nn);
  p->f = Kokkos::View<double *, Memory>("f", Layout::kNumDisplacements * nn);
  p->s = Kokkos::View<double *, Memory>("s", Layout::kNumStresses * nn);
  p->r = Kokkos::View<double *, Memory>("r", Layout::kNumStresses * nn);
  p->y = Kokkos::View<double *, Memory>("y", Layout::kNumStresses * nn);
  // u strains the mesh (a uniform u has K12^T u = 0, which the check before timing could not
  // compare against): u_i = 1e-3 (1 + i mod 7).
  auto hu = Kokkos::create_mirror_view(p->u);
  for (std::size_t i = 0; i < hu.extent(0); ++i)
    hu(i) = 1e-3 * static_cast<double>(1 + i % 7);
  Kokkos::deep_copy(p->u, hu);
  Kokkos::deep_copy(p->s, 1.0);
  Kokkos::fence();
  current = std::move(p);
  return *current;
}

template <class V> double bytes(const V &v) {
  return static_cast<double>(v.span() * sizeof(typename V::value_type));
}

/// Bytes per element of what an apply by `method` reads: the operator storage plus the mesh.
double bytesPerElement(const Problem &p, Method method) {
  const double mesh =
      bytes(p.data.mesh.coordinates) + bytes(p.data.mesh.connectivity) + bytes(p.data.material);
  double op = 0.0;
  if (method == Assembled)
    op = bytes(p.dgraph.rowOffsets) + bytes(p.dgraph.columns) + bytes(p.dgraph.transpose) +
         bytes(p.assembled.coupling) + bytes(p.assembled.compliance);
  else if (method == Partial || method == PartialAtomic)
    op = bytes(p.partial.geometry.weight) + bytes(p.partial.geometry.gradient);
  if (method == Partial || method == MatrixFree)
    op += bytes(p.partial.coloredElements);
  return (mesh + op) / p.mesh.numElements();
}

const MixedMatrixFreeOperators<Memory> &operatorsOf(const Problem &p, Method method) {
  return method == Partial         ? p.partial
         : method == MatrixFree    ? p.matrixFree
         : method == PartialAtomic ? p.partialAtomic
                                   : p.matrixFreeAtomic;
}

/// Counters of an apply or setup case: elements, elements/s and what an apply reads per element.
void elementCounters(benchmark::State &state, const Problem &p, Method method) {
  const double ne = p.mesh.numElements();
  state.counters["elements"] = ne;
  state.counters["elements/s"] =
      benchmark::Counter(ne, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bytes/element"] = bytesPerElement(p, method);
}

ElementType typeOf(const benchmark::State &state) {
  return state.range(0) == 8 ? ElementType::Quad8 : ElementType::Quad4;
}

template <class Ops> void applyOnce(const Problem &p, const Ops &ops, Op op) {
  if (op == CouplingTranspose)
    applyCouplingTranspose(Exec(), ops, ConstVector(p.u), p.r);
  else if (op == Coupling)
    applyCoupling(Exec(), ops, 1.0, ConstVector(p.s), 0.0, p.f);
  else
    applyCompliance(Exec(), ops, ConstVector(p.s), p.y);
}

/// Largest difference between `method`'s apply and the assembled operators' (the baseline),
/// relative to the largest entry of the assembled result; checked before a case is timed.
double differenceFromAssembled(const Problem &p, Method method, Op op) {
  const auto out = op == CouplingTranspose ? p.r : op == Coupling ? p.f : p.y;
  applyOnce(p, p.assembled, op);
  const std::vector<double> ref = toHostVector(out);
  if (method != Assembled)
    applyOnce(p, operatorsOf(p, method), op);
  const std::vector<double> got = toHostVector(out);
  double d = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    d = std::max(d, std::abs(got[i] - ref[i]));
    scale = std::max(scale, std::abs(ref[i]));
  }
  return d / scale;
}

/// Relative difference from the assembled apply above which a case is not timed (the forms
/// differ by summation order only: ~1e-15).
constexpr double kApplyTolerance = 1e-10;

void apply(benchmark::State &state) {
  const auto method = static_cast<Method>(state.range(2));
  const auto op = static_cast<Op>(state.range(3));
  const Problem &p = problem(typeOf(state), static_cast<int>(state.range(1)));
  if (differenceFromAssembled(p, method, op) > kApplyTolerance) {
    state.SkipWithError("differs from the assembled operators");
    return;
  }
  for (auto _ : state) {
    if (method == Assembled)
      applyOnce(p, p.assembled, op);
    else
      applyOnce(p, operatorsOf(p, method), op);
    Kokkos::fence();
  }
  elementCounters(state, p, method);
}

/// The strip of bench_mixed_solver: 4 x 1, ny element rows of 4 ny elements.
Mesh stripMesh(ElementType type, int ny) { return rectangleMesh(4.0, 1.0, 4 * ny, ny, type); }

/// The linear mixed model on `mesh` (kept alive by the caller): one isotropic plane-stress
/// material (E = 1, nu = 0.3), thickness 1, clamped at x = 0.
std::unique_ptr<MixedModel> clampedStrip(const Mesh &mesh) {
  auto model = std::make_unique<MixedModel>(
      mesh, std::vector<int>(mesh.numElements(), 0),
      std::vector<PlaneMatrix>{isotropicStiffness(1.0, 0.3, PlaneAnalysis::PlaneStress)}, 1.0);
  for (LocalIndex n : mesh.nodesOf("left")) {
    model->prescribe(n, 0, 0.0);
    model->prescribe(n, 1, 0.0);
  }
  return model;
}

/// The model's operator form that applies the blocks as `method` does (colored scatter).
MixedOperatorForm formOf(Method method) {
  return method == Assembled ? MixedOperatorForm::Assembled
         : method == Partial ? MixedOperatorForm::PartialAssembly
                             : MixedOperatorForm::MatrixFree;
}

/// The device-memory budget of the set-up model (the solve benchmark's strip, ~1e4 elements):
/// bytes per element of every view it holds (MixedModel::deviceViewBytes), as counters
/// `B/el <view>` and the total; one iteration, the time means nothing.
void memory(benchmark::State &state) {
  const auto method = static_cast<Method>(state.range(2));
  const ElementType type = typeOf(state);
  const int ny = static_cast<int>(state.range(1));
  const Mesh mesh = stripMesh(type, ny);
  auto strip = clampedStrip(mesh);
  MixedModel &model = *strip;
  MixedOptions o;
  o.operators = formOf(method);
  for (auto _ : state) {
    model.setup(o, MPI_COMM_WORLD);
    Kokkos::fence();
  }
  double total = 0.0;
  for (const auto &[name, bytes] : model.deviceViewBytes()) {
    const double perElement = static_cast<double>(bytes) / mesh.numElements();
    total += perElement;
    if (bytes > 0)
      state.counters["B/el " + name] = perElement;
  }
  state.counters["B/el total"] = total;
  state.counters["nodes/el"] = static_cast<double>(mesh.numNodes()) / mesh.numElements();
}

void setup(benchmark::State &state) {
  const auto method = static_cast<Method>(state.range(2));
  const ElementType type = typeOf(state);
  const Problem &p = problem(type, static_cast<int>(state.range(1)));
  for (auto _ : state) {
    dispatchPlaneElement(type, "this 2D benchmark", [&](auto elem) {
      using Elem = decltype(elem);
      if (method == Assembled)
        benchmark::DoNotOptimize(assembleMixedOperators<Elem>(Exec(), p.data, p.dgraph, p.map));
      else if (method == Partial)
        benchmark::DoNotOptimize(precomputeMixedGeometry<Elem>(Exec(), p.data));
      else // the element coloring (host) and its upload
        benchmark::DoNotOptimize(
            makeMixedMatrixFree(Exec(), p.data, p.mesh, false, MixedScatter::Colored));
    });
    Kokkos::fence();
  }
  elementCounters(state, p, method);
}

bool large = false;

/// The linear mixed model's Schur solve (consistent M, a = 0.05, flexible CG + BoomerAMG(Kd), the
/// defaults) on the strip of bench_mixed_solver (4 x 1, clamped at x = 0, end shear) with K12,
/// K12^T and M applied by `method` (assembled, partial assembly or matrix-free, colored): the time
/// of solve() (the Krylov iterations with their inner CG on M, and the stress recovery).
void solve(benchmark::State &state) {
  const auto method = static_cast<Method>(state.range(2));
  const ElementType type = typeOf(state);
  const int ny = static_cast<int>(state.range(1));
  const Mesh mesh = stripMesh(type, ny);
  auto strip = clampedStrip(mesh);
  MixedModel &model = *strip;
  model.addEdgeLoad(mesh.boundaries.at("right"), 0.0, 1e-3, 0.0);
  MixedOptions o;
  o.linear.tolerance = 1e-8;
  o.linear.maxIterations = 5000;
  o.operators = formOf(method);
  model.setup(o, MPI_COMM_WORLD);
  LinearSolveStats st = model.solve(1.0); // checked before it is timed
  if (!st.converged) {
    state.SkipWithError("did not converge");
    return;
  }
  for (auto _ : state) {
    st = model.solve(1.0);
    Kokkos::fence();
  }
  state.counters["elements"] = mesh.numElements();
  state.counters["elements/s"] = benchmark::Counter(static_cast<double>(mesh.numElements()),
                                                    benchmark::Counter::kIsIterationInvariantRate);
  state.counters["iterations"] = st.iterations;
  state.counters["inner"] =
      static_cast<double>(model.innerIterations()) / std::max(1L, model.operatorApplications());
  state.counters["assembly_s"] = model.assemblySeconds();
  state.SetLabel(model.solverName());
}

/// Elements per side: ~1e3, 1e4, 1e5 (and 1e6 with --mixcon_large) elements.
std::vector<int64_t> sides() {
  std::vector<int64_t> s{32, 100, 316};
  if (large)
    s.push_back(1000);
  return s;
}

void registerAll() {
  benchmark::RegisterBenchmark("apply", apply)
      ->ArgsProduct({{4, 8},
                     sides(),
                     {Assembled, Partial, MatrixFree, PartialAtomic, MatrixFreeAtomic},
                     {CouplingTranspose, Coupling, Compliance}})
      ->ArgNames({"nodes", "n", "method", "op"})
      ->UseRealTime()
      ->Unit(benchmark::kMicrosecond);
  // ~1e3 and ~1e4 elements (4 ny^2), ~1e5 with --mixcon_large.
  std::vector<int64_t> ny{16, 50};
  if (large)
    ny.push_back(158);
  benchmark::RegisterBenchmark("solve", solve)
      ->ArgsProduct({{4, 8}, ny, {Assembled, Partial, MatrixFree}})
      ->ArgNames({"nodes", "ny", "method"})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("memory", memory)
      ->ArgsProduct({{4, 8}, {50}, {Assembled, Partial, MatrixFree}})
      ->ArgNames({"nodes", "ny", "method"})
      ->Iterations(1);
  benchmark::RegisterBenchmark("setup", setup)
      ->ArgsProduct({{4, 8}, sides(), {Assembled, Partial, MatrixFree}})
      ->ArgNames({"nodes", "n", "method"})
      ->UseRealTime()
      ->Unit(benchmark::kMicrosecond);
}

} // namespace

int main(int argc, char **argv) {
  // --mixcon_large (ours, removed before Google Benchmark parses the rest): add 1e6 elements.
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--mixcon_large") == 0)
      large = true;
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
  Environment env(argc, argv);
  benchmark::Initialize(&argc, argv);
  benchmark::AddCustomContext("kokkos", Environment::describe());
  benchmark::AddCustomContext("git", MIXCON_GIT_HASH);
  registerAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  current.reset(); // Kokkos views freed before Kokkos finalizes
  return 0;
}
