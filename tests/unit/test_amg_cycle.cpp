// mixcon's V-cycle on BoomerAMG's hierarchy (solver/AmgCycle.hpp, `amg_cycle`): against a plain
// host V-cycle written as hypre_BoomerAMGCycle does it (relax type 16, scaled Chebyshev) on a
// hand-made hierarchy, against hypre's own V-cycle on the hierarchy hypre built, in single
// precision, after a kept hierarchy's new values, and inside the solver's CG.
#include <core/Transfer.hpp>
#include <kernels/SparseMatrix.hpp>
#include <solver/AmgCycle.hpp>
#include <solver/DofMap.hpp>
#include <solver/Krylov.hpp>

#include <support/Differences.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace mixcon;
using mixcon::test::relativeDifference2;

namespace {
using Memory = Kokkos::DefaultExecutionSpace::memory_space;
using Exec = Kokkos::DefaultExecutionSpace;

/// A CSR matrix on the host, owned (the test's hierarchy and its reference V-cycle).
struct HostMatrix {
  int rows = 0, cols = 0;
  std::vector<int> ro{0}, co;
  std::vector<double> va;
  AmgHostCsr view() const { return {ro.data(), co.data(), va.data(), rows, cols}; }
  std::vector<double> times(const std::vector<double> &x) const {
    std::vector<double> y(rows, 0.0);
    for (int i = 0; i < rows; ++i)
      for (int k = ro[i]; k < ro[i + 1]; ++k)
        y[i] += va[k] * x[co[k]];
    return y;
  }
  std::vector<double> transposeTimes(const std::vector<double> &x) const {
    std::vector<double> y(cols, 0.0);
    for (int i = 0; i < rows; ++i)
      for (int k = ro[i]; k < ro[i + 1]; ++k)
        y[co[k]] += va[k] * x[i];
    return y;
  }
};

HostMatrix fromDense(const std::vector<std::vector<double>> &a) {
  HostMatrix m;
  m.rows = static_cast<int>(a.size());
  m.cols = static_cast<int>(a[0].size());
  for (const auto &row : a) {
    for (int j = 0; j < m.cols; ++j)
      if (row[j] != 0.0) {
        m.co.push_back(j);
        m.va.push_back(row[j]);
      }
    m.ro.push_back(static_cast<int>(m.co.size()));
  }
  return m;
}

std::vector<std::vector<double>> dense(const HostMatrix &m) {
  std::vector<std::vector<double>> a(m.rows, std::vector<double>(m.cols, 0.0));
  for (int i = 0; i < m.rows; ++i)
    for (int k = m.ro[i]; k < m.ro[i + 1]; ++k)
      a[i][m.co[k]] += m.va[k];
  return a;
}

/// P^T A P, dense products (small levels).
HostMatrix galerkin(const HostMatrix &a, const HostMatrix &p) {
  const auto ad = dense(a), pd = dense(p);
  std::vector<std::vector<double>> c(p.cols, std::vector<double>(p.cols, 0.0));
  for (int i = 0; i < p.cols; ++i)
    for (int j = 0; j < p.cols; ++j)
      for (int r = 0; r < a.rows; ++r)
        for (int s = 0; s < a.rows; ++s)
          c[i][j] += pd[r][i] * ad[r][s] * pd[s][j];
  return fromDense(c);
}

/// d interleaved components per node on a line of n nodes: the 1D Laplacian (2, -1) plus a
/// shift, times the d x d coupling b (a Kronecker product of SPD matrices: SPD).
HostMatrix chain(int n, int d, const std::vector<std::vector<double>> &b) {
  std::vector<std::vector<double>> a(n * d, std::vector<double>(n * d, 0.0));
  for (int p = 0; p < n; ++p)
    for (int q = std::max(0, p - 1); q <= std::min(n - 1, p + 1); ++q)
      for (int i = 0; i < d; ++i)
        for (int j = 0; j < d; ++j)
          a[p * d + i][q * d + j] = (p == q ? 2.1 : -1.0) * b[i][j];
  return fromDense(a);
}

/// Linear interpolation from every other node (n = 2 m + 1 fine nodes, m coarse), per component.
HostMatrix interpolation(int m, int d) {
  const int n = 2 * m + 1;
  std::vector<std::vector<double>> p(n * d, std::vector<double>(m * d, 0.0));
  for (int c = 0; c < m; ++c)
    for (int i = 0; i < d; ++i) {
      const int f = 2 * c + 1;
      p[f * d + i][c * d + i] = 1.0;
      p[(f - 1) * d + i][c * d + i] = 0.5;
      p[(f + 1) * d + i][c * d + i] = 0.5;
    }
  return fromDense(p);
}

/// The entries (i, j) with i % d == j % d.
HostMatrix sameComponent(const HostMatrix &a, int d) {
  HostMatrix m;
  m.rows = a.rows;
  m.cols = a.cols;
  for (int i = 0; i < a.rows; ++i) {
    for (int k = a.ro[i]; k < a.ro[i + 1]; ++k)
      if (a.co[k] % d == i % d) {
        m.co.push_back(a.co[k]);
        m.va.push_back(a.va[k]);
      }
    m.ro.push_back(static_cast<int>(m.co.size()));
  }
  return m;
}

std::vector<double> solveDense(std::vector<std::vector<double>> a, std::vector<double> b) {
  const int n = static_cast<int>(b.size());
  for (int k = 0; k < n; ++k) {
    int piv = k;
    for (int i = k + 1; i < n; ++i)
      if (std::abs(a[i][k]) > std::abs(a[piv][k]))
        piv = i;
    std::swap(a[k], a[piv]);
    std::swap(b[k], b[piv]);
    for (int i = k + 1; i < n; ++i) {
      const double l = a[i][k] / a[k][k];
      for (int j = k; j < n; ++j)
        a[i][j] -= l * a[k][j];
      b[i] -= l * b[k];
    }
  }
  std::vector<double> x(n);
  for (int i = n - 1; i >= 0; --i) {
    double s = b[i];
    for (int j = i + 1; j < n; ++j)
      s -= a[i][j] * x[j];
    x[i] = s / a[i][i];
  }
  return x;
}

/// One level of the reference hierarchy.
struct RefLevel {
  HostMatrix a, p;
  std::vector<double> ds, coefficients;
};

/// hypre_ParCSRRelax_Cheby_Solve, scaled, variant 0, as written there (hypre 2.26, par_cheby.c):
/// the residual product with u even where u = 0.
void chebyshev(const RefLevel &l, const std::vector<double> &f, std::vector<double> &u) {
  const int n = l.a.rows, order = static_cast<int>(l.coefficients.size());
  const std::vector<double> au = l.a.times(u);
  std::vector<double> r(n), v(n), tmp(n), orig = u;
  for (int j = 0; j < n; ++j)
    r[j] = l.ds[j] * (f[j] - au[j]);
  for (int j = 0; j < n; ++j)
    u[j] = r[j] * l.coefficients[order - 1];
  for (int i = order - 2; i >= 0; --i) {
    for (int j = 0; j < n; ++j)
      tmp[j] = l.ds[j] * u[j];
    v = l.a.times(tmp);
    for (int j = 0; j < n; ++j)
      u[j] = l.coefficients[i] * r[j] + l.ds[j] * v[j];
  }
  for (int j = 0; j < n; ++j)
    u[j] = orig[j] + l.ds[j] * u[j];
}

/// hypre_BoomerAMGCycle's V-cycle from u = 0 on every level; the coarsest solved exactly, or
/// (smoothedCoarsest: hypre's coarsest solve where its coarsening stopped early, relax type 16
/// there) by one Chebyshev sweep from zero.
std::vector<double> referenceCycle(const std::vector<RefLevel> &levels, std::size_t l,
                                   const std::vector<double> &f, bool smoothedCoarsest = false) {
  const RefLevel &v = levels[l];
  std::vector<double> u(f.size(), 0.0);
  if (l + 1 == levels.size()) {
    if (!smoothedCoarsest)
      return solveDense(dense(v.a), f);
    chebyshev(v, f, u);
    return u;
  }
  chebyshev(v, f, u);
  const std::vector<double> au = v.a.times(u);
  std::vector<double> g(f.size());
  for (std::size_t i = 0; i < f.size(); ++i)
    g[i] = f[i] - au[i];
  const std::vector<double> uc =
      referenceCycle(levels, l + 1, v.p.transposeTimes(g), smoothedCoarsest);
  const std::vector<double> pu = v.p.times(uc);
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] += pu[i];
  chebyshev(v, f, u);
  return u;
}

