// Batched element kernels of the displacement model, Eq. (25) of the report, for all elements at
// once: the linear stiffness K^L = t int B^T C B dA (element matrices, or computed and scattered
// into CSR with atomics in one pass), the load vector F^L = t int Psi^T f dA, boundary tractions
// and pressures, internal force, and stress recovery. Element type is a template parameter
// (traits); everything runs on the execution space passed first. Data flow: mesh -> kernels (this)
// -> solver.
#pragma once

#include <core/ElementTraits.hpp>
#include <kernels/Material.hpp>
#include <kernels/SparseMatrix.hpp>

namespace mixcon {

/// What every element kernel reads: geometry, per-element material index, material table.
/// Views are owned by the caller (shallow copies, reference counted).
template <class MemorySpace> struct ElementData {
  MeshView<MemorySpace> mesh;
  Kokkos::View<int *, MemorySpace> material;          ///< per element, index into stiffness
  Kokkos::View<PlaneMatrix *, MemorySpace> stiffness; ///< plane [C] per material, global axes
  double thickness = 1.0;
};

namespace detail {

template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void gatherCoordinates(const MeshView<MemorySpace> &m, LocalIndex e,
                                              double (&xe)[Elem::kNumNodes][2]) {
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    const LocalIndex n = m.connectivity(e, a);
    xe[a][0] = m.coordinates(n, 0);
    xe[a][1] = m.coordinates(n, 1);
  }
}

/// Small-strain Voigt strain (xx, yy, engineering xy) from gradients and element displacements.
template <class Elem>
KOKKOS_INLINE_FUNCTION void strainFromGradients(const double (&dndx)[Elem::kNumNodes][2],
                                                const double (&ue)[Elem::kNumNodes][2],
                                                double (&eps)[3]) {
  eps[0] = eps[1] = eps[2] = 0.0;
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    eps[0] += dndx[a][0] * ue[a][0];
    eps[1] += dndx[a][1] * ue[a][1];
    eps[2] += dndx[a][1] * ue[a][0] + dndx[a][0] * ue[a][1];
  }
}

} // namespace detail

/// Elements per work item of the K^L kernels: a batch of consecutive elements computed in SIMD
/// lanes on CPUs (every scalar of linearStiffness becomes an array over the lanes, and the lane
/// loops are the innermost, unit-stride ones the compiler vectorizes); one element per thread
/// on GPUs. 4 lanes measured 1.2-1.6x over 1 (2 threads, SSE2 code, bench_linear_stiffness);
/// 2 and 8 were slower than 4.
template <class ExecSpace>
constexpr int kStiffnessLanes =
    Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible ? 4 : 1;

