// Pointwise physics of the mixed (Hellinger-Reissner) model, apart from any element loop (the
// libCEED / MFEM split, as kernels/PointPhysics.hpp for the displacement model): at one
// quadrature point, from the displacement gradient h, the interpolated stress unknowns s (Voigt)
// and the prestress tau, a point functor gives
//  - the equilibrium stress P that multiplies the test gradients (G_u(a, i) += da P_ij g_aj),
//  - the strain-compatibility residual r of the stress equations (G_S(a, c) += da psi_a r_c),
//  - and, for the Jacobian, dP/dh, dP/ds, dr/dh and dr/ds,
// with the stabilization a (0: the report's model), the stiffness C and the compliance D.
// Two forms (kernels/Nonlinear.hpp, docs/theory.md "Geometric nonlinearity"):
//  - MixedIncrementPoint, total Lagrangian on the last converged configuration c1 (Eq. (9),
//    (16)-(22)): h = du/dX, F = I + h, E = (F^T F - I) / 2, Sigma = tau + (1 - a) s + a C E,
//    P = F Sigma, r = (1 - a) (E - D s);
//  - MixedCurrentPoint, on the current configuration: h = du/dx, e = (h + h^T - h^T h) / 2
//    (Almansi), P = (1 - a) s + a C e (Cauchy, s the total stress unknowns, no prestress),
//    r = (1 - a) (e - D s).
// Derivatives are with respect to the point's own arguments (h as an independent Dim x Dim
// matrix, entries numbered i * Dim + j); the element driver (kernels/ElementDriver.hpp,
// mixedElement) applies the kinematics (dh for a nodal perturbation, the change of da and of
// the current gradients). Templated on the dimension, device-callable, no loops over nodes.
// Layer: kernels.
#pragma once

#include <kernels/PointPhysics.hpp>

namespace mixcon {

/// What a mixed point functor returns at one quadrature point (see the file comment). The
/// derivative members are filled only by evaluate<true>.
template <int Dim> struct MixedPointResponse {
  static constexpr int kSize = Voigt<Dim>::kSize;
  Mat<Dim, Dim> stress;                      ///< P, multiplies the test gradients
  Vector<kSize> compatibility;               ///< r, the stress equations' residual density
  Mat<Dim * Dim, Dim * Dim> dStressDGrad;    ///< d P_ij / d h_kl at (i Dim + j, k Dim + l)
  Mat<Dim * Dim, kSize> dStressDStress;      ///< d P_ij / d s_c at (i Dim + j, c)
  Mat<kSize, Dim * Dim> dCompatibilityDGrad; ///< d r_c / d h_kl at (c, k Dim + l)
  Mat<kSize, kSize> dCompatibilityDStress;   ///< d r_c / d s_k
};

namespace detail {
/// d(Voigt strain, engineering shear) / d h_kl of sym(A^T dh): symmetricProductTangent with
/// C = I (the Green-Lagrange strain with A = F, the Almansi strain with A = I - h).
template <int Dim>
KOKKOS_INLINE_FUNCTION Mat<Voigt<Dim>::kSize, Dim * Dim> strainVariation(const Mat<Dim, Dim> &a) {
  return symmetricProductTangent<Dim>(identity<Voigt<Dim>::kSize>(), a);
}
/// d r / d s = -(1 - a) D.
template <int N> KOKKOS_INLINE_FUNCTION Mat<N, N> scaledCompliance(const Mat<N, N> &d, double b1) {
  Mat<N, N> r{};
  for (int c = 0; c < N; ++c)
    for (int k = 0; k < N; ++k)
      r.m[c][k] = -b1 * d.m[c][k];
  return r;
}
} // namespace detail

/// The incremental (total-Lagrangian) Hellinger-Reissner point of the mixed model: h = du/dX on
/// the last converged configuration, s the stress increment S, tau the prestress (both Voigt).
/// kPrestress: the element driver gathers tau; kCurrentConfiguration: false (geometry on X).
template <int Dim> struct MixedIncrementPoint {
  static constexpr int kDim = Dim;
  static constexpr int kSize = Voigt<Dim>::kSize;
  static constexpr bool kPrestress = true;
  static constexpr bool kCurrentConfiguration = false;
  using Matrix = Mat<kSize, kSize>;

  Matrix c;       ///< Voigt stiffness C (the stabilization's law)
  Matrix d;       ///< Voigt compliance D
  double a = 0.0; ///< stabilization in [0, 1)

  /// Green-Lagrange strain (Voigt, engineering shear) of the increment: sym(h) + h^T h / 2.
  KOKKOS_INLINE_FUNCTION static Vector<kSize> strain(const Mat<Dim, Dim> &h) {
    Mat<Dim, Dim> f = h;
    for (int i = 0; i < Dim; ++i)
      f.m[i][i] += 1.0;
    return strainToVoigt<Dim>(SaintVenantKirchhoffPoint<Dim>::strain(f));
  }

  template <bool Tangent>
  KOKKOS_INLINE_FUNCTION MixedPointResponse<Dim>
  evaluate(const Mat<Dim, Dim> &h, const Vector<kSize> &s, const Vector<kSize> &tau) const {
    const double b1 = 1.0 - a;
    Mat<Dim, Dim> f = h;
    for (int i = 0; i < Dim; ++i)
      f.m[i][i] += 1.0;
    const Vector<kSize> e = strain(h);
    const Vector<kSize> ce = matvec(c, e), ds = matvec(d, s);
    Vector<kSize> sigma{};
    MixedPointResponse<Dim> out{};
    for (int k = 0; k < kSize; ++k) {
      sigma.v[k] = tau.v[k] + b1 * s.v[k] + a * ce.v[k];
      out.compatibility.v[k] = b1 * (e.v[k] - ds.v[k]);
    }
    const Mat<Dim, Dim> st = voigtToStress<Dim>(sigma);
    out.stress = matmul(f, st);
    if (!Tangent)
      return out;
    // dE/dh = sym(F^T dh); dSigma/dh = a C dE/dh; dP = dh Sigma + F dSigma.
    const Mat<kSize, Dim *Dim> de = detail::strainVariation<Dim>(f);
    const Mat<kSize, Dim *Dim> dsig = matmul(c, de);
    for (int k = 0; k < Dim; ++k)
      for (int l = 0; l < Dim; ++l) {
        Vector<kSize> dsv{};
        for (int v = 0; v < kSize; ++v)
          dsv.v[v] = a * dsig.m[v][k * Dim + l];
        const Mat<Dim, Dim> fds = matmul(f, voigtToStress<Dim>(dsv));
        for (int i = 0; i < Dim; ++i)
          for (int j = 0; j < Dim; ++j)
            out.dStressDGrad.m[i * Dim + j][k * Dim + l] =
                (i == k ? st.m[l][j] : 0.0) + fds.m[i][j];
      }
    // dP/ds_c = (1 - a) F T_c, T_c the symmetric unit tensor of Voigt component c.
    for (int v = 0; v < kSize; ++v) {
      const int r = Voigt<Dim>::row(v), q = Voigt<Dim>::col(v);
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) {
          double x = (j == q ? f.m[i][r] : 0.0);
          if (r != q && j == r)
            x += f.m[i][q];
          out.dStressDStress.m[i * Dim + j][v] = b1 * x;
        }
    }
    for (int v = 0; v < kSize; ++v)
      for (int kl = 0; kl < Dim * Dim; ++kl)
        out.dCompatibilityDGrad.m[v][kl] = b1 * de.m[v][kl];
    out.dCompatibilityDStress = detail::scaledCompliance(d, b1);
    return out;
  }
};

