// Matrix-free application of the linear mixed model's blocks (issue 16, item 3): the coupling
// y = K12 s, its transpose r = K12^T u and the consistent compliance z = M s computed element by
// element at the quadrature points, without element or global matrices (MFEM's partial / full
// assembly split, libCEED's point functions):
//   partial assembly - per element and quadrature point only the geometric factors are stored:
//                      the weight t w det J and the weighted physical gradients t w det J dpsi/dx
//                      (1 + n Dim doubles per point); the shape values are the reference table's;
//   matrix-free      - the geometry is recomputed from the nodal coordinates at every apply.
// Per point the arithmetic is that of Eq. (29)-(30) written with Voigt<Dim>: the strain
// eps = B u (engineering shear), the force B^T sigma, the compliance psi^T D psi; the element
// results are scattered (atomic adds, or element colors without atomics: MixedScatter) into the
// same node-interleaved unknowns as the assembled MixedOperators (u: Dim per node, stresses:
// Voigt<Dim>::kSize per node). The lumped compliance blocks (the inner CG's preconditioner, the
// Schur preconditioner) stay assembled. Layer: kernels (data flow: mesh -> kernels (this) -> solver
// (MixedModel)).
#pragma once

#include <kernels/ElementDriver.hpp>
#include <kernels/MixedElasticity.hpp>
#include <mesh/Mesh.hpp>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace mixcon {

/// The geometric factors of the partial assembly of every element e and quadrature point q:
/// weight(e, q) = t w_q det J and gradient(e, q, Dim a + i) = weight(e, q) dpsi_a/dx_i.
template <class MemorySpace> struct MixedPointGeometry {
  Kokkos::View<double **, MemorySpace> weight;
  Kokkos::View<double ***, MemorySpace> gradient;
};

/// How element results reach the nodes: atomic adds (one launch; GPUs), or element colors (no
/// two elements of a color share a node; one launch per color, plain adds; CPUs, where an atomic
/// double add is a compare-and-swap loop: measured up to 2.4x the colored apply on one thread,
/// bench/bench_mixed_operators.cpp).
enum class MixedScatter { Atomic, Colored };

/// The default scatter of an execution space: colored on host spaces, atomic on devices.
template <class ExecSpace>
constexpr MixedScatter kDefaultMixedScatter =
    Kokkos::SpaceAccessibility<ExecSpace, Kokkos::HostSpace>::accessible ? MixedScatter::Colored
                                                                         : MixedScatter::Atomic;

/// The mixed blocks K12, K12^T and M applied element by element. With `partialAssembly` the
/// geometric factors come from `geometry`; otherwise `geometry` is empty and they are recomputed
/// from the coordinates in `data.mesh` at every apply. With the colored scatter, the elements of
/// color c are coloredElements(colorOffsets[c] .. colorOffsets[c + 1] - 1).
template <class MemorySpace> struct MixedMatrixFreeOperators {
  static constexpr int kMaxColors = 64;
  MixedElementData<MemorySpace> data;
  ElementType type = ElementType::Quad4;
  LocalIndex numNodes = 0;
  bool partialAssembly = false;
  MixedPointGeometry<MemorySpace> geometry;
  MixedScatter scatter = MixedScatter::Atomic;
  Kokkos::View<LocalIndex *, MemorySpace> coloredElements;
  int numColors = 0;
  LocalIndex colorOffsets[kMaxColors + 1] = {};
};

namespace detail {

/// Shape values, natural derivatives and weights of an element's quadrature rule, filled once on
/// the host and captured by value in the kernels (shared by all elements).
template <class Elem> struct ReferencePoints {
  static constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nq = Elem::kNumQp;
  double sh[nq][n], dn[nq][n][dim], w[nq];
};

template <class Elem> ReferencePoints<Elem> referencePoints() {
  ReferencePoints<Elem> r;
  for (int q = 0; q < Elem::kNumQp; ++q)
    r.w[q] = referencePoint<Elem>(q, r.sh[q], r.dn[q]);
  return r;
}

/// Weighted gradients wg[a][i] = f dpsi_a/dx_i of element e at point q and f = t w det J: read
/// from the partial assembly (Stored) or recomputed from the element's coordinates xe.
template <class Elem, bool Stored, class MemorySpace>
KOKKOS_INLINE_FUNCTION double pointFactors(const MixedMatrixFreeOperators<MemorySpace> &op,
                                           const ReferencePoints<Elem> &ref, LocalIndex e, int q,
                                           const double (&xe)[Elem::kNumNodes][Elem::kDim],
                                           double (&wg)[Elem::kNumNodes][Elem::kDim]) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  if constexpr (Stored) {
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < dim; ++i)
        wg[a][i] = op.geometry.gradient(e, q, dim * a + i);
    return op.geometry.weight(e, q);
  } else {
    const double f = op.data.thickness * ref.w[q] * pointGeometry<Elem>(xe, ref.dn[q], wg);
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < dim; ++i)
        wg[a][i] *= f;
    return f;
  }
}

