// Operations on interleaved fields (solver/FieldOps.hpp).
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/Krylov.hpp>
#include <solver/ModelBase.hpp>

#include <cmath>
#include <limits>

namespace mixcon {
namespace fieldops {

double seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Two-norm of the first `width` of every `stride` entries of v, restricted to entries whose
/// flag is `flagged` (flags: nullptr-like empty view means all).
double strideNorm(const ConstVec &v, int stride, int first, int width,
                  const Kokkos::View<const int *, Memory> &flags, int flagged) {
  const LocalIndex n = v.extent(0) / stride;
  const bool useFlags = flags.extent(0) > 0;
  double s = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::nonlinear::norm", Kokkos::RangePolicy<Exec>(0, n),
      KOKKOS_LAMBDA(LocalIndex k, double &acc) {
        for (int c = first; c < first + width; ++c) {
          const LocalIndex i = stride * k + c;
          if (!useFlags || (flags(i) != 0) == (flagged != 0))
            acc += v(i) * v(i);
        }
      },
      s);
  return std::sqrt(s);
}

double relative(double num, double den) {
  if (den > 0.0)
    return num / den;
  return num == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
}

void affine(const ConstVec &base, double lambda, const ConstVec &x, const Vec &out) {
  Kokkos::parallel_for(
      "mixcon::fieldops::affine", Kokkos::RangePolicy<Exec>(0, out.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { out(i) = base(i) + lambda * x(i); });
}

double affineNorm(const ConstVec &base, double lambda, const ConstVec &x) {
  double sum = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::fieldops::affineNorm", Kokkos::RangePolicy<Exec>(0, x.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i, double &s) {
        const double v = base(i) + lambda * x(i);
        s += v * v;
      },
      sum);
  return std::sqrt(sum);
}

/// y(stride k + c) += alpha x(width k + c), c < width.
void addDisplacementVector(const Vec &y, int stride, int width, double alpha, const ConstVec &x) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::addDisplacementVector", Kokkos::RangePolicy<Exec>(0, x.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { y(stride * (i / width) + i % width) += alpha * x(i); });
}

/// dst(width k + c) = scale src(stride k + offset + c), k < dst.extent(0) / width (gathers a
/// field out of an interleaved vector, e.g. the stresses out of 5 unknowns per node).
void gather(const ConstVec &src, int stride, int offset, int width, const Vec &dst, double scale) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::gather", Kokkos::RangePolicy<Exec>(0, dst.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { dst(i) = scale * src(fieldRow(stride, offset, width, i)); });
}

/// dst(i) = sign a(r, r), r = stride (i / width) + offset + i % width: diagonal entries of the
/// rows of one field of an interleaved CSR matrix.
void fieldDiagonal(const CsrMatrix<Memory> &a, int stride, int offset, int width, const Vec &dst,
                   double sign) {
  auto ro = a.rowOffsets;
  auto co = a.columns;
  auto va = a.values;
  Kokkos::parallel_for(
      "mixcon::nonlinear::fieldDiagonal", Kokkos::RangePolicy<Exec>(0, dst.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) {
        const LocalIndex r = fieldRow(stride, offset, width, i);
        for (Offset k = ro(r); k < ro(r + 1); ++k)
          if (co(k) == r)
            dst(i) = sign * va(k);
      });
}

/// b <- sign * (the block of a's field rows [rowOffset, rowOffset + rowWidth) and field
/// columns [columnOffset, columnOffset + columnWidth)), with a on expandGraph(graph, stride) and b
/// on expandGraph(graph, rowWidth, columnWidth) of the same graph (both list a row's neighbour
/// nodes in the same order).
void extractFieldBlock(const CsrMatrix<Memory> &a, int stride, int rowOffset, int rowWidth,
                       int columnOffset, int columnWidth, const CsrMatrix<Memory> &b, double sign) {
  auto ra = a.rowOffsets;
  auto va = a.values;
  auto rb = b.rowOffsets;
  auto vb = b.values;
  Kokkos::parallel_for(
      "mixcon::nonlinear::extractFieldBlock", Kokkos::RangePolicy<Exec>(0, b.numRows),
      KOKKOS_LAMBDA(LocalIndex r) {
        const LocalIndex p = r / rowWidth, i = r % rowWidth;
        const Offset first = rb(r);
        const LocalIndex neighbours = static_cast<LocalIndex>((rb(r + 1) - first) / columnWidth);
        const Offset src = ra(stride * p + rowOffset + i);
        for (LocalIndex j = 0; j < neighbours; ++j)
          for (int c = 0; c < columnWidth; ++c)
            vb(first + columnWidth * j + c) = sign * va(src + stride * j + columnOffset + c);
      });
}

/// y(width p + c) = sum_k a(r, k) x(k), r = stride p + offset + c: the rows of one field of an
/// interleaved CSR matrix times x, gathered (a product with [A B] or [C -M] of the mixed
/// Jacobian that reads only those rows).
void multiplyFieldRows(const CsrMatrix<Memory> &a, int stride, int offset, int width,
                       const ConstVec &x, const Vec &y) {
  auto ro = a.rowOffsets;
  auto co = a.columns;
  auto va = a.values;
  Kokkos::parallel_for(
      "mixcon::nonlinear::multiplyFieldRows", Kokkos::RangePolicy<Exec>(0, y.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) {
        const LocalIndex r = fieldRow(stride, offset, width, i);
        double s = 0.0;
        for (Offset k = ro(r); k < ro(r + 1); ++k)
          s += va(k) * x(co(k));
        y(i) = s;
      });
}

