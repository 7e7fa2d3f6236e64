// Flexible CG and flexible GMRES on device vectors; the small Hessenberg system lives on the host.
#include <solver/Krylov.hpp>
#include <solver/Rules.hpp>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

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

namespace {

/// Hands out the workspace's vectors in order. Every vector is fully written (by the operator,
/// preconditioner or a copy) before it is read, so none is zero-filled.
class Vectors {
public:
  Vectors(KrylovWorkspace &w, std::size_t n) : workspace_(w), n_(n) {}
  DeviceVector next() { return workspace_.get(count_++, n_); }

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

KrylovStats flexibleCg(const KrylovOptions &o, const LinearMap &a, const LinearMap &p,
                       const ConstDeviceVector &b, double bnorm, const DeviceVector &x,
                       Vectors work) {
  KrylovStats s;
  auto r = work.next(), rOld = work.next(), z = work.next(), d = work.next(), q = work.next();
  const double norm = o.backwardErrorFloor ? operatorNormEstimate(a, z, q) : 0.0;
  double rnorm = residual(a, b, x, r);
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
      axpby(alpha, d, 1.0, x);
      Kokkos::deep_copy(rOld, r);
      axpby(-alpha, q, 1.0, r);
      rnorm = std::sqrt(dot(r, r));
      ++s.iterations;
      p(r, z);
      const double rzNew = dot(r, z);
      const double beta = (rzNew - dot(z, rOld)) / rz; // flexible (Polak-Ribiere) beta
      rz = rzNew;
      axpby(1.0, z, beta, d);
    }
    rnorm = residual(a, b, x, r);
  }
  s.relativeResidual = rnorm / bnorm;
  s.converged = std::isfinite(s.relativeResidual) &&
                (s.relativeResidual <= o.tolerance || atFloor(rnorm, norm, x, bnorm));
  return s;
}

KrylovStats flexibleGmres(const KrylovOptions &o, const LinearMap &a, const LinearMap &p,
                          const ConstDeviceVector &b, double bnorm, const DeviceVector &x,
                          Vectors work) {
  const int m = o.restart;
  KrylovStats s;
  // Basis vectors are allocated as the iterations reach them: memory follows the iterations
  // taken, not the restart length.
  std::vector<DeviceVector> v{work.next()}, z;
  std::vector<std::vector<double>> h(m + 1, std::vector<double>(m, 0.0));
  std::vector<double> cs(m), sn(m), g(m + 1);
  double norm = 0.0;
  if (o.backwardErrorFloor) {
    z.push_back(work.next());
    v.push_back(work.next());
    norm = operatorNormEstimate(a, z[0], v[1]);
  }
  double rnorm = residual(a, b, x, v[0]);
  while (rnorm > o.tolerance * bnorm && !atFloor(rnorm, norm, x, bnorm) &&
         s.iterations < o.maxIterations) {
    axpby(0.0, v[0], 1.0 / rnorm, v[0]);
    std::fill(g.begin(), g.end(), 0.0);
    g[0] = rnorm;
    int k = 0;
    for (; k < m && s.iterations < o.maxIterations; ++k) {
      if (z.size() == static_cast<std::size_t>(k)) {
        z.push_back(work.next());
        v.push_back(work.next());
      }
      p(v[k], z[k]);
      a(z[k], v[k + 1]);
      for (int i = 0; i <= k; ++i) { // modified Gram-Schmidt
        h[i][k] = dot(v[k + 1], v[i]);
        axpby(-h[i][k], v[i], 1.0, v[k + 1]);
      }
      h[k + 1][k] = std::sqrt(dot(v[k + 1], v[k + 1]));
      if (h[k + 1][k] > 0.0)
        axpby(0.0, v[k + 1], 1.0 / h[k + 1][k], v[k + 1]);
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
    for (int i = 0; i < k; ++i)
      axpby(y[i], z[i], 1.0, x);
    rnorm = residual(a, b, x, v[0]);
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
