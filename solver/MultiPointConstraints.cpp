// Multipoint constraints on the device: T uploaded from its host description, T^T A T + D formed
// row by row (symbolic + numeric phase), T y + s, T^T v and the condensed free-residual norm.
// Layer: solver.
#include <core/Transfer.hpp>
#include <solver/MultiPointConstraints.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace mixcon {

namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Memory = Exec::memory_space;
using Policy = Kokkos::RangePolicy<Exec>;

/// Host arrays of one type uploaded in one copy, then split into their views on the device.
template <class T> class Upload {
public:
  void add(Kokkos::View<T *, Memory> &view, const char *label, const std::vector<T> &h) {
    parts_.push_back({&view, label, data_.size(), h.size()});
    data_.insert(data_.end(), h.begin(), h.end());
  }
  void run() {
    Kokkos::View<T *, Memory> all("mixcon::mpc::upload", data_.size());
    if (!data_.empty())
      copyToDevice(all, data_);
    for (const Part &p : parts_) {
      *p.view = Kokkos::View<T *, Memory>(std::string(p.label), p.size);
      if (p.size > 0)
        Kokkos::deep_copy(*p.view, Kokkos::subview(all, std::make_pair(p.first, p.first + p.size)));
    }
  }

private:
  struct Part {
    Kokkos::View<T *, Memory> *view;
    const char *label;
    std::size_t first, size;
  };
  std::vector<Part> parts_;
  std::vector<T> data_;
};

/// The contributions to row j of T^T A T: calls f(column, value) for every product term (the
/// same column may come several times). Row j of T^T A T = sum_i T_ij (A T)_i, (A T)_i = sum_l
/// A_il T_l; T_ij = delta_ij for unlisted i, the transpose entries for listed i.
struct ReducedRows {
  Kokkos::View<const Offset *, Memory> ro;
  Kokkos::View<const LocalIndex *, Memory> co;
  Kokkos::View<const double *, Memory> va;
  MultiPointView<Memory> t;

  /// Row i of A T, scaled by `scale`.
  template <class F>
  KOKKOS_INLINE_FUNCTION void productRow(LocalIndex i, double scale, const F &f) const {
    for (Offset k = ro(i); k < ro(i + 1); ++k) {
      const LocalIndex l = co(k);
      const double a = scale * va(k);
      const int r = t.rowOf(l);
      if (r < 0) {
        f(l, a);
      } else {
        for (Offset e = t.rowStart(r); e < t.rowStart(r + 1); ++e)
          f(t.columns(e), a * t.values(e));
      }
    }
  }
  template <class F> KOKKOS_INLINE_FUNCTION void visit(LocalIndex j, const F &f) const {
    if (t.rowOf(j) < 0)
      productRow(j, 1.0, f);
    const int q = t.targetOf(j);
    if (q >= 0)
      for (Offset e = t.targetStart(q); e < t.targetStart(q + 1); ++e)
        productRow(t.rows(t.sourceRow(e)), t.sourceValue(e), f);
  }
};

/// (T^T w)(j), w given by a function of the unknown.
template <class W>
KOKKOS_INLINE_FUNCTION double transposeAt(const MultiPointView<Memory> &t, LocalIndex j,
                                          const W &w) {
  if (t.slave(j))
    return 0.0;
  double v = t.rowOf(j) < 0 ? w(j) : 0.0;
  const int q = t.targetOf(j);
  if (q >= 0)
    for (Offset e = t.targetStart(q); e < t.targetStart(q + 1); ++e)
      v += t.sourceValue(e) * w(t.rows(t.sourceRow(e)));
  return v;
}

} // namespace

