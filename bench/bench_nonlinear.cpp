// Google Benchmark: the geometrically nonlinear kernels against the linear K^L assembly measured
// in the same run (the baseline): the displacement model's fused internal force + exact tangent
// assembly (Almansi law), the mixed model's fused residual + Jacobian assembly (current form,
// 5 unknowns per node), and one full Newton iteration of the displacement model (assembly, AMG
// setup, GMRES solve, residual) on a bent unit square. Counters: elements/s, DOF/s.
#include <bench/BenchMain.hpp>
#include <kernels/Nonlinear.hpp>
#include <mesh/Generators.hpp>
#include <solver/MixedModel.hpp>
#include <solver/Nonlinear.hpp>
#include <support/NonlinearReference.hpp>

#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>

using namespace mixcon;
using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;

namespace {

ElementType typeOf(const benchmark::State &state) {
  return state.range(0) == 8 ? ElementType::Quad8 : ElementType::Quad4;
}

const std::vector<PlaneMatrix> kMaterial{orthotropicStiffness(
    {1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4}, PlaneAnalysis::PlaneStress, 0.3)};

/// A smooth finite deformation (bending plus stretch, strains of a few percent) of the unit square.
std::vector<double> bentField(const Mesh &mesh, int stride) {
  std::vector<double> x(stride * static_cast<std::size_t>(mesh.numNodes()), 0.0);
  for (LocalIndex k = 0; k < mesh.numNodes(); ++k) {
    const double X = mesh.x(k), Y = mesh.y(k);
    x[stride * k] = 0.03 * X + 0.05 * X * Y;
    x[stride * k + 1] = 0.2 * X * X - 0.01 * Y;
  }
  return x;
}

struct Timer {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
};

void linearBaseline(benchmark::State &state) {
  const Mesh mesh = rectangleMesh(1.0, 1.0, state.range(1), state.range(1), typeOf(state));
  ElementData<Memory> d;
  d.mesh = toDevice<Memory>(mesh);
  d.material = Kokkos::View<int *, Memory>("material", mesh.numElements());
  d.stiffness = Kokkos::View<PlaneMatrix *, Memory>("stiffness", 1);
  auto h = Kokkos::create_mirror_view(d.stiffness);
  h(0) = kMaterial[0];
  Kokkos::deep_copy(d.stiffness, h);
  const NodeGraph g = buildNodeGraph(mesh);
  auto a = expandGraph<Memory>(g, 2);
  const auto map = elementScatterMap<Memory>(mesh, g);
  dispatchPlaneElement(mesh.elementType, "this 2D benchmark", [&](auto elem) {
    using Elem = decltype(elem);
    for (auto _ : state) {
      Timer t;
      Kokkos::deep_copy(Exec(), a.values, 0.0);
      assembleLinearStiffness<Elem>(Exec(), d, map, a);
      Exec().fence();
      state.SetIterationTime(t.seconds());
    }
  });
  state.counters["elem/s"] = benchmark::Counter(static_cast<double>(mesh.numElements()),
                                                benchmark::Counter::kIsIterationInvariantRate);
}

/// GB/s of a fused residual + tangent assembly with `d` unknowns per node, counted as for the
/// K^L assembly (bench_linear_stiffness.cpp): zeroing the CSR values, (d n)^2 atomic
/// read-modify-writes (16 B) and d n residual ones per element, the scatter map (n^2 ints).
void setAssemblyTraffic(benchmark::State &state, const Mesh &mesh, int d) {
  const double n = mesh.nodesPerElement;
  const double nnz = static_cast<double>(buildNodeGraph(mesh).columns.size()) * d * d;
  const double bytes =
      nnz * 8.0 + mesh.numElements() * ((d * n) * (d * n) * 16.0 + d * n * 16.0 + n * n * 4.0);
  state.counters["GB/s"] =
      benchmark::Counter(bytes / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

/// Residual + exact tangent of the displacement model with the elastic law `law`.
void displacementAssembly(benchmark::State &state, ElasticLaw law) {
  const Mesh mesh = rectangleMesh(1.0, 1.0, state.range(1), state.range(1), typeOf(state));
  NonlinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), kMaterial, 1.0);
  model.setElasticLaw(law);
  model.prescribe(0, 0, 0.0);
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  model.setup(o, MPI_COMM_WORLD);
  model.setDisplacement(bentField(mesh, 2));
  for (auto _ : state) {
    Timer t;
    model.evaluate(1.0, true); // zero, residual + tangent, norms
    Exec().fence();
    state.SetIterationTime(t.seconds());
  }
  state.counters["elem/s"] = benchmark::Counter(static_cast<double>(mesh.numElements()),
                                                benchmark::Counter::kIsIterationInvariantRate);
  state.counters["DOF"] = 2.0 * mesh.numNodes();
  setAssemblyTraffic(state, mesh, 2);
}

void mixedAssembly(benchmark::State &state) {
  const Mesh mesh = rectangleMesh(1.0, 1.0, state.range(1), state.range(1), typeOf(state));
  NonlinearMixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), kMaterial, 1.0);
  model.prescribe(0, 0, 0.0);
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  model.setup(o, MPI_COMM_WORLD);
  auto x = bentField(mesh, 5);
  for (std::size_t k = 0; k < x.size() / 5; ++k)
    x[5 * k + 2] = 1e3; // a prestress
  model.setIncrement(x);
  for (auto _ : state) {
    Timer t;
    model.evaluate(1.0, true);
    Exec().fence();
    state.SetIterationTime(t.seconds());
  }
  state.counters["elem/s"] = benchmark::Counter(static_cast<double>(mesh.numElements()),
                                                benchmark::Counter::kIsIterationInvariantRate);
  state.counters["DOF"] = 5.0 * mesh.numNodes();
  setAssemblyTraffic(state, mesh, 5);
}

