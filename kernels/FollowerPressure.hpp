// Follower pressures on the current boundary of a body and their load stiffness, for both
// models and both dimensions (Ndof unknowns per node, the displacements first): element edges
// in 2D (assembleFollowerPressure), element faces of solids (assembleFollowerFacePressure).
// The pressure acts normal to the deformed boundary, so the force depends on the nodal
// positions; its derivative (the load stiffness) is not symmetric. Derivations in
// docs/theory.md, "Follower pressure". Device code, no virtual calls. Layer: kernels.
#pragma once

#include <kernels/LinearElasticity.hpp>
#include <kernels/SparseMatrix.hpp>

namespace mixcon {

/// Follower pressure p (positive into the body) on element edges, on the current configuration:
/// nodal coordinates m.coordinates + u (u: displacement dofs `Ndof * node + i` of `u`).
/// Adds -f_ext to g (the residual is internal minus external force) and, when mat.numRows > 0,
/// the load stiffness -d f_ext / du to mat. The pressure force is linear in the nodal positions:
/// f_a = -p t int N_a (dy/ds, -dx/ds) ds.
template <int Ndof, class Elem, class ExecSpace, class MemorySpace, class Map>
void assembleFollowerPressure(const ExecSpace &exec, const MeshView<MemorySpace> &m,
                              const Kokkos::View<const double *, MemorySpace> &u,
                              const Kokkos::View<LocalIndex *[2], MemorySpace> &edges,
                              const Kokkos::View<const double *, MemorySpace> &pressure,
                              double scale, double thickness, const Map &map,
                              const CsrMatrix<MemorySpace> &mat,
                              const Kokkos::View<double *, MemorySpace> &g) {
  const bool tangent = mat.numRows > 0;
  Kokkos::parallel_for(
      "mixcon::kernels::followerPressure", Kokkos::RangePolicy<ExecSpace>(exec, 0, edges.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        constexpr int ne = Elem::kNodesPerEdge;
        const LocalIndex e = edges(k, 0);
        const int edge = edges(k, 1);
        const double p = scale * pressure(k) * thickness;
        int local[ne];
        LocalIndex nodes[ne];
        double xe[ne][2], fe[ne][2] = {}, kab[ne][ne] = {};
        for (int a = 0; a < ne; ++a) {
          local[a] = Elem::edgeNode(edge, a);
          nodes[a] = m.connectivity(e, local[a]);
          for (int i = 0; i < 2; ++i)
            xe[a][i] = m.coordinates(nodes[a], i) + u(Ndof * nodes[a] + i);
        }
        for (int q = 0; q < Elem::kNumEdgeQp; ++q) {
          double s, w, sh[ne], ds[ne];
          detail::gauss1d(Elem::kNumEdgeQp, q, s, w);
          edgeShape<ne>(s, sh, ds);
          double tx = 0.0, ty = 0.0;
          for (int a = 0; a < ne; ++a) {
            tx += ds[a] * xe[a][0];
            ty += ds[a] * xe[a][1];
          }
          for (int a = 0; a < ne; ++a) {
            fe[a][0] -= p * w * sh[a] * ty;
            fe[a][1] += p * w * sh[a] * tx;
            for (int b = 0; b < ne; ++b)
              kab[a][b] += p * w * sh[a] * ds[b];
          }
        }
        for (int a = 0; a < ne; ++a)
          for (int i = 0; i < 2; ++i)
            Kokkos::atomic_add(&g(Ndof * nodes[a] + i), -fe[a][i]);
        if (!tangent)
          return;
        // -d f_ax / d y_b = p t int N_a dN_b/ds, -d f_ay / d x_b = -p t int N_a dN_b/ds.
        for (int a = 0; a < ne; ++a)
          for (int b = 0; b < ne; ++b) {
            const Offset base = Ndof * map(e, local[a], local[b]);
            Kokkos::atomic_add(&mat.values(mat.rowOffsets(Ndof * nodes[a]) + base + 1), kab[a][b]);
            Kokkos::atomic_add(&mat.values(mat.rowOffsets(Ndof * nodes[a] + 1) + base), -kab[a][b]);
          }
      });
}

/// Follower pressure p (positive into the body) on element faces of a solid, on the current
/// configuration (nodal coordinates m.coordinates + u, u's displacement dofs `Ndof * node + i`):
/// the 3D form of assembleFollowerPressure. faces(k) = (element, local face: Elem::sideNode).
/// The force f_a = -p int N_a (x_s x x_t) ds dt (x_s, x_t the face's tangents: their cross
/// product is the outward normal times the area element) is added as -f_ext to g and, when
/// mat.numRows > 0, its load stiffness -d f_ext / dx_b = p int N_a (N_b,t [x_s]x - N_b,s [x_t]x)
/// to mat ([v]x w = v x w).
template <int Ndof, class Elem, class ExecSpace, class MemorySpace, class Map>
void assembleFollowerFacePressure(const ExecSpace &exec, const MeshView<MemorySpace, 3> &m,
                                  const Kokkos::View<const double *, MemorySpace> &u,
                                  const Kokkos::View<LocalIndex *[2], MemorySpace> &faces,
                                  const Kokkos::View<const double *, MemorySpace> &pressure,
                                  double scale, const Map &map, const CsrMatrix<MemorySpace> &mat,
                                  const Kokkos::View<double *, MemorySpace> &g) {
  static_assert(Elem::kDim == 3, "the face form of assembleFollowerPressure");
  using Side = typename Elem::Side;
  const bool tangent = mat.numRows > 0;
  Kokkos::parallel_for(
      "mixcon::kernels::followerFacePressure",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, faces.extent(0)), KOKKOS_LAMBDA(LocalIndex k) {
        constexpr int nf = Side::kNumNodes;
        const LocalIndex e = faces(k, 0);
        const int face = faces(k, 1);
        const double p = scale * pressure(k);
        int local[nf];
        LocalIndex nodes[nf];
        double xf[nf][3], ge[nf][3] = {};
        // The face's load stiffness, summed over its quadrature points before the scatter (one
        // atomic per entry and face): ke[a][b][i][j] = d g_(a,i) / d x_(b,j).
        double ke[nf][nf][3][3]; // nf <= 8: 4.6 KB, zeroed only with a tangent
        if (tangent)
          for (int a = 0; a < nf; ++a)
            for (int b = 0; b < nf; ++b)
              for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                  ke[a][b][i][j] = 0.0;
        for (int a = 0; a < nf; ++a) {
          local[a] = Elem::sideNode(face, a);
          nodes[a] = m.connectivity(e, local[a]);
          for (int i = 0; i < 3; ++i)
            xf[a][i] = m.coordinates(nodes[a], i) + u(Ndof * nodes[a] + i);
        }
        for (int q = 0; q < Side::kNumQp; ++q) {
          double st[2], w, sh[nf], ds[nf][2];
          Side::quadraturePoint(q, st, w);
          Side::shape(st, sh, ds);
          double t1[3], t2[3], na[3];
          detail::faceFrame<nf>(xf, ds, t1, t2, na);
          for (int a = 0; a < nf; ++a)
            for (int i = 0; i < 3; ++i)
              ge[a][i] += p * w * sh[a] * na[i];
          if (!tangent)
            continue;
          // [v]x (i, m) = eps_ijm v_j.
          const double s1[3][3] = {
              {0.0, -t1[2], t1[1]}, {t1[2], 0.0, -t1[0]}, {-t1[1], t1[0], 0.0}};
          const double s2[3][3] = {
              {0.0, -t2[2], t2[1]}, {t2[2], 0.0, -t2[0]}, {-t2[1], t2[0], 0.0}};
          for (int a = 0; a < nf; ++a)
            for (int b = 0; b < nf; ++b) {
              const double c1 = p * w * sh[a] * ds[b][1], c2 = p * w * sh[a] * ds[b][0];
              for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                  ke[a][b][i][j] += c1 * s1[i][j] - c2 * s2[i][j];
            }
        }
        for (int a = 0; a < nf; ++a)
          for (int i = 0; i < 3; ++i)
            Kokkos::atomic_add(&g(Ndof * nodes[a] + i), ge[a][i]);
        if (!tangent)
          return;
        for (int a = 0; a < nf; ++a)
          for (int b = 0; b < nf; ++b) {
            const Offset base = Ndof * map(e, local[a], local[b]);
            for (int i = 0; i < 3; ++i) {
              const Offset row = mat.rowOffsets(Ndof * nodes[a] + i) + base;
              for (int j = 0; j < 3; ++j)
                Kokkos::atomic_add(&mat.values(row + j), ke[a][b][i][j]);
            }
          }
      });
}

} // namespace mixcon
