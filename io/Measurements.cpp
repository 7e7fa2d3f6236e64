// Measurement file, boundary check, angular interpolation and symmetrization (hybrid mode).
#include <io/Measurements.hpp>
#include <mesh/GmshReader.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>

namespace mixcon {

namespace {

std::string where(const std::string &name, int line) {
  return name + ":" + std::to_string(line) + ": ";
}

bool parseNumber(const std::string &cell, double &v) {
  try {
    std::size_t used = 0;
    v = std::stod(cell, &used);
    while (used < cell.size() && std::isspace(static_cast<unsigned char>(cell[used])))
      ++used;
    return used == cell.size() && std::isfinite(v);
  } catch (const std::exception &) {
    return false;
  }
}

/// Distance from p to the segment ab.
double segmentDistance(const double p[2], const double a[2], const double b[2]) {
  const double d[2] = {b[0] - a[0], b[1] - a[1]};
  const double len2 = d[0] * d[0] + d[1] * d[1];
  double t = len2 > 0.0 ? ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p[0] - a[0] - t * d[0], p[1] - a[1] - t * d[1]);
}

} // namespace

std::vector<MeasuredStep> parseMeasurements(const std::string &text, const std::string &name) {
  std::istringstream in(text);
  std::string row;
  int line = 0;
  std::vector<MeasuredStep> steps;
  bool header = false;
  while (std::getline(in, row)) {
    ++line;
    if (!row.empty() && row.back() == '\r')
      row.pop_back();
    if (row.find_first_not_of(" \t") == std::string::npos || row[0] == '#')
      continue;
    if (!header) {
      std::string compact;
      for (char c : row)
        if (!std::isspace(static_cast<unsigned char>(c)))
          compact += c;
      if (compact != "step,load,x,y,ux,uy")
        throw InputError(where(name, line) + "expected the header 'step,load,x,y,ux,uy', found '" +
                         clipValue(row) + "'");
      header = true;
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream ss(row);
    for (std::string c; std::getline(ss, c, ',');)
      cells.push_back(c);
    if (cells.size() != 6)
      throw InputError(where(name, line) + "expected 6 values (step,load,x,y,ux,uy), found " +
                       std::to_string(cells.size()));
    double v[6];
    for (int k = 0; k < 6; ++k)
      if (!parseNumber(cells[k], v[k]))
        throw InputError(where(name, line) + "value " + std::to_string(k + 1) + " ('" +
                         clipValue(cells[k]) + "') is not a finite number");
    // Compared before the cast: a double outside int's range does not convert.
    if (!(v[0] >= 1.0 && v[0] <= std::numeric_limits<int>::max()) || std::floor(v[0]) != v[0])
      throw InputError(where(name, line) + "step must be a positive integer");
    const int step = static_cast<int>(v[0]);
    if (steps.empty() || step != steps.back().step) {
      const int expected = steps.empty() ? 1 : steps.back().step + 1;
      if (step != expected)
        throw InputError(where(name, line) + "step " + std::to_string(step) +
                         " out of order: expected step " + std::to_string(expected) +
                         " (rows grouped by step, numbered 1, 2, ...)");
      steps.push_back({step, v[1], {}});
    } else if (v[1] != steps.back().load) {
      throw InputError(where(name, line) + "step " + std::to_string(step) + " has two loads (" +
                       cells[1] + " and " + std::to_string(steps.back().load) + ")");
    }
    steps.back().points.push_back({v[2], v[3], v[4], v[5], line});
  }
  if (!header)
    throw InputError(name + ": empty measurement file (expected the header 'step,load,x,y,ux,uy')");
  if (steps.empty())
    throw InputError(name + ": no measured points");
  for (const auto &s : steps)
    if (s.points.size() < 2)
      throw InputError(name + ": step " + std::to_string(s.step) +
                       " has fewer than 2 measured points");
  return steps;
}

std::vector<MeasuredStep> readMeasurements(const std::string &file) {
  return parseMeasurements(readInputFile(file, "measurement file"), file);
}

void checkNearBoundary(const Mesh &mesh, const std::string &boundary,
                       const std::vector<MeasuredStep> &steps, double maxDistance,
                       const std::string &file, bool mirrorY, double mirrorAxis) {
  const auto &edges = mesh.boundaries.at(boundary);
  const int npe = mesh.elementType == ElementType::Quad8 ? 3 : 2;
  std::vector<std::array<double, 4>> segments; // straight pieces through the edge nodes
  for (const auto &e : edges) {
    const LocalIndex a = mesh.edgeNode(e, 0), b = mesh.edgeNode(e, 1);
    if (npe == 3) {
      const LocalIndex m = mesh.edgeNode(e, 2);
      segments.push_back({mesh.x(a), mesh.y(a), mesh.x(m), mesh.y(m)});
      segments.push_back({mesh.x(m), mesh.y(m), mesh.x(b), mesh.y(b)});
    } else {
      segments.push_back({mesh.x(a), mesh.y(a), mesh.x(b), mesh.y(b)});
    }
  }
  for (const auto &s : steps)
    for (const auto &p : s.points) {
      double best = 1e300;
      const double q[2] = {p.x, p.y}, m[2] = {p.x, 2 * mirrorAxis - p.y};
      for (const auto &g : segments) {
        const double a[2] = {g[0], g[1]}, b[2] = {g[2], g[3]};
        best = std::min(best, segmentDistance(q, a, b));
        if (mirrorY)
          best = std::min(best, segmentDistance(m, a, b));
      }
      if (best > maxDistance) {
        std::ostringstream m;
        m << where(file, p.line) << "the measured point (" << p.x << ", " << p.y << ") lies "
          << best << " from boundary '" << boundary << "' (max_distance " << maxDistance
          << "): the measurements do not match the mesh";
        throw InputError(m.str());
      }
    }
}

AngularProfile::AngularProfile(const MeasuredStep &step, std::array<double, 2> center) {
  std::vector<std::array<double, 3>> p;
  for (const auto &m : step.points)
    p.push_back({std::atan2(m.y - center[1], m.x - center[0]), m.ux, m.uy});
  std::sort(p.begin(), p.end());
  for (const auto &q : p) {
    if (!angle_.empty() && q[0] - angle_.back() < 1e-12) {
      // Two points at the same angle: keep their mean.
      ux_.back() = 0.5 * (ux_.back() + q[1]);
      uy_.back() = 0.5 * (uy_.back() + q[2]);
      continue;
    }
    angle_.push_back(q[0]);
    ux_.push_back(q[1]);
    uy_.push_back(q[2]);
  }
  // All around: the wrap-around gap is no larger than twice the largest gap between points.
  double largest = 0.0;
  for (std::size_t k = 1; k < angle_.size(); ++k)
    largest = std::max(largest, angle_[k] - angle_[k - 1]);
  const double wrap = angle_.front() + 2 * M_PI - angle_.back();
  periodic_ = angle_.size() >= 3 && wrap <= 2.0 * largest + 1e-12;
}

bool AngularProfile::covers(double theta) const {
  const double tol = 1e-9;
  return periodic_ || (theta >= angle_.front() - tol && theta <= angle_.back() + tol) ||
         (theta + 2 * M_PI <= angle_.back() + tol) || (theta - 2 * M_PI >= angle_.front() - tol);
}

std::array<double, 2> AngularProfile::at(double theta) const {
  // Bring theta into [front, front + 2 pi) and locate its interval (wrapping when periodic).
  const std::size_t n = angle_.size();
  while (theta < angle_.front() - 1e-9)
    theta += 2 * M_PI;
  while (theta >= angle_.front() + 2 * M_PI - 1e-15)
    theta -= 2 * M_PI;
  if (theta <= angle_.front())
    return {ux_.front(), uy_.front()};
  const auto it = std::upper_bound(angle_.begin(), angle_.end(), theta);
  std::size_t i1 = static_cast<std::size_t>(it - angle_.begin()), i0 = i1 - 1;
  double a0 = angle_[i0], a1;
  if (i1 == n) {
    if (!periodic_ || theta <= angle_.back() + 1e-9)
      return {ux_.back(), uy_.back()};
    i1 = 0;
    a1 = angle_.front() + 2 * M_PI;
  } else {
    a1 = angle_[i1];
  }
  const double t = (theta - a0) / (a1 - a0);
  return {(1 - t) * ux_[i0] + t * ux_[i1], (1 - t) * uy_[i0] + t * uy_[i1]};
}

BoundaryValues boundaryValues(const Mesh &mesh, const std::vector<LocalIndex> &nodes,
                              const AngularProfile &profile, std::array<double, 2> center,
                              bool symmetrize, int step) {
  BoundaryValues out;
  double largest = 0.0, asym = 0.0;
  bool mirrored = true;
  for (LocalIndex n : nodes) {
    const double theta = std::atan2(mesh.y(n) - center[1], mesh.x(n) - center[0]);
    if (!profile.covers(theta)) {
      std::ostringstream m;
      m << "step " << step << ": boundary node " << (mesh.nodeIds.empty() ? n + 1 : mesh.nodeIds[n])
        << " at angle " << theta * 180.0 / M_PI
        << " deg lies outside the measured range: the measurements do not cover the boundary";
      throw InputError(m.str());
    }
    std::array<double, 2> u = profile.at(theta);
    largest = std::max(largest, std::hypot(u[0], u[1]));
    if (symmetrize && profile.covers(-theta)) {
      const std::array<double, 2> v = profile.at(-theta);
      asym = std::max(asym, std::hypot(u[0] - v[0], u[1] + v[1]));
      u = {0.5 * (u[0] + v[0]), 0.5 * (u[1] - v[1])};
    } else if (symmetrize) {
      mirrored = false;
    }
    out.nodes.push_back(n);
    out.theta.push_back(theta);
    out.ux.push_back(u[0]);
    out.uy.push_back(u[1]);
  }
  if (symmetrize && mirrored)
    out.asymmetry = largest > 0.0 ? asym / largest : 0.0;
  return out;
}

} // namespace mixcon
