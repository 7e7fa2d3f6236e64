// Google Benchmark: the machine's rooflines for the performance report, measured in the same run
// as the kernels (this shared machine is noisy): STREAM triad bandwidth (GB/s) and the
// floating-point peak this build reaches (GFLOP/s) with independent multiply-add chains, scalar
// (8 chains per work item, the shape of the element kernels' inner loops) and in a loop the
// compiler vectorizes (32 chains). Both are what code compiled with mixcon's flags can reach
// (no -march; see docs/performance.md), not the hardware's AVX2/FMA peak. And the sparse
// product that bounds the 3D cube's PCG (docs/performance.md, issue 17's table 3g): y = K x on
// the 27-point pattern of a grid of nodes with 3 unknowns each, stored as CSR with 32-bit
// columns (hypre's layout, 12 bytes per nonzero), as 3 x 3 blocks (BSR, 8 bytes per nonzero
// and one column per block) and as mixcon's CG multiplies K: the CSR's values read by its node
// blocks (kernels/SparseMatrix.hpp: one column per block, the values in the CSR's order).
#include <bench/BenchMain.hpp>
#include <kernels/SparseMatrix.hpp>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <vector>

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

/// The 27-point, 3-unknowns-per-node pattern of an m^3 grid of nodes, with the entry of row r and
/// column c equal to entry(r, c) in both layouts.
struct GridMatrix {
  int m;
  std::vector<int> blockOffsets, blockColumns; // node graph (BSR)
  static double entry(long r, long c) { return r == c ? 30.0 : -0.1 - 0.01 * ((r + 2 * c) % 7); }

  explicit GridMatrix(int nodesPerSide) : m(nodesPerSide) {
    blockOffsets.push_back(0);
    for (int z = 0; z < m; ++z)
      for (int y = 0; y < m; ++y)
        for (int x = 0; x < m; ++x) {
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int X = x + dx, Y = y + dy, Z = z + dz;
                if (X >= 0 && Y >= 0 && Z >= 0 && X < m && Y < m && Z < m)
                  blockColumns.push_back((Z * m + Y) * m + X);
              }
          blockOffsets.push_back(static_cast<int>(blockColumns.size()));
        }
  }
  long numNodes() const { return long(m) * m * m; }
  long numBlocks() const { return static_cast<long>(blockColumns.size()); }
};

