// Pointwise constitutive law (kernels/Material.hpp) against textbook formulas.
#include <kernels/Material.hpp>

#include <gtest/gtest.h>

#include <cmath>

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
