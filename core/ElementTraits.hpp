// Element types as compile-time traits: shape functions, natural-coordinate derivatives,
// quadrature rules and edge topology for the 2D isoparametric quadrilaterals of the report, and
// the trilinear hexahedron (Hex8) of the 3D kernels. Every element gives the dimension-generic
// reference API the element driver uses (quadraturePoint(q, xi[kDim], w), shape(xi[kDim], n,
// dn)); the quadrilaterals keep their (xi, eta) forms, which the 2D kernels call.
// Everything here is device-callable and allocation free, except dispatchElement (host). Layer:
// core, the bottom one (mesh, kernels and everything above include it).
#pragma once

#include <core/Compat.hpp>
#include <core/Tensor.hpp>

#include <stdexcept>
#include <string>

namespace mixcon {

/// Runtime tag used on the host to choose the compile-time traits once (switch, then template).
enum class ElementType { Quad4, Quad8, Hex8, Hex20, Tet4, Tet10 };

namespace detail {
// Gauss-Legendre abscissae and weights on [-1, 1].
KOKKOS_INLINE_FUNCTION void gauss1d(int order, int i, double &x, double &w) {
  if (order == 2) {
    constexpr double a = 0.57735026918962576451; // 1/sqrt(3)
    x = (i == 0) ? -a : a;
    w = 1.0;
  } else {                                       // order 3
    constexpr double a = 0.77459666924148337704; // sqrt(3/5)
    x = (i == 0) ? -a : (i == 1 ? 0.0 : a);
    w = (i == 1) ? 8.0 / 9.0 : 5.0 / 9.0;
  }
}
/// Point q of the tensor Gauss rule of `order` points per direction on the cube (xi fastest,
/// zeta slowest) and its weight.
KOKKOS_INLINE_FUNCTION void tensorGaussPoint3(int order, int q, double (&xi)[3], double &w) {
  double w0, w1, w2;
  gauss1d(order, q % order, xi[0], w0);
  gauss1d(order, (q / order) % order, xi[1], w1);
  gauss1d(order, q / (order * order), xi[2], w2);
  w = w0 * w1 * w2;
}
// Natural coordinates of the four corners, counter-clockwise from (-1,-1).
KOKKOS_INLINE_FUNCTION double cornerXi(int a) { return (a == 0 || a == 3) ? -1.0 : 1.0; }
KOKKOS_INLINE_FUNCTION double cornerEta(int a) { return (a < 2) ? -1.0 : 1.0; }
} // namespace detail

/// 4-node bilinear quadrilateral, 2x2 Gauss quadrature, 2-node edges.
struct Quad4 {
  static constexpr ElementType kType = ElementType::Quad4;
  static constexpr int kDim = 2;
  using Layout = FieldLayout<kDim>; ///< unknowns per node of each model in this dimension
  static constexpr int kNumNodes = 4;
  static constexpr int kGaussOrder = 2;
  static constexpr int kNumQp = 4;
  static constexpr int kNumEdges = 4;
  static constexpr int kNodesPerEdge = 2;
  static constexpr int kNumEdgeQp = 2;
  static constexpr const char *kName = "quad4";

  /// Shape functions N and derivatives dN/dxi (dN[a][0]) and dN/deta (dN[a][1]).
  KOKKOS_INLINE_FUNCTION static void shape(double xi, double eta, double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][2]) {
    for (int a = 0; a < kNumNodes; ++a) {
      const double xa = detail::cornerXi(a), ea = detail::cornerEta(a);
      n[a] = 0.25 * (1.0 + xi * xa) * (1.0 + eta * ea);
      dn[a][0] = 0.25 * xa * (1.0 + eta * ea);
      dn[a][1] = 0.25 * ea * (1.0 + xi * xa);
    }
  }
  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double &xi, double &eta) {
    xi = detail::cornerXi(a);
    eta = detail::cornerEta(a);
  }
  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double (&xi)[kDim]) {
    nodeNatural(a, xi[0], xi[1]);
  }
  /// Local node k (0..kNodesPerEdge-1) of edge e; edge e runs from corner e to corner e+1.
  KOKKOS_INLINE_FUNCTION static int edgeNode(int e, int k) { return k == 0 ? e : (e + 1) % 4; }
  /// The dimension-generic boundary API: the sides of a 2D element are its edges.
  static constexpr int kNumSides = kNumEdges;
  static constexpr int kNodesPerSide = kNodesPerEdge;
  KOKKOS_INLINE_FUNCTION static int sideNode(int s, int k) { return edgeNode(s, k); }
  /// Quadrature point q of the element rule (tensor Gauss), natural coordinates and weight.
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double &xi, double &eta, double &w) {
    double wx, we;
    detail::gauss1d(kGaussOrder, q % kGaussOrder, xi, wx);
    detail::gauss1d(kGaussOrder, q / kGaussOrder, eta, we);
    w = wx * we;
  }
  /// The dimension-generic forms of quadraturePoint and shape (natural coordinates as an array).
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    quadraturePoint(q, xi[0], xi[1], w);
  }
  KOKKOS_INLINE_FUNCTION static void shape(const double (&xi)[kDim], double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][kDim]) {
    shape(xi[0], xi[1], n, dn);
  }
};