/// K^L (Eq. (25)) of the W elements first, first + 1, ... (clamped to last: a short final batch
/// repeats its last element) into lane l of ke[i][j][l], dofs ordered (u_1, v_1, u_2, ...). Per
/// quadrature point: the gradients, C B_b for every node, the 2 x 2 blocks B_a^T (C B_b) for
/// a <= b; the lower blocks mirrored at the end (C is symmetric).
template <class Elem, int W, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
linearStiffnessLanes(const ElementData<MemorySpace> &d, LocalIndex first, LocalIndex last,
                     double (&ke)[2 * Elem::kNumNodes][2 * Elem::kNumNodes][W]) {
  constexpr int n = Elem::kNumNodes;
  double xe[n][2][W], c[3][3][W];
  for (int l = 0; l < W; ++l) {
    const LocalIndex e = first + l < last ? first + l : last;
    for (int a = 0; a < n; ++a) {
      const LocalIndex k = d.mesh.connectivity(e, a);
      xe[a][0][l] = d.mesh.coordinates(k, 0);
      xe[a][1][l] = d.mesh.coordinates(k, 1);
    }
    const PlaneMatrix m = d.stiffness(d.material(e));
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s)
        c[r][s][l] = m.m[r][s];
  }
  for (int i = 0; i < 2 * n; ++i)
    for (int j = 0; j < 2 * n; ++j)
      for (int l = 0; l < W; ++l)
        ke[i][j][l] = 0.0;
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double xi, eta, w, sh[n], dn[n][2];
    Elem::quadraturePoint(q, xi, eta, w);
    Elem::shape(xi, eta, sh, dn); // shared by the lanes
    double g[n][2][W], f[W];
    double j00[W] = {}, j01[W] = {}, j10[W] = {}, j11[W] = {};
    for (int a = 0; a < n; ++a)
      for (int l = 0; l < W; ++l) {
        j00[l] += xe[a][0][l] * dn[a][0];
        j01[l] += xe[a][0][l] * dn[a][1];
        j10[l] += xe[a][1][l] * dn[a][0];
        j11[l] += xe[a][1][l] * dn[a][1];
      }
    double i00[W], i01[W], i10[W], i11[W];
    for (int l = 0; l < W; ++l) {
      const double det = j00[l] * j11[l] - j01[l] * j10[l];
      const double inv = 1.0 / det;
      i00[l] = j11[l] * inv;
      i01[l] = -j01[l] * inv;
      i10[l] = -j10[l] * inv;
      i11[l] = j00[l] * inv;
      f[l] = d.thickness * w * det;
    }
    for (int a = 0; a < n; ++a)
      for (int l = 0; l < W; ++l) {
        g[a][0][l] = dn[a][0] * i00[l] + dn[a][1] * i10[l];
        g[a][1][l] = dn[a][0] * i01[l] + dn[a][1] * i11[l];
      }
    for (int b = 0; b < n; ++b) {
      double cb[3][2][W];
      for (int r = 0; r < 3; ++r)
        for (int l = 0; l < W; ++l) {
          cb[r][0][l] = (c[r][0][l] * g[b][0][l] + c[r][2][l] * g[b][1][l]) * f[l];
          cb[r][1][l] = (c[r][1][l] * g[b][1][l] + c[r][2][l] * g[b][0][l]) * f[l];
        }
      for (int a = 0; a <= b; ++a)
        for (int l = 0; l < W; ++l) {
          ke[2 * a][2 * b][l] += g[a][0][l] * cb[0][0][l] + g[a][1][l] * cb[2][0][l];
          ke[2 * a][2 * b + 1][l] += g[a][0][l] * cb[0][1][l] + g[a][1][l] * cb[2][1][l];
          ke[2 * a + 1][2 * b][l] += g[a][1][l] * cb[1][0][l] + g[a][0][l] * cb[2][0][l];
          ke[2 * a + 1][2 * b + 1][l] += g[a][1][l] * cb[1][1][l] + g[a][0][l] * cb[2][1][l];
        }
    }
  }
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < b; ++a)
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
          for (int l = 0; l < W; ++l)
            ke[2 * b + j][2 * a + i][l] = ke[2 * a + i][2 * b + j][l];
}

/// Element linear stiffness K^L of element e (Eq. (25)), dofs ordered (u_1, v_1, u_2, v_2, ...):
/// one lane of linearStiffnessLanes (one arithmetic for both).
template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
linearStiffness(const ElementData<MemorySpace> &d, LocalIndex e,
                double (&ke)[2 * Elem::kNumNodes][2 * Elem::kNumNodes]) {
  constexpr int nd = 2 * Elem::kNumNodes;
  double k[nd][nd][1];
  linearStiffnessLanes<Elem, 1>(d, e, e, k);
  for (int i = 0; i < nd; ++i)
    for (int j = 0; j < nd; ++j)
      ke[i][j] = k[i][j][0];
}

