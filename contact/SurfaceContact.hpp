// Elastic-elastic node-to-segment contact with Coulomb friction (the report's "elastic pin"
// algorithm after Bathe and Chaudhary): the nodes of a contactor surface against the segments of
// a target surface of another body (or another part of the mesh). Each iteration the contactor
// nodes are projected onto the target (contact/SegmentSearch.hpp, on the device); a node that
// penetrates closes, a closed node carries a normal multiplier N (compressive >= 0) and, in
// stick, a tangential multiplier T; it is released when N turns tensile, slips when
// |T| > mu N (then the friction force mu N acts against the slip on the contactor and, through
// the segment's shape functions, back on the target nodes), and sticks again when its slip
// reverses. The multipliers are the contactor's nodal contact forces: the constraints are
// eliminated from the linear systems (solver/MultiPointConstraints.hpp; the contactor's normal
// and in stick tangential displacement follow the target segment), which keeps the systems
// symmetric positive definite for CG + BoomerAMG, and the multipliers are recovered exactly as
// the contactor's reactions (docs/contact.md, "Elastic-elastic contact"). Host orchestration;
// the search runs on the device. Data flow: solver -> contact.
#pragma once

#include <contact/RigidContact.hpp>
#include <solver/ContactIterations.hpp>
#include <solver/MultiPointConstraints.hpp>

#include <array>
#include <string>
#include <vector>

namespace mixcon {

/// One contactor surface against one target surface.
struct SurfaceContactSpec {
  std::vector<LocalIndex> contactor; ///< contactor nodes
  /// Target segments: the two end nodes and the middle node (Quad8 edge) or -1; the target body
  /// lies on the left of the direction end 0 -> end 1 (mixcon's boundary edges).
  std::vector<std::array<LocalIndex, 3>> target;
  double friction = 0.0; ///< Coulomb coefficient mu
  std::string name;      ///< for messages ("contactor -> target")
};

/// A closed contactor node's constraint for one correction: its displacement along n follows
/// the target point (weights of the target nodes at the projection), moved by normalStep; in
/// stick its tangential displacement follows the anchor point, moved by tangentStep.
struct SurfacePair {
  LocalIndex node = -1;
  double normal[2] = {0.0, 0.0};  ///< target's outward normal at the projection
  double tangent[2] = {0.0, 0.0}; ///< tangentBasis<2>(normal): (-n_y, n_x)
  int normalCount = 0;
  LocalIndex normalNodes[3] = {-1, -1, -1};
  double normalWeights[3] = {0.0, 0.0, 0.0};
  double normalStep = 0.0; ///< -gap
  bool stick = false;
  int tangentCount = 0;
  LocalIndex tangentNodes[3] = {-1, -1, -1};
  double tangentWeights[3] = {0.0, 0.0, 0.0};
  double tangentStep = 0.0; ///< -t . (x - x_anchor)
};

/// The segments of a named boundary (its edges in element order: the body on their left);
/// throws InputError naming the boundary when the mesh has none of that name.
std::vector<std::array<LocalIndex, 3>> boundarySegments(const Mesh &mesh, const std::string &name);

class SurfaceContact final : public ContactIterations {
public:
  /// Throws InputError when a node is both contactor and target (in any pair) or a surface is
  /// empty.
  /// `nodeIds`: the mesh's external node ids (Mesh::nodeIds) that messages name nodes by; empty:
  /// index + 1.
  SurfaceContact(LocalIndex numNodes, std::vector<SurfaceContactSpec> specs,
                 std::vector<long> nodeIds = {});

  /// Projects every contactor node at the current positions (coordinates + u, `stride`
  /// unknowns per node, displacements first) onto its target; returns the number penetrating.
  LocalIndex detect(const Kokkos::View<const double *[2], DeviceSpace> &coordinates,
                    const Kokkos::View<const double *, DeviceSpace> &u, int stride);
  /// Which displacement components carry Dirichlet conditions (2 per node): a contactor node
  /// with one of them held takes the contact condition on the other.
  void setPrescribed(std::vector<int> flags) { prescribed_ = std::move(flags); }
  const std::vector<int> &prescribed() const { return prescribed_; }

  /// The closed pairs at the last detection, and the friction forces of slip pairs on the
  /// bodies (2 per node, global components; equal and opposite on contactor and target).
  const std::vector<SurfacePair> &closedPairs() const { return pairs_; }
  const std::vector<double> &frictionForces() const { return friction_; }

