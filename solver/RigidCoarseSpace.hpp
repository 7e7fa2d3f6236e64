// A second level for the AMG preconditioner of slender parts: the rigid-body modes of small node
// aggregates (smoothed aggregation's tentative prolongator, orthonormalized per aggregate and
// smoothed by one damped Jacobi step), with their Galerkin operator P^T A P factorized once.
// Around one BoomerAMG V-cycle B it forms the balancing preconditioner
//   M^-1 r = C r + (I - C A) B (I - A C) r,   C = P (P^T A P)^-1 P^T,
// which is symmetric positive definite for SPD A and B. On a strip the classical hierarchy
// cannot represent bending at lengths between its coarsest level and the elements; the
// aggregates' rotations do (docs/performance.md, "A rigid-body coarse space"). Host-side
// (Eigen products, SuiteSparse factorization), one rank; the matrix is the constrained one of the
// solver (identity-like rows of prescribed unknowns, which the coarse space leaves alone). Data
// flow: solver.
#pragma once

#include <solver/LinearSolver.hpp> // DeviceSpace

#include <memory>
#include <string>
#include <vector>

namespace mixcon {

/// Aggregates of the nodes of a graph (rows of node neighbours, self included or not), as in
/// smoothed aggregation (Vanek, Mandel, Brezina 1996): a node whose neighbours are all free
/// starts an aggregate with them; a node left over joins the aggregate of its first aggregated
/// neighbour; one with none starts its own with its free neighbours. Returns the aggregate of
/// each node (0, 1, ...).
std::vector<int> aggregateNodes(const std::vector<Offset> &rowOffsets,
                                const std::vector<LocalIndex> &columns);

/// The largest rigid-body coarse space worth factorizing in `dim` (2 or 3) dimensions: its
/// Cholesky (CHOLMOD, solver/SparseDirect.hpp) fills as a 2D or a 3D finite-element matrix does.
/// Measured on compact meshes (docs/performance.md, issue 20 section 7): 2D, 193,548 coarse
/// unknowns in a 19-21 s setup (a Quad4 square of 760 x 760; 334,668: 40 s); 3D, 29,478, 41,154
/// and 63,888 in 17, 30 and 41 s (the Hex8 cubes N = 48, 56 and 64; with Eigen's simplicial
/// LDL^T before, 29,478 took 62-104 s).
inline long rigidCoarseSpaceLimit(int dim) { return dim == 3 ? 64000 : 200000; }

class RigidCoarseSpace {
public:
  /// The coarse space of the matrix `a` (interleaved unknowns, `dofsPerNode` = the positions'
  /// columns, 2 or 3) on the nodes at `positions`; its operator factorized by Cholesky where `a`
  /// is symmetric, by LU where not. ok() false, with why(), where it cannot be built (a singular
  /// or, symmetric, indefinite coarse operator; more than `maxSize` coarse unknowns).
  RigidCoarseSpace(const CsrMatrix<DeviceSpace> &a,
                   const Kokkos::View<const double **, DeviceSpace> &positions, long maxSize,
                   bool symmetric = true);
  ~RigidCoarseSpace();
  RigidCoarseSpace(const RigidCoarseSpace &) = delete;
  RigidCoarseSpace &operator=(const RigidCoarseSpace &) = delete;

  bool ok() const { return why_.empty(); }
  const std::string &why() const { return why_; }
  int size() const { return size_; }             ///< coarse unknowns
  int aggregates() const { return aggregates_; } ///< node aggregates
  /// z = C r = P (P^T A P)^-1 P^T r; host arrays of the matrix's row count.
  void apply(const double *r, double *z) const;
  /// Host arrays of the prolongator P (n x size(), CSR), for tests.
  void prolongator(std::vector<Offset> &rowOffsets, std::vector<LocalIndex> &columns,
                   std::vector<double> &values) const;

private:
  struct Factors;
  std::unique_ptr<Factors> factors_;
  std::string why_;
  int size_ = 0;
  int aggregates_ = 0;
};

} // namespace mixcon
