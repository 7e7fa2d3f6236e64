// The generic element driver (kernels/ElementDriver.hpp) with the linear point law against the
// host reference element matrices (tests/support/Reference.hpp: explicit B, Eigen), for both
// element types and both plane analyses with a rotated orthotropic material; the updated- and
// total-Lagrangian drivers with the Almansi and St. Venant-Kirchhoff laws against host reference
// forces (tests/support/NonlinearReference.hpp: through b^-1, and with an explicit B_NL(F)) and
// their tangents against central differences of the assembled residual, at finite strain plus
// rotation; and the point laws (kernels/PointPhysics.hpp) alone: closed forms for Hooke's law, the
// nonlinear laws' stresses against the element kernels' own strain functions and their tangents
// against central differences of their stresses.
#include <kernels/ElementDriver.hpp>
#include <kernels/LinearElasticity.hpp>
#include <kernels/Nonlinear.hpp>
#include <support/KernelFixture.hpp>
#include <support/NonlinearReference.hpp>
#include <support/Params.hpp>
#include <support/RandomTensor.hpp>
#include <support/Reference.hpp>

#include <gtest/gtest.h>

#include <random>
#include <tuple>

using namespace mixcon;
using namespace mixcon::test;
using Exec = Kokkos::DefaultExecutionSpace;

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace element_driver_tests {

using Param = std::tuple<ElementType, PlaneAnalysis>;

/// The kernel fixture (distorted mesh, checkerboard of two materials) with its materials
/// replaced by a rotated orthotropic one and an isotropic one, both in `analysis`.
Fixture makeDriverFixture(ElementType type, PlaneAnalysis analysis) {
  Fixture f = makeFixture(type);
  f.materials = {orthotropicStiffness({1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.3, 0.35}, analysis, 0.7),
                 isotropicStiffness(2.0e5, 0.3, analysis)};
  auto hs = Kokkos::create_mirror_view(f.data.stiffness);
  hs(0) = f.materials[0];
  hs(1) = f.materials[1];
  Kokkos::deep_copy(f.data.stiffness, hs);
  return f;
}

Eigen::MatrixXd referenceElement(const Fixture &f, LocalIndex e) {
  return test::referenceStiffness(test::elementCoordinates(f.mesh, e),
                                  test::toEigen(f.materials[f.elementMaterial[e]]),
                                  f.data.thickness);
}

/// Element matrices of the single-element path (elementStiffness, one lane) on the device.
template <class Elem>
Kokkos::View<double ***, Memory> singleLaneMatrices(const ElementData<Memory> &d, LocalIndex ne) {
  constexpr int nd = 2 * Elem::kNumNodes;
  Kokkos::View<double ***, Memory> ke("ke", ne, nd, nd);
  const auto law = linearElasticLaw(d);
  Kokkos::parallel_for(
      "mixcon::test::singleLane", Kokkos::RangePolicy<Exec>(0, ne), KOKKOS_LAMBDA(LocalIndex e) {
        double k[nd][nd];
        elementStiffness<Elem>(d.mesh, d.thickness, law, e, k);
        for (int i = 0; i < nd; ++i)
          for (int j = 0; j < nd; ++j)
            ke(e, i, j) = k[i][j];
      });
  return ke;
}

/// Dense assembly of the host reference element matrices (2 dofs per node).
Eigen::MatrixXd denseReference(const Fixture &f) {
  const int n = 2 * f.mesh.numNodes();
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
    const Eigen::MatrixXd k = referenceElement(f, e);
    for (int p = 0; p < f.mesh.nodesPerElement; ++p)
      for (int q = 0; q < f.mesh.nodesPerElement; ++q)
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j)
            dense(2 * f.mesh.node(e, p) + i, 2 * f.mesh.node(e, q) + j) += k(2 * p + i, 2 * q + j);
  }
  return dense;
}

/// A rotated orthotropic plane stiffness (plane strain).
PlaneMatrix rotatedOrthotropic() {
  return orthotropicStiffness({1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.3, 0.35},
                              PlaneAnalysis::PlaneStrain, 0.7);
}