/// A 4-level hierarchy (63 -> 31 -> 15 -> 7 nodes, d components) on the matrix a, with the
/// Chebyshev coefficients of the given order (any values: the test compares operations).
std::vector<RefLevel> hierarchy(const HostMatrix &a, int d, int order) {
  std::vector<RefLevel> levels;
  HostMatrix current = a;
  for (int m : {31, 15, 7, 0}) {
    RefLevel l;
    l.a = current;
    for (int i = 0; i < current.rows; ++i)
      for (int k = current.ro[i]; k < current.ro[i + 1]; ++k)
        if (current.co[k] == i)
          l.ds.push_back(1.0 / std::sqrt(std::abs(current.va[k])));
    for (int c = 0; c < order; ++c)
      l.coefficients.push_back(0.9 - 0.45 * c + 0.1 * c * c);
    if (m > 0) {
      l.p = interpolation(m, d);
      current = galerkin(current, l.p);
    }
    levels.push_back(l);
  }
  return levels;
}

CsrMatrix<Memory> toDevice(const HostMatrix &a) {
  CsrMatrix<Memory> m;
  m.numRows = a.rows;
  m.numColumns = a.cols;
  m.rowOffsets = Kokkos::View<Offset *, Memory>("ro", a.rows + 1);
  m.columns = Kokkos::View<LocalIndex *, Memory>("co", a.co.size());
  m.values = Kokkos::View<double *, Memory>("va", a.va.size());
  auto hr = Kokkos::create_mirror_view(m.rowOffsets);
  auto hc = Kokkos::create_mirror_view(m.columns);
  auto hv = Kokkos::create_mirror_view(m.values);
  for (int i = 0; i <= a.rows; ++i)
    hr(i) = a.ro[i];
  for (std::size_t k = 0; k < a.co.size(); ++k) {
    hc(k) = a.co[k];
    hv(k) = a.va[k];
  }
  Kokkos::deep_copy(m.rowOffsets, hr);
  Kokkos::deep_copy(m.columns, hc);
  Kokkos::deep_copy(m.values, hv);
  return m;
}

