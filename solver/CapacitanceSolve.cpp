// The capacitance form of a constrained solve on a kept factorization (CapacitanceSolve.hpp).
// Layer: solver.
#include <solver/CapacitanceSolve.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/HostAlgebra.hpp>
#include <solver/Krylov.hpp>

#include <kernels/SparseMatrix.hpp>

#include <core/Transfer.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mixcon {

namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Policy = Kokkos::RangePolicy<Exec>;

/// A device copy of a host list (O(conditions), uploaded once per correction).
template <class T>
Kokkos::View<T *, DeviceSpace> upload(const std::vector<T> &list, const char *label) {
  Kokkos::View<T *, DeviceSpace> d(std::string(label), list.size());
  copyToDevice(d, list);
  return d;
}

/// Moves the entries of `rows` at base unknowns (prescribed in every correction, x_u = value_u)
/// to the conditions' right-hand sides; drops conditions left empty. False for such a condition
/// that the base values do not satisfy (inconsistent constraints: left to the elimination).
bool withoutBaseEntries(const Kokkos::View<const int *, DeviceSpace> &base,
                        const Kokkos::View<const double *, DeviceSpace> &values,
                        std::vector<LinearCondition> &rows) {
  std::vector<LocalIndex> unknowns;
  for (const LinearCondition &r : rows)
    for (const auto &e : r.entries)
      unknowns.push_back(e.first);
  std::sort(unknowns.begin(), unknowns.end());
  unknowns.erase(std::unique(unknowns.begin(), unknowns.end()), unknowns.end());
  const std::size_t t = unknowns.size();
  const auto du = upload(unknowns, "mixcon::capacitance::entryUnknowns");
  Kokkos::View<double *[2], DeviceSpace> dv("mixcon::capacitance::entryBase", t);
  Kokkos::parallel_for(
      "mixcon::capacitance::gatherBase", Policy(0, static_cast<LocalIndex>(t)),
      KOKKOS_LAMBDA(LocalIndex q) {
        dv(q, 0) = base(du(q)) != 0 ? 1.0 : 0.0;
        dv(q, 1) = values(du(q));
      });
  const auto hv = copyToHost(dv);
  std::vector<LinearCondition> kept;
  for (LinearCondition &r : rows) {
    double scale = std::abs(r.value);
    LinearCondition out;
    out.value = r.value;
    for (const auto &e : r.entries) {
      const auto q = static_cast<std::size_t>(
          std::lower_bound(unknowns.begin(), unknowns.end(), e.first) - unknowns.begin());
      scale = std::max(scale, std::abs(e.second * hv(q, 1)));
      if (hv(q, 0) != 0.0)
        out.value -= e.second * hv(q, 1);
      else if (e.second != 0.0)
        out.entries.push_back(e);
    }
    if (!out.entries.empty())
      kept.push_back(std::move(out));
    else if (std::abs(out.value) > 1e-12 * scale)
      return false;
  }
  rows = std::move(kept);
  return true;
}

/// Entries where two arrays differ (exactly).
int differences(const Kokkos::View<const double *, DeviceSpace> &a,
                const Kokkos::View<const double *, DeviceSpace> &b) {
  int count = 0;
  Kokkos::parallel_reduce(
      "mixcon::capacitance::sameValues", Policy(0, static_cast<Offset>(a.extent(0))),
      KOKKOS_LAMBDA(Offset k, int &acc) { acc += a(k) != b(k) ? 1 : 0; }, count);
  return count;
}

/// Entries where two flag arrays differ (set or not).
int flagDifferences(const Kokkos::View<const int *, DeviceSpace> &a,
                    const Kokkos::View<const int *, DeviceSpace> &b) {
  int count = 0;
  Kokkos::parallel_reduce(
      "mixcon::capacitance::sameFlags", Policy(0, static_cast<LocalIndex>(a.extent(0))),
      KOKKOS_LAMBDA(LocalIndex i, int &acc) { acc += (a(i) != 0) != (b(i) != 0) ? 1 : 0; }, count);
  return count;
}