/// Element stiffness matrices of all elements into ke(e, i, j) (extent E x 2n x 2n).
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void computeLinearStiffness(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                            const Kokkos::View<double ***, P...> &ke) {
  constexpr int nd = 2 * Elem::kNumNodes;
  constexpr int W = kStiffnessLanes<ExecSpace>;
  const LocalIndex ne = static_cast<LocalIndex>(d.material.extent(0));
  Kokkos::parallel_for(
      "mixcon::kernels::linearStiffness", Kokkos::RangePolicy<ExecSpace>(exec, 0, (ne + W - 1) / W),
      KOKKOS_LAMBDA(LocalIndex batch) {
        const LocalIndex first = batch * W;
        double k[nd][nd][W];
        linearStiffnessLanes<Elem, W>(d, first, ne - 1, k);
        for (int l = 0; l < W && first + l < ne; ++l)
          for (int i = 0; i < nd; ++i)
            for (int j = 0; j < nd; ++j)
              ke(first + l, i, j) = k[i][j][l];
      });
}

/// Adds an element matrix (node-interleaved, 2 dofs per node) into CSR through the scatter map.
template <class Elem, class MemorySpace, class Map>
KOKKOS_INLINE_FUNCTION void
scatterElementMatrix(const CsrMatrix<MemorySpace> &a, const Map &map,
                     const MeshView<MemorySpace> &m, LocalIndex e,
                     const double (&ke)[2 * Elem::kNumNodes][2 * Elem::kNumNodes]) {
  for (int p = 0; p < Elem::kNumNodes; ++p) {
    const LocalIndex row = m.connectivity(e, p);
    for (int i = 0; i < 2; ++i) {
      const Offset start = a.rowOffsets(2 * row + i);
      for (int b = 0; b < Elem::kNumNodes; ++b) {
        const Offset k = start + 2 * map(e, p, b);
        Kokkos::atomic_add(&a.values(k), ke[2 * p + i][2 * b]);
        Kokkos::atomic_add(&a.values(k + 1), ke[2 * p + i][2 * b + 1]);
      }
    }
  }
}

/// Computes K^L for all elements and adds it into `a` (pattern from expandGraph(graph, 2)) via the
/// scatter map from elementScatterMap (of any graph containing the node graph), times `scale`. One
/// pass, no element-matrix storage; `a.values` must be zeroed by the caller beforehand if a fresh
/// matrix is wanted.
template <class Elem, class ExecSpace, class MemorySpace, class Map>
void assembleLinearStiffness(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                             const Map &map, const CsrMatrix<MemorySpace> &a, double scale = 1.0) {
  constexpr int nd = 2 * Elem::kNumNodes;
  constexpr int W = kStiffnessLanes<ExecSpace>;
  const LocalIndex ne = static_cast<LocalIndex>(d.material.extent(0));
  Kokkos::parallel_for(
      "mixcon::kernels::assembleLinearStiffness",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, (ne + W - 1) / W), KOKKOS_LAMBDA(LocalIndex batch) {
        const LocalIndex first = batch * W;
        double kw[nd][nd][W];
        linearStiffnessLanes<Elem, W>(d, first, ne - 1, kw);
        for (int l = 0; l < W && first + l < ne; ++l) {
          double k[nd][nd];
          for (int i = 0; i < nd; ++i)
            for (int j = 0; j < nd; ++j)
              k[i][j] = scale * kw[i][j][l];
          scatterElementMatrix<Elem>(a, map, d.mesh, first + l, k);
        }
      });
}

/// Physical coordinates of every quadrature point of the element rule: xq(e, q, 0..1).
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void quadraturePointCoordinates(const ExecSpace &exec, const MeshView<MemorySpace> &m,
                                const Kokkos::View<double **[2], P...> &xq) {
  Kokkos::parallel_for(
      "mixcon::kernels::quadraturePoints",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, m.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        double xe[Elem::kNumNodes][2];
        detail::gatherCoordinates<Elem>(m, e, xe);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double xi, eta, w, sh[Elem::kNumNodes], dn[Elem::kNumNodes][2];
          Elem::quadraturePoint(q, xi, eta, w);
          Elem::shape(xi, eta, sh, dn);
          double x = 0.0, y = 0.0;
          for (int a = 0; a < Elem::kNumNodes; ++a) {
            x += sh[a] * xe[a][0];
            y += sh[a] * xe[a][1];
          }
          xq(e, q, 0) = x;
          xq(e, q, 1) = y;
        }
      });
}

