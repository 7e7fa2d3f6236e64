// Google Benchmark: node-to-segment search (contact/SegmentSearch.hpp). A closed wavy surface of
// N linear segments and N contactor points scattered within twice the search radius of it (the
// situation of a contact step: every point near the surface); grid build time, grid query
// throughput (queries/s; points numbered along the surface, and in random order) and the
// brute-force search on the same data (up to N = 1e5, one iteration there: its O(N^2) cost),
// in one run so the speed-up is a ratio. Threads: run with
// OMP_NUM_THREADS=1 and 2 (docs/performance.md).
#include <bench/BenchMain.hpp>
#include <contact/SegmentSearch.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

using namespace mixcon;
using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;

namespace search_bench {

struct Data {
  SegmentSet<Memory> set;
  Kokkos::View<double *[2], Memory> queries;
  double radius;
};

/// N segments on the loop r = 1 + 0.2 sin(5 t), N points within 2 radii of it (random, fixed
/// seed); radius = 2 segment lengths. `ordered`: the points numbered along the surface, as the
/// contactor nodes of a mesh boundary are; otherwise in random order (no memory locality).
Data makeData(int n, bool ordered) {
  Kokkos::View<double *[2], Memory> p("points", n), q("queries", n);
  Kokkos::View<int *[3], Memory> nodes("nodes", n);
  auto hp = Kokkos::create_mirror_view(p);
  auto hq = Kokkos::create_mirror_view(q);
  auto hn = Kokkos::create_mirror_view(nodes);
  const double radius = 2 * 2 * M_PI * 1.1 / n;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> along(n);
  for (int i = 0; i < n; ++i)
    along[i] = 2 * M_PI * u(rng);
  if (ordered)
    std::sort(along.begin(), along.end());
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n, r = 1.0 + 0.2 * std::sin(5 * t);
    hp(i, 0) = r * std::cos(t);
    hp(i, 1) = r * std::sin(t);
    hn(i, 0) = i;
    hn(i, 1) = (i + 1) % n;
    hn(i, 2) = -1;
    const double s = along[i], rs = 1.0 + 0.2 * std::sin(5 * s) + 2 * radius * (2 * u(rng) - 1);
    hq(i, 0) = rs * std::cos(s);
    hq(i, 1) = rs * std::sin(s);
  }
  Kokkos::deep_copy(p, hp);
  Kokkos::deep_copy(q, hq);
  Kokkos::deep_copy(nodes, hn);
  return {SegmentSet<Memory>{p, nodes}, q, radius};
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void gridBuild(benchmark::State &state) {
  const Data d = makeData(static_cast<int>(state.range(0)), true);
  SegmentGrid<Exec> grid;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    grid.build(Exec(), d.set, d.radius);
    Exec().fence();
    state.SetIterationTime(seconds(t0));
  }
  state.counters["segments/s"] =
      benchmark::Counter(state.range(0), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["entries/segment"] = static_cast<double>(grid.entries()) / state.range(0);
}

void gridQuery(benchmark::State &state) {
  const Data d = makeData(static_cast<int>(state.range(0)), state.range(1) != 0);
  SegmentGrid<Exec> grid;
  grid.build(Exec(), d.set, d.radius);
  SearchResults<Memory> out(static_cast<LocalIndex>(state.range(0)));
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    grid.query(Exec(), Kokkos::View<const double *[2], Memory>(d.queries), out);
    Exec().fence();
    state.SetIterationTime(seconds(t0));
  }
  state.counters["queries/s"] =
      benchmark::Counter(state.range(0), benchmark::Counter::kIsIterationInvariantRate);
}

void bruteForce(benchmark::State &state) {
  const Data d = makeData(static_cast<int>(state.range(0)), true);
  SearchResults<Memory> out(static_cast<LocalIndex>(state.range(0)));
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    bruteForceSearch(Exec(), d.set, Kokkos::View<const double *[2], Memory>(d.queries), d.radius,
                     out);
    Exec().fence();
    state.SetIterationTime(seconds(t0));
  }
  state.counters["queries/s"] =
      benchmark::Counter(state.range(0), benchmark::Counter::kIsIterationInvariantRate);
}

} // namespace search_bench
using namespace search_bench;

BENCHMARK(gridBuild)
    ->RangeMultiplier(10)
    ->Range(1000, 10000000)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
// Second argument: 1 queries numbered along the surface, 0 in random order.
BENCHMARK(gridQuery)
    ->ArgsProduct({{1000, 10000, 100000, 1000000, 10000000}, {1, 0}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(bruteForce)->Arg(1000)->Arg(10000)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(bruteForce)->Arg(100000)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);

int main(int argc, char **argv) { return runBenchmarks(argc, argv); }