/// 8-node serendipity quadrilateral, 3x3 Gauss quadrature, 3-node edges. Node order as Gmsh:
/// corners 0..3 counter-clockwise, then mid-side nodes 4 (0-1), 5 (1-2), 6 (2-3), 7 (3-0).
struct Quad8 {
  static constexpr ElementType kType = ElementType::Quad8;
  static constexpr int kDim = 2;
  using Layout = FieldLayout<kDim>; ///< unknowns per node of each model in this dimension
  static constexpr int kNumNodes = 8;
  static constexpr int kGaussOrder = 3;
  static constexpr int kNumQp = 9;
  static constexpr int kNumEdges = 4;
  static constexpr int kNodesPerEdge = 3;
  static constexpr int kNumEdgeQp = 3;
  static constexpr const char *kName = "quad8";

  KOKKOS_INLINE_FUNCTION static void shape(double xi, double eta, double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][2]) {
    for (int a = 0; a < 4; ++a) {
      const double xa = detail::cornerXi(a), ea = detail::cornerEta(a);
      const double p = 1.0 + xi * xa, q = 1.0 + eta * ea, s = xi * xa + eta * ea - 1.0;
      n[a] = 0.25 * p * q * s;
      dn[a][0] = 0.25 * xa * q * (s + p);
      dn[a][1] = 0.25 * ea * p * (s + q);
    }
    // Mid-sides on eta = -1 and eta = +1 (nodes 4, 6): xi_a = 0.
    for (int k = 0; k < 2; ++k) {
      const int a = 4 + 2 * k;
      const double ea = (k == 0) ? -1.0 : 1.0;
      n[a] = 0.5 * (1.0 - xi * xi) * (1.0 + eta * ea);
      dn[a][0] = -xi * (1.0 + eta * ea);
      dn[a][1] = 0.5 * ea * (1.0 - xi * xi);
    }
    // Mid-sides on xi = +1 and xi = -1 (nodes 5, 7): eta_a = 0.
    for (int k = 0; k < 2; ++k) {
      const int a = 5 + 2 * k;
      const double xa = (k == 0) ? 1.0 : -1.0;
      n[a] = 0.5 * (1.0 + xi * xa) * (1.0 - eta * eta);
      dn[a][0] = 0.5 * xa * (1.0 - eta * eta);
      dn[a][1] = -eta * (1.0 + xi * xa);
    }
  }
  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double &xi, double &eta) {
    if (a < 4) {
      xi = detail::cornerXi(a);
      eta = detail::cornerEta(a);
    } else {
      constexpr double mx[4] = {0.0, 1.0, 0.0, -1.0}, me[4] = {-1.0, 0.0, 1.0, 0.0};
      xi = mx[a - 4];
      eta = me[a - 4];
    }
  }
  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double (&xi)[kDim]) {
    nodeNatural(a, xi[0], xi[1]);
  }
  /// Edge e: corner e, corner e+1, mid-side 4+e (the order of a 3-node Gmsh line).
  KOKKOS_INLINE_FUNCTION static int edgeNode(int e, int k) {
    return k == 0 ? e : (k == 1 ? (e + 1) % 4 : 4 + e);
  }
  /// The dimension-generic boundary API: the sides of a 2D element are its edges.
  static constexpr int kNumSides = kNumEdges;
  static constexpr int kNodesPerSide = kNodesPerEdge;
  KOKKOS_INLINE_FUNCTION static int sideNode(int s, int k) { return edgeNode(s, k); }
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double &xi, double &eta, double &w) {
    double wx, we;
    detail::gauss1d(kGaussOrder, q % kGaussOrder, xi, wx);
    detail::gauss1d(kGaussOrder, q / kGaussOrder, eta, we);
    w = wx * we;
  }
  /// The dimension-generic forms of quadraturePoint and shape (natural coordinates as an array).
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    quadraturePoint(q, xi[0], xi[1], w);
  }
  KOKKOS_INLINE_FUNCTION static void shape(const double (&xi)[kDim], double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][kDim]) {
    shape(xi[0], xi[1], n, dn);
  }
};