/// Adds F^L = t int Psi^T f dA (Eq. (25)) to rhs (2 dofs per node), with the body force per unit
/// volume given at the element quadrature points: f(e, q, 0..1).
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void assembleBodyForce(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                       const Kokkos::View<const double **[2], P...> &f,
                       const Kokkos::View<double *, MemorySpace> &rhs) {
  Kokkos::parallel_for(
      "mixcon::kernels::bodyForce", Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes;
        double xe[n][2], fe[n][2] = {};
        detail::gatherCoordinates<Elem>(d.mesh, e, xe);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double xi, eta, w, sh[n], dn[n][2], g[n][2];
          Elem::quadraturePoint(q, xi, eta, w);
          Elem::shape(xi, eta, sh, dn);
          const double s = d.thickness * w * physicalGradients<Elem>(xe, dn, g);
          for (int a = 0; a < n; ++a) {
            fe[a][0] += sh[a] * f(e, q, 0) * s;
            fe[a][1] += sh[a] * f(e, q, 1) * s;
          }
        }
        for (int a = 0; a < n; ++a) {
          const LocalIndex node = d.mesh.connectivity(e, a);
          Kokkos::atomic_add(&rhs(2 * node), fe[a][0]);
          Kokkos::atomic_add(&rhs(2 * node + 1), fe[a][1]);
        }
      });
}

/// Adds boundary loads on element edges to rhs: edges(k) = (element, local edge), load(k) =
/// (t_x, t_y, p): a traction per unit area of the edge's face plus a pressure p acting against
/// the outward normal (positive p pushes into the body), both on the reference geometry.
template <class Elem, class ExecSpace, class MemorySpace>
void assembleEdgeLoads(const ExecSpace &exec, const MeshView<MemorySpace> &m,
                       const Kokkos::View<LocalIndex *[2], MemorySpace> &edges,
                       const Kokkos::View<double *[3], MemorySpace> &load, double thickness,
                       const Kokkos::View<double *, MemorySpace> &rhs) {
  Kokkos::parallel_for(
      "mixcon::kernels::edgeLoads", Kokkos::RangePolicy<ExecSpace>(exec, 0, edges.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        constexpr int ne = Elem::kNodesPerEdge;
        const LocalIndex e = edges(k, 0);
        const int edge = edges(k, 1);
        LocalIndex nodes[ne];
        double xe[ne][2], fe[ne][2] = {};
        for (int a = 0; a < ne; ++a) {
          nodes[a] = m.connectivity(e, Elem::edgeNode(edge, a));
          xe[a][0] = m.coordinates(nodes[a], 0);
          xe[a][1] = m.coordinates(nodes[a], 1);
        }
        for (int q = 0; q < Elem::kNumEdgeQp; ++q) {
          double s, w, sh[ne], ds[ne];
          detail::gauss1d(Elem::kNumEdgeQp, q, s, w);
          edgeShape<ne>(s, sh, ds);
          double tx = 0.0, ty = 0.0; // dx/ds
          for (int a = 0; a < ne; ++a) {
            tx += ds[a] * xe[a][0];
            ty += ds[a] * xe[a][1];
          }
          const double len = detail::sqrt(tx * tx + ty * ty);
          // Counter-clockwise element: outward normal times |dx/ds| is (ty, -tx).
          const double fx = load(k, 0) * len - load(k, 2) * ty;
          const double fy = load(k, 1) * len + load(k, 2) * tx;
          for (int a = 0; a < ne; ++a) {
            fe[a][0] += sh[a] * fx * w * thickness;
            fe[a][1] += sh[a] * fy * w * thickness;
          }
        }
        for (int a = 0; a < ne; ++a) {
          Kokkos::atomic_add(&rhs(2 * nodes[a]), fe[a][0]);
          Kokkos::atomic_add(&rhs(2 * nodes[a] + 1), fe[a][1]);
        }
      });
}

