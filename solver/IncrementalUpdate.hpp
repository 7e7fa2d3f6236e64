// The end of an increment of the mixed models' incremental form, one function for 2D
// (NonlinearMixedModel) and 3D (SolidNonlinearMixedModel): the push-forward of the nodal stress
// (Eq. (5b), kernels/Nonlinear.hpp), the move of the configuration c1 and of the total
// displacement. Layer: solver.
#pragma once

#include <solver/FieldOps.hpp>
#include <solver/Krylov.hpp>
#include <solver/NonlinearModel.hpp>

#include <kernels/Nonlinear.hpp>

namespace mixcon::detail {

/// Commits the increment x (the mixed unknowns, LayoutOf<Elem>::kMixedUnknowns per node) taken
/// from c1 (mesh, thickness) with the nodal stress tau: tau <- F (tau + S) F^T / J by `update`
/// (Projected: the L2 projection onto the nodal stresses of c2 with the scalar mass `mass`,
/// made on `graph` when empty; NodalAverage: F averaged at the nodes), c1 <- c1 + u, displacement
/// (the total to c1, Dim per node) += u, x <- 0. `dispatch(f)` calls f(Elem{}) for the mesh's
/// element type. Where the projection fails (CommitFailure), c1, tau, displacement and x are as
/// they were: the projection runs on copies of c2 and tau, which replace them once it succeeded.
template <int Dim, class Dispatch>
void commitIncrementalState(const Dispatch &dispatch, const MeshView<DeviceSpace, Dim> &mesh,
                            double thickness, StressUpdate update, const NodeGraph &graph,
                            const Kokkos::View<int ***, Kokkos::LayoutRight, DeviceSpace> &map,
                            CsrMatrix<DeviceSpace> &mass, const fieldops::Vec &x,
                            const fieldops::Vec &tau, const fieldops::Vec &displacement) {
  using namespace fieldops;
  constexpr int stride = FieldLayout<Dim>::kMixedUnknowns;
  if (update == StressUpdate::Projected) {
    Vec load("mixcon::nonlinear::projectionLoad", tau.extent(0));
    dispatch([&](auto elem) {
      pushForwardProjectionLoad<decltype(elem)>(Exec(), mesh, thickness, ConstVec(tau), ConstVec(x),
                                                load);
    });
    MeshView<DeviceSpace, Dim> moved = mesh; // c2, on its own coordinates until accepted
    moved.coordinates = decltype(moved.coordinates)(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::nonlinear::c2"),
        mesh.coordinates.extent(0));
    movedCoordinates(mesh.coordinates, x, stride, moved.coordinates);
    if (mass.numRows == 0)
      mass = expandGraph<DeviceSpace>(graph, 1);
    Kokkos::deep_copy(mass.values, 0.0);
    dispatch([&](auto elem) {
      assembleScalarMass<decltype(elem)>(Exec(), moved, thickness, map, mass);
    });
    Vec projected("mixcon::nonlinear::projectedStress", tau.extent(0));
    Kokkos::deep_copy(projected, tau); // the previous stresses as the initial guess
    projectNodalComponents(mass, ConstVec(load), FieldLayout<Dim>::kNumStresses, projected);
    Kokkos::deep_copy(tau, projected);
    Kokkos::deep_copy(mesh.coordinates, moved.coordinates);
  } else {
    dispatch(
        [&](auto elem) { pushForwardNodalStress<decltype(elem)>(Exec(), mesh, ConstVec(x), tau); });
    movedCoordinates(mesh.coordinates, x, stride, mesh.coordinates);
  }
  Vec increment("mixcon::nonlinear::increment", displacement.extent(0));
  gather(x, stride, 0, Dim, increment);
  axpby(1.0, increment, 1.0, displacement);
  Kokkos::deep_copy(x, 0.0);
}

} // namespace mixcon::detail
