// A contact enforcement as the solver layer sees it: a provider of constraints and forces. What
// the nonlinear models ask in each evaluation (detection at the current positions, contact forces
// added to the residual, the residual norm over the unknowns the constraints leave free) and each
// correction (the linearized system solved with the contact constraints), and what the load
// stepper asks between equilibrium iterations (the report's nested contact iterations): statuses
// updated from positions and contact forces, commit / rollback with the load increment, cycle
// detection by a status signature. Implemented in contact/ by RigidContact (rigid obstacles) and
// SurfaceContact (elastic-elastic node-to-segment), so that solver/ never includes contact/.
// What constrains a correction is one device object, a ConstraintSet (solver/ConstraintSet.hpp:
// Dirichlet flags and values, local frames, multipoint rows): rigid contact gives local frames
// and held components, node-to-segment contact multipoint rows, and the models solve their
// corrections through it (NonlinearModel::correctWithContact); correct() solves only what has
// unknowns of its own (force-driven obstacles). Host-side interface (virtual, never on the
// device). Layer: solver.
#pragma once

#include <solver/Checkpoint.hpp>
#include <solver/ConstraintSet.hpp>
#include <solver/LinearSolver.hpp>

#include <kernels/SparseMatrix.hpp>

#include <string>
#include <vector>

namespace mixcon {

/// One correction of a nonlinear model, as handed to its contact enforcement (`stride` unknowns
/// per node, the displacement pair first).
struct ContactCorrection {
  double lambda = 0.0; ///< the load factor the correction aims at
  int stride = 2;
  const CsrMatrix<DeviceSpace> *tangent = nullptr; ///< the unconstrained tangent
  CsrMatrix<DeviceSpace> *work = nullptr;          ///< storage for a constrained copy
  Kokkos::View<const int *, DeviceSpace> flags;    ///< Dirichlet flags per unknown
  Kokkos::View<const double *, DeviceSpace> g;     ///< the residual f_int - f_ext
  /// Prescribed displacements at load factor 1 and the current total displacement (2 per node).
  Kokkos::View<const double *, DeviceSpace> prescribed, displacement;
  /// Stages: the prescribed values the stage starts from (empty: none); the prescribed values
  /// at lambda are prescribedBase + lambda prescribed.
  Kokkos::View<const double *, DeviceSpace> prescribedBase;
  Kokkos::View<double *, DeviceSpace> rhs, target; ///< work vectors (one value per unknown)
  LinearSolver *solver = nullptr;
  double stiffnessScale = 0.0; ///< RMS diagonal of K^L (scales eliminated constraints)
  double *setupSeconds = nullptr;
};

class ContactIterations {
public:
  virtual ~ContactIterations() = default;

  // ---- in each evaluation and correction of the model
  /// Detection at the positions coordinates + x (`stride` unknowns per node; `flags` the
  /// Dirichlet flags per unknown).
  virtual void locate(const Kokkos::View<const double *[2], DeviceSpace> &coordinates,
                      const Kokkos::View<const double *, DeviceSpace> &x, int stride,
                      const Kokkos::View<const int *, DeviceSpace> &flags) = 0;
  /// Subtracts the contact forces that act as loads (friction of slipping nodes) from g.
  virtual void subtractForces(const Kokkos::View<double *, DeviceSpace> &g, int stride) const = 0;
  /// ||g|| over the displacement unknowns held neither by Dirichlet flags nor by the contact
  /// constraints (plus the balance of force-driven obstacles).
  virtual double freeResidualNorm(const Kokkos::View<const double *, DeviceSpace> &g,
                                  const Kokkos::View<const int *, DeviceSpace> &flags,
                                  int stride) const = 0;
  /// The reference force norm of the equilibrium check given the applied loads' norm (forces on
  /// force-driven obstacles added).
  virtual double externalForceNorm(double appliedLoads) const { return appliedLoads; }
  /// True when a contact constraint holds (a closed node or pair): corrections then go through
  /// correct().
  virtual bool constrains() const = 0;
  /// The constraints of the correction `system` as one device object: the model's Dirichlet
  /// flags with their remaining step (written to system.target) and the contact's frames and
  /// multipoint rows; valid until the next call or status change. nullptr where the correction
  /// has unknowns of its own (force-driven obstacles) and only correct() solves it.
  virtual const ConstraintSet *constraintSet(const ContactCorrection &) { return nullptr; }
  /// The correction dx with the contact constraints enforced.
  virtual LinearSolveStats correct(const ContactCorrection &system,
                                   const Kokkos::View<double *, DeviceSpace> &dx) = 0;

  // ---- between equilibrium iterations (the load stepper)
  /// Moves what the load factor drives (rigid obstacles); nothing for surface contact.
  virtual void setLoadFactor(double lambda) = 0;
  /// Seats unsupported force-driven obstacles; returns how many moved.
  virtual int seatForceDriven() { return 0; }
  /// Closes the open candidates already touching (gap <= tolerance, relative to the contact
  /// surface's size for surface contact); returns how many closed.
  virtual int closeTouching(double tolerance) = 0;
  /// Status update from the residual g = f_int - f_ext (`stride` unknowns per node,
  /// displacements first) and optionally the nodal stresses; returns the number of changes.
  virtual int updateStatus(const std::vector<double> &g, int stride, std::string &log,
                           const std::vector<double> *stress, bool frozen) = 0;
  /// The nodes at which updateStatus reads g and the stresses (the rest may be left 0, so only
  /// those are copied to the host); nullptr: every node.
  virtual const std::vector<LocalIndex> *statusNodes() const { return nullptr; }
  virtual bool penetrationWithin(double relative, std::string &where) const = 0;
  virtual void commit() = 0;
  virtual void rollback() = 0;
  /// The committed state (statuses, stick anchors, contact forces, obstacle motion) into
  /// `state` under "contact/..." names; restoreCommitted makes a saved state the committed one
  /// and returns to it, so that a restarted run continues as the uninterrupted one would.
  /// Throws std::runtime_error when `state` does not fit this contact.
  virtual void saveCommitted(Checkpoint &state) const = 0;
  virtual void restoreCommitted(const Checkpoint &state) = 0;
  virtual std::string signature() const = 0;
  /// True when the linearized constraints of closed nodes are exact (flat rigid obstacles): with
  /// a linear body, one converged linear solve then satisfies the equilibrium iterations.
  virtual bool linearConstraints() const { return false; }
};

} // namespace mixcon
