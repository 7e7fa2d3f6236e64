// Closed-form references that a problem file can ask to be compared with its results
// (verification: {type: lame_cylinder | cantilever, ...}); the comparison is printed and stored in
// summary.json. Data flow: apps (after the solve).
#pragma once

#include <io/Problem.hpp>

#include <array>
#include <string>
#include <vector>

namespace mixcon {

struct VerificationRow {
  std::string quantity;
  double computed = 0.0;
  double reference = 0.0;
  double relativeError = 0.0;
};

struct VerificationResult {
  std::string title;
  std::vector<VerificationRow> rows;
  double tolerance = 0.0;
  bool passed = true;
  std::string table() const; ///< human-readable comparison
  std::string json() const;
};

/// Lame thick-walled cylinder under inner/outer pressure (Timoshenko & Goodier, Theory of
/// Elasticity, 3rd ed., section 28): sigma_r = A - B/r^2, sigma_theta = A + B/r^2 with
/// A = (p_i a^2 - p_o b^2)/(b^2 - a^2), B = (p_i - p_o) a^2 b^2 / (b^2 - a^2).
struct LameSolution {
  double a, b, pi, po, e, nu;
  bool planeStrain;
  double sigmaR(double r) const;
  double sigmaTheta(double r) const;
  double radialDisplacement(double r) const;
};

/// Thick-walled sphere a <= r <= b under internal pressure pi and external pressure po
/// (Timoshenko & Goodier, Theory of Elasticity, sec. 136): with A = (pi a^3 - po b^3) / (b^3 - a^3)
/// and B = (pi - po) a^3 b^3 / (b^3 - a^3), sigma_r = A - B / r^3, sigma_t = A + B / (2 r^3) (hoop,
/// both tangential directions), u_r = r [(1 - 2 nu) A + (1 + nu) B / (2 r^3)] / E.
struct LameSphereSolution {
  double a, b, pi, po, e, nu;
  double sigmaR(double r) const;
  double sigmaTheta(double r) const;
  double radialDisplacement(double r) const;
};

/// Kirsch (1898): an infinite plate with a circular hole of radius a at the origin under remote
/// uniaxial tension S along x (Timoshenko & Goodier, Theory of Elasticity, sec. 35); the stress
/// concentration sigma_xx(0, a) = 3 S. Displacements by integrating the strains (checked
/// symbolically): 8 G u_r = S [(k-1) r + 2a^2/r + (2r + 2(k+1) a^2/r - 2a^4/r^3) cos 2t],
/// 8 G u_t = S [-2r + 2(1-k) a^2/r - 2a^4/r^3] sin 2t, k = (3-nu)/(1+nu) (plane stress) or
/// 3 - 4 nu (plane strain).
struct KirschSolution {
  double a, s, e, nu;
  bool planeStrain;
  std::array<double, 3> stress(double x, double y) const; ///< xx, yy, xy
  std::array<double, 2> displacement(double x, double y) const;
};

/// Timoshenko beam: tip deflection P L^3 / (3 E I) + P L / (kappa G A), kappa = 5/6, for a
/// cantilever of length L, depth h, thickness t under an end load P (plane strain uses
/// E / (1 - nu^2) and nu / (1 - nu)).
double timoshenkoTipDeflection(double p, double l, double h, double t, double e, double nu,
                               bool planeStrain);

/// Compares nodal results of the last step (displacement N x 2, stress N x 3, at `loadFactor`)
/// with the closed form named in problem.verification.
VerificationResult verify(const Problem &problem, const std::vector<double> &displacement,
                          const std::vector<double> &stress, double loadFactor);

} // namespace mixcon