std::vector<double> testVector(int n) {
  std::vector<double> b(n);
  for (int i = 0; i < n; ++i)
    b[i] = 1.0 + 0.5 * ((7 * i) % 5) - (i % 3 == 1 ? 2.0 : 0.0);
  return b;
}

std::vector<double> applyCycle(AmgCycle &cycle, const std::vector<double> &b) {
  Kokkos::View<double *, Memory> db("b", b.size()), dx("x", b.size());
  auto hb = Kokkos::create_mirror_view(db);
  for (std::size_t i = 0; i < b.size(); ++i)
    hb(i) = b[i];
  Kokkos::deep_copy(db, hb);
  cycle.apply(db, dx);
  auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dx);
  return std::vector<double>(hx.data(), hx.data() + hx.size());
}

/// n^3 nodes of a unit grid with 3 interleaved components: the 27-point stencil (26.5 on the
/// diagonal, -1 to each neighbour: diagonally dominant) times a 3 x 3 SPD coupling; the node
/// positions for the rigid-body modes.
CsrMatrix<Memory> grid3d(int n, double scale, Kokkos::View<double **, Memory> &positions) {
  const double b[3][3] = {{2.0, 0.5, 0.3}, {0.5, 1.5, 0.4}, {0.3, 0.4, 1.0}};
  HostMatrix m;
  m.rows = m.cols = 3 * n * n * n;
  const auto node = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
          for (int kk = std::max(0, k - 1); kk <= std::min(n - 1, k + 1); ++kk)
            for (int jj = std::max(0, j - 1); jj <= std::min(n - 1, j + 1); ++jj)
              for (int ii = std::max(0, i - 1); ii <= std::min(n - 1, i + 1); ++ii) {
                const bool self = ii == i && jj == j && kk == k;
                // a mild variation along x: the levels differ from a constant stencil
                const double w = (self ? 26.5 : -1.0) * scale * (1.0 + 0.3 * (i + ii) / n);
                for (int e = 0; e < 3; ++e) {
                  m.co.push_back(3 * node(ii, jj, kk) + e);
                  m.va.push_back(w * b[c][e]);
                }
              }
          m.ro.push_back(static_cast<int>(m.co.size()));
        }
  positions = Kokkos::View<double **, Memory>("positions", n * n * n, 3);
  auto hp = Kokkos::create_mirror_view(positions);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        hp(node(i, j, k), 0) = i;
        hp(node(i, j, k), 1) = j;
        hp(node(i, j, k), 2) = k;
      }
  Kokkos::deep_copy(positions, hp);
  return toDevice(m);
}

