// Google Benchmark: node-to-segment constraint elimination (solver/MultiPointConstraints.hpp), the
// device path against the host Eigen path it replaced (tests/support/MultiPointReference.hpp,
// with the device -> host copy of A and the copy back of T^T A T the old code made), on a
// contact-sized case: the K^L pattern of a Quad8 block (2 unknowns per node, random symmetric
// diagonally dominant values) with the bottom row of nodes as contactors, each constrained to
// 3 nodes of the top row (slip: framed rows; stick: two slaves per node). Cases: device with the
// symbolic phase (first correction after a status change), device with the symbolic phase reused
// (the constrained pairs unchanged), host Eigen. Each case checks its matrix against the host
// reference before timing (SkipWithError on a mismatch).
#include <bench/BenchMain.hpp>
#include <mesh/Generators.hpp>
#include <support/MultiPointReference.hpp>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <random>

using namespace mixcon;
using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;

namespace multipoint_bench {

/// How a case eliminates: device with its symbolic phase (the first correction after a status
/// change), device reusing the symbolic phase (the constrained pairs unchanged), host Eigen.
enum Path { DeviceSymbolic = 0, DeviceReused = 1, HostEigen = 2 };

/// Largest relative entry difference from the host reference above which a case is not timed.
constexpr double kMismatchTolerance = 1e-13;

struct Case {
  CsrMatrix<Memory> a;
  MultiPointConstraints c;
  std::vector<double> b;
};

Case makeCase(int n, bool stick) {
  const Mesh mesh = rectangleMesh(1.0, 1.0, n, n, ElementType::Quad8);
  Case k;
  k.a = expandGraph<Memory>(buildNodeGraph(mesh), 2);
  const LocalIndex rows = k.a.numRows;
  const auto ro = toHostVector(k.a.rowOffsets);
  const auto co = toHostVector(k.a.columns);
  std::vector<double> va(co.size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (LocalIndex i = 0; i < rows; ++i)
    for (Offset e = ro[i]; e < ro[i + 1]; ++e)
      if (co[e] > i) { // symmetric: set (i, j) and (j, i) together
        const double v = u(rng);
        va[e] = v;
        const LocalIndex j = co[e];
        for (Offset f = ro[j]; f < ro[j + 1]; ++f)
          if (co[f] == i)
            va[f] = v;
      }
  for (LocalIndex i = 0; i < rows; ++i) {
    double s = 1.0;
    for (Offset e = ro[i]; e < ro[i + 1]; ++e)
      s += co[e] != i ? std::abs(va[e]) : 0.0;
    for (Offset e = ro[i]; e < ro[i + 1]; ++e)
      if (co[e] == i)
        va[e] = s;
  }
  copyToDevice(k.a.values, va);
  const auto bottom = mesh.nodesOf("bottom"), top = mesh.nodesOf("top");
  for (std::size_t q = 0; q < bottom.size(); ++q) {
    const LocalIndex i0 = 2 * bottom[q];
    const double angle = 0.3 * u(rng), nn[2] = {std::sin(angle), std::cos(angle)},
                 tt[2] = {-nn[1], nn[0]};
    std::vector<std::pair<LocalIndex, double>> normalRow, tangentRow;
    for (int a = 0; a < 3; ++a)
      for (int d = 0; d < 2; ++d) {
        const LocalIndex j = 2 * top[(q + a) % top.size()] + d;
        normalRow.emplace_back(j, (a == 2 ? 0.5 : 0.25) * nn[d]);
        tangentRow.emplace_back(j, (a == 2 ? 0.5 : 0.25) * tt[d]);
      }
    for (int d = 0; d < 2; ++d) {
      std::vector<std::pair<LocalIndex, double>> row;
      for (const auto &e : normalRow)
        row.emplace_back(e.first, nn[d] * e.second);
      if (stick)
        for (const auto &e : tangentRow)
          row.emplace_back(e.first, tt[d] * e.second);
      else
        row.emplace_back(i0 + 1, tt[d]);
      k.c.addRow(i0 + d, row, 1e-3 * nn[d]);
    }
    k.c.slaves.push_back(i0);
    if (stick)
      k.c.slaves.push_back(i0 + 1);
  }
  k.b.resize(rows);
  for (double &v : k.b)
    v = u(rng);
  return k;
}

test::MpcSparse toEigen(const CsrMatrix<Memory> &a) {
  const auto ro = copyToHost(a.rowOffsets);
  const auto co = copyToHost(a.columns);
  const auto va = copyToHost(a.values);
  std::vector<Eigen::Triplet<double, long>> t;
  t.reserve(co.extent(0));
  for (LocalIndex i = 0; i < a.numRows; ++i)
    for (Offset k = ro(i); k < ro(i + 1); ++k)
      t.emplace_back(i, co(k), va(k));
  test::MpcSparse m(a.numRows, a.numColumns);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

/// The old path: A and b to the host, Eigen products, T^T A T and b back to the device.
CsrMatrix<Memory> hostElimination(const Case &k, const Kokkos::View<double *, Memory> &b) {
  const test::MpcSparse a = toEigen(k.a);
  auto hb = copyToHost(b);
  Eigen::Map<Eigen::VectorXd> bm(hb.data(), k.a.numRows);
  Eigen::VectorXd rhs = bm;
  test::MpcSparse r = test::referenceElimination(a, k.c, 1.0, rhs);
  bm = rhs;
  copyToDevice(b, hb);
  CsrMatrix<Memory> out;
  out.numRows = out.numColumns = k.a.numRows;
  out.rowOffsets = Kokkos::View<Offset *, Memory>("ro", k.a.numRows + 1);
  out.columns = Kokkos::View<LocalIndex *, Memory>("co", r.nonZeros());
  out.values = Kokkos::View<double *, Memory>("va", r.nonZeros());
  copyToDevice(out.rowOffsets,
               std::vector<Offset>(r.outerIndexPtr(), r.outerIndexPtr() + k.a.numRows + 1));
  copyToDevice(out.columns,
               std::vector<LocalIndex>(r.innerIndexPtr(), r.innerIndexPtr() + r.nonZeros()));
  copyToDevice(out.values, std::vector<double>(r.valuePtr(), r.valuePtr() + r.nonZeros()));
  return out;
}

/// Largest entry difference between a device result and the host reference, relative.
double mismatch(const Case &k, const CsrMatrix<Memory> &r) {
  Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(k.b.data(), k.b.size());
  const test::MpcSparse ref = test::referenceElimination(toEigen(k.a), k.c, 1.0, b);
  const test::MpcSparse got = toEigen(r);
  const test::MpcSparse diff = ref - got;
  return diff.coeffs().cwiseAbs().maxCoeff() / ref.coeffs().cwiseAbs().maxCoeff();
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// range(0): elements per side; range(1): 0 slip, 1 stick; range(2): the Path.
void eliminate(benchmark::State &state) {
  const Case k = makeCase(static_cast<int>(state.range(0)), state.range(1) != 0);
  const auto path = static_cast<Path>(state.range(2));
  Kokkos::View<double *, Memory> b("b", k.a.numRows);
  ConstraintElimination elimination;
  {
    copyToDevice(b, k.b);
    const auto r = path == HostEigen
                       ? hostElimination(k, b)
                       : elimination.eliminate(k.a, toDevice(k.c, k.a.numRows), 1.0, b);
    if (mismatch(k, r) > kMismatchTolerance) {
      state.SkipWithError("the eliminated matrix differs from the host reference");
      return;
    }
  }
  for (auto _ : state) {
    copyToDevice(b, k.b);
    Exec().fence();
    const auto t0 = std::chrono::steady_clock::now();
    if (path == HostEigen) {
      benchmark::DoNotOptimize(hostElimination(k, b));
    } else {
      if (path == DeviceSymbolic)
        elimination = ConstraintElimination();
      benchmark::DoNotOptimize(elimination.eliminate(k.a, toDevice(k.c, k.a.numRows), 1.0, b));
    }
    Exec().fence();
    state.SetIterationTime(seconds(t0));
  }
  state.counters["unknowns"] = k.a.numRows;
  state.counters["contact rows"] = static_cast<double>(k.c.rows.size());
  state.counters["nnz/s"] = benchmark::Counter(static_cast<double>(k.a.numNonzeros()),
                                               benchmark::Counter::kIsIterationInvariantRate);
}

} // namespace multipoint_bench
using namespace multipoint_bench;

BENCHMARK(eliminate)
    ->ArgNames({"n", "stick", "path"})
    ->ArgsProduct({{16, 64, 128}, {0, 1}, {DeviceSymbolic, DeviceReused, HostEigen}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

int main(int argc, char **argv) { return mixcon::runBenchmarks(argc, argv); }
