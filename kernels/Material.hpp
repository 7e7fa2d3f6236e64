// Pointwise constitutive laws. Materials are full 3D objects: a 6x6 stiffness and compliance in
// Voigt order xx, yy, zz, yz, xz, xy (engineering shear strain) from isotropic, orthotropic
// (9 constants and an orientation) or general anisotropic (21 constants) data, rotated to global
// axes by the Bond transformation. The 2D kernels use the anisotropic plane constitutive matrix
// [C] = [C11 C12 C16; C12 C22 C26; C16 C26 C66] of the report's Eq. (25) (Voigt order xx, yy, xy),
// obtained as the plane-strain or plane-stress REDUCTION of the 3D object. Small POD structs and
// pure functions, callable on host and device. Data flow: kernels (used by every element kernel).
#pragma once

#include <core/Compat.hpp>
#include <core/Tensor.hpp>

namespace mixcon {

enum class PlaneAnalysis { PlaneStress, PlaneStrain };

/// 3x3 symmetric plane constitutive (or compliance) matrix in Voigt order xx, yy, xy.
using PlaneMatrix = Mat<3, 3>;

/// 6x6 symmetric constitutive (stiffness or compliance) matrix of a solid in Voigt order xx, yy,
/// zz, yz, xz, xy with engineering shear strain (Voigt<3>).
using SolidMatrix = Mat<6, 6>;

/// Orientation of a material: R(i, a) is global component i of material axis a (columns are the
/// material axes 1, 2, 3 in x, y, z), so a vector's global components are R times its material
/// components. Proper orthogonal.
using Rotation = Mat<3, 3>;

/// Orthotropic engineering constants in the material axes (1, 2 in plane, 3 out of plane in 2D).
/// nu_ij is the Poisson ratio for stress in i and contraction in j (nu_ij / E_i = nu_ji / E_j).
/// g13 and g23 are the transverse shear moduli, needed by the 3D objects only: 0 means not given
/// (the 2D problem file has no keys for them); plane reductions with axis 3 along z do not depend
/// on them, and the plane builders below substitute g12 for a missing one.
struct OrthotropicConstants {
  double e1, e2, e3;
  double g12;
  double nu12, nu13, nu23;
  double g13 = 0.0, g23 = 0.0;
};

/// General anisotropic stiffness: the 21 independent entries of the symmetric 6x6 stiffness in
/// Voigt order xx, yy, zz, yz, xz, xy, upper triangle row by row (C11 C12 C13 C14 C15 C16 C22 ...
/// C26 C33 ... C66; C44 is the yz shear, C66 the xy shear).
struct AnisotropicConstants {
  double c[21];
};

/// Inverse of a 3x3 matrix; returns the determinant of `a` (zero or negative: not invertible / not
/// positive definite, and `inv` is then left unchanged when zero).
KOKKOS_INLINE_FUNCTION double invert3(const PlaneMatrix &a, PlaneMatrix &inv) {
  return inverse(a, inv);
}

// ---------------------------------------------------------------------------------------------
// Orientation and the Bond transformation of 6x6 constitutive matrices.

/// Rotation by `theta` (radians, counter-clockwise seen from +z) about z: material axis 1 makes
/// the angle theta with x in the x-y plane (the 2D material angle).
KOKKOS_INLINE_FUNCTION Rotation rotationAboutZ(double theta) {
  const double c = detail::cos(theta), s = detail::sin(theta);
  return Rotation{{{c, -s, 0.0}, {s, c, 0.0}, {0.0, 0.0, 1.0}}};
}

/// Rotation by `theta` (radians, right-handed) about x.
KOKKOS_INLINE_FUNCTION Rotation rotationAboutX(double theta) {
  const double c = detail::cos(theta), s = detail::sin(theta);
  return Rotation{{{1.0, 0.0, 0.0}, {0.0, c, -s}, {0.0, s, c}}};
}

/// Rotation by `theta` (radians, right-handed) about y.
KOKKOS_INLINE_FUNCTION Rotation rotationAboutY(double theta) {
  const double c = detail::cos(theta), s = detail::sin(theta);
  return Rotation{{{c, 0.0, s}, {0.0, 1.0, 0.0}, {-s, 0.0, c}}};
}

/// Bond matrix M of stresses: sigma_global = M sigma_material (Voigt) for sigma_global =
/// R sigma_material R^T.
KOKKOS_INLINE_FUNCTION SolidMatrix stressBond(const Rotation &r) {
  using V = Voigt<3>;
  SolidMatrix m{};
  for (int k = 0; k < 6; ++k)
    for (int l = 0; l < 6; ++l) {
      const int i = V::row(k), j = V::col(k), a = V::row(l), b = V::col(l);
      m.m[k][l] = r.m[i][a] * r.m[j][b] + (a != b ? r.m[i][b] * r.m[j][a] : 0.0);
    }
  return m;
}

/// Bond matrix N of strains with engineering shear: eps_global = N eps_material (Voigt). For a
/// rotation N = M^-T, so that sigma . eps is frame independent.
KOKKOS_INLINE_FUNCTION SolidMatrix strainBond(const Rotation &r) {
  using V = Voigt<3>;
  SolidMatrix n{};
  for (int k = 0; k < 6; ++k)
    for (int l = 0; l < 6; ++l) {
      const int i = V::row(k), j = V::col(k), a = V::row(l), b = V::col(l);
      const double t =
          a == b ? r.m[i][a] * r.m[j][a] : 0.5 * (r.m[i][a] * r.m[j][b] + r.m[i][b] * r.m[j][a]);
      n.m[k][l] = (i == j ? 1.0 : 2.0) * t;
    }
  return n;
}

/// Stiffness in global axes of a stiffness given in material axes: C_global = M C M^T.
KOKKOS_INLINE_FUNCTION SolidMatrix rotateStiffness(const SolidMatrix &c, const Rotation &r) {
  const SolidMatrix m = stressBond(r);
  return matmulNT(matmul(m, c), m);
}

/// Compliance in global axes of a compliance given in material axes: S_global = N S N^T.
KOKKOS_INLINE_FUNCTION SolidMatrix rotateCompliance(const SolidMatrix &s, const Rotation &r) {
  const SolidMatrix n = strainBond(r);
  return matmulNT(matmul(n, s), n);
}

/// Compliance from stiffness or stiffness from compliance (the inverse of a symmetric positive
/// definite 6x6). Returns false, leaving `out` unchanged, when `in` is not positive definite.
KOKKOS_INLINE_FUNCTION bool invertConstitutive(const SolidMatrix &in, SolidMatrix &out) {
  return spdInverse(in, out);
}

// ---------------------------------------------------------------------------------------------
// 3D constitutive objects: stiffness() and compliance() in global axes.

/// Isotropic solid: Young's modulus e and Poisson's ratio nu (-1 < nu < 0.5 for a positive
/// definite law).
struct IsotropicMaterial {
  double e, nu;

