// Nodal local frames ("skew" coordinates) for assembled systems: at selected nodes the two
// displacement unknowns are expressed in a local orthonormal frame (n, t) — for contact with a
// rigid obstacle the surface normal and tangent, so that "held on the obstacle" and "stick" become
// ordinary prescribed components and "slip" a free one (the report's polar-Cartesian local
// coordinates). With R_p = [n t] (columns) at framed nodes and I elsewhere, the system A x = b
// becomes (R^T A R) x~ = R^T b and x = R x~. Works on CSR patterns from expandGraph(graph, ndof)
// (node-major, `ndof` interleaved unknowns per node, displacements first); the other unknowns of
// a node (stresses of the mixed model) are untouched. One thread per node row: race free.
// The tangents of a frame come from one function, tangentBasis<Dim>(n) (2D: t = (-n_y, n_x);
// 3D: two orthonormal tangents completing n to a right-handed frame), which contact frames use
// too. Data flow: solver (used by contact).
#pragma once

#include <kernels/SparseMatrix.hpp>

namespace mixcon {

/// The unit tangents t[0..Dim-2] completing the unit normal n to an orthonormal right-handed
/// frame (n, t...). 2D: t = (-n_y, n_x). 3D: t0 = normalized (a x n) with a the coordinate axis
/// least aligned with n (well conditioned for every n), t1 = n x t0, so that (n, t0, t1) is
/// right-handed.
template <int Dim>
KOKKOS_INLINE_FUNCTION void tangentBasis(const double (&n)[Dim], double (&t)[Dim - 1][Dim]) {
  static_assert(Dim == 2 || Dim == 3, "tangentBasis: 2D or 3D");
  if constexpr (Dim == 2) {
    t[0][0] = -n[1];
    t[0][1] = n[0];
  } else {
    const double ax = n[0] < 0 ? -n[0] : n[0], ay = n[1] < 0 ? -n[1] : n[1],
                 az = n[2] < 0 ? -n[2] : n[2];
    const int k = ax <= ay && ax <= az ? 0 : (ay <= az ? 1 : 2);
    double a[3] = {0.0, 0.0, 0.0};
    a[k] = 1.0;
    double u[3] = {a[1] * n[2] - a[2] * n[1], a[2] * n[0] - a[0] * n[2], a[0] * n[1] - a[1] * n[0]};
    const double l = detail::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int i = 0; i < 3; ++i)
      t[0][i] = u[i] / l;
    t[1][0] = n[1] * t[0][2] - n[2] * t[0][1];
    t[1][1] = n[2] * t[0][0] - n[0] * t[0][2];
    t[1][2] = n[0] * t[0][1] - n[1] * t[0][0];
  }
}

/// A <- R^T A R and, if b is not empty, b <- R^T b. `normal(p)` is n of node p (t from
/// tangentBasis), used where framed(p) != 0.
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
        const double np[2] = {normal(p, 0), normal(p, 1)};
        double tp[1][2];
        tangentBasis<2>(np, tp);
        for (int j = 0; j < neighbours; ++j) {
          const LocalIndex q = co(first + ndof * j) / ndof;
          const bool fq = framed(q) != 0;
          if (!fp && !fq)
            continue;
          const double nq[2] = {normal(q, 0), normal(q, 1)};
          double tq[1][2];
          tangentBasis<2>(nq, tq);
          // Rows (p, 0..1): left-multiply by R_p^T, over every column of the block.
          if (fp)
            for (int c = 0; c < ndof; ++c) {
              const Offset k0 = ro(ndof * p) + ndof * j + c, k1 = ro(ndof * p + 1) + ndof * j + c;
              const double v0 = va(k0), v1 = va(k1);
              va(k0) = np[0] * v0 + np[1] * v1;       // n . v
              va(k1) = tp[0][0] * v0 + tp[0][1] * v1; // t . v
            }
          // Columns (q, 0..1): right-multiply by R_q, over every row of the block.
          if (fq)
            for (int r = 0; r < ndof; ++r) {
              const Offset k = ro(ndof * p + r) + ndof * j;
              const double v0 = va(k), v1 = va(k + 1);
              va(k) = v0 * nq[0] + v1 * nq[1];
              va(k + 1) = v0 * tq[0][0] + v1 * tq[0][1];
            }
        }
        if (haveRhs && fp) {
          const double v0 = b(ndof * p), v1 = b(ndof * p + 1);
          b(ndof * p) = np[0] * v0 + np[1] * v1;
          b(ndof * p + 1) = tp[0][0] * v0 + tp[0][1] * v1;
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
        const double n[2] = {normal(p, 0), normal(p, 1)};
        double t[1][2];
        tangentBasis<2>(n, t);
        const double v0 = v(ndof * p), v1 = v(ndof * p + 1);
        v(ndof * p) = n[0] * v0 + n[1] * v1;
        v(ndof * p + 1) = t[0][0] * v0 + t[0][1] * v1;
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
        const double n[2] = {normal(p, 0), normal(p, 1)};
        double t[1][2];
        tangentBasis<2>(n, t);
        const double a = v(ndof * p), b = v(ndof * p + 1); // normal and tangential components
        v(ndof * p) = n[0] * a + t[0][0] * b;
        v(ndof * p + 1) = n[1] * a + t[0][1] * b;
      });
}

} // namespace mixcon
