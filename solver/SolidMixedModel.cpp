// SolidMixedModel (solver/SolidMixedModel.hpp): host orchestration of device kernels. Layer:
// solver.
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/SolidMixedModel.hpp>

#include <kernels/Nonlinear.hpp>

#include <chrono>

namespace mixcon {

using namespace fieldops;

namespace {
constexpr int kUnknowns = FieldLayout<3>::kMixedUnknowns; // 9
constexpr int kStresses = FieldLayout<3>::kNumStresses;   // 6
constexpr int kStressOffset = FieldLayout<3>::kStressOffset;

std::vector<SolidMatrix> compliances(const std::vector<SolidMatrix> &stiffness) {
  std::vector<SolidMatrix> d(stiffness.size());
  for (std::size_t k = 0; k < stiffness.size(); ++k)
    if (!invertConstitutive(stiffness[k], d[k]))
      throw InputError("mixed model: the stiffness of material " + std::to_string(k) +
                       " is not positive definite");
  return d;
}
} // namespace

SolidMixedModel::SolidMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                                 const std::vector<SolidMatrix> &stiffness, double stabilization)
    : ModelBase(mesh, elementMaterial, stiffness), stabilization_(stabilization) {
  if (mesh.elementType != ElementType::Hex8 && mesh.elementType != ElementType::Hex20)
    throw InputError("the 3D mixed model takes hex8 or hex20 meshes so far (equal-order tet4 and "
                     "tet10 mixed elements are not checked yet); this mesh is " +
                     elementTypeName(mesh.elementType));
  if (!(stabilization >= 0.0 && stabilization < 1.0))
    throw InputError("mixed model: the stabilization must lie in [0, 1)");
  compliance_ = compliances(stiffness); // refuses a law without a compliance before any work
}

void SolidMixedModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  if (options.type != LinearSolverType::Direct)
    throw InputError("the 3D mixed model solves with solver: direct so far (its block-triangular "
                     "AMG solve is the next step of issue 17)");
  const auto start = std::chrono::steady_clock::now();
  checkRigidBodyModes();
  const LocalIndex nn = mesh_.numNodes();
  const NodeGraph graph = buildNodeGraph(mesh_);
  operator_ = expandGraph<Memory>(graph, kUnknowns);
  const auto map = elementScatterMap<Memory>(mesh_, graph);
  // The compliance D = C^-1 of each material next to its stiffness, on the device.
  Kokkos::View<SolidMatrix *, Memory> compliance("mixcon::mixed3d::compliance", compliance_.size());
  auto hd = hostMirror(compliance);
  for (std::size_t k = 0; k < compliance_.size(); ++k)
    hd(k) = compliance_[k];
  copyToDevice(compliance, hd);
  x_ = Kokkos::View<double *, Memory>("mixcon::mixed3d::unknowns", kUnknowns * nn);
  const Kokkos::View<double *, Memory> zero("mixcon::mixed3d::zero", kUnknowns * nn);
  const Kokkos::View<double *, Memory> tau("mixcon::mixed3d::prestress", kStresses * nn);
  Kokkos::View<double *, Memory> g("mixcon::mixed3d::residual", kUnknowns * nn);
  const auto assemble = [&](auto elem) { // the hexahedra (the constructor refuses the rest)
    using Elem = decltype(elem);
    const MixedIncrementLaw<Memory, 3> law{solid_.material, solid_.stiffness, compliance,
                                           stabilization_};
    return assembleNonlinearRows<kUnknowns, Elem>(
        Exec(), solid_.mesh,
        SolidMixedKernel<Elem, Memory>{solid_.mesh, law, Kokkos::View<const double *, Memory>(zero),
                                       Kokkos::View<const double *, Memory>(tau)},
        map, operator_, g);
  };
  const LocalIndex inverted =
      mesh_.elementType == ElementType::Hex8 ? assemble(Hex8{}) : assemble(Hex20{});
  if (inverted >= 0)
    throw InputError("mixed model: element " + std::to_string(mesh_.elementId(inverted)) + " of " +
                     mesh_.source + " is inverted (non-positive Jacobian)");
  commitStaged();
  flags_ = Kokkos::View<int *, Memory>("mixcon::mixed3d::constrained", kUnknowns * nn);
  scatter<int>(isConstrained_, kUnknowns, 0, dim(), flags_, true);
  rhs_ = Kokkos::View<double *, Memory>("mixcon::mixed3d::rhs", kUnknowns * nn);
  Exec().fence();
  assemblySeconds_ = seconds(start);
  // Symmetric but indefinite: Eigen's supernodal LU (measured 3.3 s against 13.0 s for the
  // simplicial LDL^T on the 9,801 unknowns of examples/lame_sphere.yaml as Hex20 mixed), which
  // also takes a = 0, whose zero displacement block has no LDL^T without pivoting.
  LinearSolverOptions o = options;
  o.symmetric = false;
  solver_ = makeLinearSolver(o, DofMap::serial(nn, kUnknowns), comm);
  // The constrained system of load factor 1 (F on the displacement rows, the prescribed values
  // g), factorized once: loads and prescribed values scale with the load factor, so its
  // right-hand side does too (as in LinearDisplacementModel).
  constrained_ = cloneValues(operator_);
  Kokkos::View<double *, Memory> target("mixcon::mixed3d::target", kUnknowns * nn);
  prescribedStep(flags_, prescribed_, zero, 1.0, kUnknowns, dim(), target);
  addDisplacementVector(rhs_, kUnknowns, dim(), 1.0, load_);
  applyDirichlet(Exec(), constrained_, Kokkos::View<const int *, Memory>(flags_),
                 Kokkos::View<const double *, Memory>(target), rhs_);
  solver_->setup(constrained_);
}

LinearSolveStats SolidMixedModel::solve(double loadFactor) {
  const LinearSolveStats s = solver_->solve(scaledCopy(rhs_, loadFactor), x_);
  gather(x_, kUnknowns, 0, dim(), u_);
  return s;
}

std::vector<double> SolidMixedModel::nodalStressHost() const {
  Kokkos::View<double *, Memory> s("mixcon::mixed3d::stress", kStresses * mesh_.numNodes());
  gather(x_, kUnknowns, kStressOffset, kStresses, s);
  return toHost(s);
}

std::vector<double> SolidMixedModel::reactionHost(double loadFactor) const {
  Kokkos::View<double *, Memory> f("mixcon::mixed3d::internalForce", dim() * mesh_.numNodes());
  multiplyFieldRows(operator_, kUnknowns, 0, dim(), x_, f);
  return reactionFrom(f, loadFactor);
}

} // namespace mixcon