/// Largest deviation of law.tangent(x) from central differences of law.stress at x, relative
/// to the tangent's largest entry.
template <class Law, int Dim> double tangentDifferenceError(const Law &law, Mat<Dim, Dim> x) {
  constexpr int nv = Voigt<Dim>::kSize;
  const auto t = law.tangent(x);
  double err = 0.0, scale = 0.0;
  const double step = 1e-6;
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) {
      Mat<Dim, Dim> xp = x, xm = x;
      xp.m[i][j] += step;
      xm.m[i][j] -= step;
      const auto sp = law.stress(xp), sm = law.stress(xm);
      for (int k = 0; k < nv; ++k) {
        const double fd = (sp.v[k] - sm.v[k]) / (2.0 * step);
        err = std::max(err, std::abs(fd - t.m[k][i * Dim + j]));
        scale = std::max(scale, std::abs(t.m[k][i * Dim + j]));
      }
    }
  return err / scale;
}

/// The Voigt<3> stiffness of an isotropic solid as a LinearElasticPoint<3>.
LinearElasticPoint<3> isotropicSolidPoint(double e, double nu) {
  return LinearElasticPoint<3>{IsotropicMaterial{e, nu}.stiffness()};
}

/// Internal force of the displacement model with `law` (assembleAlmansi, or assembleNonlinear with
/// SvkKernel) at displacements u (and, when `a` has rows, its tangent into a).
template <class Map>
Eigen::VectorXd displacementForce(const Fixture &f, const Eigen::VectorXd &u, const Map &map,
                                  const CsrMatrix<Memory> &a,
                                  ElasticLaw law = ElasticLaw::Almansi) {
  Kokkos::View<double *, Memory> g("g", u.size());
  const Kokkos::View<const double *, Memory> du = toView(u);
  LocalIndex inverted = -2;
  dispatchPlaneElement(f.mesh.elementType, "this 2D test", [&](auto elem) {
    using Elem = decltype(elem);
    inverted = law == ElasticLaw::Almansi
                   ? assembleAlmansi<Elem>(Exec(), f.data, du, map, a, g)
                   : assembleNonlinear<2, Elem>(Exec(), f.data.mesh,
                                                SvkKernel<Elem, Memory>{f.data, du}, map, a, g);
  });
  EXPECT_EQ(inverted, -1);
  return toEigen(g);
}

/// Finite strain (random displacements of size 0.03 on the 3 x 2 body, elements of size 0.5:
/// strains of a few per cent) plus a rigid rotation of 0.3 rad.
Eigen::VectorXd strainedAndRotated(const Fixture &f) {
  Eigen::VectorXd u = 0.03 * randomVector(2 * f.mesh.numNodes(), 5);
  const double th = 0.3;
  for (LocalIndex k = 0; k < f.mesh.numNodes(); ++k) {
    const double x = f.mesh.x(k), y = f.mesh.y(k);
    u(2 * k) += (std::cos(th) - 1) * x - std::sin(th) * y;
    u(2 * k + 1) += std::sin(th) * x + (std::cos(th) - 1) * y;
  }
  return u;
}

/// Largest deviation of the assembled tangent of `law` at u from central differences (step
/// 1e-7) of the assembled residual, relative to the largest difference quotient.
double tangentError(const Fixture &f, const Eigen::VectorXd &u, ElasticLaw law) {
  const NodeGraph g = buildNodeGraph(f.mesh);
  auto a = expandGraph<Memory>(g, 2);
  const auto map = elementScatterMap<Memory>(f.mesh, g);
  displacementForce(f, u, map, a, law);
  const CsrMatrix<Memory> none;
  const double h = 1e-7;
  Eigen::MatrixXd fd(u.size(), u.size());
  for (int j = 0; j < u.size(); ++j) {
    Eigen::VectorXd up = u, um = u;
    up(j) += h;
    um(j) -= h;
    fd.col(j) =
        (displacementForce(f, up, map, none, law) - displacementForce(f, um, map, none, law)) /
        (2 * h);
  }
  return relativeError(toDense(a), fd);
}

} // namespace element_driver_tests
using namespace element_driver_tests;