/// The current-configuration Hellinger-Reissner point of the mixed model (the default,
/// path-independent form): h = du/dx of the total displacement on the current configuration,
/// s the total Cauchy stress unknowns (Voigt), no prestress (tau is ignored).
/// kCurrentConfiguration: the element driver integrates over x = X + u and adds the change of
/// da and of the current gradients.
template <int Dim> struct MixedCurrentPoint {
  static constexpr int kDim = Dim;
  static constexpr int kSize = Voigt<Dim>::kSize;
  static constexpr bool kPrestress = false;
  static constexpr bool kCurrentConfiguration = true;
  using Matrix = Mat<kSize, kSize>;

  Matrix c;       ///< Voigt stiffness C (the stabilization's law)
  Matrix d;       ///< Voigt compliance D
  double a = 0.0; ///< stabilization in [0, 1)

  template <bool Tangent>
  KOKKOS_INLINE_FUNCTION MixedPointResponse<Dim>
  evaluate(const Mat<Dim, Dim> &h, const Vector<kSize> &s, const Vector<kSize> & = {}) const {
    const double b1 = 1.0 - a;
    const Vector<kSize> e = strainToVoigt<Dim>(AlmansiPoint<Dim>::strain(h));
    const Vector<kSize> ce = matvec(c, e), ds = matvec(d, s);
    Vector<kSize> sigma{};
    MixedPointResponse<Dim> out{};
    for (int k = 0; k < kSize; ++k) {
      sigma.v[k] = b1 * s.v[k] + a * ce.v[k];
      out.compatibility.v[k] = b1 * (e.v[k] - ds.v[k]);
    }
    out.stress = voigtToStress<Dim>(sigma);
    if (!Tangent)
      return out;
    // de/dh = sym((I - h)^T dh); dP/dh = a C de/dh (as a symmetric tensor).
    Mat<Dim, Dim> ih{};
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j)
        ih.m[i][j] = (i == j ? 1.0 : 0.0) - h.m[i][j];
    const Mat<kSize, Dim *Dim> de = detail::strainVariation<Dim>(ih);
    const Mat<kSize, Dim *Dim> dsig = matmul(c, de);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        const int v = Voigt<Dim>::index(i, j);
        for (int kl = 0; kl < Dim * Dim; ++kl)
          out.dStressDGrad.m[i * Dim + j][kl] = a * dsig.m[v][kl];
        for (int w = 0; w < kSize; ++w)
          out.dStressDStress.m[i * Dim + j][w] = w == v ? b1 : 0.0;
      }
    for (int v = 0; v < kSize; ++v)
      for (int kl = 0; kl < Dim * Dim; ++kl)
        out.dCompatibilityDGrad.m[v][kl] = b1 * de.m[v][kl];
    out.dCompatibilityDStress = detail::scaledCompliance(d, b1);
    return out;
  }
};

} // namespace mixcon
