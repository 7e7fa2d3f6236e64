// Google Benchmark: solver scaling of the mixed model against the displacement model on the
// DESIGN-NOTES strip (4 x 1, clamped at x = 0, end shear, E = 1, nu = 0.3, plane stress): Krylov
// iterations and time to a 1e-8 relative residual versus the number of unknowns, from about 1e3
// to 1e6, for
//   displacement  - hypre PCG + BoomerAMG on Kd (the baseline)
//   lumped a=0    - flexible CG on the assembled lumped Schur complement S_L, AMG(S_L)
//   lumped a>0    - same on S_a,L = (1-a) S_L + a Kd
//   exact a       - flexible CG on the matrix-free consistent-M S_a (inner CG on M), AMG(S_a,L)
//   exact-kd a    - same, AMG built on Kd instead (`preconditioner: auto`, method schur)
//   block-triangular a - flexible GMRES on the whole saddle point, block-triangular
//                   preconditioner (AMG(Kd), CG on M to 1e-2 or tighter): `method:
//                   block_triangular`
//   lumped-block-triangular a - the same with lumped M (AMG(S_a,L), M~ = M_L)
//   block-triangular-schur a - consistent M, block-triangular with AMG(S_a,L) for S~
//                   (`method: block_triangular, preconditioner: lumped_schur`); Quad4 only (on
//                   Quad8, whose row-sum lumped M is refused, it did not converge: 15,030
//                   iterations over the AMG ladder at 63k unknowns)
// Each solve runs once per case (real time; the counters carry the figures). Counters:
// unknowns (5 per node mixed, 2 displacement), iterations, setup_s (assembly + AMG setup),
// solve_s, inner (CG iterations on M per outer iteration), Munknowns/s (unknowns / solve time).
// MIXCON_BENCH_MAX_UNKNOWNS caps the sizes (default 1.1e6; the mixed unknowns, 5 per node, count).
// All but the exact (AMG(S_L)) cases also run on the displacement model's largest meshes
// (about 1e6 displacement unknowns, 2.5e6 mixed). MIXCON_BENCH_STRESS_TOLERANCE sets the
// block-triangular preconditioner's CG tolerance on M (default 1e-2), MIXCON_BENCH_RESTART its
// GMRES restart (default 30), MIXCON_BENCH_AMG_CYCLE who runs the V-cycles (`amg_cycle`: hypre,
// double, single; unset: auto), MIXCON_BENCH_CHEBYSHEV_ORDER the Chebyshev smoother's order
// (`chebyshev_order`, 1 to 4; unset: 2).
#include <bench/BenchMain.hpp>
#include <mesh/Generators.hpp>
#include <solver/DisplacementModel.hpp>
#include <solver/MixedModel.hpp>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>

using namespace mixcon;

