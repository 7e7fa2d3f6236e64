// Contact corrections on one factorization: A x = b under a ConstraintSet whose conditions
// change from one correction to the next (contact nodes closing and opening, stick and slip),
// while A and the fixed Dirichlet rows stay (linear kinematics: the Hertz runs take 25
// corrections on one stiffness). A0, the matrix with only the fixed ("base") rows eliminated, is
// factorized once; the m changing conditions c_k . x = d_k (a node's normal or tangential
// component in its local frame, a prescribed global component, or a multipoint row given as a
// condition: node-to-segment contact's n . u_p - sum_i w_i n . u_i = step) enter through the
// capacitance matrix S = C A0^-1 C^T (the Sherman-Morrison-Woodbury form of the constrained
// solve):
//   y = A0^-1 b0,   S lambda = C y - d,   x = y - A0^-1 C^T lambda,
// with the columns A0^-1 e_u kept for every unknown u a condition has touched since the
// factorization (two solves per node a condition touches, once per factorization; at most
// kMaxColumns, and 32 Mi values in all). Entries at base unknowns move to d. The
// result is the constrained system's solution up to round-off, as solveConstrained's
// elimination gives it.
// Used only where the solver's solve() is exact on a kept factorization
// (LinearSolver::keepsFactorization: the direct solver, `solver: {reuse_factorization: true}`),
// multipoint rows come with their conditions (ConstraintSet::conditions), at most
// kMaxConditions conditions hold, and the matrix is the one of the previous correction (a
// Newton tangent that changes in every correction goes on by elimination, at the cost of a copy
// and a comparison of its values); otherwise the caller solves through solveConstrained.
// Layer: solver.
#pragma once

#include <solver/ConstraintSet.hpp>
#include <solver/LinearSolver.hpp>

#include <memory>
#include <vector>

namespace mixcon {

class CapacitanceSolve {
public:
  /// Most changing conditions (rows of C) and kept columns handled; more go through
  /// solveConstrained (S is dense, and a column costs a solve and a vector).
  static constexpr int kMaxConditions = 400;
  static constexpr int kMaxColumns = 2 * kMaxConditions;
  /// Largest relative residual of a solution taken (free rows and conditions, checked after
  /// every solve); the direct solver's are about 1e-15, a nearly singular A0 (a body held only
  /// by contact) gives O(1).
  static constexpr double kResidualBound = 1e-9;

  /// x solving A x = b under `c`, where `base` flags the unknowns prescribed in every correction
  /// (their values in c.values). `solver` is the caller's: the method applies where it keeps
  /// its factorization (LinearSolver::keepsFactorization), and A0 is factorized by a solver of
  /// its kind held here (LinearSolver::another), so that the caller's factorization and state
  /// stay as they are. Returns false, with b untouched, where the method does not apply (see
  /// the file comment), and for a matrix or base flags other than the last call's (a matrix is
  /// used from its second correction on, so that a Newton tangent new in every correction costs
  /// only a copy and a comparison): the caller then solves as before. Adds the time spent in
  /// the factorization and the kept columns to *setupSeconds when given.
  bool solve(const ConstraintSet &c, const Kokkos::View<const int *, DeviceSpace> &base,
             const CsrMatrix<DeviceSpace> &a, const Kokkos::View<double *, DeviceSpace> &b,
             const LinearSolver &solver, const Kokkos::View<double *, DeviceSpace> &x,
             LinearSolveStats &stats, double *setupSeconds = nullptr);

  /// Factorizations of A0 made so far, and solves made by this method.
  int factorizations() const { return factorizations_; }
  int solves() const { return solves_; }

private:
  /// True when `a` and `base` are those recorded (pattern, values, flags).
  bool sameMatrix(const CsrMatrix<DeviceSpace> &a,
                  const Kokkos::View<const int *, DeviceSpace> &base) const;
  void record(const CsrMatrix<DeviceSpace> &a, const Kokkos::View<const int *, DeviceSpace> &base);
  /// A0 factorized by own_ (made from `solver` first); false where A0 is singular.
  bool factorize(const ConstraintSet &c, const Kokkos::View<const int *, DeviceSpace> &base,
                 const CsrMatrix<DeviceSpace> &a, const LinearSolver &solver);
  /// The kept column A0^-1 e_u (solved now if u has none).
  int column(LocalIndex u, LinearSolveStats &stats);

  // The matrix and base flags of the last call, and whether own_ holds A0's factorization for
  // them.
  std::unique_ptr<LinearSolver> own_;
  bool factored_ = false;
  const Offset *rowOffsets_ = nullptr;
  const LocalIndex *columns_ = nullptr;
  Kokkos::View<double *, DeviceSpace> values_; ///< A's values
  Kokkos::View<int *, DeviceSpace> base_;      ///< the base flags
  // The kept columns A0^-1 e_u.
  std::vector<int> columnOf_; ///< per unknown: its column, or -1
  std::vector<LocalIndex> unknownOf_;
  std::vector<Kokkos::View<double *, DeviceSpace>> w_;
  Kokkos::View<double *, DeviceSpace> lifted_;          ///< b0
  Kokkos::View<double *, DeviceSpace> force_, product_; ///< C^T lambda, A x
  /// The method failed for the recorded matrix (A0 singular, S singular, or a residual above
  /// kResidualBound): not tried again until the matrix or the base flags change.
  bool declined_ = false;
  double normInf_ = 0.0; ///< ||A||_inf of the recorded matrix
  int factorizations_ = 0, solves_ = 0;
};

} // namespace mixcon