/// The residual alone (batched element kernel + atomic scatter, zeroing and norms included) of
/// the displacement model (Almansi law) or the mixed model (current form, a = 0), in the
/// deformed state of displacementAssembly / mixedAssembly; the tests' host reference of the same
/// residual is residualHostReference.
void residualOnly(benchmark::State &state) {
  const Mesh mesh = rectangleMesh(1.0, 1.0, state.range(1), state.range(1), typeOf(state));
  const bool mixed = state.range(2) != 0;
  std::unique_ptr<NonlinearModel> model;
  if (mixed)
    model = std::make_unique<NonlinearMixedModel>(mesh, std::vector<int>(mesh.numElements(), 0),
                                                  kMaterial, 1.0);
  else
    model = std::make_unique<NonlinearDisplacementModel>(
        mesh, std::vector<int>(mesh.numElements(), 0), kMaterial, 1.0);
  if (mixed)
    static_cast<NonlinearMixedModel &>(*model).setStabilization(0.0);
  model->prescribe(0, 0, 0.0);
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  model->setup(o, MPI_COMM_WORLD);
  auto x = bentField(mesh, mixed ? 5 : 2);
  if (mixed) {
    for (std::size_t k = 0; k < x.size() / 5; ++k)
      x[5 * k + 2] = 1e3; // a prestress
    static_cast<NonlinearMixedModel &>(*model).setIncrement(x);
  } else {
    static_cast<NonlinearDisplacementModel &>(*model).setDisplacement(x);
  }
  for (auto _ : state) {
    Timer t;
    model->evaluate(1.0, false);
    Exec().fence();
    state.SetIterationTime(t.seconds());
  }
  state.counters["elem/s"] = benchmark::Counter(static_cast<double>(mesh.numElements()),
                                                benchmark::Counter::kIsIterationInvariantRate);
}

