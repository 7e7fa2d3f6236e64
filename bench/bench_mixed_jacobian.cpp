// Google Benchmark: the nonlinear mixed model's Jacobian product y = J dx three ways, current
// form, a = 0, on a bent unit square (strains of a few percent, a stress state): matrix-free
// (kernels/MixedJacobianAction.hpp: the point law re-evaluated at every apply, colored scatter on
// host spaces), the CSR product of the assembled J (kernels/SparseMatrix.hpp multiply), and the
// assembly of J itself (assembleMixedCurrent: residual + Jacobian, the cost the matrix-free
// product avoids once per Newton step). Counters: elem/s; bytes/elem = what each way keeps per
// element beyond the state vectors (J's CSR arrays, or the action's element color list).
// JX/newtonStep: the first Newton iteration of NonlinearMixedModel (block-triangular GMRES,
// current form, a = 0.05, setup excluded: tangent, preconditioner setup, solve, the next
// residual and tangent) on a square clamped on the left and displaced on the right, with the
// assembled or the matrix-free Jacobian (MixedNewtonSolverOptions::jacobian).
#include <bench/BenchMain.hpp>
#include <kernels/MixedJacobianAction.hpp>
#include <mesh/Generators.hpp>
#include <solver/NonlinearMixedModel.hpp>

#include <benchmark/benchmark.h>

#include <chrono>
#include <random>

using namespace mixcon;
using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;