/// Nodal coordinates of element e, only where the geometry is recomputed.
template <class Elem, bool Stored, class MemorySpace>
KOKKOS_INLINE_FUNCTION void coordinatesIfNeeded(const MeshView<MemorySpace, Elem::kDim> &mesh,
                                                LocalIndex e,
                                                double (&xe)[Elem::kNumNodes][Elem::kDim]) {
  if constexpr (!Stored)
    for (int a = 0; a < Elem::kNumNodes; ++a)
      for (int i = 0; i < Elem::kDim; ++i)
        xe[a][i] = mesh.coordinates(mesh.connectivity(e, a), i);
}

} // namespace detail

/// Point arithmetic of the mixed blocks in any dimension (Voigt<Dim> components, engineering
/// shear), with weighted gradients wg[a][i] = f dpsi_a/dx_i.
/// The weighted strain f eps(u) = sum_a B_a u_a.
template <int Dim, int N>
KOKKOS_INLINE_FUNCTION Vector<Voigt<Dim>::kSize> weightedStrain(const double (&wg)[N][Dim],
                                                                const double (&ue)[N][Dim]) {
  using V = Voigt<Dim>;
  Vector<V::kSize> eps{};
  for (int a = 0; a < N; ++a)
    for (int k = 0; k < V::kSize; ++k) {
      eps[k] += ue[a][V::row(k)] * wg[a][V::col(k)];
      if (V::isShear(k))
        eps[k] += ue[a][V::col(k)] * wg[a][V::row(k)];
    }
  return eps;
}

/// fe[a] += B_a^T sigma (f included in wg): the nodal forces of a point stress.
template <int Dim, int N>
KOKKOS_INLINE_FUNCTION void addWeightedDivergence(const double (&wg)[N][Dim],
                                                  const Vector<Voigt<Dim>::kSize> &sigma,
                                                  double (&fe)[N][Dim]) {
  using V = Voigt<Dim>;
  for (int a = 0; a < N; ++a)
    for (int k = 0; k < V::kSize; ++k) {
      fe[a][V::row(k)] += wg[a][V::col(k)] * sigma[k];
      if (V::isShear(k))
        fe[a][V::col(k)] += wg[a][V::row(k)] * sigma[k];
    }
}

/// The stress sigma = sum_b psi_b s_b interpolated from nodal stresses se.
template <int Dim, int N>
KOKKOS_INLINE_FUNCTION Vector<Voigt<Dim>::kSize>
interpolateStress(const double (&sh)[N], const double (&se)[N][Voigt<Dim>::kSize]) {
  Vector<Voigt<Dim>::kSize> s{};
  for (int b = 0; b < N; ++b)
    for (int k = 0; k < Voigt<Dim>::kSize; ++k)
      s[k] += sh[b] * se[b][k];
  return s;
}

/// se[b] += psi_b sigma for every node b: the transpose of interpolateStress (a point's stress
/// components spread to the element's nodes by the stress shape functions).
template <int Dim, int N>
KOKKOS_INLINE_FUNCTION void addInterpolatedTranspose(const double (&sh)[N],
                                                     const Vector<Voigt<Dim>::kSize> &sigma,
                                                     double (&se)[N][Voigt<Dim>::kSize]) {
  for (int b = 0; b < N; ++b)
    for (int k = 0; k < Voigt<Dim>::kSize; ++k)
      se[b][k] += sh[b] * sigma[k];
}