/// The tests' host references of the same residuals (tests/support/NonlinearReference.hpp:
/// F = dx/dX, b^-1 and explicit B matrices with Eigen dynamic matrices, one element at a time).
void residualHostReference(benchmark::State &state) {
  test::Fixture f;
  f.mesh = rectangleMesh(1.0, 1.0, state.range(1), state.range(1), typeOf(state));
  f.materials = kMaterial;
  f.elementMaterial.assign(f.mesh.numElements(), 0);
  f.data.thickness = 1.0;
  const bool mixed = state.range(2) != 0;
  auto xs = bentField(f.mesh, mixed ? 5 : 2);
  if (mixed)
    for (std::size_t k = 0; k < xs.size() / 5; ++k)
      xs[5 * k + 2] = 1e3;
  const Eigen::Map<const Eigen::VectorXd> x(xs.data(), static_cast<Eigen::Index>(xs.size()));
  double sum = 0.0;
  for (auto _ : state) {
    Timer t;
    const Eigen::VectorXd g =
        mixed ? test::referenceMixedCurrent(f, x) : test::referenceAlmansiForce(f, x);
    sum += g(0);
    state.SetIterationTime(t.seconds());
  }
  benchmark::DoNotOptimize(sum);
  state.counters["elem/s"] = benchmark::Counter(static_cast<double>(f.mesh.numElements()),
                                                benchmark::Counter::kIsIterationInvariantRate);
}

/// The unit square clamped on its left edge under a follower pressure on the top.
void clampUnderPressure(NonlinearModel &model, const Mesh &mesh) {
  for (LocalIndex n : mesh.nodesOf("left")) {
    model.prescribe(n, 0, 0.0);
    model.prescribe(n, 1, 0.0);
  }
  model.addFollowerPressure(mesh.boundaries.at("top"), 2e3);
}

/// Where the time of the last timed Newton iteration went.
struct NewtonTimes {
  LinearSolveStats solve; ///< the correction's solver statistics (solveSeconds: whole correction)
  double evaluateSeconds = 0.0;       ///< residual + tangent, and the new residual
  double preconditionerSeconds = 0.0; ///< preconditioner setup inside the correction
};

/// Times one Newton iteration from the undeformed state per benchmark iteration: residual and
/// tangent, the correction, the new residual.
NewtonTimes timeNewtonIterations(NonlinearModel &model, benchmark::State &state) {
  NewtonTimes last;
  for (auto _ : state) {
    model.rollback(); // the same iteration each time: from the undeformed state
    Timer t;
    model.evaluate(1.0, true);
    Exec().fence();
    const double evaluate = t.seconds();
    const double setupBefore = model.solverSetupSeconds();
    double inc = 0.0;
    last.solve = model.correct(1.0, inc);
    last.preconditionerSeconds = model.solverSetupSeconds() - setupBefore;
    Timer e;
    model.evaluate(1.0, false);
    Exec().fence();
    last.evaluateSeconds = evaluate + e.seconds();
    state.SetIterationTime(t.seconds());
  }
  return last;
}

/// One Newton iteration of the displacement model: residual + tangent assembly, BoomerAMG setup
/// on the (nonsymmetric) tangent, GMRES to 1e-8, update, residual. Clamped left edge, a
/// follower pressure on the top edge.
void newtonIteration(benchmark::State &state) {
  const Mesh mesh = rectangleMesh(1.0, 1.0, state.range(1), state.range(1), typeOf(state));
  NonlinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), kMaterial, 1.0);
  clampUnderPressure(model, mesh);
  LinearSolverOptions o; // amg
  model.setup(o, MPI_COMM_WORLD);
  const int linear = timeNewtonIterations(model, state).solve.iterations;
  state.counters["DOF/s"] =
      benchmark::Counter(2.0 * mesh.numNodes(), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["DOF"] = 2.0 * mesh.numNodes();
  state.counters["gmres_its"] = linear;
}

/// Peak resident memory of the process so far (MB).
double peakMegabytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

