// The push-forward kernels of the mixed model's incremental form (kernels/Nonlinear.hpp, one each
// for 2D and 3D: pushForwardNodalStress, pushForwardProjectionLoad, assembleScalarMass) against
// plain host references (Eigen, the elements' shape functions and rules) on distorted meshes
// (Quad4, Quad8; Hex8, Hex20, Tet4, Tet10) with random nodal increments (displacement gradients
// of about 10 %) and random stresses, where F varies from point to point and from element to
// element, unlike the closed-form checks of the models (a rigid rotation, a homogeneous
// increment). To 1e-12 of the largest value.
#include <kernels/Nonlinear.hpp>
#include <kernels/SparseMatrix.hpp>
#include <support/KernelFixture.hpp>
#include <support/SolidMesh.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>

using namespace mixcon;
using namespace mixcon::test;

namespace {

template <class Elem> Mesh meshOf() {
  if constexpr (Elem::kDim == 2)
    return makeFixture(Elem::kType, 4, 3).mesh;
  else
    return distortedBox(2, Elem::kType);
}

template <int Dim> using Tensor = Eigen::Matrix<double, Dim, Dim>;

/// Shape functions sh and physical gradients g (rows: nodes) of element e of `mesh` at the
/// natural point xi of `Rule` (an element type or its mixed rule); returns det(dx/dxi).
template <class Rule>
double hostPoint(const Mesh &mesh, LocalIndex e, const double (&xi)[Rule::kDim],
                 Eigen::Matrix<double, Rule::kNumNodes, 1> &sh,
                 Eigen::Matrix<double, Rule::kNumNodes, Rule::kDim> &g) {
  constexpr int n = Rule::kNumNodes, dim = Rule::kDim;
  double s[n], dn[n][dim];
  Rule::shape(xi, s, dn);
  Tensor<dim> jac = Tensor<dim>::Zero(); // d x_i / d xi_j
  Eigen::Matrix<double, n, dim> dnat;
  for (int a = 0; a < n; ++a) {
    sh(a) = s[a];
    for (int j = 0; j < dim; ++j) {
      dnat(a, j) = dn[a][j];
      for (int i = 0; i < dim; ++i)
        jac(i, j) += mesh.coordinate(mesh.node(e, a), i) * dn[a][j];
    }
  }
  g = dnat * jac.inverse();
  return jac.determinant();
}

/// The increment's displacement gradient of element e at the point of gradients g (x: the mixed
/// unknowns, LayoutOf<Elem>).
template <class Elem>
Tensor<Elem::kDim> hostGradient(const Mesh &mesh, LocalIndex e, const Eigen::VectorXd &x,
                                const Eigen::Matrix<double, Elem::kNumNodes, Elem::kDim> &g) {
  constexpr int dim = Elem::kDim, nu = LayoutOf<Elem>::kMixedUnknowns;
  Tensor<dim> h = Tensor<dim>::Zero();
  for (int a = 0; a < Elem::kNumNodes; ++a)
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j)
        h(i, j) += x(nu * mesh.node(e, a) + i) * g(a, j);
  return h;
}

template <int Dim> Tensor<Dim> tensorOf(const Eigen::VectorXd &v, Eigen::Index at) {
  Tensor<Dim> t;
  for (int k = 0; k < Voigt<Dim>::kSize; ++k)
    t(Voigt<Dim>::row(k), Voigt<Dim>::col(k)) = t(Voigt<Dim>::col(k), Voigt<Dim>::row(k)) =
        v(at + k);
  return t;
}

/// Random increment (displacements times 0.1 of the element size's order, stresses of order 1)
/// and prestress.
template <class Elem> void randomState(const Mesh &mesh, Eigen::VectorXd &x, Eigen::VectorXd &tau) {
  using L = LayoutOf<Elem>;
  const LocalIndex nn = mesh.numNodes();
  x = randomVector(L::kMixedUnknowns * nn, 41);
  for (LocalIndex k = 0; k < nn; ++k)
    for (int i = 0; i < Elem::kDim; ++i)
      x(L::kMixedUnknowns * k + i) *= 0.02;
  tau = randomVector(L::kNumStresses * nn, 42);
}

double relativeMax(const Eigen::VectorXd &got, const Eigen::VectorXd &expect) {
  return (got - expect).cwiseAbs().maxCoeff() / expect.cwiseAbs().maxCoeff();
}