class ElementDriverTest : public ::testing::TestWithParam<Param> {};
INSTANTIATE_TEST_SUITE_P(
    Elements, ElementDriverTest,
    ::testing::Combine(::testing::Values(ElementType::Quad4, ElementType::Quad8),
                       ::testing::Values(PlaneAnalysis::PlaneStress, PlaneAnalysis::PlaneStrain)),
    [](const ::testing::TestParamInfo<Param> &info) {
      return std::string(std::get<0>(info.param) == ElementType::Quad8 ? "Quad8" : "Quad4") +
             (std::get<1>(info.param) == PlaneAnalysis::PlaneStrain ? "PlaneStrain"
                                                                    : "PlaneStress");
    });

TEST_P(ElementDriverTest, ElementStiffnessMatchesHostReference) {
  const auto [type, analysis] = GetParam();
  const Fixture f = makeDriverFixture(type, analysis);
  dispatchPlaneElement(type, "this 2D test", [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int nd = 2 * Elem::kNumNodes;
    const LocalIndex ne = f.mesh.numElements();
    // Lanes (the library path; 30 elements: the last batch of 4 is short) and one lane.
    Kokkos::View<double ***, Memory> lanes("ke", ne, nd, nd);
    computeLinearStiffness<Elem>(Exec(), f.data, lanes);
    const auto hl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), lanes);
    const auto h1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                        singleLaneMatrices<Elem>(f.data, ne));
    for (LocalIndex e = 0; e < ne; ++e) {
      const Eigen::MatrixXd ref = referenceElement(f, e);
      const double scale = ref.cwiseAbs().maxCoeff();
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j) {
          ASSERT_NEAR(hl(e, i, j), ref(i, j), 1e-13 * scale)
              << "element " << e << " entry " << i << "," << j;
          ASSERT_NEAR(h1(e, i, j), ref(i, j), 1e-13 * scale)
              << "element " << e << " entry " << i << "," << j;
        }
    }
  });
}

TEST_P(ElementDriverTest, AssembledStiffnessMatchesDenseReference) {
  const auto [type, analysis] = GetParam();
  const Fixture f = makeDriverFixture(type, analysis);
  const NodeGraph g = buildNodeGraph(f.mesh);
  auto a = expandGraph<Memory>(g, 2);
  const auto map = elementScatterMap<Memory>(f.mesh, g);
  dispatchPlaneElement(type, "this 2D test", [&](auto elem) {
    assembleLinearStiffness<decltype(elem)>(Exec(), f.data, map, a, 0.5);
  });
  const Eigen::MatrixXd dense = 0.5 * denseReference(f);
  EXPECT_LT(relativeError(toDense(a), dense), 1e-13);
}

TEST_P(ElementDriverTest, ResidualAndPointStressMatchHostReference) {
  const auto [type, analysis] = GetParam();
  const Fixture f = makeDriverFixture(type, analysis);
  const int n = 2 * f.mesh.numNodes();
  const Eigen::VectorXd u = randomVector(n, 11);
  const auto du = toView(u);
  Kokkos::View<double *, Memory> fi("fi", n);
  dispatchPlaneElement(type, "this 2D test", [&](auto elem) {
    using Elem = decltype(elem);
    assembleInternalForce<Elem>(Exec(), f.data, Kokkos::View<const double *, Memory>(du), fi);
    // Stress at the quadrature points against C B u of the host reference.
    Kokkos::View<double **[3], Memory> sq("sq", f.mesh.numElements(), Elem::kNumQp);
    gaussPointStress<Elem>(Exec(), f.data, Kokkos::View<const double *, Memory>(du), sq);
    const auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sq);
    for (LocalIndex e = 0; e < f.mesh.numElements(); ++e) {
      Eigen::VectorXd ue(2 * Elem::kNumNodes);
      for (int a = 0; a < Elem::kNumNodes; ++a)
        for (int c = 0; c < 2; ++c)
          ue(2 * a + c) = u(2 * f.mesh.node(e, a) + c);
      const Eigen::Matrix3d c = test::toEigen(f.materials[f.elementMaterial[e]]);
      int q = 0;
      test::forEachReferencePoint(
          test::elementCoordinates(f.mesh, e),
          [&](const Eigen::VectorXd &, const Eigen::MatrixXd &dx, double) {
            const Eigen::Vector3d s = c * test::referenceB(dx) * ue;
            for (int k = 0; k < 3; ++k)
              ASSERT_NEAR(hs(e, q, k), s(k), 1e-13 * s.cwiseAbs().maxCoeff())
                  << "element " << e << " point " << q;
            ++q;
          });
    }
  });
  const Eigen::VectorXd ref = denseReference(f) * u;
  EXPECT_LT((toEigen(fi) - ref).cwiseAbs().maxCoeff(), 1e-13 * ref.cwiseAbs().maxCoeff());
}

