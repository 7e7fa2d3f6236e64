// SparseDirect: CHOLMOD and UMFPACK (SuiteSparse) behind solver/SparseDirect.hpp.
#include <solver/SparseDirect.hpp>

#include <cholmod.h>
#include <dlfcn.h>
#include <umfpack.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

namespace mixcon {

namespace {
using Long = SuiteSparse_long;

/// OpenBLAS's own threads held to one while SuiteSparse runs, then given back. mixcon links
/// whichever libblas.so.3 Debian's alternatives name, and they prefer OpenBLAS's pthread
/// (priority 100) and OpenMP (95) builds to the serial one (90) cmake/install-deps.sh installs:
/// a machine where another package brought one of them gives CHOLMOD and UMFPACK a threaded
/// BLAS, which starts its threads for every dense update of a front or supernode beside
/// mixcon's OpenMP threads. A safeguard: measured (docs/performance.md, issue 20, section 7a)
/// within the noise for the pthread build, 10-15 % for the OpenMP build beside another run. The
/// calls are looked up at run time (absent: another BLAS, nothing done). OpenBLAS's OpenMP build
/// takes its count from omp_set_num_threads, which openblas_set_num_threads calls: the
/// caller's OpenMP count is restored as well.
class SequentialBlas {
public:
  SequentialBlas() {
    const Api &api = blas();
    if (!api.get || !api.set)
      return;
    saved_ = api.get();
    if (saved_ > 1) {
#ifdef _OPENMP
      openmp_ = omp_get_max_threads();
#endif
      api.set(1);
    }
  }
  ~SequentialBlas() {
    if (saved_ > 1) {
      blas().set(saved_);
#ifdef _OPENMP
      omp_set_num_threads(openmp_);
#endif
    }
  }
  SequentialBlas(const SequentialBlas &) = delete;
  SequentialBlas &operator=(const SequentialBlas &) = delete;

  struct Api {
    int (*get)() = nullptr;
    void (*set)(int) = nullptr;
  };
  static const Api &blas() {
    static const Api api = [] {
      Api a;
      a.get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
      a.set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
      return a;
    }();
    return api;
  }

private:
  int saved_ = 0;
  int openmp_ = 1;
};
} // namespace

/// The matrix as compressed rows, kept for the solves (UMFPACK's iterative refinement reads it)
/// and the residual. Compressed rows of A are compressed columns of A^T: CHOLMOD reads one
/// triangle of them (A symmetric), UMFPACK factors A^T and solves with its transpose.
struct SparseDirect::Impl {
  std::vector<Long> rows, columns; ///< columns sorted within each row (UMFPACK needs them so)
  std::vector<double> values;
  std::vector<Offset> order; ///< values[k] = the given values[order[k]]
  Long n = 0;
  bool analyzed = false; ///< the kept analysis belongs to this method and pattern

  cholmod_common common{};
  cholmod_factor *factor = nullptr;
  cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr; ///< solve2's workspace

  double control[UMFPACK_CONTROL] = {};
  double info[UMFPACK_INFO] = {};
  void *symbolic = nullptr, *numeric = nullptr;
  std::vector<Long> wi; ///< wsolve's workspace
  std::vector<double> w;

