// The linear displacement model of the report (Eq. (24)-(25) without K^sigma): assembles K^L and
// F^L with the batched kernels, applies prescribed displacements, solves with hypre AMG or the
// direct solver, and recovers stresses and reactions. Loads and prescribed values form a reference
// load that a load factor scales. Device-resident throughout; host copies only on request.
// Data flow: mesh -> kernels -> solver (this) -> io.
#pragma once

#include <kernels/LinearElasticity.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/LinearSolver.hpp>

#include <array>
#include <functional>
#include <memory>
#include <vector>

namespace mixcon {

class LinearDisplacementModel {
public:
  using Exec = Kokkos::DefaultExecutionSpace;
  using Memory = DeviceSpace;

  /// `elementMaterial[e]` indexes `stiffness` (plane [C] in global axes); thickness t of Eq. (25).
  LinearDisplacementModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                          const std::vector<PlaneMatrix> &stiffness, double thickness);

  const DofMap &dofs() const { return dofs_; }
  const Mesh &mesh() const { return mesh_; }

  /// Reference loads (all scaled by the load factor at solve time). Nodal forces and prescribed
  /// values are staged on the host and copied to the device once, in setup().
  void addEdgeLoad(const std::vector<BoundaryEdge> &edges, double tx, double ty, double pressure);
  void addNodalForce(LocalIndex node, double fx, double fy);
  /// Body force per unit volume, evaluated on the host at each quadrature point (x, y, element).
  void addBodyForce(const std::function<std::array<double, 2>(double, double, LocalIndex)> &f);
  /// Prescribes component `comp` (0: x, 1: y) of `node` (reference value, scaled too).
  void prescribe(LocalIndex node, int comp, double value);
  LocalIndex numConstrained() const;

  /// Assembles K^L, applies the constraints and sets the linear solver up (AMG hierarchy or
  /// factorization). Call after all loads and constraints are given.
  void setup(const LinearSolverOptions &options, MPI_Comm comm);
  /// Solves K u = lambda F with u = lambda g on constrained unknowns; result in displacement().
  LinearSolveStats solve(double loadFactor);

  Kokkos::View<double *, Memory> displacement() const { return u_; }
  const CsrMatrix<Memory> &unconstrainedStiffness() const { return stiffness_; }
  double assemblySeconds() const { return assemblySeconds_; }
  double solverSetupSeconds() const { return solver_ ? solver_->setupSeconds() : 0.0; }
  std::string solverName() const { return solver_ ? solver_->name() : std::string(); }

  /// Host copies for output.
  std::vector<double> displacementHost() const;
  std::vector<double> nodalStressHost() const; ///< N x 3, recovered from 2x2 Gauss points
  void gaussPointStressHost(std::vector<double> &coordinates, std::vector<double> &stress,
                            int &pointsPerElement) const;
  /// Reactions K u - lambda F (N x 2): the support forces at constrained nodes, ~0 elsewhere.
  std::vector<double> reactionHost(double loadFactor) const;

private:
  Mesh const &mesh_;
  DofMap dofs_;
  ElementData<Memory> data_;
  NodeGraph graph_;
  CsrMatrix<Memory> stiffness_;         ///< unconstrained K^L
  CsrMatrix<Memory> constrained_;       ///< K^L with identity-like constrained rows
  Kokkos::View<double *, Memory> load_; ///< reference external load F
  Kokkos::View<double *, Memory> rhs_;  ///< constrained right-hand side for lambda = 1
  Kokkos::View<double *, Memory> u_;
  Kokkos::View<int *, Memory> isConstrained_;
  Kokkos::View<double *, Memory> prescribed_;
  std::vector<double> stagedNodalForce_; ///< host, added to load_ by setup()
  std::vector<int> constrainedHost_;     ///< host staging of isConstrained_
  std::vector<double> prescribedHost_;   ///< host staging of prescribed_
  std::unique_ptr<LinearSolver> solver_;
  double assemblySeconds_ = 0.0;
};

} // namespace mixcon
