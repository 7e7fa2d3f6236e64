// What the load stepper asks of a contact enforcement between equilibrium iterations (the
// report's nested contact iterations): statuses updated from positions and contact forces,
// commit / rollback with the load increment, cycle detection by a status signature. Implemented
// by RigidContact (rigid obstacles) and SurfaceContact (elastic-elastic node-to-segment).
// Host-side interface (virtual, never on the device). Data flow: solver <- contact.
#pragma once

#include <solver/Checkpoint.hpp>

#include <string>
#include <vector>

namespace mixcon {

class ContactIterations {
public:
  virtual ~ContactIterations() = default;
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
