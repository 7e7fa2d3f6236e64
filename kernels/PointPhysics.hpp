// Pointwise physics of the displacement model, apart from any element loop (libCEED's
// quadrature-point functions, MFEM's point stage of partial assembly): a point law gets what it
// needs at one quadrature point (a strain, a displacement gradient) and returns the stress and
// its consistent tangent; the element driver (kernels/ElementDriver.hpp) does gather, geometry
// and scatter around it. Small structs of plain data with device-callable members, templated on
// the dimension; no loops over nodes here. Layer: kernels (used by the element kernels).
#pragma once

#include <core/Tensor.hpp>
#include <kernels/Material.hpp>

namespace mixcon {

/// Small-strain Voigt strain (engineering shear) of a displacement gradient grad(i, j) =
/// du_i / dx_j: eps_k = grad(r, r) for a normal component, grad(r, c) + grad(c, r) for a shear
/// component (r, c) = (Voigt::row(k), Voigt::col(k)).
template <int Dim>
KOKKOS_INLINE_FUNCTION Vector<Voigt<Dim>::kSize> smallStrain(const Mat<Dim, Dim> &grad) {
  using V = Voigt<Dim>;
  Vector<V::kSize> eps{};
  for (int k = 0; k < V::kSize; ++k) {
    const int r = V::row(k), c = V::col(k);
    eps.v[k] = V::isShear(k) ? grad.m[r][c] + grad.m[c][r] : grad.m[r][r];
  }
  return eps;
}

/// The tangent of C : sym(A^T X) with respect to X: column i * Dim + j is C times the Voigt
/// strain (engineering shear: x2) of sym(A^T E_ij), E_ij the unit matrix of entry (i, j). Both
/// finite-strain laws below vary their strain this way: the Almansi strain with A = I - h, the
/// Green-Lagrange strain with A = F.
template <int Dim>
KOKKOS_INLINE_FUNCTION Mat<Voigt<Dim>::kSize, Dim * Dim>
symmetricProductTangent(const Mat<Voigt<Dim>::kSize, Voigt<Dim>::kSize> &c,
                        const Mat<Dim, Dim> &a) {
  using V = Voigt<Dim>;
  Mat<V::kSize, Dim * Dim> t{};
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) {
      // sym(A^T E_ij)_rs = (A_ir delta_js + A_is delta_jr) / 2.
      Vector<V::kSize> de{};
      for (int k = 0; k < V::kSize; ++k) {
        const int r = V::row(k), s = V::col(k);
        de.v[k] =
            (V::isShear(k) ? 1.0 : 0.5) * ((s == j ? a.m[i][r] : 0.0) + (r == j ? a.m[i][s] : 0.0));
      }
      const Vector<V::kSize> ds = matvec(c, de);
      for (int k = 0; k < V::kSize; ++k)
        t.m[k][i * Dim + j] = ds.v[k];
    }
  return t;
}

/// Linear elasticity at a point (Hooke's law, the report's Eq. (25)): sigma = C eps and
/// d sigma / d eps = C, with C the Voigt stiffness of the point's material in global axes (in 2D
/// the plane-strain or plane-stress PlaneMatrix) and eps the Voigt strain with engineering shear.
/// The tangent does not depend on the strain (kConstantTangent).
template <int Dim> struct LinearElasticPoint {
  static constexpr int kDim = Dim;
  static constexpr int kSize = Voigt<Dim>::kSize;
  static constexpr bool kConstantTangent = true;
  using Stiffness = Mat<kSize, kSize>;

  Stiffness c; ///< Voigt stiffness, symmetric

  /// Cauchy stress (Voigt) of the strain eps (Voigt, engineering shear).
  KOKKOS_INLINE_FUNCTION Vector<kSize> stress(const Vector<kSize> &eps) const {
    return matvec(c, eps);
  }
  /// d stress / d eps at strain eps: C.
  KOKKOS_INLINE_FUNCTION Stiffness tangent(const Vector<kSize> &) const { return c; }
};

