// The plain host reference of the mixed model's nonlinear element kernels: the two hand-written
// 2D element loops (5 unknowns per node, [2][2] arrays, the Hellinger-Reissner physics written
// inline) that kernels/Nonlinear.hpp had before mixedIncrementElement and mixedCurrentElement
// went through the generic element driver (kernels/ElementDriver.hpp: mixedElement with the
// point laws of kernels/MixedPointPhysics.hpp). Kept verbatim (renamed, run on the host with
// HostSpace views) so that tests compare the driver against them (tests/unit/test_mixed_point.cpp).
#pragma once

#include <kernels/Nonlinear.hpp>

namespace mixcon::test {

/// Mixed model, element e: the incremental Hellinger-Reissner residual ge (5 per node: G_u x, y,
/// G_S xx, yy, xy; without external loads) at increment (u, S) from configuration c1 (d.mesh)
/// with nodal prestress tau, and when `Tangent` its Jacobian ke. With stabilization a > 0 the
/// equilibrium stress is tau + (1 - a) S + a C E(u) and the stress equations are scaled by
/// (1 - a): the nonlinear form of the linear model's a Kd + (1 - a) K12 M^-1 K12^T (a = 0: the
/// report's model). Returns false for an inverted element (in c1 or in the incremented
/// configuration).
template <class Elem, bool Tangent, class MemorySpace>
inline bool referenceMixedIncrementElement(const MixedElementData<MemorySpace> &d,
                                           const Kokkos::View<const double *, MemorySpace> &tau,
                                           const Kokkos::View<const double *, MemorySpace> &x,
                                           double a, LocalIndex e,
                                           double (&ge)[5 * Elem::kNumNodes],
                                           double (&ke)[5 * Elem::kNumNodes][5 * Elem::kNumNodes]) {
  constexpr int n = Elem::kNumNodes;
  double xe[n][2], ue[n][2], se[n][3], te[n][3];
  detail::gatherCoordinates<Elem>(d.mesh, e, xe);
  for (int p = 0; p < n; ++p) {
    const LocalIndex k = d.mesh.connectivity(e, p);
    for (int i = 0; i < 2; ++i)
      ue[p][i] = x(5 * k + i);
    for (int c = 0; c < 3; ++c) {
      se[p][c] = x(5 * k + 2 + c);
      te[p][c] = tau(3 * k + c);
    }
  }
  const PlaneMatrix dm = d.compliance(d.material(e));
  const PlaneMatrix cm = d.stiffness(d.material(e));
  const double b1 = 1.0 - a;
  bool valid = true;
  detail::clearElement<Tangent>(ge, ke);
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double xi, eta, w, sh[n], dn[n][2], g[n][2], h[2][2];
    Elem::quadraturePoint(q, xi, eta, w);
    Elem::shape(xi, eta, sh, dn);
    const double det = physicalGradients<Elem>(xe, dn, g);
    const double jw = d.thickness * w * det;
    detail::nodalGradient<n>(ue, g, h);
    const double f[2][2] = {{1.0 + h[0][0], h[0][1]}, {h[1][0], 1.0 + h[1][1]}};
    if (!(det > 0.0) || !(f[0][0] * f[1][1] - f[0][1] * f[1][0] > 0.0))
      valid = false;
    double sv[3] = {}, tv[3] = {};
    for (int p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c) {
        sv[c] += sh[p] * se[p][c];
        tv[c] += sh[p] * te[p][c];
      }
    // Green-Lagrange strain of the increment, Voigt (xx, yy, 2 xy), and C E for the
    // stabilization.
    const double ev[3] = {h[0][0] + 0.5 * (h[0][0] * h[0][0] + h[1][0] * h[1][0]),
                          h[1][1] + 0.5 * (h[0][1] * h[0][1] + h[1][1] * h[1][1]),
                          h[0][1] + h[1][0] + h[0][0] * h[0][1] + h[1][0] * h[1][1]};
    double ce[3], r[3];
    for (int c = 0; c < 3; ++c) {
      ce[c] = cm.m[c][0] * ev[0] + cm.m[c][1] * ev[1] + cm.m[c][2] * ev[2];
      r[c] = b1 * (ev[c] - (dm.m[c][0] * sv[0] + dm.m[c][1] * sv[1] + dm.m[c][2] * sv[2]));
    }
    double sig[3];
    for (int c = 0; c < 3; ++c)
      sig[c] = tv[c] + b1 * sv[c] + a * ce[c];
    const double st[2][2] = {{sig[0], sig[2]}, {sig[2], sig[1]}};
    double fs[2][2]; // (F Sigma)_ik
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 2; ++k)
        fs[i][k] = f[i][0] * st[0][k] + f[i][1] * st[1][k];
    for (int p = 0; p < n; ++p) {
      for (int i = 0; i < 2; ++i)
        ge[5 * p + i] += jw * (fs[i][0] * g[p][0] + fs[i][1] * g[p][1]);
      for (int c = 0; c < 3; ++c)
        ge[5 * p + 2 + c] += jw * sh[p] * r[c];
    }
    if constexpr (Tangent) { // the tangent terms (a plain if leaves dead code: nvcc warns)
      // dE(voigt)/du_(p,i) = bl[p][i][c]: (F_i0 g_p0, F_i1 g_p1, F_i0 g_p1 + F_i1 g_p0).
      double bl[n][2][3];
      for (int p = 0; p < n; ++p)
        for (int i = 0; i < 2; ++i) {
          bl[p][i][0] = f[i][0] * g[p][0];
          bl[p][i][1] = f[i][1] * g[p][1];
          bl[p][i][2] = f[i][0] * g[p][1] + f[i][1] * g[p][0];
        }
      for (int p = 0; p < n; ++p) {
        const double gp0 = st[0][0] * g[p][0] + st[0][1] * g[p][1];
        const double gp1 = st[1][0] * g[p][0] + st[1][1] * g[p][1];
        double cb[2][3]; // a C bl[p][i]
        for (int i = 0; i < 2; ++i)
          for (int c = 0; c < 3; ++c)
            cb[i][c] = a * (cm.m[c][0] * bl[p][i][0] + cm.m[c][1] * bl[p][i][1] +
                            cm.m[c][2] * bl[p][i][2]);
        for (int b = 0; b < n; ++b) {
          const double kg = jw * (gp0 * g[b][0] + gp1 * g[b][1]);
          ke[5 * p][5 * b] += kg;
          ke[5 * p + 1][5 * b + 1] += kg;
          if (a != 0.0)
            for (int i = 0; i < 2; ++i)
              for (int m = 0; m < 2; ++m)
                ke[5 * p + i][5 * b + m] +=
                    jw * (cb[i][0] * bl[b][m][0] + cb[i][1] * bl[b][m][1] + cb[i][2] * bl[b][m][2]);
          for (int i = 0; i < 2; ++i)
            for (int c = 0; c < 3; ++c) {
              const double v = jw * b1 * bl[p][i][c] * sh[b];
              ke[5 * p + i][5 * b + 2 + c] += v;
              ke[5 * b + 2 + c][5 * p + i] += v;
            }
          for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
              ke[5 * p + 2 + c][5 * b + 2 + k] -= jw * b1 * sh[p] * sh[b] * dm.m[c][k];
        }
      }
    }
  }
  return valid;
}