  /// C = lambda 1 (x) 1 + 2 mu I: C11 = lambda + 2 mu, C12 = lambda, C44 = mu.
  KOKKOS_INLINE_FUNCTION SolidMatrix stiffness() const {
    const double lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    const double mu = e / (2.0 * (1.0 + nu));
    SolidMatrix c{};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        c.m[i][j] = lambda;
      c.m[i][i] = lambda + 2.0 * mu;
      c.m[3 + i][3 + i] = mu;
    }
    return c;
  }
  /// S11 = 1/E, S12 = -nu/E, S44 = 1/mu = 2 (1 + nu) / E.
  KOKKOS_INLINE_FUNCTION SolidMatrix compliance() const {
    SolidMatrix s{};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        s.m[i][j] = -nu / e;
      s.m[i][i] = 1.0 / e;
      s.m[3 + i][3 + i] = 2.0 * (1.0 + nu) / e;
    }
    return s;
  }
};

/// Compliance of orthotropic constants in their material axes (all nine constants must be
/// positive where they divide: e1, e2, e3, g12, g13, g23).
KOKKOS_INLINE_FUNCTION SolidMatrix orthotropicMaterialCompliance(const OrthotropicConstants &k) {
  SolidMatrix s{};
  s.m[0][0] = 1.0 / k.e1;
  s.m[1][1] = 1.0 / k.e2;
  s.m[2][2] = 1.0 / k.e3;
  s.m[0][1] = s.m[1][0] = -k.nu12 / k.e1;
  s.m[0][2] = s.m[2][0] = -k.nu13 / k.e1;
  s.m[1][2] = s.m[2][1] = -k.nu23 / k.e2;
  s.m[3][3] = 1.0 / k.g23; // yz = 23
  s.m[4][4] = 1.0 / k.g13; // xz = 13
  s.m[5][5] = 1.0 / k.g12; // xy = 12
  return s;
}