/// ||A||_inf on the device.
double rowSumNorm(const CsrMatrix<DeviceSpace> &a) {
  const auto ro = a.rowOffsets;
  const auto va = a.values;
  double norm = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::capacitance::rowSumNorm", Policy(0, a.numRows),
      KOKKOS_LAMBDA(LocalIndex i, double &m) {
        double sum = 0.0;
        for (Offset k = ro(i); k < ro(i + 1); ++k)
          sum += detail::fabs(va(k));
        m = sum > m ? sum : m;
      },
      Kokkos::Max<double>(norm));
  return norm;
}

/// max(||b - A x - C^T lambda|| / sqrt(||b||^2 + ||C^T lambda||^2) over the free rows, the
/// largest |c_k . x - d_k| relative to |d_k| + sum_e |c_ke| u), C^T lambda given as `mu` at
/// `unknowns` (sorted), u the larger of max|x| and ||b|| / ||A||_inf (`normInf`); `force` and
/// `product` are scratch vectors of A's size.
double constrainedResidual(const CsrMatrix<DeviceSpace> &a,
                           const Kokkos::View<const int *, DeviceSpace> &base,
                           const Kokkos::View<const double *, DeviceSpace> &b,
                           const Kokkos::View<const double *, DeviceSpace> &x,
                           const std::vector<LocalIndex> &unknowns, const std::vector<double> &mu,
                           const std::vector<LinearCondition> &rows, double normInf,
                           const Kokkos::View<double *, DeviceSpace> &force,
                           const Kokkos::View<double *, DeviceSpace> &product) {
  const LocalIndex n = a.numRows;
  // C^T lambda (at the touched unknowns) and x there, through one small upload and copy.
  const std::size_t t = unknowns.size();
  const auto du = upload(unknowns, "mixcon::capacitance::residualUnknowns");
  const auto dm = upload(mu, "mixcon::capacitance::multipliers");
  const auto f = force;
  Kokkos::deep_copy(f, 0.0);
  Kokkos::parallel_for(
      "mixcon::capacitance::scatterMultipliers", Policy(0, static_cast<LocalIndex>(t)),
      KOKKOS_LAMBDA(LocalIndex q) {
        f(du(q)) = dm(q);
        dm(q) = x(du(q));
      });
  const auto hx = copyToHost(dm);
  multiply(Exec(), a, x, product);
  const auto ax = product;
  double r2 = 0.0, b2 = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::capacitance::residual", Policy(0, n),
      KOKKOS_LAMBDA(LocalIndex i, double &rr, double &bb) {
        if (base(i))
          return;
        const double r = b(i) - ax(i) - f(i);
        rr += r * r;
        bb += b(i) * b(i) + f(i) * f(i);
      },
      r2, b2);
  // The conditions, relative to |d_k| + sum_e |c_ke| u, u the larger of max|x| and the
  // displacement scale ||b|| / ||A|| of the correction (near convergence x is round-off).
  double xmax = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::capacitance::largestUnknown", Policy(0, n),
      KOKKOS_LAMBDA(LocalIndex i, double &m) {
        const double v = detail::fabs(x(i));
        m = v > m ? v : m;
      },
      Kokkos::Max<double>(xmax));
  xmax = std::max(xmax, normInf > 0.0 ? std::sqrt(b2) / normInf : 0.0);
  double worst = 0.0;
  for (const LinearCondition &r : rows) {
    double cx = 0.0, scale = std::abs(r.value);
    for (const auto &e : r.entries) {
      const auto q = static_cast<std::size_t>(
          std::lower_bound(unknowns.begin(), unknowns.end(), e.first) - unknowns.begin());
      cx += e.second * hx(q);
      scale += std::abs(e.second) * xmax;
    }
    if (scale > 0.0)
      worst = std::max(worst, std::abs(cx - r.value) / scale);
  }
  return std::max(b2 > 0.0 ? std::sqrt(r2 / b2) : std::sqrt(r2), worst);
}

} // namespace

bool CapacitanceSolve::sameMatrix(const CsrMatrix<DeviceSpace> &a,
                                  const Kokkos::View<const int *, DeviceSpace> &base) const {
  return a.rowOffsets.data() == rowOffsets_ && a.columns.data() == columns_ &&
         values_.extent(0) == a.values.extent(0) && base_.extent(0) == base.extent(0) &&
         differences(a.values, values_) == 0 && flagDifferences(base, base_) == 0;
}