std::vector<double> preconditioned(LinearSolver &s, const std::vector<double> &b) {
  Kokkos::View<double *, Memory> db("b", b.size()), dx("x", b.size());
  auto hb = Kokkos::create_mirror_view(db);
  for (std::size_t i = 0; i < b.size(); ++i)
    hb(i) = b[i];
  Kokkos::deep_copy(db, hb);
  s.precondition(db, dx);
  auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dx);
  return std::vector<double>(hx.data(), hx.data() + hx.size());
}

std::vector<double> solved(LinearSolver &s, const std::vector<double> &b, LinearSolveStats &st) {
  Kokkos::View<double *, Memory> db("b", b.size()), dx("x", b.size());
  auto hb = Kokkos::create_mirror_view(db);
  for (std::size_t i = 0; i < b.size(); ++i)
    hb(i) = b[i];
  Kokkos::deep_copy(db, hb);
  st = s.solve(db, dx);
  auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dx);
  return std::vector<double>(hx.data(), hx.data() + hx.size());
}

LinearSolverOptions chebyshevAmg(AmgCycleKind cycle, bool separate, int order = 2) {
  LinearSolverOptions o;
  o.smoother = AmgSmoother::Chebyshev;
  o.chebyshevOrder = order;
  o.separateComponents = separate;
  o.rigidBodyModes = !separate;
  o.aggressiveLevels = 1; // the 3D defaults: aggressive coarsening, truncated interpolation
  o.interpolationMaxElements = 4;
  o.coarseSpace = CoarseSpace::None;
  o.escalationCoarsestSizes.clear();
  o.directFallbackUnknowns = 0;
  o.cycle = cycle;
  return o;
}

/// The hierarchy as LinearSolver hands it over: the coarsest level's smoother only where it is
/// smoothed (smoothedCoarsest), else solved exactly.
std::vector<HostAmgLevel> describe(const std::vector<RefLevel> &levels,
                                   bool smoothedCoarsest = false) {
  std::vector<HostAmgLevel> h(levels.size());
  for (std::size_t l = 0; l < levels.size(); ++l) {
    h[l].a = levels[l].a.view();
    if (l + 1 < levels.size())
      h[l].p = levels[l].p.view();
    if (l + 1 < levels.size() || smoothedCoarsest) {
      h[l].ds = levels[l].ds.data();
      h[l].coefficients = levels[l].coefficients;
    }
  }
  return h;
}
} // namespace

// The kernels against the host V-cycle, for Chebyshev orders 1 to 4 (order 1 ends without a
// product, order 2 is the default, 3 and 4 take the alternating work vectors), on one component
// and on two with the fine level filtered to equal components (amg_matrix:
// separate_components): double to round-off, single to its precision (and not to double's).
// It fails for a wrong coefficient order, a skipped or doubled smoothing step, a restriction by
// P instead of P^T, a wrong filter, or single precision that is not single.
TEST(AmgCycle, MatchesTheHostVcycleForEachChebyshevOrder) {
  const std::vector<std::vector<double>> one = {{1.0}};
  const std::vector<std::vector<double>> two = {{2.0, 0.6}, {0.6, 1.0}};
  for (int d : {1, 2}) {
    const HostMatrix a = chain(63, d, d == 1 ? one : two);
    const HostMatrix filtered = d == 1 ? a : sameComponent(a, d);
    ASSERT_EQ(a.rows, 63 * d);
    for (int order = 1; order <= 4; ++order) {
      const std::vector<RefLevel> levels = hierarchy(filtered, d, order);
      const std::vector<double> b = testVector(a.rows);
      const std::vector<double> ref = referenceCycle(levels, 0, b);
      const CsrMatrix<Memory> fine = toDevice(a);
      AmgCycle dp(fine, d == 1 ? 0 : d, describe(levels), AmgCyclePrecision::Double);
      AmgCycle sp(fine, d == 1 ? 0 : d, describe(levels), AmgCyclePrecision::Single);
      EXPECT_EQ(dp.levels(), 4);
      const double ed = relativeDifference2(applyCycle(dp, b), ref);
      const double es = relativeDifference2(applyCycle(sp, b), ref);
      EXPECT_LT(ed, 1e-13) << "d " << d << " order " << order;
      EXPECT_LT(es, 1e-5) << "d " << d << " order " << order;
      EXPECT_GT(es, 1e-10) << "d " << d << " order " << order; // single is single
    }
  }
}