// Tangent tolerance 1e-8: measured 6e-10 to 8e-10 for both laws.
TEST_P(ElementDriverTest, AlmansiResidualAndTangentMatchReferenceAndDifferences) {
  const auto [type, analysis] = GetParam();
  const Fixture f = makeDriverFixture(type, analysis);
  const Eigen::VectorXd u = strainedAndRotated(f);
  const NodeGraph g = buildNodeGraph(f.mesh);
  const auto map = elementScatterMap<Memory>(f.mesh, g);
  const Eigen::VectorXd force = displacementForce(f, u, map, CsrMatrix<Memory>{});
  const Eigen::VectorXd ref = referenceAlmansiForce(f, u);
  EXPECT_LT((force - ref).cwiseAbs().maxCoeff(), 1e-12 * ref.cwiseAbs().maxCoeff());
  EXPECT_LT(tangentError(f, u, ElasticLaw::Almansi), 1e-8);
}

TEST_P(ElementDriverTest, SaintVenantKirchhoffResidualAndTangentMatchReferenceAndDifferences) {
  const auto [type, analysis] = GetParam();
  const Fixture f = makeDriverFixture(type, analysis);
  const Eigen::VectorXd u = strainedAndRotated(f);
  const NodeGraph g = buildNodeGraph(f.mesh);
  const auto map = elementScatterMap<Memory>(f.mesh, g);
  const Eigen::VectorXd force =
      displacementForce(f, u, map, CsrMatrix<Memory>{}, ElasticLaw::SaintVenantKirchhoff);
  const Eigen::VectorXd ref = referenceSvkForce(f, u);
  EXPECT_LT((force - ref).cwiseAbs().maxCoeff(), 1e-12 * ref.cwiseAbs().maxCoeff());
  EXPECT_LT(tangentError(f, u, ElasticLaw::SaintVenantKirchhoff), 1e-8);
}

TEST(PointPhysics, LinearElasticPlaneStrainIsHookesLaw) {
  // Isotropic plane strain: sigma_xx = (lambda + 2 mu) eps_xx + lambda eps_yy,
  // sigma_yy = lambda eps_xx + (lambda + 2 mu) eps_yy, sigma_xy = mu gamma_xy.
  const double e = 2.0e5, nu = 0.3;
  const double lambda = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
  const LinearElasticPoint<2> point{isotropicStiffness(e, nu, PlaneAnalysis::PlaneStrain)};
  // Displacement gradient: eps = (1e-3, -4e-4, gamma = 2e-4 + 4e-4).
  const Mat<2, 2> grad{{{1e-3, 2e-4}, {4e-4, -4e-4}}};
  const Vector<3> eps = smallStrain(grad);
  EXPECT_DOUBLE_EQ(eps[0], 1e-3);
  EXPECT_DOUBLE_EQ(eps[1], -4e-4);
  EXPECT_DOUBLE_EQ(eps[2], 6e-4);
  const Vector<3> s = point.stress(eps);
  const double scale = (lambda + 2 * mu) * 1e-3;
  EXPECT_NEAR(s[0], (lambda + 2 * mu) * 1e-3 + lambda * -4e-4, 1e-14 * scale);
  EXPECT_NEAR(s[1], lambda * 1e-3 + (lambda + 2 * mu) * -4e-4, 1e-14 * scale);
  EXPECT_NEAR(s[2], mu * 6e-4, 1e-14 * scale);
  const auto t = point.tangent(eps);
  EXPECT_NEAR(t(0, 0), lambda + 2 * mu, 1e-14 * scale / 1e-3);
  EXPECT_NEAR(t(0, 1), lambda, 1e-14 * scale / 1e-3);
  EXPECT_NEAR(t(2, 2), mu, 1e-14 * scale / 1e-3);
}