DeviceMultiPointConstraints toDevice(const MultiPointConstraints &c, LocalIndex n) {
  DeviceMultiPointConstraints t;
  t.numUnknowns = n;
  const std::size_t m = c.rows.size();
  std::vector<Offset> rowStart(m + 1, 0);
  std::vector<LocalIndex> columns;
  std::vector<double> values;
  t.pattern.reserve(2 * m);
  for (std::size_t r = 0; r < m; ++r) {
    for (const auto &[col, v] : c.entries[r]) {
      columns.push_back(col);
      values.push_back(v);
    }
    rowStart[r + 1] = static_cast<Offset>(columns.size());
    t.pattern.push_back(c.rows[r]);
    t.pattern.push_back(static_cast<LocalIndex>(c.entries[r].size()));
  }
  t.pattern.insert(t.pattern.end(), columns.begin(), columns.end());
  // The transpose of the listed rows, grouped by column (targets in increasing order).
  std::vector<std::pair<LocalIndex, std::size_t>> byColumn; // (column, entry)
  byColumn.reserve(columns.size());
  for (std::size_t e = 0; e < columns.size(); ++e)
    byColumn.emplace_back(columns[e], e);
  std::stable_sort(byColumn.begin(), byColumn.end(),
                   [](const auto &x, const auto &y) { return x.first < y.first; });
  std::vector<LocalIndex> targets, sourceRow;
  std::vector<Offset> targetStart{0};
  std::vector<double> sourceValue;
  std::vector<LocalIndex> entryRow(columns.size());
  for (std::size_t r = 0; r < m; ++r)
    for (Offset e = rowStart[r]; e < rowStart[r + 1]; ++e)
      entryRow[e] = static_cast<LocalIndex>(r);
  for (std::size_t k = 0; k < byColumn.size(); ++k) {
    if (k == 0 || byColumn[k].first != byColumn[k - 1].first) {
      if (k > 0)
        targetStart.push_back(static_cast<Offset>(k));
      targets.push_back(byColumn[k].first);
    }
    sourceRow.push_back(entryRow[byColumn[k].second]);
    sourceValue.push_back(values[byColumn[k].second]);
  }
  if (!byColumn.empty())
    targetStart.push_back(static_cast<Offset>(byColumn.size()));
  // Three copies: the indices, the offsets, the values.
  Upload<LocalIndex> indices;
  Upload<Offset> starts;
  Upload<double> reals;
  Kokkos::View<LocalIndex *, Memory> slaves;
  indices.add(t.rows, "mixcon::mpc::rows", c.rows);
  indices.add(t.columns, "mixcon::mpc::columns", columns);
  indices.add(t.targets, "mixcon::mpc::targets", targets);
  indices.add(t.sourceRow, "mixcon::mpc::sourceRow", sourceRow);
  indices.add(slaves, "mixcon::mpc::slaves", c.slaves);
  starts.add(t.rowStart, "mixcon::mpc::rowStart", rowStart);
  starts.add(t.targetStart, "mixcon::mpc::targetStart", targetStart);
  reals.add(t.values, "mixcon::mpc::values", values);
  reals.add(t.offset, "mixcon::mpc::offset", c.offset);
  reals.add(t.sourceValue, "mixcon::mpc::sourceValue", sourceValue);
  indices.run();
  starts.run();
  reals.run();
  // Per-unknown lookups, filled on the device.
  t.rowOf = Kokkos::View<int *, Memory>("mixcon::mpc::rowOf", n);
  t.targetOf = Kokkos::View<int *, Memory>("mixcon::mpc::targetOf", n);
  t.slave = Kokkos::View<int *, Memory>("mixcon::mpc::slave", n);
  Kokkos::deep_copy(t.rowOf, -1);
  Kokkos::deep_copy(t.targetOf, -1);
  const auto rows = t.rows, tg = t.targets;
  const auto rowOf = t.rowOf, targetOf = t.targetOf, slave = t.slave;
  Kokkos::parallel_for(
      "mixcon::mpc::rowOf", Policy(0, static_cast<LocalIndex>(m)),
      KOKKOS_LAMBDA(LocalIndex r) { rowOf(rows(r)) = r; });
  Kokkos::parallel_for(
      "mixcon::mpc::targetOf", Policy(0, static_cast<LocalIndex>(targets.size())),
      KOKKOS_LAMBDA(LocalIndex q) { targetOf(tg(q)) = q; });
  Kokkos::parallel_for(
      "mixcon::mpc::slave", Policy(0, static_cast<LocalIndex>(c.slaves.size())),
      KOKKOS_LAMBDA(LocalIndex s) { slave(slaves(s)) = 1; });
  return t;
}