/// One Newton step of the nonlinear mixed model (current form, 5 unknowns per node) with its
/// iterative solver (solver: amg: flexible GMRES on the Schur complement, inner block-Jacobi CG on
/// the stress block, BoomerAMG on K^L of the current configuration): setup included once (pattern,
/// AMG preconditioner), then residual + Jacobian, the solve and the new residual, timed from the
/// undeformed state. Clamped left edge, a follower pressure on the top. Peak memory: the
/// process's resident maximum (run the large case alone, as bench/report --full does).
void mixedNewtonStep(benchmark::State &state) {
  const Mesh mesh = rectangleMesh(1.0, 1.0, state.range(1), state.range(1), typeOf(state));
  NonlinearMixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), kMaterial, 1.0);
  model.setStabilization(state.range(2) / 100.0);
  MixedNewtonSolverOptions so;
  so.method = state.range(3) ? MixedNewtonSolver::Schur : MixedNewtonSolver::BlockTriangular;
  model.setIterativeSolver(so);
  clampUnderPressure(model, mesh);
  LinearSolverOptions o; // amg
  o.tolerance = 1e-6;
  // BoomerAMG on K^L with one level of aggressive coarsening and interpolation truncated to 4
  // entries: at 65k and 1e6 elements 25 % faster than the defaults (cheaper setup and V-cycle,
  // a few more iterations; docs/performance.md).
  o.aggressiveLevels = 1;
  o.interpolationMaxElements = 4;
  Timer setup;
  model.setup(o, MPI_COMM_WORLD);
  const double setupSeconds = setup.seconds();
  const NewtonTimes times = timeNewtonIterations(model, state);
  const int linear = times.solve.iterations;
  const long inner = model.innerIterations();
  state.counters["evaluate_s"] = times.evaluateSeconds;
  state.counters["precond_setup_s"] = times.preconditionerSeconds;
  state.counters["krylov_s"] = times.solve.solveSeconds - times.preconditionerSeconds;
  state.counters["elements"] = static_cast<double>(mesh.numElements());
  state.counters["DOF"] = 5.0 * mesh.numNodes();
  state.counters["DOF/s"] =
      benchmark::Counter(5.0 * mesh.numNodes(), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fgmres_its"] = linear;
  state.counters["inner_cg_its"] = static_cast<double>(inner);
  state.counters["setup_s"] = setupSeconds;
  state.counters["peak_MB"] = peakMegabytes();
}

} // namespace

BENCHMARK(linearBaseline)
    ->Name("KL/assembleCsr/baseline")
    ->ArgsProduct({{4, 8}, {128, 512}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(displacementAssembly, almansi, ElasticLaw::Almansi)
    ->Name("NL/displacement/residualAndTangent")
    ->ArgsProduct({{4, 8}, {128, 512}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(displacementAssembly, svk, ElasticLaw::SaintVenantKirchhoff)
    ->Name("NL/displacement/residualAndTangent/svk")
    ->ArgsProduct({{4, 8}, {128, 512}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(mixedAssembly)
    ->Name("NL/mixed/residualAndJacobian")
    ->ArgsProduct({{4, 8}, {128, 512}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(residualOnly)
    ->Name("NL/residual/threads")
    ->ArgsProduct({{4, 8}, {64, 256}, {0, 1}})
    ->ArgNames({"nodes", "n", "mixed"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(residualHostReference)
    ->Name("NL/residual/host-reference")
    ->ArgsProduct({{4, 8}, {64, 256}, {0, 1}})
    ->ArgNames({"nodes", "n", "mixed"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(newtonIteration)
    ->Name("NL/displacement/newtonIteration")
    ->ArgsProduct({{4, 8}, {128, 256}})
    ->ArgNames({"nodes", "n"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// The 1e6-element step (n = 1000) only with MIXCON_BENCH_FULL=1 (bench/report --full): about
// a minute and several GB. MIXCON_BENCH_NEWTON_N=n adds an n x n mesh (the largest step that
// fits a GPU: bench/gpu/measure.sh newton-large).
const bool kFull = std::getenv("MIXCON_BENCH_FULL") != nullptr;
std::vector<int64_t> newtonStepSizes() {
  std::vector<int64_t> n =
      kFull ? std::vector<int64_t>{128, 256, 1000} : std::vector<int64_t>{128, 256};
  if (const char *extra = std::getenv("MIXCON_BENCH_NEWTON_N"))
    n.push_back(std::atoll(extra));
  return n;
}
BENCHMARK(mixedNewtonStep)
    ->Name("NL/mixed/newtonStep")
    ->ArgsProduct({{4}, newtonStepSizes(), {0, 5}, {0, 1}})
    ->ArgNames({"nodes", "n", "a_percent", "schur"})
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

int main(int argc, char **argv) { return mixcon::runBenchmarks(argc, argv); }