  Impl() {
    cholmod_l_start(&common);
    common.print = 0;                      // outcomes are reported through the status, not printed
    common.quick_return_if_not_posdef = 1; // the caller turns to the LU then
    // LL' also for the simplicial factors CHOLMOD picks for small or very sparse matrices: their
    // default LDL' accepts negative pivots, so an indefinite matrix would pass unnoticed.
    common.final_ll = 1;
    umfpack_dl_defaults(control);
    control[UMFPACK_PRL] = 0;
    // No iterative refinement inside the solve: the direct solver refines on the true
    // residual where the tolerance asks for it (solver/LinearSolver.cpp). UMFPACK's two steps
    // by default cost 20 % of the Hex20 cantilever's run above (8.4 s against 6.8 s).
    control[UMFPACK_IRSTEP] = 0;
  }
  ~Impl() {
    release();
    cholmod_l_finish(&common);
  }
  void release() {
    cholmod_l_free_factor(&factor, &common);
    cholmod_l_free_dense(&x, &common);
    cholmod_l_free_dense(&y, &common);
    cholmod_l_free_dense(&e, &common);
    if (symbolic)
      umfpack_dl_free_symbolic(&symbolic);
    if (numeric)
      umfpack_dl_free_numeric(&numeric);
    analyzed = false;
  }
  cholmod_sparse view() {
    cholmod_sparse a{};
    a.nrow = a.ncol = static_cast<std::size_t>(n);
    a.nzmax = values.size();
    a.p = rows.data();
    a.i = columns.data();
    a.x = values.data();
    a.stype = 1; // symmetric, one triangle read
    a.itype = CHOLMOD_LONG;
    a.xtype = CHOLMOD_REAL;
    a.dtype = CHOLMOD_DOUBLE;
    a.sorted = 1;
    a.packed = 1;
    return a;
  }
};

SparseDirect::SparseDirect() : impl_(std::make_unique<Impl>()) {}
SparseDirect::~SparseDirect() = default;

const char *SparseDirect::name(Method method) {
  return method == Method::Cholesky ? "CHOLMOD Cholesky" : "UMFPACK LU";
}

bool SparseDirect::isSymmetric(const HostCsr &a, double relative, double absolute) {
  const std::int64_t n = a.size;
  std::vector<char> sorted(static_cast<std::size_t>(n), 1);
  for (std::int64_t i = 0; i < n; ++i)
    for (Offset k = a.rowOffsets[i] + 1; k < a.rowOffsets[i + 1] && sorted[i]; ++k)
      sorted[i] = a.columns[k - 1] < a.columns[k];
  const auto find = [&](std::int64_t row, LocalIndex column) { // a(row, column), 0 if absent
    const LocalIndex *first = a.columns + a.rowOffsets[row];
    const LocalIndex *last = a.columns + a.rowOffsets[row + 1];
    const LocalIndex *it =
        sorted[row] ? std::lower_bound(first, last, column) : std::find(first, last, column);
    return it != last && *it == column ? a.values[it - a.columns] : 0.0;
  };
  for (std::int64_t i = 0; i < n; ++i)
    for (Offset k = a.rowOffsets[i]; k < a.rowOffsets[i + 1]; ++k) {
      const LocalIndex j = a.columns[k];
      if (j <= i)
        continue; // each pair once, from its entry above the diagonal
      const double aij = a.values[k], aji = find(j, static_cast<LocalIndex>(i));
      const double d = std::fabs(aij - aji);
      if (d > absolute && d > relative * std::max(std::fabs(aij), std::fabs(aji)))
        return false;
    }
  for (std::int64_t i = 0; i < n; ++i) // entries below it whose partner above is absent
    for (Offset k = a.rowOffsets[i]; k < a.rowOffsets[i + 1]; ++k) {
      const LocalIndex j = a.columns[k];
      if (j < i && std::fabs(a.values[k]) > absolute && find(j, static_cast<LocalIndex>(i)) == 0.0)
        return false;
    }
  return true;
}

SparseDirect::Estimate SparseDirect::estimateCholesky(const HostCsr &a) {
  // CHOLMOD reads compressed columns; a symmetric pattern's rows are its columns. Unsorted
  // columns are allowed for the analysis (sorted = 0).
  std::vector<Long> p(a.rowOffsets, a.rowOffsets + a.size + 1);
  std::vector<Long> i(a.columns, a.columns + (a.size > 0 ? a.rowOffsets[a.size] : 0));
  cholmod_sparse view{};
  view.nrow = view.ncol = static_cast<std::size_t>(a.size);
  view.nzmax = i.size();
  view.p = p.data();
  view.i = i.data();
  view.stype = 1;
  view.itype = CHOLMOD_LONG;
  view.xtype = CHOLMOD_PATTERN;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 0;
  view.packed = 1;
  cholmod_common common{};
  cholmod_l_start(&common);
  common.print = 0;
  // AMD alone: CHOLMOD's default would also try METIS on large 3D patterns (2.8 s on a Hex20
  // cube of 181,875 unknowns against 0.9 s); AMD's fill is the larger, so the estimate errs
  // towards a dearer factorization.
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_AMD;
  common.postorder = 1;
  common.supernodal = CHOLMOD_SIMPLICIAL; // the counts need no supernodal symbolic factor
  cholmod_factor *f = cholmod_l_analyze(&view, &common);
  const Estimate e{common.fl, common.lnz};
  const int status = common.status;
  const bool ok = f != nullptr && status >= CHOLMOD_OK;
  cholmod_l_free_factor(&f, &common);
  cholmod_l_finish(&common);
  if (!ok)
    throw std::runtime_error("CHOLMOD: the analysis failed (status " + std::to_string(status) +
                             ", out of memory?)");
  return e;
}

bool SparseDirect::controlsBlasThreads() {
  return SequentialBlas::blas().get && SequentialBlas::blas().set;
}

SparseDirect::Outcome SparseDirect::factor(Method method, const HostCsr &a) {
  const SequentialBlas sequential;
  Impl &m = *impl_;
  const Long nnz = a.size > 0 ? static_cast<Long>(a.rowOffsets[a.size]) : 0;
  bool same =
      m.analyzed && method == method_ && m.n == a.size && static_cast<Long>(m.values.size()) == nnz;
  for (Long i = 0; same && i <= a.size; ++i)
    same = m.rows[i] == static_cast<Long>(a.rowOffsets[i]);
  for (Long k = 0; same && k < nnz; ++k)
    same = m.columns[k] == static_cast<Long>(a.columns[m.order[k]]);
  if (!same) {
    m.release();
    m.n = a.size;
    m.rows.assign(a.rowOffsets, a.rowOffsets + a.size + 1);
    m.order.resize(static_cast<std::size_t>(nnz));
    m.columns.resize(static_cast<std::size_t>(nnz));
    for (Long i = 0; i < m.n; ++i) {
      const auto first = m.order.begin() + m.rows[i], last = m.order.begin() + m.rows[i + 1];
      std::iota(first, last, static_cast<Offset>(m.rows[i]));
      std::sort(first, last, [&](Offset p, Offset q) { return a.columns[p] < a.columns[q]; });
    }
    for (Long k = 0; k < nnz; ++k)
      m.columns[k] = a.columns[m.order[k]];
  } else {
    ++reuses_;
  }
  m.values.resize(static_cast<std::size_t>(nnz));
  for (Long k = 0; k < nnz; ++k)
    m.values[k] = a.values[m.order[k]];
  method_ = method;

  if (method == Method::Cholesky) {
    cholmod_sparse view = m.view();
    if (!same) {
      m.factor = cholmod_l_analyze(&view, &m.common);
      if (!m.factor)
        throw std::runtime_error("CHOLMOD: the analysis failed (status " +
                                 std::to_string(m.common.status) + ", out of memory?)");
      m.analyzed = true;
    }
    cholmod_l_factorize(&view, m.factor, &m.common);
    if (m.common.status == CHOLMOD_NOT_POSDEF)
      return Outcome::NotPositiveDefinite;
    // Should a simplicial LDL' be left all the same: its D (the first entry of each column of
    // L) must be positive.
    if (m.common.status >= CHOLMOD_OK && !m.factor->is_ll && !m.factor->is_super) {
      const auto *p = static_cast<const Long *>(m.factor->p);
      const auto *d = static_cast<const double *>(m.factor->x);
      for (Long j = 0; j < m.n; ++j)
        if (!(d[p[j]] > 0.0))
          return Outcome::NotPositiveDefinite;
    }
    if (m.common.status < CHOLMOD_OK)
      throw std::runtime_error("CHOLMOD: the factorization failed (status " +
                               std::to_string(m.common.status) + ", out of memory?)");
    return Outcome::Factored;
  }
  if (!same) {
    // Both of UMFPACK's strategies are analysed and the one with fewer estimated flops kept:
    // neither is right for every matrix here, nor is UMFPACK's own choice (by the share of
    // nonzero diagonal entries). Measured (flops of the numeric factorization): the 3D mixed
    // Jacobian with a = 0 (Hex20 cantilever, 4,392 unknowns, many zero diagonal entries):
    // unsymmetric (UMFPACK's choice) 18 GFlop, 3.4 s; symmetric 0.19 GFlop, 0.16 s. The 2D
    // mixed Jacobian in contact (wood plate, 6,050 unknowns): symmetric 1.9-2.9 GFlop, 0.5-0.7
    // s; unsymmetric 0.33-0.45 GFlop, 0.12-0.2 s. The estimates rank them the same way (24.8
    // against 0.26 GFlop, 0.63 against 4.9).
    // The same for the fill-reducing ordering: each strategy is analysed with UMFPACK's AMD
    // (COLAMD for the unsymmetric strategy) and with METIS (on A + A^T, or on A^T A for the
    // unsymmetric strategy). Measured, numeric factorization with the ordering chosen against
    // AMD/COLAMD alone (the unsymmetric strategy in each case): the wood plate's 2D mixed
    // Jacobian in contact (6,050 unknowns) 0.25-0.32 against 0.33-0.45 GFlop; the 3D mixed Hex8
    // matrix of a 6^3 cube (3,087 unknowns) 1.1 against 3.5 GFlop, 0.19 against 0.31 s. The two
    // METIS analyses cost time (0.27 s on that cube, 2.6 s on the 12^3 cube's 19,773 unknowns),
    // paid once per pattern: on the 12^3 cube one factorization with its analyses took 9.1 s
    // against 10.4 s; examples/wood_plate_study.py 126.3 s against 158.8 s (docs/performance.md
    // section 7b). Should a SuiteSparse without METIS refuse those two analyses, they are skipped.
    double best = std::numeric_limits<double>::infinity();
    for (const auto &[strategy, ordering] :
         {std::pair{UMFPACK_STRATEGY_SYMMETRIC, UMFPACK_ORDERING_AMD},
          std::pair{UMFPACK_STRATEGY_SYMMETRIC, UMFPACK_ORDERING_METIS},
          std::pair{UMFPACK_STRATEGY_UNSYMMETRIC, UMFPACK_ORDERING_AMD},
          std::pair{UMFPACK_STRATEGY_UNSYMMETRIC, UMFPACK_ORDERING_METIS}}) {
      double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
      std::copy(m.control, m.control + UMFPACK_CONTROL, control);
      control[UMFPACK_STRATEGY] = strategy;
      control[UMFPACK_ORDERING] = ordering;
      void *symbolic = nullptr;
      const Long status = umfpack_dl_symbolic(m.n, m.n, m.rows.data(), m.columns.data(),
                                              m.values.data(), &symbolic, control, info);
      if (status != UMFPACK_OK) {
        if (symbolic)
          umfpack_dl_free_symbolic(&symbolic);
        if (ordering == UMFPACK_ORDERING_METIS)
          continue; // METIS is optional in SuiteSparse; AMD/COLAMD stays
        throw std::runtime_error("UMFPACK: the analysis failed (status " + std::to_string(status) +
                                 ")");
      }
      if (info[UMFPACK_FLOPS_ESTIMATE] < best) {
        best = info[UMFPACK_FLOPS_ESTIMATE];
        if (m.symbolic)
          umfpack_dl_free_symbolic(&m.symbolic);
        m.symbolic = symbolic;
        m.control[UMFPACK_STRATEGY] = strategy;
        m.control[UMFPACK_ORDERING] = ordering;
      } else {
        umfpack_dl_free_symbolic(&symbolic);
      }
    }
    m.analyzed = true;
    m.wi.assign(static_cast<std::size_t>(m.n), 0);
    m.w.assign(static_cast<std::size_t>(5 * m.n), 0.0);
  }
  if (m.numeric)
    umfpack_dl_free_numeric(&m.numeric);
  const Long status = umfpack_dl_numeric(m.rows.data(), m.columns.data(), m.values.data(),
                                         m.symbolic, &m.numeric, m.control, m.info);
  if (status == UMFPACK_WARNING_singular_matrix)
    return Outcome::Singular;
  if (status != UMFPACK_OK)
    throw std::runtime_error("UMFPACK: the factorization failed (status " + std::to_string(status) +
                             ", out of memory?)");
  return Outcome::Factored;
}

void SparseDirect::solve(const double *b, double *x) const {
  const SequentialBlas sequential;
  Impl &m = *impl_;
  if (method_ == Method::Lu) {
    // The matrix UMFPACK holds is A^T: its transposed solve is A x = b.
    const Long status =
        umfpack_dl_wsolve(UMFPACK_At, m.rows.data(), m.columns.data(), m.values.data(), x, b,
                          m.numeric, m.control, m.info, m.wi.data(), m.w.data());
    // A singular factor still solves (with infinities the caller's residual check sees).
    if (status != UMFPACK_OK && status != UMFPACK_WARNING_singular_matrix)
      throw std::runtime_error("UMFPACK: the solve failed (status " + std::to_string(status) + ")");
    return;
  }
  cholmod_dense rhs{};
  rhs.nrow = rhs.d = static_cast<std::size_t>(m.n);
  rhs.ncol = 1;
  rhs.nzmax = rhs.nrow;
  rhs.x = const_cast<double *>(b); // read only
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_l_solve2(CHOLMOD_A, m.factor, &rhs, nullptr, &m.x, nullptr, &m.y, &m.e, &m.common))
    throw std::runtime_error("CHOLMOD: the solve failed (status " +
                             std::to_string(m.common.status) + ")");
  const auto *solution = static_cast<const double *>(m.x->x);
  std::copy(solution, solution + m.n, x);
}