// A kept hierarchy: new fine values (the same pattern) change the cycle as they change the host
// V-cycle whose coarse levels and coefficients stay.
TEST(AmgCycle, NewFineValuesKeepTheCoarseLevels) {
  const std::vector<std::vector<double>> two = {{2.0, 0.6}, {0.6, 1.0}};
  const HostMatrix a = chain(63, 2, two);
  std::vector<RefLevel> levels = hierarchy(sameComponent(a, 2), 2, 2);
  AmgCycle cycle(toDevice(a), 2, describe(levels), AmgCyclePrecision::Double);
  HostMatrix stiffer = a;
  for (double &v : stiffer.va)
    v *= 3.0;
  cycle.setFineMatrix(toDevice(stiffer));
  levels[0].a = sameComponent(stiffer, 2); // ds, the coefficients and the coarse levels stay
  const std::vector<double> b = testVector(a.rows);
  EXPECT_LT(relativeDifference2(applyCycle(cycle, b), referenceCycle(levels, 0, b)), 1e-13);
}

// Wide interpolation (aggressive coarsening's long rows of P^T): 63 fine nodes from 3 coarse
// ones with hat functions 30 nodes wide, so that each row of P^T holds about 60 entries and takes
// the general sort of the transpose; the cycle stays the host's.
TEST(AmgCycle, LongRowsOfTheTransposeKeepTheHostVcycle) {
  const HostMatrix a = chain(63, 1, {{1.0}});
  std::vector<std::vector<double>> wide(63, std::vector<double>(3, 0.0));
  for (int f = 0; f < 63; ++f)
    for (int c = 0; c < 3; ++c)
      wide[f][c] = std::max(0.0, 1.0 - std::abs(f - (16.0 + 15.0 * c)) / 30.0);
  std::vector<RefLevel> levels(2);
  levels[0].a = a;
  levels[0].p = fromDense(wide);
  levels[0].coefficients = {0.9, 0.55};
  for (int i = 0; i < a.rows; ++i)
    levels[0].ds.push_back(1.0 / std::sqrt(2.1));
  levels[1].a = galerkin(a, levels[0].p);
  int longest = 0;
  for (int c = 0; c < 3; ++c) {
    int count = 0;
    for (int f = 0; f < 63; ++f)
      count += wide[f][c] != 0.0;
    longest = std::max(longest, count);
  }
  ASSERT_GT(longest, 32);
  const std::vector<double> b = testVector(a.rows);
  AmgCycle cycle(toDevice(a), 0, describe(levels), AmgCyclePrecision::Double);
  EXPECT_LT(relativeDifference2(applyCycle(cycle, b), referenceCycle(levels, 0, b)), 1e-13);
}

// The fine level read by node blocks (nodeBlocks of the fine matrix, as the solver gives them):
// the same cycle as the host's in double and single precision and after a kept hierarchy's new
// values, unfiltered (whole blocks) and with the separate components' filter (on the host the
// blocks' diagonals side by side; elsewhere the filtered CSR). Every entry differs from its
// neighbours (a position-dependent factor on the chain), so that an entry read from the wrong
// block, row or component changes the cycle.
TEST(AmgCycle, NodeBlocksOfTheFineLevelKeepTheHostVcycle) {
  const std::vector<std::vector<double>> two = {{2.0, 0.6}, {0.6, 1.0}};
  HostMatrix a = chain(63, 2, two);
  for (int i = 0; i < a.rows; ++i)
    for (int k = a.ro[i]; k < a.ro[i + 1]; ++k)
      a.va[k] *= 1.0 + 0.01 * ((7 * i + 3 * a.co[k]) % 11);
  const CsrMatrix<Memory> fine = toDevice(a);
  const NodeBlocks<Memory> blocks = nodeBlocks(Exec(), fine, 2);
  ASSERT_EQ(blocks.d, 2);
  const std::vector<double> b = testVector(a.rows);
  for (int filter : {0, 2}) {
    std::vector<RefLevel> levels = hierarchy(filter > 0 ? sameComponent(a, 2) : a, 2, 2);
    const std::vector<double> ref = referenceCycle(levels, 0, b);
    AmgCycle dp(fine, filter, describe(levels), AmgCyclePrecision::Double, blocks);
    AmgCycle sp(fine, filter, describe(levels), AmgCyclePrecision::Single, blocks);
    const bool byBlocks = filter == 0 || kHostAccessible<DeviceSpace>;
    EXPECT_EQ(dp.fineLevelByNodeBlocks(), byBlocks) << filter;
    EXPECT_EQ(sp.fineLevelByNodeBlocks(), byBlocks) << filter;
    EXPECT_LT(relativeDifference2(applyCycle(dp, b), ref), 1e-13) << filter;
    const double es = relativeDifference2(applyCycle(sp, b), ref);
    EXPECT_LT(es, 1e-5) << filter;
    EXPECT_GT(es, 1e-10) << filter;
    HostMatrix stiffer = a;
    for (double &v : stiffer.va)
      v *= 3.0;
    dp.setFineMatrix(toDevice(stiffer));
    levels[0].a = filter > 0 ? sameComponent(stiffer, 2) : stiffer;
    EXPECT_LT(relativeDifference2(applyCycle(dp, b), referenceCycle(levels, 0, b)), 1e-13)
        << filter;
  }
}