namespace detail {

/// Nodal values of element e from v (C per node, interleaved).
template <int N, int C, class Mesh, class View>
KOKKOS_INLINE_FUNCTION void gatherNodal(const Mesh &mesh, const View &v, LocalIndex e,
                                        double (&ve)[N][C]) {
  for (int a = 0; a < N; ++a) {
    const LocalIndex k = mesh.connectivity(e, a);
    for (int c = 0; c < C; ++c)
      ve[a][c] = v(C * k + c);
  }
}

/// v += scale ve through element e's nodes, atomically or (colored elements) plainly.
template <bool Atomic, int N, int C, class Mesh, class View>
KOKKOS_INLINE_FUNCTION void scatterNodal(const Mesh &mesh, LocalIndex e, double scale,
                                         const double (&ve)[N][C], const View &v) {
  for (int a = 0; a < N; ++a) {
    const LocalIndex k = mesh.connectivity(e, a);
    for (int c = 0; c < C; ++c) {
      if constexpr (Atomic)
        Kokkos::atomic_add(&v(C * k + c), scale * ve[a][c]);
      else
        v(C * k + c) += scale * ve[a][c];
    }
  }
}

/// body(e) for every element: one launch (Atomic) or one launch per color.
template <bool Atomic, class ExecSpace, class MemorySpace, class Body>
void forEachElement(const ExecSpace &exec, const MixedMatrixFreeOperators<MemorySpace> &op,
                    const char *label, const Body &body) {
  if constexpr (Atomic) {
    Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(exec, 0, op.data.material.extent(0)),
                         body);
  } else {
    const auto list = op.coloredElements;
    for (int c = 0; c < op.numColors; ++c)
      Kokkos::parallel_for(
          label, Kokkos::RangePolicy<ExecSpace>(exec, op.colorOffsets[c], op.colorOffsets[c + 1]),
          KOKKOS_LAMBDA(LocalIndex i) { body(list(i)); });
  }
}

template <class Elem, bool Stored, bool Atomic, class ExecSpace, class MemorySpace>
void couplingTransposeKernel(const ExecSpace &exec, const MixedMatrixFreeOperators<MemorySpace> &op,
                             const Kokkos::View<const double *, MemorySpace> &u,
                             const Kokkos::View<double *, MemorySpace> &r) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  constexpr int nu = FieldLayout<dim>::kNumDisplacements, nv = FieldLayout<dim>::kNumStresses;
  const auto ref = referencePoints<Elem>();
  Kokkos::deep_copy(exec, r, 0.0);
  forEachElement<Atomic>(
      exec, op, "mixcon::mixed::matrixFree::couplingTranspose", KOKKOS_LAMBDA(LocalIndex e) {
        double xe[n][dim], ue[n][dim], wg[n][dim], re[n][nv] = {};
        coordinatesIfNeeded<Elem, Stored>(op.data.mesh, e, xe);
        gatherNodal<n, nu>(op.data.mesh, u, e, ue);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          pointFactors<Elem, Stored>(op, ref, e, q, xe, wg);
          addInterpolatedTranspose<dim, n>(ref.sh[q], weightedStrain<dim, n>(wg, ue), re);
        }
        scatterNodal<Atomic, n, nv>(op.data.mesh, e, 1.0, re, r);
      });
}

template <class Elem, bool Stored, bool Atomic, class ExecSpace, class MemorySpace>
void couplingKernel(const ExecSpace &exec, const MixedMatrixFreeOperators<MemorySpace> &op,
                    double alpha, const Kokkos::View<const double *, MemorySpace> &s,
                    const Kokkos::View<double *, MemorySpace> &f) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  constexpr int nu = FieldLayout<dim>::kNumDisplacements, nv = FieldLayout<dim>::kNumStresses;
  const auto ref = referencePoints<Elem>();
  forEachElement<Atomic>(
      exec, op, "mixcon::mixed::matrixFree::coupling", KOKKOS_LAMBDA(LocalIndex e) {
        double xe[n][dim], se[n][nv], wg[n][dim], fe[n][dim] = {};
        coordinatesIfNeeded<Elem, Stored>(op.data.mesh, e, xe);
        gatherNodal<n, nv>(op.data.mesh, s, e, se);
        for (int q = 0; q < Elem::kNumQp; ++q) {
          pointFactors<Elem, Stored>(op, ref, e, q, xe, wg);
          addWeightedDivergence<dim, n>(wg, interpolateStress<dim, n>(ref.sh[q], se), fe);
        }
        scatterNodal<Atomic, n, nu>(op.data.mesh, e, alpha, fe, f);
      });
}

