// Prescribed displacements on an assembled system, kept as scaled identity rows (DESIGN-NOTES 3):
// column entries of constrained unknowns are moved to the right-hand side so the matrix stays
// symmetric (CG + AMG), each constrained row keeps only its diagonal d_ii and gets rhs d_ii g_i.
// Data flow: solver.
#pragma once

#include <kernels/SparseMatrix.hpp>

namespace mixcon {

/// Applies constraints in place. `constrained(i)` != 0 marks unknown i, `value(i)` its prescribed
/// value. Rows are independent, so the kernel is race free. A zero diagonal becomes 1.
template <class ExecSpace, class MemorySpace>
void applyDirichlet(const ExecSpace &exec, const CsrMatrix<MemorySpace> &a,
                    const Kokkos::View<const int *, MemorySpace> &constrained,
                    const Kokkos::View<const double *, MemorySpace> &value,
                    const Kokkos::View<double *, MemorySpace> &rhs) {
  auto ro = a.rowOffsets;
  auto co = a.columns;
  auto va = a.values;
  Kokkos::parallel_for(
      "mixcon::solver::applyDirichlet", Kokkos::RangePolicy<ExecSpace>(exec, 0, a.numRows),
      KOKKOS_LAMBDA(LocalIndex i) {
        if (constrained(i)) {
          double diag = 0.0;
          for (Offset k = ro(i); k < ro(i + 1); ++k) {
            if (co(k) == i)
              diag = va(k);
            else
              va(k) = 0.0;
          }
          if (diag == 0.0) {
            diag = 1.0;
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
              va(k) = 0.0;
            }
          rhs(i) -= shift;
        }
      });
}

} // namespace mixcon
