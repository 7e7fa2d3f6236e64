// The constraint set applied to an assembled system and to a residual, on the device.
// Layer: solver.
#include <solver/ConstraintSet.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/LocalFrames.hpp>

#include <chrono>
#include <cmath>

namespace mixcon {

namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Policy = Kokkos::RangePolicy<Exec>;

} // namespace

namespace detail {
void copyMatrix(const CsrMatrix<DeviceSpace> &a, CsrMatrix<DeviceSpace> &work) {
  if (work.numRows != a.numRows || work.rowOffsets.data() != a.rowOffsets.data() ||
      work.values.extent(0) != a.values.extent(0)) {
    work = a;
    work.values =
        Kokkos::View<double *, DeviceSpace>("mixcon::constraints::values", a.values.extent(0));
  }
  Kokkos::deep_copy(work.values, a.values);
}
} // namespace detail

LinearSolveStats solveConstrained(const ConstraintSet &c, const CsrMatrix<DeviceSpace> &a,
                                  CsrMatrix<DeviceSpace> &work, ConstraintElimination &elimination,
                                  const Kokkos::View<double *, DeviceSpace> &b,
                                  LinearSolver &solver,
                                  const Kokkos::View<double *, DeviceSpace> &x,
                                  double *setupSeconds) {
  const auto start = std::chrono::steady_clock::now();
  const LocalIndex n = a.numRows;
  // Frames: A <- R^T A R, b <- R^T b (on a copy of A).
  CsrMatrix<DeviceSpace> rotated;
  if (c.hasFrames()) {
    detail::copyMatrix(a, work);
    rotateToLocalFrames(Exec(), work, c.stride, c.framed, c.normal, b);
    rotated = work;
  }
  // Multipoint rows: (T^T A T + D), b <- T^T (b - A s); the slaves join the prescribed unknowns.
  Kokkos::View<const int *, DeviceSpace> flags = c.flags;
  if (c.hasMultipoint()) {
    work = elimination.eliminate(c.hasFrames() ? rotated : a, *c.multipoint, c.slaveDiagonal, b);
    Kokkos::View<int *, DeviceSpace> held("mixcon::constraints::held", n);
    const auto slave = c.multipoint->slave;
    const auto f = c.flags;
    Kokkos::parallel_for(
        "mixcon::constraints::heldOrSlave", Policy(0, n),
        KOKKOS_LAMBDA(LocalIndex i) { held(i) = f(i) || slave(i) ? 1 : 0; });
    flags = held;
  } else if (!c.hasFrames()) {
    detail::copyMatrix(a, work);
  }
  applyDirichlet(Exec(), work, flags, c.values, b);
  Exec().fence();
  solver.setup(work);
  if (setupSeconds)
    *setupSeconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  LinearSolveStats s = solver.solve(b, x);
  if (c.hasMultipoint())
    expandConstrained(*c.multipoint, x);
  if (c.hasFrames())
    fromLocalFrames(Exec(), c.stride, c.framed, c.normal, x);
  return s;
}

double constrainedFreeNorm(const ConstraintSet &c,
                           const Kokkos::View<const double *, DeviceSpace> &g) {
  Kokkos::View<const double *, DeviceSpace> local = g;
  if (c.hasFrames()) { // R^T g
    Kokkos::View<double *, DeviceSpace> r("mixcon::constraints::localResidual", g.extent(0));
    Kokkos::deep_copy(r, g);
    toLocalFrames(Exec(), c.stride, c.framed, c.normal, r);
    local = r;
  }
  if (c.hasMultipoint())
    return condensedFreeNorm(*c.multipoint, local, c.flags, c.stride);
  const auto flags = c.flags;
  const int stride = c.stride;
  double sum = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::constraints::freeNorm", Policy(0, static_cast<LocalIndex>(g.extent(0))),
      KOKKOS_LAMBDA(LocalIndex i, double &acc) {
        if (i % stride < 2 && !flags(i))
          acc += local(i) * local(i);
      },
      sum);
  return std::sqrt(sum);
}

} // namespace mixcon
