// SolidMixedModel (solver/SolidMixedModel.hpp): host orchestration of device kernels. Layer:
// solver.
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/SolidMixedModel.hpp>
#include <solver/SolidMixedSolve.hpp>

#include <kernels/Nonlinear.hpp>

#include <algorithm>
#include <chrono>

namespace mixcon {

using namespace fieldops;

namespace {
constexpr int kUnknowns = FieldLayout<3>::kMixedUnknowns; // 9
constexpr int kStresses = FieldLayout<3>::kNumStresses;   // 6
constexpr int kStressOffset = FieldLayout<3>::kStressOffset;
} // namespace

namespace detail {
void checkSolidMixedElement(const Mesh &mesh) {
  if (spatialDimension(mesh.elementType) != 3)
    throw InputError("the 3D mixed model takes hexahedra or tetrahedra; this mesh is " +
                     elementTypeName(mesh.elementType));
}

std::vector<SolidMatrix> solidCompliances(const std::vector<SolidMatrix> &stiffness) {
  std::vector<SolidMatrix> d(stiffness.size());
  for (std::size_t k = 0; k < stiffness.size(); ++k)
    if (!invertConstitutive(stiffness[k], d[k]))
      throw InputError("mixed model: the stiffness of material " + std::to_string(k) +
                       " is not positive definite");
  return d;
}

Kokkos::View<SolidMatrix *, DeviceSpace> deviceMatrices(const std::vector<SolidMatrix> &m,
                                                        const char *label) {
  Kokkos::View<SolidMatrix *, DeviceSpace> v(std::string(label), m.size());
  auto h = hostMirror(v);
  for (std::size_t k = 0; k < m.size(); ++k)
    h(k) = m[k];
  copyToDevice(v, h);
  return v;
}
} // namespace detail

SolidMixedModel::SolidMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                                 const std::vector<SolidMatrix> &stiffness, double stabilization)
    : ModelBase(mesh, elementMaterial, stiffness), stabilization_(stabilization) {
  detail::checkSolidMixedElement(mesh);
  if (!(stabilization >= 0.0 && stabilization < 1.0))
    throw InputError("mixed model: the stabilization must lie in [0, 1)");
  compliance_ =
      detail::solidCompliances(stiffness); // refuses a law without a compliance before any work
}

SolidMixedModel::~SolidMixedModel() = default;

double SolidMixedModel::solverSetupSeconds() const {
  return (iterative_ ? iterative_->setupSeconds() : 0.0) +
         (solver_ ? solver_->setupSeconds() : 0.0);
}

std::string SolidMixedModel::solverName() const {
  // After a fall back the LU solves.
  return solver_ ? solver_->name() : iterative_ ? iterative_->name() : std::string();
}

void SolidMixedModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  const auto start = std::chrono::steady_clock::now();
  checkRigidBodyModes();
  const LocalIndex nn = mesh_.numNodes();
  const NodeGraph graph = buildNodeGraph(mesh_);
  // solver: amg, jacobian: matrix_free or large enough (solidJacobianWithoutMatrix): the operator
  // is applied without its matrix.
  const bool withoutMatrix =
      options.type == LinearSolverType::Amg &&
      solidJacobianWithoutMatrix(jacobian_, static_cast<long>(kUnknowns) * nn);
  operator_ = withoutMatrix ? CsrMatrix<Memory>{} : expandGraph<Memory>(graph, kUnknowns);
  iterative_.reset(); // holds the products of matrixFree_
  matrixFree_.reset();
  const auto map = elementScatterMap<Memory>(mesh_, graph);
  const auto compliance = detail::deviceMatrices(compliance_, "mixcon::mixed3d::compliance");
  x_ = Kokkos::View<double *, Memory>("mixcon::mixed3d::unknowns", kUnknowns * nn);
  const Kokkos::View<double *, Memory> zero("mixcon::mixed3d::zero", kUnknowns * nn);
  const Kokkos::View<double *, Memory> tau("mixcon::mixed3d::prestress", kStresses * nn);
  Kokkos::View<double *, Memory> g("mixcon::mixed3d::residual", kUnknowns * nn);
  const auto assemble = [&](auto elem) {
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
      dispatchSolidElement(mesh_.elementType, "the 3D mixed model", assemble);
  if (inverted >= 0)
    throw InputError("mixed model: element " + std::to_string(mesh_.elementId(inverted)) + " of " +
                     mesh_.source + " is inverted (non-positive Jacobian)");
  commitStaged();
  flags_ = Kokkos::View<int *, Memory>("mixcon::mixed3d::constrained", kUnknowns * nn);
  scatter<int>(isConstrained_, kUnknowns, 0, dim(), flags_, true);
  rhs_ = Kokkos::View<double *, Memory>("mixcon::mixed3d::rhs", kUnknowns * nn);
  Exec().fence();
  assemblySeconds_ = seconds(start);
  Kokkos::View<double *, Memory> target("mixcon::mixed3d::target", kUnknowns * nn);
  prescribedStep(flags_, prescribed_, zero, 1.0, kUnknowns, dim(), target);
  addDisplacementVector(rhs_, kUnknowns, dim(), 1.0, load_);
  target_ = target;
  options_ = options;
  comm_ = comm;
  if (options.type == LinearSolverType::Amg) {
    // The block-triangular solve on the unconstrained operator (F and g of load factor 1 kept),
    // K^L of the reference configuration for the AMG.
    Kokkos::View<double **, Memory> positions("mixcon::mixed3d::positions", nn, dim());
    Kokkos::deep_copy(positions, referenceCoordinates());
    iterative_ = std::make_unique<SolidMixedSolve>(
        graph, options, preconditionerTolerance_, restart_, dofs_, comm, positions, !withoutMatrix);
    iterative_->zeroStiffness();
    dispatchSolidElement(mesh_.elementType, "the 3D mixed model", [&](auto elem) {
      assembleLinearStiffness<decltype(elem)>(Exec(), solid_, map, iterative_->stiffness());
    });
    if (withoutMatrix) { // the incremental law at x = 0 without prestress: the linear operator
      matrixFree_ =
          std::make_unique<SolidMixedMatrixFree>(mesh_, solid_, compliance, stabilization_, false);
      const auto pointStart = std::chrono::steady_clock::now();
      matrixFree_->update(ConstVec(zero));
      assemblySeconds_ += seconds(pointStart); // the point matrices are its assembly
      iterative_->refresh(matrixFree_->operators(), isConstrained_);
    } else {
      iterative_->refresh(operator_, isConstrained_);
    }
  } else {
    setupDirect();
  }
}

