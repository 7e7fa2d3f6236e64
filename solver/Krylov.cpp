// Flexible CG and flexible GMRES on device vectors; the small Hessenberg system lives on the host.
#include <solver/Krylov.hpp>
#include <solver/Rules.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace mixcon::detail {

/// N sums reduced together (the fused dots of Gram-Schmidt and CG). Kokkos 3.x joins through
/// volatile references, 4.x through plain ones.
template <int N> struct Sums {
  double v[N];
  KOKKOS_INLINE_FUNCTION Sums() {
    for (int c = 0; c < N; ++c)
      v[c] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION Sums &operator+=(const Sums &o) {
    for (int c = 0; c < N; ++c)
      v[c] += o.v[c];
    return *this;
  }
#if KOKKOS_VERSION < 40000 // Kokkos 4 joins plain references (C++20 deprecates volatile +=)
  KOKKOS_INLINE_FUNCTION void operator+=(const volatile Sums &o) volatile {
    for (int c = 0; c < N; ++c)
      v[c] += o.v[c];
  }
#endif
};

/// Columns per pass of BlockOps::dots (one slot of the sums is w . w).
constexpr int kDotsWidth = 16;

/// A second classical Gram-Schmidt pass runs where the first left less than kSecondPass of ||w||
/// (Daniel, Gragg, Kaufman and Stewart 1976, Math. Comp. 30: 1/sqrt(2), as Belos's ICGS and
/// PETSc's "refine if needed"). One pass loses orthogonality like eps kappa^2 of the vectors
/// orthogonalized, which in GMRES grow dependent as the residual falls; two passes keep the
/// basis orthogonal to working precision ("twice is enough": Giraud, Langou, Rozloznik, Smith
/// 2005, Numer. Math. 101).
constexpr double kSecondPass = 0.70710678118654752;

} // namespace mixcon::detail

namespace Kokkos {
template <int N> struct reduction_identity<mixcon::detail::Sums<N>> {
  KOKKOS_FORCEINLINE_FUNCTION static mixcon::detail::Sums<N> sum() {
    return mixcon::detail::Sums<N>();
  }
};
} // namespace Kokkos

