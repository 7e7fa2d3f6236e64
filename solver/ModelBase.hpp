// What the linear displacement model and the mixed model share: the mesh and element data on the
// device, the displacement unknowns with their numbering, the reference external load (edge
// loads, body forces, nodal forces) and the prescribed displacements, staged on the host and
// copied to the device once. A load factor scales loads and prescribed values at solve time.
// The host-side interface (virtual, never called on the device) lets drivers run either model.
// Data flow: mesh -> kernels -> solver (this) -> io.
#pragma once

#include <kernels/LinearElasticity.hpp>
#include <solver/Checkpoint.hpp>
#include <solver/LinearSolver.hpp>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace mixcon {

class ModelBase {
public:
  using Exec = Kokkos::DefaultExecutionSpace;
  using Memory = DeviceSpace;

  /// `elementMaterial[e]` indexes `stiffness` (plane [C] in global axes); thickness t of Eq. (25).
  /// A 2D mesh (quadrilaterals).
  ModelBase(const Mesh &mesh, const std::vector<int> &elementMaterial,
            const std::vector<PlaneMatrix> &stiffness, double thickness);
  /// A 3D mesh (solids): `stiffness` is the 6 x 6 Voigt [C] of each material in global axes.
  ModelBase(const Mesh &mesh, const std::vector<int> &elementMaterial,
            const std::vector<SolidMatrix> &stiffness);
  virtual ~ModelBase() = default;
  ModelBase(const ModelBase &) = delete;
  ModelBase &operator=(const ModelBase &) = delete;

  const DofMap &dofs() const { return dofs_; }
  const Mesh &mesh() const { return mesh_; }
  int dim() const { return mesh_.dim(); } ///< spatial dimension: displacement unknowns per node

  /// Reference loads (all scaled by the load factor at solve time). Nodal forces and prescribed
  /// values are staged on the host and copied to the device once, in setup().
  /// A traction (per unit area, components beyond dim() ignored) and a pressure (positive into
  /// the body) on boundary sides: element edges in 2D (times the thickness), faces in 3D.
  void addSideLoad(const std::vector<BoundaryEdge> &sides, const std::array<double, 3> &traction,
                   double pressure);
  /// The 2D form of addSideLoad.
  void addEdgeLoad(const std::vector<BoundaryEdge> &edges, double tx, double ty, double pressure) {
    addSideLoad(edges, {tx, ty, 0.0}, pressure);
  }
  /// A force at a node (components beyond dim() ignored).
  void addNodalForce(LocalIndex node, const std::array<double, 3> &force);
  void addNodalForce(LocalIndex node, double fx, double fy) { addNodalForce(node, {fx, fy, 0.0}); }
  /// Body force per unit volume, evaluated on the host at each quadrature point (x, y, element).
  /// 2D meshes.
  void addBodyForce(const std::function<std::array<double, 2>(double, double, LocalIndex)> &f);
  /// The same in 3D: f(x, y, z, element).
  void
  addBodyForce3D(const std::function<std::array<double, 3>(double, double, double, LocalIndex)> &f);
  /// Prescribes component `comp` (0: x, 1: y, 2: z) of `node` (reference value, scaled too).
  void prescribe(LocalIndex node, int comp, double value);
  LocalIndex numConstrained() const;

  /// Throws InputError naming the mode when the prescribed components leave a body (a part of the
  /// mesh connected through elements) free to move as a rigid body: a translation or a rotation
  /// (three modes in 2D, six in 3D), whose stiffness is zero, so that the system is singular. The
  /// linear models call it in setup(); the contact models do not (a body may rest on obstacles).
  void checkRigidBodyModes() const { checkRigidBodyModes(constrainedHost_); }
  /// The same for the components flagged in `constrained` (one flag per displacement unknown, as
  /// constrainedFlags()): the supports of a later stage, checked before the first solve.
  void checkRigidBodyModes(const std::vector<int> &constrained) const;
  const std::vector<int> &constrainedFlags() const { return constrainedHost_; }
  /// Replaces the reference values of components prescribed before setup() (e.g. measured
  /// displacements that change from step to step) and copies them to the device.
  struct PrescribedValue {
    LocalIndex node;
    int comp;
    double value;
  };
  void updatePrescribed(const std::vector<PrescribedValue> &values);

  /// Solves for load factor lambda: loads lambda F, u = lambda g on constrained unknowns.
  virtual LinearSolveStats solve(double loadFactor) = 0;
  virtual double assemblySeconds() const = 0;
  virtual double solverSetupSeconds() const = 0;
  virtual std::string solverName() const = 0;

  Kokkos::View<double *, Memory> displacement() const { return u_; }
  /// Host copies for output.
  std::vector<double> displacementHost() const;
  /// Nodal stresses N x 3 in 2D, N x 6 in 3D (Voigt<Dim> order; displacement model: recovered
  /// from Gauss points; mixed model: the stress unknowns themselves).
  virtual std::vector<double> nodalStressHost() const = 0;
  /// Stresses C eps(u) at the quadrature points, computed from the displacements.
  virtual void gaussPointStressHost(std::vector<double> &coordinates, std::vector<double> &stress,
                                    int &pointsPerElement) const;
  /// Reactions (internal force - lambda F, N x dim()): support forces at constrained nodes, ~0
  /// elsewhere.
  virtual std::vector<double> reactionHost(double loadFactor) const = 0;

