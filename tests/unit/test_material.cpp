// Pointwise constitutive laws (kernels/Material.hpp) against textbook formulas, the first
// version's 2D formulas (the host reference of the plane reductions) and Eigen.
#include <kernels/Material.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace mixcon;

namespace {
void expectMatrixNear(const PlaneMatrix &a, const PlaneMatrix &b, double tol) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << "(" << i << "," << j << ")";
}
} // namespace

TEST(Material, IsotropicPlaneStressAndStrainMatchTextbook) {
  const double e = 210000.0, nu = 0.3;
  // Plane stress: E/(1-nu^2) [1 nu 0; nu 1 0; 0 0 (1-nu)/2].
  const double s = e / (1 - nu * nu);
  expectMatrixNear(isotropicStiffness(e, nu, PlaneAnalysis::PlaneStress),
                   PlaneMatrix{{{s, s * nu, 0}, {s * nu, s, 0}, {0, 0, s * (1 - nu) / 2}}}, 1e-9);
  // Plane strain: E/((1+nu)(1-2nu)) [1-nu nu 0; nu 1-nu 0; 0 0 (1-2nu)/2].
  const double p = e / ((1 + nu) * (1 - 2 * nu));
  expectMatrixNear(
      isotropicStiffness(e, nu, PlaneAnalysis::PlaneStrain),
      PlaneMatrix{
          {{p * (1 - nu), p * nu, 0}, {p * nu, p * (1 - nu), 0}, {0, 0, p * (1 - 2 * nu) / 2}}},
      1e-9);
}

TEST(Material, OrthotropicComplianceInvertsStiffness) {
  const OrthotropicConstants k{1.6e6, 1.1e5, 1.0e5, 1.0e5, 0.4, 0.35, 0.45};
  for (auto a : {PlaneAnalysis::PlaneStress, PlaneAnalysis::PlaneStrain}) {
    const PlaneMatrix c = orthotropicStiffness(k, a, 0.0), d = orthotropicCompliance(k, a);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double s = 0;
        for (int l = 0; l < 3; ++l)
          s += c.m[i][l] * d.m[l][j];
        EXPECT_NEAR(s, i == j ? 1.0 : 0.0, 1e-12);
      }
    EXPECT_TRUE(isPositiveDefinite(c));
  }
  // Plane stress: D11 = 1/E1, D12 = -nu12/E1, D66 = 1/G12.
  const PlaneMatrix d = orthotropicCompliance(k, PlaneAnalysis::PlaneStress);
  EXPECT_DOUBLE_EQ(d.m[0][0], 1 / k.e1);
  EXPECT_DOUBLE_EQ(d.m[0][1], -k.nu12 / k.e1);
  EXPECT_DOUBLE_EQ(d.m[2][2], 1 / k.g12);
}

TEST(Material, RotationByNinetyDegreesSwapsAxes) {
  const OrthotropicConstants k{1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4};
  const PlaneMatrix c0 = orthotropicStiffness(k, PlaneAnalysis::PlaneStress, 0.0);
  const PlaneMatrix c90 = orthotropicStiffness(k, PlaneAnalysis::PlaneStress, M_PI / 2);
  EXPECT_NEAR(c90.m[0][0], c0.m[1][1], 1e-6);
  EXPECT_NEAR(c90.m[1][1], c0.m[0][0], 1e-6);
  EXPECT_NEAR(c90.m[0][1], c0.m[0][1], 1e-6);
  EXPECT_NEAR(c90.m[2][2], c0.m[2][2], 1e-6);
  EXPECT_NEAR(c90.m[0][2], 0.0, 1e-6);
}

TEST(Material, RotationsComposeAndLeaveIsotropyInvariant) {
  const OrthotropicConstants k{1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4};
  const PlaneMatrix c = orthotropicStiffness(k, PlaneAnalysis::PlaneStress, 0.0);
  expectMatrixNear(rotateStiffness(rotateStiffness(c, 0.3), 0.5), rotateStiffness(c, 0.8), 1e-6);
  const PlaneMatrix r = rotateStiffness(c, 0.7);
  EXPECT_GT(std::abs(r.m[0][2]), 1e3); // coupling terms C16 appear off-axis
  const PlaneMatrix iso = isotropicStiffness(1.0, 0.25, PlaneAnalysis::PlaneStrain);
  expectMatrixNear(rotateStiffness(iso, 1.234), iso, 1e-14);
}

