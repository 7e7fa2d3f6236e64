// Nodal local frames ("skew" coordinates) for assembled systems: at selected nodes the two
// displacement unknowns are expressed in a local orthonormal frame (n, t) — for contact with a
// rigid obstacle the surface normal and tangent, so that "held on the obstacle" and "stick" become
// ordinary prescribed components and "slip" a free one (the report's polar-Cartesian local
// coordinates). With R_p = [n t] (columns) at framed nodes and I elsewhere, the system A x = b
// becomes (R^T A R) x~ = R^T b and x = R x~. Works on CSR patterns from expandGraph(graph, ndof)
// (node-major, `ndof` interleaved unknowns per node, displacements first); the other unknowns of
// a node (stresses of the mixed model) are untouched. One thread per node row: race free.
// Data flow: solver (used by contact).
#pragma once

#include <kernels/SparseMatrix.hpp>

namespace mixcon {

/// A <- R^T A R and, if b is not empty, b <- R^T b. `normal(p)` is n of node p (t = (-n_y, n_x)),
/// used where framed(p) != 0.
template <class ExecSpace, class MemorySpace>
void rotateToLocalFrames(const ExecSpace &exec, const CsrMatrix<MemorySpace> &a, int ndof,
                         const Kokkos::View<const int *, MemorySpace> &framed,
                         const Kokkos::View<const double *[2], MemorySpace> &normal,
                         const Kokkos::View<double *, MemorySpace> &b) {
  auto ro = a.rowOffsets;
  auto co = a.columns;
  auto va = a.values;
  const bool haveRhs = b.extent(0) > 0;
  Kokkos::parallel_for(
      "mixcon::solver::rotateToLocalFrames",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, a.numRows / ndof), KOKKOS_LAMBDA(LocalIndex p) {
        const Offset first = ro(ndof * p);
        const int neighbours = static_cast<int>((ro(ndof * p + 1) - first) / ndof);
        const bool fp = framed(p) != 0;
        const double np0 = normal(p, 0), np1 = normal(p, 1);
        for (int j = 0; j < neighbours; ++j) {
          const LocalIndex q = co(first + ndof * j) / ndof;
          const bool fq = framed(q) != 0;
          if (!fp && !fq)
            continue;
          const double nq0 = normal(q, 0), nq1 = normal(q, 1);
          // Rows (p, 0..1): left-multiply by R_p^T, over every column of the block.
          if (fp)
            for (int c = 0; c < ndof; ++c) {
              const Offset k0 = ro(ndof * p) + ndof * j + c, k1 = ro(ndof * p + 1) + ndof * j + c;
              const double v0 = va(k0), v1 = va(k1);
              va(k0) = np0 * v0 + np1 * v1;  // n . v
              va(k1) = -np1 * v0 + np0 * v1; // t . v
            }
          // Columns (q, 0..1): right-multiply by R_q, over every row of the block.
          if (fq)
            for (int r = 0; r < ndof; ++r) {
              const Offset k = ro(ndof * p + r) + ndof * j;
              const double v0 = va(k), v1 = va(k + 1);
              va(k) = v0 * nq0 + v1 * nq1;
              va(k + 1) = -v0 * nq1 + v1 * nq0;
            }
        }
        if (haveRhs && fp) {
          const double v0 = b(ndof * p), v1 = b(ndof * p + 1);
          b(ndof * p) = np0 * v0 + np1 * v1;
          b(ndof * p + 1) = -np1 * v0 + np0 * v1;
        }
      });
}

/// v <- R^T v (global -> local components) at framed nodes.
template <class ExecSpace, class MemorySpace>
void toLocalFrames(const ExecSpace &exec, int ndof,
                   const Kokkos::View<const int *, MemorySpace> &framed,
                   const Kokkos::View<const double *[2], MemorySpace> &normal,
                   const Kokkos::View<double *, MemorySpace> &v) {
  Kokkos::parallel_for(
      "mixcon::solver::toLocalFrames", Kokkos::RangePolicy<ExecSpace>(exec, 0, framed.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        if (!framed(p))
          return;
        const double n0 = normal(p, 0), n1 = normal(p, 1);
        const double v0 = v(ndof * p), v1 = v(ndof * p + 1);
        v(ndof * p) = n0 * v0 + n1 * v1;
        v(ndof * p + 1) = -n1 * v0 + n0 * v1;
      });
}

/// v <- R v (local -> global components) at framed nodes.
template <class ExecSpace, class MemorySpace>
void fromLocalFrames(const ExecSpace &exec, int ndof,
                     const Kokkos::View<const int *, MemorySpace> &framed,
                     const Kokkos::View<const double *[2], MemorySpace> &normal,
                     const Kokkos::View<double *, MemorySpace> &v) {
  Kokkos::parallel_for(
      "mixcon::solver::fromLocalFrames", Kokkos::RangePolicy<ExecSpace>(exec, 0, framed.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        if (!framed(p))
          return;
        const double n0 = normal(p, 0), n1 = normal(p, 1);
        const double a = v(ndof * p), t = v(ndof * p + 1); // normal and tangential components
        v(ndof * p) = n0 * a - n1 * t;
        v(ndof * p + 1) = n1 * a + n0 * t;
      });
}

} // namespace mixcon