/// 8-node trilinear hexahedron, 2x2x2 Gauss quadrature. Node order as Gmsh and VTK: the bottom
/// face (zeta = -1) counter-clockwise from (-1,-1,-1), nodes 0..3, then the top face (zeta = +1)
/// in the same order, nodes 4..7. Faces (the sides of the boundary API) are 4-node quadrilaterals
/// whose nodes run counter-clockwise seen from outside, so that dx/ds x dx/dt of the face's
/// bilinear map points out of the element: 0 (zeta = -1), 1 (zeta = +1), 2 (eta = -1), 3 (xi = +1),
/// 4 (eta = +1), 5 (xi = -1).
struct Hex8 {
  static constexpr ElementType kType = ElementType::Hex8;
  static constexpr int kDim = 3;
  using Layout = FieldLayout<kDim>; ///< unknowns per node of each model in this dimension
  static constexpr int kNumNodes = 8;
  static constexpr int kGaussOrder = 2;
  static constexpr int kNumQp = 8;
  static constexpr int kNumSides = 6;
  static constexpr int kNodesPerSide = 4;
  using Side = Quad4; ///< a face: the bilinear quadrilateral of its 4 nodes (and its 2x2 rule)
  static constexpr bool kSimplex = false;
  static constexpr const char *kName = "hex8";

  /// Local node k (0..3) of face f (see the struct's comment for the numbering).
  KOKKOS_INLINE_FUNCTION static int sideNode(int f, int k) {
    constexpr int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                 {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    return faces[f][k];
  }

  /// Natural coordinates of node a.
  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double (&xi)[kDim]) {
    xi[0] = detail::cornerXi(a % 4);
    xi[1] = detail::cornerEta(a % 4);
    xi[2] = a < 4 ? -1.0 : 1.0;
  }
  /// Shape functions N_a = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a) / 8 and dN_a/dxi_j.
  KOKKOS_INLINE_FUNCTION static void shape(const double (&xi)[kDim], double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][kDim]) {
    for (int a = 0; a < kNumNodes; ++a) {
      double xa[kDim];
      nodeNatural(a, xa);
      const double p0 = 1.0 + xi[0] * xa[0], p1 = 1.0 + xi[1] * xa[1], p2 = 1.0 + xi[2] * xa[2];
      n[a] = 0.125 * p0 * p1 * p2;
      dn[a][0] = 0.125 * xa[0] * p1 * p2;
      dn[a][1] = 0.125 * xa[1] * p0 * p2;
      dn[a][2] = 0.125 * xa[2] * p0 * p1;
    }
  }
  /// Quadrature point q of the tensor Gauss rule (xi fastest, zeta slowest) and its weight.
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    detail::tensorGaussPoint3(kGaussOrder, q, xi, w);
  }
};

namespace detail {
/// The node layout shared by the quadratic solids (Hex20, Tet10) over their linear element
/// Linear (Hex8, Tet4): Linear's corners first, then one node at the middle of each edge
/// Elem::edgeCorner(k, 0..1); a face lists its Linear corners, then the mid-edge nodes of its
/// edges corner 0-1, 1-2, ... (the order of Quad8 and Tri6).
template <class Elem, class Linear> struct MidEdgeNodes {
  static constexpr int kCorners = Linear::kNumNodes;
  static constexpr int kEdges = Elem::kNumNodes - kCorners;
  static constexpr int kFaceCorners = Linear::kNodesPerSide;

  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double (&xi)[3]) {
    if (a < kCorners) {
      Linear::nodeNatural(a, xi);
      return;
    }
    double x0[3], x1[3];
    Linear::nodeNatural(Elem::edgeCorner(a - kCorners, 0), x0);
    Linear::nodeNatural(Elem::edgeCorner(a - kCorners, 1), x1);
    for (int i = 0; i < 3; ++i)
      xi[i] = 0.5 * (x0[i] + x1[i]);
  }
  KOKKOS_INLINE_FUNCTION static int sideNode(int f, int k) {
    if (k < kFaceCorners)
      return Linear::sideNode(f, k);
    const int c0 = Linear::sideNode(f, k - kFaceCorners);
    const int c1 = Linear::sideNode(f, (k - kFaceCorners + 1) % kFaceCorners);
    for (int e = 0; e < kEdges; ++e)
      if ((Elem::edgeCorner(e, 0) == c0 && Elem::edgeCorner(e, 1) == c1) ||
          (Elem::edgeCorner(e, 0) == c1 && Elem::edgeCorner(e, 1) == c0))
        return kCorners + e;
    return -1; // not reached: every face edge is an element edge
  }
};
} // namespace detail

