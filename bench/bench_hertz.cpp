// Google Benchmark: the Hertz contact examples end to end, as a user runs them (problem file
// read, mesh generated, every load step with its contact iterations, contact.csv and
// summary.json written; HDF5 off): the cylinder on a rigid plane
// (examples/hertz/hertz_refined.yaml, graded Quad8, rigid-obstacle contact) and the elastic
// cylinder on an elastic block (examples/elastic_contact/hertz_two_body.yaml, Quad4,
// node-to-segment contact), and the report's 84-element mesh. Counters: unknowns, steps, Newton
// corrections, closed contact nodes at the last step. The accuracy against the closed form is
// in examples/hertz_study.py and examples/elastic_contact_study.py.
#include <apps/Analysis.hpp>
#include <bench/BenchMain.hpp>
#include <io/Problem.hpp>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <filesystem>

using namespace mixcon;

namespace {

/// 0: rigid plane, graded Quad8; 1: two elastic bodies, Quad4; 2: the report's 84-element mesh
/// (the smoke run's size).
const char *kCases[] = {"examples/hertz/hertz_refined.yaml",
                        "examples/elastic_contact/hertz_two_body.yaml",
                        "examples/hertz/hertz_report.yaml"};

void hertzEndToEnd(benchmark::State &state) {
  const std::string path = std::string(MIXCON_SOURCE_DIR) + "/" + kCases[state.range(0)];
  const auto out = std::filesystem::temp_directory_path() /
                   ("mixcon_bench_hertz_" + std::to_string(state.range(0)));
  RunResult r;
  Problem p;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    p = readProblem(path);
    p.writeHdf5 = false;
    RunOptions o;
    o.outputDirectory = out.string();
    r = runAnalysis(p, o, MPI_COMM_WORLD);
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  if (!r.converged)
    state.SkipWithError("the Hertz run did not converge");
  int corrections = 0;
  for (const auto &s : r.steps)
    corrections += s.iterations;
  std::filesystem::remove_all(out);
  state.counters["unknowns"] = 2.0 * p.mesh.numNodes();
  state.counters["steps"] = static_cast<double>(r.steps.size());
  state.counters["corrections"] = corrections;
  state.counters["closed"] = r.steps.empty() ? 0 : r.steps.back().contactClosed;
}

} // namespace

BENCHMARK(hertzEndToEnd)
    ->Name("hertz/endToEnd")
    ->DenseRange(0, 2)
    ->ArgName("case")
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

int main(int argc, char **argv) { return mixcon::runBenchmarks(argc, argv); }
