// LinearDisplacementModel: host orchestration of device kernels.
#include <core/Transfer.hpp>
#include <solver/DisplacementModel.hpp>

#include <chrono>

namespace mixcon {

void LinearDisplacementModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  const auto start = std::chrono::steady_clock::now();
  checkRigidBodyModes(); // before assembly: a singular system is refused, naming the free mode
  if (stiffness_.numRows == 0) {
    graph_ = buildNodeGraph(mesh_);
    stiffness_ = expandGraph<Memory>(graph_, dofs_.dofsPerNode);
    const auto map = elementScatterMap<Memory>(mesh_, graph_);
    dispatchElement(mesh_.elementType, [&](auto elem) {
      assembleLinearStiffness<decltype(elem)>(Exec(), data_, map, stiffness_);
    });
  }
  commitStaged();
  constrained_ = cloneValues(stiffness_);
  rhs_ = Kokkos::View<double *, Memory>("mixcon::model::rhs", load_.extent(0));
  Kokkos::deep_copy(rhs_, load_);
  applyDirichlet(Exec(), constrained_, Kokkos::View<const int *, Memory>(isConstrained_),
                 Kokkos::View<const double *, Memory>(prescribed_), rhs_);
  Exec().fence();
  assemblySeconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  solver_ = makeLinearSolver(options, dofs_, comm);
  solver_->setNearNullSpace(data_.mesh.coordinates);
  solver_->setup(constrained_);
}

LinearSolveStats LinearDisplacementModel::solve(double loadFactor) {
  return solver_->solve(scaledCopy(rhs_, loadFactor), u_);
}

std::vector<double> LinearDisplacementModel::nodalStressHost() const {
  constexpr int kStress = ModelLayout::kNumStresses;
  Kokkos::View<double *[kStress], Memory> s("mixcon::model::nodalStress", mesh_.numNodes());
  dispatchElement(mesh_.elementType, [&](auto elem) {
    nodalStressRecovery<decltype(elem)>(Exec(), data_, Kokkos::View<const double *, Memory>(u_), s);
  });
  auto h = copyToHost(s);
  std::vector<double> out(kStress * static_cast<std::size_t>(mesh_.numNodes()));
  for (LocalIndex n = 0; n < mesh_.numNodes(); ++n)
    for (int c = 0; c < kStress; ++c)
      out[kStress * n + c] = h(n, c);
  return out;
}

std::vector<double> LinearDisplacementModel::reactionHost(double loadFactor) const {
  Kokkos::View<double *, Memory> f("mixcon::model::internalForce", u_.extent(0));
  dispatchElement(mesh_.elementType, [&](auto elem) {
    assembleInternalForce<decltype(elem)>(Exec(), data_, Kokkos::View<const double *, Memory>(u_),
                                          f);
  });
  return reactionFrom(f, loadFactor);
}

} // namespace mixcon