/// 20-node serendipity hexahedron, 3x3x3 Gauss quadrature. Node order as VTK and XDMF
/// (Hexahedron_20): the corners as Hex8 (0..7), then the mid-edge nodes of the bottom face's edges
/// 8 (0-1), 9 (1-2), 10 (2-3), 11 (3-0), of the top face's 12 (4-5), 13 (5-6), 14 (6-7),
/// 15 (7-4), and of the vertical edges 16 (0-4), 17 (1-5), 18 (2-6), 19 (3-7). (Gmsh numbers the
/// mid-edge nodes otherwise; its reader reorders them.) Faces as Hex8 (same corners, same
/// outward counter-clockwise order), each an 8-node quadrilateral: its corners, then the
/// mid-edge nodes of its edges in the order corner 0-1, 1-2, 2-3, 3-0 (Quad8's order).
struct Hex20 {
  static constexpr ElementType kType = ElementType::Hex20;
  static constexpr int kDim = 3;
  using Layout = FieldLayout<kDim>; ///< unknowns per node of each model in this dimension
  static constexpr int kNumNodes = 20;
  static constexpr int kGaussOrder = 3;
  static constexpr int kNumQp = 27;
  static constexpr int kNumSides = 6;
  static constexpr int kNodesPerSide = 8;
  using Side = Quad8; ///< a face: the serendipity quadrilateral of its 8 nodes (and its 3x3 rule)
  static constexpr bool kSimplex = false;
  static constexpr const char *kName = "hex20";

  /// The corners (Hex8 numbering) that mid-edge node 8 + k lies between.
  KOKKOS_INLINE_FUNCTION static int edgeCorner(int k, int end) {
    constexpr int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    return edges[k][end];
  }
  /// Natural coordinates of node a.
  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double (&xi)[kDim]) {
    detail::MidEdgeNodes<Hex20, Hex8>::nodeNatural(a, xi);
  }
  /// Serendipity shape functions: corner a, N = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a)
  /// (xi xi_a + eta eta_a + zeta zeta_a - 2) / 8; mid-edge node with xi_a = 0 (and likewise for
  /// the other directions), N = (1 - xi^2)(1 + eta eta_a)(1 + zeta zeta_a) / 4.
  KOKKOS_INLINE_FUNCTION static void shape(const double (&xi)[kDim], double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][kDim]) {
    for (int a = 0; a < kNumNodes; ++a) {
      double xa[kDim];
      nodeNatural(a, xa);
      double p[kDim]; // 1 + xi_i xa_i
      for (int i = 0; i < kDim; ++i)
        p[i] = 1.0 + xi[i] * xa[i];
      if (a < 8) {
        const double s = xi[0] * xa[0] + xi[1] * xa[1] + xi[2] * xa[2] - 2.0;
        n[a] = 0.125 * p[0] * p[1] * p[2] * s;
        for (int i = 0; i < kDim; ++i) {
          const double others = p[(i + 1) % 3] * p[(i + 2) % 3];
          dn[a][i] = 0.125 * others * xa[i] * (s + p[i]);
        }
      } else {
        int zero = 0; // the direction along the node's edge: xa = 0 there
        for (int i = 0; i < kDim; ++i)
          if (xa[i] == 0.0)
            zero = i;
        const int j = (zero + 1) % 3, k = (zero + 2) % 3;
        const double q = 1.0 - xi[zero] * xi[zero];
        n[a] = 0.25 * q * p[j] * p[k];
        dn[a][zero] = -0.5 * xi[zero] * p[j] * p[k];
        dn[a][j] = 0.25 * q * xa[j] * p[k];
        dn[a][k] = 0.25 * q * p[j] * xa[k];
      }
    }
  }
  /// Local node k (0..7) of face f: the Hex8 face's corners, then its edges' mid-edge nodes.
  KOKKOS_INLINE_FUNCTION static int sideNode(int f, int k) {
    return detail::MidEdgeNodes<Hex20, Hex8>::sideNode(f, k);
  }
  /// Quadrature point q of the tensor Gauss rule (xi fastest, zeta slowest) and its weight.
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    detail::tensorGaussPoint3(kGaussOrder, q, xi, w);
  }
};