/// Orthotropic solid: nine engineering constants in the material axes and the orientation of
/// those axes (identity: axes 1, 2, 3 along x, y, z).
struct OrthotropicMaterial {
  OrthotropicConstants constants;
  Rotation orientation;

  KOKKOS_INLINE_FUNCTION SolidMatrix compliance() const {
    return rotateCompliance(orthotropicMaterialCompliance(constants), orientation);
  }
  /// The inverse of compliance(); the zero matrix when the constants give no positive definite
  /// law (check with isSymmetricPositiveDefinite).
  KOKKOS_INLINE_FUNCTION SolidMatrix stiffness() const {
    SolidMatrix c{};
    invertConstitutive(compliance(), c);
    return c;
  }
};

/// The symmetric 6x6 matrix of 21 constants (upper triangle row by row).
KOKKOS_INLINE_FUNCTION SolidMatrix anisotropicStiffness(const AnisotropicConstants &k) {
  SolidMatrix c{};
  int n = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j) {
      c.m[i][j] = k.c[n];
      c.m[j][i] = k.c[n];
      ++n;
    }
  return c;
}

/// The 21 constants (upper triangle row by row) of a symmetric 6x6 stiffness.
KOKKOS_INLINE_FUNCTION AnisotropicConstants anisotropicConstants(const SolidMatrix &c) {
  AnisotropicConstants k{};
  int n = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j)
      k.c[n++] = c.m[i][j];
  return k;
}

/// General anisotropic solid: 21 stiffness constants in the material axes and their orientation.
struct AnisotropicMaterial {
  AnisotropicConstants constants;
  Rotation orientation;

  KOKKOS_INLINE_FUNCTION SolidMatrix stiffness() const {
    return rotateStiffness(anisotropicStiffness(constants), orientation);
  }
  /// The inverse of stiffness(); the zero matrix when the constants are not positive definite.
  KOKKOS_INLINE_FUNCTION SolidMatrix compliance() const {
    SolidMatrix s{};
    invertConstitutive(stiffness(), s);
    return s;
  }
};

// ---------------------------------------------------------------------------------------------
// Plane reductions of a 3D law (the 2D models lie in the x-y plane).
//
// Plane strain (eps_zz = eps_yz = eps_xz = 0, the kinematics of a 2D displacement u(x, y),
// v(x, y), w = 0): the in-plane rows and columns xx, yy, xy of the stiffness.
// Plane stress (sigma_zz = sigma_yz = sigma_xz = 0): the inverse of the in-plane rows and
// columns of the compliance, i.e. the out-of-plane strains are condensed out.
// Both are exact for a material for which z is normal to a plane of symmetry (monoclinic about z:
// isotropic, orthotropic with axis 3 along z at any angle about z), where in-plane stresses and
// the out-of-plane shears yz, xz do not couple. For a material that couples them (C14, C15, C24,
// C25, C34, C35, C46 or C56 nonzero in global axes, e.g. an orthotropic material tilted out of the
// plane) the reductions are the usual approximations: plane strain keeps eps_yz = eps_xz = 0 and
// drops the shear stresses sigma_yz, sigma_xz they induce (which would drive an antiplane
// displacement w(x, y) in a real body: generalized plane strain is not modelled); plane stress
// lets eps_zz, eps_yz, eps_xz take the values that make the out-of-plane stresses vanish (the
// thin-plate reading). Neither reduction needs the constants that do not couple to the plane
// (G13, G23 of an orthotropic material with axis 3 along z).

/// Voigt<3> component of plane component k (xx, yy, xy -> 0, 1, 5).
KOKKOS_INLINE_FUNCTION constexpr int planeToSolidComponent(int k) { return k == 2 ? 5 : k; }

