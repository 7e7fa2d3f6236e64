// Batched element kernels of the displacement model, Eq. (25) of the report, for all elements at
// once: the linear stiffness K^L = t int B^T C B dA (element matrices, or computed and scattered
// into CSR with atomics in one pass), the load vector F^L = t int Psi^T f dA, boundary tractions
// and pressures, internal force, and stress recovery. Element type is a template parameter
// (traits); everything runs on the execution space passed first. K^L, the internal force and the
// quadrature-point stress are the generic element driver (kernels/ElementDriver.hpp) with the
// linear point law (kernels/PointPhysics.hpp). Data flow: mesh -> kernels (this) -> solver.
#pragma once

#include <core/ElementTraits.hpp>
#include <kernels/ElementDriver.hpp>
#include <kernels/Material.hpp>
#include <kernels/PointPhysics.hpp>
#include <kernels/SparseMatrix.hpp>

namespace mixcon {

/// What every element kernel reads: geometry, per-element material index, material table (the
/// Voigt stiffness [C] in global axes: the plane PlaneMatrix in 2D, the SolidMatrix in 3D).
/// Views are owned by the caller (shallow copies, reference counted). `thickness` is the 2D
/// out-of-plane thickness t of Eq. (25); 1 in 3D.
template <class MemorySpace, int Dim = 2> struct ElementData {
  static constexpr int kDim = Dim;
  using Stiffness = Mat<Voigt<Dim>::kSize, Voigt<Dim>::kSize>;
  MeshView<MemorySpace, Dim> mesh;
  Kokkos::View<int *, MemorySpace> material;        ///< per element, index into stiffness
  Kokkos::View<Stiffness *, MemorySpace> stiffness; ///< [C] per material, global axes
  double thickness = 1.0;
};

/// The point law of the linear model for the element driver (kernels/ElementDriver.hpp):
/// element e's LinearElasticPoint with its material's Voigt stiffness [C].
template <class MemorySpace, int Dim = 2> struct LinearElasticLaw {
  Kokkos::View<int *, MemorySpace> material;
  Kokkos::View<typename ElementData<MemorySpace, Dim>::Stiffness *, MemorySpace> stiffness;
  KOKKOS_INLINE_FUNCTION LinearElasticPoint<Dim> at(LocalIndex e) const {
    return LinearElasticPoint<Dim>{stiffness(material(e))};
  }
};

/// The linear law of the element data's materials.
template <class MemorySpace, int Dim>
KOKKOS_INLINE_FUNCTION LinearElasticLaw<MemorySpace, Dim>
linearElasticLaw(const ElementData<MemorySpace, Dim> &d) {
  return LinearElasticLaw<MemorySpace, Dim>{d.material, d.stiffness};
}

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

/// Element linear stiffness K^L = t int B^T C B dA of element e (Eq. (25)), dofs ordered (u_1,
/// v_1, u_2, v_2, ...): the element driver's stiffness with the linear point law.
template <class Elem, class MemorySpace>
KOKKOS_INLINE_FUNCTION void
linearStiffness(const ElementData<MemorySpace> &d, LocalIndex e,
                double (&ke)[2 * Elem::kNumNodes][2 * Elem::kNumNodes]) {
  elementStiffness<Elem>(d.mesh, d.thickness, linearElasticLaw(d), e, ke);
}

/// Element stiffness matrices of all elements into ke(e, i, j) (extent E x 2n x 2n).
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void computeLinearStiffness(const ExecSpace &exec, const ElementData<MemorySpace, Elem::kDim> &d,
                            const Kokkos::View<double ***, P...> &ke) {
  computeElementStiffness<Elem>(exec, d.mesh, d.thickness, linearElasticLaw(d), ke);
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
/// matrix is wanted. (The element driver's assembleElementStiffness with the linear point law.)
template <class Elem, class ExecSpace, class MemorySpace, class Map>
void assembleLinearStiffness(const ExecSpace &exec, const ElementData<MemorySpace, Elem::kDim> &d,
                             const Map &map, const CsrMatrix<MemorySpace> &a, double scale = 1.0) {
  assembleElementStiffness<Elem>(exec, d.mesh, d.thickness, linearElasticLaw(d), map, a, scale);
}

/// Physical coordinates of every quadrature point of the element rule: xq(e, q, 0..Dim-1).
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void quadraturePointCoordinates(const ExecSpace &exec, const MeshView<MemorySpace, Elem::kDim> &m,
                                const Kokkos::View<double * * [Elem::kDim], P...> &xq) {
  Kokkos::parallel_for(
      "mixcon::kernels::quadraturePoints",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, m.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
        double xe[n][dim];
        detail::gatherElementCoordinates<Elem>(m, e, xe);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double sh[n], dn[n][dim];
          detail::referencePoint<Elem>(q, sh, dn);
          for (int i = 0; i < dim; ++i) {
            double x = 0.0;
            for (int a = 0; a < n; ++a)
              x += sh[a] * xe[a][i];
            xq(e, q, i) = x;
          }
        }
      });
}

