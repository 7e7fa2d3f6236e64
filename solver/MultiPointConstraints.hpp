// Linear multi-point constraints eliminated from an assembled system (master-slave elimination):
// every slave unknown s is an affine combination of master unknowns, x_s = sum_j a_sj x_j + b_s,
// written x = T y + s with T the identity on the other unknowns and a zero column at each slave.
// The system A x = f becomes (T^T A T + D) y = T^T (f - A s), D holding a positive diagonal on
// the slaves (which then decouple with y_s = 0), and x = T y + s afterwards. T^T A T is symmetric
// positive definite when A is, so CG + BoomerAMG keep working; no multiplier unknowns, no saddle
// point. Used for node-to-segment contact (contact/SurfaceContact.hpp): a contactor node's normal
// (and in stick tangential) displacement follows its target segment's nodes. A unit vector per
// slave row allows rotated local frames: `frame` rows of T replace the identity at a node's
// displacement pair. Masters must not be slaves.
// The host struct MultiPointConstraints describes T (built per correction from the closed
// contact pairs, O(contact nodes)); DeviceMultiPoint is its device form (the listed rows of T and
// their transpose as CSR in Kokkos Views), and the elimination, expansion and condensation run on
// the device (Kokkos loops, no host copy of A or of any vector). T is the identity plus a few
// short rows, so T^T A T is formed row by row: a symbolic phase (the reduced pattern, reused while
// T's and A's patterns stay the same) and a numeric phase. Nothing here is 2D-specific (unknown
// indices only). Layer: solver (used by contact).
#pragma once

#include <kernels/SparseMatrix.hpp>

#include <vector>

namespace mixcon {

/// x = T y + s, T stored by rows (only rows that differ from the identity). Host description.
struct MultiPointConstraints {
  /// Row r of T (an unknown index) and its entries (column, value); rows not listed are the
  /// identity. A slave row lists only masters; a rotated (framed) unknown lists the local
  /// components of its own node it combines. A row is listed at most once.
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

/// T on the device: the listed rows (CSR over the m listed rows), their transpose (CSR over the
/// unknowns that listed rows send to, "targets"), and per unknown its listed row, its target
/// entry and its slave flag. Views only, so that device code may capture it by value.
template <class MemorySpace> struct MultiPointView {
  LocalIndex numUnknowns = 0;
  Kokkos::View<LocalIndex *, MemorySpace> rows;      ///< m listed rows
  Kokkos::View<Offset *, MemorySpace> rowStart;      ///< m + 1
  Kokkos::View<LocalIndex *, MemorySpace> columns;   ///< entries of the listed rows
  Kokkos::View<double *, MemorySpace> values;        ///< their values
  Kokkos::View<double *, MemorySpace> offset;        ///< s at each listed row (m)
  Kokkos::View<LocalIndex *, MemorySpace> targets;   ///< unknowns appearing as entry columns
  Kokkos::View<Offset *, MemorySpace> targetStart;   ///< targets + 1
  Kokkos::View<LocalIndex *, MemorySpace> sourceRow; ///< listed row (0..m-1) sending to it
  Kokkos::View<double *, MemorySpace> sourceValue;   ///< T(rows(sourceRow), target)
  Kokkos::View<int *, MemorySpace> rowOf;            ///< per unknown: listed row or -1
  Kokkos::View<int *, MemorySpace> targetOf;         ///< per unknown: target entry or -1
  Kokkos::View<int *, MemorySpace> slave;            ///< per unknown: 1 at slaves
  LocalIndex numRows() const { return static_cast<LocalIndex>(rows.extent(0)); }
  bool empty() const { return rows.extent(0) == 0; }
};

/// The device form of T with the host key of its pattern (rows, row lengths, columns), by which
/// ConstraintElimination decides to reuse its symbolic phase. Built by toDevice from the host
/// description, uploading O(entries); the per-unknown views are filled on the device.
template <class MemorySpace> struct DeviceMultiPoint : MultiPointView<MemorySpace> {
  std::vector<LocalIndex> pattern;
  const MultiPointView<MemorySpace> &view() const { return *this; }
};

using DeviceMultiPointConstraints = DeviceMultiPoint<Kokkos::DefaultExecutionSpace::memory_space>;

/// The device form of `c` on `numUnknowns` unknowns.
DeviceMultiPointConstraints toDevice(const MultiPointConstraints &c, LocalIndex numUnknowns);

/// The eliminated system on the device: T^T A T + D, D = `slaveDiagonal` on the slaves' diagonal
/// (every diagonal entry present), and rhs <- T^T (rhs - A s), zero at the slaves. The symbolic
/// phase (the pattern of T^T A T) is kept and reused by the next call while the patterns of A
/// (its views) and of T (rows and columns) are unchanged.
class ConstraintElimination {
public:
  using Memory = Kokkos::DefaultExecutionSpace::memory_space;
  CsrMatrix<Memory> eliminate(const CsrMatrix<Memory> &a, const DeviceMultiPointConstraints &t,
                              double slaveDiagonal, const Kokkos::View<double *, Memory> &rhs);
  /// True when the last eliminate() reused the previous symbolic phase.
  bool reusedPattern() const { return reused_; }

private:
  CsrMatrix<Memory> pattern_; ///< the reduced pattern (values unused)
  std::vector<LocalIndex> key_;
  const Offset *aRows_ = nullptr;
  const LocalIndex *aColumns_ = nullptr;
  LocalIndex n_ = -1;
  bool reused_ = false;
};

/// x <- T y + s (y given in x).
void expandConstrained(
    const DeviceMultiPointConstraints &t,
    const Kokkos::View<double *, Kokkos::DefaultExecutionSpace::memory_space> &x);

/// v <- T^T v (condensed residual: the forces a constrained system balances), zero at slaves.
void condenseVector(const DeviceMultiPointConstraints &t,
                    const Kokkos::View<double *, Kokkos::DefaultExecutionSpace::memory_space> &v);

/// ||T^T g|| over the unknowns i with i % stride < 2 held neither by `flags` nor as slaves (a
/// device reduction; nothing copied).
double condensedFreeNorm(
    const DeviceMultiPointConstraints &t,
    const Kokkos::View<const double *, Kokkos::DefaultExecutionSpace::memory_space> &g,
    const Kokkos::View<const int *, Kokkos::DefaultExecutionSpace::memory_space> &flags,
    int stride);

} // namespace mixcon