double SparseDirect::residual(const double *b, const double *x, double *r) const {
  const Impl &m = *impl_;
  double sum = 0.0;
  for (Long i = 0; i < m.n; ++i) {
    double ri = b[i];
    for (Long k = m.rows[i]; k < m.rows[i + 1]; ++k)
      ri -= m.values[k] * x[m.columns[k]];
    r[i] = ri;
    sum += ri * ri;
  }
  return std::sqrt(sum);
}

double SparseDirect::solveRefined(const double *b, double *x, int steps, double target) const {
  const auto n = static_cast<std::size_t>(impl_->n);
  solve(b, x);
  std::vector<double> r(n), dx(n), xc(n), rc(n);
  double rn = residual(b, x, r.data());
  for (int step = 0; step < steps && rn > target; ++step) {
    solve(r.data(), dx.data());
    for (std::size_t i = 0; i < n; ++i)
      xc[i] = x[i] + dx[i];
    const double cn = residual(b, xc.data(), rc.data());
    if (!(cn < rn))
      break;
    std::copy(xc.begin(), xc.end(), x);
    r.swap(rc);
    rn = cn;
  }
  return rn;
}

double SparseDirect::pivotRatio() const {
  Impl &m = *impl_;
  if (method_ == Method::Lu)
    return m.info[UMFPACK_RCOND];
  return m.factor ? cholmod_l_rcond(m.factor, &m.common) : 0.0;
}

} // namespace mixcon
