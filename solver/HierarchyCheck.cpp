#include <solver/HierarchyCheck.hpp>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace mixcon::detail {

void DiagonalRange::add(double aii) {
  ++rows;
  if (!(aii > 0.0) || !std::isfinite(aii)) {
    improper = true;
    return;
  }
  smallest = std::min(smallest, aii);
  largest = std::max(largest, aii);
}

std::string unsoundDiagonals(const std::vector<DiagonalRange> &levels) {
  if (levels.empty() || levels[0].rows == 0 || levels[0].improper)
    return {};
  const double fine = levels[0].largest / levels[0].smallest;
  for (std::size_t l = 1; l < levels.size(); ++l) {
    const DiagonalRange &d = levels[l];
    if (d.rows == 0)
      continue;
    if (d.improper)
      return "has a zero, negative or non-finite diagonal entry on level " + std::to_string(l);
    if (!(d.largest <= kUnsoundSpreadGrowth * fine * d.smallest)) {
      std::ostringstream o;
      o << "is singular to working precision (diagonal entries from " << std::setprecision(2)
        << d.smallest << " to " << d.largest << " on level " << l << ")";
      return o.str();
    }
  }
  return {};
}

} // namespace mixcon::detail