void SolidMixedModel::setupDirect() {
  // Symmetric but indefinite: the LU (UMFPACK; Eigen's supernodal LU before it measured 3.3 s
  // against 13.0 s for the simplicial LDL^T on the 9,801 unknowns of examples/lame_sphere.yaml
  // as Hex20 mixed), which also takes a = 0, whose zero displacement block has no LDL^T
  // without pivoting.
  LinearSolverOptions o = options_;
  o.type = LinearSolverType::Direct;
  o.symmetric = false;
  o.indefinite = true;
  solver_ = makeLinearSolver(o, DofMap::serial(mesh_.numNodes(), kUnknowns), comm_);
  // The constrained system of load factor 1 (F on the displacement rows, the prescribed values
  // g), factorized once: loads and prescribed values scale with the load factor, so its
  // right-hand side does too (as in LinearDisplacementModel).
  constrained_ = cloneValues(operator_);
  constrainedRhs_ =
      Kokkos::View<double *, Memory>("mixcon::mixed3d::constrainedRhs", rhs_.extent(0));
  Kokkos::deep_copy(constrainedRhs_, rhs_);
  applyDirichlet(Exec(), constrained_, Kokkos::View<const int *, Memory>(flags_),
                 Kokkos::View<const double *, Memory>(target_), constrainedRhs_);
  solver_->setup(constrained_);
}

LinearSolveStats SolidMixedModel::solve(double loadFactor) {
  LinearSolveStats s;
  std::string note;
  if (iterative_ && !solver_) {
    const long unknowns = static_cast<long>(kUnknowns) * mesh_.numNodes();
    const bool fallback =
        !matrixFree_ &&
        directFallbackFits(comm_, unknowns,
                           std::min(options_.directFallbackUnknowns, kSolidMixedDirectFallback));
    s = iterative_->solve(
        flags_, isConstrained_, scaledCopy(rhs_, loadFactor), scaledCopy(target_, loadFactor), x_,
        luWhenCheaper(fallback && options_.directWhenCheaper, operatorCost_, operator_,
                      std::chrono::steady_clock::now(), "the block-triangular solve"));
    note = s.note; // the AMG's ladder steps
    if (!s.converged && fallback) {
      appendNote(note, "the block-triangular solve did not converge (relative residual " +
                           std::to_string(s.relativeResidual) +
                           "): falling back to the direct LU (" + std::to_string(unknowns) +
                           " unknowns)");
      setupDirect();
    }
  }
  if (solver_) {
    const int iterations = s.iterations;
    s = solver_->solve(scaledCopy(constrainedRhs_, loadFactor), x_);
    s.iterations += iterations;
    appendNote(note, s.note);
    s.note = note;
  }
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
  if (matrixFree_) {
    Kokkos::View<double *, Memory> y("mixcon::mixed3d::operatorTimesSolution", x_.extent(0));
    matrixFree_->applyJacobian(x_, y);
    gather(ConstVec(y), kUnknowns, 0, dim(), f);
  } else {
    multiplyFieldRows(operator_, kUnknowns, 0, dim(), x_, f);
  }
  return reactionFrom(f, loadFactor);
}

} // namespace mixcon