  // ContactIterations: the enforcement in the models' evaluations and corrections.
  void locate(const Kokkos::View<const double *[2], DeviceSpace> &coordinates,
              const Kokkos::View<const double *, DeviceSpace> &x, int stride,
              const Kokkos::View<const int *, DeviceSpace> &flags) override;
  void subtractForces(const Kokkos::View<double *, DeviceSpace> &g, int stride) const override;
  double freeResidualNorm(const Kokkos::View<const double *, DeviceSpace> &g,
                          const Kokkos::View<const int *, DeviceSpace> &flags,
                          int stride) const override;
  bool constrains() const override { return !pairs_.empty(); }
  /// The model's Dirichlet conditions and the closed pairs' multipoint rows (no frames).
  const ConstraintSet *constraintSet(const ContactCorrection &system) override;
  LinearSolveStats correct(const ContactCorrection &system,
                           const Kokkos::View<double *, DeviceSpace> &dx) override;

  void setLoadFactor(double) override {}
  int closeTouching(double tolerance) override;
  int updateStatus(const std::vector<double> &g, int stride, std::string &log,
                   const std::vector<double> *stress, bool frozen) override;
  /// The contactor nodes: the status update reads the residual only there.
  const std::vector<LocalIndex> *statusNodes() const override { return &node_; }
  bool penetrationWithin(double relative, std::string &where) const override;
  void commit() override;
  void rollback() override;
  void saveCommitted(Checkpoint &state) const override;
  void restoreCommitted(const Checkpoint &state) override;
  std::string signature() const override;

