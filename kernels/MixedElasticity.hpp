// Batched element kernels of the mixed (Hellinger-Reissner) model, Eq. (29)-(32) of the report:
// displacements and stresses are both interpolated with the same shape functions psi (equal
// order, 5 unknowns per node: u, v, Sxx, Syy, Sxy). Blocks:
//   coupling   K12 = t int [B^L]^T [psi^sigma] dA          (2n x 3n per element)
//   compliance K22 = t int [psi^sigma]^T [D] [psi^sigma] dA (3n x 3n, D = C^-1; the mixed system
//              carries it as -M)
//   geometric  K11 = t int [B^sigma]^T [tau] [B^sigma] dA  (tau interpolated from nodal stresses)
//   F^NL       = t int [B^L]^T {tau} dA
// Because the stress interpolation is psi times the 3x3 identity and D is constant per element,
// every block factors into scalar integrals: K12 into Gx[a][b] = t int dpsi_a/dx psi_b dA and
// Gy[a][b], K22 into the scalar mass m[a][b] = t int psi_a psi_b dA times D. The assembled
// operators keep that factorization (two scalars per node pair for the coupling instead of six).
// Data flow: mesh -> kernels (this) -> solver (MixedModel).
#pragma once

#include <core/Transfer.hpp>
#include <kernels/GeometricStiffness.hpp>

namespace mixcon {

/// How the compliance mass is lumped to 3x3 nodal blocks.
enum class MassLumping {
  RowSum, ///< m_L,a = sum_b m_ab: positive for Quad4, keeps constant stress states exact
  Hrz     ///< Hinton-Rock-Zienkiewicz: m_L,a = m_aa * (sum_ab m_ab) / (sum_c m_cc), positive
};

/// Mixed-element traits: the stress interpolation paired with a displacement element (equal
/// order, Mirza-Olson complete) and the lumping rule of its compliance mass. Quad8 serendipity row
/// sums are negative at the corners (-1/12 of the area on a rectangle), so Quad8 uses HRZ.
/// Only row sums keep constant stress states exact (M_L 1 = M 1 is what a constant stress field
/// needs, and no positive diagonal matches Quad8's negative corner row sums): HRZ-lumped Quad8
/// fails the patch test, so it serves as a preconditioner only, never as the model's M.
template <class Elem> struct MixedTraits;
template <> struct MixedTraits<Quad4> {
  using StressElement = Quad4;
  static constexpr MassLumping kLumping = MassLumping::RowSum;
};
template <> struct MixedTraits<Quad8> {
  using StressElement = Quad8;
  static constexpr MassLumping kLumping = MassLumping::Hrz;
};

/// The lumping rule of an element type (host).
MassLumping massLumping(ElementType type);

/// Throws InputError unless (displacement, stress) interpolations form a pairing mixcon
/// implements: equal order. Quad8 displacements with Quad4 stresses violate the Mirza-Olson
/// completeness criterion (the bilinear stress field cannot represent the strains of the
/// quadratic displacement field); Quad4 displacements with Quad8 stresses have more stress than
/// strain modes per element (a singular saddle-point system).
void checkMixedPairing(ElementType displacement, ElementType stress);

/// Element data of the mixed model: that of the displacement model plus the compliance
/// D = C^-1 per material.
template <class MemorySpace> struct MixedElementData : ElementData<MemorySpace> {
  Kokkos::View<PlaneMatrix *, MemorySpace> compliance;
};

/// Scalar integrals of element e: gx[a][b] = t int dpsi_a/dx psi_b, gy[a][b] = t int dpsi_a/dy
/// psi_b and m[a][b] = t int psi_a psi_b over the element (a: displacement node, b: stress node).
template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void mixedIntegrals(const MeshView<MemorySpace> &mesh, LocalIndex e,
                                           double thickness,
                                           double (&gx)[Elem::kNumNodes][Elem::kNumNodes],
                                           double (&gy)[Elem::kNumNodes][Elem::kNumNodes],
                                           double (&m)[Elem::kNumNodes][Elem::kNumNodes]) {
  constexpr int n = Elem::kNumNodes;
  double xe[n][2];
  detail::gatherCoordinates<Elem>(mesh, e, xe);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      gx[a][b] = gy[a][b] = m[a][b] = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double xi, eta, w, sh[n], dn[n][2], g[n][2];
    Elem::quadraturePoint(q, xi, eta, w);
    Elem::shape(xi, eta, sh, dn);
    const double f = thickness * w * physicalGradients<Elem>(xe, dn, g);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        gx[a][b] += g[a][0] * sh[b] * f;
        gy[a][b] += g[a][1] * sh[b] * f;
        m[a][b] += sh[a] * sh[b] * f;
      }
  }
}