/// 3-node triangle: the face of a Tet4 (not an element of the program). Natural coordinates
/// (s, t) with nodes at (0, 0), (1, 0), (0, 1); the 3-point rule of degree 2 (Strang & Fix).
struct Tri3 {
  static constexpr int kDim = 2;
  static constexpr int kNumNodes = 3;
  static constexpr int kNumQp = 3;
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    xi[0] = q == 1 ? 2.0 / 3.0 : 1.0 / 6.0;
    xi[1] = q == 2 ? 2.0 / 3.0 : 1.0 / 6.0;
    w = 1.0 / 6.0;
  }
  KOKKOS_INLINE_FUNCTION static void shape(const double (&xi)[kDim], double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][kDim]) {
    n[0] = 1.0 - xi[0] - xi[1];
    n[1] = xi[0];
    n[2] = xi[1];
    dn[0][0] = dn[0][1] = -1.0;
    dn[1][0] = 1.0;
    dn[1][1] = 0.0;
    dn[2][0] = 0.0;
    dn[2][1] = 1.0;
  }
};

/// 6-node triangle: the face of a Tet10. Corners as Tri3, then the mid-edge nodes 3 (0-1),
/// 4 (1-2), 5 (2-0); the same 3-point rule (exact for the loads of a flat face).
struct Tri6 {
  static constexpr int kDim = 2;
  static constexpr int kNumNodes = 6;
  static constexpr int kNumQp = 3;
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    Tri3::quadraturePoint(q, xi, w);
  }
  KOKKOS_INLINE_FUNCTION static void shape(const double (&xi)[kDim], double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][kDim]) {
    const double l[3] = {1.0 - xi[0] - xi[1], xi[0], xi[1]};
    const double dl[3][2] = {{-1.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}};
    for (int a = 0; a < 3; ++a) {
      n[a] = l[a] * (2.0 * l[a] - 1.0);
      for (int j = 0; j < 2; ++j)
        dn[a][j] = (4.0 * l[a] - 1.0) * dl[a][j];
      const int b = (a + 1) % 3;
      n[3 + a] = 4.0 * l[a] * l[b];
      for (int j = 0; j < 2; ++j)
        dn[3 + a][j] = 4.0 * (dl[a][j] * l[b] + l[a] * dl[b][j]);
    }
  }
};

namespace detail {
/// Barycentric coordinates of the tetrahedron's natural point: L0 = 1 - xi - eta - zeta,
/// L1 = xi, L2 = eta, L3 = zeta, and dL_a / dxi_j.
KOKKOS_INLINE_FUNCTION void tetBarycentric(const double (&xi)[3], double (&l)[4]) {
  l[0] = 1.0 - xi[0] - xi[1] - xi[2];
  l[1] = xi[0];
  l[2] = xi[1];
  l[3] = xi[2];
}
KOKKOS_INLINE_FUNCTION double tetBarycentricDerivative(int a, int j) {
  return a == 0 ? -1.0 : (a - 1 == j ? 1.0 : 0.0);
}
/// Face f of a tetrahedron, corner k: counter-clockwise seen from outside.
KOKKOS_INLINE_FUNCTION int tetFaceCorner(int f, int k) {
  constexpr int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return faces[f][k];
}
} // namespace detail

