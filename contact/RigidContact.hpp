// Enforcement of contact with rigid obstacles in the report's way (Wilkenson-Rahman): boundary
// nodes of named boundaries are checked against their obstacle; nodes in contact are held on the
// obstacle surface in local normal/tangential coordinates (the normal component prescribed so
// the gap closes; in stick the tangential one too, at the point where the node stuck); in slip
// the tangential component is free and the Coulomb friction force mu N opposes the slip. Statuses
// are updated between equilibrium iterations (the report's nested contact and friction
// iterations): open nodes that penetrate close, closed nodes whose contact force turns tensile
// open, stick nodes whose tangential force exceeds mu N slip, slip nodes that reverse stick.
// Contact forces are the nodal reactions of the displacement model (N = G . n, T = G . t).
// Host orchestration; detection runs as a batched device kernel. Data flow: solver -> contact.
#pragma once

#include <contact/ContactStatus.hpp>
#include <contact/RigidObstacle.hpp>
#include <mesh/Mesh.hpp>
#include <solver/ContactIterations.hpp>
#include <solver/LinearSolver.hpp>

#include <array>
#include <string>
#include <vector>

namespace mixcon {

/// One obstacle and the boundary nodes checked against it.
struct RigidContactSpec {
  RigidObstacle obstacle;
  std::vector<LocalIndex> nodes;
  double friction = 0.0;        ///< Coulomb coefficient mu (0: frictionless)
  double drive[2] = {0.0, 0.0}; ///< rigid motion of the obstacle at load factor 1
  /// Components driven by a force instead: the obstacle's motion along them is an unknown and
  /// the contact forces it exerts on the body balance lambda * force there (a loaded pin).
  bool forceDriven[2] = {false, false};
  double force[2] = {0.0, 0.0}; ///< force on the obstacle at load factor 1 (forceDriven parts)
  /// Whether the mixed model's nodal stresses decide release and slip (the report's way);
  /// false: the nodal contact forces decide, as for the displacement model.
  bool statusFromStress = true;
  std::string name; ///< for messages (e.g. the boundary)
};

/// Per-node constraint data for one Newton correction (host arrays, N nodes).
struct ContactConstraints {
  std::vector<int> framed;         ///< node uses its local (n, t) frame
  std::vector<double> normal;      ///< 2 per node
  std::vector<int> normalFixed;    ///< local normal component prescribed
  std::vector<int> tangentFixed;   ///< local tangential component prescribed (stick)
  std::vector<double> normalStep;  ///< prescribed change of the normal component (-gap)
  std::vector<double> tangentStep; ///< prescribed change of the tangential component (stick)
  std::vector<double> force;       ///< 2 per node: friction forces on the body (slip), global
  std::vector<int> obstacle;       ///< obstacle (spec index) of a framed node, -1 otherwise
};

/// One force-driven component of an obstacle's motion: spec index and direction (0: x, 1: y).
struct DrivenComponent {
  int obstacle;
  int direction;
};

class RigidContact final : public ContactIterations {
public:
  /// `nodeIds`: the mesh's external node ids (Mesh::nodeIds) that messages name nodes by; empty:
  /// index + 1.
  RigidContact(LocalIndex numNodes, std::vector<RigidContactSpec> specs,
               std::vector<long> nodeIds = {});

  /// Moves every obstacle to its position at load factor lambda: point + lambda drive along
  /// displacement-driven components; force-driven components keep their current motion.
  void setLoadFactor(double lambda) override;
  /// Stages: over the stage, obstacle s moves from `baseMotion` by `drive` (lambda drive at load
  /// factor lambda, displacement-driven components), and the force on it goes from `baseForce`
  /// by `force` (force-driven components). Which components are force driven stays.
  void setStageDrive(int s, const std::array<double, 2> &baseMotion,
                     const std::array<double, 2> &drive, const std::array<double, 2> &baseForce,
                     const std::array<double, 2> &force);
  /// The force-driven components of all obstacles (empty: every obstacle is displacement
  /// driven), the force on them at the current load factor, and their current motion.
  const std::vector<DrivenComponent> &drivenComponents() const { return driven_; }
  double drivenForce(const DrivenComponent &c) const;
  /// Rigid motion of obstacle s from its declared position (2 components).
  const double *obstacleMotion(int s) const { return &motion_[2 * static_cast<std::size_t>(s)]; }
  /// Translates obstacle s by `delta` (2 components); call detect() again afterwards.
  void moveObstacle(int s, const double *delta);
  /// Moves every force-driven obstacle that has no closed node along its force until the first
  /// candidate touches it (uses the last detection), so that the obstacle is supported; throws
  /// InputError when no candidate lies in the way. Returns how many obstacles moved.
  int seatForceDriven() override;