/// Lumped scalar mass of one element by the element's lumping rule (MixedTraits).
template <class Elem>
KOKKOS_INLINE_FUNCTION void lumpMass(const double (&m)[Elem::kNumNodes][Elem::kNumNodes],
                                     double (&ml)[Elem::kNumNodes]) {
  constexpr int n = Elem::kNumNodes;
  if constexpr (MixedTraits<Elem>::kLumping == MassLumping::RowSum) {
    for (int a = 0; a < n; ++a) {
      ml[a] = 0.0;
      for (int b = 0; b < n; ++b)
        ml[a] += m[a][b];
    }
  } else {
    double total = 0.0, diagonal = 0.0;
    for (int a = 0; a < n; ++a) {
      diagonal += m[a][a];
      for (int b = 0; b < n; ++b)
        total += m[a][b];
    }
    for (int a = 0; a < n; ++a)
      ml[a] = m[a][a] * total / diagonal;
  }
}

/// Everything the mixed kernels need of one element: the scalar integrals, the lumped masses and
/// the element's compliance.
template <class Elem> struct MixedElementBlocks {
  double gx[Elem::kNumNodes][Elem::kNumNodes], gy[Elem::kNumNodes][Elem::kNumNodes];
  double m[Elem::kNumNodes][Elem::kNumNodes], ml[Elem::kNumNodes];
  PlaneMatrix d;
};

template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void mixedElementBlocks(const MixedElementData<MemorySpace> &d, LocalIndex e,
                                               MixedElementBlocks<Elem> &b) {
  mixedIntegrals<Elem>(d.mesh, e, d.thickness, b.gx, b.gy, b.m);
  lumpMass<Elem>(b.m, b.ml);
  b.d = d.compliance(d.material(e));
}

/// Element matrices of all elements: k12(e) (2n x 3n, dofs u_a,v_a by Sxx_b,Syy_b,Sxy_b),
/// k22(e) = t int psi^T D psi (3n x 3n) and its lumped counterpart k22l(e) (3n x 3n, 3x3 nodal
/// blocks on the diagonal).
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void computeMixedElementMatrices(const ExecSpace &exec, const MixedElementData<MemorySpace> &d,
                                 const Kokkos::View<double ***, P...> &k12,
                                 const Kokkos::View<double ***, P...> &k22,
                                 const Kokkos::View<double ***, P...> &k22l) {
  Kokkos::parallel_for(
      "mixcon::kernels::mixedElementMatrices",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes;
        MixedElementBlocks<Elem> blk;
        mixedElementBlocks<Elem>(d, e, blk);
        for (int a = 0; a < n; ++a)
          for (int b = 0; b < n; ++b) {
            // B_a^T = [dx 0 dy; 0 dy dx] times psi_b
            const double v[2][3] = {{blk.gx[a][b], 0.0, blk.gy[a][b]},
                                    {0.0, blk.gy[a][b], blk.gx[a][b]}};
            for (int i = 0; i < 2; ++i)
              for (int p = 0; p < 3; ++p)
                k12(e, 2 * a + i, 3 * b + p) = v[i][p];
            for (int p = 0; p < 3; ++p)
              for (int r = 0; r < 3; ++r) {
                k22(e, 3 * a + p, 3 * b + r) = blk.m[a][b] * blk.d.m[p][r];
                k22l(e, 3 * a + p, 3 * b + r) = a == b ? blk.ml[a] * blk.d.m[p][r] : 0.0;
              }
          }
      });
}