/// 4-node linear tetrahedron (constant strain), one-point rule (exact for its stiffness). Node
/// order as Gmsh and VTK: natural coordinates (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), positive
/// volume when node 3 lies on the side of face 0-1-2 that (x1 - x0) x (x2 - x0) points to. Faces
/// (3-node triangles, counter-clockwise seen from outside): 0 (0 2 1), 1 (0 1 3), 2 (1 2 3),
/// 3 (0 3 2).
struct Tet4 {
  static constexpr ElementType kType = ElementType::Tet4;
  static constexpr int kDim = 3;
  using Layout = FieldLayout<kDim>; ///< unknowns per node of each model in this dimension
  static constexpr int kNumNodes = 4;
  static constexpr int kNumQp = 1;
  static constexpr int kNumSides = 4;
  static constexpr int kNodesPerSide = 3;
  static constexpr bool kSimplex = true;
  using Side = Tri3;
  static constexpr const char *kName = "tet4";

  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double (&xi)[kDim]) {
    for (int i = 0; i < kDim; ++i)
      xi[i] = a == i + 1 ? 1.0 : 0.0;
  }
  KOKKOS_INLINE_FUNCTION static void shape(const double (&xi)[kDim], double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][kDim]) {
    double l[4];
    detail::tetBarycentric(xi, l);
    for (int a = 0; a < kNumNodes; ++a) {
      n[a] = l[a];
      for (int j = 0; j < kDim; ++j)
        dn[a][j] = detail::tetBarycentricDerivative(a, j);
    }
  }
  KOKKOS_INLINE_FUNCTION static int sideNode(int f, int k) { return detail::tetFaceCorner(f, k); }
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int, double (&xi)[kDim], double &w) {
    xi[0] = xi[1] = xi[2] = 0.25;
    w = 1.0 / 6.0;
  }
};

/// 10-node quadratic tetrahedron, 4-point rule of degree 2 (exact for its stiffness on straight
/// edges). Node order as VTK and XDMF (Tetrahedron_10): the corners as Tet4, then the mid-edge
/// nodes 4 (0-1), 5 (1-2), 6 (2-0), 7 (0-3), 8 (1-3), 9 (2-3). (Gmsh numbers the last two
/// 8 (2-3), 9 (1-3); its reader swaps them.) Faces as Tet4, each a 6-node triangle: its corners,
/// then the mid-edge nodes of its edges c0-c1, c1-c2, c2-c0.
struct Tet10 {
  static constexpr ElementType kType = ElementType::Tet10;
  static constexpr int kDim = 3;
  using Layout = FieldLayout<kDim>; ///< unknowns per node of each model in this dimension
  static constexpr int kNumNodes = 10;
  static constexpr int kNumQp = 4;
  static constexpr int kNumSides = 4;
  static constexpr int kNodesPerSide = 6;
  static constexpr bool kSimplex = true;
  using Side = Tri6;
  static constexpr const char *kName = "tet10";

  /// The corners that mid-edge node 4 + k lies between.
  KOKKOS_INLINE_FUNCTION static int edgeCorner(int k, int end) {
    constexpr int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
    return edges[k][end];
  }
  KOKKOS_INLINE_FUNCTION static void nodeNatural(int a, double (&xi)[kDim]) {
    detail::MidEdgeNodes<Tet10, Tet4>::nodeNatural(a, xi);
  }
  /// Corners L_a (2 L_a - 1), mid-edge nodes 4 L_a L_b.
  KOKKOS_INLINE_FUNCTION static void shape(const double (&xi)[kDim], double (&n)[kNumNodes],
                                           double (&dn)[kNumNodes][kDim]) {
    double l[4];
    detail::tetBarycentric(xi, l);
    for (int a = 0; a < 4; ++a) {
      n[a] = l[a] * (2.0 * l[a] - 1.0);
      for (int j = 0; j < kDim; ++j)
        dn[a][j] = (4.0 * l[a] - 1.0) * detail::tetBarycentricDerivative(a, j);
    }
    for (int k = 0; k < 6; ++k) {
      const int a = edgeCorner(k, 0), b = edgeCorner(k, 1);
      n[4 + k] = 4.0 * l[a] * l[b];
      for (int j = 0; j < kDim; ++j)
        dn[4 + k][j] = 4.0 * (detail::tetBarycentricDerivative(a, j) * l[b] +
                              l[a] * detail::tetBarycentricDerivative(b, j));
    }
  }
  /// Local node k (0..5) of face f: its corners, then the mid-edge nodes of its edges.
  KOKKOS_INLINE_FUNCTION static int sideNode(int f, int k) {
    return detail::MidEdgeNodes<Tet10, Tet4>::sideNode(f, k);
  }
  /// The symmetric 4-point rule of degree 2: points with barycentric (a, b, b, b) and
  /// permutations, a = (5 + 3 sqrt 5) / 20, b = (5 - sqrt 5) / 20, weights 1/24.
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    constexpr double a = 0.58541019662496845446, b = 0.13819660112501051518;
    for (int i = 0; i < kDim; ++i)
      xi[i] = q == i + 1 ? a : b;
    w = 1.0 / 24.0;
  }
};