// A coarsest level that comes with its smoother (hypre's coarsest solve where its coarsening
// stopped early: relax type 16 there, as the cube's N = 100 on 16 threads showed) is smoothed
// once from zero, as the host V-cycle does it, on one component and on two filtered ones, in
// double and single precision, for orders 1 and 3; it is not the exact coarsest solve.
TEST(AmgCycle, ASmoothedCoarsestLevelIsOneChebyshevSweepFromZero) {
  const std::vector<std::vector<double>> one = {{1.0}};
  const std::vector<std::vector<double>> two = {{2.0, 0.6}, {0.6, 1.0}};
  for (int d : {1, 2}) {
    const HostMatrix a = chain(63, d, d == 1 ? one : two);
    for (int order : {1, 3}) {
      const std::vector<RefLevel> levels = hierarchy(d == 1 ? a : sameComponent(a, d), d, order);
      const std::vector<double> b = testVector(a.rows);
      const std::vector<double> ref = referenceCycle(levels, 0, b, true);
      const CsrMatrix<Memory> fine = toDevice(a);
      AmgCycle dp(fine, d == 1 ? 0 : d, describe(levels, true), AmgCyclePrecision::Double);
      AmgCycle sp(fine, d == 1 ? 0 : d, describe(levels, true), AmgCyclePrecision::Single);
      const std::vector<double> x = applyCycle(dp, b);
      EXPECT_LT(relativeDifference2(x, ref), 1e-13) << "d " << d << " order " << order;
      EXPECT_LT(relativeDifference2(applyCycle(sp, b), ref), 1e-5) << "d " << d;
      EXPECT_GT(relativeDifference2(x, referenceCycle(levels, 0, b)), 1e-6)
          << "d " << d << " order " << order << ": the coarsest level was solved exactly";
    }
  }
}

// A singular coarsest level is refused with its size named.
TEST(AmgCycle, RefusesASingularCoarsestLevel) {
  const HostMatrix a = chain(63, 1, {{1.0}});
  std::vector<RefLevel> levels = hierarchy(a, 1, 2);
  HostMatrix &coarsest = levels.back().a;
  for (int k = coarsest.ro[2]; k < coarsest.ro[3]; ++k)
    coarsest.va[k] = 0.0; // a zero row
  try {
    AmgCycle cycle(toDevice(a), 0, describe(levels), AmgCyclePrecision::Double);
    FAIL() << "a singular coarsest level was accepted";
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("7 unknowns"), std::string::npos) << e.what();
  }
}