void CapacitanceSolve::record(const CsrMatrix<DeviceSpace> &a,
                              const Kokkos::View<const int *, DeviceSpace> &base) {
  rowOffsets_ = a.rowOffsets.data();
  columns_ = a.columns.data();
  if (values_.extent(0) != a.values.extent(0))
    values_ =
        Kokkos::View<double *, DeviceSpace>("mixcon::capacitance::values", a.values.extent(0));
  Kokkos::deep_copy(values_, a.values);
  if (base_.extent(0) != base.extent(0))
    base_ = Kokkos::View<int *, DeviceSpace>("mixcon::capacitance::base", base.extent(0));
  Kokkos::deep_copy(base_, base);
  factored_ = false; // nothing factorized for it yet
  declined_ = false;
  normInf_ = rowSumNorm(a); // the scale of the conditions' residual
}

bool CapacitanceSolve::factorize(const ConstraintSet &c,
                                 const Kokkos::View<const int *, DeviceSpace> &base,
                                 const CsrMatrix<DeviceSpace> &a, const LinearSolver &solver) {
  if (!own_)
    own_ = solver.another();
  if (!own_)
    return false;
  // A0: A with the base rows and columns eliminated (the solver keeps its own copy).
  CsrMatrix<DeviceSpace> a0;
  detail::copyMatrix(a, a0);
  Kokkos::View<double *, DeviceSpace> scratch("mixcon::capacitance::scratch", a.numRows);
  applyDirichlet(Exec(), a0, base, c.values, scratch);
  Exec().fence();
  columnOf_.assign(static_cast<std::size_t>(a.numRows), -1);
  unknownOf_.clear();
  try {
    own_->setup(a0);
  } catch (const std::runtime_error &) {
    return false; // A0 singular to working precision
  }
  factored_ = true;
  ++factorizations_;
  return true;
}

int CapacitanceSolve::column(LocalIndex u, LinearSolveStats &stats) {
  int &col = columnOf_[static_cast<std::size_t>(u)];
  if (col >= 0)
    return col;
  col = static_cast<int>(unknownOf_.size());
  if (static_cast<std::size_t>(col) == w_.size())
    w_.emplace_back("mixcon::capacitance::column", columnOf_.size());
  const auto w = w_[static_cast<std::size_t>(col)];
  Kokkos::View<double *, DeviceSpace> e("mixcon::capacitance::unit", columnOf_.size());
  Kokkos::deep_copy(Kokkos::subview(e, u), 1.0);
  const LinearSolveStats s = own_->solve(e, w);
  stats.solveSeconds += s.solveSeconds;
  stats.converged = stats.converged && s.converged;
  unknownOf_.push_back(u);
  return col;
}

