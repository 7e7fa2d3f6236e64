// Linear multi-point constraints eliminated from an assembled system (master-slave elimination):
// every slave unknown s is an affine combination of master unknowns, x_s = sum_j a_sj x_j + b_s,
// written x = T y + s with T the identity on the other unknowns and a zero column at each slave.
// The system A x = f becomes (T^T A T + D) y = T^T (f - A s), D holding a positive diagonal on
// the slaves (which then decouple with y_s = 0), and x = T y + s afterwards. T^T A T is symmetric
// positive definite when A is, so CG + BoomerAMG keep working; no multiplier unknowns, no saddle
// point. Used for node-to-segment contact (contact/SurfaceContact.hpp): a contactor node's normal
// (and in stick tangential) displacement follows its target segment's nodes. A unit vector per
// slave row allows rotated local frames: `frame` rows of T replace the identity at a node's
// displacement pair. Masters must not be slaves. Host implementation with Eigen sparse products;
// nothing here is 2D-specific (unknown indices only). Data flow: solver (used by contact).
#pragma once

#include <kernels/SparseMatrix.hpp>

#include <vector>

namespace mixcon {

/// x = T y + s, T stored by rows (only rows that differ from the identity).
struct MultiPointConstraints {
  /// Row r of T (an unknown index) and its entries (column, value); rows not listed are the
  /// identity. A slave row lists only masters; a rotated (framed) unknown lists the local
  /// components of its own node it combines.
  std::vector<LocalIndex> rows;
  std::vector<std::vector<std::pair<LocalIndex, double>>> entries;
  std::vector<double> offset;     ///< s at each listed row
  std::vector<LocalIndex> slaves; ///< unknowns whose column of T is zero (y_s = 0)
  bool empty() const { return rows.empty(); }
  void clear() {
    rows.clear();
    entries.clear();
    offset.clear();
    slaves.clear();
  }
  void addRow(LocalIndex row, std::vector<std::pair<LocalIndex, double>> e, double s) {
    rows.push_back(row);
    entries.push_back(std::move(e));
    offset.push_back(s);
  }
};

/// The eliminated system: returns T^T A T with `slaveDiagonal` on every slave's diagonal, and
/// rhs <- T^T (rhs - A s) (zero at the slaves). `a` may be on any memory space the host can copy.
CsrMatrix<Kokkos::DefaultExecutionSpace::memory_space> eliminateConstraints(
    const CsrMatrix<Kokkos::DefaultExecutionSpace::memory_space> &a, const MultiPointConstraints &c,
    double slaveDiagonal,
    const Kokkos::View<double *, Kokkos::DefaultExecutionSpace::memory_space> &rhs);

/// x <- T y + s (y given in x).
void expandConstrained(
    const MultiPointConstraints &c,
    const Kokkos::View<double *, Kokkos::DefaultExecutionSpace::memory_space> &x);

/// v <- T^T v on the host (condensed residual: the forces a constrained system balances).
void condenseVector(const MultiPointConstraints &c, std::vector<double> &v);

} // namespace mixcon
