// LinearDisplacementModel: host orchestration of device kernels.
#include <core/Transfer.hpp>
#include <solver/DisplacementModel.hpp>

#include <chrono>

namespace mixcon {

CsrMatrix<LinearDisplacementModel::Memory> LinearDisplacementModel::assembleStiffness() const {
  NodeGraph own; // before the first setup, which keeps the graph
  const NodeGraph &graph = graph_.rowOffsets.empty() ? (own = buildNodeGraph(mesh_)) : graph_;
  CsrMatrix<Memory> k = expandGraph<Memory>(graph, dofs_.dofsPerNode);
  const auto map = elementScatterMap<Memory>(mesh_, graph);
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    assembleLinearStiffness<Elem>(Exec(), elementData<Elem::kDim>(), map, k);
  });
  return k;
}

void LinearDisplacementModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  const auto start = std::chrono::steady_clock::now();
  checkRigidBodyModes(); // before assembly: a singular system is refused, naming the free mode
  if (graph_.rowOffsets.empty())
    graph_ = buildNodeGraph(mesh_);
  // One copy of K^L: the constraints are applied to it in place (reactions come from the
  // element internal forces, not from K^L), so a later setup assembles it again. An unconstrained
  // copy beside it was 1/4 of the peak memory of the 3.1M-unknown cube (docs/performance.md).
  solver_.reset(); // the solver holds the last constrained matrix: released before the new one
  stiffness_ = assembleStiffness();
  commitStaged();
  rhs_ = Kokkos::View<double *, Memory>("mixcon::model::rhs", load_.extent(0));
  Kokkos::deep_copy(rhs_, load_);
  applyDirichlet(Exec(), stiffness_, Kokkos::View<const int *, Memory>(isConstrained_),
                 Kokkos::View<const double *, Memory>(prescribed_), rhs_);
  Exec().fence();
  assemblySeconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  solver_ = makeLinearSolver(options, dofs_, comm);
  solver_->setNearNullSpace(referenceCoordinates());
  solver_->setup(stiffness_);
}

LinearSolveStats LinearDisplacementModel::solve(double loadFactor) {
  return solver_->solve(scaledCopy(rhs_, loadFactor), u_);
}

std::vector<double> LinearDisplacementModel::nodalStressHost() const {
  return dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    // The extent from Elem, not a local constant (nvcc 13, docs/gpu.md).
    Kokkos::View<double * [Voigt<Elem::kDim>::kSize], Memory> s("mixcon::model::nodalStress",
                                                                mesh_.numNodes());
    const Kokkos::View<const double *, Memory> u(u_);
    if constexpr (Elem::kDim == 2)
      nodalStressRecovery<Elem>(Exec(), data_, u, s);
    else
      solidNodalStressRecovery<Elem>(Exec(), solid_, u, s);
    return toHostVector(s);
  });
}

std::vector<double> LinearDisplacementModel::reactionHost(double loadFactor) const {
  Kokkos::View<double *, Memory> f("mixcon::model::internalForce", u_.extent(0));
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    assembleInternalForce<Elem>(Exec(), elementData<Elem::kDim>(),
                                Kokkos::View<const double *, Memory>(u_), f);
  });
  return reactionFrom(f, loadFactor);
}

} // namespace mixcon