namespace {

/// The symbolic phase: the pattern of T^T A T with every diagonal entry (a free function: CUDA
/// refuses device lambdas in private member functions).
CsrMatrix<Memory> reducedPattern(const CsrMatrix<Memory> &a, const MultiPointView<Memory> &t) {
  const LocalIndex n = a.numRows;
  const ReducedRows rr{a.rowOffsets, a.columns, a.values, t};
  // Upper bound of each reduced row (every contribution and the diagonal), then the candidate
  // columns, sorted and made unique per row, then compacted.
  Kokkos::View<Offset *, Memory> bound("mixcon::mpc::bound", n + 1);
  Kokkos::parallel_for(
      "mixcon::mpc::rowBound", Policy(0, n), KOKKOS_LAMBDA(LocalIndex j) {
        Offset c = 1;
        rr.visit(j, [&](LocalIndex, double) { ++c; });
        bound(j + 1) = c;
      });
  Offset total = 0;
  Kokkos::parallel_scan(
      "mixcon::mpc::boundScan", Policy(0, n + 1),
      KOKKOS_LAMBDA(LocalIndex i, Offset & sum, bool final) {
        sum += bound(i);
        if (final)
          bound(i) = sum;
      },
      total);
  Kokkos::View<LocalIndex *, Memory> cand("mixcon::mpc::candidates", total);
  Kokkos::View<Offset *, Memory> rowOffsets("mixcon::mpc::rowOffsets", n + 1);
  Kokkos::parallel_for(
      "mixcon::mpc::candidates", Policy(0, n), KOKKOS_LAMBDA(LocalIndex j) {
        const Offset first = bound(j);
        Offset c = first;
        cand(c++) = j;
        rr.visit(j, [&](LocalIndex col, double) { cand(c++) = col; });
        // Shell sort (gaps 1, 4, 13, 40, ...: rows that receive constrained rows hold many
        // repeated candidates), then unique.
        const Offset len = c - first;
        Offset gap = 1;
        while (gap < len / 3)
          gap = 3 * gap + 1;
        for (; gap > 0; gap /= 3)
          for (Offset i = first + gap; i < c; ++i) {
            const LocalIndex v = cand(i);
            Offset k = i;
            while (k >= first + gap && cand(k - gap) > v) {
              cand(k) = cand(k - gap);
              k -= gap;
            }
            cand(k) = v;
          }
        Offset u = first;
        for (Offset i = first + 1; i < c; ++i)
          if (cand(i) != cand(u))
            cand(++u) = cand(i);
        rowOffsets(j + 1) = u - first + 1;
      });
  Offset nnz = 0;
  Kokkos::parallel_scan(
      "mixcon::mpc::rowScan", Policy(0, n + 1),
      KOKKOS_LAMBDA(LocalIndex i, Offset & sum, bool final) {
        sum += rowOffsets(i);
        if (final)
          rowOffsets(i) = sum;
      },
      nnz);
  Kokkos::View<LocalIndex *, Memory> columns("mixcon::mpc::reducedColumns", nnz);
  Kokkos::parallel_for(
      "mixcon::mpc::compact", Policy(0, n), KOKKOS_LAMBDA(LocalIndex j) {
        const Offset from = bound(j), to = rowOffsets(j);
        for (Offset k = 0; k < rowOffsets(j + 1) - to; ++k)
          columns(to + k) = cand(from + k);
      });
  CsrMatrix<Memory> pattern;
  pattern.numRows = pattern.numColumns = n;
  pattern.rowOffsets = rowOffsets;
  pattern.columns = columns;
  return pattern;
}

} // namespace