/// Adds F^L = t int Psi^T f dA (Eq. (25); 3D: int Psi^T f dV) to rhs (Dim dofs per node), with
/// the body force per unit volume given at the element quadrature points: f(e, q, 0..Dim-1).
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void assembleBodyForce(const ExecSpace &exec, const ElementData<MemorySpace, Elem::kDim> &d,
                       const Kokkos::View<const double * * [Elem::kDim], P...> &f,
                       const Kokkos::View<double *, MemorySpace> &rhs) {
  Kokkos::parallel_for(
      "mixcon::kernels::bodyForce", Kokkos::RangePolicy<ExecSpace>(exec, 0, d.material.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
        double xe[n][dim], fe[n][dim] = {};
        detail::gatherElementCoordinates<Elem>(d.mesh, e, xe);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          double sh[n], dn[n][dim];
          const double w = detail::referencePoint<Elem>(q, sh, dn);
          const double s = d.thickness * w * jacobianDeterminant<Elem>(xe, dn);
          for (int a = 0; a < n; ++a)
            for (int i = 0; i < dim; ++i)
              fe[a][i] += sh[a] * f(e, q, i) * s;
        }
        for (int a = 0; a < n; ++a) {
          const LocalIndex node = d.mesh.connectivity(e, a);
          for (int i = 0; i < dim; ++i)
            Kokkos::atomic_add(&rhs(dim * node + i), fe[a][i]);
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

namespace detail {
/// The tangents t1 = dx/ds, t2 = dx/dt of a face with nodal coordinates xf at a point with natural
/// shape derivatives ds, and na = t1 x t2 (the outward normal times the area element when the
/// face's nodes run counter-clockwise seen from outside).
template <int N>
KOKKOS_INLINE_FUNCTION void faceFrame(const double (&xf)[N][3], const double (&ds)[N][2],
                                      double (&t1)[3], double (&t2)[3], double (&na)[3]) {
  for (int i = 0; i < 3; ++i) {
    t1[i] = t2[i] = 0.0;
    for (int a = 0; a < N; ++a) {
      t1[i] += ds[a][0] * xf[a][i];
      t2[i] += ds[a][1] * xf[a][i];
    }
  }
  na[0] = t1[1] * t2[2] - t1[2] * t2[1];
  na[1] = t1[2] * t2[0] - t1[0] * t2[2];
  na[2] = t1[0] * t2[1] - t1[1] * t2[0];
}
} // namespace detail

/// Adds boundary loads on the faces of 3D elements to rhs (3 dofs per node): faces(k) =
/// (element, local face: Elem::sideNode), load(k) = (t_x, t_y, t_z, p): a traction per unit area
/// plus a pressure p acting against the outward normal (positive p pushes into the body), both on
/// the reference geometry. The face is integrated with its own element (Elem::Side: the 4-node
/// quadrilateral of a Hex8 face) and rule; dx/ds x dx/dt is the outward normal times the area
/// element because the face's nodes run counter-clockwise seen from outside.
template <class Elem, class ExecSpace, class MemorySpace>
void assembleFaceLoads(const ExecSpace &exec, const MeshView<MemorySpace, 3> &m,
                       const Kokkos::View<LocalIndex *[2], MemorySpace> &faces,
                       const Kokkos::View<double *[4], MemorySpace> &load,
                       const Kokkos::View<double *, MemorySpace> &rhs) {
  static_assert(Elem::kDim == 3, "assembleFaceLoads is the 3D boundary load (2D: edge loads)");
  using Side = typename Elem::Side;
  static_assert(Side::kNumNodes == Elem::kNodesPerSide, "a face is its Side element");
  Kokkos::parallel_for(
      "mixcon::kernels::faceLoads", Kokkos::RangePolicy<ExecSpace>(exec, 0, faces.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        constexpr int nf = Side::kNumNodes;
        const LocalIndex e = faces(k, 0);
        const int face = faces(k, 1);
        LocalIndex nodes[nf];
        double xf[nf][3], fe[nf][3] = {};
        for (int a = 0; a < nf; ++a) {
          nodes[a] = m.connectivity(e, Elem::sideNode(face, a));
          for (int i = 0; i < 3; ++i)
            xf[a][i] = m.coordinates(nodes[a], i);
        }
        for (int q = 0; q < Side::kNumQp; ++q) {
          double st[2], w, sh[nf], ds[nf][2];
          Side::quadraturePoint(q, st, w);
          Side::shape(st, sh, ds);
          double t1[3], t2[3], na[3]; // dx/ds, dx/dt, their cross product
          detail::faceFrame<nf>(xf, ds, t1, t2, na);
          const double area = detail::sqrt(na[0] * na[0] + na[1] * na[1] + na[2] * na[2]);
          for (int i = 0; i < 3; ++i) {
            const double f = load(k, i) * area - load(k, 3) * na[i];
            for (int a = 0; a < nf; ++a)
              fe[a][i] += sh[a] * f * w;
          }
        }
        for (int a = 0; a < nf; ++a)
          for (int i = 0; i < 3; ++i)
            Kokkos::atomic_add(&rhs(3 * nodes[a] + i), fe[a][i]);
      });
}

/// Device inputs of assembleFaceLoads for one load (t_x, t_y, t_z, p) shared by a list of faces.
template <class MemorySpace> struct FaceLoadBatch {
  Kokkos::View<LocalIndex *[2], MemorySpace> faces;
  Kokkos::View<double *[4], MemorySpace> load;
};

/// Copies `faces` and the uniform load (traction, pressure) to `MemorySpace`.
template <class MemorySpace>
FaceLoadBatch<MemorySpace> uniformFaceLoads(const std::vector<BoundaryEdge> &faces,
                                            const double (&traction)[3], double pressure) {
  FaceLoadBatch<MemorySpace> b{
      Kokkos::View<LocalIndex *[2], MemorySpace>("mixcon::kernels::faces", faces.size()),
      Kokkos::View<double *[4], MemorySpace>("mixcon::kernels::faceLoads", faces.size())};
  auto hf = Kokkos::create_mirror_view(b.faces);
  auto hl = Kokkos::create_mirror_view(b.load);
  for (std::size_t k = 0; k < faces.size(); ++k) {
    hf(k, 0) = faces[k].element;
    hf(k, 1) = faces[k].edge;
    for (int i = 0; i < 3; ++i)
      hl(k, i) = traction[i];
    hl(k, 3) = pressure;
  }
  Kokkos::deep_copy(b.faces, hf);
  Kokkos::deep_copy(b.load, hl);
  return b;
}

/// Internal force f = K^L u = t int B^T C eps(u) dA assembled element by element (matrix free),
/// added to f: the element driver's residual with the linear point law.
template <class Elem, class ExecSpace, class MemorySpace>
void assembleInternalForce(const ExecSpace &exec, const ElementData<MemorySpace, Elem::kDim> &d,
                           const Kokkos::View<const double *, MemorySpace> &u,
                           const Kokkos::View<double *, MemorySpace> &f) {
  assembleElementResidual<Elem>(exec, d.mesh, d.thickness, linearElasticLaw(d), u, f);
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
  const auto s = linearElasticLaw(d).at(e).stress(Vector<3>{{eps[0], eps[1], eps[2]}});
  for (int k = 0; k < 3; ++k)
    sig[k] = s.v[k];
}
} // namespace detail

/// Cauchy stress (Voigt<Dim> order: xx, yy, xy; 3D xx, yy, zz, yz, xz, xy) of the linear model at
/// every quadrature point of the element rule (the element driver's quadraturePointStress with
/// the linear point law).
template <class Elem, class ExecSpace, class MemorySpace, class... P>
void gaussPointStress(const ExecSpace &exec, const ElementData<MemorySpace, Elem::kDim> &d,
                      const Kokkos::View<const double *, MemorySpace> &u,
                      const Kokkos::View<double * * [Voigt<Elem::kDim>::kSize], P...> &stress) {
  quadraturePointStress<Elem>(exec, d.mesh, linearElasticLaw(d), u, stress);
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

/// Stress C eps(u) of the linear model at a point of a solid element, for recoverSolidNodalStress:
/// from the element's nodal coordinates xe, displacements ue and natural shape derivatives dn.
template <class Elem, class MemorySpace> struct SolidLinearStress {
  LinearElasticLaw<MemorySpace, 3> law;
  KOKKOS_INLINE_FUNCTION Vector<6> operator()(LocalIndex e, const double (&xe)[Elem::kNumNodes][3],
                                              const double (&ue)[Elem::kNumNodes][3],
                                              const double (&dn)[Elem::kNumNodes][3]) const {
    double g[Elem::kNumNodes][3];
    detail::pointGeometry<Elem>(xe, dn, g);
    return law.at(e).stress(smallStrain(detail::displacementGradient<Elem>(ue, g)));
  }
};

/// Nodal stresses of a solid mesh, averaged over the elements sharing the node (the 3D form of
/// recoverNodalStress): for hexahedra the point stress at the 2 x 2 x 2 Gauss points (+-1/sqrt(3)
/// in each natural direction) extrapolated trilinearly to every element node; for tetrahedra the
/// point stress at the node itself (constant in a Tet4, linear in a Tet10).
/// `pointStress(e, xe, ue, dn)` gives the Voigt<3> stress of element e at the point of natural
/// shape derivatives dn (e.g. SolidLinearStress). `nodal` (N x 6, Voigt<3> order) is overwritten.
template <class Elem, class ExecSpace, class MemorySpace, class PointStress>
void recoverSolidNodalStress(const ExecSpace &exec, const MeshView<MemorySpace, 3> &mesh,
                             const Kokkos::View<const double *, MemorySpace> &u,
                             const PointStress &pointStress,
                             const Kokkos::View<double *[6], MemorySpace> &nodal) {
  static_assert(Elem::kDim == 3, "recoverSolidNodalStress is the 3D recovery");
  const LocalIndex nn = nodal.extent(0);
  Kokkos::View<double *, MemorySpace> count("mixcon::kernels::stressCount", nn);
  Kokkos::deep_copy(exec, nodal, 0.0);
  Kokkos::parallel_for(
      "mixcon::kernels::solidNodalStressRecovery",
      Kokkos::RangePolicy<ExecSpace>(exec, 0, mesh.connectivity.extent(0)),
      KOKKOS_LAMBDA(LocalIndex e) {
        constexpr int n = Elem::kNumNodes, kCorners = 8, kS = 6;
        constexpr double g = 0.57735026918962576451; // 1/sqrt(3)
        // Named before the `if constexpr`: nvcc's extended lambdas may not first-capture there.
        const auto &sum = nodal;
        const auto &hits = count;
        const auto &stressAt = pointStress;
        double xe[n][3], ue[n][3], sg[kCorners][kS];
        detail::gatherElementCoordinates<Elem>(mesh, e, xe);
        detail::gatherElementDisplacements<Elem>(mesh, u, e, ue);
        if constexpr (Elem::kSimplex) {
          for (int a = 0; a < n; ++a) {
            double xa[3], sh[n], dn[n][3];
            Elem::nodeNatural(a, xa);
            Elem::shape(xa, sh, dn);
            const Vector<kS> sig = stressAt(e, xe, ue, dn);
            const LocalIndex node = mesh.connectivity(e, a);
            for (int k = 0; k < kS; ++k)
              Kokkos::atomic_add(&sum(node, k), sig.v[k]);
            Kokkos::atomic_add(&hits(node), 1.0);
          }
        } else {
          // Corner c of the Gauss cube: sign of direction i is bit i of c.
          for (int c = 0; c < kCorners; ++c) {
            const double xi[3] = {(c & 1) ? g : -g, (c & 2) ? g : -g, (c & 4) ? g : -g};
            double sh[n], dn[n][3];
            Elem::shape(xi, sh, dn);
            const Vector<kS> sig = stressAt(e, xe, ue, dn);
            for (int k = 0; k < kS; ++k)
              sg[c][k] = sig.v[k];
          }
          for (int a = 0; a < n; ++a) {
            double xa[3];
            Elem::nodeNatural(a, xa);
            const LocalIndex node = mesh.connectivity(e, a);
            for (int k = 0; k < kS; ++k) {
              double v = 0.0;
              for (int c = 0; c < kCorners; ++c)
                v += 0.125 * (1.0 + xa[0] / g * ((c & 1) ? 1.0 : -1.0)) *
                     (1.0 + xa[1] / g * ((c & 2) ? 1.0 : -1.0)) *
                     (1.0 + xa[2] / g * ((c & 4) ? 1.0 : -1.0)) * sg[c][k];
              Kokkos::atomic_add(&sum(node, k), v);
            }
            Kokkos::atomic_add(&hits(node), 1.0);
          }
        }
      });
  Kokkos::parallel_for(
      "mixcon::kernels::solidNodalStressAverage", Kokkos::RangePolicy<ExecSpace>(exec, 0, nn),
      KOKKOS_LAMBDA(LocalIndex i) {
        if (count(i) > 0.0)
          for (int k = 0; k < 6; ++k)
            nodal(i, k) /= count(i);
      });
}

/// Nodal stresses of the linear model in 3D (recoverSolidNodalStress of C eps(u)).
template <class Elem, class ExecSpace, class MemorySpace>
void solidNodalStressRecovery(const ExecSpace &exec, const ElementData<MemorySpace, 3> &d,
                              const Kokkos::View<const double *, MemorySpace> &u,
                              const Kokkos::View<double *[6], MemorySpace> &nodal) {
  recoverSolidNodalStress<Elem>(exec, d.mesh, u,
                                SolidLinearStress<Elem, MemorySpace>{linearElasticLaw(d)}, nodal);
}

} // namespace mixcon
