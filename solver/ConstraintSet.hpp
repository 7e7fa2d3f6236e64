// One device object for what constrains a linear system A x = b of the solver layer: prescribed
// unknowns (Dirichlet flags and values), local frames (node rotations R, solver/LocalFrames.hpp)
// and multipoint rows (x~ = T y + s, solver/MultiPointConstraints.hpp). A contact provider hands
// a model's corrections one such set (solver/ContactIterations.hpp) instead of host vectors; the
// views live on the device and are owned by whoever built the set (the set refers to them).
// Meaning, for a system in global components: x = R (T y + s), y_i = value_i at the prescribed
// unknowns and at the slaves, and y solves (T^T R^T A R T + D) y = T^T R^T (b - A R s) on the
// other unknowns (the constraints applied in the order frames, multipoint rows, Dirichlet rows).
// Flags, values and the multipoint rows refer to the frames' (local) components at framed nodes.
// Layer: solver.
#pragma once

#include <solver/LinearSolver.hpp>
#include <solver/MultiPointConstraints.hpp>

#include <utility>
#include <vector>

namespace mixcon {

/// A linear condition sum_e c_e x_e = d on the global unknowns (host description).
struct LinearCondition {
  std::vector<std::pair<LocalIndex, double>> entries;
  double value = 0.0;
};

struct ConstraintSet {
  int stride = 2;                               ///< unknowns per node, the displacement pair first
  Kokkos::View<const int *, DeviceSpace> flags; ///< per unknown: prescribed (Dirichlet)
  Kokkos::View<const double *, DeviceSpace> values;        ///< per unknown: the prescribed value
  Kokkos::View<const int *, DeviceSpace> framed;           ///< per node; empty: no local frames
  Kokkos::View<const double *[2], DeviceSpace> normal;     ///< per node: n of its frame
  const DeviceMultiPointConstraints *multipoint = nullptr; ///< T and s; nullptr: none
  double slaveDiagonal = 1.0; ///< D at the slaves (scale it like A's diagonal)
  /// The multipoint rows' constraints written as conditions on the global unknowns, for a
  /// solver that takes them in that form (solver/CapacitanceSolve.hpp); nullptr: not given, and
  /// only the elimination solves the set.
  const std::vector<LinearCondition> *conditions = nullptr;
  bool hasFrames() const { return framed.extent(0) > 0; }
  bool hasMultipoint() const { return multipoint && !multipoint->empty(); }
};

/// x solving A x = b under `c` (b is overwritten). `work`: storage for the constrained matrix
/// (its values are replaced; with multipoint rows it becomes the reduced matrix);
/// `elimination` keeps the symbolic phase of T^T A T between calls. Adds the time spent
/// preparing the matrix and in the solver's setup to *setupSeconds when given.
LinearSolveStats solveConstrained(const ConstraintSet &c, const CsrMatrix<DeviceSpace> &a,
                                  CsrMatrix<DeviceSpace> &work, ConstraintElimination &elimination,
                                  const Kokkos::View<double *, DeviceSpace> &b,
                                  LinearSolver &solver,
                                  const Kokkos::View<double *, DeviceSpace> &x,
                                  double *setupSeconds = nullptr);

namespace detail {
/// `work` = a: its pattern shared when it already fits, the values copied.
void copyMatrix(const CsrMatrix<DeviceSpace> &a, CsrMatrix<DeviceSpace> &work);
} // namespace detail

/// ||T^T R^T g|| over the displacement unknowns (i % stride < 2) neither prescribed nor slaves:
/// the residual the constrained system balances (a device reduction; nothing copied).
double constrainedFreeNorm(const ConstraintSet &c,
                           const Kokkos::View<const double *, DeviceSpace> &g);

} // namespace mixcon
