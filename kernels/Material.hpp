// Pointwise constitutive law of the report: the anisotropic plane constitutive matrix
// [C] = [C11 C12 C16; C12 C22 C26; C16 C26 C66] of Eq. (25) (Voigt order xx, yy, xy with
// engineering shear strain), built from isotropic or orthotropic engineering constants, reduced to
// plane stress or plane strain, and rotated by a material angle. Small POD structs and pure
// functions, callable on host and device. Data flow: kernels (used by every element kernel).
#pragma once

#include <core/Compat.hpp>

namespace mixcon {

enum class PlaneAnalysis { PlaneStress, PlaneStrain };

/// 3x3 symmetric plane constitutive (or compliance) matrix in Voigt order xx, yy, xy.
struct PlaneMatrix {
  double m[3][3];
};

/// Orthotropic engineering constants in the material axes (1, 2 in plane, 3 out of plane).
/// nu_ij is the Poisson ratio for stress in i and contraction in j (nu_ij / E_i = nu_ji / E_j).
struct OrthotropicConstants {
  double e1, e2, e3;
  double g12;
  double nu12, nu13, nu23;
};

/// Inverse of a 3x3 matrix; returns the determinant of `a` (zero or negative: not invertible / not
/// positive definite, and `inv` is then left unchanged).
KOKKOS_INLINE_FUNCTION double invert3(const PlaneMatrix &a, PlaneMatrix &inv) {
  const auto &m = a.m;
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  if (det == 0.0)
    return det;
  const double r = 1.0 / det;
  inv.m[0][0] = c00 * r;
  inv.m[1][0] = c01 * r;
  inv.m[2][0] = c02 * r;
  inv.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * r;
  inv.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * r;
  inv.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * r;
  inv.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * r;
  inv.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * r;
  inv.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * r;
  return det;
}

/// In-plane compliance [D] in the material axes, reduced for plane stress (sigma_33 = 0) or plane
/// strain (epsilon_33 = 0: D_ij - D_i3 D_j3 / D_33).
KOKKOS_INLINE_FUNCTION PlaneMatrix orthotropicCompliance(const OrthotropicConstants &k,
                                                         PlaneAnalysis analysis) {
  const double s11 = 1.0 / k.e1, s22 = 1.0 / k.e2, s33 = 1.0 / k.e3;
  const double s12 = -k.nu12 / k.e1, s13 = -k.nu13 / k.e1, s23 = -k.nu23 / k.e2;
  PlaneMatrix d{{{s11, s12, 0.0}, {s12, s22, 0.0}, {0.0, 0.0, 1.0 / k.g12}}};
  if (analysis == PlaneAnalysis::PlaneStrain) {
    d.m[0][0] -= s13 * s13 / s33;
    d.m[0][1] -= s13 * s23 / s33;
    d.m[1][0] = d.m[0][1];
    d.m[1][1] -= s23 * s23 / s33;
  }
  return d;
}

/// Rotates a plane constitutive matrix given in material axes to the global x-y axes, where the
/// material axis 1 makes the angle `theta` (radians, counter-clockwise) with x:
/// C_global = T^-1 C T^-T with T the stress transformation (sigma_material = T sigma_global).
KOKKOS_INLINE_FUNCTION PlaneMatrix rotateStiffness(const PlaneMatrix &c, double theta) {
  const double co = detail::cos(theta), si = detail::sin(theta);
  // T^-1 = T(-theta)
  const double ti[3][3] = {{co * co, si * si, -2.0 * co * si},
                           {si * si, co * co, 2.0 * co * si},
                           {co * si, -co * si, co * co - si * si}};
  double tmp[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
        s += ti[i][k] * c.m[k][j];
      tmp[i][j] = s;
    }
  PlaneMatrix r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
        s += tmp[i][k] * ti[j][k];
      r.m[i][j] = s;
    }
  return r;
}

/// Orthotropic plane stiffness [C] in global axes (material axis 1 at angle theta from x).
KOKKOS_INLINE_FUNCTION PlaneMatrix orthotropicStiffness(const OrthotropicConstants &k,
                                                        PlaneAnalysis analysis, double theta) {
  PlaneMatrix c{};
  invert3(orthotropicCompliance(k, analysis), c);
  return rotateStiffness(c, theta);
}

/// Isotropic plane stiffness [C] from Young's modulus and Poisson's ratio.
KOKKOS_INLINE_FUNCTION PlaneMatrix isotropicStiffness(double e, double nu, PlaneAnalysis analysis) {
  const OrthotropicConstants k{e, e, e, e / (2.0 * (1.0 + nu)), nu, nu, nu};
  return orthotropicStiffness(k, analysis, 0.0);
}

/// True when the matrix is symmetric positive definite (leading principal minors positive).
KOKKOS_INLINE_FUNCTION bool isPositiveDefinite(const PlaneMatrix &c) {
  const auto &m = c.m;
  const double m1 = m[0][0];
  const double m2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  PlaneMatrix dummy{};
  const double m3 = invert3(c, dummy);
  return m1 > 0.0 && m2 > 0.0 && m3 > 0.0;
}

/// sigma = C eps for Voigt vectors (engineering shear strain).
KOKKOS_INLINE_FUNCTION void applyStiffness(const PlaneMatrix &c, const double (&eps)[3],
                                           double (&sig)[3]) {
  for (int i = 0; i < 3; ++i)
    sig[i] = c.m[i][0] * eps[0] + c.m[i][1] * eps[1] + c.m[i][2] * eps[2];
}

/// Elastic law of the geometrically nonlinear displacement model (both reduce to Hooke's law at
/// small strain and differ at second order in the strain).
enum class ElasticLaw : int {
  /// Cauchy stress = C : Almansi strain of the current configuration (the report's Eq. (26)).
  Almansi = 0,
  /// 2nd Piola-Kirchhoff stress = C : Green-Lagrange strain (St. Venant-Kirchhoff, the usual
  /// "linear elastic material with geometric nonlinearity" of total-Lagrangian codes).
  SaintVenantKirchhoff = 1
};

} // namespace mixcon