/// The element of the 3D mixed models: the displacement element with a quadrature rule that
/// integrates the compliance mass M = int Psi^T D Psi of its equal-order stresses exactly on
/// straight-edged elements (degree twice the shape functions'). The hexahedra's tensor rules do on
/// parallelepipeds (Hex8 2x2x2, Hex20 3x3x3; on distorted ones det J adds degrees, as for any
/// isoparametric mass) and keep M regular; the tetrahedra's displacement rules do not (Tet4: one
/// point, Tet10: degree 2), and with them M is singular: the patch test's displacements came out
/// exact but its nodal stresses wrong (3.3x the exact value on Tet4, 3.5 % off on Tet10).
template <class Elem> struct MixedRuleOf { using type = Elem; };
/// Tet4 with Tet10's 4-point rule of degree 2.
struct Tet4Mixed : Tet4 {
  static constexpr int kNumQp = 4;
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    Tet10::quadraturePoint(q, xi, w);
  }
};
/// Tet10 with the symmetric 14-point rule of degree 5 (positive weights; Walkington, "Quadrature
/// on simplices of arbitrary dimension", 2000): 4 points with barycentric (b1, a1, a1, a1) and
/// permutations, 4 with (b2, a2, a2, a2), 6 with (a3, a3, b3, b3).
struct Tet10Mixed : Tet10 {
  static constexpr int kNumQp = 14;
  KOKKOS_INLINE_FUNCTION static void quadraturePoint(int q, double (&xi)[kDim], double &w) {
    constexpr double a1 = 0.0927352503108912, b1 = 0.7217942490673264, w1 = 0.01224884051939366;
    constexpr double a2 = 0.3108859192633006, b2 = 0.0673422422100982, w2 = 0.01878132095300264;
    constexpr double a3 = 0.4544962958743504, b3 = 0.0455037041256496, w3 = 0.007091003462846911;
    constexpr int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    double l[4];
    if (q < 8) { // one corner b, the others a
      const double a = q < 4 ? a1 : a2, b = q < 4 ? b1 : b2;
      for (int k = 0; k < 4; ++k)
        l[k] = k == q % 4 ? b : a;
      w = q < 4 ? w1 : w2;
    } else { // two corners a3, the others b3
      for (int k = 0; k < 4; ++k)
        l[k] = k == pairs[q - 8][0] || k == pairs[q - 8][1] ? a3 : b3;
      w = w3;
    }
    for (int i = 0; i < kDim; ++i)
      xi[i] = l[i + 1];
  }
};
template <> struct MixedRuleOf<Tet4> { using type = Tet4Mixed; };
template <> struct MixedRuleOf<Tet10> { using type = Tet10Mixed; };
template <class Elem> using MixedRule = typename MixedRuleOf<Elem>::type;

/// 1D shape functions along an element edge, parameter s in [-1, 1] from the edge's first to
/// its second node (a 3-node edge has its middle node last).
template <int NodesPerEdge>
KOKKOS_INLINE_FUNCTION void edgeShape(double s, double (&n)[NodesPerEdge],
                                      double (&dn)[NodesPerEdge]) {
  if constexpr (NodesPerEdge == 2) {
    n[0] = 0.5 * (1.0 - s);
    n[1] = 0.5 * (1.0 + s);
    dn[0] = -0.5;
    dn[1] = 0.5;
  } else {
    n[0] = 0.5 * s * (s - 1.0);
    n[1] = 0.5 * s * (s + 1.0);
    n[2] = 1.0 - s * s;
    dn[0] = s - 0.5;
    dn[1] = s + 0.5;
    dn[2] = -2.0 * s;
  }
}

/// Jacobian of the isoparametric map at one point: J[i][j] = d x_i / d xi_j, its determinant,
/// and the physical shape-function gradients dNdx[a][i] = d N_a / d x_i.
/// Coordinates come as xe[a][i] of the element's nodes.
template <class Elem>
KOKKOS_INLINE_FUNCTION double physicalGradients(const double (&xe)[Elem::kNumNodes][2],
                                                const double (&dn)[Elem::kNumNodes][2],
                                                double (&dndx)[Elem::kNumNodes][2]) {
  static_assert(Elem::kDim == 2, "physicalGradients is the 2D map (2x2 Jacobian)");
  double j00 = 0, j01 = 0, j10 = 0, j11 = 0;
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    j00 += xe[a][0] * dn[a][0];
    j01 += xe[a][0] * dn[a][1];
    j10 += xe[a][1] * dn[a][0];
    j11 += xe[a][1] * dn[a][1];
  }
  const double det = j00 * j11 - j01 * j10;
  const double inv = 1.0 / det;
  // d xi_j / d x_i = (J^-1)[j][i]
  const double i00 = j11 * inv, i01 = -j01 * inv, i10 = -j10 * inv, i11 = j00 * inv;
  for (int a = 0; a < Elem::kNumNodes; ++a) {
    dndx[a][0] = dn[a][0] * i00 + dn[a][1] * i10;
    dndx[a][1] = dn[a][0] * i01 + dn[a][1] * i11;
  }
  return det;
}