TEST(PointPhysics, LinearElasticSolidIsHookesLaw) {
  // sigma = lambda tr(eps) I + 2 mu eps in 3D (Voigt xx, yy, zz, yz, xz, xy).
  const double e = 7.0e4, nu = 0.33;
  const double lambda = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
  const Mat<3, 3> grad = randomMatrix<3>(5, 1e-3);
  const Vector<6> s = isotropicSolidPoint(e, nu).stress(smallStrain(grad));
  const double tr = grad(0, 0) + grad(1, 1) + grad(2, 2);
  double scale = 0.0;
  for (int k = 0; k < 6; ++k)
    scale = std::max(scale, std::abs(s[k]));
  for (int k = 0; k < 6; ++k) {
    const int i = Voigt<3>::row(k), j = Voigt<3>::col(k);
    const double exact = (i == j ? lambda * tr : 0.0) + mu * (grad(i, j) + grad(j, i));
    EXPECT_NEAR(s[k], exact, 1e-14 * scale) << "component " << k;
  }
}

TEST(PointPhysics, AlmansiStressIsTheElementKernelsLaw) {
  const PlaneMatrix c = rotatedOrthotropic();
  const Mat<2, 2> h = randomMatrix<2>(3, 0.2);
  const double hh[2][2] = {{h(0, 0), h(0, 1)}, {h(1, 0), h(1, 1)}};
  double es[2][2], s[2][2];
  detail::almansiStrain(hh, es);
  detail::stressFromStrainTensor(c, es, s);
  const Vector<3> p = AlmansiPoint<2>{c}.stress(h);
  const double scale = std::max({std::abs(s[0][0]), std::abs(s[1][1]), std::abs(s[0][1])});
  EXPECT_NEAR(p[0], s[0][0], 1e-14 * scale);
  EXPECT_NEAR(p[1], s[1][1], 1e-14 * scale);
  EXPECT_NEAR(p[2], s[0][1], 1e-14 * scale);
}

/// Host reference of the Cauchy stress at spatial gradient h (Eigen), F = (I - h)^-1: for
/// St. Venant-Kirchhoff E = (F^T F - I) / 2, S = C : E (engineering shears), sigma =
/// F S F^T / det F; for Almansi sigma = C : e with e = (I - (F F^T)^-1) / 2.
template <int Dim>
Eigen::VectorXd cauchyReference(ElasticLaw law, const Mat<Voigt<Dim>::kSize, Voigt<Dim>::kSize> &c,
                                const Mat<Dim, Dim> &h) {
  Eigen::MatrixXd hm(Dim, Dim);
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j)
      hm(i, j) = h(i, j);
  const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(Dim, Dim);
  const Eigen::MatrixXd f = (id - hm).inverse();
  const bool svk = law == ElasticLaw::SaintVenantKirchhoff;
  const Eigen::MatrixXd e = svk ? Eigen::MatrixXd(0.5 * (f.transpose() * f - id))
                                : Eigen::MatrixXd(0.5 * (id - (f * f.transpose()).inverse()));
  constexpr int nv = Voigt<Dim>::kSize;
  Eigen::VectorXd ev(nv);
  for (int k = 0; k < nv; ++k) {
    const int i = Voigt<Dim>::row(k), j = Voigt<Dim>::col(k);
    ev(k) = i == j ? e(i, j) : 2.0 * e(i, j);
  }
  Eigen::MatrixXd cm(nv, nv);
  for (int r = 0; r < nv; ++r)
    for (int k = 0; k < nv; ++k)
      cm(r, k) = c(r, k);
  const Eigen::VectorXd sv = cm * ev;
  Eigen::MatrixXd pk2(Dim, Dim);
  for (int k = 0; k < nv; ++k) {
    const int i = Voigt<Dim>::row(k), j = Voigt<Dim>::col(k);
    pk2(i, j) = pk2(j, i) = sv(k);
  }
  const Eigen::MatrixXd sigma =
      svk ? Eigen::MatrixXd(f * pk2 * f.transpose() / f.determinant()) : pk2;
  Eigen::VectorXd out(nv);
  for (int k = 0; k < nv; ++k)
    out(k) = sigma(Voigt<Dim>::row(k), Voigt<Dim>::col(k));
  return out;
}