template <class Elem, bool Stored, bool Atomic, class ExecSpace, class MemorySpace>
void complianceKernel(const ExecSpace &exec, const MixedMatrixFreeOperators<MemorySpace> &op,
                      const Kokkos::View<const double *, MemorySpace> &x,
                      const Kokkos::View<double *, MemorySpace> &y) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim;
  constexpr int nv = FieldLayout<dim>::kNumStresses;
  const auto ref = referencePoints<Elem>();
  Kokkos::deep_copy(exec, y, 0.0);
  forEachElement<Atomic>(
      exec, op, "mixcon::mixed::matrixFree::compliance", KOKKOS_LAMBDA(LocalIndex e) {
        double xe[n][dim], xs[n][nv], wg[n][dim], ye[n][nv] = {};
        coordinatesIfNeeded<Elem, Stored>(op.data.mesh, e, xe);
        gatherNodal<n, nv>(op.data.mesh, x, e, xs);
        const auto d = op.data.compliance(op.data.material(e));
        for (int q = 0; q < Elem::kNumQp; ++q) {
          const double f = pointFactors<Elem, Stored>(op, ref, e, q, xe, wg);
          const auto sigma = interpolateStress<dim, n>(ref.sh[q], xs);
          Vector<nv> z;
          for (int r = 0; r < nv; ++r) {
            z[r] = 0.0;
            for (int c = 0; c < nv; ++c)
              z[r] += d.m[r][c] * sigma[c];
            z[r] *= f;
          }
          addInterpolatedTranspose<dim, n>(ref.sh[q], z, ye);
        }
        scatterNodal<Atomic, n, nv>(op.data.mesh, e, 1.0, ye, y);
      });
}

/// Runs f(Elem, Stored, Atomic) for the operators' element type, geometry source and scatter.
template <class MemorySpace, class F>
void dispatchMatrixFree(const MixedMatrixFreeOperators<MemorySpace> &op, F &&f) {
  dispatchPlaneElement(op.type, "the matrix-free mixed operators", [&](auto elem) {
    const bool atomic = op.scatter == MixedScatter::Atomic;
    if (op.partialAssembly && atomic)
      f(elem, std::true_type{}, std::true_type{});
    else if (op.partialAssembly)
      f(elem, std::true_type{}, std::false_type{});
    else if (atomic)
      f(elem, std::false_type{}, std::true_type{});
    else
      f(elem, std::false_type{}, std::false_type{});
  });
}

/// Greedy element coloring (no two elements of a color share a node) into op's color lists;
/// false when more than kMaxColors colors would be needed (op then keeps the atomic scatter).
template <class MemorySpace>
bool colorElements(const Mesh &mesh, MixedMatrixFreeOperators<MemorySpace> &op) {
  constexpr int maxColors = MixedMatrixFreeOperators<MemorySpace>::kMaxColors;
  const LocalIndex ne = mesh.numElements();
  std::vector<std::uint64_t> used(mesh.numNodes(), 0); // colors taken at each node
  std::vector<int> color(ne);
  int numColors = 0;
  for (LocalIndex e = 0; e < ne; ++e) {
    std::uint64_t taken = 0;
    for (int a = 0; a < mesh.nodesPerElement; ++a)
      taken |= used[mesh.node(e, a)];
    int c = 0;
    while (c < maxColors && (taken >> c & 1u))
      ++c;
    if (c == maxColors)
      return false;
    color[e] = c;
    numColors = std::max(numColors, c + 1);
    for (int a = 0; a < mesh.nodesPerElement; ++a)
      used[mesh.node(e, a)] |= std::uint64_t(1) << c;
  }
  std::vector<LocalIndex> count(numColors + 1, 0);
  for (LocalIndex e = 0; e < ne; ++e)
    ++count[color[e] + 1];
  for (int c = 0; c < numColors; ++c)
    count[c + 1] += count[c];
  op.numColors = numColors;
  for (int c = 0; c <= numColors; ++c)
    op.colorOffsets[c] = count[c];
  op.coloredElements =
      Kokkos::View<LocalIndex *, MemorySpace>("mixcon::mixed::matrixFree::coloredElements", ne);
  auto h = hostMirror(op.coloredElements);
  for (LocalIndex e = 0; e < ne; ++e)
    h(count[color[e]]++) = e;
  copyToDevice(op.coloredElements, h);
  return true;
}

} // namespace detail

