// Google Benchmark: the machine's rooflines for the performance report, measured in the same run
// as the kernels (this shared machine is noisy): STREAM triad bandwidth (GB/s) and the
// floating-point peak this build reaches (GFLOP/s) with independent multiply-add chains, scalar
// (8 chains per work item, the shape of the element kernels' inner loops) and in a loop the
// compiler vectorizes (32 chains). Both are what code compiled with mixcon's flags can reach
// (no -march; see docs/performance.md), not the hardware's AVX2/FMA peak.
#include <bench/BenchMain.hpp>

#include <benchmark/benchmark.h>

#include <chrono>

using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;

namespace machine_bench {

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void streamTriad(benchmark::State &state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0)) * 1000000;
  Kokkos::View<double *, Memory> a("a", n), b("b", n), c("c", n);
  Kokkos::deep_copy(b, 1.0);
  Kokkos::deep_copy(c, 2.0);
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    Kokkos::parallel_for(
        "mixcon::bench::triad", Kokkos::RangePolicy<Exec>(0, n),
        KOKKOS_LAMBDA(std::size_t i) { a(i) = b(i) + 3.0 * c(i); });
    Exec().fence();
    state.SetIterationTime(seconds(t0));
  }
  state.counters["GB/s"] =
      benchmark::Counter(24.0 * n / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

/// Chains of a = a x + y, `Width` independent ones per work item, `iterations` long; 4 work
/// items per thread.
template <int Width> void multiplyAdd(benchmark::State &state) {
  const int items = 4 * Exec().concurrency();
  const int iterations = 1 << 16;
  Kokkos::View<double *, Memory> out("out", items);
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    Kokkos::parallel_for(
        "mixcon::bench::multiplyAdd", Kokkos::RangePolicy<Exec>(0, items), KOKKOS_LAMBDA(int t) {
          double acc[Width];
          for (int j = 0; j < Width; ++j)
            acc[j] = 1e-3 * (t + j);
          const double x = 0.999999, y = 1e-9;
          for (int i = 0; i < iterations; ++i)
            for (int j = 0; j < Width; ++j)
              acc[j] = acc[j] * x + y;
          double s = 0.0;
          for (int j = 0; j < Width; ++j)
            s += acc[j];
          out(t) = s;
        });
    Exec().fence();
    state.SetIterationTime(seconds(t0));
  }
  state.counters["GFLOP/s"] =
      benchmark::Counter(2.0 * Width * iterations * static_cast<double>(items) / 1e9,
                         benchmark::Counter::kIsIterationInvariantRate);
}

} // namespace machine_bench
using namespace machine_bench;

BENCHMARK(streamTriad)
    ->Name("machine/stream-triad")
    ->Arg(32)
    ->ArgName("Mdoubles")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(multiplyAdd<8>)
    ->Name("machine/flops-scalar")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(multiplyAdd<32>)
    ->Name("machine/flops-vector")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

int main(int argc, char **argv) { return mixcon::runBenchmarks(argc, argv); }