// On the hierarchy hypre builds (3D, three components; the full matrix with the rigid-body
// modes as interpolation vectors, and the separate components): the double-precision copy's
// V-cycle is hypre's BoomerAMGSolve V-cycle to round-off, after a fresh setup and after a setup
// that keeps the hierarchy with new values; single precision is within its precision of it. For
// the Chebyshev orders 2 (hypre's default) and 1 (the 3D default).
// It fails where a level, an interpolation, a Chebyshev scaling or coefficient is read wrong,
// where the kept hierarchy's fine level is not updated, or where the copy is not taken.
TEST(AmgCycle, IsHypresVcycleOnTheHierarchyHypreBuilt) {
  for (const auto &[separate, order] :
       {std::pair(false, 2), std::pair(true, 2), std::pair(false, 1), std::pair(true, 1)}) {
    Kokkos::View<double **, Memory> positions;
    const CsrMatrix<Memory> a = grid3d(9, 1.0, positions);
    const DofMap dofs = DofMap::serial(9 * 9 * 9, 3);
    auto hypre =
        makeLinearSolver(chebyshevAmg(AmgCycleKind::Hypre, separate, order), dofs, MPI_COMM_WORLD);
    auto dp = makeLinearSolver(chebyshevAmg(AmgCycleKind::MixconDouble, separate, order), dofs,
                               MPI_COMM_WORLD);
    auto sp = makeLinearSolver(chebyshevAmg(AmgCycleKind::MixconSingle, separate, order), dofs,
                               MPI_COMM_WORLD);
    for (auto *s : {hypre.get(), dp.get(), sp.get()})
      s->setNearNullSpace(positions);
    const std::vector<double> b = testVector(a.numRows);
    for (double scale : {1.0, 2.5}) { // the second setup keeps the hierarchies
      Kokkos::View<double **, Memory> unused;
      const CsrMatrix<Memory> m = scale == 1.0 ? a : grid3d(9, scale, unused);
      for (auto *s : {hypre.get(), dp.get(), sp.get()})
        s->setup(m);
      const std::vector<double> ref = preconditioned(*hypre, b);
      EXPECT_LT(relativeDifference2(preconditioned(*dp, b), ref), 1e-12)
          << "separate " << separate << " order " << order << " scale " << scale;
      const double es = relativeDifference2(preconditioned(*sp, b), ref);
      EXPECT_LT(es, 1e-5) << "separate " << separate << " order " << order << " scale " << scale;
      EXPECT_GT(es, 1e-10) << "separate " << separate << " order " << order << " scale " << scale;
    }
    // after the setups: the copies were taken (not hypre's cycle under another name)
    EXPECT_EQ(hypre->name().find("by mixcon"), std::string::npos) << hypre->name();
    EXPECT_NE(dp->name().find("V-cycle by mixcon in double precision"), std::string::npos)
        << dp->name();
    EXPECT_NE(sp->name().find("V-cycle by mixcon in single precision"), std::string::npos)
        << sp->name();
    EXPECT_EQ(dp->builds(), 1);
    EXPECT_EQ(dp->reuses(), 1);
  }
}

// Inside the solver: mixcon's CG around the single-precision cycle reaches hypre PCG's solution
// with about its iterations, on the full matrix and on the separate components.
TEST(AmgCycle, SinglePrecisionCycleSolvesAsHypresPcg) {
  for (bool separate : {false, true}) {
    Kokkos::View<double **, Memory> positions;
    const CsrMatrix<Memory> a = grid3d(10, 1.0, positions);
    const DofMap dofs = DofMap::serial(1000, 3);
    auto hypre =
        makeLinearSolver(chebyshevAmg(AmgCycleKind::Hypre, separate), dofs, MPI_COMM_WORLD);
    auto sp =
        makeLinearSolver(chebyshevAmg(AmgCycleKind::MixconSingle, separate), dofs, MPI_COMM_WORLD);
    const std::vector<double> b = testVector(a.numRows);
    LinearSolveStats sh, ss;
    for (auto *s : {hypre.get(), sp.get()}) {
      s->setNearNullSpace(positions);
      s->setup(a);
    }
    const std::vector<double> xh = solved(*hypre, b, sh), xs = solved(*sp, b, ss);
    ASSERT_TRUE(sh.converged);
    ASSERT_TRUE(ss.converged) << ss.relativeResidual;
    EXPECT_LE(ss.relativeResidual, 1e-8);
    EXPECT_LT(relativeDifference2(xs, xh), 1e-6) << separate;
    EXPECT_GT(ss.iterations, 1);
    EXPECT_LE(std::abs(ss.iterations - sh.iterations), 2)
        << "separate " << separate << ": " << ss.iterations << " against " << sh.iterations;
  }
}