/// The partial assembly's geometric factors of all elements (MixedPointGeometry).
template <class Elem, class ExecSpace, class MemorySpace>
MixedPointGeometry<MemorySpace> precomputeMixedGeometry(const ExecSpace &exec,
                                                        const MixedElementData<MemorySpace> &d) {
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nq = Elem::kNumQp;
  const LocalIndex ne = d.material.extent(0);
  MixedPointGeometry<MemorySpace> g;
  g.weight = Kokkos::View<double **, MemorySpace>("mixcon::mixed::matrixFree::weight", ne, nq);
  g.gradient =
      Kokkos::View<double ***, MemorySpace>("mixcon::mixed::matrixFree::gradient", ne, nq, n * dim);
  MixedMatrixFreeOperators<MemorySpace> op; // recomputing geometry: reads data only
  op.data = d;
  const auto ref = detail::referencePoints<Elem>();
  auto weight = g.weight;
  auto gradient = g.gradient;
  Kokkos::parallel_for(
      "mixcon::mixed::matrixFree::precompute", Kokkos::RangePolicy<ExecSpace>(exec, 0, ne),
      KOKKOS_LAMBDA(LocalIndex e) {
        double xe[n][dim], wg[n][dim];
        detail::coordinatesIfNeeded<Elem, false>(op.data.mesh, e, xe);
        for (int q = 0; q < nq; ++q) {
          weight(e, q) = detail::pointFactors<Elem, false>(op, ref, e, q, xe, wg);
          for (int a = 0; a < n; ++a)
            for (int i = 0; i < dim; ++i)
              gradient(e, q, dim * a + i) = wg[a][i];
        }
      });
  return g;
}

/// The matrix-free operators of `d` (the element data of `mesh`, which gives the element type and
/// the host connectivity for the coloring); with `partialAssembly` the geometric factors are
/// computed here (the setup cost), otherwise only the color lists (colored scatter) are stored.
template <class ExecSpace, class MemorySpace>
MixedMatrixFreeOperators<MemorySpace>
makeMixedMatrixFree(const ExecSpace &exec, const MixedElementData<MemorySpace> &d, const Mesh &mesh,
                    bool partialAssembly, MixedScatter scatter = kDefaultMixedScatter<ExecSpace>) {
  MixedMatrixFreeOperators<MemorySpace> op;
  op.data = d;
  op.type = mesh.elementType;
  op.numNodes = mesh.numNodes();
  op.partialAssembly = partialAssembly;
  op.scatter = scatter;
  if (scatter == MixedScatter::Colored && !detail::colorElements(mesh, op))
    op.scatter = MixedScatter::Atomic;
  const ElementType type = mesh.elementType;
  if (partialAssembly)
    dispatchPlaneElement(type, "the matrix-free mixed operators", [&](auto elem) {
      op.geometry = precomputeMixedGeometry<decltype(elem)>(exec, d);
    });
  return op;
}

/// r = K12^T u (stresses: Voigt size per node; u: Dim per node), element by element.
template <class ExecSpace, class MemorySpace>
void applyCouplingTranspose(const ExecSpace &exec, const MixedMatrixFreeOperators<MemorySpace> &op,
                            const Kokkos::View<const double *, MemorySpace> &u,
                            const Kokkos::View<double *, MemorySpace> &r) {
  detail::dispatchMatrixFree(op, [&](auto elem, auto stored, auto atomic) {
    detail::couplingTransposeKernel<decltype(elem), decltype(stored)::value,
                                    decltype(atomic)::value>(exec, op, u, r);
  });
}

/// f = beta f + alpha K12 s, element by element (f scaled first, then atomic adds).
template <class ExecSpace, class MemorySpace>
void applyCoupling(const ExecSpace &exec, const MixedMatrixFreeOperators<MemorySpace> &op,
                   double alpha, const Kokkos::View<const double *, MemorySpace> &s, double beta,
                   const Kokkos::View<double *, MemorySpace> &f) {
  if (beta == 0.0)
    Kokkos::deep_copy(exec, f, 0.0);
  else if (beta != 1.0)
    Kokkos::parallel_for(
        "mixcon::mixed::matrixFree::scale", Kokkos::RangePolicy<ExecSpace>(exec, 0, f.extent(0)),
        KOKKOS_LAMBDA(LocalIndex i) { f(i) *= beta; });
  detail::dispatchMatrixFree(op, [&](auto elem, auto stored, auto atomic) {
    detail::couplingKernel<decltype(elem), decltype(stored)::value, decltype(atomic)::value>(
        exec, op, alpha, s, f);
  });
}

/// y = M x with the consistent compliance mass, element by element.
template <class ExecSpace, class MemorySpace>
void applyCompliance(const ExecSpace &exec, const MixedMatrixFreeOperators<MemorySpace> &op,
                     const Kokkos::View<const double *, MemorySpace> &x,
                     const Kokkos::View<double *, MemorySpace> &y) {
  detail::dispatchMatrixFree(op, [&](auto elem, auto stored, auto atomic) {
    detail::complianceKernel<decltype(elem), decltype(stored)::value, decltype(atomic)::value>(
        exec, op, x, y);
  });
}

} // namespace mixcon
