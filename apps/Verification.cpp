// Closed-form comparisons for the verification section of problem files.
#include <apps/Verification.hpp>
#include <io/Results.hpp>

#include <cmath>
#include <iomanip>
#include <sstream>
#include <utility>

namespace mixcon {

namespace {
/// The constants A and B of sigma_r = A - B/r^2, sigma_theta = A + B/r^2.
std::pair<double, double> lameConstants(const LameSolution &s) {
  const double a2 = s.a * s.a, b2 = s.b * s.b;
  return {(s.pi * a2 - s.po * b2) / (b2 - a2), (s.pi - s.po) * a2 * b2 / (b2 - a2)};
}
} // namespace

double LameSolution::sigmaR(double r) const {
  const auto [ca, cb] = lameConstants(*this);
  return ca - cb / (r * r);
}

double LameSolution::sigmaTheta(double r) const {
  const auto [ca, cb] = lameConstants(*this);
  return ca + cb / (r * r);
}

double LameSolution::radialDisplacement(double r) const {
  const auto [ca, cb] = lameConstants(*this);
  if (planeStrain)
    return (1.0 + nu) / e * ((1.0 - 2.0 * nu) * ca * r + cb / r);
  return ((1.0 - nu) * ca * r + (1.0 + nu) * cb / r) / e;
}

std::array<double, 3> KirschSolution::stress(double x, double y) const {
  const double r = std::hypot(x, y), t = std::atan2(y, x), q = a * a / (r * r);
  const double c = std::cos(2 * t), sn = std::sin(2 * t);
  const double srr = s / 2 * (1 - q) + s / 2 * (1 - 4 * q + 3 * q * q) * c;
  const double stt = s / 2 * (1 + q) - s / 2 * (1 + 3 * q * q) * c;
  const double srt = -s / 2 * (1 + 2 * q - 3 * q * q) * sn;
  const double ct = std::cos(t), st = std::sin(t);
  return {srr * ct * ct + stt * st * st - 2 * srt * st * ct,
          srr * st * st + stt * ct * ct + 2 * srt * st * ct,
          (srr - stt) * st * ct + srt * (ct * ct - st * st)};
}

std::array<double, 2> KirschSolution::displacement(double x, double y) const {
  const double r = std::hypot(x, y), t = std::atan2(y, x);
  const double k = planeStrain ? 3 - 4 * nu : (3 - nu) / (1 + nu), g = e / (2 * (1 + nu));
  const double a2 = a * a, a4 = a2 * a2, f = s / (8 * g);
  const double ur = f * ((k - 1) * r + 2 * a2 / r +
                         (2 * r + 2 * (k + 1) * a2 / r - 2 * a4 / (r * r * r)) * std::cos(2 * t));
  const double ut = f * (-2 * r + 2 * (1 - k) * a2 / r - 2 * a4 / (r * r * r)) * std::sin(2 * t);
  return {ur * std::cos(t) - ut * std::sin(t), ur * std::sin(t) + ut * std::cos(t)};
}

double timoshenkoTipDeflection(double p, double l, double h, double t, double e, double nu,
                               bool planeStrain) {
  if (planeStrain) {
    e = e / (1.0 - nu * nu);
    nu = nu / (1.0 - nu);
  }
  const double i = t * h * h * h / 12.0, area = t * h, g = e / (2.0 * (1.0 + nu));
  return p * l * l * l / (3.0 * e * i) + p * l / (5.0 / 6.0 * g * area);
}

std::string VerificationResult::table() const {
  std::ostringstream s;
  s << title << "\n";
  s << "  " << std::left << std::setw(34) << "quantity" << std::right << std::setw(15) << "mixcon"
    << std::setw(15) << "closed form" << std::setw(12) << "rel. error"
    << "\n";
  for (const auto &r : rows)
    s << "  " << std::left << std::setw(34) << r.quantity << std::right << std::setw(15)
      << std::setprecision(6) << r.computed << std::setw(15) << r.reference << std::setw(11)
      << std::setprecision(3) << 100.0 * r.relativeError << "%\n";
  s << "  verification " << (passed ? "PASSED" : "FAILED") << " (tolerance " << 100.0 * tolerance
    << "%)\n";
  return s.str();
}

std::string VerificationResult::json() const {
  std::ostringstream s;
  s << std::setprecision(10) << "{\"title\": " << jsonString(title)
    << ", \"tolerance\": " << tolerance << ", \"passed\": " << (passed ? "true" : "false")
    << ", \"rows\": [";
  for (std::size_t i = 0; i < rows.size(); ++i)
    s << (i ? ", " : "") << "{\"quantity\": " << jsonString(rows[i].quantity)
      << ", \"computed\": " << rows[i].computed << ", \"reference\": " << rows[i].reference
      << ", \"relative_error\": " << rows[i].relativeError << "}";
  s << "]}";
  return s.str();
}

VerificationResult verify(const Problem &p, const std::vector<double> &u,
                          const std::vector<double> &stress, double loadFactor) {
  VerificationResult v;
  v.tolerance = p.verification.tolerance;
  const auto &mat = p.materials.front();
  const bool planeStrain = p.model.analysis == PlaneAnalysis::PlaneStrain;
  const Mesh &mesh = p.mesh;
  auto add = [&](const std::string &q, double computed, double reference, double scale) {
    const double err = std::abs(computed - reference) / scale;
    v.rows.push_back({q, computed, reference, err});
    v.passed = v.passed && err <= v.tolerance;
  };

  if (p.verification.type == "lame_cylinder") {
    const auto &s = p.verification;
    const LameSolution lame{s.innerRadius,
                            s.outerRadius,
                            loadFactor * s.innerPressure,
                            loadFactor * s.outerPressure,
                            mat.youngs,
                            mat.poisson,
                            planeStrain};
    v.title = "Lame thick cylinder (Timoshenko & Goodier, sec. 28), a = " +
              std::to_string(s.innerRadius) + ", b = " + std::to_string(s.outerRadius);
    for (double r0 : {s.innerRadius, s.outerRadius}) {
      double ur = 0.0, st = 0.0, sr = 0.0;
      int count = 0;
      for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
        const double x = mesh.x(n), y = mesh.y(n), r = std::hypot(x, y);
        if (std::abs(r - r0) > 1e-6 * r0)
          continue;
        const double c = x / r, sn = y / r;
        const double sxx = stress[3 * n], syy = stress[3 * n + 1], sxy = stress[3 * n + 2];
        ur += u[2 * n] * c + u[2 * n + 1] * sn;
        sr += sxx * c * c + syy * sn * sn + 2.0 * sxy * c * sn;
        st += sxx * sn * sn + syy * c * c - 2.0 * sxy * c * sn;
        ++count;
      }
      if (count == 0)
        throw InputError(p.file + ": verification: no mesh node lies on r = " + std::to_string(r0));
      const std::string at = r0 == s.innerRadius ? "r = a" : "r = b";
      const double pscale = std::max(std::abs(lame.pi), std::abs(lame.po));
      add("radial displacement u_r(" + at + ")", ur / count, lame.radialDisplacement(r0),
          std::abs(lame.radialDisplacement(r0)));
      add("hoop stress sigma_theta(" + at + ")", st / count, lame.sigmaTheta(r0),
          std::abs(lame.sigmaTheta(r0)));
      add("radial stress sigma_r(" + at + ")", sr / count, lame.sigmaR(r0), pscale);
    }
  } else if (p.verification.type == "cantilever") {
    const auto &s = p.verification;
    const auto nodes = mesh.nodesOf(s.tipNodeSet);
    const int dim = mesh.dim();
    double tip = 0.0;
    for (LocalIndex n : nodes)
      tip += u[dim * static_cast<std::size_t>(n) + 1];
    tip /= static_cast<double>(nodes.size());
    // 3D: a rectangular section of `width` (z) x `height` (y), neither plane stress nor strain.
    const double ref = timoshenkoTipDeflection(loadFactor * s.load, s.length, s.height,
                                               dim == 3 ? s.width : p.model.thickness, mat.youngs,
                                               mat.poisson, dim == 2 && planeStrain);
    v.title = "Cantilever tip deflection vs Timoshenko beam theory (kappa = 5/6)";
    add("tip deflection (mean over '" + s.tipNodeSet + "')", tip, ref, std::abs(ref));
  }
  return v;
}

} // namespace mixcon
