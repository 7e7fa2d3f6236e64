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

namespace {
/// A and B of LameSphereSolution.
std::pair<double, double> lameSphereConstants(const LameSphereSolution &s) {
  const double a3 = s.a * s.a * s.a, b3 = s.b * s.b * s.b;
  return {(s.pi * a3 - s.po * b3) / (b3 - a3), (s.pi - s.po) * a3 * b3 / (b3 - a3)};
}
} // namespace

double LameSphereSolution::sigmaR(double r) const {
  const auto [ca, cb] = lameSphereConstants(*this);
  return ca - cb / (r * r * r);
}

double LameSphereSolution::sigmaTheta(double r) const {
  const auto [ca, cb] = lameSphereConstants(*this);
  return ca + cb / (2.0 * r * r * r);
}

double LameSphereSolution::radialDisplacement(double r) const {
  const auto [ca, cb] = lameSphereConstants(*this);
  return r * ((1.0 - 2.0 * nu) * ca + (1.0 + nu) * cb / (2.0 * r * r * r)) / e;
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
  // A 3D cylinder (lame_cylinder on a solid mesh) is held in z at its ends: plane strain.
  const bool planeStrain = p.model.analysis == PlaneAnalysis::PlaneStrain || p.mesh.dim() == 3;
  const Mesh &mesh = p.mesh;
  auto add = [&](const std::string &q, double computed, double reference, double scale) {
    const double err = std::abs(computed - reference) / scale;
    v.rows.push_back({q, computed, reference, err});
    v.passed = v.passed && err <= v.tolerance;
  };

  if (p.verification.type == "lame_cylinder" || p.verification.type == "lame_sphere") {
    const auto &s = p.verification;
    const bool sphere = s.type == "lame_sphere";
    const LameSolution cylinder{s.innerRadius,
                                s.outerRadius,
                                loadFactor * s.innerPressure,
                                loadFactor * s.outerPressure,
                                mat.youngs,
                                mat.poisson,
                                planeStrain};
    const LameSphereSolution ball{
        s.innerRadius, s.outerRadius, loadFactor * s.innerPressure, loadFactor * s.outerPressure,
        mat.youngs,    mat.poisson};
    const auto closed = [&](double r) {
      return sphere ? std::array<double, 3>{ball.radialDisplacement(r), ball.sigmaTheta(r),
                                            ball.sigmaR(r)}
                    : std::array<double, 3>{cylinder.radialDisplacement(r), cylinder.sigmaTheta(r),
                                            cylinder.sigmaR(r)};
    };
    v.title = std::string(sphere ? "Lame thick sphere (Timoshenko & Goodier, sec. 136)"
                                 : "Lame thick cylinder (Timoshenko & Goodier, sec. 28)") +
              ", a = " + std::to_string(s.innerRadius) + ", b = " + std::to_string(s.outerRadius);
    // The radius is measured in the first `rdim` coordinates: from the centre for the sphere, from
    // the z axis for the cylinder (in 2D and 3D).
    const int dim = mesh.dim(), ns = dim == 3 ? 6 : 3, rdim = sphere ? 3 : 2;
    for (double r0 : {s.innerRadius, s.outerRadius}) {
      double ur = 0.0, st = 0.0, sr = 0.0;
      int count = 0;
      for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
        double x[3] = {0.0, 0.0, 0.0}, r = 0.0;
        for (int i = 0; i < rdim; ++i) {
          x[i] = mesh.coordinate(n, i);
          r += x[i] * x[i];
        }
        r = std::sqrt(r);
        if (std::abs(r - r0) > 1e-6 * r0)
          continue;
        // The radial direction e = x / r; sigma_r = e . sigma e. The hoop stress is the mean of
        // the other normal stresses across the radius: (trace - sigma_r) / (rdim - 1) over the
        // first rdim axes (the sphere's two tangential ones are both sigma_t).
        const double *sv = &stress[static_cast<std::size_t>(ns) * n];
        double tensor[3][3] = {};
        for (int k = 0; k < ns; ++k) {
          const int i = dim == 3 ? Voigt<3>::row(k) : Voigt<2>::row(k);
          const int j = dim == 3 ? Voigt<3>::col(k) : Voigt<2>::col(k);
          tensor[i][j] = tensor[j][i] = sv[k];
        }
        double srr = 0.0, trace = 0.0, radial = 0.0;
        for (int i = 0; i < rdim; ++i) {
          trace += tensor[i][i];
          radial += u[static_cast<std::size_t>(dim) * n + i] * x[i] / r;
          for (int j = 0; j < rdim; ++j)
            srr += x[i] * tensor[i][j] * x[j] / (r * r);
        }
        ur += radial;
        sr += srr;
        st += (trace - srr) / (rdim - 1);
        ++count;
      }
      if (count == 0)
        throw InputError(p.file + ": verification: no mesh node lies on r = " + std::to_string(r0));
      const std::string at = r0 == s.innerRadius ? "r = a" : "r = b";
      const auto ref = closed(r0);
      const double pscale =
          std::max(std::abs(loadFactor * s.innerPressure), std::abs(loadFactor * s.outerPressure));
      add("radial displacement u_r(" + at + ")", ur / count, ref[0], std::abs(ref[0]));
      add("hoop stress sigma_theta(" + at + ")", st / count, ref[1], std::abs(ref[1]));
      add("radial stress sigma_r(" + at + ")", sr / count, ref[2], pscale);
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
