// Small fixed-size tensor algebra for the element and point kernels of every dimension: matrices
// and vectors of compile-time size, the Voigt map between symmetric Dim x Dim tensors and their
// Dim(Dim+1)/2 components, and the field layout of a node's unknowns in the displacement and the
// mixed model. Everything is device-callable (no allocation, no exceptions, no std:: containers).
// Layer: core, the bottom one (every other layer may include it).
#pragma once

#include <core/Compat.hpp>

#include <cfloat>

namespace mixcon {

/// Dense R x C matrix of doubles, row-major, held by value (an aggregate: Mat<2, 2>{{{a, b},
/// {c, d}}}; Mat<R, C>{} is the zero matrix).
template <int R, int C> struct Mat {
  static_assert(R > 0 && C > 0, "a matrix has at least one row and one column");
  static constexpr int kRows = R;
  static constexpr int kCols = C;
  double m[R][C];
  KOKKOS_INLINE_FUNCTION double &operator()(int i, int j) { return m[i][j]; }
  KOKKOS_INLINE_FUNCTION const double &operator()(int i, int j) const { return m[i][j]; }
};

/// Column vector of N doubles held by value (Vector<N>{} is the zero vector).
template <int N> struct Vector {
  static_assert(N > 0, "a vector has at least one component");
  static constexpr int kSize = N;
  double v[N];
  KOKKOS_INLINE_FUNCTION double &operator[](int i) { return v[i]; }
  KOKKOS_INLINE_FUNCTION const double &operator[](int i) const { return v[i]; }
};

/// The N x N identity.
template <int N> KOKKOS_INLINE_FUNCTION Mat<N, N> identity() {
  Mat<N, N> r{};
  for (int i = 0; i < N; ++i)
    r.m[i][i] = 1.0;
  return r;
}

/// A^T.
template <int R, int C> KOKKOS_INLINE_FUNCTION Mat<C, R> transpose(const Mat<R, C> &a) {
  Mat<C, R> r{};
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j)
      r.m[j][i] = a.m[i][j];
  return r;
}

/// A B.
template <int R, int K, int C>
KOKKOS_INLINE_FUNCTION Mat<R, C> matmul(const Mat<R, K> &a, const Mat<K, C> &b) {
  Mat<R, C> r{};
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) {
      double s = 0.0;
      for (int k = 0; k < K; ++k)
        s += a.m[i][k] * b.m[k][j];
      r.m[i][j] = s;
    }
  return r;
}

/// A^T B (A is K x R).
template <int K, int R, int C>
KOKKOS_INLINE_FUNCTION Mat<R, C> matmulTN(const Mat<K, R> &a, const Mat<K, C> &b) {
  Mat<R, C> r{};
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) {
      double s = 0.0;
      for (int k = 0; k < K; ++k)
        s += a.m[k][i] * b.m[k][j];
      r.m[i][j] = s;
    }
  return r;
}

/// A B^T (B is C x K).
template <int R, int K, int C>
KOKKOS_INLINE_FUNCTION Mat<R, C> matmulNT(const Mat<R, K> &a, const Mat<C, K> &b) {
  Mat<R, C> r{};
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) {
      double s = 0.0;
      for (int k = 0; k < K; ++k)
        s += a.m[i][k] * b.m[j][k];
      r.m[i][j] = s;
    }
  return r;
}

/// A x.
template <int R, int C>
KOKKOS_INLINE_FUNCTION Vector<R> matvec(const Mat<R, C> &a, const Vector<C> &x) {
  Vector<R> y{};
  for (int i = 0; i < R; ++i) {
    double s = 0.0;
    for (int j = 0; j < C; ++j)
      s += a.m[i][j] * x.v[j];
    y.v[i] = s;
  }
  return y;
}

/// A^T x.
template <int R, int C>
KOKKOS_INLINE_FUNCTION Vector<C> matvecT(const Mat<R, C> &a, const Vector<R> &x) {
  Vector<C> y{};
  for (int j = 0; j < C; ++j) {
    double s = 0.0;
    for (int i = 0; i < R; ++i)
      s += a.m[i][j] * x.v[i];
    y.v[j] = s;
  }
  return y;
}

/// x . y.
template <int N> KOKKOS_INLINE_FUNCTION double inner(const Vector<N> &x, const Vector<N> &y) {
  double s = 0.0;
  for (int i = 0; i < N; ++i)
    s += x.v[i] * y.v[i];
  return s;
}

KOKKOS_INLINE_FUNCTION double determinant(const Mat<2, 2> &a) {
  return a.m[0][0] * a.m[1][1] - a.m[0][1] * a.m[1][0];
}