/// The node graph on the device with, for every entry (i, j), the position of entry (j, i)
/// (the graph is symmetric), so transposed block products run row by row without atomics.
template <class MemorySpace> struct DeviceNodeGraph {
  Kokkos::View<Offset *, MemorySpace> rowOffsets;
  Kokkos::View<LocalIndex *, MemorySpace> columns;
  Kokkos::View<Offset *, MemorySpace> transpose;
  LocalIndex numNodes = 0;
};

template <class MemorySpace> DeviceNodeGraph<MemorySpace> toDevice(const NodeGraph &g) {
  DeviceNodeGraph<MemorySpace> d;
  d.numNodes = g.numNodes();
  d.rowOffsets = Kokkos::View<Offset *, MemorySpace>("mixcon::graph::rowOffsets", g.numNodes() + 1);
  d.columns = Kokkos::View<LocalIndex *, MemorySpace>("mixcon::graph::columns", g.columns.size());
  d.transpose = Kokkos::View<Offset *, MemorySpace>("mixcon::graph::transpose", g.columns.size());
  auto hr = hostMirror(d.rowOffsets);
  auto hc = hostMirror(d.columns);
  auto ht = hostMirror(d.transpose);
  const auto t = transposePositions(g);
  for (std::size_t i = 0; i < g.rowOffsets.size(); ++i)
    hr(i) = g.rowOffsets[i];
  for (std::size_t k = 0; k < g.columns.size(); ++k) {
    hc(k) = g.columns[k];
    ht(k) = t[k];
  }
  copyToDevice(d.rowOffsets, hr);
  copyToDevice(d.columns, hc);
  copyToDevice(d.transpose, ht);
  return d;
}

/// Assembled mixed operators on the node graph (node-block storage):
///   coupling(p) = (Gx, Gy) for entry p = (k, i): Gx = sum_e t int psi_k dpsi_i/dx dA, so that the
///     3x2 block K21[k][i] = K12[i][k]^T = [Gx 0; 0 Gy; Gy Gx];
///   compliance(p) = M[k][l] (3x3), the consistent compliance mass;
///   lumped(k), lumpedInverse(k): the lumped 3x3 nodal blocks and their inverses.
template <class MemorySpace> struct MixedOperators {
  DeviceNodeGraph<MemorySpace> graph;
  Kokkos::View<double *[2], MemorySpace> coupling;
  Kokkos::View<double *[3][3], MemorySpace> compliance;
  Kokkos::View<double *[3][3], MemorySpace> lumped;
  Kokkos::View<double *[3][3], MemorySpace> lumpedInverse;
};

/// y = B x for 3x3 nodal blocks B(k) (the lumped compliance or its inverse).
template <class ExecSpace, class MemorySpace>
void applyNodalBlocks(const ExecSpace &exec, const Kokkos::View<double *[3][3], MemorySpace> &b,
                      const Kokkos::View<const double *, MemorySpace> &x,
                      const Kokkos::View<double *, MemorySpace> &y) {
  Kokkos::parallel_for(
      "mixcon::mixed::nodalBlocks", Kokkos::RangePolicy<ExecSpace>(exec, 0, b.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        const double x0 = x(3 * k), x1 = x(3 * k + 1), x2 = x(3 * k + 2);
        for (int r = 0; r < 3; ++r)
          y(3 * k + r) = b(k, r, 0) * x0 + b(k, r, 1) * x1 + b(k, r, 2) * x2;
      });
}

/// inv(k) = b(k)^-1 for 3x3 nodal blocks (the lumped compliance, or the nodal blocks of the
/// nonlinear mixed model's stress block); a singular block (a node without elements) leaves
/// inv(k) as it was (zero in a new view).
template <class ExecSpace, class MemorySpace>
void invertNodalBlocks(const ExecSpace &exec, const Kokkos::View<double *[3][3], MemorySpace> &b,
                       const Kokkos::View<double *[3][3], MemorySpace> &inv) {
  Kokkos::parallel_for(
      "mixcon::kernels::invertNodalBlocks", Kokkos::RangePolicy<ExecSpace>(exec, 0, b.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        Mat<3, 3> a, ai{};
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            a.m[r][c] = b(k, r, c);
        if (inverse(a, ai) == 0.0)
          return;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            inv(k, r, c) = ai.m[r][c];
      });
}