/// In-plane rows and columns xx, yy, xy of a 6x6 constitutive matrix.
KOKKOS_INLINE_FUNCTION PlaneMatrix inPlaneBlock(const SolidMatrix &a) {
  PlaneMatrix p{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      p.m[i][j] = a.m[planeToSolidComponent(i)][planeToSolidComponent(j)];
  return p;
}

/// Plane-strain stiffness of a 3D stiffness (global axes): its in-plane rows and columns.
KOKKOS_INLINE_FUNCTION PlaneMatrix planeStrainFromStiffness(const SolidMatrix &c) {
  return inPlaneBlock(c);
}

/// Plane-stress stiffness of a 3D compliance (global axes): the inverse of its in-plane rows and
/// columns (the zero matrix when that block is singular).
KOKKOS_INLINE_FUNCTION PlaneMatrix planeStressFromCompliance(const SolidMatrix &s) {
  PlaneMatrix c{};
  invert3(inPlaneBlock(s), c);
  return c;
}

/// Plane stiffness [C] of a 3D constitutive object (IsotropicMaterial, OrthotropicMaterial,
/// AnisotropicMaterial or anything with stiffness() and compliance() in global axes).
template <class Material>
KOKKOS_INLINE_FUNCTION PlaneMatrix planeStiffness(const Material &material,
                                                  PlaneAnalysis analysis) {
  return analysis == PlaneAnalysis::PlaneStrain ? planeStrainFromStiffness(material.stiffness())
                                                : planeStressFromCompliance(material.compliance());
}

/// Plane compliance [D] = [C]^-1 of a 3D constitutive object: the in-plane block of the compliance
/// for plane stress, the inverse of the in-plane block of the stiffness for plane strain (the zero
/// matrix when that block is singular).
template <class Material>
KOKKOS_INLINE_FUNCTION PlaneMatrix planeCompliance(const Material &material,
                                                   PlaneAnalysis analysis) {
  if (analysis == PlaneAnalysis::PlaneStress)
    return inPlaneBlock(material.compliance());
  PlaneMatrix d{};
  invert3(inPlaneBlock(material.stiffness()), d);
  return d;
}

// ---------------------------------------------------------------------------------------------
// The 2D builders (problem-file materials), as reductions of the 3D objects.

namespace detail {
/// The constants with a missing (non-positive) g13 or g23 replaced by g12: the plane reductions
/// with axis 3 along z do not depend on them (the shears yz, xz decouple exactly), but the 6x6
/// algebra must not divide by zero.
KOKKOS_INLINE_FUNCTION OrthotropicConstants withTransverseShear(OrthotropicConstants k) {
  if (!(k.g13 > 0.0))
    k.g13 = k.g12;
  if (!(k.g23 > 0.0))
    k.g23 = k.g12;
  return k;
}
} // namespace detail

/// In-plane compliance [D] in the material axes, reduced for plane stress (sigma_33 = 0: the
/// in-plane block of the compliance) or plane strain (epsilon_33 = 0: the inverse of the in-plane
/// block of the stiffness, which equals D_ij - D_i3 D_j3 / D_33 for axis 3 along z).
KOKKOS_INLINE_FUNCTION PlaneMatrix orthotropicCompliance(const OrthotropicConstants &k,
                                                         PlaneAnalysis analysis) {
  return planeCompliance(OrthotropicMaterial{detail::withTransverseShear(k), identity<3>()},
                         analysis);
}

/// Rotates a plane constitutive matrix given in material axes to the global x-y axes, where the
/// material axis 1 makes the angle `theta` (radians, counter-clockwise) with x:
/// C_global = T^-1 C T^-T with T the stress transformation (sigma_material = T sigma_global).
/// (The in-plane block of rotateStiffness(SolidMatrix, rotationAboutZ(theta)).)
KOKKOS_INLINE_FUNCTION PlaneMatrix rotateStiffness(const PlaneMatrix &c, double theta) {
  const double co = detail::cos(theta), si = detail::sin(theta);
  // T^-1 = T(-theta)
  const PlaneMatrix ti{{{co * co, si * si, -2.0 * co * si},
                        {si * si, co * co, 2.0 * co * si},
                        {co * si, -co * si, co * co - si * si}}};
  return matmulNT(matmul(ti, c), ti);
}

/// Orthotropic plane stiffness [C] in global axes (material axis 1 at angle theta from x, axis 3
/// along z).
KOKKOS_INLINE_FUNCTION PlaneMatrix orthotropicStiffness(const OrthotropicConstants &k,
                                                        PlaneAnalysis analysis, double theta) {
  return planeStiffness(OrthotropicMaterial{detail::withTransverseShear(k), rotationAboutZ(theta)},
                        analysis);
}

/// Isotropic plane stiffness [C] from Young's modulus and Poisson's ratio.
KOKKOS_INLINE_FUNCTION PlaneMatrix isotropicStiffness(double e, double nu, PlaneAnalysis analysis) {
  return planeStiffness(IsotropicMaterial{e, nu}, analysis);
}

/// True when the matrix is symmetric positive definite (leading principal minors positive).
KOKKOS_INLINE_FUNCTION bool isPositiveDefinite(const PlaneMatrix &c) {
  const auto &m = c.m;
  const double m1 = m[0][0];
  const double m2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  const double m3 = determinant(c);
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