namespace {

enum Method {
  Displacement = 0,
  Lumped = 1,
  Exact = 2,
  ExactKd = 3,
  BlockTriangular = 4,
  LumpedBlockTriangular = 5,
  BlockTriangularLumpedSchur = 6
};

double maxUnknowns() {
  const char *v = std::getenv("MIXCON_BENCH_MAX_UNKNOWNS");
  return v ? std::atof(v) : 1.1e6;
}

void strip(benchmark::State &state) {
  const auto method = static_cast<Method>(state.range(0));
  const ElementType type = state.range(1) == 8 ? ElementType::Quad8 : ElementType::Quad4;
  const int ny = static_cast<int>(state.range(2));
  const double a = state.range(3) / 100.0;
  const Mesh mesh = rectangleMesh(4.0, 1.0, 4 * ny, ny, type);
  const long unknowns = static_cast<long>(mesh.numNodes()) * (method == Displacement ? 2 : 5);
  if (unknowns > maxUnknowns()) {
    state.SkipWithError("above MIXCON_BENCH_MAX_UNKNOWNS");
    for (auto _ : state) {
    }
    return;
  }
  const std::vector<int> mat(mesh.numElements(), 0);
  const std::vector<PlaneMatrix> c{isotropicStiffness(1.0, 0.3, PlaneAnalysis::PlaneStress)};
  std::unique_ptr<ModelBase> model;
  if (method == Displacement)
    model = std::make_unique<LinearDisplacementModel>(mesh, mat, c, 1.0);
  else
    model = std::make_unique<MixedModel>(mesh, mat, c, 1.0);
  for (LocalIndex n : mesh.nodesOf("left")) {
    model->prescribe(n, 0, 0.0);
    model->prescribe(n, 1, 0.0);
  }
  model->addEdgeLoad(mesh.boundaries.at("right"), 0.0, 1e-3, 0.0);
  LinearSolverOptions lo;
  lo.tolerance = 1e-8;
  lo.maxIterations = 5000;
  if (const char *t = std::getenv("MIXCON_STRONG_THRESHOLD"))
    lo.strongThreshold = std::atof(t);
  // Who runs the V-cycle (amg_cycle): hypre, double, single; unset: the default (auto)
  if (const char *c = std::getenv("MIXCON_BENCH_AMG_CYCLE")) {
    const std::string v = c;
    if (v != "hypre" && v != "double" && v != "single" && v != "auto") {
      state.SkipWithError("MIXCON_BENCH_AMG_CYCLE: hypre, double, single or auto");
      return;
    }
    lo.cycle = v == "hypre"    ? AmgCycleKind::Hypre
               : v == "double" ? AmgCycleKind::MixconDouble
               : v == "single" ? AmgCycleKind::MixconSingle
                               : AmgCycleKind::Automatic;
  }
  if (const char *c = std::getenv("MIXCON_BENCH_CHEBYSHEV_ORDER")) { // 1 to 4; unset: 2, as in 2D
    lo.chebyshevOrder = std::atoi(c);
    if (lo.chebyshevOrder < 1 || lo.chebyshevOrder > 4) {
      state.SkipWithError("MIXCON_BENCH_CHEBYSHEV_ORDER: 1 to 4");
      return;
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  if (method == Displacement) {
    static_cast<LinearDisplacementModel &>(*model).setup(lo, MPI_COMM_WORLD);
  } else {
    MixedOptions o;
    o.linear = lo;
    o.stabilization = a;
    const bool lumped = method == Lumped || method == LumpedBlockTriangular;
    o.compliance = lumped ? ComplianceMass::Lumped : ComplianceMass::Consistent;
    o.preconditioner = method == ExactKd || method == BlockTriangular
                           ? SchurPreconditioner::Stiffness
                           : SchurPreconditioner::LumpedSchur;
    o.method = method == BlockTriangular || method == LumpedBlockTriangular ||
                       method == BlockTriangularLumpedSchur
                   ? MixedLinearMethod::BlockTriangular
                   : MixedLinearMethod::Schur;
    if (const char *t = std::getenv("MIXCON_BENCH_STRESS_TOLERANCE"))
      o.preconditionerTolerance = std::atof(t);
    if (const char *r = std::getenv("MIXCON_BENCH_RESTART"))
      o.restart = std::atoi(r);
    static_cast<MixedModel &>(*model).setup(o, MPI_COMM_WORLD);
  }
  const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  LinearSolveStats st;
  for (auto _ : state) {
    st = model->solve(1.0);
    Kokkos::fence();
  }
  if (!st.converged)
    state.SkipWithError("did not converge");
  state.counters["unknowns"] = static_cast<double>(unknowns);
  state.counters["iterations"] = st.iterations;
  state.counters["setup_s"] = setup;
  state.counters["solve_s"] = st.solveSeconds;
  state.counters["Munknowns/s"] = unknowns / st.solveSeconds / 1e6;
  if (method != Displacement) {
    const auto &m = static_cast<const MixedModel &>(*model);
    state.counters["inner"] =
        st.iterations > 0 ? static_cast<double>(m.innerIterations()) / m.operatorApplications() : 0;
  }
  state.SetLabel(model->solverName());
}

void sizes(benchmark::internal::Benchmark *b, std::initializer_list<int> methods, int a) {
  for (int m : methods) {
    // 2 unknowns per node for the displacement model: two more sizes reach 1e6 unknowns. The
    // default's competitors also run there (the comparison on the same mesh).
    const bool sameMesh = m != Exact;
    for (int ny : {8, 16, 32, 64, 128, 224, 352})
      if (ny < 352 || sameMesh)
        b->Args({m, 4, ny, m == Displacement ? 0 : a});
    for (int ny : {4, 8, 16, 32, 64, 128, 200})
      if (m != Lumped && m != LumpedBlockTriangular && m != BlockTriangularLumpedSchur &&
          (ny < 200 || sameMesh)) // HRZ: refused
        b->Args({m, 8, ny, m == Displacement ? 0 : a});
  }
}

} // namespace

BENCHMARK(strip)
    ->Name("strip/displacement")
    ->Apply([](auto *b) { sizes(b, {Displacement}, 0); })
        -> ArgNames({"method", "nodes", "ny", "a%"}) -> Iterations(1) -> Unit(benchmark::kSecond);
BENCHMARK(strip)
    ->Name("strip/mixed-lumped")
    ->Apply([](auto *b) {
      sizes(b, {Lumped}, 0);
      sizes(b, {Lumped}, 5);
    }) -> ArgNames({"method", "nodes", "ny", "a%"}) -> Iterations(1) -> Unit(benchmark::kSecond);
BENCHMARK(strip)
    ->Name("strip/mixed-exact")
    ->Apply([](auto *b) {
      sizes(b, {Exact}, 5);
      sizes(b, {Exact}, 1);
      sizes(b, {Exact}, 0);
    }) -> ArgNames({"method", "nodes", "ny", "a%"}) -> Iterations(1) -> Unit(benchmark::kSecond);
BENCHMARK(strip)
    ->Name("strip/mixed-exact-kd")
    ->Apply([](auto *b) {
      sizes(b, {ExactKd}, 5);
      sizes(b, {ExactKd}, 1);
    }) -> ArgNames({"method", "nodes", "ny", "a%"}) -> Iterations(1) -> Unit(benchmark::kSecond);

BENCHMARK(strip)
    ->Name("strip/mixed-block-triangular")
    ->Apply([](auto *b) {
      sizes(b, {BlockTriangular}, 5);
      sizes(b, {BlockTriangular}, 1);
    }) -> ArgNames({"method", "nodes", "ny", "a%"}) -> Iterations(1) -> Unit(benchmark::kSecond);

BENCHMARK(strip)
    ->Name("strip/mixed-block-triangular-schur")
    ->Apply([](auto *b) { sizes(b, {BlockTriangularLumpedSchur}, 5); })
        -> ArgNames({"method", "nodes", "ny", "a%"}) -> Iterations(1) -> Unit(benchmark::kSecond);

BENCHMARK(strip)
    ->Name("strip/mixed-lumped-block-triangular")
    ->Apply([](auto *b) { sizes(b, {LumpedBlockTriangular}, 5); })
        -> ArgNames({"method", "nodes", "ny", "a%"}) -> Iterations(1) -> Unit(benchmark::kSecond);

int main(int argc, char **argv) { return mixcon::runBenchmarks(argc, argv); }
