// Whether an AMG hierarchy is numerically sound, judged from its levels' diagonals alone: a pure
// function over numbers every rank has (LinearSolver reduces them over its ranks first), so that
// the decision is tested apart from hypre. Data flow: solver (checks of a built hierarchy).
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace mixcon::detail {

/// The diagonal of one level over all ranks: its smallest and largest positive finite entries,
/// whether any entry is zero, negative or not finite, and how many rows it has.
struct DiagonalRange {
  double smallest = std::numeric_limits<double>::infinity();
  double largest = 0.0;
  bool improper = false; ///< an entry that is zero, negative or not finite
  long rows = 0;
  /// Adds one row's diagonal entry.
  void add(double aii);
};

/// A coarse level whose diagonal spreads (largest over smallest) this many times more than the
/// fine level's makes a hierarchy unsound (sound hierarchies measured at most 4e4, unsound ones
/// 1e30 and more: docs/performance.md, issue 20 section 1c).
inline constexpr double kUnsoundSpreadGrowth = 1e10;

/// Why the hierarchy with these levels (the fine level first) is unsound, or empty: a coarse level
/// with rows whose diagonal has an improper entry, or spreads more than kUnsoundSpreadGrowth times
/// the fine level's. A Galerkin product P^T A P of an SPD A has a positive diagonal of A's
/// magnitudes, so the check applies only where the fine level's diagonal is positive and finite
/// (empty otherwise: an indefinite or nonsymmetric matrix says nothing about its coarse levels).
std::string unsoundDiagonals(const std::vector<DiagonalRange> &levels);

} // namespace mixcon::detail