// The default (auto) takes the single-precision copy with the Chebyshev smoother, and around it
// mixcon's GMRES for a matrix declared nonsymmetric; with another smoother it keeps hypre's cycle
// without a word.
TEST(AmgCycle, AutoIsSinglePrecisionWhereItApplies) {
  Kokkos::View<double **, Memory> positions;
  const CsrMatrix<Memory> a = grid3d(6, 1.0, positions);
  const std::vector<double> b = testVector(a.numRows);
  for (bool symmetric : {true, false}) {
    LinearSolverOptions o = chebyshevAmg(AmgCycleKind::Automatic, false);
    o.symmetric = symmetric;
    auto s = makeLinearSolver(o, DofMap::serial(216, 3), MPI_COMM_WORLD);
    s->setNearNullSpace(positions);
    const std::string before = s->name();
    s->setup(a);
    EXPECT_EQ(s->name(), before); // the start-up line names what runs
    EXPECT_EQ(s->name().find(symmetric ? "CG + BoomerAMG (Chebyshev of order 2; its V-cycle by "
                                         "mixcon in single precision)"
                                       : "GMRES + BoomerAMG (Chebyshev of order 2; its V-cycle by "
                                         "mixcon in single precision)"),
              0u)
        << s->name();
    LinearSolveStats st;
    solved(*s, b, st);
    EXPECT_TRUE(st.converged) << symmetric;
    EXPECT_LE(st.relativeResidual, 1e-8) << symmetric;
  }
  LinearSolverOptions gs = chebyshevAmg(AmgCycleKind::Automatic, false);
  gs.smoother = AmgSmoother::L1GaussSeidel;
  auto s = makeLinearSolver(gs, DofMap::serial(216, 3), MPI_COMM_WORLD);
  s->setNearNullSpace(positions);
  s->setup(a);
  EXPECT_EQ(s->name().find("mixcon"), std::string::npos) << s->name();
  EXPECT_EQ(s->name().find("hypre PCG + BoomerAMG"), 0u) << s->name();
}

// The Chebyshev order reaches hypre: hypre's own V-cycle differs between orders 1 and 2 (the copies
// above read the order from hypre's data, so they would agree with hypre whatever order it kept),
// and so does the copy's.
TEST(AmgCycle, ChebyshevOrderReachesHypre) {
  Kokkos::View<double **, Memory> positions;
  const CsrMatrix<Memory> a = grid3d(9, 1.0, positions);
  const DofMap dofs = DofMap::serial(9 * 9 * 9, 3);
  const std::vector<double> b = testVector(a.numRows);
  for (AmgCycleKind kind : {AmgCycleKind::Hypre, AmgCycleKind::MixconDouble}) {
    std::vector<double> y[2];
    for (int order : {1, 2}) {
      auto s = makeLinearSolver(chebyshevAmg(kind, false, order), dofs, MPI_COMM_WORLD);
      s->setNearNullSpace(positions);
      s->setup(a);
      y[order - 1] = preconditioned(*s, b);
      EXPECT_NE(s->name().find("Chebyshev of order " + std::to_string(order)), std::string::npos)
          << s->name();
    }
    EXPECT_GT(relativeDifference2(y[0], y[1]), 1e-3) << static_cast<int>(kind);
  }
}

// The Chebyshev order is 1 to 4 (hypre's polynomials); another is refused before any setup.
TEST(AmgCycle, ChebyshevOrderOutsideOneToFourIsRefused) {
  for (int order : {0, 5})
    EXPECT_THROW(makeLinearSolver(chebyshevAmg(AmgCycleKind::Automatic, false, order),
                                  DofMap::serial(8, 3), MPI_COMM_WORLD),
                 std::invalid_argument)
        << order;
}

// Where the copy does not apply (another smoother), hypre's cycle runs and the name says why.
TEST(AmgCycle, OtherSmoothersKeepHypresCycleAndSaySo) {
  Kokkos::View<double **, Memory> positions;
  const CsrMatrix<Memory> a = grid3d(6, 1.0, positions);
  LinearSolverOptions o = chebyshevAmg(AmgCycleKind::MixconSingle, false);
  o.smoother = AmgSmoother::L1GaussSeidel;
  auto s = makeLinearSolver(o, DofMap::serial(216, 3), MPI_COMM_WORLD);
  s->setNearNullSpace(positions);
  s->setup(a);
  EXPECT_NE(s->name().find("hypre's V-cycle: mixcon's takes the Chebyshev smoother only"),
            std::string::npos)
      << s->name();
  LinearSolveStats st;
  solved(*s, testVector(a.numRows), st);
  EXPECT_TRUE(st.converged);
}
