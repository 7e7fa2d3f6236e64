// How far one array is from a reference, the two measures the tests compare with. Tests only.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace mixcon::test {

/// max_i |a_i - ref_i| / max_i |ref_i| (INFINITY where the sizes differ or ref is empty).
inline double maxRelativeDifference(const std::vector<double> &a, const std::vector<double> &ref) {
  if (a.size() != ref.size() || ref.empty())
    return INFINITY;
  double d = 0.0, scale = 1e-300;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - ref[i]));
    scale = std::max(scale, std::abs(ref[i]));
  }
  return d / scale;
}

/// ||a - ref||_2 / ||ref||_2 (INFINITY where the sizes differ or ref is empty).
inline double relativeDifference2(const std::vector<double> &a, const std::vector<double> &ref) {
  if (a.size() != ref.size() || ref.empty())
    return INFINITY;
  double d = 0.0, n = 1e-300;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d += (a[i] - ref[i]) * (a[i] - ref[i]);
    n += ref[i] * ref[i];
  }
  return std::sqrt(d / n);
}

} // namespace mixcon::test