/// Mixed model in the current configuration (the default form, path independent): unknowns the
/// total displacement u and the nodal Cauchy stress tau (5 per node in x), reference geometry
/// d.mesh, current x = X + u. Residual ge: G_u = t int B(x)^T [(1 - a) tau + a C e(u)] da,
/// G_S = (1 - a) t int psi (e(u) - D tau) da with e the Almansi strain of the total
/// displacement (the displacement model's law, imposed weakly); Jacobian ke exact (not
/// symmetric). At u = 0 it is the linear model; its Newton step from any state is Eq. (30) with
/// the 2nd Piola-Kirchhoff increment pushed forward to first order (docs/theory.md).
template <class Elem, bool Tangent, class MemorySpace>
inline bool referenceMixedCurrentElement(const MixedElementData<MemorySpace> &d,
                                         const Kokkos::View<const double *, MemorySpace> &x,
                                         double a, LocalIndex e, double (&ge)[5 * Elem::kNumNodes],
                                         double (&ke)[5 * Elem::kNumNodes][5 * Elem::kNumNodes]) {
  constexpr int n = Elem::kNumNodes;
  double xe[n][2], ue[n][2], te[n][3];
  for (int p = 0; p < n; ++p) {
    const LocalIndex k = d.mesh.connectivity(e, p);
    for (int i = 0; i < 2; ++i) {
      ue[p][i] = x(5 * k + i);
      xe[p][i] = d.mesh.coordinates(k, i) + ue[p][i];
    }
    for (int c = 0; c < 3; ++c)
      te[p][c] = x(5 * k + 2 + c);
  }
  const PlaneMatrix dm = d.compliance(d.material(e));
  const PlaneMatrix cm = d.stiffness(d.material(e));
  const double b1 = 1.0 - a;
  bool valid = true;
  detail::clearElement<Tangent>(ge, ke);
  for (int q = 0; q < Elem::kNumQp; ++q) {
    double sh[n], g[n][2], h[2][2], es[2][2], sa[2][2]; // sa = C e, the stabilization's stress
    const double jw =
        detail::almansiPoint<Elem>(q, xe, ue, cm, d.thickness, sh, g, h, es, sa, valid);
    double tv[3] = {};
    for (int p = 0; p < n; ++p)
      for (int c = 0; c < 3; ++c)
        tv[c] += sh[p] * te[p][c];
    const double ev[3] = {es[0][0], es[1][1], 2.0 * es[0][1]};
    double r[3];
    for (int c = 0; c < 3; ++c)
      r[c] = ev[c] - (dm.m[c][0] * tv[0] + dm.m[c][1] * tv[1] + dm.m[c][2] * tv[2]);
    const double t[2][2] = {{tv[0], tv[2]}, {tv[2], tv[1]}};
    double st[2][2]; // equilibrium stress (1 - a) tau + a C e
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        st[i][j] = b1 * t[i][j] + a * sa[i][j];
    for (int p = 0; p < n; ++p) {
      for (int i = 0; i < 2; ++i)
        ge[5 * p + i] += jw * (st[i][0] * g[p][0] + st[i][1] * g[p][1]);
      for (int c = 0; c < 3; ++c)
        ge[5 * p + 2 + c] += jw * b1 * sh[p] * r[c];
    }
    if constexpr (Tangent) { // the tangent terms (a plain if leaves dead code: nvcc warns)
      for (int b = 0; b < n; ++b)
        for (int m = 0; m < 2; ++m) {
          // Perturbation delta u_b = unit vector m: d(da) = da g_bm, d g_aj = -g_am g_bj.
          double de[2][2], ds[2][2];
          detail::almansiVariation(g[b], m, es, de);
          detail::stressFromStrainTensor(cm, de, ds);
          const double dev[3] = {de[0][0], de[1][1], 2.0 * de[0][1]};
          for (int p = 0; p < n; ++p) {
            for (int i = 0; i < 2; ++i) {
              double v = 0.0;
              for (int j = 0; j < 2; ++j)
                v += a * ds[i][j] * g[p][j] + st[i][j] * (g[p][j] * g[b][m] - g[p][m] * g[b][j]);
              ke[5 * p + i][5 * b + m] += jw * v;
            }
            for (int c = 0; c < 3; ++c)
              ke[5 * p + 2 + c][5 * b + m] += jw * b1 * sh[p] * (dev[c] + r[c] * g[b][m]);
          }
        }
      for (int p = 0; p < n; ++p)
        for (int b = 0; b < n; ++b) {
          const double v = jw * b1 * sh[b];
          // d G_u(p, i) / d tau(b, c): B^L of node p times psi_b.
          ke[5 * p][5 * b + 2] += v * g[p][0];
          ke[5 * p][5 * b + 4] += v * g[p][1];
          ke[5 * p + 1][5 * b + 3] += v * g[p][1];
          ke[5 * p + 1][5 * b + 4] += v * g[p][0];
          for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
              ke[5 * p + 2 + c][5 * b + 2 + k] -= jw * b1 * sh[p] * sh[b] * dm.m[c][k];
        }
    }
  }
  return valid;
}

} // namespace mixcon::test
