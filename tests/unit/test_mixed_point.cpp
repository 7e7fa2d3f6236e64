// The mixed (Hellinger-Reissner) point laws (kernels/MixedPointPhysics.hpp) alone:
//  - every derivative of MixedIncrementPoint and MixedCurrentPoint, 2D and 3D, a = 0 and 0.3,
//    against central differences of their values;
//  - closed forms: with S = C E(h) (E the strain of the form, written out here) the compatibility
//    residual vanishes, and at h = 0 the equilibrium stress is tau + (1 - a) S (resp. (1 - a) S)
//    and r = -(1 - a) D S.
#include <kernels/Material.hpp>
#include <kernels/MixedPointPhysics.hpp>
#include <support/RandomTensor.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace mixcon;

namespace mixed_point_tests {

using test::randomMatrix;
using test::randomVector;

/// Stiffness and compliance of the dimension: a rotated orthotropic solid in 3D, its plane-strain
/// reduction in 2D (compliance the inverse).
template <int Dim> struct Constitutive;
template <> struct Constitutive<3> {
  static OrthotropicMaterial material() {
    return {{1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.3, 0.35, 0.8e5, 0.6e5},
            matmul(rotationAboutZ(0.7), matmul(rotationAboutX(0.4), rotationAboutY(-0.3)))};
  }
  static SolidMatrix c() { return material().stiffness(); }
  static SolidMatrix d() { return material().compliance(); }
};
template <> struct Constitutive<2> {
  static PlaneMatrix c() {
    return orthotropicStiffness({1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.3, 0.35},
                                PlaneAnalysis::PlaneStrain, 0.7);
  }
  static PlaneMatrix d() {
    PlaneMatrix inv{};
    invert3(c(), inv);
    return inv;
  }
};

/// Largest deviation of each analytic derivative of `point` at (h, s, tau) from central
/// differences of its values, relative to that derivative's largest entry.
template <class Point, int Dim>
void expectDerivativesMatchDifferences(const Point &point, const Mat<Dim, Dim> &h,
                                       const Vector<Voigt<Dim>::kSize> &s,
                                       const Vector<Voigt<Dim>::kSize> &tau) {
  constexpr int nv = Voigt<Dim>::kSize;
  const auto r = point.template evaluate<true>(h, s, tau);
  // Values agree with evaluate<false>.
  const auto r0 = point.template evaluate<false>(h, s, tau);
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j)
      EXPECT_EQ(r.stress.m[i][j], r0.stress.m[i][j]);
  double errPh = 0, scPh = 0, errRh = 0, scRh = 0, errPs = 0, scPs = 0, errRs = 0, scRs = 0;
  const double dh = 1e-6;
  for (int k = 0; k < Dim; ++k)
    for (int l = 0; l < Dim; ++l) {
      Mat<Dim, Dim> hp = h, hm = h;
      hp.m[k][l] += dh;
      hm.m[k][l] -= dh;
      const auto p = point.template evaluate<false>(hp, s, tau);
      const auto m = point.template evaluate<false>(hm, s, tau);
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) {
          const double fd = (p.stress.m[i][j] - m.stress.m[i][j]) / (2 * dh);
          errPh = std::max(errPh, std::abs(fd - r.dStressDGrad.m[i * Dim + j][k * Dim + l]));
          scPh = std::max(scPh, std::abs(r.dStressDGrad.m[i * Dim + j][k * Dim + l]));
        }
      for (int c = 0; c < nv; ++c) {
        const double fd = (p.compatibility.v[c] - m.compatibility.v[c]) / (2 * dh);
        errRh = std::max(errRh, std::abs(fd - r.dCompatibilityDGrad.m[c][k * Dim + l]));
        scRh = std::max(scRh, std::abs(r.dCompatibilityDGrad.m[c][k * Dim + l]));
      }
    }
  const double ds = 1e-3; // stresses of order 1e3..1e4
  for (int w = 0; w < nv; ++w) {
    Vector<nv> sp = s, sm = s;
    sp.v[w] += ds;
    sm.v[w] -= ds;
    const auto p = point.template evaluate<false>(h, sp, tau);
    const auto m = point.template evaluate<false>(h, sm, tau);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        const double fd = (p.stress.m[i][j] - m.stress.m[i][j]) / (2 * ds);
        errPs = std::max(errPs, std::abs(fd - r.dStressDStress.m[i * Dim + j][w]));
        scPs = std::max(scPs, std::abs(r.dStressDStress.m[i * Dim + j][w]));
      }
    for (int c = 0; c < nv; ++c) {
      const double fd = (p.compatibility.v[c] - m.compatibility.v[c]) / (2 * ds);
      errRs = std::max(errRs, std::abs(fd - r.dCompatibilityDStress.m[c][w]));
      scRs = std::max(scRs, std::abs(r.dCompatibilityDStress.m[c][w]));
    }
  }
  // (The current form's d stress / d grad is zero at a = 0; then the differences must be too.)
  EXPECT_LE(errPh, 1e-7 * scPh) << "d stress / d grad";
  EXPECT_GT(scRh, 0.0);
  EXPECT_LE(errRh, 1e-7 * scRh) << "d compatibility / d grad";
  EXPECT_GT(scPs, 0.0);
  EXPECT_LE(errPs, 1e-7 * scPs) << "d stress / d S";
  EXPECT_GT(scRs, 0.0);
  EXPECT_LE(errRs, 1e-7 * scRs) << "d compatibility / d S";
}