/// y = K x on the grid's matrix; state.range(0): nodes per side, range(1): 0 CSR, 1 BSR, 2 the
/// CSR's values by mixcon's node blocks (kernels/SparseMatrix.hpp, the CG's product with K).
void sparseProduct(benchmark::State &state) {
  const GridMatrix g(static_cast<int>(state.range(0)));
  const bool blocks = state.range(1) == 1;
  const bool nodeBlocked = state.range(1) == 2;
  const long nodes = g.numNodes(), rows = 3 * nodes, nnz = 9 * g.numBlocks();
  Kokkos::View<int *, Memory> offsets("offsets", blocks ? nodes + 1 : rows + 1),
      columns("columns", blocks ? g.numBlocks() : nnz);
  Kokkos::View<double *, Memory> values("values", nnz), x("x", rows), y("y", rows);
  {
    auto ho = Kokkos::create_mirror_view(offsets);
    auto hc = Kokkos::create_mirror_view(columns);
    auto hv = Kokkos::create_mirror_view(values);
    long k = 0;
    for (long node = 0; node < nodes; ++node) {
      if (blocks) {
        ho(node) = g.blockOffsets[node];
        for (int b = g.blockOffsets[node]; b < g.blockOffsets[node + 1]; ++b) {
          hc(b) = g.blockColumns[b];
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
              hv(9L * b + 3 * r + c) = GridMatrix::entry(3 * node + r, 3L * g.blockColumns[b] + c);
        }
      } else {
        for (int r = 0; r < 3; ++r) {
          ho(3 * node + r) = static_cast<int>(k);
          for (int b = g.blockOffsets[node]; b < g.blockOffsets[node + 1]; ++b)
            for (int c = 0; c < 3; ++c) {
              hc(k) = 3 * g.blockColumns[b] + c;
              hv(k++) = GridMatrix::entry(3 * node + r, 3L * g.blockColumns[b] + c);
            }
        }
      }
    }
    ho(blocks ? nodes : rows) = blocks ? static_cast<int>(g.numBlocks()) : static_cast<int>(k);
    Kokkos::deep_copy(offsets, ho);
    Kokkos::deep_copy(columns, hc);
    Kokkos::deep_copy(values, hv);
  }
  mixcon::NodeBlocks<Memory> nb;
  if (nodeBlocked) { // mixcon's CSR of the same matrix (64-bit offsets), then its node blocks
    mixcon::CsrMatrix<Memory> csr;
    csr.numRows = csr.numColumns = static_cast<mixcon::LocalIndex>(rows);
    csr.rowOffsets = Kokkos::View<mixcon::Offset *, Memory>("rowOffsets", rows + 1);
    const auto ro = csr.rowOffsets;
    Kokkos::parallel_for(
        "mixcon::bench::rowOffsets", Kokkos::RangePolicy<Exec>(0, rows + 1),
        KOKKOS_LAMBDA(long r) { ro(r) = offsets(r); });
    csr.columns = columns;
    csr.values = values;
    nb = mixcon::nodeBlocks(Exec(), csr, 3);
    if (nb.d != 3) {
      state.SkipWithError("the grid's CSR has no 3 x 3 node blocks");
      return;
    }
  }
  const auto product = [&] {
    if (nodeBlocked)
      mixcon::multiply(Exec(), nb, Kokkos::View<const double *, Memory>(values),
                       Kokkos::View<const double *, Memory>(x), y);
    else if (blocks)
      Kokkos::parallel_for(
          "mixcon::bench::bsrProduct", Kokkos::RangePolicy<Exec>(0, nodes), KOKKOS_LAMBDA(long n) {
            double s0 = 0.0, s1 = 0.0, s2 = 0.0;
            for (int b = offsets(n); b < offsets(n + 1); ++b) {
              const long c = 3L * columns(b), v = 9L * b;
              const double x0 = x(c), x1 = x(c + 1), x2 = x(c + 2);
              s0 += values(v) * x0 + values(v + 1) * x1 + values(v + 2) * x2;
              s1 += values(v + 3) * x0 + values(v + 4) * x1 + values(v + 5) * x2;
              s2 += values(v + 6) * x0 + values(v + 7) * x1 + values(v + 8) * x2;
            }
            y(3 * n) = s0;
            y(3 * n + 1) = s1;
            y(3 * n + 2) = s2;
          });
    else
      Kokkos::parallel_for(
          "mixcon::bench::csrProduct", Kokkos::RangePolicy<Exec>(0, rows), KOKKOS_LAMBDA(long r) {
            double s = 0.0;
            for (int k = offsets(r); k < offsets(r + 1); ++k)
              s += values(k) * x(columns(k));
            y(r) = s;
          });
  };
  // Check before timing: for x_c = 1 + c mod 5, y against a plain host loop over the pattern.
  Kokkos::parallel_for(
      "mixcon::bench::productInput", Kokkos::RangePolicy<Exec>(0, rows),
      KOKKOS_LAMBDA(long c) { x(c) = 1.0 + static_cast<double>(c % 5); });
  product();
  Exec().fence();
  auto hy = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), y);
  for (long node = 0; node < nodes; ++node)
    for (int r = 0; r < 3; ++r) {
      double ref = 0.0;
      for (int b = g.blockOffsets[node]; b < g.blockOffsets[node + 1]; ++b)
        for (int c = 0; c < 3; ++c) {
          const long col = 3L * g.blockColumns[b] + c;
          ref += GridMatrix::entry(3 * node + r, col) * (1.0 + static_cast<double>(col % 5));
        }
      if (std::fabs(hy(3 * node + r) - ref) > 1e-12 * std::fabs(ref) + 1e-12) {
        state.SkipWithError("the product differs from the host reference");
        return;
      }
    }
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    product();
    Exec().fence();
    state.SetIterationTime(seconds(t0));
  }
  // Bytes: values, columns, offsets, x once and y written.
  const double bytes =
      nodeBlocked
          ? 8.0 * nnz + 4.0 * nb.columns.extent(0) + 8.0 * nb.offsets.extent(0) + 16.0 * rows
          : 8.0 * nnz + 4.0 * columns.extent(0) + 4.0 * offsets.extent(0) + 16.0 * rows;
  state.counters["GB/s"] =
      benchmark::Counter(bytes / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["Gnnz/s"] =
      benchmark::Counter(nnz / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bytes/nnz"] = bytes / nnz;
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

BENCHMARK(sparseProduct)
    ->Name("machine/sparse-product")
    ->ArgsProduct({{16, 64}, {0, 1, 2}})
    ->ArgNames({"nodesPerSide", "format"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

int main(int argc, char **argv) { return mixcon::runBenchmarks(argc, argv); }