template <class Elem> void checkNodalPushForward() {
  using L = LayoutOf<Elem>;
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nv = L::kNumStresses;
  constexpr int nu = L::kMixedUnknowns, so = L::kStressOffset;
  const Mesh mesh = meshOf<Elem>();
  const LocalIndex nn = mesh.numNodes();
  Eigen::VectorXd x, tau;
  randomState<Elem>(mesh, x, tau);
  // Host: F averaged over the elements at each node (each element's gradient at the node).
  std::vector<Tensor<dim>> sum(nn, Tensor<dim>::Zero());
  std::vector<int> count(nn, 0);
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < n; ++a) {
      double xi[dim];
      Elem::nodeNatural(a, xi);
      Eigen::Matrix<double, n, 1> sh;
      Eigen::Matrix<double, n, dim> g;
      hostPoint<Elem>(mesh, e, xi, sh, g);
      sum[mesh.node(e, a)] += hostGradient<Elem>(mesh, e, x, g);
      ++count[mesh.node(e, a)];
    }
  Eigen::VectorXd expect(nv * nn);
  for (LocalIndex k = 0; k < nn; ++k) {
    const Tensor<dim> f = Tensor<dim>::Identity() + sum[k] / count[k];
    Eigen::VectorXd s(nv);
    for (int c = 0; c < nv; ++c)
      s(c) = tau(nv * k + c) + x(nu * k + so + c);
    const Tensor<dim> t = f * tensorOf<dim>(s, 0) * f.transpose() / f.determinant();
    for (int c = 0; c < nv; ++c)
      expect(nv * k + c) = t(Voigt<dim>::row(c), Voigt<dim>::col(c));
  }
  const auto mv = toDevice<Memory, dim>(mesh);
  const auto out = toView(tau);
  pushForwardNodalStress<Elem>(Kokkos::DefaultExecutionSpace(), mv,
                               Kokkos::View<const double *, Memory>(toView(x)), out);
  EXPECT_LT(relativeMax(toEigen(out), expect), 1e-12) << Elem::kName;
  EXPECT_GT(relativeMax(tau, expect), 1e-3) << Elem::kName << ": the update changes tau";
}

template <class Elem> void checkProjection() {
  using L = LayoutOf<Elem>;
  using Rule = MixedRule<Elem>;
  constexpr int n = Elem::kNumNodes, dim = Elem::kDim, nv = L::kNumStresses;
  constexpr int nu = L::kMixedUnknowns, so = L::kStressOffset;
  const Mesh mesh = meshOf<Elem>();
  const LocalIndex nn = mesh.numNodes();
  const double thickness = dim == 2 ? 0.7 : 1.0;
  Eigen::VectorXd x, tau;
  randomState<Elem>(mesh, x, tau);
  // Host: b = t int psi F Sigma F^T dA and the scalar mass t int psi psi^T dA on MixedRule<Elem>.
  Eigen::VectorXd b = Eigen::VectorXd::Zero(nv * nn);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(nn, nn);
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int q = 0; q < Rule::kNumQp; ++q) {
      double xi[dim], w;
      Rule::quadraturePoint(q, xi, w);
      Eigen::Matrix<double, n, 1> sh;
      Eigen::Matrix<double, n, dim> g;
      const double jw = thickness * w * hostPoint<Rule>(mesh, e, xi, sh, g);
      const Tensor<dim> f = Tensor<dim>::Identity() + hostGradient<Elem>(mesh, e, x, g);
      Eigen::VectorXd s = Eigen::VectorXd::Zero(nv);
      for (int a = 0; a < n; ++a)
        for (int c = 0; c < nv; ++c)
          s(c) += sh(a) * (tau(nv * mesh.node(e, a) + c) + x(nu * mesh.node(e, a) + so + c));
      const Tensor<dim> t = f * tensorOf<dim>(s, 0) * f.transpose();
      for (int a = 0; a < n; ++a) {
        for (int c = 0; c < nv; ++c)
          b(nv * mesh.node(e, a) + c) += jw * sh(a) * t(Voigt<dim>::row(c), Voigt<dim>::col(c));
        for (int r = 0; r < n; ++r)
          m(mesh.node(e, a), mesh.node(e, r)) += jw * sh(a) * sh(r);
      }
    }
  const auto mv = toDevice<Memory, dim>(mesh);
  Kokkos::View<double *, Memory> load("load", nv * nn);
  pushForwardProjectionLoad<Elem>(Kokkos::DefaultExecutionSpace(), mv, thickness,
                                  Kokkos::View<const double *, Memory>(toView(tau)),
                                  Kokkos::View<const double *, Memory>(toView(x)), load);
  EXPECT_LT(relativeMax(toEigen(load), b), 1e-12) << Elem::kName;
  const NodeGraph graph = buildNodeGraph(mesh);
  const auto map = elementScatterMap<Memory>(mesh, graph);
  const CsrMatrix<Memory> mass = expandGraph<Memory>(graph, 1);
  assembleScalarMass<Elem>(Kokkos::DefaultExecutionSpace(), mv, thickness, map, mass);
  const Eigen::MatrixXd got = toDense(mass);
  EXPECT_LT((got - m).cwiseAbs().maxCoeff() / m.cwiseAbs().maxCoeff(), 1e-12) << Elem::kName;
}

} // namespace

TEST(PushForward, NodalAverageIsTheHostReference) {
  checkNodalPushForward<Quad4>();
  checkNodalPushForward<Quad8>();
  checkNodalPushForward<Hex8>();
  checkNodalPushForward<Hex20>();
  checkNodalPushForward<Tet4>();
  checkNodalPushForward<Tet10>();
}

TEST(PushForward, ProjectionLoadAndMassAreTheHostReference) {
  checkProjection<Quad4>();
  checkProjection<Quad8>();
  checkProjection<Hex8>();
  checkProjection<Hex20>();
  checkProjection<Tet4>();
  checkProjection<Tet10>();
}