/// Allocates and assembles the mixed operators of all elements (atomic scatter through the node
/// scatter map of `graph`), then inverts the lumped blocks.
template <class Elem, class ExecSpace, class MemorySpace, class Map>
MixedOperators<MemorySpace>
assembleMixedOperators(const ExecSpace &exec, const MixedElementData<MemorySpace> &d,
                       const DeviceNodeGraph<MemorySpace> &graph, const Map &map) {
  MixedOperators<MemorySpace> ops;
  ops.graph = graph;
  const Offset nnz = graph.columns.extent(0);
  const LocalIndex nn = graph.numNodes;
  ops.coupling = Kokkos::View<double *[2], MemorySpace>("mixcon::mixed::coupling", nnz);
  ops.compliance = Kokkos::View<double *[3][3], MemorySpace>("mixcon::mixed::compliance", nnz);
  ops.lumped = Kokkos::View<double *[3][3], MemorySpace>("mixcon::mixed::lumped", nn);
  ops.lumpedInverse = Kokkos::View<double *[3][3], MemorySpace>("mixcon::mixed::lumpedInv", nn);
  auto ro = graph.rowOffsets;
  auto cp = ops.coupling;
  auto cm = ops.compliance;
  auto lm = ops.lumped;
  auto li = ops.lumpedInverse;
  Kokkos::parallel_for(
      "mixcon::kernels::assembleMixedOperators",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes;
        MixedElementBlocks<Elem> blk;
        mixedElementBlocks<Elem>(d, e, blk);
        for (int a = 0; a < n; ++a) { // a: stress node (row), b: displacement / stress column
          const LocalIndex k = d.mesh.connectivity(e, a);
          for (int b = 0; b < n; ++b) {
            const Offset p = ro(k) + map(e, a, b);
            Kokkos::atomic_add(&cp(p, 0), blk.gx[b][a]);
            Kokkos::atomic_add(&cp(p, 1), blk.gy[b][a]);
            for (int r = 0; r < 3; ++r)
              for (int s = 0; s < 3; ++s)
                Kokkos::atomic_add(&cm(p, r, s), blk.m[a][b] * blk.d.m[r][s]);
          }
          for (int r = 0; r < 3; ++r)
            for (int s = 0; s < 3; ++s)
              Kokkos::atomic_add(&lm(k, r, s), blk.ml[a] * blk.d.m[r][s]);
        }
      });
  invertNodalBlocks(exec, lm, li); // nodes without elements keep a zero inverse
  return ops;
}

/// Only the lumped compliance blocks and their inverses of all elements (what the matrix-free
/// path keeps assembled: the inner CG's preconditioner), same arithmetic as
/// assembleMixedOperators; graph, coupling and compliance stay empty.
template <class Elem, class ExecSpace, class MemorySpace>
MixedOperators<MemorySpace> assembleLumpedCompliance(const ExecSpace &exec,
                                                     const MixedElementData<MemorySpace> &d,
                                                     LocalIndex numNodes) {
  MixedOperators<MemorySpace> ops;
  ops.lumped = Kokkos::View<double *[3][3], MemorySpace>("mixcon::mixed::lumped", numNodes);
  ops.lumpedInverse =
      Kokkos::View<double *[3][3], MemorySpace>("mixcon::mixed::lumpedInv", numNodes);
  auto lm = ops.lumped;
  Kokkos::parallel_for(
      "mixcon::kernels::assembleLumpedCompliance",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        MixedElementBlocks<Elem> blk;
        mixedElementBlocks<Elem>(d, e, blk);
        for (int a = 0; a < Elem::kNumNodes; ++a) {
          const LocalIndex k = d.mesh.connectivity(e, a);
          for (int r = 0; r < 3; ++r)
            for (int s = 0; s < 3; ++s)
              Kokkos::atomic_add(&lm(k, r, s), blk.ml[a] * blk.d.m[r][s]);
        }
      });
  invertNodalBlocks(exec, lm, ops.lumpedInverse);
  return ops;
}