TEST(Material, RotatedStiffnessGivesSameEnergyForRotatedStrain) {
  // Energy is frame independent: eps_g^T C_g eps_g = eps_m^T C_m eps_m with eps_m the strain
  // components in the material axes (engineering shear).
  const OrthotropicConstants k{1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4};
  const double th = 0.4;
  const PlaneMatrix cm = orthotropicStiffness(k, PlaneAnalysis::PlaneStress, 0.0);
  const PlaneMatrix cg = orthotropicStiffness(k, PlaneAnalysis::PlaneStress, th);
  const double eg[3] = {1e-3, -4e-4, 7e-4};
  const double c = std::cos(th), s = std::sin(th);
  const double em[3] = {c * c * eg[0] + s * s * eg[1] + c * s * eg[2],
                        s * s * eg[0] + c * c * eg[1] - c * s * eg[2],
                        -2 * c * s * eg[0] + 2 * c * s * eg[1] + (c * c - s * s) * eg[2]};
  double wg = 0, wm = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      wg += eg[i] * cg.m[i][j] * eg[j];
      wm += em[i] * cm.m[i][j] * em[j];
    }
  EXPECT_NEAR(wg, wm, 1e-12 * std::abs(wm));
}

TEST(Material, DetectsIndefiniteMatrix) {
  const PlaneMatrix bad{{{1.0, 2.0, 0.0}, {2.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};
  EXPECT_FALSE(isPositiveDefinite(bad));
}

// ---------------------------------------------------------------------------------------------
// The 3D constitutive objects and their plane reductions.

namespace material_tests {

/// The 2D formulas of the first version (kernels/Material.hpp before the 3D objects), copied as
/// the host reference of the reductions: the plane compliance in material axes, the 3x3 adjugate
/// inverse and the rotation T^-1 C T^-T.
namespace legacy {
double invert3(const double (&m)[3][3], double (&inv)[3][3]) {
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  if (det == 0.0)
    return det;
  const double r = 1.0 / det;
  inv[0][0] = c00 * r;
  inv[1][0] = c01 * r;
  inv[2][0] = c02 * r;
  inv[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * r;
  inv[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * r;
  inv[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * r;
  inv[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * r;
  inv[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * r;
  inv[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * r;
  return det;
}
void compliance(const OrthotropicConstants &k, bool planeStrain, double (&d)[3][3]) {
  const double s11 = 1.0 / k.e1, s22 = 1.0 / k.e2, s33 = 1.0 / k.e3;
  const double s12 = -k.nu12 / k.e1, s13 = -k.nu13 / k.e1, s23 = -k.nu23 / k.e2;
  const double d0[3][3] = {{s11, s12, 0.0}, {s12, s22, 0.0}, {0.0, 0.0, 1.0 / k.g12}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      d[i][j] = d0[i][j];
  if (planeStrain) {
    d[0][0] -= s13 * s13 / s33;
    d[0][1] -= s13 * s23 / s33;
    d[1][0] = d[0][1];
    d[1][1] -= s23 * s23 / s33;
  }
}
void rotate(const double (&c)[3][3], double theta, double (&r)[3][3]) {
  const double co = std::cos(theta), si = std::sin(theta);
  const double ti[3][3] = {{co * co, si * si, -2.0 * co * si},
                           {si * si, co * co, 2.0 * co * si},
                           {co * si, -co * si, co * co - si * si}};
  double tmp[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
        s += ti[i][k] * c[k][j];
      tmp[i][j] = s;
    }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
        s += tmp[i][k] * ti[j][k];
      r[i][j] = s;
    }
}
PlaneMatrix stiffness(const OrthotropicConstants &k, bool planeStrain, double theta) {
  double d[3][3], c[3][3] = {}, r[3][3];
  compliance(k, planeStrain, d);
  invert3(d, c);
  rotate(c, theta, r);
  PlaneMatrix out{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      out.m[i][j] = r[i][j];
  return out;
}
} // namespace legacy

template <int N> double maxAbs(const Mat<N, N> &a) {
  double s = 0.0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      s = std::max(s, std::abs(a.m[i][j]));
  return s;
}

/// |a - b| <= rel * max|b| entrywise.
template <int N> void expectRelNear(const Mat<N, N> &a, const Mat<N, N> &b, double rel) {
  const double tol = rel * maxAbs(b);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << "(" << i << "," << j << ")";
}

template <int N> Eigen::Matrix<double, N, N> toEigen(const Mat<N, N> &a) {
  Eigen::Matrix<double, N, N> e;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      e(i, j) = a.m[i][j];
  return e;
}

/// Constant sets of the shipped examples and the unit tests, plus a strongly anisotropic one and
/// a near-incompressible one.
std::vector<OrthotropicConstants> constantSets() {
  return {{1.6e6, 1.1e5, 1.0e5, 1.0e5, 0.4, 0.35, 0.45},
          {1.4e5, 1.0e4, 1.0e4, 5.0e3, 0.3, 0.3, 0.4},
          {12000.0, 600.0, 400.0, 750.0, 0.45, 0.5, 0.55},
          {210e3, 210e3, 210e3, 210e3 / 2.6, 0.3, 0.3, 0.3},
          {1.0, 1.0, 1.0, 1.0 / 2.98, 0.49, 0.49, 0.49},
          {5.0e4, 8.0e3, 2.0e3, 1.2e3, 0.28, 0.1, 0.6}};
}

const double kAngles[] = {0.0, 0.3, M_PI / 6, M_PI / 4, 1.1, M_PI / 2, 2.5, -0.7, M_PI};

/// A rotation about no coordinate axis (z, then y, then x).
Rotation generalRotation() {
  return matmul(rotationAboutX(0.4), matmul(rotationAboutY(-1.1), rotationAboutZ(0.7)));
}

} // namespace material_tests
using namespace material_tests;

TEST(Material, PlaneReductionsReproduceTheFirstVersionsFormulas) {
  for (const OrthotropicConstants &k : constantSets())
    for (const double theta : kAngles)
      for (const bool strain : {false, true}) {
        SCOPED_TRACE(testing::Message() << "E1 " << k.e1 << " theta " << theta
                                        << (strain ? " plane strain" : " plane stress"));
        const PlaneAnalysis a = strain ? PlaneAnalysis::PlaneStrain : PlaneAnalysis::PlaneStress;
        const PlaneMatrix ref = legacy::stiffness(k, strain, theta);
        expectRelNear(orthotropicStiffness(k, a, theta), ref, 1e-13);
        // The same through the 3D object with explicit (arbitrary) transverse shear moduli: they
        // do not enter a reduction about z.
        OrthotropicConstants k3 = k;
        k3.g13 = 0.37 * k.g12;
        k3.g23 = 2.9 * k.g12;
        expectRelNear(planeStiffness(OrthotropicMaterial{k3, rotationAboutZ(theta)}, a), ref,
                      1e-13);
        double d[3][3];
        legacy::compliance(k, strain, d);
        PlaneMatrix dref{};
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            dref.m[i][j] = d[i][j];
        expectRelNear(orthotropicCompliance(k, a), dref, 1e-13);
      }
  // Isotropic through the first version's orthotropic path.
  for (const double nu : {-0.5, 0.0, 0.25, 0.3, 0.45, 0.499})
    for (const bool strain : {false, true}) {
      const double e = 7.0e4;
      const OrthotropicConstants k{e, e, e, e / (2.0 * (1.0 + nu)), nu, nu, nu};
      expectRelNear(isotropicStiffness(
                        e, nu, strain ? PlaneAnalysis::PlaneStrain : PlaneAnalysis::PlaneStress),
                    legacy::stiffness(k, strain, 0.0), 1e-13);
    }
}

TEST(Material, ReductionsAboutZNeedNoTransverseShear) {
  // A problem-file orthotropic material has no G13/G23 (zero): the reductions about z stay finite
  // and equal to those with any positive G13/G23.
  const OrthotropicConstants k{1.6e6, 1.1e5, 1.0e5, 1.0e5, 0.4, 0.35, 0.45};
  ASSERT_EQ(k.g13, 0.0);
  ASSERT_EQ(k.g23, 0.0);
  OrthotropicConstants k3 = k;
  k3.g13 = 1.0;
  k3.g23 = 1e9;
  for (auto a : {PlaneAnalysis::PlaneStress, PlaneAnalysis::PlaneStrain}) {
    const PlaneMatrix c = orthotropicStiffness(k, a, 0.9);
    EXPECT_TRUE(isPositiveDefinite(c));
    EXPECT_EQ(maxAbs(c), maxAbs(c)); // not NaN
    expectRelNear(c, planeStiffness(OrthotropicMaterial{k3, rotationAboutZ(0.9)}, a), 1e-13);
  }
}

TEST(Material, IsotropicClosedForms) {
  for (const double nu : {0.0, 0.2, 0.3, 0.45}) {
    const double e = 2.1e5;
    const double lambda = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
    // 3D: C11 = lambda + 2 mu, C12 = lambda, C44 = mu, no coupling of normal and shear.
    const SolidMatrix c = IsotropicMaterial{e, nu}.stiffness();
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        double expected = 0.0;
        if (i < 3 && j < 3)
          expected = i == j ? lambda + 2 * mu : lambda;
        else if (i == j)
          expected = mu;
        EXPECT_NEAR(c.m[i][j], expected, 1e-12 * e) << "(" << i << "," << j << ")";
      }
    expectRelNear(matmul(IsotropicMaterial{e, nu}.compliance(), c), identity<6>(), 1e-14);
    // Plane strain: lambda + 2 mu, lambda, mu.
    const PlaneMatrix ps = isotropicStiffness(e, nu, PlaneAnalysis::PlaneStrain);
    EXPECT_NEAR(ps.m[0][0], lambda + 2 * mu, 1e-12 * e);
    EXPECT_NEAR(ps.m[1][1], lambda + 2 * mu, 1e-12 * e);
    EXPECT_NEAR(ps.m[0][1], lambda, 1e-12 * e);
    EXPECT_NEAR(ps.m[2][2], mu, 1e-12 * e);
    EXPECT_EQ(ps.m[0][2], 0.0);
    // Plane stress: E / (1 - nu^2), nu E / (1 - nu^2), mu.
    const PlaneMatrix pt = isotropicStiffness(e, nu, PlaneAnalysis::PlaneStress);
    EXPECT_NEAR(pt.m[0][0], e / (1 - nu * nu), 1e-12 * e);
    EXPECT_NEAR(pt.m[0][1], nu * e / (1 - nu * nu), 1e-12 * e);
    EXPECT_NEAR(pt.m[2][2], mu, 1e-12 * e);
    EXPECT_EQ(pt.m[1][2], 0.0);
  }
}

TEST(Material, BondRotationKeepsTheEnergyAndTransformsTensors) {
  const OrthotropicConstants k{1.6e6, 1.1e5, 1.0e5, 1.0e5, 0.4, 0.35, 0.45, 7.0e4, 3.0e4};
  const SolidMatrix cm = OrthotropicMaterial{k, identity<3>()}.stiffness();
  const Rotation r = generalRotation();
  EXPECT_NEAR(determinant(r), 1.0, 1e-15);
  const SolidMatrix cg = rotateStiffness(cm, r);
  // A strain tensor given in material axes and its global components R eps R^T.
  const Mat<3, 3> em{{{1e-3, 2e-4, -3e-4}, {2e-4, -5e-4, 4e-4}, {-3e-4, 4e-4, 6e-4}}};
  const Mat<3, 3> eg = matmulNT(matmul(r, em), r);
  const Vector<6> evm = strainToVoigt(em), evg = strainToVoigt(eg);
  // The strain Bond matrix gives the same global Voigt components.
  const Vector<6> evb = matvec(strainBond(r), evm);
  for (int q = 0; q < 6; ++q)
    EXPECT_NEAR(evb[q], evg[q], 1e-17);
  // Energy eps : C : eps is frame independent.
  const double wm = inner(evm, matvec(cm, evm)), wg = inner(evg, matvec(cg, evg));
  EXPECT_NEAR(wg, wm, 1e-13 * wm);
  // Stress: the stress Bond matrix maps sigma_m to R sigma_m R^T, and sigma_g = C_g eps_g.
  const Vector<6> sm = matvec(cm, evm), sg = matvec(cg, evg);
  const Vector<6> sgTensor = stressToVoigt(matmulNT(matmul(r, voigtToStress<3>(sm)), r));
  for (int q = 0; q < 6; ++q) {
    EXPECT_NEAR(sg[q], sgTensor[q], 1e-12 * maxAbs(cm) * 1e-3);
    EXPECT_NEAR(matvec(stressBond(r), sm)[q], sgTensor[q], 1e-12 * maxAbs(cm) * 1e-3);
  }
  // N = M^-T.
  expectRelNear(matmulTN(stressBond(r), strainBond(r)), identity<6>(), 1e-15);
  // Compliance and stiffness rotate consistently: S_g C_g = I.
  const SolidMatrix sg6 = rotateCompliance(orthotropicMaterialCompliance(k), r);
  expectRelNear(matmul(sg6, cg), identity<6>(), 1e-13);
  expectRelNear(OrthotropicMaterial{k, r}.compliance(), sg6, 0.0);
  expectRelNear(OrthotropicMaterial{k, r}.stiffness(), cg, 1e-13);
}

TEST(Material, QuarterTurnsPermuteTheMaterialAxes) {
  const OrthotropicConstants k{1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.35, 0.45, 7.0e4, 3.0e4};
  const SolidMatrix cm = OrthotropicMaterial{k, identity<3>()}.stiffness();
  // 90 degrees about z: axis 1 along y, axis 2 along -x. xx <-> yy, yz <-> xz.
  const SolidMatrix cz = OrthotropicMaterial{k, rotationAboutZ(M_PI / 2)}.stiffness();
  const double tol = 1e-12 * maxAbs(cm);
  EXPECT_NEAR(cz.m[0][0], cm.m[1][1], tol);
  EXPECT_NEAR(cz.m[1][1], cm.m[0][0], tol);
  EXPECT_NEAR(cz.m[0][2], cm.m[1][2], tol);
  EXPECT_NEAR(cz.m[1][2], cm.m[0][2], tol);
  EXPECT_NEAR(cz.m[3][3], cm.m[4][4], tol);
  EXPECT_NEAR(cz.m[4][4], cm.m[3][3], tol);
  EXPECT_NEAR(cz.m[5][5], cm.m[5][5], tol);
  EXPECT_NEAR(cz.m[0][5], 0.0, tol);
  // 90 degrees about x: axis 2 along z, axis 3 along -y. E2 is the modulus along z.
  const SolidMatrix sx = OrthotropicMaterial{k, rotationAboutX(M_PI / 2)}.compliance();
  EXPECT_NEAR(sx.m[2][2], 1.0 / k.e2, 1e-12 / k.e2);
  EXPECT_NEAR(sx.m[1][1], 1.0 / k.e3, 1e-12 / k.e3);
  EXPECT_NEAR(sx.m[0][0], 1.0 / k.e1, 1e-12 / k.e1);
  EXPECT_NEAR(sx.m[0][2], -k.nu12 / k.e1, 1e-12 / k.e1); // contraction along 2 (= z) under 1
  EXPECT_NEAR(sx.m[5][5], 1.0 / k.g13, 1e-12 / k.g13);   // xy plane is the material 1-3 plane
  EXPECT_NEAR(sx.m[4][4], 1.0 / k.g12, 1e-12 / k.g12);   // xz plane is the material 1-2 plane
  // The 2D angle: the in-plane block of the 3D rotation about z is the plane rotation.
  for (const double theta : kAngles)
    expectRelNear(planeStrainFromStiffness(rotateStiffness(cm, rotationAboutZ(theta))),
                  rotateStiffness(planeStrainFromStiffness(cm), theta), 1e-13);
}

TEST(Material, AnisotropicConstantsReproduceAnOrthotropicMaterial) {
  const OrthotropicConstants k{1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.35, 0.45, 7.0e4, 3.0e4};
  const Rotation r = generalRotation();
  const OrthotropicMaterial orth{k, r};
  const AnisotropicMaterial aniso{
      anisotropicConstants(OrthotropicMaterial{k, identity<3>()}.stiffness()), r};
  // Upper triangle row by row: C11 first, C16 sixth, C22 seventh, C66 last.
  const SolidMatrix cm = OrthotropicMaterial{k, identity<3>()}.stiffness();
  EXPECT_EQ(aniso.constants.c[0], cm.m[0][0]);
  EXPECT_EQ(aniso.constants.c[6], cm.m[1][1]);
  EXPECT_EQ(aniso.constants.c[15], cm.m[3][3]);
  EXPECT_EQ(aniso.constants.c[20], cm.m[5][5]);
  expectRelNear(anisotropicStiffness(aniso.constants), cm, 0.0);
  expectRelNear(aniso.stiffness(), orth.stiffness(), 1e-13);
  expectRelNear(aniso.compliance(), orth.compliance(), 1e-12);
  for (auto a : {PlaneAnalysis::PlaneStress, PlaneAnalysis::PlaneStrain}) {
    expectRelNear(planeStiffness(aniso, a), planeStiffness(orth, a), 1e-12);
    expectRelNear(matmul(planeStiffness(aniso, a), planeCompliance(aniso, a)), identity<3>(),
                  1e-12);
  }
}

TEST(Material, PlaneStressCondensesTheOutOfPlaneStresses) {
  // A tilted orthotropic material couples in-plane and out-of-plane shear; plane stress must be
  // the static condensation sigma_zz = sigma_yz = sigma_xz = 0 of the full stiffness (Eigen
  // reference: C_pp - C_po C_oo^-1 C_op), plane strain its in-plane block.
  const OrthotropicConstants k{1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.35, 0.45, 7.0e4, 3.0e4};
  const OrthotropicMaterial m{k, generalRotation()};
  const Eigen::Matrix<double, 6, 6> c = toEigen(m.stiffness());
  const int p[3] = {0, 1, 5}, o[3] = {2, 3, 4};
  Eigen::Matrix3d cpp, cpo, coo;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      cpp(i, j) = c(p[i], p[j]);
      cpo(i, j) = c(p[i], o[j]);
      coo(i, j) = c(o[i], o[j]);
    }
  EXPECT_GT(cpo.cwiseAbs().maxCoeff(), 1e3); // the coupling is there
  const Eigen::Matrix3d condensed = cpp - cpo * coo.inverse() * cpo.transpose();
  const PlaneMatrix ps = planeStiffness(m, PlaneAnalysis::PlaneStress);
  const PlaneMatrix pe = planeStiffness(m, PlaneAnalysis::PlaneStrain);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(ps.m[i][j], condensed(i, j), 1e-11 * cpp.cwiseAbs().maxCoeff());
      EXPECT_EQ(pe.m[i][j], c(p[i], p[j]));
    }
}

TEST(Material, DetectsIndefiniteSolidLaws) {
  // nu12 = 1.5 with E1 = E2 makes the compliance indefinite.
  const OrthotropicConstants bad{1.0, 1.0, 1.0, 0.4, 1.5, 0.3, 0.3, 0.4, 0.4};
  EXPECT_FALSE(isSymmetricPositiveDefinite(orthotropicMaterialCompliance(bad)));
  EXPECT_EQ(maxAbs(OrthotropicMaterial{bad, identity<3>()}.stiffness()), 0.0);
  EXPECT_FALSE(isPositiveDefinite(orthotropicStiffness(bad, PlaneAnalysis::PlaneStrain, 0.3)));
  EXPECT_FALSE(isPositiveDefinite(orthotropicStiffness(bad, PlaneAnalysis::PlaneStress, 0.3)));
  // Isotropic beyond nu = 0.5 and an anisotropic set with a too large off-diagonal term.
  EXPECT_FALSE(isSymmetricPositiveDefinite(IsotropicMaterial{1.0, 0.6}.stiffness()));
  EXPECT_TRUE(isSymmetricPositiveDefinite(IsotropicMaterial{1.0, 0.3}.stiffness()));
  AnisotropicConstants a = anisotropicConstants(IsotropicMaterial{1.0, 0.3}.stiffness());
  EXPECT_TRUE(isSymmetricPositiveDefinite(anisotropicStiffness(a)));
  a.c[3] = 2.0; // C14: normal xx to shear yz, beyond sqrt(C11 C44)
  EXPECT_FALSE(isSymmetricPositiveDefinite(anisotropicStiffness(a)));
  EXPECT_EQ(maxAbs(AnisotropicMaterial{a, identity<3>()}.compliance()), 0.0);
}

namespace material_tests {
/// The device-callable builders run once in a Kokkos kernel: out holds the plane-stress and
/// plane-strain stiffness of an orthotropic material at angle theta, the isotropic plane-strain
/// stiffness, the plane-stress stiffness of the tilted anisotropic material and its 6x6 rotated
/// stiffness.
void buildOnDevice(const OrthotropicConstants &k, double theta, const AnisotropicMaterial &aniso,
                   const Kokkos::View<double *, Kokkos::DefaultExecutionSpace::memory_space> &out) {
  Kokkos::parallel_for(
      "mixcon::test::materialOnDevice", Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, 1),
      KOKKOS_LAMBDA(int) {
        PlaneMatrix p[4] = {orthotropicStiffness(k, PlaneAnalysis::PlaneStress, theta),
                            orthotropicStiffness(k, PlaneAnalysis::PlaneStrain, theta),
                            isotropicStiffness(3.0, 0.2, PlaneAnalysis::PlaneStrain),
                            planeStiffness(aniso, PlaneAnalysis::PlaneStress)};
        int n = 0;
        for (int q = 0; q < 4; ++q)
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              out(n++) = p[q].m[i][j];
        const SolidMatrix c = aniso.stiffness();
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j)
            out(n++) = c.m[i][j];
      });
}
} // namespace material_tests

TEST(Material, DeviceBuildersMatchHostCalls) {
  const OrthotropicConstants k{1.6e6, 1.1e5, 1.0e5, 1.0e5, 0.4, 0.35, 0.45};
  const double theta = 0.6;
  const AnisotropicMaterial aniso{
      anisotropicConstants(OrthotropicMaterial{
          OrthotropicConstants{1.6e6, 1.1e5, 0.9e5, 1.0e5, 0.4, 0.35, 0.45, 7.0e4, 3.0e4},
          identity<3>()}
                               .stiffness()),
      generalRotation()};
  std::vector<double> ref;
  const PlaneMatrix p[4] = {orthotropicStiffness(k, PlaneAnalysis::PlaneStress, theta),
                            orthotropicStiffness(k, PlaneAnalysis::PlaneStrain, theta),
                            isotropicStiffness(3.0, 0.2, PlaneAnalysis::PlaneStrain),
                            planeStiffness(aniso, PlaneAnalysis::PlaneStress)};
  for (const auto &m : p)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        ref.push_back(m.m[i][j]);
  const SolidMatrix c = aniso.stiffness();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      ref.push_back(c.m[i][j]);
  Kokkos::View<double *, Kokkos::DefaultExecutionSpace::memory_space> out("out", ref.size());
  buildOnDevice(k, theta, aniso, out);
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  for (std::size_t q = 0; q < ref.size(); ++q)
    EXPECT_NEAR(h(q), ref[q], 1e-13 * std::max(1.0, std::abs(ref[q]))) << "entry " << q;
}