/// Almansi law of the updated-Lagrangian displacement model (the report's Eq. (26), corrected):
/// Cauchy stress sigma = C : e with the Almansi strain e = (h + h^T - h^T h) / 2 of the spatial
/// displacement gradient h = du/dx (x the current configuration). tangent(h) is d sigma / d h,
/// the Voigt rows against the entries h(i, j) numbered i * Dim + j. (The element kernel varies
/// the current configuration too: there dh = (I - h) dl with dl = d(delta u)/dx.)
template <int Dim> struct AlmansiPoint {
  static constexpr int kDim = Dim;
  static constexpr int kSize = Voigt<Dim>::kSize;
  static constexpr bool kConstantTangent = false;
  using Stiffness = Mat<kSize, kSize>;

  Stiffness c; ///< Voigt stiffness, symmetric

  /// Almansi strain tensor of h.
  KOKKOS_INLINE_FUNCTION static Mat<Dim, Dim> strain(const Mat<Dim, Dim> &h) {
    Mat<Dim, Dim> e{};
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        double hh = 0.0;
        for (int k = 0; k < Dim; ++k)
          hh += h.m[k][i] * h.m[k][j];
        e.m[i][j] = 0.5 * (h.m[i][j] + h.m[j][i] - hh);
      }
    return e;
  }
  /// Cauchy stress (Voigt) at spatial displacement gradient h.
  KOKKOS_INLINE_FUNCTION Vector<kSize> stress(const Mat<Dim, Dim> &h) const {
    return matvec(c, strainToVoigt<Dim>(strain(h)));
  }
  /// d sigma / d h: column i * Dim + j is C times the Voigt strain of
  /// de = sym((I - h)^T E_ij), E_ij the unit matrix of entry (i, j).
  KOKKOS_INLINE_FUNCTION Mat<kSize, Dim * Dim> tangent(const Mat<Dim, Dim> &h) const {
    Mat<Dim, Dim> a{}; // I - h
    for (int i = 0; i < Dim; ++i)
      for (int r = 0; r < Dim; ++r)
        a.m[i][r] = (r == i ? 1.0 : 0.0) - h.m[i][r];
    return symmetricProductTangent<Dim>(c, a);
  }
};

/// St. Venant-Kirchhoff law of the total-Lagrangian displacement model: 2nd Piola-Kirchhoff
/// stress S = C : E with the Green-Lagrange strain E = (F^T F - I) / 2 of the deformation
/// gradient F = I + du/dX. tangent(f) is d S / d F, the Voigt rows against the entries F(i, j)
/// numbered i * Dim + j (dE = sym(F^T dF)).
template <int Dim> struct SaintVenantKirchhoffPoint {
  static constexpr int kDim = Dim;
  static constexpr int kSize = Voigt<Dim>::kSize;
  static constexpr bool kConstantTangent = false;
  using Stiffness = Mat<kSize, kSize>;

  Stiffness c; ///< Voigt stiffness, symmetric

  /// Green-Lagrange strain tensor of F.
  KOKKOS_INLINE_FUNCTION static Mat<Dim, Dim> strain(const Mat<Dim, Dim> &f) {
    Mat<Dim, Dim> e = matmulTN(f, f);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j)
        e.m[i][j] = 0.5 * (e.m[i][j] - (i == j ? 1.0 : 0.0));
    return e;
  }
  /// 2nd Piola-Kirchhoff stress (Voigt) at deformation gradient F.
  KOKKOS_INLINE_FUNCTION Vector<kSize> stress(const Mat<Dim, Dim> &f) const {
    return matvec(c, strainToVoigt<Dim>(strain(f)));
  }
  /// d S / d F: column i * Dim + j is C times the Voigt strain of dE = sym(F^T E_ij).
  KOKKOS_INLINE_FUNCTION Mat<kSize, Dim * Dim> tangent(const Mat<Dim, Dim> &f) const {
    return symmetricProductTangent<Dim>(c, f);
  }
};

} // namespace mixcon