namespace {

enum class Way { MatrixFree, Csr, Assembly };

struct Problem {
  Mesh mesh;
  MixedElementData<Memory> d;
  Kokkos::View<double *, Memory> x, dx, y, g;
};

Problem makeProblem(ElementType type, int n) {
  Problem p;
  p.mesh = rectangleMesh(1.0, 1.0, n, n, type);
  const LocalIndex ne = p.mesh.numElements(), nn = p.mesh.numNodes();
  p.d.mesh = toDevice<Memory>(p.mesh);
  p.d.thickness = 1.0;
  p.d.material = Kokkos::View<int *, Memory>("material", ne); // zeros: material 0
  p.d.stiffness = Kokkos::View<PlaneMatrix *, Memory>("stiffness", 1);
  p.d.compliance = Kokkos::View<PlaneMatrix *, Memory>("compliance", 1);
  auto hs = Kokkos::create_mirror_view(p.d.stiffness);
  auto hc = Kokkos::create_mirror_view(p.d.compliance);
  hs(0) = orthotropicStiffness({1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4},
                               PlaneAnalysis::PlaneStress, 0.3);
  invert3(hs(0), hc(0));
  Kokkos::deep_copy(p.d.stiffness, hs);
  Kokkos::deep_copy(p.d.compliance, hc);
  p.x = Kokkos::View<double *, Memory>("x", 5 * nn);
  p.dx = Kokkos::View<double *, Memory>("dx", 5 * nn);
  p.y = Kokkos::View<double *, Memory>("y", 5 * nn);
  p.g = Kokkos::View<double *, Memory>("g", 5 * nn);
  auto hx = Kokkos::create_mirror_view(p.x);
  auto hd = Kokkos::create_mirror_view(p.dx);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (LocalIndex k = 0; k < nn; ++k) {
    const double X = p.mesh.x(k), Y = p.mesh.y(k);
    hx(5 * k) = 0.03 * X + 0.05 * X * Y;
    hx(5 * k + 1) = 0.2 * X * X - 0.01 * Y;
    for (int c = 2; c < 5; ++c)
      hx(5 * k + c) = 1e3 * u(rng);
    for (int c = 0; c < 5; ++c)
      hd(5 * k + c) = u(rng);
  }
  Kokkos::deep_copy(p.x, hx);
  Kokkos::deep_copy(p.dx, hd);
  return p;
}

template <class Elem> void run(benchmark::State &state, Way way, const Problem &p) {
  const Kokkos::View<const double *, Memory> x = p.x, dx = p.dx;
  const NodeGraph graph = buildNodeGraph(p.mesh);
  CsrMatrix<Memory> jac;
  Kokkos::View<int ***, Kokkos::LayoutRight, Memory> map;
  MixedElementColors<Memory> colors;
  double bytes = 0.0;
  if (way == Way::MatrixFree) {
    colors = mixedElementColors<Memory>(p.mesh, kDefaultMixedScatter<Exec>);
    bytes = static_cast<double>(colors.elements.extent(0) * sizeof(LocalIndex));
  } else {
    jac = expandGraph<Memory>(graph, 5);
    map = elementScatterMap<Memory>(p.mesh, graph);
    assembleMixedCurrent<Elem>(Exec(), p.d, x, 0.0, map, jac, p.g);
    bytes = static_cast<double>(jac.numNonzeros() * (sizeof(double) + sizeof(LocalIndex)) +
                                (jac.numRows + 1) * sizeof(Offset));
    if (way == Way::Assembly) // + the scatter map the assembly keeps
      bytes += static_cast<double>(map.size() * sizeof(int));
  }
  Exec().fence();
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    if (way == Way::MatrixFree) {
      applyMixedCurrentJacobian<Elem>(Exec(), p.d, x, 0.0, dx, p.y, colors);
    } else if (way == Way::Csr) {
      multiply(Exec(), jac, dx, p.y);
    } else {
      Kokkos::deep_copy(jac.values, 0.0);
      Kokkos::deep_copy(p.g, 0.0);
      assembleMixedCurrent<Elem>(Exec(), p.d, x, 0.0, map, jac, p.g);
    }
    Exec().fence();
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  const double ne = p.mesh.numElements();
  state.counters["elem"] = ne;
  state.counters["elem/s"] = benchmark::Counter(ne, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bytes/elem"] = bytes / ne;
}

void jacobianProduct(benchmark::State &state, Way way) {
  const bool quad8 = state.range(0) == 8;
  const Problem p = makeProblem(quad8 ? ElementType::Quad8 : ElementType::Quad4,
                                static_cast<int>(state.range(1)));
  if (quad8)
    run<Quad8>(state, way, p);
  else
    run<Quad4>(state, way, p);
}

void newtonStep(benchmark::State &state) {
  const int n = static_cast<int>(state.range(1));
  const Mesh mesh =
      rectangleMesh(1.0, 1.0, n, n, state.range(0) == 8 ? ElementType::Quad8 : ElementType::Quad4);
  const std::vector<PlaneMatrix> material{orthotropicStiffness(
      {1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4}, PlaneAnalysis::PlaneStress, 0.3)};
  int fgmres = 0;
  for (auto _ : state) {
    NonlinearMixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), material, 1.0);
    model.setStabilization(0.05);
    for (LocalIndex k : mesh.nodesOf("left")) {
      model.prescribe(k, 0, 0.0);
      model.prescribe(k, 1, 0.0);
    }
    for (LocalIndex k : mesh.nodesOf("right")) {
      model.prescribe(k, 0, 0.05);
      model.prescribe(k, 1, 0.2);
    }
    MixedNewtonSolverOptions so;
    so.jacobian = state.range(2) != 0 ? JacobianForm::MatrixFree : JacobianForm::Assembled;
    model.setIterativeSolver(so);
    LinearSolverOptions o; // amg
    o.tolerance = 1e-6;
    model.setup(o, MPI_COMM_WORLD);
    const auto t0 = std::chrono::steady_clock::now();
    model.evaluate(1.0, true);
    double inc = 0.0;
    fgmres = model.correct(1.0, inc).iterations;
    model.evaluate(1.0, true);
    Exec().fence();
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (model.matrixFree() != (state.range(2) != 0))
      state.SkipWithError("the matrix-free option was not taken");
  }
  state.counters["elem"] = mesh.numElements();
  state.counters["fgmres_its"] = fgmres;
}

} // namespace

// n x n elements: 1024, 1e4, 1e5.
#define MIXCON_JX(way, name)                                                                       \
  BENCHMARK_CAPTURE(jacobianProduct, name, way)                                                    \
      ->Name("JX/" #name)                                                                          \
      ->ArgsProduct({{4, 8}, {32, 100, 316}})                                                      \
      ->ArgNames({"nodes", "n"})                                                                   \
      ->UseManualTime()                                                                            \
      ->Unit(benchmark::kMillisecond)
MIXCON_JX(Way::MatrixFree, matrixFree);
MIXCON_JX(Way::Csr, csr);
MIXCON_JX(Way::Assembly, assembly);

BENCHMARK(newtonStep)
    ->Name("JX/newtonStep")
    ->ArgsProduct({{4, 8}, {32, 100}, {0, 1}})
    ->ArgNames({"nodes", "n", "matrix_free"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

int main(int argc, char **argv) { return mixcon::runBenchmarks(argc, argv); }