template <int Dim> void pointDerivativesCase() {
  std::mt19937 rng(17 + Dim);
  constexpr int nv = Voigt<Dim>::kSize;
  for (double a : {0.0, 0.3}) {
    const MixedIncrementPoint<Dim> inc{Constitutive<Dim>::c(), Constitutive<Dim>::d(), a};
    const MixedCurrentPoint<Dim> cur{Constitutive<Dim>::c(), Constitutive<Dim>::d(), a};
    for (int trial = 0; trial < 3; ++trial) {
      const Mat<Dim, Dim> h = randomMatrix<Dim>(rng, 0.2);
      const Vector<nv> s = randomVector<nv>(rng, 1e4), tau = randomVector<nv>(rng, 1e4);
      SCOPED_TRACE(::testing::Message() << "a = " << a << " trial " << trial);
      expectDerivativesMatchDifferences(inc, h, s, tau);
      expectDerivativesMatchDifferences(cur, h, s, tau);
    }
  }
}

TEST(MixedPointPhysics, DerivativesMatchFiniteDifferences2D) { pointDerivativesCase<2>(); }
TEST(MixedPointPhysics, DerivativesMatchFiniteDifferences3D) { pointDerivativesCase<3>(); }

/// Green-Lagrange (incremental form) or Almansi (current form) strain, Voigt with engineering
/// shear, written out: E = (h + h^T + h^T h) / 2, e = (h + h^T - h^T h) / 2.
template <int Dim> Vector<Voigt<Dim>::kSize> writtenStrain(const Mat<Dim, Dim> &h, bool almansi) {
  using V = Voigt<Dim>;
  Vector<V::kSize> e{};
  for (int k = 0; k < V::kSize; ++k) {
    const int i = V::row(k), j = V::col(k);
    double hh = 0.0;
    for (int m = 0; m < Dim; ++m)
      hh += h.m[m][i] * h.m[m][j];
    const double t = 0.5 * (h.m[i][j] + h.m[j][i] + (almansi ? -hh : hh));
    e.v[k] = (i == j ? 1.0 : 2.0) * t;
  }
  return e;
}

template <int Dim> void closedFormCase() {
  constexpr int nv = Voigt<Dim>::kSize;
  std::mt19937 rng(29 + Dim);
  const auto c = Constitutive<Dim>::c();
  const auto d = Constitutive<Dim>::d();
  for (double a : {0.0, 0.3}) {
    const MixedIncrementPoint<Dim> inc{c, d, a};
    const MixedCurrentPoint<Dim> cur{c, d, a};
    const Mat<Dim, Dim> h = randomMatrix<Dim>(rng, 0.1);
    const Vector<nv> tau = randomVector<nv>(rng, 1e4);
    for (int form = 0; form < 2; ++form) {
      // S = C E(h): the strain of the stress equals the strain of the displacement.
      const Vector<nv> s = matvec(c, writtenStrain<Dim>(h, form == 1));
      const auto r = form == 0 ? inc.template evaluate<false>(h, s, tau)
                               : cur.template evaluate<false>(h, s, tau);
      double scale = 0.0;
      for (int k = 0; k < nv; ++k)
        scale = std::max(scale, std::abs(writtenStrain<Dim>(h, form == 1).v[k]));
      for (int k = 0; k < nv; ++k)
        EXPECT_NEAR(r.compatibility.v[k], 0.0, 1e-12 * scale) << "form " << form << " a " << a;
    }
    // h = 0: P = tau + (1 - a) S (incremental), (1 - a) S (current); r = -(1 - a) D S.
    const Vector<nv> s = randomVector<nv>(rng, 1e4);
    const Mat<Dim, Dim> zero{};
    const auto ri = inc.template evaluate<false>(zero, s, tau);
    const auto rc = cur.template evaluate<false>(zero, s, tau);
    const Vector<nv> ds = matvec(d, s);
    for (int k = 0; k < nv; ++k) {
      const int i = Voigt<Dim>::row(k), j = Voigt<Dim>::col(k);
      EXPECT_NEAR(ri.stress.m[i][j], tau.v[k] + (1 - a) * s.v[k], 1e-12 * 2e4);
      EXPECT_NEAR(ri.stress.m[j][i], tau.v[k] + (1 - a) * s.v[k], 1e-12 * 2e4);
      EXPECT_NEAR(rc.stress.m[i][j], (1 - a) * s.v[k], 1e-12 * 2e4);
      EXPECT_NEAR(ri.compatibility.v[k], -(1 - a) * ds.v[k], 1e-12 * std::abs(ds.v[k]) + 1e-20);
      EXPECT_NEAR(rc.compatibility.v[k], -(1 - a) * ds.v[k], 1e-12 * std::abs(ds.v[k]) + 1e-20);
    }
  }
}

TEST(MixedPointPhysics, CompatibilityVanishesForTheStressOfTheStrain2D) { closedFormCase<2>(); }
TEST(MixedPointPhysics, CompatibilityVanishesForTheStressOfTheStrain3D) { closedFormCase<3>(); }

} // namespace mixed_point_tests