/// r = K12^T u: stress-node residual r (3 per node, interleaved) from displacements u (2 per node).
template <class ExecSpace, class MemorySpace>
void applyCouplingTranspose(const ExecSpace &exec, const MixedOperators<MemorySpace> &ops,
                            const Kokkos::View<const double *, MemorySpace> &u,
                            const Kokkos::View<double *, MemorySpace> &r) {
  auto ro = ops.graph.rowOffsets;
  auto co = ops.graph.columns;
  auto cp = ops.coupling;
  Kokkos::parallel_for(
      "mixcon::mixed::couplingTranspose",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, ops.graph.numNodes), KOKKOS_LAMBDA(LocalIndex k) {
        double s0 = 0.0, s1 = 0.0, s2 = 0.0;
        for (Offset p = ro(k); p < ro(k + 1); ++p) {
          const LocalIndex i = co(p);
          const double gx = cp(p, 0), gy = cp(p, 1), ux = u(2 * i), uy = u(2 * i + 1);
          s0 += gx * ux;
          s1 += gy * uy;
          s2 += gy * ux + gx * uy;
        }
        r(3 * k) = s0;
        r(3 * k + 1) = s1;
        r(3 * k + 2) = s2;
      });
}

/// f = beta f + alpha K12 s: displacement-node forces from nodal stresses s (3 per node). Runs row
/// by row through the transpose positions (no atomics).
template <class ExecSpace, class MemorySpace>
void applyCoupling(const ExecSpace &exec, const MixedOperators<MemorySpace> &ops, double alpha,
                   const Kokkos::View<const double *, MemorySpace> &s, double beta,
                   const Kokkos::View<double *, MemorySpace> &f) {
  auto ro = ops.graph.rowOffsets;
  auto co = ops.graph.columns;
  auto tr = ops.graph.transpose;
  auto cp = ops.coupling;
  Kokkos::parallel_for(
      "mixcon::mixed::coupling", Kokkos::RangePolicy<ExecSpace>(exec, 0, ops.graph.numNodes),
      KOKKOS_LAMBDA(LocalIndex i) {
        double fx = 0.0, fy = 0.0;
        for (Offset p = ro(i); p < ro(i + 1); ++p) {
          const LocalIndex k = co(p);
          const Offset t = tr(p); // entry (k, i)
          const double gx = cp(t, 0), gy = cp(t, 1);
          fx += gx * s(3 * k) + gy * s(3 * k + 2);
          fy += gy * s(3 * k + 1) + gx * s(3 * k + 2);
        }
        f(2 * i) = (beta == 0.0 ? 0.0 : beta * f(2 * i)) + alpha * fx;
        f(2 * i + 1) = (beta == 0.0 ? 0.0 : beta * f(2 * i + 1)) + alpha * fy;
      });
}

/// y = M x with the consistent compliance mass (3x3 blocks on the node graph).
template <class ExecSpace, class MemorySpace>
void applyCompliance(const ExecSpace &exec, const MixedOperators<MemorySpace> &ops,
                     const Kokkos::View<const double *, MemorySpace> &x,
                     const Kokkos::View<double *, MemorySpace> &y) {
  auto ro = ops.graph.rowOffsets;
  auto co = ops.graph.columns;
  auto cm = ops.compliance;
  Kokkos::parallel_for(
      "mixcon::mixed::compliance", Kokkos::RangePolicy<ExecSpace>(exec, 0, ops.graph.numNodes),
      KOKKOS_LAMBDA(LocalIndex k) {
        double s[3] = {0.0, 0.0, 0.0};
        for (Offset p = ro(k); p < ro(k + 1); ++p) {
          const LocalIndex l = co(p);
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
              s[r] += cm(p, r, c) * x(3 * l + c);
        }
        for (int r = 0; r < 3; ++r)
          y(3 * k + r) = s[r];
      });
}