  // ContactIterations: the enforcement in the models' evaluations and corrections.
  void locate(const Kokkos::View<const double *[2], DeviceSpace> &coordinates,
              const Kokkos::View<const double *, DeviceSpace> &x, int stride,
              const Kokkos::View<const int *, DeviceSpace> &flags) override;
  void subtractForces(const Kokkos::View<double *, DeviceSpace> &g, int stride) const override;
  double freeResidualNorm(const Kokkos::View<const double *, DeviceSpace> &g,
                          const Kokkos::View<const int *, DeviceSpace> &flags,
                          int stride) const override;
  bool constrains() const override;
  /// The correction's constraints (solver/ConstraintSet.hpp): local (n, t) frames at closed
  /// nodes, their normal (and in stick tangential) components and the model's Dirichlet
  /// unknowns prescribed, the prescribed steps in system.target. nullptr with force-driven
  /// obstacles: their motion is an unknown of the correction that only correct() condenses.
  const ConstraintSet *constraintSet(const ContactCorrection &system) override;
  /// solveConstrained through the constraint set, then (force-driven obstacles) the condensed
  /// obstacle motion added.
  LinearSolveStats correct(const ContactCorrection &system,
                           const Kokkos::View<double *, DeviceSpace> &dx) override;
  double externalForceNorm(double appliedLoads) const override;

  /// Projects every candidate at the current position (coordinates + u, `stride` unknowns per
  /// node, displacements first) onto its obstacle; returns the number penetrating.
  LocalIndex detect(const Kokkos::View<const double *[2], DeviceSpace> &coordinates,
                    const Kokkos::View<const double *, DeviceSpace> &u, int stride);

  /// Constraints of the current statuses at the last detected positions (call detect first).
  /// A closed node is moved onto the surface by -gap along n; a stick node is held at its
  /// anchor along t.
  const ContactConstraints &constraints() const { return constraints_; }

  /// Updates statuses from the last detection and the contact forces: `g` the residual
  /// f_int - f_ext (without contact forces) with `stride` unknowns per node. With `stress`
  /// (nodal Cauchy stress, 3 per node: the mixed model) release and slip are decided from the
  /// stresses rotated to the surface, sigma_nn = n.s.n (tensile: release) and tau_nt = t.s.n
  /// (slip when |tau_nt| > mu |sigma_nn|), as the report does; otherwise from the forces N, T.
  /// Returns the number of status changes; `log` lists them (empty when none).
  /// With `frozen` the statuses stay and only the friction forces of slip nodes are updated to
  /// mu N (how a cycling active set is resolved).
  int updateStatus(const std::vector<double> &g, int stride, std::string &log,
                   const std::vector<double> *stress = nullptr, bool frozen = false) override;

  /// Closes the open candidates already touching their obstacle (gap <= tolerance) at the last
  /// detection: a body that rests on an obstacle is supported from the first iteration.
  /// Returns how many closed.
  int closeTouching(double tolerance) override;

  /// Whether every closed node penetrates its obstacle by at most `relative` times the
  /// obstacle's size (a pin's radius; for a half-plane the extent of its candidate nodes along
  /// it); `where` names the worst node otherwise.
  bool penetrationWithin(double relative, std::string &where) const override;

  /// Accept the current state as converged; rollback() returns to the last commit.
  void commit() override;
  void rollback() override;
  void saveCommitted(Checkpoint &state) const override;
  void restoreCommitted(const Checkpoint &state) override;
  /// A string of the statuses (cycle detection).
  std::string signature() const override;
  /// The status update reads the residual and stresses at the candidate nodes only.
  const std::vector<LocalIndex> *statusNodes() const override { return &node_; }