/// v(stride p + offset + c) *= s for c < width.
void scaleField(const Vec &v, int stride, int offset, int width, double s) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::scaleField", Kokkos::RangePolicy<Exec>(0, v.extent(0) / stride),
      KOKKOS_LAMBDA(LocalIndex p) {
        for (int c = 0; c < width; ++c)
          v(stride * p + offset + c) *= s;
      });
}

/// blocks(p) = node p's kStress x kStress diagonal block of m (kStress unknowns per node,
/// pattern of expandGraph(graph, kStress)).
void nodalDiagonalBlocks(const CsrMatrix<Memory> &m,
                         const Kokkos::View<double *[kStress][kStress], Memory> &blocks) {
  auto ro = m.rowOffsets;
  auto co = m.columns;
  auto va = m.values;
  Kokkos::parallel_for(
      "mixcon::nonlinear::nodalDiagonalBlocks", Kokkos::RangePolicy<Exec>(0, blocks.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        for (int i = 0; i < kStress; ++i)
          for (Offset k = ro(kStress * p + i); k < ro(kStress * p + i + 1); ++k) {
            const LocalIndex c = co(k);
            if (c / kStress == p)
              blocks(p, i, c % kStress) = va(k);
          }
      });
}

/// y = x / d, entry by entry (Jacobi).
void divide(const ConstVec &x, const ConstVec &d, const Vec &y) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::divide", Kokkos::RangePolicy<Exec>(0, y.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { y(i) = x(i) / d(i); });
}

/// out(k, i) = base(k, i) + x(stride k + i): node coordinates moved by the displacement
/// unknowns of x (out may be base).
void movedCoordinates(const Kokkos::View<const double **, Memory> &base, const ConstVec &x,
                      int stride, const Kokkos::View<double **, Memory> &out) {
  const int dim = static_cast<int>(base.extent(1));
  Kokkos::parallel_for(
      "mixcon::nonlinear::movedCoordinates", Kokkos::RangePolicy<Exec>(0, out.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        for (int i = 0; i < dim; ++i)
          out(k, i) = base(k, i) + x(stride * k + i);
      });
}

/// The remaining prescribed change of every constrained unknown: t(stride k + c) =
/// lambda g(width k + c) - u(width k + c) where flags(stride k + c) != 0 (c < width), 0
/// elsewhere.
void prescribedStep(const Kokkos::View<const int *, Memory> &flags, const ConstVec &g,
                    const ConstVec &u, double lambda, int stride, int width, const Vec &t,
                    const ConstVec &base) {
  const bool hasBase = base.extent(0) > 0;
  Kokkos::parallel_for(
      "mixcon::nonlinear::prescribedStep", Kokkos::RangePolicy<Exec>(0, t.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) {
        // the displacement dof when i % stride < width
        const LocalIndex j = width * (i / stride) + i % stride;
        t(i) = flags(i) ? (hasBase ? base(j) : 0.0) + lambda * g(j) - u(j) : 0.0;
      });
}

/// Solves the constrained tangent for the correction: rhs = -g on free rows; prescribed rows
/// reach `target` (the remaining prescribed change). A freshly assembled tangent is constrained
/// and handed to the solver; a reused one (modified Newton) keeps its factorization.
LinearSolveStats constrainedSolve(const CsrMatrix<Memory> &tangent, bool fresh,
                                  CsrMatrix<Memory> &work,
                                  const Kokkos::View<const int *, Memory> &flags, const ConstVec &g,
                                  const ConstVec &target, const Vec &rhs, const Vec &diag,
                                  LinearSolver &solver, const Vec &dx, double &setupSeconds) {
  axpby(-1.0, g, 0.0, rhs);
  if (fresh) {
    const auto start = std::chrono::steady_clock::now();
    if (work.numRows == 0)
      work = cloneValues(tangent);
    else
      Kokkos::deep_copy(work.values, tangent.values);
    applyDirichlet(Exec(), work, flags, target, rhs);
    constrainedDiagonal(Exec(), work, flags, diag);
    Exec().fence();
    solver.setup(work);
    setupSeconds += seconds(start);
  } else {
    Kokkos::parallel_for(
        "mixcon::nonlinear::constrainedRhs", Kokkos::RangePolicy<Exec>(0, g.extent(0)),
        KOKKOS_LAMBDA(LocalIndex i) {
          if (flags(i))
            rhs(i) = diag(i) * target(i);
        });
  }
  return solver.solve(rhs, dx);
}

void subtractNodalForces(const Vec &g, int stride, const std::vector<double> &f) {
  Vec fd("mixcon::nonlinear::friction", f.size());
  auto h = hostMirror(fd);
  for (std::size_t i = 0; i < f.size(); ++i)
    h(i) = f[i];
  copyToDevice(fd, h);
  Vec spread("mixcon::nonlinear::frictionSpread", g.extent(0));
  scatter<double>(fd, stride, 0, kDisp, spread, true);
  axpby(-1.0, spread, 1.0, g);
}

} // namespace fieldops
} // namespace mixcon