namespace mixcon {

using Exec = Kokkos::DefaultExecutionSpace;

void multiply(const CsrMatrix<DeviceSpace> &a, const ConstDeviceVector &x, const DeviceVector &y) {
  multiply(Kokkos::DefaultExecutionSpace(), a, x, y);
}

double dot(const ConstDeviceVector &a, const ConstDeviceVector &b) {
  double s = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::krylov::dot", Kokkos::RangePolicy<Exec>(0, a.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i, double &acc) { acc += a(i) * b(i); }, s);
  return s;
}

void axpby(double alpha, const ConstDeviceVector &x, double beta, const DeviceVector &y) {
  Kokkos::parallel_for(
      "mixcon::krylov::axpby", Kokkos::RangePolicy<Exec>(0, y.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { y(i) = alpha * x(i) + (beta == 0.0 ? 0.0 : beta * y(i)); });
}

DeviceVector KrylovWorkspace::get(std::size_t i, std::size_t n) {
  if (vectors_.size() <= i)
    vectors_.resize(i + 1);
  if (vectors_[i].extent(0) != n)
    vectors_[i] =
        DeviceVector(Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::krylov::work"), n);
  return vectors_[i];
}

DeviceBlock KrylovWorkspace::block(std::size_t i, std::size_t n, std::size_t columns,
                                   std::size_t limit, std::size_t keep) {
  if (blocks_.size() <= i)
    blocks_.resize(i + 1);
  DeviceBlock &b = blocks_[i];
  const std::size_t have = b.extent(0) == n ? b.extent(1) : 0;
  if (have >= columns)
    return b;
  const std::size_t cols = std::min(std::max(limit, columns), std::max(columns, 2 * have));
  DeviceBlock grown(Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::krylov::basis"), n,
                    cols);
  keep = std::min(keep, have);
  if (keep > 0) {
    const auto first = std::make_pair(std::size_t(0), keep);
    Kokkos::deep_copy(Kokkos::subview(grown, Kokkos::ALL, first),
                      Kokkos::subview(b, Kokkos::ALL, first));
  }
  b = grown;
  return b;
}

namespace detail {

Kokkos::View<double *, DeviceSpace> BlockOps::coefficients(const std::vector<double> &c, int k) {
  if (coefficients_.extent(0) < static_cast<std::size_t>(k))
    coefficients_ = Kokkos::View<double *, DeviceSpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::krylov::coefficients"),
        std::max<std::size_t>(k, 2 * coefficients_.extent(0)));
  const auto part = Kokkos::subview(coefficients_, std::make_pair(0, k));
  Kokkos::deep_copy(part, Kokkos::View<const double *, Kokkos::HostSpace, Kokkos::MemoryUnmanaged>(
                              c.data(), static_cast<std::size_t>(k)));
  return coefficients_;
}

double BlockOps::dots(const DeviceBlock &v, int k, const ConstDeviceVector &w,
                      std::vector<double> &h) {
  double ww = 0.0;
  // Passes of at most kDotsWidth - 1 columns; the first also sums w . w.
  for (int j0 = 0, pass = 0; pass == 0 || j0 < k; ++pass) {
    const bool norm = pass == 0;
    const int count = std::min(k - j0, kDotsWidth - 1);
    Sums<kDotsWidth> s;
    Kokkos::parallel_reduce(
        "mixcon::krylov::blockDots", Kokkos::RangePolicy<Exec>(0, w.extent(0)),
        KOKKOS_LAMBDA(LocalIndex i, Sums<kDotsWidth> & acc) {
          const double wi = w(i);
          for (int c = 0; c < count; ++c)
            acc.v[c] += v(i, j0 + c) * wi;
          if (norm)
            acc.v[kDotsWidth - 1] += wi * wi;
        },
        Kokkos::Sum<Sums<kDotsWidth>>(s));
    for (int c = 0; c < count; ++c)
      h[j0 + c] = s.v[c];
    if (norm)
      ww = s.v[kDotsWidth - 1];
    j0 += count;
  }
  return ww;
}

double BlockOps::subtract(const DeviceBlock &v, int k, const std::vector<double> &c,
                          const DeviceVector &w) {
  const auto cd = coefficients(c, k);
  double ww = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::krylov::blockSubtract", Kokkos::RangePolicy<Exec>(0, w.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i, double &acc) {
        double t = w(i);
        for (int j = 0; j < k; ++j)
          t -= cd(j) * v(i, j);
        w(i) = t;
        acc += t * t;
      },
      ww);
  return ww;
}

void BlockOps::add(const DeviceBlock &v, int k, const std::vector<double> &c,
                   const DeviceVector &x) {
  if (k == 0)
    return;
  const auto cd = coefficients(c, k);
  Kokkos::parallel_for(
      "mixcon::krylov::blockAdd", Kokkos::RangePolicy<Exec>(0, x.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) {
        double t = x(i);
        for (int j = 0; j < k; ++j)
          t += cd(j) * v(i, j);
        x(i) = t;
      });
}

double BlockOps::orthogonalize(const DeviceBlock &v, int k, const DeviceVector &w,
                               std::vector<double> &h) {
  const double before = dots(v, k, w, h);
  double after = subtract(v, k, h, w);
  if (k > 0 && after < kSecondPass * kSecondPass * before) { // cancelled: once more
    ++reorthogonalizations_;
    second_.resize(k);
    dots(v, k, w, second_);
    after = subtract(v, k, second_, w);
    for (int j = 0; j < k; ++j)
      h[j] += second_[j];
  }
  return std::sqrt(after);
}

} // namespace detail

namespace {

/// Hands out the workspace's vectors in order. Every vector is fully written (by the operator,
/// preconditioner or a copy) before it is read, so none is zero-filled.
class Vectors {
public:
  Vectors(KrylovWorkspace &w, std::size_t n) : workspace_(w), n_(n) {}
  DeviceVector next() { return workspace_.get(count_++, n_); }
  /// Block `which` (0, 1, ...) with at least `columns` columns: KrylovWorkspace::block.
  DeviceBlock block(std::size_t which, int columns, int limit, int keep) {
    return workspace_.block(which, n_, columns, limit, keep);
  }
  detail::BlockOps &blockOps() { return workspace_.blockOps(); }

private:
  KrylovWorkspace &workspace_;
  std::size_t n_;
  std::size_t count_ = 0;
};

/// r = b - A x; returns ||r||.
double residual(const LinearMap &a, const ConstDeviceVector &b, const DeviceVector &x,
                const DeviceVector &r) {
  a(x, r);
  axpby(1.0, b, -1.0, r);
  return std::sqrt(dot(r, r));
}

/// The backward-error test of KrylovOptions::backwardErrorFloor: ||r|| small against
/// ||A|| ||x|| + ||b|| (operatorNorm 0: never).
bool atFloor(double rnorm, double operatorNorm, const ConstDeviceVector &x, double bnorm) {
  if (!(operatorNorm > 0.0))
    return false;
  const double ax = operatorNorm * std::sqrt(dot(x, x));
  return ax <= kGrowthLimit * bnorm && rnorm <= kBackwardErrorFloor * (ax + bnorm);
}

/// ||A w|| / ||w|| for w of pseudo-random signs (an estimate of ||A||, from below).
double operatorNormEstimate(const LinearMap &a, const DeviceVector &w, const DeviceVector &y) {
  Kokkos::parallel_for(
      "mixcon::krylov::signs", Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, w.extent(0)),
      KOKKOS_LAMBDA(std::size_t i) {
        const unsigned h = static_cast<unsigned>(i) * 2654435761u; // Knuth's multiplicative hash
        w(i) = (h >> 16) & 1u ? 1.0 : -1.0;
      });
  a(w, y);
  return std::sqrt(dot(y, y) / dot(w, w));
}