CsrMatrix<Memory> ConstraintElimination::eliminate(const CsrMatrix<Memory> &a,
                                                   const DeviceMultiPointConstraints &t,
                                                   double slaveDiagonal,
                                                   const Kokkos::View<double *, Memory> &rhs) {
  const LocalIndex n = a.numRows;
  reused_ = n == n_ && a.rowOffsets.data() == aRows_ && a.columns.data() == aColumns_ &&
            t.pattern == key_ && pattern_.numRows == n;
  if (!reused_) {
    pattern_ = reducedPattern(a, t.view());
    key_ = t.pattern;
    aRows_ = a.rowOffsets.data();
    aColumns_ = a.columns.data();
    n_ = n;
  }
  CsrMatrix<Memory> r = pattern_;
  r.values = Kokkos::View<double *, Memory>("mixcon::mpc::reducedValues", pattern_.numNonzeros());
  const ReducedRows rr{a.rowOffsets, a.columns, a.values, t.view()};
  const auto ro = r.rowOffsets;
  const auto co = r.columns;
  const auto va = r.values;
  Kokkos::parallel_for(
      "mixcon::mpc::reducedValues", Policy(0, n), KOKKOS_LAMBDA(LocalIndex j) {
        const Offset first = ro(j), last = ro(j + 1);
        const auto at = [&](LocalIndex col) { // binary search in the sorted row
          Offset lo = first, hi = last;
          while (hi - lo > 1) {
            const Offset mid = (lo + hi) / 2;
            if (co(mid) <= col)
              lo = mid;
            else
              hi = mid;
          }
          return lo;
        };
        rr.visit(j, [&](LocalIndex col, double v) { va(at(col)) += v; });
        if (rr.t.slave(j))
          va(at(j)) += slaveDiagonal;
      });
  // rhs <- T^T (rhs - A s): (rhs - A s)(i) evaluated where T^T reads it.
  const auto aro = a.rowOffsets;
  const auto aco = a.columns;
  const auto ava = a.values;
  const auto rowOf = t.rowOf;
  const auto offset = t.offset;
  Kokkos::View<double *, Memory> out("mixcon::mpc::reducedRhs", n);
  Kokkos::parallel_for(
      "mixcon::mpc::reducedRhs", Policy(0, n), KOKKOS_LAMBDA(LocalIndex j) {
        const auto shifted = [&](LocalIndex i) {
          double v = rhs(i);
          for (Offset k = aro(i); k < aro(i + 1); ++k) {
            const int q = rowOf(aco(k));
            if (q >= 0)
              v -= ava(k) * offset(q);
          }
          return v;
        };
        out(j) = transposeAt(rr.t, j, shifted);
      });
  Kokkos::deep_copy(rhs, out);
  return r;
}

void expandConstrained(const DeviceMultiPointConstraints &t,
                       const Kokkos::View<double *, Memory> &x) {
  if (t.empty())
    return;
  Kokkos::View<double *, Memory> y("mixcon::mpc::reduced", x.extent(0));
  Kokkos::deep_copy(y, x);
  const auto rows = t.rows;
  const auto rowStart = t.rowStart;
  const auto columns = t.columns;
  const auto values = t.values;
  const auto offset = t.offset;
  Kokkos::parallel_for(
      "mixcon::mpc::expand", Policy(0, t.numRows()), KOKKOS_LAMBDA(LocalIndex r) {
        double v = offset(r);
        for (Offset e = rowStart(r); e < rowStart(r + 1); ++e)
          v += values(e) * y(columns(e));
        x(rows(r)) = v;
      });
}

void condenseVector(const DeviceMultiPointConstraints &t, const Kokkos::View<double *, Memory> &v) {
  Kokkos::View<double *, Memory> w("mixcon::mpc::uncondensed", v.extent(0));
  Kokkos::deep_copy(w, v);
  const MultiPointView<Memory> tc = t.view();
  Kokkos::parallel_for(
      "mixcon::mpc::condense", Policy(0, static_cast<LocalIndex>(v.extent(0))),
      KOKKOS_LAMBDA(LocalIndex j) {
        v(j) = transposeAt(tc, j, [&](LocalIndex i) { return w(i); });
      });
}

double condensedFreeNorm(const DeviceMultiPointConstraints &t,
                         const Kokkos::View<const double *, Memory> &g,
                         const Kokkos::View<const int *, Memory> &flags, int stride) {
  const MultiPointView<Memory> tc = t.view();
  double sum = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::mpc::condensedFreeNorm", Policy(0, static_cast<LocalIndex>(g.extent(0))),
      KOKKOS_LAMBDA(LocalIndex j, double &acc) {
        if (j % stride >= 2 || flags(j))
          return;
        const double v = transposeAt(tc, j, [&](LocalIndex i) { return g(i); });
        acc += v * v;
      },
      sum);
  return std::sqrt(sum);
}

} // namespace mixcon
