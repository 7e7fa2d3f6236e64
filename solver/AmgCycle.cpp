// BoomerAMG's V-cycle on mixcon's kernels (solver/AmgCycle.hpp).
#include <core/Transfer.hpp>
#include <solver/AmgCycle.hpp>
#include <solver/HostAlgebra.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace mixcon {

namespace {

using Exec = Kokkos::DefaultExecutionSpace;

/// A pivot below this times the largest marks the coarsest matrix singular to working precision
/// (as the direct solver's kSingularPivot).
constexpr double kSingularPivot = 1e-14;

/// dst = src, a host mirror of dst filled on the host: counted where it is a transfer (the
/// hierarchy goes from hypre's host memory to the device), nothing where the mirror is dst.
template <class D, class H> void upload(const D &dst, const H &src) {
  if constexpr (!kHostAccessible<DeviceSpace>)
    copyToDevice(dst, src);
  else
    Kokkos::deep_copy(dst, src); // the same memory: no copy
}

} // namespace

/// The levels of one precision (a namespace-scope class: nvcc refuses extended lambdas in a
/// class nested privately, docs/gpu.md).
template <class S> struct detail::AmgLevels {
  /// CSR with mixcon's index types; the views may be shared with the caller's matrix.
  struct Matrix {
    Kokkos::View<const Offset *, DeviceSpace> rowOffsets;
    Kokkos::View<const LocalIndex *, DeviceSpace> columns;
    Kokkos::View<const S *, DeviceSpace> values;
    LocalIndex rows = 0;
    /// The fine level read by node blocks (blocks.d > 0): unfiltered, whole d x d blocks, its
    /// values in the CSR's order; filtered (`diagonals`), each block's d diagonal entries side by
    /// side (rowOffsets and columns then empty: the blocks' own).
    NodeBlocks<DeviceSpace> blocks;
    bool diagonals = false;
    std::size_t bytes() const {
      return rowOffsets.span() * sizeof(Offset) + columns.span() * sizeof(LocalIndex) +
             values.span() * sizeof(S);
    }
  };
  struct Level {
    Matrix a, p, r; ///< p: from the next coarser level; r = p^T
    Kokkos::View<S *, DeviceSpace> ds;
    S c[4] = {0, 0, 0, 0};
    int order = 0;
    /// The right-hand side (f, read; fw, its storage: the fine level in double reads b itself),
    /// the iterate (the fine level in double: x itself), the scaled residual and two work vectors.
    Kokkos::View<const S *, DeviceSpace> f;
    Kokkos::View<S *, DeviceSpace> fw, u, res, t, t2;
  };
  std::vector<Level> level;
  /// The fine matrix's values where they are this copy's own (single precision, or filtered).
  Kokkos::View<S *, DeviceSpace> fineValues;
  /// The coarsest matrix's inverse, in double in either precision: the coarsest level of a
  /// slender part is as ill-conditioned as the whole (cond ~ (L/h)^4), and a single-precision
  /// inverse would lose its coarse correction there; it is small (at most 2000 unknowns).
  Kokkos::View<double **, Kokkos::LayoutRight, DeviceSpace> inverse;
  int components = 0; ///< the fine level keeps only i % d == j % d (0: all entries)
  /// The fine level's own pattern where it is filtered (else the caller's, shared).
  Kokkos::View<Offset *, DeviceSpace> fineOffsets;
  Kokkos::View<LocalIndex *, DeviceSpace> fineColumns;
  /// The fine matrix's node blocks (d = 0: none; else its products read one column per block).
  NodeBlocks<DeviceSpace> fineBlocks;
  /// The filtered fine level as its blocks' diagonals (fineBlocks.d == components).
  bool fineDiagonals = false;

  // ---- the fine level ----

  void setFine(const CsrMatrix<DeviceSpace> &fine) {
    Matrix &a = level[0].a;
    a.rows = fine.numRows;
    a.blocks = fineBlocks;
    a.diagonals = fineDiagonals;
    if (fineDiagonals) {
      const int d = components;
      const auto v = ownValues(fineBlocks.columns.extent(0) * d);
      const auto bo = fineBlocks.offsets;
      const auto ro = fine.rowOffsets;
      const auto values = fine.values;
      Kokkos::parallel_for( // block j of node I: row dI + c holds its entry c at (j - bo(I)) d + c
          "mixcon::amg::cycle::blockDiagonals", Kokkos::RangePolicy<Exec>(0, fineBlocks.numNodes()),
          KOKKOS_LAMBDA(LocalIndex node) {
            for (int c = 0; c < d; ++c) {
              const Offset row = ro(d * node + c);
              for (Offset j = bo(node); j < bo(node + 1); ++j)
                v(d * j + c) = static_cast<S>(values(row + (j - bo(node)) * d + c));
            }
          });
      a.rowOffsets = {};
      a.columns = {};
      a.values = v;
    } else if (components > 1) {
      if (fineColumns.extent(0) == 0)
        filterPattern(fine);
      const auto v = ownValues(fineColumns.extent(0));
      const int d = components;
      const auto ro = fine.rowOffsets;
      const auto co = fine.columns;
      const auto values = fine.values;
      const auto offsets = fineOffsets;
      Kokkos::parallel_for( // the entries kept, in the order filterPattern kept them
          "mixcon::amg::cycle::filterValues", Kokkos::RangePolicy<Exec>(0, fine.numRows),
          KOKKOS_LAMBDA(LocalIndex i) {
            Offset at = offsets(i);
            for (Offset k = ro(i); k < ro(i + 1); ++k)
              if (co(k) % d == i % d)
                v(at++) = static_cast<S>(values(k));
          });
      a.rowOffsets = fineOffsets;
      a.columns = fineColumns;
      a.values = v;
    } else {
      a.rowOffsets = fine.rowOffsets;
      a.columns = fine.columns;
      if constexpr (std::is_same_v<S, double>) {
        a.values = fine.values;
      } else {
        const auto v = ownValues(fine.values.extent(0));
        const auto values = fine.values;
        Kokkos::parallel_for(
            "mixcon::amg::cycle::convertValues", Kokkos::RangePolicy<Exec>(0, v.extent(0)),
            KOKKOS_LAMBDA(std::size_t k) { v(k) = static_cast<S>(values(k)); });
        a.values = v;
      }
    }
    Exec().fence();
  }

  /// fineValues of n entries (kept from the last setup where n is the same).
  Kokkos::View<S *, DeviceSpace> ownValues(std::size_t n) {
    if (fineValues.extent(0) != n)
      fineValues = Kokkos::View<S *, DeviceSpace>(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::amg::cycle::fineValues"), n);
    return fineValues;
  }

  /// The pattern of the entries that couple equal components.
  void filterPattern(const CsrMatrix<DeviceSpace> &fine) {
    const LocalIndex n = fine.numRows;
    const int d = components;
    const auto ro = fine.rowOffsets;
    const auto co = fine.columns;
    fineOffsets = Kokkos::View<Offset *, DeviceSpace>("mixcon::amg::cycle::fineOffsets", n + 1);
    const auto offsets = fineOffsets;
    Kokkos::parallel_for(
        "mixcon::amg::cycle::filterCount", Kokkos::RangePolicy<Exec>(0, n),
        KOKKOS_LAMBDA(LocalIndex i) {
          Offset c = 0;
          for (Offset k = ro(i); k < ro(i + 1); ++k)
            c += co(k) % d == i % d;
          offsets(i + 1) = c;
        });
    Kokkos::parallel_scan(
        "mixcon::amg::cycle::filterScan", Kokkos::RangePolicy<Exec>(0, n + 1),
        KOKKOS_LAMBDA(LocalIndex i, Offset & sum, bool last) {
          sum += offsets(i);
          if (last)
            offsets(i) = sum;
        });
    Offset kept = 0;
    Kokkos::deep_copy(kept, Kokkos::subview(fineOffsets, n));
    fineColumns = Kokkos::View<LocalIndex *, DeviceSpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::amg::cycle::fineColumns"), kept);
    const auto columns = fineColumns;
    Kokkos::parallel_for(
        "mixcon::amg::cycle::filterFill", Kokkos::RangePolicy<Exec>(0, n),
        KOKKOS_LAMBDA(LocalIndex i) {
          Offset at = offsets(i);
          for (Offset k = ro(i); k < ro(i + 1); ++k)
            if (co(k) % d == i % d)
              columns(at++) = co(k);
        });
  }

  // ---- the coarse levels, copied from the host ----

  /// A matrix filled on the host (hypre's arrays are host memory) and then uploaded.
  struct HostFill {
    Kokkos::View<Offset *, DeviceSpace> ro;
    Kokkos::View<LocalIndex *, DeviceSpace> co;
    Kokkos::View<S *, DeviceSpace> va;
    typename Kokkos::View<Offset *, DeviceSpace>::HostMirror hro;
    typename Kokkos::View<LocalIndex *, DeviceSpace>::HostMirror hco;
    typename Kokkos::View<S *, DeviceSpace>::HostMirror hva;
    LocalIndex rows;
    HostFill(LocalIndex n, Offset nnz, const std::string &label)
        : ro(Kokkos::view_alloc(Kokkos::WithoutInitializing, label), n + 1),
          co(Kokkos::view_alloc(Kokkos::WithoutInitializing, label), nnz),
          va(Kokkos::view_alloc(Kokkos::WithoutInitializing, label), nnz), hro(hostMirror(ro)),
          hco(hostMirror(co)), hva(hostMirror(va)), rows(n) {}
    Matrix upload() const {
      mixcon::upload(ro, hro);
      mixcon::upload(co, hco);
      mixcon::upload(va, hva);
      Matrix m;
      m.rows = rows;
      m.rowOffsets = ro;
      m.columns = co;
      m.values = va;
      return m;
    }
  };

  // On the host's threads: the coarse levels of the full 3D stiffness hold tens of millions of
  // entries.
  static Matrix copy(const AmgHostCsr &h, const std::string &label) {
    HostFill m(h.rows, h.rowOffsets[h.rows], label);
    const int *hr = h.rowOffsets, *hc = h.columns;
    const double *hv = h.values;
    const auto ro = m.hro;
    const auto co = m.hco;
    const auto va = m.hva;
    Kokkos::parallel_for("mixcon::amg::cycle::copyLevel", HostRange(0, h.rows), [=](int i) {
      ro(i) = hr[i];
      for (int k = hr[i]; k < hr[i + 1]; ++k) {
        co(k) = hc[k];
        va(k) = static_cast<S>(hv[k]);
      }
    });
    Kokkos::DefaultHostExecutionSpace().fence();
    ro(h.rows) = hr[h.rows];
    return m.upload();
  }

  /// R = P^T of a host CSR P (rows: the finer level, columns: the coarser), each row of R in
  /// ascending columns (the order of a serial transpose, so that sums are reproducible).
  static Matrix transpose(const AmgHostCsr &p, const std::string &label) {
    const Offset nnz = p.rowOffsets[p.rows];
    HostFill m(p.columnsCount, nnz, label);
    const int *pr = p.rowOffsets, *pc = p.columns;
    const double *pv = p.values;
    const auto ro = m.hro;
    const auto co = m.hco;
    const auto va = m.hva;
    Kokkos::deep_copy(ro, Offset(0));
    Kokkos::parallel_for( // each column's count
        "mixcon::amg::cycle::transposeCount", HostRange(0, nnz),
        [=](Offset k) { Kokkos::atomic_increment(&ro(pc[k] + 1)); });
    Kokkos::parallel_scan("mixcon::amg::cycle::transposeScan", HostRange(0, p.columnsCount + 1),
                          [=](int j, Offset &sum, bool last) {
                            sum += ro(j);
                            if (last)
                              ro(j) = sum;
                          });
    Kokkos::View<Offset *, Kokkos::HostSpace> at(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::amg::cycle::transposeAt"),
        p.columnsCount);
    Kokkos::parallel_for("mixcon::amg::cycle::transposeStart", HostRange(0, p.columnsCount),
                         [=](int j) { at(j) = ro(j); });
    Kokkos::parallel_for( // in any order ...
        "mixcon::amg::cycle::transposeFill", HostRange(0, p.rows), [=](int i) {
          for (int k = pr[i]; k < pr[i + 1]; ++k) {
            const Offset q = Kokkos::atomic_fetch_add(&at(pc[k]), Offset(1));
            co(q) = i;
            va(q) = static_cast<S>(pv[k]);
          }
        });
    Kokkos::parallel_for( // ... then each row sorted by its columns
        "mixcon::amg::cycle::transposeSort", HostRange(0, p.columnsCount), [=](int j) {
          if (ro(j + 1) - ro(j) > 32) { // long rows (aggressive coarsening): a general sort
            std::vector<std::pair<LocalIndex, S>> row;
            for (Offset k = ro(j); k < ro(j + 1); ++k)
              row.emplace_back(co(k), va(k));
            std::sort(row.begin(), row.end());
            for (Offset k = ro(j); k < ro(j + 1); ++k)
              std::tie(co(k), va(k)) = row[static_cast<std::size_t>(k - ro(j))];
            return;
          }
          for (Offset k = ro(j) + 1; k < ro(j + 1); ++k) { // short rows: by insertion
            const LocalIndex c = co(k);
            const S v = va(k);
            Offset q = k;
            for (; q > ro(j) && co(q - 1) > c; --q) {
              co(q) = co(q - 1);
              va(q) = va(q - 1);
            }
            co(q) = c;
            va(q) = v;
          }
        });
    Kokkos::DefaultHostExecutionSpace().fence();
    return m.upload();
  }

  void coarsestInverse(const AmgHostCsr &a) {
    const int n = a.rows;
    std::vector<double> dense(static_cast<std::size_t>(n) * n, 0.0), inv;
    for (int i = 0; i < n; ++i)
      for (int k = a.rowOffsets[i]; k < a.rowOffsets[i + 1]; ++k)
        dense[static_cast<std::size_t>(i) * n + a.columns[k]] += a.values[k];
    if (!invertSmallDense(dense, n, inv, kSingularPivot))
      throw std::runtime_error("the coarsest AMG level (" + std::to_string(n) +
                               " unknowns) is singular to working precision");
    inverse = Kokkos::View<double **, Kokkos::LayoutRight, DeviceSpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::amg::cycle::coarsestInverse"), n,
        n);
    auto h = hostMirror(inverse);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        h(i, j) = inv[static_cast<std::size_t>(i) * n + j];
    upload(inverse, h);
  }

  static Kokkos::View<S *, DeviceSpace> vector(LocalIndex n, const std::string &label) {
    return Kokkos::View<S *, DeviceSpace>(Kokkos::view_alloc(Kokkos::WithoutInitializing, label),
                                          n);
  }

  /// Level l's Chebyshev smoother (coefficients, scaling) and its work vectors.
  void chebyshevLevel(std::size_t l, const HostAmgLevel &h, LocalIndex n) {
    Level &v = level[l];
    v.order = static_cast<int>(h.coefficients.size());
    if (v.order < 1 || v.order > 4 || h.ds == nullptr)
      throw std::runtime_error("AMG level " + std::to_string(l) +
                               ": a Chebyshev order of 1 to 4 and its scaling, not order " +
                               std::to_string(v.order));
    for (int m = 0; m < v.order; ++m)
      v.c[m] = static_cast<S>(h.coefficients[m]);
    v.ds = vector(n, "mixcon::amg::cycle::chebyshevScaling");
    auto hds = hostMirror(v.ds);
    for (LocalIndex i = 0; i < n; ++i)
      hds(i) = static_cast<S>(h.ds[i]);
    upload(v.ds, hds);
    v.res = vector(n, "mixcon::amg::cycle::scaledResidual");
    v.t = vector(n, "mixcon::amg::cycle::work");
    if (v.order > 2)
      v.t2 = vector(n, "mixcon::amg::cycle::work");
  }

  AmgLevels(const CsrMatrix<DeviceSpace> &fine, int filterComponents,
            const std::vector<HostAmgLevel> &host, const NodeBlocks<DeviceSpace> &blocks)
      : components(filterComponents) {
    // The separate components' level by blocks: their diagonals copied side by side (read in
    // place from the whole blocks, every cache line of the matrix was read, and the cube's solve
    // took longer than with the level's own CSR, docs/performance.md table 3i). On the host only:
    // not yet measured on a GPU, where the CSR's rows are the measured path.
    const bool fits = blocks.d > 0 && blocks.numNodes() * blocks.d == fine.numRows;
    if (fits && components <= 1)
      fineBlocks = blocks;
    if (fits && components == blocks.d && kHostAccessible<DeviceSpace>) {
      fineBlocks = blocks;
      fineDiagonals = true;
    }
    const std::size_t L = host.size();
    level.resize(L);
    for (std::size_t l = 0; l < L; ++l) {
      Level &v = level[l];
      const HostAmgLevel &h = host[l];
      const LocalIndex n = l == 0 ? fine.numRows : h.a.rows;
      if (h.a.rows != n || (l + 1 < L && (h.p.rows != n || h.p.columnsCount != host[l + 1].a.rows)))
        throw std::runtime_error("AMG level " + std::to_string(l) +
                                 ": its matrix and interpolation do not fit the levels beside it");
      // smoothed: every level but the coarsest, which is inverted unless it comes with its
      // smoother (hypre's coarsest solve where its coarsening stopped early)
      if (l + 1 < L || !h.coefficients.empty())
        chebyshevLevel(l, h, n);
      else
        coarsestInverse(h.a);
      if (l > 0 && v.order > 0)
        v.a = copy(h.a, "mixcon::amg::cycle::levelMatrix");
      if (l + 1 < L) {
        v.p = copy(h.p, "mixcon::amg::cycle::interpolation");
        v.r = transpose(h.p, "mixcon::amg::cycle::restriction");
      }
      if (l > 0 || !std::is_same_v<S, double>) {
        v.fw = vector(n, "mixcon::amg::cycle::rightHandSide");
        v.f = v.fw;
        v.u = vector(n, "mixcon::amg::cycle::iterate");
      }
    }
    setFine(fine);
  }

  // ---- the cycle ----

  /// rows() on node blocks of D unknowns: each node's D rows, their epilogues in row order. Whole
  /// blocks (detail::nodeBlockRows), or the filtered level's block diagonals: a node's D rows in
  /// one pass, D sums side by side, each in the order of the filtered CSR's row.
  template <int D, class F>
  static void nodeRows(const char *label, const Matrix &a,
                       const Kokkos::View<const S *, DeviceSpace> &x, const F &epilogue) {
    const auto bo = a.blocks.offsets;
    const auto bc = a.blocks.columns;
    const auto va = a.values;
    const bool diagonals = a.diagonals;
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<Exec>(0, a.blocks.numNodes()), KOKKOS_LAMBDA(LocalIndex node) {
          if (!diagonals) {
            detail::nodeBlockRows<D>(node, bo, bc, va, x, epilogue);
            return;
          }
          // 64-bit positions: with an int column sign-extended per block this loop took 1.5x the
          // time (perf, the cube's solve at N = 100; docs/performance.md table 3l)
          S s[D] = {};
          const Offset first = bo(node), last = bo(node + 1);
          Offset at = D * first;
          for (Offset j = first; j < last; ++j, at += D) {
            const Offset c = D * static_cast<Offset>(bc(j));
            for (int k = 0; k < D; ++k)
              s[k] += va(at + k) * x(c + k);
          }
          for (int k = 0; k < D; ++k)
            epilogue(D * node + k, s[k]);
        });
  }

  /// For each row i: epilogue(i, (A x)_i).
  template <class F>
  static void rows(const char *label, const Matrix &a,
                   const Kokkos::View<const S *, DeviceSpace> &x, const F &epilogue) {
    if (a.blocks.d == 3) {
      nodeRows<3>(label, a, x, epilogue);
      return;
    }
    if (a.blocks.d == 2) {
      nodeRows<2>(label, a, x, epilogue);
      return;
    }
    const auto ro = a.rowOffsets;
    const auto co = a.columns;
    const auto va = a.values;
    Kokkos::parallel_for(
        label, Kokkos::RangePolicy<Exec>(0, a.rows), KOKKOS_LAMBDA(LocalIndex i) {
          S s = 0;
          for (Offset k = ro(i); k < ro(i + 1); ++k)
            s += va(k) * x(co(k));
          epilogue(i, s);
        });
  }

  /// hypre_ParCSRRelax_Cheby_Solve (scaled, variant 0) on level l: u += D^-1/2 p(D^-1/2 A
  /// D^-1/2) D^-1/2 (f - A u), from u = 0 when `zero` (then without the product with u).
  void smooth(Level &v, bool zero) {
    const auto ds = v.ds;
    const auto f = v.f;
    const auto r = v.res;
    const auto u = v.u;
    auto t = v.t, t2 = v.t2;
    const S top = v.c[v.order - 1];
    if (zero) {
      Kokkos::parallel_for(
          "mixcon::amg::cycle::smoothStart", Kokkos::RangePolicy<Exec>(0, v.f.extent(0)),
          KOKKOS_LAMBDA(LocalIndex i) {
            r(i) = ds(i) * f(i);
            t(i) = ds(i) * top * r(i);
          });
    } else {
      rows(
          "mixcon::amg::cycle::smoothResidual", v.a, u, KOKKOS_LAMBDA(LocalIndex i, S s) {
            r(i) = ds(i) * (f(i) - s);
            t(i) = ds(i) * top * r(i);
          });
    }
    if (v.order == 1) { // u = u + D^-1/2 c0 r = u + t
      Kokkos::parallel_for(
          "mixcon::amg::cycle::smoothEnd", Kokkos::RangePolicy<Exec>(0, v.f.extent(0)),
          KOKKOS_LAMBDA(LocalIndex i) { u(i) = (zero ? S(0) : u(i)) + t(i); });
      return;
    }
    for (int m = v.order - 2; m > 0; --m) {
      const S c = v.c[m];
      const auto out = t2;
      rows(
          "mixcon::amg::cycle::smoothStep", v.a, t,
          KOKKOS_LAMBDA(LocalIndex i, S s) { out(i) = ds(i) * (c * r(i) + ds(i) * s); });
      std::swap(t, t2);
    }
    const S c0 = v.c[0];
    rows(
        "mixcon::amg::cycle::smoothLast", v.a, t, KOKKOS_LAMBDA(LocalIndex i, S s) {
          u(i) = (zero ? S(0) : u(i)) + ds(i) * (c0 * r(i) + ds(i) * s);
        });
  }

  void cycle(std::size_t l) {
    if (l + 1 == level.size() && level[l].order > 0) { // one sweep from zero, as hypre's
      smooth(level[l], true);
      return;
    }
    if (l + 1 == level.size()) {
      const auto inv = inverse;
      const auto f = level[l].f;
      const auto u = level[l].u;
      const LocalIndex n = static_cast<LocalIndex>(inv.extent(0));
      Kokkos::parallel_for(
          "mixcon::amg::cycle::coarsest", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) {
            double s = 0.0;
            for (int j = 0; j < n; ++j)
              s += inv(i, j) * static_cast<double>(f(j));
            u(i) = static_cast<S>(s);
          });
      return;
    }
    Level &fine = level[l];
    Level &coarse = level[l + 1];
    smooth(fine, true);
    const auto f = fine.f;
    const auto residual = fine.res;
    rows(
        "mixcon::amg::cycle::residual", fine.a, fine.u,
        KOKKOS_LAMBDA(LocalIndex i, S s) { residual(i) = f(i) - s; });
    const auto fc = coarse.fw;
    rows(
        "mixcon::amg::cycle::restrict", fine.r, residual,
        KOKKOS_LAMBDA(LocalIndex i, S s) { fc(i) = s; });
    cycle(l + 1);
    const auto u = fine.u;
    rows(
        "mixcon::amg::cycle::interpolate", fine.p, coarse.u,
        KOKKOS_LAMBDA(LocalIndex i, S s) { u(i) += s; });
    smooth(fine, false);
  }

  void apply(const Kokkos::View<const double *, DeviceSpace> &b,
             const Kokkos::View<double *, DeviceSpace> &x) {
    Level &fine = level[0];
    if constexpr (std::is_same_v<S, double>) { // the cycle reads b and writes x themselves
      fine.f = b;
      fine.u = x;
      cycle(0);
      fine.f = {}; // not kept past the call
      fine.u = {};
    } else {
      const auto f = fine.fw;
      Kokkos::parallel_for(
          "mixcon::amg::cycle::toCyclePrecision", Kokkos::RangePolicy<Exec>(0, f.extent(0)),
          KOKKOS_LAMBDA(LocalIndex i) { f(i) = static_cast<S>(b(i)); });
      cycle(0);
      const auto u = fine.u;
      Kokkos::parallel_for(
          "mixcon::amg::cycle::fromCyclePrecision", Kokkos::RangePolicy<Exec>(0, f.extent(0)),
          KOKKOS_LAMBDA(LocalIndex i) { x(i) = static_cast<double>(u(i)); });
    }
  }

  std::size_t bytes() const {
    std::size_t b = inverse.span() * sizeof(double);
    for (std::size_t l = 0; l < level.size(); ++l) {
      const Level &v = level[l];
      // the fine matrix's pattern is the caller's unless filtered; its values unless converted
      if (l > 0)
        b += v.a.bytes();
      else if (components > 1)
        b += v.a.bytes();
      else if (!std::is_same_v<S, double>)
        b += v.a.values.span() * sizeof(S);
      b += v.p.bytes() + v.r.bytes();
      // (a sum, not a range-for over a braced list of the views: nvcc 13 misparses that)
      b += (v.ds.span() + v.fw.span() + v.u.span() + v.res.span() + v.t.span() + v.t2.span()) *
           sizeof(S);
    }
    return b;
  }
};

