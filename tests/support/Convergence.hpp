// Convergence studies of the validation suite: two error measures at successive refinements,
// printed with their rates, and the expectations every study makes of them.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

namespace mixcon::test {

/// The (displacement, stress) errors at refinement levels 0 .. levels - 1 (`errors(level)`, each
/// level halving the mesh size), printed as "  <what> <label(level)>: displacement error ...,
/// stress error ... (rates ..., ...)" with the rates log2(e_(l-1) / e_l). Expects every refinement
/// to reduce both errors and the last two rates to exceed `lastRates`. Returns the finest errors.
inline std::array<double, 2>
expectConvergence(const std::string &what, int levels, const std::function<std::string(int)> &label,
                  const std::function<std::array<double, 2>(int)> &errors,
                  const std::array<double, 2> &lastRates) {
  std::array<double, 2> previous{};
  for (int level = 0; level < levels; ++level) {
    const std::array<double, 2> err = errors(level);
    std::printf("  %s %s: displacement error %.3e, stress error %.3e", what.c_str(),
                label(level).c_str(), err[0], err[1]);
    if (level > 0) {
      const double ru = std::log2(previous[0] / err[0]), rs = std::log2(previous[1] / err[1]);
      std::printf(" (rates %.2f, %.2f)", ru, rs);
      EXPECT_LT(err[0], previous[0]) << what << " " << label(level);
      EXPECT_LT(err[1], previous[1]) << what << " " << label(level);
      if (level == levels - 1) {
        EXPECT_GT(ru, lastRates[0]) << what << ": displacement rate";
        EXPECT_GT(rs, lastRates[1]) << what << ": stress rate";
      }
    }
    std::printf("\n");
    previous = err;
  }
  return previous;
}

} // namespace mixcon::test