/// Whether every entry of x is zero (one pass, no product).
bool isZero(const ConstDeviceVector &x) {
  LocalIndex nonzero = 0;
  Kokkos::parallel_reduce(
      "mixcon::krylov::isZero", Kokkos::RangePolicy<Exec>(0, x.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i, LocalIndex & acc) { acc += x(i) != 0.0 ? 1 : 0; }, nonzero);
  return nonzero == 0;
}

/// x += alpha d and r -= alpha q in one pass; returns ||r||^2 after.
double updateIterate(double alpha, const ConstDeviceVector &d, const ConstDeviceVector &q,
                     const DeviceVector &x, const DeviceVector &r) {
  double rr = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::krylov::cgUpdate", Kokkos::RangePolicy<Exec>(0, r.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i, double &acc) {
        x(i) += alpha * d(i);
        const double t = r(i) - alpha * q(i);
        r(i) = t;
        acc += t * t;
      },
      rr);
  return rr;
}

/// (z . r, z . q) in one pass.
detail::Sums<2> twoDots(const ConstDeviceVector &z, const ConstDeviceVector &r,
                        const ConstDeviceVector &q) {
  detail::Sums<2> s;
  Kokkos::parallel_reduce(
      "mixcon::krylov::cgDots", Kokkos::RangePolicy<Exec>(0, z.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i, detail::Sums<2> & acc) {
        acc.v[0] += z(i) * r(i);
        acc.v[1] += z(i) * q(i);
      },
      Kokkos::Sum<detail::Sums<2>>(s));
  return s;
}

KrylovStats flexibleCg(const KrylovOptions &o, const LinearMap &a, const LinearMap &p,
                       const ConstDeviceVector &b, double bnorm, const DeviceVector &x,
                       Vectors work) {
  KrylovStats s;
  auto r = work.next(), z = work.next(), d = work.next(), q = work.next();
  const double norm = o.backwardErrorFloor ? operatorNormEstimate(a, z, q) : 0.0;
  double rnorm = bnorm; // the residual of x = 0 is b, without a product
  if (o.exactOperator && isZero(x))
    Kokkos::deep_copy(r, b);
  else
    rnorm = residual(a, b, x, r);
  // Restart from the true residual whenever the recursive one has converged but the true one
  // (operator applied with inner iterations) has not.
  while (rnorm > o.tolerance * bnorm && !atFloor(rnorm, norm, x, bnorm) &&
         s.iterations < o.maxIterations) {
    p(r, z);
    Kokkos::deep_copy(d, z);
    double rz = dot(r, z);
    while (rnorm > o.tolerance * bnorm && s.iterations < o.maxIterations) {
      a(d, q);
      const double dq = dot(d, q);
      if (!(dq > 0.0)) { // not positive definite, or breakdown: use GMRES for such operators
        s.relativeResidual = residual(a, b, x, r) / bnorm;
        return s;
      }
      const double alpha = rz / dq;
      rnorm = std::sqrt(updateIterate(alpha, d, q, x, r));
      ++s.iterations;
      p(r, z);
      // Flexible (Polak-Ribiere) beta = z . (r - r_old) / rz with r_old = r + alpha q (Notay
      // 2000, SIAM J. Sci. Comput. 22), so no copy of r_old is kept.
      const detail::Sums<2> zs = twoDots(z, r, q);
      const double beta = -alpha * zs.v[1] / rz;
      rz = zs.v[0];
      axpby(1.0, z, beta, d);
    }
    if (o.exactOperator)
      break;
    rnorm = residual(a, b, x, r);
  }
  s.relativeResidual = rnorm / bnorm;
  s.converged = std::isfinite(s.relativeResidual) &&
                (s.relativeResidual <= o.tolerance || atFloor(rnorm, norm, x, bnorm));
  return s;
}

DeviceVector column(const DeviceBlock &block, int j) {
  return Kokkos::subview(block, Kokkos::ALL, j);
}

/// Columns of the basis allocated before the iterations need more (blocks grow by doubling).
constexpr int kFirstColumns = 8;

