// hypre's ParCSR matrix of mixcon's CSR matrix on one rank, built in place instead of through
// hypre's IJ interface (the AMG solver's fine level, solver/LinearSolver.cpp). Host code, CPU
// hypre only; internal (it includes hypre's internal headers: not installed). Data flow: solver.
#pragma once
#include <core/Transfer.hpp>
#include <kernels/SparseMatrix.hpp>

#include <HYPRE.h>
#include <_hypre_parcsr_mv.h>

#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mixcon::detail {

/// True for the entry (i, j) of a matrix with `d` interleaved unknowns per node that couples a
/// component with the same component (the first owned row is a node's first unknown); d = 0
/// keeps every entry. (The usual d as constants: their remainders are multiplications, not a
/// division for each of the 250M entries of the 3.1M-unknown cube's K.)
inline bool sameComponent(LocalIndex i, LocalIndex j, int d) {
  switch (d) {
  case 0:
  case 1:
    return true;
  case 2:
    return i % 2 == j % 2;
  case 3:
    return i % 3 == j % 3;
  default:
    return i % d == j % d;
  }
}

/// The columns and values of serialParCsr's matrix `m` from `a`: the entries that
/// sameComponent(i, j, d) keeps, in a's order, each row's diagonal swapped with its first entry;
/// also a kept hierarchy's new values (the same entries). On the host's threads (the rows are
/// independent).
inline void fillSerialParCsr(hypre_ParCSRMatrix *m, const CsrMatrix<DeviceSpace> &a, int d) {
  hypre_CSRMatrix *diag = hypre_ParCSRMatrixDiag(m);
  const HYPRE_Int *ri = hypre_CSRMatrixI(diag);
  HYPRE_Int *rj = hypre_CSRMatrixJ(diag);
  HYPRE_Complex *rv = hypre_CSRMatrixData(diag);
  const auto ro = hostReadable(a.rowOffsets);
  const auto co = hostReadable(a.columns);
  const auto va = hostReadable(a.values);
  Kokkos::parallel_for("mixcon::solver::serialParCsr", HostRange(0, a.numRows), [&](LocalIndex i) {
    HYPRE_Int q = ri[i], diagonal = -1;
    for (auto k = ro(i); k < ro(i + 1); ++k)
      if (sameComponent(i, co(k), d)) {
        if (co(k) == i)
          diagonal = q;
        rj[q] = static_cast<HYPRE_Int>(co(k));
        rv[q++] = va(k);
      }
    if (diagonal > ri[i]) { // as hypre's assembly: swapped with the row's first entry
      std::swap(rj[diagonal], rj[ri[i]]);
      std::swap(rv[diagonal], rv[ri[i]]);
    }
  });
  Kokkos::DefaultHostExecutionSpace().fence();
}

/// hypre's ParCSR matrix of `a` on a communicator of one rank (it owns every row), built in place:
/// the entries (i, j) that sameComponent(i, j, d) keeps, `counts` of them per row, in a's order
/// with each row's diagonal swapped to the front. That is the matrix HYPRE_IJMatrixSetValues (after
/// SetDiagOffdSizes) and HYPRE_IJMatrixAssemble build from the same rows, the same entries in the
/// same places (tests/unit/test_amg_robust.cpp, HypreMatrix.*), without the copies on the way (the
/// separate components' entries gathered in chunks with 8-byte global columns, hypre's copy of
/// them, its assembly's pass over every row for the diagonal) and, for a kept hierarchy's new
/// values (fillSerialParCsr), without SetValues' search of the assembled row for every entry.
/// The caller owns it (hypre_ParCSRMatrixDestroy).
inline hypre_ParCSRMatrix *serialParCsr(MPI_Comm comm, const CsrMatrix<DeviceSpace> &a,
                                        const std::vector<HYPRE_Int> &counts, int d) {
  const LocalIndex n = a.numRows;
  std::size_t total = 0;
  for (LocalIndex i = 0; i < n; ++i)
    total += static_cast<std::size_t>(counts[i]);
  if (total > static_cast<std::size_t>(std::numeric_limits<HYPRE_Int>::max()))
    throw std::runtime_error("hypre's matrix: " + std::to_string(total) +
                             " entries on one rank exceed hypre's integer type (HYPRE_Int)");
  HYPRE_BigInt starts[2] = {0, n};
  hypre_ParCSRMatrix *m =
      hypre_ParCSRMatrixCreate(comm, n, n, starts, starts, 0, static_cast<HYPRE_Int>(total), 0);
  if (hypre_ParCSRMatrixInitialize(m) != 0) {
    hypre_ParCSRMatrixDestroy(m);
    HYPRE_ClearAllErrors(); // as check() in solver/LinearSolver.cpp: the next call starts clean
    throw std::runtime_error("hypre's matrix: hypre_ParCSRMatrixInitialize failed");
  }
  HYPRE_Int *ri = hypre_CSRMatrixI(hypre_ParCSRMatrixDiag(m));
  ri[0] = 0;
  for (LocalIndex i = 0; i < n; ++i)
    ri[i + 1] = ri[i] + counts[i];
  fillSerialParCsr(m, a, d);
  // as the IJ assembly leaves it: the nonzero rows of both blocks listed; the communication
  // package and the global nonzero counts left to hypre (made where it needs them)
  hypre_CSRMatrixSetRownnz(hypre_ParCSRMatrixDiag(m));
  hypre_CSRMatrixSetRownnz(hypre_ParCSRMatrixOffd(m));
  return m;
}

} // namespace mixcon::detail