/// Device inputs of assembleEdgeLoads for one load (t_x, t_y, p) shared by a list of edges.
template <class MemorySpace> struct EdgeLoadBatch {
  Kokkos::View<LocalIndex *[2], MemorySpace> edges;
  Kokkos::View<double *[3], MemorySpace> load;
};

/// Copies `edges` and the uniform load (tx, ty, pressure) to `MemorySpace`.
template <class MemorySpace>
EdgeLoadBatch<MemorySpace> uniformEdgeLoads(const std::vector<BoundaryEdge> &edges, double tx,
                                            double ty, double pressure) {
  EdgeLoadBatch<MemorySpace> b{
      Kokkos::View<LocalIndex *[2], MemorySpace>("mixcon::kernels::edges", edges.size()),
      Kokkos::View<double *[3], MemorySpace>("mixcon::kernels::edgeLoads", edges.size())};
  auto he = Kokkos::create_mirror_view(b.edges);
  auto hl = Kokkos::create_mirror_view(b.load);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    he(k, 0) = edges[k].element;
    he(k, 1) = edges[k].edge;
    hl(k, 0) = tx;
    hl(k, 1) = ty;
    hl(k, 2) = pressure;
  }
  Kokkos::deep_copy(b.edges, he);
  Kokkos::deep_copy(b.load, hl);
  return b;
}

/// Internal force f = K^L u assembled element by element (matrix free), added to f.
template <class Elem, class ExecSpace, class MemorySpace>
void assembleInternalForce(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                           const Kokkos::View<const double *, MemorySpace> &u,
                           const Kokkos::View<double *, MemorySpace> &f) {
  Kokkos::parallel_for(
      "mixcon::kernels::internalForce",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, nd = 2 * n;
        double k[nd][nd], ue[nd];
        linearStiffness<Elem>(d, e, k);
        for (int a = 0; a < n; ++a) {
          const LocalIndex node = d.mesh.connectivity(e, a);
          ue[2 * a] = u(2 * node);
          ue[2 * a + 1] = u(2 * node + 1);
        }
        for (int a = 0; a < n; ++a) {
          const LocalIndex node = d.mesh.connectivity(e, a);
          for (int i = 0; i < 2; ++i) {
            double s = 0.0;
            for (int j = 0; j < nd; ++j)
              s += k[2 * a + i][j] * ue[j];
            Kokkos::atomic_add(&f(2 * node + i), s);
          }
        }
      });
}

namespace detail {
/// Stress C eps(u) at natural point (xi, eta) of element e.
template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void stressAt(const ElementData<MemorySpace> &d,
                                     const Kokkos::View<const double *, MemorySpace> &u,
                                     LocalIndex e, const double (&xe)[Elem::kNumNodes][2],
                                     double xi, double eta, double (&sig)[3]) {
  double sh[Elem::kNumNodes], dn[Elem::kNumNodes][2], g[Elem::kNumNodes][2], ue[Elem::kNumNodes][2],
      eps[3];
  Elem::shape(xi, eta, sh, dn);
  physicalGradients<Elem>(xe, dn, g);
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    const LocalIndex node = d.mesh.connectivity(e, a);
    ue[a][0] = u(2 * node);
    ue[a][1] = u(2 * node + 1);
  }
  strainFromGradients<Elem>(g, ue, eps);
  applyStiffness(d.stiffness(d.material(e)), eps, sig);
}
} // namespace detail

