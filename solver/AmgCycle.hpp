// BoomerAMG's V-cycle run by mixcon's own kernels on a copy of the hierarchy hypre built: the
// same levels, interpolation, scaled Chebyshev smoothing and coarsest solve, in double or single
// precision, on the default execution space. hypre sets the hierarchy up; this copy applies it.
// What it changes against hypre's cycle (hypre_BoomerAMGCycle with relax type 16, 2.26):
// - a level's first smoothing starts from zero (every level of a preconditioning V-cycle does),
//   so its residual product with that zero is skipped: 2k products with A per level instead of
//   2k + 1 for Chebyshev order k (4 instead of 5 for hypre's default order 2);
// - the restriction multiplies by R = P^T stored as its own rows instead of hypre's transposed
//   product with P;
// - in single precision (LinearSolverOptions::cycle MixconSingle) the levels hold 4-byte values
//   and vectors: 8 bytes per nonzero instead of 12; the coarsest level's inverse stays double. The
//   Krylov method around it stays in double and is flexible (mixcon's CG, Notay's beta), so its
//   tolerance is A's as before.
// The host sees the levels through AmgHostCsr (non-owning, hypre's arrays or any other); the first
// level is mixcon's own matrix (device memory), so that a kept hierarchy takes new fine-level
// values without hypre. Data flow: solver.
#pragma once
#include <kernels/SparseMatrix.hpp>
#include <solver/LinearSolver.hpp>

#include <memory>
#include <string>
#include <vector>

namespace mixcon {

/// The precision of the V-cycle (problem key `amg_cycle`).
enum class AmgCyclePrecision { Double, Single };

/// A CSR matrix on the host, not owned (hypre's local diag block: int offsets and columns).
struct AmgHostCsr {
  const int *rowOffsets = nullptr;
  const int *columns = nullptr;
  const double *values = nullptr;
  int rows = 0;
  int columnsCount = 0;
};

/// One coarse level as hypre holds it after its setup: the level's matrix (unused for level 0,
/// which is the fine matrix given separately), the interpolation P to it from the coarser level
/// below (absent on the coarsest), the Chebyshev scaling ds = 1 / sqrt(|a_ii|) and the polynomial
/// coefficients (order = coefficients' count, 1 to 4) of hypre_ParCSRRelax_Cheby_Solve (on the
/// coarsest: none where it is solved exactly, hypre's usual coarsest solve).
struct HostAmgLevel {
  AmgHostCsr a;
  AmgHostCsr p;
  const double *ds = nullptr;
  std::vector<double> coefficients;
};

namespace detail {
template <class Scalar> struct AmgLevels;
} // namespace detail

class AmgCycle {
public:
  /// Copies the hierarchy: levels[0] describes the fine level, whose matrix is `fine` (device;
  /// with filterComponents = d > 1 only its entries (i, j) with i % d == j % d, the matrix of
  /// LinearSolverOptions::separateComponents); levels.back() is the coarsest, solved exactly by a
  /// dense inverse formed here, or, where it carries Chebyshev coefficients and a scaling (hypre's
  /// coarsest solve where its coarsening stopped early: one sweep of the smoother, relax type 16
  /// on the coarsest level), smoothed once from zero. In double precision without the filter the
  /// fine level shares `fine`'s views (its values changed in place are seen). With fineBlocks
  /// (nodeBlocks(fine, d)) and no filter the fine level's products read one column per node block;
  /// with the filter (d = fineBlocks.d) on a host-accessible space the filtered level keeps each
  /// block's d diagonal entries side by side, one column per block, and reads a node's d rows in
  /// one pass (elsewhere it keeps its own CSR). Throws std::runtime_error where the levels do not
  /// fit together or the coarsest matrix is singular to working precision.
  AmgCycle(const CsrMatrix<DeviceSpace> &fine, int filterComponents,
           const std::vector<HostAmgLevel> &levels, AmgCyclePrecision precision,
           const NodeBlocks<DeviceSpace> &fineBlocks = {});
  ~AmgCycle();
  AmgCycle(const AmgCycle &) = delete;
  AmgCycle &operator=(const AmgCycle &) = delete;

  /// New values of the fine matrix, same rows (a kept hierarchy: the coarse levels and the
  /// smoothing coefficients stay, as in hypre's cycle after IJMatrixSetValues on its level 0).
  void setFineMatrix(const CsrMatrix<DeviceSpace> &fine);

  /// x = B b: one V-cycle from a zero initial guess (x and b distinct: in double precision the
  /// fine level reads b and iterates in x).
  void apply(const Kokkos::View<const double *, DeviceSpace> &b,
             const Kokkos::View<double *, DeviceSpace> &x);

  int levels() const;
  /// Whether the fine level's products go by node blocks (the blocks given fit).
  bool fineLevelByNodeBlocks() const;
  /// Bytes held on the device by the copy (matrices, transposes, vectors, the dense inverse).
  std::size_t bytes() const;
  AmgCyclePrecision precision() const { return precision_; }

private:
  AmgCyclePrecision precision_;
  std::unique_ptr<detail::AmgLevels<double>> double_;
  std::unique_ptr<detail::AmgLevels<float>> single_;
};

std::string amgCyclePrecisionName(AmgCyclePrecision p);

} // namespace mixcon