  /// Host vector of a device view.
  static std::vector<double> toHost(const Kokkos::View<const double *, Memory> &v);
  /// Copies a host vector into a device view of the same length (or a prefix of it).
  static void fromHost(const std::vector<double> &h, const Kokkos::View<double *, Memory> &v);
  /// Host vector of the length of `v` (`perNode` values per node) holding the values of `nodes`
  /// and 0 elsewhere: only those are copied (O(nodes), e.g. contact candidates).
  static std::vector<double> toHostAt(const Kokkos::View<const double *, Memory> &v, int perNode,
                                      const std::vector<LocalIndex> &nodes);

protected:
  // ---- Load histories (stages; public in NonlinearModel, whose driver runs them; the linear
  // models solve lambda times their loads): a stage moves every load and prescribed value from
  // where the previous stage ended (its base) to the values it names, linearly in its load factor
  // lambda in [0, 1]: applied = base + lambda * reference. A run without stages has no base.
  /// Begins a new stage after setup(): the prescribed values start from the current
  /// displacements of the constrained components (a support added now holds its node where it
  /// is), the reference loads are cleared. Then: the add* calls give the loads the stage starts
  /// from, loadsToBase() makes them the base, the add* calls that follow give the stage's change
  /// of the loads (end minus start), prescribe() the end values, release() frees components;
  /// commitStage() copies it all to the device.
  void beginStage();
  /// Moves the loads given since beginStage() into the base (they are the stage's start).
  void loadsToBase();
  /// Frees component `comp` of `node` for the new stage. The support force it carried,
  /// `reaction` (the component of reactionHost() at the end of the previous stage), joins the
  /// base and is ramped to zero over the stage, so that the stage starts in equilibrium.
  void release(LocalIndex node, int comp, double reaction);
  /// Copies the new stage's loads, constraints and prescribed values to the device.
  virtual void commitStage();
  /// The loads, constraints and prescribed values of the current stage (base and reference)
  /// into `state` under "loading/..." names (nothing without stages), and back: restoring makes
  /// a restarted run continue inside its stage as the uninterrupted one would (throws
  /// std::runtime_error when `state` does not fit).
  void saveLoading(Checkpoint &state) const;
  void restoreLoading(const Checkpoint &state);
  /// True once a stage has begun: the applied loads have a base.
  bool staged() const { return loadBase_.extent(0) > 0; }

  /// Copies the staged nodal forces (then clears them) and constraints to the device.
  void commitStaged();
  /// Host copy of internalForce - the applied load at `loadFactor` (the reactions).
  std::vector<double> reactionFrom(const Kokkos::View<const double *, Memory> &internalForce,
                                   double loadFactor) const;
  /// g -= the applied external load at lambda (base + lambda F) on the displacement unknowns of
  /// g (`stride` unknowns per node).
  void subtractLoad(const Kokkos::View<double *, Memory> &g, int stride, double lambda) const;
  /// ||base + lambda F||.
  double appliedLoadNorm(double lambda) const;
  /// What the models re-derive from the constraint flags when a stage changes them (the mixed
  /// models' flags over all unknowns).
  virtual void constraintsChanged() {}

  /// The reference node coordinates (N x dim()) of the mesh on the device.
  Kokkos::View<const double **, Memory> referenceCoordinates() const {
    if (dim() == 2)
      return data_.mesh.coordinates;
    return solid_.mesh.coordinates;
  }
  /// The element data of dimension Dim (the one of the mesh; the other is empty).
  template <int Dim> const ElementData<Memory, Dim> &elementData() const {
    if constexpr (Dim == 2)
      return data_;
    else
      return solid_;
  }

  Mesh const &mesh_;
  DofMap dofs_;
  ElementData<Memory> data_;            ///< 2D meshes (the 2D-only models use it directly)
  ElementData<Memory, 3> solid_;        ///< 3D meshes
  Kokkos::View<double *, Memory> load_; ///< reference external load F
  Kokkos::View<double *, Memory> u_;
  Kokkos::View<int *, Memory> isConstrained_;
  Kokkos::View<double *, Memory> prescribed_; ///< reference prescribed values (end - base)
  /// Stages: the loads and prescribed values the current stage starts from (empty without
  /// stages).
  Kokkos::View<double *, Memory> loadBase_, prescribedBase_;

private:
  /// Element data of dimension Dim and the per-unknown vectors (the constructors' common part).
  template <int Dim, class Stiffness>
  void initialize(ElementData<Memory, Dim> &data, const std::vector<int> &elementMaterial,
                  const std::vector<Stiffness> &stiffness, double thickness);

  std::vector<double> stagedNodalForce_; ///< host, added to load_ by commitStaged()
  std::vector<int> constrainedHost_;     ///< host staging of isConstrained_
  std::vector<double> prescribedHost_;   ///< host staging: end values of the prescribed unknowns
  std::vector<double> stagedBase_;       ///< stages: released support forces, added to the base
  /// Copies the prescribed reference values (end values, minus the base in a stage) to the device.
  void uploadPrescribed();
  /// Copies the constraint flags, then the prescribed values, to the device.
  void uploadConstraints();
  /// v += h (a host vector staged beside a device one: nodal forces, released support forces).
  static void addHost(const std::vector<double> &h, const Kokkos::View<double *, Memory> &v);
};

/// A new vector lambda * v (device).
Kokkos::View<double *, DeviceSpace> scaledCopy(const Kokkos::View<const double *, DeviceSpace> &v,
                                               double lambda);

/// Deep copy of a CSR matrix's values (structure shared).
template <class Memory> CsrMatrix<Memory> cloneValues(const CsrMatrix<Memory> &a) {
  CsrMatrix<Memory> b = a;
  b.values = Kokkos::View<double *, Memory>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::csr::values"), a.values.extent(0));
  Kokkos::deep_copy(b.values, a.values);
  return b;
}

} // namespace mixcon