/// Adds scale * K12 M_L^-1 K12^T (the lumped Schur complement on displacements) into `s`, a CSR
/// matrix with 2 interleaved dofs per node on the second-neighbour graph (expandGraph of
/// secondNeighbourGraph). One thread per stress node k: sum over the pairs (i, j) of its
/// displacement neighbours of K21[k][i]^T Minv_k K21[k][j], atomically.
template <class ExecSpace, class MemorySpace>
void assembleLumpedSchur(const ExecSpace &exec, const MixedOperators<MemorySpace> &ops,
                         double scale, const CsrMatrix<MemorySpace> &s) {
  auto ro = ops.graph.rowOffsets;
  auto co = ops.graph.columns;
  auto cp = ops.coupling;
  auto li = ops.lumpedInverse;
  auto sr = s.rowOffsets;
  auto sc = s.columns;
  auto sv = s.values;
  Kokkos::parallel_for(
      "mixcon::mixed::assembleLumpedSchur",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, ops.graph.numNodes), KOKKOS_LAMBDA(LocalIndex k) {
        for (Offset p = ro(k); p < ro(k + 1); ++p) {
          const LocalIndex i = co(p);
          // V = K21[k][i]^T Minv_k (2x3); K21[k][i]^T = [gx 0 gy; 0 gy gx]
          const double gx = cp(p, 0), gy = cp(p, 1);
          double v[2][3];
          for (int c = 0; c < 3; ++c) {
            v[0][c] = scale * (gx * li(k, 0, c) + gy * li(k, 2, c));
            v[1][c] = scale * (gy * li(k, 1, c) + gx * li(k, 2, c));
          }
          const Offset row0 = sr(2 * i), row1 = sr(2 * i + 1);
          for (Offset q = ro(k); q < ro(k + 1); ++q) {
            const LocalIndex j = co(q);
            const double hx = cp(q, 0), hy = cp(q, 1);
            // binary search for column 2j in row 2i
            Offset lo = row0, hi = sr(2 * i + 1);
            while (hi - lo > 1) {
              const Offset mid = lo + (hi - lo) / 2;
              if (sc(mid) <= 2 * j)
                lo = mid;
              else
                hi = mid;
            }
            const Offset off = lo - row0;
            for (int r = 0; r < 2; ++r) {
              // (V K21[k][j])[r] = V[r] * [hx 0; 0 hy; hy hx]
              const double b0 = v[r][0] * hx + v[r][2] * hy;
              const double b1 = v[r][1] * hy + v[r][2] * hx;
              const Offset at = (r == 0 ? row0 : row1) + off;
              Kokkos::atomic_add(&sv(at), b0);
              Kokkos::atomic_add(&sv(at + 1), b1);
            }
          }
        }
      });
}

/// Geometric stiffness K11 (Eq. (31)) and F^NL with tau interpolated from nodal stresses s (3 per
/// node): the generic kernels of kernels/GeometricStiffness.hpp with a NodalStressField.
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void computeMixedGeometricStiffness(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                                    const Kokkos::View<const double *, MemorySpace> &s,
                                    const Kokkos::View<double ***, P...> &kg) {
  computeGeometricStiffness<Elem>(exec, d, NodalStressField<MemorySpace>{d.mesh, s}, kg);
}

/// Adds K11 of all elements into `a` (2 dofs per node) through the scatter map of a's graph.
template <class Elem, class ExecSpace, class MemorySpace, class Map>
void assembleMixedGeometricStiffness(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                                     const Kokkos::View<const double *, MemorySpace> &s,
                                     const Map &map, const CsrMatrix<MemorySpace> &a) {
  assembleGeometricStiffness<Elem>(exec, d, NodalStressField<MemorySpace>{d.mesh, s}, map, a);
}

/// Adds F^NL = t int [B^L]^T {tau} dA (Eq. (31)) to f (2 per node).
template <class Elem, class ExecSpace, class MemorySpace>
void assembleMixedStressForce(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                              const Kokkos::View<const double *, MemorySpace> &s,
                              const Kokkos::View<double *, MemorySpace> &f) {
  assembleStressForce<Elem>(exec, d, NodalStressField<MemorySpace>{d.mesh, s}, f);
}

} // namespace mixcon
