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
#include <type_traits>
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

/// An initialized n x n ParCSR matrix of `total` entries on a communicator of one rank, its row
/// offsets hypre's (to be filled by the caller), its columns and values `columns` and `values`
/// where given (read where they are; not hypre's to free) or else hypre's own. The caller
/// finishes it with finishSerialParCsr and owns it (hypre_ParCSRMatrixDestroy).
inline hypre_ParCSRMatrix *newSerialParCsr(MPI_Comm comm, LocalIndex n, std::size_t total,
                                           HYPRE_Int *columns = nullptr,
                                           HYPRE_Complex *values = nullptr) {
  if (total > static_cast<std::size_t>(std::numeric_limits<HYPRE_Int>::max()))
    throw std::runtime_error("hypre's matrix: " + std::to_string(total) +
                             " entries on one rank exceed hypre's integer type (HYPRE_Int)");
  HYPRE_BigInt starts[2] = {0, n};
  hypre_ParCSRMatrix *m =
      hypre_ParCSRMatrixCreate(comm, n, n, starts, starts, 0, static_cast<HYPRE_Int>(total), 0);
  hypre_CSRMatrix *diag = hypre_ParCSRMatrixDiag(m);
  if (columns) { // Initialize allocates only what is not set
    hypre_CSRMatrixJ(diag) = columns;
    hypre_CSRMatrixData(diag) = values;
    hypre_CSRMatrixOwnsData(diag) = 0;
  }
  if (hypre_ParCSRMatrixInitialize(m) != 0) {
    hypre_ParCSRMatrixDestroy(m);
    HYPRE_ClearAllErrors(); // as check() in solver/LinearSolver.cpp: the next call starts clean
    throw std::runtime_error("hypre's matrix: hypre_ParCSRMatrixInitialize failed");
  }
  return m;
}

/// newSerialParCsr's matrix as the IJ assembly leaves it: the nonzero rows of both blocks listed;
/// the communication package and the global nonzero counts left to hypre (made where it needs
/// them).
inline hypre_ParCSRMatrix *finishSerialParCsr(hypre_ParCSRMatrix *m) {
  hypre_CSRMatrixSetRownnz(hypre_ParCSRMatrixDiag(m));
  hypre_CSRMatrixSetRownnz(hypre_ParCSRMatrixOffd(m));
  return m;
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
  hypre_ParCSRMatrix *m = newSerialParCsr(comm, n, total);
  HYPRE_Int *ri = hypre_CSRMatrixI(hypre_ParCSRMatrixDiag(m));
  ri[0] = 0;
  for (LocalIndex i = 0; i < n; ++i)
    ri[i + 1] = ri[i] + counts[i];
  fillSerialParCsr(m, a, d);
  return finishSerialParCsr(m);
}

/// `a`'s rows in hypre's order, in place, for as long as this lives: each row's diagonal swapped
/// with its first entry, as serialParCsr places them, so that borrowedParCsr's matrix of `a` is
/// serialParCsr's without the copy. restore() (or the destructor, where an exception came first)
/// swaps them back: `a` is then bit for bit what it was. Host-accessible memory only.
class DiagonalFirst {
public:
  explicit DiagonalFirst(const CsrMatrix<DeviceSpace> &a) : a_(a), at_(a.numRows, 0) {
    Kokkos::fence(); // no kernel still reads or writes `a` (managed memory: written here)
    const auto ro = a_.rowOffsets;
    const auto co = a_.columns;
    Kokkos::parallel_for("mixcon::solver::findDiagonal", HostRange(0, a_.numRows),
                         [&](LocalIndex i) {
                           for (auto k = ro(i); k < ro(i + 1); ++k)
                             if (co(k) == i)
                               at_[i] = k - ro(i);
                         });
    Kokkos::DefaultHostExecutionSpace().fence();
    swapRows();
  }
  ~DiagonalFirst() { restore(); }
  DiagonalFirst(const DiagonalFirst &) = delete;
  DiagonalFirst &operator=(const DiagonalFirst &) = delete;