bool CapacitanceSolve::solve(const ConstraintSet &c,
                             const Kokkos::View<const int *, DeviceSpace> &base,
                             const CsrMatrix<DeviceSpace> &a,
                             const Kokkos::View<double *, DeviceSpace> &b,
                             const LinearSolver &solver,
                             const Kokkos::View<double *, DeviceSpace> &x, LinearSolveStats &stats,
                             double *setupSeconds) {
  if (!solver.keepsFactorization() || base.extent(0) != c.flags.extent(0) ||
      (c.hasMultipoint() && !c.conditions))
    return false;
  // A matrix seen for the first time is left to the elimination (a Newton tangent that changes
  // in every correction costs only this copy and comparison); once the same matrix comes
  // again, the method applies.
  if (!sameMatrix(a, base)) {
    record(a, base);
    return false;
  }
  if (declined_)
    return false; // this matrix failed the method once (a singular A0: a body held by contact)
  const auto start = std::chrono::steady_clock::now();
  const LocalIndex n = a.numRows;
  const int stride = c.stride;
  // The changing conditions: prescribed unknowns the base does not hold, compacted on the
  // device, then the multipoint rows' conditions.
  const auto flags = c.flags;
  LocalIndex m = 0;
  Kokkos::parallel_reduce(
      "mixcon::capacitance::countConditions", Policy(0, n),
      KOKKOS_LAMBDA(LocalIndex i, LocalIndex & acc) {
        acc += flags(i) != 0 && base(i) == 0 ? 1 : 0;
      },
      m);
  const std::size_t given = c.hasMultipoint() ? c.conditions->size() : 0;
  if (static_cast<std::size_t>(m) + given > static_cast<std::size_t>(kMaxConditions))
    return false;
  Kokkos::View<LocalIndex *, DeviceSpace> index("mixcon::capacitance::conditions", m);
  Kokkos::View<double *[4], DeviceSpace> data("mixcon::capacitance::conditionData", m);
  const auto values = c.values;
  const auto framed = c.framed;
  const auto normal = c.normal;
  const bool frames = c.hasFrames();
  Kokkos::parallel_scan(
      "mixcon::capacitance::gatherConditions", Policy(0, n),
      KOKKOS_LAMBDA(LocalIndex i, LocalIndex & k, bool last) {
        if (flags(i) == 0 || base(i) != 0)
          return;
        if (last) {
          const LocalIndex p = i / stride;
          index(k) = i;
          data(k, 0) = values(i);
          data(k, 1) = frames && framed(p) ? 1.0 : 0.0;
          data(k, 2) = frames ? normal(p, 0) : 0.0;
          data(k, 3) = frames ? normal(p, 1) : 0.0;
        }
        ++k;
      });
  const auto hi = copyToHost(index);
  const auto hd = copyToHost(data);
  std::vector<LinearCondition> rows(static_cast<std::size_t>(m));
  for (LocalIndex k = 0; k < m; ++k) {
    const LocalIndex i = hi(k), i0 = i - i % stride;
    const int comp = i % stride;
    LinearCondition &r = rows[static_cast<std::size_t>(k)];
    r.value = hd(k, 0);
    if (hd(k, 1) == 0.0) { // a global component
      r.entries = {{i, 1.0}};
      continue;
    }
    if (comp > 1)
      return false; // local frames turn only the displacement pair
    const double nx = hd(k, 2), ny = hd(k, 3);
    // The normal n, or the tangent t = (-n_y, n_x), of the node's frame.
    r.entries = {{i0, comp == 0 ? nx : -ny}, {i0 + 1, comp == 0 ? ny : nx}};
  }
  if (given > 0)
    rows.insert(rows.end(), c.conditions->begin(), c.conditions->end());
  if (!withoutBaseEntries(base, values, rows))
    return false;

  // The unknowns the conditions touch: each needs its column A0^-1 e_u.
  std::vector<LocalIndex> touched; // entry q of condition k: q in [first k, first k+1)
  std::vector<std::size_t> first(rows.size() + 1, 0);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    for (const auto &e : rows[k].entries)
      touched.push_back(e.first);
    first[k + 1] = touched.size();
  }
  std::vector<LocalIndex> distinct = touched;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  // The kept columns: at most kMaxColumns, and at most 32 Mi values (256 MB) in all.
  const std::size_t maxColumns = std::min<std::size_t>(
      kMaxColumns, std::max<std::size_t>(16, (std::size_t{1} << 25) / std::max(n, 1)));
  if (distinct.size() > maxColumns)
    return false;

  // A0 factorized (or its factorization kept while A, the base flags and the solver's
  // factorization stay).
  if (!factored_ && !factorize(c, base, a, solver)) {
    declined_ = true; // A0 singular (a body held only by contact), or no solver of the kind
    own_.reset();
    return false;
  }
  std::size_t missing = 0;
  for (LocalIndex u : distinct)
    missing += columnOf_[static_cast<std::size_t>(u)] < 0 ? 1 : 0;
  if (unknownOf_.size() + missing > maxColumns) {
    columnOf_.assign(columnOf_.size(), -1); // start afresh with the columns needed now
    unknownOf_.clear();
  }
  LinearSolveStats s;
  s.converged = true;
  for (LocalIndex u : distinct)
    column(u, s);
  if (setupSeconds)
    *setupSeconds += fieldops::seconds(start);

  // y = A0^-1 b0, b0 the right-hand side lifted by the base values (b itself is kept until the
  // method is known to apply).
  if (lifted_.extent(0) != b.extent(0))
    lifted_ = Kokkos::View<double *, DeviceSpace>("mixcon::capacitance::rhs", b.extent(0));
  Kokkos::deep_copy(lifted_, b);
  liftDirichlet(Exec(), a, base, c.values, lifted_);
  const LinearSolveStats sy = own_->solve(lifted_, x);
  s.solveSeconds += sy.solveSeconds;
  s.relativeResidual = sy.relativeResidual;
  s.converged = s.converged && sy.converged;
  s.iterations = 1;

  if (!rows.empty()) {
    // y and the columns at the touched unknowns, gathered on the device, copied once:
    // g(q, 0) = y(touched q), g(q, 1 + p) = (A0^-1 e_{touched p})(touched q).
    const std::size_t t = touched.size();
    const auto dt = upload(touched, "mixcon::capacitance::touched");
    Kokkos::View<double **, Kokkos::LayoutLeft, DeviceSpace> g("mixcon::capacitance::gathered", t,
                                                               t + 1);
    const Kokkos::View<const double *, DeviceSpace> y = x;
    Kokkos::parallel_for(
        "mixcon::capacitance::gatherSolution", Policy(0, static_cast<LocalIndex>(t)),
        KOKKOS_LAMBDA(LocalIndex q) { g(q, 0) = y(dt(q)); });
    for (std::size_t p = 0; p < t; ++p) {
      const auto w = w_[static_cast<std::size_t>(columnOf_[static_cast<std::size_t>(touched[p])])];
      const auto gp = Kokkos::subview(g, Kokkos::ALL, p + 1);
      Kokkos::parallel_for(
          "mixcon::capacitance::gatherColumn", Policy(0, static_cast<LocalIndex>(t)),
          KOKKOS_LAMBDA(LocalIndex q) { gp(q) = w(dt(q)); });
    }
    const auto hg = copyToHost(g);
    // S = C A0^-1 C^T and C y - d.
    const std::size_t mm = rows.size();
    const auto coefficient = [&](std::size_t k, std::size_t q) {
      return rows[k].entries[q - first[k]].second;
    };
    std::vector<double> cap(mm * mm, 0.0), rhs(mm, 0.0), lambda;
    for (std::size_t k = 0; k < mm; ++k) {
      for (std::size_t q = first[k]; q < first[k + 1]; ++q)
        rhs[k] += coefficient(k, q) * hg(q, 0);
      rhs[k] -= rows[k].value;
      for (std::size_t l = 0; l < mm; ++l)
        for (std::size_t q = first[k]; q < first[k + 1]; ++q)
          for (std::size_t p = first[l]; p < first[l + 1]; ++p)
            cap[mm * k + l] += coefficient(k, q) * coefficient(l, p) * hg(q, 1 + p);
    }
    if (!solveSmallDense(cap, mm, rhs, lambda, 1e-12)) {
      declined_ = true; // S singular: A0 singular (a body held by contact) or dependent rows
      own_.reset();
      return false;
    }
    // x = y - A0^-1 C^T lambda = y - sum_u mu_u A0^-1 e_u, mu = C^T lambda.
    std::vector<double> mu(distinct.size(), 0.0);
    const auto slot = [&](LocalIndex u) {
      return static_cast<std::size_t>(std::lower_bound(distinct.begin(), distinct.end(), u) -
                                      distinct.begin());
    };
    for (std::size_t k = 0; k < mm; ++k)
      for (std::size_t q = first[k]; q < first[k + 1]; ++q)
        mu[slot(touched[q])] += lambda[k] * coefficient(k, q);
    for (std::size_t j = 0; j < distinct.size(); ++j) {
      const int col = columnOf_[static_cast<std::size_t>(distinct[j])];
      axpby(-mu[j], Kokkos::View<const double *, DeviceSpace>(w_[static_cast<std::size_t>(col)]),
            1.0, x);
    }
    // The true residual of the constrained system: b - A x - C^T lambda on the free rows and
    // C x - d. A nearly singular A0 gives columns too large to combine accurately: declined.
    if (force_.extent(0) != static_cast<std::size_t>(n)) {
      force_ = Kokkos::View<double *, DeviceSpace>("mixcon::capacitance::force", n);
      product_ = Kokkos::View<double *, DeviceSpace>("mixcon::capacitance::product", n);
    }
    s.relativeResidual =
        constrainedResidual(a, base, b, x, distinct, mu, rows, normInf_, force_, product_);
    if (!(s.relativeResidual <= kResidualBound)) {
      declined_ = true;
      own_.reset();
      return false;
    }
  }
  ++solves_;
  stats = s;
  return true;
}

} // namespace mixcon