  LocalIndex numCandidates() const { return static_cast<LocalIndex>(node_.size()); }
  LocalIndex candidateNode(LocalIndex k) const { return node_[k]; }
  ContactStatus status(LocalIndex k) const { return status_[k]; }
  double gap(LocalIndex k) const { return gap_[k]; }
  double angle(LocalIndex k) const { return angle_[k]; }
  /// Unit normal into the body at candidate k's projection (last detection), 2 components.
  const double *normal(LocalIndex k) const { return &normal_[2 * static_cast<std::size_t>(k)]; }
  double normalForce(LocalIndex k) const { return normalForce_[k]; }
  double tangentForce(LocalIndex k) const { return tangentForce_[k]; }
  LocalIndex numClosed() const;
  const std::vector<RigidContactSpec> &specs() const { return specs_; }
  /// Half-planes only (a circle's normal turns with the contact point).
  bool linearConstraints() const override {
    for (const auto &s : specs_)
      if (s.obstacle.kind != ObstacleKind::HalfPlane)
        return false;
    return true;
  }
  int obstacleOf(LocalIndex k) const { return obstacle_[k]; }
  double arcCoordinate(LocalIndex k) const { return arc_[k]; }
  /// "obstacle <s + 1> ('<name>')": obstacle s as the problem file's `contact:` list numbers it.
  std::string obstacleLabel(int s) const;

  // The constraints on the device (public only because CUDA's extended lambdas cannot live in
  // private member functions; not for callers).
  /// constraints_ on the device for the kernels of an evaluation and a correction: one entry per
  /// node that is framed or carries a friction force (O(candidates), uploaded once after each
  /// buildConstraints), and per mesh node its entry (-1: none), filled on the device.
  struct DeviceConstraints {
    Kokkos::View<LocalIndex *, DeviceSpace> node;
    Kokkos::View<int *[4], DeviceSpace> flags;     ///< framed, normalFixed, tangentFixed, obstacle
    Kokkos::View<double *[6], DeviceSpace> values; ///< n0, n1, normalStep, tangentStep, fx, fy
    Kokkos::View<int *, DeviceSpace> entry;        ///< mesh node -> entry, -1: none
  };
  const DeviceConstraints &deviceConstraints() const;
  /// Component d of the contact force obstacle o exerts on the body from a residual-like device
  /// vector y (`stride` unknowns per node, `dirichlet` flags per unknown), a device reduction.
  double obstacleForce(const Kokkos::View<const double *, DeviceSpace> &y, int stride,
                       const Kokkos::View<const int *, DeviceSpace> &dirichlet, int o, int d,
                       bool withFriction) const;
  /// The constraint set of a correction, whether or not obstacles are force driven.
  const ConstraintSet &buildSet(const ContactCorrection &system);

private:
  void buildConstraints();
  std::vector<RigidContactSpec> specs_;
  std::vector<long> nodeIds_; ///< external node ids for messages (Mesh::externalId)
  LocalIndex numNodes_;
  std::vector<LocalIndex> node_; ///< candidate k -> node
  std::vector<int> obstacle_;    ///< candidate k -> spec index
  std::vector<ContactStatus> status_;
  std::vector<double> gap_, angle_, arc_, normal_, normalForce_, tangentForce_;
  std::vector<double> anchorArc_, committedArc_; ///< stick anchors; arc at the last commit
  std::vector<double> motion_;                   ///< 2 per obstacle: motion from `point`
  std::vector<DrivenComponent> driven_;
  double lambda_ = 0.0;
  std::vector<double> baseMotion_, baseForce_; ///< stages: 2 per obstacle, where a stage starts
  /// The last converged state. committedArc and committedGap (NaN when unknown: a restart file
  /// written before it was saved) are also the initial state's before anything is committed:
  /// where a node that closes in the next increment starts from.
  struct Saved {
    std::vector<ContactStatus> status;
    std::vector<double> anchorArc, normalForce, tangentForce, motion, committedArc, committedGap;
  } saved_;
  void uploadObstacles();
  /// Candidate k's arc since `from`: arc_[k] - from, on a circle across the angle pi too.
  double arcChange(std::size_t k, double from) const;
  ContactConstraints constraints_;
  Kokkos::View<RigidObstacle *, DeviceSpace> obstacles_;
  Kokkos::View<LocalIndex *, DeviceSpace> nodesDevice_;
  Kokkos::View<int *, DeviceSpace> obstacleDevice_;
  ContactDetection<DeviceSpace> detection_;
  Kokkos::View<double *[5], DeviceSpace> detected_; ///< gap, normal, angle, arc (one copy)

  mutable DeviceConstraints device_;
  mutable bool deviceStale_ = true;
  // The constraint set of the last correction and the per-unknown / per-node views it refers to.
  ConstraintSet set_;
  Kokkos::View<int *, DeviceSpace> setFlags_, setFramed_;
  Kokkos::View<double *[2], DeviceSpace> setNormal_;
  ConstraintElimination elimination_; ///< unused (no multipoint rows); solveConstrained's slot
};

} // namespace mixcon
