// Prescribed displacements on an assembled system, kept as scaled identity rows (DESIGN-NOTES 3):
// column entries of constrained unknowns are moved to the right-hand side so the matrix stays
// symmetric (CG + AMG), each constrained row keeps only its diagonal d_ii and gets rhs d_ii g_i.
// Data flow: solver.
#pragma once

#include <kernels/SparseMatrix.hpp>

namespace mixcon {

namespace detail {
/// One row of the constraints: a constrained row keeps its diagonal d_ii (1 where it is 0) and
/// gets rhs d_ii g_i; a free row moves its constrained columns' terms to the rhs. The matrix is
/// changed only with kModifyMatrix (otherwise the rhs is lifted for a matrix already changed).
template <class MemorySpace, bool kModifyMatrix> struct DirichletRows {
  Kokkos::View<const Offset *, MemorySpace> ro;
  Kokkos::View<const LocalIndex *, MemorySpace> co;
  Kokkos::View<double *, MemorySpace> va;
  Kokkos::View<const int *, MemorySpace> constrained;
  Kokkos::View<const double *, MemorySpace> value;
  Kokkos::View<double *, MemorySpace> rhs;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex i) const {
    if (constrained(i)) {
      double diag = 0.0;
      for (Offset k = ro(i); k < ro(i + 1); ++k) {
        if (co(k) == i)
          diag = va(k);
        else if (kModifyMatrix)
          va(k) = 0.0;
      }
      if (diag == 0.0) {
        diag = 1.0;
        if (kModifyMatrix)
          for (Offset k = ro(i); k < ro(i + 1); ++k)
            if (co(k) == i)
              va(k) = 1.0;
      }
      rhs(i) = diag * value(i);
    } else {
      double shift = 0.0;
      for (Offset k = ro(i); k < ro(i + 1); ++k)
        if (constrained(co(k))) {
          shift += va(k) * value(co(k));
          if (kModifyMatrix)
            va(k) = 0.0;
        }
      rhs(i) -= shift;
    }
  }
};
} // namespace detail

/// Applies constraints in place. `constrained(i)` != 0 marks unknown i, `value(i)` its prescribed
/// value. Rows are independent, so the kernel is race free. A zero diagonal becomes 1.
template <class ExecSpace, class MemorySpace>
void applyDirichlet(const ExecSpace &exec, const CsrMatrix<MemorySpace> &a,
                    const Kokkos::View<const int *, MemorySpace> &constrained,
                    const Kokkos::View<const double *, MemorySpace> &value,
                    const Kokkos::View<double *, MemorySpace> &rhs) {
  Kokkos::parallel_for("mixcon::solver::applyDirichlet",
                       Kokkos::RangePolicy<ExecSpace>(exec, 0, a.numRows),
                       detail::DirichletRows<MemorySpace, true>{a.rowOffsets, a.columns, a.values,
                                                                constrained, value, rhs});
}

/// The right-hand side applyDirichlet would give, `a` (the unconstrained matrix) left as it is:
/// for a system whose constrained matrix was factorized before and only b changes.
template <class ExecSpace, class MemorySpace>
void liftDirichlet(const ExecSpace &exec, const CsrMatrix<MemorySpace> &a,
                   const Kokkos::View<const int *, MemorySpace> &constrained,
                   const Kokkos::View<const double *, MemorySpace> &value,
                   const Kokkos::View<double *, MemorySpace> &rhs) {
  Kokkos::parallel_for("mixcon::solver::liftDirichlet",
                       Kokkos::RangePolicy<ExecSpace>(exec, 0, a.numRows),
                       detail::DirichletRows<MemorySpace, false>{a.rowOffsets, a.columns, a.values,
                                                                 constrained, value, rhs});
}

/// Matrix-free form of the same constraints, for an operator A applied without a matrix:
/// A_c x = P A P x + D_c x, P zeroing constrained entries and D_c holding, on constrained
/// unknowns, the diagonal `diag` the assembled preconditioner kept there (so both agree).
/// y = P x.
template <class ExecSpace, class MemorySpace>
void maskConstrained(const ExecSpace &exec,
                     const Kokkos::View<const int *, MemorySpace> &constrained,
                     const Kokkos::View<const double *, MemorySpace> &x,
                     const Kokkos::View<double *, MemorySpace> &y) {
  Kokkos::parallel_for(
      "mixcon::solver::maskConstrained", Kokkos::RangePolicy<ExecSpace>(exec, 0, x.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { y(i) = constrained(i) ? 0.0 : x(i); });
}

/// y = P y + D_c x (completes A_c x after y = A P x).
template <class ExecSpace, class MemorySpace>
void finishConstrained(const ExecSpace &exec,
                       const Kokkos::View<const int *, MemorySpace> &constrained,
                       const Kokkos::View<const double *, MemorySpace> &diag,
                       const Kokkos::View<const double *, MemorySpace> &x,
                       const Kokkos::View<double *, MemorySpace> &y) {
  Kokkos::parallel_for(
      "mixcon::solver::finishConstrained", Kokkos::RangePolicy<ExecSpace>(exec, 0, x.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) {
        if (constrained(i))
          y(i) = diag(i) * x(i);
      });
}

/// diag(i) = a_ii on constrained rows, 0 elsewhere.
template <class ExecSpace, class MemorySpace>
void constrainedDiagonal(const ExecSpace &exec, const CsrMatrix<MemorySpace> &a,
                         const Kokkos::View<const int *, MemorySpace> &constrained,
                         const Kokkos::View<double *, MemorySpace> &diag) {
  auto ro = a.rowOffsets;
  auto co = a.columns;
  auto va = a.values;
  Kokkos::parallel_for(
      "mixcon::solver::constrainedDiagonal", Kokkos::RangePolicy<ExecSpace>(exec, 0, a.numRows),
      KOKKOS_LAMBDA(LocalIndex i) {
        double d = 0.0;
        if (constrained(i))
          for (Offset k = ro(i); k < ro(i + 1); ++k)
            if (co(k) == i)
              d = va(k);
        diag(i) = d;
      });
}

/// Constrained right-hand side for A_c: b = P (f - A g) + D_c g, given Ag = A g.
template <class ExecSpace, class MemorySpace>
void constrainedRhs(const ExecSpace &exec,
                    const Kokkos::View<const int *, MemorySpace> &constrained,
                    const Kokkos::View<const double *, MemorySpace> &diag,
                    const Kokkos::View<const double *, MemorySpace> &f,
                    const Kokkos::View<const double *, MemorySpace> &g,
                    const Kokkos::View<const double *, MemorySpace> &ag,
                    const Kokkos::View<double *, MemorySpace> &b) {
  Kokkos::parallel_for(
      "mixcon::solver::constrainedRhs", Kokkos::RangePolicy<ExecSpace>(exec, 0, b.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { b(i) = constrained(i) ? diag(i) * g(i) : f(i) - ag(i); });
}

} // namespace mixcon