  LocalIndex numCandidates() const { return static_cast<LocalIndex>(node_.size()); }
  LocalIndex candidateNode(LocalIndex k) const { return node_[k]; }
  int pairOf(LocalIndex k) const { return spec_[k]; }
  int obstacleOf(LocalIndex k) const { return spec_[k]; } ///< the pair (output's "obstacle")
  /// Polar angle (radians) of the target's outward normal at the projection: on a circular
  /// target (a pin) the angle of the contact point about its centre, as for a rigid pin.
  double angle(LocalIndex k) const;
  ContactStatus status(LocalIndex k) const { return status_[k]; }
  double gap(LocalIndex k) const { return gap_[k]; }
  /// Target segment (index within its spec, -1: none within the search radius) and parameter.
  int segment(LocalIndex k) const { return segment_[k]; }
  double xi(LocalIndex k) const { return xi_[k]; }
  /// Target's outward normal at the projection (points to the contactor), 2 components.
  const double *normal(LocalIndex k) const { return &normal_[2 * static_cast<std::size_t>(k)]; }
  double normalForce(LocalIndex k) const { return normalForce_[k]; }
  double tangentForce(LocalIndex k) const { return tangentForce_[k]; }
  /// Reference arc length along the target (segments in their given order) of the projection.
  double arcCoordinate(LocalIndex k) const;
  LocalIndex numClosed() const;
  const std::vector<SurfaceContactSpec> &specs() const { return specs_; }
  /// Mean reference length of spec s's target segments.
  double segmentLength(int s) const { return meanLength_[s]; }
  /// "contact <s + 1> ('<name>')": pair s as the problem file's `contact:` list numbers it.
  std::string pairLabel(int s) const;

private:
  void buildPairs();
  /// The closed pairs as multipoint constraints on `stride` unknowns per node (the Dirichlet
  /// flags of the contactors from prescribed()), and when `conditions` is given the same
  /// constraints as conditions on the global unknowns (ConstraintSet::conditions): per pair
  /// n . u_p - sum_i w_i n . u_i = step_n, in stick also t . u_p - sum_j w_j t . u_j = step_t.
  void constraints(int stride, MultiPointConstraints &c,
                   std::vector<LinearCondition> *conditions = nullptr) const;
  /// Their device form on `numUnknowns` unknowns, built once per set of closed pairs (O(pairs)
  /// uploaded) and kept until the pairs change.
  const DeviceMultiPointConstraints &deviceConstraints(int stride, LocalIndex numUnknowns) const;
  /// The friction forces of the slip pairs on the device (nodes and 2 components each, only the
  /// nodes that carry one), uploaded by buildPairs.
  void uploadFriction();
  CsrMatrix<DeviceSpace> work_;       ///< the eliminated system of the last correction
  ConstraintElimination elimination_; ///< its symbolic phase, reused while the pairs stay
  ConstraintSet set_;                 ///< of the last correction
  /// The device constraints' rows as conditions, built with them (ConstraintSet::conditions).
  mutable std::vector<LinearCondition> conditions_;
  mutable DeviceMultiPointConstraints deviceConstraints_;
  mutable bool deviceConstraintsFresh_ = false;
  mutable int deviceConstraintsStride_ = 0;
  Kokkos::View<LocalIndex *, DeviceSpace> frictionNodes_;
  Kokkos::View<double *[2], DeviceSpace> frictionValues_;
  /// Contactor and target nodes (sorted, unique), on the host and the device: the only nodes
  /// whose positions and Dirichlet flags are copied to the host in an iteration.
  std::vector<LocalIndex> surfaceNodes_;
  Kokkos::View<LocalIndex *, DeviceSpace> deviceSurfaceNodes_;
  /// The Dirichlet flags of the surface nodes (2 each) on the device, from the last locate().
  Kokkos::View<int *[2], DeviceSpace> surfaceHeld_;
  std::vector<long> nodeIds_; ///< external node ids for messages (Mesh::externalId)
  /// Current position of the target point (spec s, segment, xi) and its node weights.
  void targetPoint(int s, int segment, double xi, double (&x)[2], LocalIndex (&nodes)[3],
                   double (&w)[3], int &count) const;
  std::vector<SurfaceContactSpec> specs_;
  /// Per spec, on the device once: its target segments and its contactor nodes (the candidates
  /// first(s) ... first(s) + count - 1, contiguous in node_).
  struct DeviceSurface {
    Kokkos::View<int *[3], DeviceSpace> segments;
    Kokkos::View<LocalIndex *, DeviceSpace> contactors;
    std::size_t first = 0;
    /// The target end nodes (unique), their surface-node index, the (segment, end) pairs at
    /// each (as 2 segment + end, increasing: CSR by targetStart), and each segment's ends as
    /// indices into targetNodes: what the continuous normal field is built from.
    Kokkos::View<LocalIndex *, DeviceSpace> targetNodes;
    Kokkos::View<int *, DeviceSpace> targetSurface;
    Kokkos::View<Offset *, DeviceSpace> targetStart;
    Kokkos::View<int *, DeviceSpace> targetEnds;
    Kokkos::View<int *[2], DeviceSpace> segmentEnds;
  };
  std::vector<DeviceSurface> device_;
  LocalIndex numNodes_;
  std::vector<LocalIndex> node_; ///< candidate k -> node
  std::vector<int> spec_;        ///< candidate k -> spec index
  std::vector<ContactStatus> status_;
  std::vector<int> segment_, anchorSegment_, committedSegment_;
  std::vector<double> xi_, anchorXi_, committedXi_, gap_, normal_, normalForce_, tangentForce_;
  std::vector<double> meanLength_, extent_;
  std::vector<std::vector<double>> arcStart_; ///< per spec: reference arc at each segment start
  /// Current node positions (host, 2 per node; only the surface nodes' are kept current).
  std::vector<double> position_;
  std::vector<int> prescribed_;
  std::vector<SurfacePair> pairs_;
  std::vector<double> friction_;
  /// The last converged state. committedSegment, committedXi and committedGap (NaN when
  /// unknown: a restart file written before it was saved) are also the initial state's before
  /// anything is committed: where a node that closes in the next increment starts from.
  struct Saved {
    std::vector<ContactStatus> status;
    std::vector<int> anchorSegment, committedSegment;
    std::vector<double> anchorXi, committedXi, normalForce, tangentForce, committedGap;
  } saved_;
  /// Where on the target candidate k crossed it during the increment that closes it: the point
  /// a fraction g0 / (g0 - g) of the way from its projection at the last converged state (gap
  /// g0 > 0, saved_) to the current one (gap g < 0) along the target, when both lie on one
  /// segment or on two that share an end; farther apart, the point as far along the chord
  /// between them projected back onto the target; no crossing: the current projection.
  void crossingPoint(std::size_t k, int &segment, double &xi) const;
};

} // namespace mixcon