/// det(d x / d xi) of the isoparametric map at a point, any dimension: coordinates xe[a][i] of
/// the element's nodes, natural derivatives dn[a][j] of its shape functions there.
template <class Elem>
KOKKOS_INLINE_FUNCTION double jacobianDeterminant(const double (&xe)[Elem::kNumNodes][Elem::kDim],
                                                  const double (&dn)[Elem::kNumNodes][Elem::kDim]) {
  Mat<Elem::kDim, Elem::kDim> jac{};
  for (int a = 0; a < Elem::kNumNodes; ++a)
    for (int i = 0; i < Elem::kDim; ++i)
      for (int j = 0; j < Elem::kDim; ++j)
        jac.m[i][j] += xe[a][i] * dn[a][j];
  return determinant(jac);
}

/// Field layout (unknowns per node, field offsets) of an element's dimension.
template <class Elem> using LayoutOf = typename Elem::Layout;

/// Calls f(ElemTraits{}) with the traits matching a runtime element type (host-side dispatch),
/// for code written for every dimension (f is instantiated with the 2D and the 3D elements).
/// Throws std::invalid_argument for a value that names no element type (never falls back).
template <class F> decltype(auto) dispatchElement(ElementType type, F &&f) {
  switch (type) {
  case ElementType::Quad4:
    return f(Quad4{});
  case ElementType::Quad8:
    return f(Quad8{});
  case ElementType::Hex8:
    return f(Hex8{});
  case ElementType::Hex20:
    return f(Hex20{});
  case ElementType::Tet4:
    return f(Tet4{});
  case ElementType::Tet10:
    return f(Tet10{});
  }
  throw std::invalid_argument("dispatchElement: unknown ElementType value " +
                              std::to_string(static_cast<int>(type)));
}

/// The name of an element type (its traits' kName).
inline std::string elementTypeName(ElementType type) {
  return dispatchElement(type, [](auto elem) { return std::string(decltype(elem)::kName); });
}

/// dispatchElement for code that exists in 2D only (the nonlinear and mixed models, contact, the
/// plane-geometry helpers): f is instantiated with the quadrilaterals alone. A 3D element type
/// throws std::invalid_argument naming `what` (the problem reader refuses such input first, with
/// its file and line; this is the guard of the C++ API).
template <class F> decltype(auto) dispatchPlaneElement(ElementType type, const char *what, F &&f) {
  switch (type) {
  case ElementType::Quad4:
    return f(Quad4{});
  case ElementType::Quad8:
    return f(Quad8{});
  case ElementType::Hex8:
  case ElementType::Hex20:
  case ElementType::Tet4:
  case ElementType::Tet10:
    break;
  }
  throw std::invalid_argument(std::string(what) + " is 2D only so far (issue 17); element type " +
                              std::to_string(static_cast<int>(type)) + " is not a quadrilateral");
}

/// dispatchElement for code that exists in 3D only (the 3D mixed models): f is instantiated with
/// the hexahedra and tetrahedra alone. A 2D element type throws std::invalid_argument naming
/// `what` (the problem reader refuses such input first, with its file and line).
template <class F> decltype(auto) dispatchSolidElement(ElementType type, const char *what, F &&f) {
  switch (type) {
  case ElementType::Hex8:
    return f(Hex8{});
  case ElementType::Hex20:
    return f(Hex20{});
  case ElementType::Tet4:
    return f(Tet4{});
  case ElementType::Tet10:
    return f(Tet10{});
  case ElementType::Quad4:
  case ElementType::Quad8:
    break;
  }
  throw std::invalid_argument(std::string(what) + " is 3D; element type " +
                              std::to_string(static_cast<int>(type)) + " is not a solid");
}

} // namespace mixcon