KOKKOS_INLINE_FUNCTION double determinant(const Mat<3, 3> &a) {
  const auto &m = a.m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) +
         m[0][1] * (m[1][2] * m[2][0] - m[1][0] * m[2][2]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/// Inverse of a 2x2 matrix by the adjugate; returns det(a). When det(a) == 0, `inv` is left
/// unchanged.
KOKKOS_INLINE_FUNCTION double inverse(const Mat<2, 2> &a, Mat<2, 2> &inv) {
  const double det = determinant(a);
  if (det == 0.0)
    return det;
  const double r = 1.0 / det;
  inv.m[0][0] = a.m[1][1] * r;
  inv.m[0][1] = -a.m[0][1] * r;
  inv.m[1][0] = -a.m[1][0] * r;
  inv.m[1][1] = a.m[0][0] * r;
  return det;
}

/// Inverse of a 3x3 matrix by the adjugate; returns det(a). When det(a) == 0, `inv` is left
/// unchanged.
KOKKOS_INLINE_FUNCTION double inverse(const Mat<3, 3> &a, Mat<3, 3> &inv) {
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

/// Cholesky factor L (lower triangular, A = L L^T) of a symmetric N x N matrix; only the lower
/// triangle of `a` is read. Returns false, leaving `l` partly written, when `a` is not positive
/// definite to working precision: a pivot is not finite or not larger than 16 eps times the
/// diagonal entry it came from (all significant digits cancelled).
template <int N> KOKKOS_INLINE_FUNCTION bool cholesky(const Mat<N, N> &a, Mat<N, N> &l) {
  for (int j = 0; j < N; ++j) {
    double d = a.m[j][j];
    for (int k = 0; k < j; ++k)
      d -= l.m[j][k] * l.m[j][k];
    // (the negated comparison also rejects NaN)
    if (!(d > 16.0 * DBL_EPSILON * a.m[j][j]) || !(d < DBL_MAX))
      return false;
    const double ljj = detail::sqrt(d);
    l.m[j][j] = ljj;
    for (int i = j + 1; i < N; ++i) {
      double s = a.m[i][j];
      for (int k = 0; k < j; ++k)
        s -= l.m[i][k] * l.m[j][k];
      l.m[i][j] = s / ljj;
    }
    for (int i = 0; i < j; ++i)
      l.m[i][j] = 0.0;
  }
  return true;
}

/// True when the symmetric matrix `a` (lower triangle read) is positive definite to working
/// precision (its Cholesky factorization succeeds).
template <int N> KOKKOS_INLINE_FUNCTION bool isSymmetricPositiveDefinite(const Mat<N, N> &a) {
  Mat<N, N> l{};
  return cholesky(a, l);
}

/// Inverse of a symmetric positive-definite N x N matrix by Cholesky (A^-1 = L^-T L^-1); only the
/// lower triangle of `a` is read and `inv` comes out exactly symmetric. Returns false, leaving
/// `inv` unchanged, when `a` is not positive definite (see cholesky). Meant for N <= 6 (Voigt
/// sizes); the cost is O(N^3) in registers.
template <int N> KOKKOS_INLINE_FUNCTION bool spdInverse(const Mat<N, N> &a, Mat<N, N> &inv) {
  Mat<N, N> l{};
  if (!cholesky(a, l))
    return false;
  // W = L^-1 (lower triangular), by forward substitution column by column.
  Mat<N, N> w{};
  for (int j = 0; j < N; ++j) {
    w.m[j][j] = 1.0 / l.m[j][j];
    for (int i = j + 1; i < N; ++i) {
      double s = 0.0;
      for (int k = j; k < i; ++k)
        s -= l.m[i][k] * w.m[k][j];
      w.m[i][j] = s / l.m[i][i];
    }
  }
  // A^-1 = W^T W, lower triangle then mirrored.
  for (int i = 0; i < N; ++i)
    for (int j = 0; j <= i; ++j) {
      double s = 0.0;
      for (int k = i; k < N; ++k)
        s += w.m[k][i] * w.m[k][j];
      inv.m[i][j] = s;
      inv.m[j][i] = s;
    }
  return true;
}

/// Voigt map of symmetric Dim x Dim tensors: component k <-> tensor entry (row(k), col(k)).
/// Order xx, yy, xy in 2D and xx, yy, zz, yz, xz, xy in 3D (normal components first, then the
/// shear components in the order of the missing index). Stresses map as they are; strains use the
/// engineering shear convention (gamma_ij = 2 eps_ij), so that sigma . eps is the work density.
template <int Dim> struct Voigt {
  static_assert(Dim == 2 || Dim == 3, "Voigt notation is defined here for 2D and 3D");
  static constexpr int kDim = Dim;
  static constexpr int kSize = Dim * (Dim + 1) / 2;

  /// Tensor row index of Voigt component k.
  KOKKOS_INLINE_FUNCTION static constexpr int row(int k) {
    return k < Dim ? k : (Dim == 2 ? 0 : (k == 3 ? 1 : 0));
  }
  /// Tensor column index of Voigt component k.
  KOKKOS_INLINE_FUNCTION static constexpr int col(int k) {
    return k < Dim ? k : (Dim == 2 ? 1 : (k == 5 ? 1 : 2));
  }
  /// Voigt component of the tensor entry (i, j) (either order).
  KOKKOS_INLINE_FUNCTION static constexpr int index(int i, int j) {
    return i == j ? i : (Dim == 2 ? 2 : 6 - i - j);
  }
  /// True for a shear (off-diagonal) component.
  KOKKOS_INLINE_FUNCTION static constexpr bool isShear(int k) { return k >= Dim; }
};

/// Voigt components of a symmetric stress tensor (the upper triangle is read).
template <int Dim>
KOKKOS_INLINE_FUNCTION Vector<Voigt<Dim>::kSize> stressToVoigt(const Mat<Dim, Dim> &t) {
  Vector<Voigt<Dim>::kSize> s{};
  for (int k = 0; k < Voigt<Dim>::kSize; ++k)
    s.v[k] = t.m[Voigt<Dim>::row(k)][Voigt<Dim>::col(k)];
  return s;
}

/// Symmetric stress tensor of Voigt components.
template <int Dim>
KOKKOS_INLINE_FUNCTION Mat<Dim, Dim> voigtToStress(const Vector<Voigt<Dim>::kSize> &s) {
  Mat<Dim, Dim> t{};
  for (int k = 0; k < Voigt<Dim>::kSize; ++k) {
    t.m[Voigt<Dim>::row(k)][Voigt<Dim>::col(k)] = s.v[k];
    t.m[Voigt<Dim>::col(k)][Voigt<Dim>::row(k)] = s.v[k];
  }
  return t;
}

/// Voigt components of a symmetric strain tensor, engineering shear (gamma = 2 eps_ij; the upper
/// triangle is read).
template <int Dim>
KOKKOS_INLINE_FUNCTION Vector<Voigt<Dim>::kSize> strainToVoigt(const Mat<Dim, Dim> &t) {
  Vector<Voigt<Dim>::kSize> e{};
  for (int k = 0; k < Voigt<Dim>::kSize; ++k)
    e.v[k] = (Voigt<Dim>::isShear(k) ? 2.0 : 1.0) * t.m[Voigt<Dim>::row(k)][Voigt<Dim>::col(k)];
  return e;
}

/// Symmetric strain tensor of Voigt components with engineering shear.
template <int Dim>
KOKKOS_INLINE_FUNCTION Mat<Dim, Dim> voigtToStrain(const Vector<Voigt<Dim>::kSize> &e) {
  Mat<Dim, Dim> t{};
  for (int k = 0; k < Voigt<Dim>::kSize; ++k) {
    const double x = (Voigt<Dim>::isShear(k) ? 0.5 : 1.0) * e.v[k];
    t.m[Voigt<Dim>::row(k)][Voigt<Dim>::col(k)] = x;
    t.m[Voigt<Dim>::col(k)][Voigt<Dim>::row(k)] = x;
  }
  return t;
}

/// Unknowns of one node in the two discretizations of the report: the displacement model carries
/// the Dim displacement components; the mixed (Hellinger-Reissner) model carries them followed by
/// the Voigt stress components (2D: u, v, Sxx, Syy, Sxy; 3D: u, v, w, Sxx, Syy, Szz, Syz, Sxz,
/// Sxy), interleaved node by node.
template <int Dim> struct FieldLayout {
  static_assert(Dim == 2 || Dim == 3, "field layouts exist for 2D and 3D");
  static constexpr int kDim = Dim;
  /// Displacement components per node.
  static constexpr int kNumDisplacements = Dim;
  /// Stress components per node (Voigt size).
  static constexpr int kNumStresses = Voigt<Dim>::kSize;
  /// Unknowns per node of the displacement model.
  static constexpr int kDisplacementUnknowns = kNumDisplacements;
  /// Unknowns per node of the mixed model.
  static constexpr int kMixedUnknowns = kNumDisplacements + kNumStresses;
  /// Offset of the displacement components inside a node's unknowns (both models).
  static constexpr int kDisplacementOffset = 0;
  /// Offset of the stress components inside a node's unknowns (mixed model).
  static constexpr int kStressOffset = kNumDisplacements;

  /// Unknown of displacement component c of node `node` in the displacement model.
  KOKKOS_INLINE_FUNCTION static constexpr int displacementDof(int node, int c) {
    return node * kDisplacementUnknowns + kDisplacementOffset + c;
  }
  /// Unknown of displacement component c of node `node` in the mixed model.
  KOKKOS_INLINE_FUNCTION static constexpr int mixedDisplacementDof(int node, int c) {
    return node * kMixedUnknowns + kDisplacementOffset + c;
  }
  /// Unknown of Voigt stress component c of node `node` in the mixed model.
  KOKKOS_INLINE_FUNCTION static constexpr int mixedStressDof(int node, int c) {
    return node * kMixedUnknowns + kStressOffset + c;
  }
};

} // namespace mixcon