/// Cauchy stress (xx, yy, xy) of the linear model at every quadrature point of the element rule.
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void gaussPointStress(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                      const Kokkos::View<const double *, MemorySpace> &u,
                      const Kokkos::View<double **[3], P...> &stress) {
  Kokkos::parallel_for(
      "mixcon::kernels::gaussPointStress",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)), KOKKOS_LAMBDA(LocalIndex e) {
        double xe[Elem::kNumNodes][2];
        detail::gatherCoordinates<Elem>(d.mesh, e, xe);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double xi, eta, w, sig[3];
          Elem::quadraturePoint(q, xi, eta, w);
          detail::stressAt<Elem>(d, u, e, xe, xi, eta, sig);
          for (int c = 0; c < 3; ++c)
            stress(e, q, c) = sig[c];
        }
      });
}

/// Stress C eps(u) of the linear model at natural point (xi, eta) of element e (a functor for
/// recoverNodalStress).
template <class Elem, class MemorySpace> struct LinearPointStress {
  ElementData<MemorySpace> d;
  Kokkos::View<const double *, MemorySpace> u;
  KOKKOS_INLINE_FUNCTION void operator()(LocalIndex e, double xi, double eta,
                                         double (&sig)[3]) const {
    double xe[Elem::kNumNodes][2];
    detail::gatherCoordinates<Elem>(d.mesh, e, xe);
    detail::stressAt<Elem>(d, u, e, xe, xi, eta, sig);
  }
};

/// Nodal stresses recovered from the 2x2 Gauss points (the superconvergent points of both Quad4
/// and Quad8): the four values pointStress(e, xi, eta, s) are extrapolated bilinearly to every
/// element node, then averaged over the elements sharing the node. `nodal` (N x 3) is
/// overwritten.
template <class Elem, class ExecSpace, class MemorySpace, class PointStress>
void recoverNodalStress(const ExecSpace &exec, const MeshView<MemorySpace> &mesh,
                        const PointStress &pointStress,
                        const Kokkos::View<double *[3], MemorySpace> &nodal) {
  const LocalIndex nn = nodal.extent(0);
  Kokkos::View<double *, MemorySpace> count("mixcon::kernels::stressCount", nn);
  Kokkos::deep_copy(exec, nodal, 0.0);
  Kokkos::parallel_for(
      "mixcon::kernels::nodalStressRecovery",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        double sg[4][3];
        constexpr double g = 0.57735026918962576451; // 1/sqrt(3)
        for (int p = 0; p < 4; ++p)
          pointStress(e, detail::cornerXi(p) * g, detail::cornerEta(p) * g, sg[p]);
        for (int a = 0; a < Elem::kNumNodes; ++a) {
          double xi, eta;
          Elem::nodeNatural(a, xi, eta);
          // Bilinear through the Gauss points: local coordinate r = xi * sqrt(3).
          const double r = xi / g, s = eta / g;
          const LocalIndex node = mesh.connectivity(e, a);
          for (int c = 0; c < 3; ++c) {
            double v = 0.0;
            for (int p = 0; p < 4; ++p)
              v += 0.25 * (1.0 + r * detail::cornerXi(p)) * (1.0 + s * detail::cornerEta(p)) *
                   sg[p][c];
            Kokkos::atomic_add(&nodal(node, c), v);
          }
          Kokkos::atomic_add(&count(node), 1.0);
        }
      });
  Kokkos::parallel_for(
      "mixcon::kernels::nodalStressAverage", Kokkos::RangePolicy<ExecSpace>(exec, 0, nn),
      KOKKOS_LAMBDA(LocalIndex n) {
        if (count(n) > 0.0)
          for (int c = 0; c < 3; ++c)
            nodal(n, c) /= count(n);
      });
}

/// Nodal stresses of the linear model (recoverNodalStress of C eps(u)).
template <class Elem, class ExecSpace, class MemorySpace>
void nodalStressRecovery(const ExecSpace &exec, const ElementData<MemorySpace> &d,
                         const Kokkos::View<const double *, MemorySpace> &u,
                         const Kokkos::View<double *[3], MemorySpace> &nodal) {
  recoverNodalStress<Elem>(exec, d.mesh, LinearPointStress<Elem, MemorySpace>{d, u}, nodal);
}

} // namespace mixcon