KrylovStats flexibleGmres(const KrylovOptions &o, const LinearMap &a, const LinearMap &p,
                          const ConstDeviceVector &b, double bnorm, const DeviceVector &x,
                          Vectors work) {
  const int m = o.restart;
  KrylovStats s;
  // V (m + 1 columns) and the preconditioned Z (m): allocated as the iterations reach them.
  DeviceBlock v = work.block(0, std::min(m + 1, kFirstColumns), m + 1, 0);
  DeviceBlock z = work.block(1, std::min(m, kFirstColumns), m, 0);
  detail::BlockOps &ops = work.blockOps();
  std::vector<std::vector<double>> h(m + 1, std::vector<double>(m, 0.0));
  std::vector<double> cs(m), sn(m), g(m + 1), hk(m + 1);
  const double norm =
      o.backwardErrorFloor ? operatorNormEstimate(a, column(z, 0), column(v, 1)) : 0.0;
  double rnorm = residual(a, b, x, column(v, 0));
  while (rnorm > o.tolerance * bnorm && !atFloor(rnorm, norm, x, bnorm) &&
         s.iterations < o.maxIterations) {
    axpby(0.0, column(v, 0), 1.0 / rnorm, column(v, 0));
    std::fill(g.begin(), g.end(), 0.0);
    g[0] = rnorm;
    int k = 0;
    for (; k < m && s.iterations < o.maxIterations; ++k) {
      if (static_cast<std::size_t>(k + 2) > v.extent(1))
        v = work.block(0, k + 2, m + 1, k + 1);
      if (static_cast<std::size_t>(k + 1) > z.extent(1))
        z = work.block(1, k + 1, m, k);
      const DeviceVector w = column(v, k + 1);
      p(column(v, k), column(z, k));
      a(column(z, k), w);
      h[k + 1][k] = ops.orthogonalize(v, k + 1, w, hk); // classical Gram-Schmidt, fused
      for (int i = 0; i <= k; ++i)
        h[i][k] = hk[i];
      if (h[k + 1][k] > 0.0)
        axpby(0.0, w, 1.0 / h[k + 1][k], w);
      for (int i = 0; i < k; ++i) { // previous Givens rotations
        const double t = cs[i] * h[i][k] + sn[i] * h[i + 1][k];
        h[i + 1][k] = -sn[i] * h[i][k] + cs[i] * h[i + 1][k];
        h[i][k] = t;
      }
      const double den = std::hypot(h[k][k], h[k + 1][k]);
      cs[k] = den > 0.0 ? h[k][k] / den : 1.0;
      sn[k] = den > 0.0 ? h[k + 1][k] / den : 0.0;
      h[k][k] = den;
      h[k + 1][k] = 0.0;
      g[k + 1] = -sn[k] * g[k];
      g[k] = cs[k] * g[k];
      ++s.iterations;
      if (std::fabs(g[k + 1]) <= o.tolerance * bnorm) {
        ++k;
        break;
      }
    }
    // x += Z y with H y = g (upper triangular, k x k)
    std::vector<double> y(k);
    for (int i = k - 1; i >= 0; --i) {
      double t = g[i];
      for (int j = i + 1; j < k; ++j)
        t -= h[i][j] * y[j];
      y[i] = h[i][i] != 0.0 ? t / h[i][i] : 0.0;
    }
    ops.add(z, k, y, x);
    rnorm = residual(a, b, x, column(v, 0));
  }
  s.relativeResidual = rnorm / bnorm;
  s.converged = std::isfinite(s.relativeResidual) &&
                (s.relativeResidual <= o.tolerance || atFloor(rnorm, norm, x, bnorm));
  return s;
}

} // namespace

KrylovStats krylovSolve(const KrylovOptions &options, const LinearMap &a, const LinearMap &p,
                        const ConstDeviceVector &b, const DeviceVector &x,
                        KrylovWorkspace *workspace) {
  if (const auto why = rules::iterationLimit(options.maxIterations))
    throw std::invalid_argument("Krylov solver: max_iterations " + *why + " (got " +
                                std::to_string(options.maxIterations) + ")");
  if (options.method == KrylovMethod::Gmres && options.restart < 1)
    throw std::invalid_argument("Krylov solver: the GMRES restart must be at least 1 (got " +
                                std::to_string(options.restart) + ")");
  const double bnorm = std::sqrt(dot(b, b));
  if (bnorm == 0.0) { // the answer is x = 0 (relative residuals are undefined)
    Kokkos::deep_copy(x, 0.0);
    KrylovStats s;
    s.converged = true;
    return s;
  }
  KrylovWorkspace local; // this solve's own vectors when the caller keeps none
  const Vectors work(workspace ? *workspace : local, b.extent(0));
  if (options.method == KrylovMethod::Cg)
    return flexibleCg(options, a, p, b, bnorm, x, work);
  return flexibleGmres(options, a, p, b, bnorm, x, work);
}

} // namespace mixcon