TEST(PointPhysics, SpatialCauchyStressMatchesTheHostReferenceOfBothLaws) {
  // spatialCauchyStress (the Gauss-point and nodal output of the displacement model) against
  // an Eigen evaluation through F = (I - h)^-1 of both laws (cauchyReference), in 2D (rotated
  // orthotropic plane law) and 3D (isotropic solid).
  const PlaneMatrix c2 = rotatedOrthotropic();
  const SolidMatrix c3 = IsotropicMaterial{7.0e4, 0.33}.stiffness();
  const auto check = [](const auto &got, const Eigen::VectorXd &want, const char *what) {
    const double scale = want.cwiseAbs().maxCoeff();
    for (int k = 0; k < static_cast<int>(want.size()); ++k)
      EXPECT_NEAR(got[k], want[k], 1e-12 * scale) << what << " component " << k;
  };
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Mat<2, 2> h2 = randomMatrix<2>(seed, 0.2);
    const Mat<3, 3> h3 = randomMatrix<3>(seed + 20, 0.2);
    for (ElasticLaw law : {ElasticLaw::Almansi, ElasticLaw::SaintVenantKirchhoff}) {
      const char *name = law == ElasticLaw::Almansi ? "Almansi" : "SVK";
      check(spatialCauchyStress<2>(law, c2, h2), cauchyReference<2>(law, c2, h2), name);
      check(spatialCauchyStress<3>(law, c3, h3), cauchyReference<3>(law, c3, h3), name);
    }
  }
}

TEST(PointPhysics, NonlinearTangentsMatchFiniteDifferences) {
  // Central differences with step 1e-6 on O(0.1) gradients: truncation ~1e-12, round-off
  // ~eps / step ~1e-10 relative.
  const PlaneMatrix c2 = rotatedOrthotropic();
  const Mat<6, 6> c3 = IsotropicMaterial{7.0e4, 0.33}.stiffness();
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Mat<2, 2> h2 = randomMatrix<2>(seed, 0.2);
    const Mat<3, 3> h3 = randomMatrix<3>(seed + 10, 0.2);
    EXPECT_LT(tangentDifferenceError(AlmansiPoint<2>{c2}, h2), 1e-8) << "seed " << seed;
    EXPECT_LT(tangentDifferenceError(AlmansiPoint<3>{c3}, h3), 1e-8) << "seed " << seed;
    Mat<2, 2> f2 = h2;
    Mat<3, 3> f3 = h3;
    for (int i = 0; i < 3; ++i) {
      if (i < 2)
        f2(i, i) += 1.0;
      f3(i, i) += 1.0;
    }
    EXPECT_LT(tangentDifferenceError(SaintVenantKirchhoffPoint<2>{c2}, f2), 1e-8)
        << "seed " << seed;
    EXPECT_LT(tangentDifferenceError(SaintVenantKirchhoffPoint<3>{c3}, f3), 1e-8)
        << "seed " << seed;
  }
}
