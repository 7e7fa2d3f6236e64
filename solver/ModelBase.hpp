// What the linear displacement model and the mixed model share: the mesh and element data on the
// device, the displacement unknowns with their numbering, the reference external load (edge
// loads, body forces, nodal forces) and the prescribed displacements, staged on the host and
// copied to the device once. A load factor scales loads and prescribed values at solve time.
// The host-side interface (virtual, never called on the device) lets drivers run either model.
// Data flow: mesh -> kernels -> solver (this) -> io.
#pragma once

#include <kernels/LinearElasticity.hpp>
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
  ModelBase(const Mesh &mesh, const std::vector<int> &elementMaterial,
            const std::vector<PlaneMatrix> &stiffness, double thickness);
  virtual ~ModelBase() = default;
  ModelBase(const ModelBase &) = delete;
  ModelBase &operator=(const ModelBase &) = delete;

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
  /// Throws InputError naming the mode when the prescribed components leave a body (a part of the
  /// mesh connected through elements) free to move as a rigid body: a translation in x or y or a
  /// rotation, whose stiffness is zero, so that the system is singular. The linear models call
  /// it in setup(); the contact models do not (a body may rest on obstacles).
  void checkRigidBodyModes() const;
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
  /// Nodal stresses N x 3 (displacement model: recovered from Gauss points; mixed model: the
  /// stress unknowns themselves).
  virtual std::vector<double> nodalStressHost() const = 0;
  /// Stresses C eps(u) at the quadrature points, computed from the displacements.
  virtual void gaussPointStressHost(std::vector<double> &coordinates, std::vector<double> &stress,
                                    int &pointsPerElement) const;
  /// Reactions (internal force - lambda F, N x 2): support forces at constrained nodes, ~0
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
  /// Copies the staged nodal forces (then clears them) and constraints to the device.
  void commitStaged();
  /// Host copy of internalForce - lambda F (the reactions).
  std::vector<double> reactionFrom(const Kokkos::View<const double *, Memory> &internalForce,
                                   double loadFactor) const;

  Mesh const &mesh_;
  DofMap dofs_;
  ElementData<Memory> data_;
  Kokkos::View<double *, Memory> load_; ///< reference external load F
  Kokkos::View<double *, Memory> u_;
  Kokkos::View<int *, Memory> isConstrained_;
  Kokkos::View<double *, Memory> prescribed_;

private:
  std::vector<double> stagedNodalForce_; ///< host, added to load_ by commitStaged()
  std::vector<int> constrainedHost_;     ///< host staging of isConstrained_
  std::vector<double> prescribedHost_;   ///< host staging of prescribed_
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
