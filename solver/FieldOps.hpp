// Operations on interleaved fields: vectors and CSR matrices whose unknowns come `stride` per
// node (the displacement pair first, then e.g. the mixed model's stresses). Norms, gathers and
// scatters of one field, diagonals, blocks and row products of one field of a matrix, the
// constrained solve of a correction. Device kernels on DeviceSpace views; used by the nonlinear
// models (solver/) and the contact enforcements (contact/). Layer: solver.
#pragma once

#include <solver/LinearSolver.hpp>

#include <kernels/SparseMatrix.hpp>

#include <chrono>
#include <vector>

namespace mixcon {
namespace fieldops {

using Exec = Kokkos::DefaultExecutionSpace;
using Memory = DeviceSpace;
using Vec = Kokkos::View<double *, Memory>;
using ConstVec = Kokkos::View<const double *, Memory>;

/// The models' per-node layout (ModelLayout, solver/DofMap.hpp) as the (stride, offset, width)
/// arguments below take it: kDisp displacements per node (the displacement model's stride), the
/// mixed model's kMixed unknowns per node with its kDisp displacements at offset 0 and its kStress
/// Voigt stresses at kStressAt.
inline constexpr int kDisp = ModelLayout::kNumDisplacements;
inline constexpr int kStress = ModelLayout::kNumStresses;
inline constexpr int kMixed = ModelLayout::kMixedUnknowns;
inline constexpr int kStressAt = ModelLayout::kStressOffset;

/// The row (or entry) of the i-th unknown of one field of an interleaved vector or matrix: the
/// `width` unknowns from `offset` of every `stride`.
KOKKOS_INLINE_FUNCTION LocalIndex fieldRow(int stride, int offset, int width, LocalIndex i) {
  return stride * (i / width) + offset + i % width;
}

/// dst(stride k + offset + c) = src(width k + c); other entries of dst set to zero when
/// `zeroRest` (the inverse of gather).
template <class T>
void scatter(const Kokkos::View<const T *, Memory> &src, int stride, int offset, int width,
             const Kokkos::View<T *, Memory> &dst, bool zeroRest) {
  if (zeroRest)
    Kokkos::deep_copy(dst, T(0));
  Kokkos::parallel_for(
      "mixcon::nonlinear::scatter", Kokkos::RangePolicy<Exec>(0, src.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { dst(fieldRow(stride, offset, width, i)) = src(i); });
}

/// Seconds since `start`.
double seconds(std::chrono::steady_clock::time_point start);

/// Two-norm of the first `width` of every `stride` entries of v, restricted to entries whose
/// flag is `flagged` (flags: nullptr-like empty view means all).
double strideNorm(const ConstVec &v, int stride, int first, int width,
                  const Kokkos::View<const int *, Memory> &flags, int flagged);

/// num / den; 0 for 0 / 0 and infinity for a positive num over a zero den.
double relative(double num, double den);

/// y(stride k + c) += alpha x(width k + c), c < width: a displacement vector (width per node,
/// e.g. the load) into an interleaved one.
void addDisplacementVector(const Vec &y, int stride, int width, double alpha, const ConstVec &x);

/// out = base + lambda x, elementwise (a stage's applied values).
void affine(const ConstVec &base, double lambda, const ConstVec &x, const Vec &out);

/// ||base + lambda x||_2.
double affineNorm(const ConstVec &base, double lambda, const ConstVec &x);

/// dst(width k + c) = scale src(stride k + offset + c), k < dst.extent(0) / width (gathers a
/// field out of an interleaved vector, e.g. the stresses out of the mixed model's kMixed unknowns
/// per node).
void gather(const ConstVec &src, int stride, int offset, int width, const Vec &dst,
            double scale = 1.0);

/// dst(i) = sign a(r, r), r = stride (i / width) + offset + i % width: diagonal entries of the
/// rows of one field of an interleaved CSR matrix.
void fieldDiagonal(const CsrMatrix<Memory> &a, int stride, int offset, int width, const Vec &dst,
                   double sign);

/// b <- sign * (the block of a's field rows [rowOffset, rowOffset + rowWidth) and field
/// columns [columnOffset, columnOffset + columnWidth)), with a on expandGraph(graph, stride) and b
/// on expandGraph(graph, rowWidth, columnWidth) of the same graph (both list a row's neighbour
/// nodes in the same order).
void extractFieldBlock(const CsrMatrix<Memory> &a, int stride, int rowOffset, int rowWidth,
                       int columnOffset, int columnWidth, const CsrMatrix<Memory> &b, double sign);

/// y(width p + c) = sum_k a(r, k) x(k), r = stride p + offset + c: the rows of one field of an
/// interleaved CSR matrix times x, gathered (a product with [A B] or [C -M] of the mixed
/// Jacobian that reads only those rows).
void multiplyFieldRows(const CsrMatrix<Memory> &a, int stride, int offset, int width,
                       const ConstVec &x, const Vec &y);

/// v(stride p + offset + c) *= s for c < width.
void scaleField(const Vec &v, int stride, int offset, int width, double s);

/// blocks(p) = node p's kStress x kStress diagonal block of m (kStress unknowns per node,
/// pattern of expandGraph(graph, kStress)); kernels/MixedElasticity.hpp inverts and applies such
/// blocks.
void nodalDiagonalBlocks(const CsrMatrix<Memory> &m,
                         const Kokkos::View<double *[kStress][kStress], Memory> &blocks);

/// y = x / d, entry by entry (Jacobi).
void divide(const ConstVec &x, const ConstVec &d, const Vec &y);

/// out(k, i) = base(k, i) + x(stride k + i), i < base.extent(1) (the dimension): node
/// coordinates moved by the displacement unknowns of x (out may be base).
void movedCoordinates(const Kokkos::View<const double **, Memory> &base, const ConstVec &x,
                      int stride, const Kokkos::View<double **, Memory> &out);

/// The remaining prescribed change of every constrained unknown: t(stride k + c) =
/// lambda g(width k + c) - u(width k + c) where flags(stride k + c) != 0 (c < width: only
/// displacement unknowns are flagged), 0 elsewhere; g and u hold `width` displacements per node.
/// With `base` (stages; empty: none) the prescribed values are base + lambda g.
void prescribedStep(const Kokkos::View<const int *, Memory> &flags, const ConstVec &g,
                    const ConstVec &u, double lambda, int stride, int width, const Vec &t,
                    const ConstVec &base = {});

/// Solves the constrained tangent for the correction: rhs = -g on free rows; prescribed rows
/// reach `target` (the remaining prescribed change). A freshly assembled tangent is constrained
/// and handed to the solver; a reused one (modified Newton) keeps its factorization.
LinearSolveStats constrainedSolve(const CsrMatrix<Memory> &tangent, bool fresh,
                                  CsrMatrix<Memory> &work,
                                  const Kokkos::View<const int *, Memory> &flags, const ConstVec &g,
                                  const ConstVec &target, const Vec &rhs, const Vec &diag,
                                  LinearSolver &solver, const Vec &dx, double &setupSeconds);

/// g(stride k + c) -= f(kDisp k + c), c < kDisp: nodal forces (e.g. friction, host)
/// subtracted from the displacement rows of a residual.
void subtractNodalForces(const Vec &g, int stride, const std::vector<double> &f);

} // namespace fieldops
} // namespace mixcon