  /// `a`'s own order again (the swaps undone; once).
  void restore() {
    if (!swapped_)
      return;
    swapRows();
    swapped_ = false;
  }

private:
  /// Each row's first entry and its diagonal exchanged (an involution: the positions are kept).
  void swapRows() {
    const auto ro = a_.rowOffsets;
    const auto co = a_.columns;
    const auto va = a_.values;
    Kokkos::parallel_for("mixcon::solver::swapDiagonal", HostRange(0, a_.numRows),
                         [&](LocalIndex i) {
                           if (at_[i] > 0) {
                             std::swap(co(ro(i)), co(ro(i) + at_[i]));
                             std::swap(va(ro(i)), va(ro(i) + at_[i]));
                           }
                         });
    Kokkos::DefaultHostExecutionSpace().fence();
  }

  CsrMatrix<DeviceSpace> a_;
  std::vector<Offset> at_; ///< each row's diagonal's place in it (0: first, or none)
  bool swapped_ = true;
};

/// hypre's ParCSR matrix of `a` on a communicator of one rank that reads a's columns and values
/// where they are (hypre_ParCSRMatrixDestroy leaves them; it frees only the row offsets, its own
/// 4-byte copy): BoomerAMG's fine level without a second copy of K (3 GB for the 3.1M-unknown
/// cube). It is serialParCsr's matrix (d = 0) while a DiagonalFirst of `a` lives and `a` is not
/// changed; ownParCsrData gives it its own copy. Host-accessible memory only.
inline hypre_ParCSRMatrix *borrowedParCsr(MPI_Comm comm, const CsrMatrix<DeviceSpace> &a) {
  static_assert(std::is_same_v<HYPRE_Int, LocalIndex> && std::is_same_v<HYPRE_Complex, double>,
                "hypre reads mixcon's columns and values as they are");
  const LocalIndex n = a.numRows;
  hypre_ParCSRMatrix *m = newSerialParCsr(comm, n, static_cast<std::size_t>(a.numNonzeros()),
                                          a.columns.data(), a.values.data());
  HYPRE_Int *ri = hypre_CSRMatrixI(hypre_ParCSRMatrixDiag(m));
  const auto ro = a.rowOffsets;
  Kokkos::parallel_for("mixcon::solver::borrowedParCsr", HostRange(0, n + 1),
                       [&](LocalIndex i) { ri[i] = static_cast<HYPRE_Int>(ro(i)); });
  Kokkos::DefaultHostExecutionSpace().fence();
  return finishSerialParCsr(m);
}

/// borrowedParCsr's matrix `m` of `a` (in a's own order again) given its own copy of a's entries
/// in hypre's order, as serialParCsr builds it: for hypre's Krylov method and V-cycle, which read
/// it at every solve while `a` is mixcon's again.
inline void ownParCsrData(hypre_ParCSRMatrix *m, const CsrMatrix<DeviceSpace> &a) {
  hypre_CSRMatrix *diag = hypre_ParCSRMatrixDiag(m);
  const auto total = static_cast<std::size_t>(a.numNonzeros());
  hypre_CSRMatrixJ(diag) = hypre_TAlloc(HYPRE_Int, total, HYPRE_MEMORY_HOST);
  hypre_CSRMatrixData(diag) = hypre_TAlloc(HYPRE_Complex, total, HYPRE_MEMORY_HOST);
  hypre_CSRMatrixOwnsData(diag) = 1; // hypre_ParCSRMatrixDestroy frees what was allocated
  if (total > 0 && (!hypre_CSRMatrixJ(diag) || !hypre_CSRMatrixData(diag))) {
    HYPRE_ClearAllErrors();
    throw std::runtime_error("hypre's matrix: no memory for its copy of " + std::to_string(total) +
                             " entries");
  }
  fillSerialParCsr(m, a, 0);
}

} // namespace mixcon::detail