AmgCycle::AmgCycle(const CsrMatrix<DeviceSpace> &fine, int filterComponents,
                   const std::vector<HostAmgLevel> &levels, AmgCyclePrecision precision,
                   const NodeBlocks<DeviceSpace> &fineBlocks)
    : precision_(precision) {
  if (levels.size() < 2)
    throw std::invalid_argument("AmgCycle: a hierarchy of at least 2 levels");
  if (precision == AmgCyclePrecision::Double)
    double_ =
        std::make_unique<detail::AmgLevels<double>>(fine, filterComponents, levels, fineBlocks);
  else
    single_ =
        std::make_unique<detail::AmgLevels<float>>(fine, filterComponents, levels, fineBlocks);
}

bool AmgCycle::fineLevelByNodeBlocks() const {
  return (double_ ? double_->level[0].a.blocks.d : single_->level[0].a.blocks.d) > 0;
}

AmgCycle::~AmgCycle() = default;

void AmgCycle::setFineMatrix(const CsrMatrix<DeviceSpace> &fine) {
  if (double_)
    double_->setFine(fine);
  else
    single_->setFine(fine);
}

void AmgCycle::apply(const Kokkos::View<const double *, DeviceSpace> &b,
                     const Kokkos::View<double *, DeviceSpace> &x) {
  if (double_)
    double_->apply(b, x);
  else
    single_->apply(b, x);
}

int AmgCycle::levels() const {
  return static_cast<int>(double_ ? double_->level.size() : single_->level.size());
}

std::size_t AmgCycle::bytes() const { return double_ ? double_->bytes() : single_->bytes(); }

std::string amgCyclePrecisionName(AmgCyclePrecision p) {
  return p == AmgCyclePrecision::Double ? "double" : "single";
}

} // namespace mixcon
