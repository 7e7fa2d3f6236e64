// MixedModel: assembly of the mixed blocks, the direct saddle-point solve, the Schur-complement
// Krylov solve (assembled lumped S_a, or matrix-free with consistent M), the block-triangular
// preconditioned GMRES on the whole saddle point, stress recovery.
#include <core/Transfer.hpp>
#include <solver/BlockTriangular.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/HostAlgebra.hpp>
#include <solver/MixedModel.hpp>
#include <solver/Rules.hpp>

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace mixcon {

namespace {
double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

} // namespace

/// The saddle-point system on the host: unknowns [u (2N); S (3N)], sparse LU.
struct MixedModel::Direct {
  HostSparseLu lu;
  std::vector<double> rhs; ///< for lambda = 1, constraints eliminated
};

MixedModel::MixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                       const std::vector<PlaneMatrix> &stiffness, double thickness,
                       ElementType stressElement)
    : ModelBase(mesh, elementMaterial, stiffness, thickness) {
  checkMixedPairing(mesh.elementType, stressElement);
  mixed_ = withCompliance(data_, stiffness);
  s_ = Kokkos::View<double *, Memory>("mixcon::mixed::stress", 3 * mesh.numNodes());
}

MixedModel::~MixedModel() = default;

MixedElementData<DeviceSpace> withCompliance(const ElementData<DeviceSpace> &d,
                                             const std::vector<PlaneMatrix> &stiffness) {
  MixedElementData<DeviceSpace> m;
  static_cast<ElementData<DeviceSpace> &>(m) = d;
  m.compliance =
      Kokkos::View<PlaneMatrix *, DeviceSpace>("mixcon::mixed::compliance", stiffness.size());
  auto h = hostMirror(m.compliance);
  for (std::size_t i = 0; i < stiffness.size(); ++i) {
    if (!isPositiveDefinite(stiffness[i]) || invert3(stiffness[i], h(i)) <= 0.0)
      throw InputError("material " + std::to_string(i) +
                       ": the plane constitutive matrix [C] is not positive definite, so the "
                       "mixed model has no compliance D = C^-1");
  }
  copyToDevice(m.compliance, h);
  return m;
}

// Measured rule: see the declaration (solver/MixedModel.hpp) and docs/performance.md.
MixedOperatorForm resolveOperatorForm(MixedOperatorForm requested, ElementType type,
                                      LocalIndex numElements) {
  if (requested != MixedOperatorForm::Auto)
    return requested;
  return type == ElementType::Quad8 && numElements >= 10000 ? MixedOperatorForm::PartialAssembly
                                                            : MixedOperatorForm::Assembled;
}

// Measured rule: see the declaration (solver/MixedModel.hpp) and docs/performance.md.
MixedLinearMethod resolveLinearMethod(MixedLinearMethod requested, ComplianceMass compliance) {
  if (requested != MixedLinearMethod::Auto)
    return requested;
  return compliance == ComplianceMass::Consistent ? MixedLinearMethod::BlockTriangular
                                                  : MixedLinearMethod::Schur;
}

void MixedModel::setInitialStress(const std::vector<double> &tau) {
  if (tau.size() != 3 * static_cast<std::size_t>(mesh_.numNodes()))
    throw std::invalid_argument("MixedModel::setInitialStress: expected 3 values per node");
  initialStress_ = tau;
}

Kokkos::View<double *, MixedModel::Memory> MixedModel::initialStressOnDevice() const {
  Kokkos::View<double *, Memory> tau("mixcon::mixed::initialStress", s_.extent(0));
  if (!initialStress_.empty()) {
    auto h = hostMirror(tau);
    for (std::size_t i = 0; i < initialStress_.size(); ++i)
      h(i) = initialStress_[i];
    copyToDevice(tau, h);
  }
  return tau;
}

std::string MixedModel::solverName() const {
  std::ostringstream s;
  s << "mixed " << (options_.compliance == ComplianceMass::Consistent ? "consistent" : "lumped")
    << " M, a = " << options_.stabilization << ", ";
  const char *amg = options_.preconditioner == SchurPreconditioner::LumpedSchur ? "S_a,L" : "Kd";
  const std::string coarse = coarseSpacePhrase(amg_.get());
  if (options_.linear.type == LinearSolverType::Direct) {
    s << "direct saddle-point LU (UMFPACK)";
  } else if (method_ == MixedLinearMethod::BlockTriangular) {
    s << "flexible GMRES on the saddle point, block-triangular preconditioner (BoomerAMG(" << amg
      << ")" << coarse << ", ";
    if (options_.compliance == ComplianceMass::Consistent)
      s << "CG on M to " << options_.preconditionerTolerance << " or tighter)";
    else
      s << "lumped M)";
  } else {
    s << (options_.krylov == KrylovMethod::Cg ? "flexible CG" : "flexible GMRES")
      << (options_.compliance == ComplianceMass::Consistent ? " on matrix-free S_a" : " on S_a,L")
      << " + BoomerAMG(" << amg << ")" << coarse;
  }
  s << ", K12/M "
    << (form_ == MixedOperatorForm::Assembled         ? "assembled"
        : form_ == MixedOperatorForm::PartialAssembly ? "by partial assembly"
                                                      : "matrix-free");
  return s.str();
}

void MixedModel::setup(const MixedOptions &options, MPI_Comm comm) {
  if (const auto why = rules::stabilizationRange(options.stabilization))
    throw InputError("mixed model: " + *why + ", got " + std::to_string(options.stabilization));
  if (const auto why = rules::lumpedCompliance(options.compliance, mesh_.elementType))
    throw InputError("mixed model: " + *why);
  checkRigidBodyModes(); // a singular system is refused before assembly, naming the free mode
  options_ = options;
  method_ = resolveLinearMethod(options_.method, options_.compliance);
  if (options_.preconditioner == SchurPreconditioner::Auto)
    options_.preconditioner = options_.compliance == ComplianceMass::Lumped
                                  ? SchurPreconditioner::LumpedSchur
                                  : SchurPreconditioner::Stiffness;
  const double a = options.stabilization;
  const auto start = std::chrono::steady_clock::now();
  commitStaged();
  graph_ = buildNodeGraph(mesh_);
  const auto dgraph = toDevice<Memory>(graph_);
  const auto map = elementScatterMap<Memory>(mesh_, graph_);
  const auto tau = initialStressOnDevice();
  form_ = resolveOperatorForm(options_.operators, mesh_.elementType, mesh_.numElements());
  // The assembled coupling is needed by the lumped-Schur preconditioner whatever the form.
  const bool assembleBlocks = form_ == MixedOperatorForm::Assembled ||
                              (options_.linear.type != LinearSolverType::Direct &&
                               options_.preconditioner == SchurPreconditioner::LumpedSchur);
  if (form_ != MixedOperatorForm::Assembled)
    matrixFree_ =
        makeMixedMatrixFree(Exec(), mixed_, mesh_, form_ == MixedOperatorForm::PartialAssembly);
  dispatchPlaneElement(mesh_.elementType, "the mixed model", [&](auto elem) {
    using Elem = decltype(elem);
    ops_ = assembleBlocks ? assembleMixedOperators<Elem>(Exec(), mixed_, dgraph, map)
                          : assembleLumpedCompliance<Elem>(Exec(), mixed_, mesh_.numNodes());
    // a Kd + K11 on the node graph: the part of S_a that is not K12 M^-1 K12^T.
    stiffness_ = expandGraph<Memory>(graph_, 2);
    if (a > 0.0)
      assembleLinearStiffness<Elem>(Exec(), data_, map, stiffness_, a);
    if (!initialStress_.empty())
      assembleMixedGeometricStiffness<Elem>(Exec(), data_, ConstDeviceVector(tau), map, stiffness_);
  });
  constrainedDiagonal_ = Kokkos::View<double *, Memory>("mixcon::mixed::diagC", u_.extent(0));
  workStressRhs_ = DeviceVector("mixcon::mixed::workStressRhs", s_.extent(0));
  workStress_ = DeviceVector("mixcon::mixed::workStress", s_.extent(0));
  Exec().fence();
  assemblySeconds_ = secondsSince(start);

  if (options_.linear.type == LinearSolverType::Direct) {
    const auto t = std::chrono::steady_clock::now();
    setupDirect();
    solverSetupSeconds_ = secondsSince(t);
    return;
  }

  // Preconditioner matrix: (1-a) K12 M_L^-1 K12^T + a Kd on the second-neighbour graph, or Kd on
  // the node graph. K11 stays out: a compressive prestress makes it indefinite, and BoomerAMG on
  // an indefinite matrix diverges, while GMRES deals with the few negative eigenvalues K11 adds
  // to the SPD-preconditioned operator.
  const auto t = std::chrono::steady_clock::now();
  if (options_.preconditioner == SchurPreconditioner::LumpedSchur) {
    const NodeGraph g2 = secondNeighbourGraph(graph_);
    precMatrix_ = expandGraph<Memory>(g2, 2);
    const auto map2 = elementScatterMap<Memory>(mesh_, g2);
    assembleLumpedSchur(Exec(), ops_, 1.0 - a, precMatrix_);
    dispatchPlaneElement(mesh_.elementType, "the mixed model", [&](auto elem) {
      using Elem = decltype(elem);
      if (a > 0.0)
        assembleLinearStiffness<Elem>(Exec(), data_, map2, precMatrix_, a);
    });
  } else {
    precMatrix_ = expandGraph<Memory>(graph_, 2);
    dispatchPlaneElement(mesh_.elementType, "the mixed model", [&](auto elem) {
      assembleLinearStiffness<decltype(elem)>(Exec(), data_, map, precMatrix_);
    });
  }
  Kokkos::View<double *, Memory> dummy("mixcon::mixed::dummyRhs", u_.extent(0));
  applyDirichlet(Exec(), precMatrix_, Kokkos::View<const int *, Memory>(isConstrained_),
                 ConstDeviceVector(prescribed_), dummy);
  constrainedDiagonal(Exec(), precMatrix_, Kokkos::View<const int *, Memory>(isConstrained_),
                      constrainedDiagonal_);
  Exec().fence();
  assemblySeconds_ += secondsSince(t);
  amg_ = makeLinearSolver(options_.linear, dofs_, comm);
  amg_->setNearNullSpace(data_.mesh.coordinates);
  amg_->setup(precMatrix_);
  solverSetupSeconds_ = amg_->setupSeconds();
  if (method_ == MixedLinearMethod::BlockTriangular)
    setupBlockTriangular();
}

namespace {
/// dm(i) = diagonal of the lumped nodal compliance blocks, stress unknown by stress unknown. A free
/// function: nvcc refuses an extended lambda inside a private member function.
template <class Lumped> void lumpedStressDiagonal(const Lumped &lumped, const DeviceVector &dm) {
  using fieldops::kStress;
  Kokkos::parallel_for(
      "mixcon::mixed::lumpedDiagonal", Kokkos::RangePolicy<fieldops::Exec>(0, dm.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { dm(i) = lumped(i / kStress, i % kStress, i % kStress); });
}
} // namespace

void MixedModel::setupBlockTriangular() {
  using namespace fieldops;
  const std::size_t nn = mesh_.numNodes();
  constrained5_ = Kokkos::View<int *, Memory>("mixcon::mixed::constrained5", kMixed * nn);
  constrainedDiagonal5_ = Kokkos::View<double *, Memory>("mixcon::mixed::diagC5", kMixed * nn);
  scatter<int>(isConstrained_, kMixed, 0, kDisp, constrained5_, true);
  scatter<double>(constrainedDiagonal_, kMixed, 0, kDisp, constrainedDiagonal5_, true);
  // The stress-row scale from the diagonals of the AMG matrix and of M (the lumped blocks' stand
  // for the consistent M's: the same order, and no assembled consistent M on every path).
  DeviceVector da("mixcon::mixed::diagS", kDisp * nn), dm("mixcon::mixed::diagM", kStress * nn);
  fieldDiagonal(precMatrix_, 1, 0, 1, da, 1.0);
  lumpedStressDiagonal(ops_.lumped, dm);
  stressRowScale_ = blockTriangularScale(ConstDeviceVector(da), ConstDeviceVector(dm));
  splitU_ = DeviceVector("mixcon::mixed::splitU", kDisp * nn);
  splitJu_ = DeviceVector("mixcon::mixed::splitJu", kDisp * nn);
  splitS_ = DeviceVector("mixcon::mixed::splitS", kStress * nn);
  splitJs_ = DeviceVector("mixcon::mixed::splitJs", kStress * nn);
  Exec().fence();
}

void MixedModel::applyCouplingTransposeBlock(const ConstDeviceVector &u,
                                             const DeviceVector &r) const {
  if (form_ == MixedOperatorForm::Assembled)
    applyCouplingTranspose(Exec(), ops_, u, r);
  else
    applyCouplingTranspose(Exec(), matrixFree_, u, r);
}

void MixedModel::applyCouplingBlock(double alpha, const ConstDeviceVector &s, double beta,
                                    const DeviceVector &f) const {
  if (form_ == MixedOperatorForm::Assembled)
    applyCoupling(Exec(), ops_, alpha, s, beta, f);
  else
    applyCoupling(Exec(), matrixFree_, alpha, s, beta, f);
}

void MixedModel::applyComplianceBlock(const ConstDeviceVector &x, const DeviceVector &y) const {
  if (form_ == MixedOperatorForm::Assembled)
    applyCompliance(Exec(), ops_, x, y);
  else
    applyCompliance(Exec(), matrixFree_, x, y);
}

void MixedModel::applyComplianceInverse(const ConstDeviceVector &r, const DeviceVector &s) {
  innerIterations_ += solveCompliance(r, s, options_.innerTolerance);
}

long MixedModel::solveCompliance(const ConstDeviceVector &r, const DeviceVector &s,
                                 double tolerance, double acceptable) {
  if (options_.compliance == ComplianceMass::Lumped) {
    applyNodalBlocks(Exec(), ops_.lumpedInverse, r, s);
    return 0;
  }
  KrylovOptions o;
  o.method = KrylovMethod::Cg;
  o.tolerance = tolerance;
  o.maxIterations = options_.innerMaxIterations;
  o.exactOperator = true; // M applied exactly: no true-residual product at start and end
  Kokkos::deep_copy(s, 0.0);
  const auto st = krylovSolve(
      o, [&](const ConstDeviceVector &x, const DeviceVector &y) { applyComplianceBlock(x, y); },
      [&](const ConstDeviceVector &x, const DeviceVector &y) {
        applyNodalBlocks(Exec(), ops_.lumpedInverse, x, y);
      },
      r, s, &complianceWork_);
  if (!st.converged && !(st.relativeResidual <= acceptable))
    throw std::runtime_error("mixed model: the inner CG on the compliance mass did not converge "
                             "(relative residual " +
                             std::to_string(st.relativeResidual) + " after " +
                             std::to_string(st.iterations) + " iterations)");
  return st.iterations;
}

void MixedModel::applySchur(const ConstDeviceVector &u, const DeviceVector &y) {
  ++operatorApplications_;
  applyCouplingTransposeBlock(u, workStressRhs_);
  applyComplianceInverse(ConstDeviceVector(workStressRhs_), workStress_);
  multiply(Exec(), stiffness_, u, y); // a Kd u + K11 u
  applyCouplingBlock(1.0 - options_.stabilization, ConstDeviceVector(workStress_), 1.0, y);
}

LinearSolveStats MixedModel::solve(double loadFactor) {
  innerIterations_ = operatorApplications_ = 0;
  if (options_.linear.type == LinearSolverType::Direct)
    return solveDirect(loadFactor);
  const auto once = [&] {
    return method_ == MixedLinearMethod::BlockTriangular ? solveBlockTriangular(loadFactor)
                                                         : solveSchur(loadFactor);
  };
  // The AMG is a preconditioner here: while the method around it fails, the AMG's escalation
  // ladder (its coarse space, a larger coarsest level, then the direct solve of the
  // preconditioner matrix) is climbed step by step, each step reported.
  return solveOnLadder(*amg_, once);
}

void MixedModel::applySaddlePoint(const ConstDeviceVector &v, const DeviceVector &y) {
  using namespace fieldops;
  ++operatorApplications_;
  gather(v, kMixed, 0, kDisp, splitU_);
  gather(v, kMixed, kStressAt, kStress, splitS_);
  const ConstDeviceVector u(splitU_), s(splitS_);
  multiply(Exec(), stiffness_, u, splitJu_); // a Kd u + K11 u
  applyCouplingBlock(1.0 - options_.stabilization, s, 1.0, splitJu_);
  applyCouplingTransposeBlock(u, splitJs_);
  if (options_.compliance == ComplianceMass::Lumped)
    applyNodalBlocks(Exec(), ops_.lumped, s, workStress_);
  else
    applyComplianceBlock(s, workStress_);
  axpby(-1.0, workStress_, 1.0, splitJs_);
  scatter<double>(splitJu_, kMixed, 0, kDisp, y, false);
  scatter<double>(splitJs_, kMixed, kStressAt, kStress, y, false);
}

LinearSolveStats MixedModel::solveBlockTriangular(double loadFactor) {
  using namespace fieldops;
  const auto start = std::chrono::steady_clock::now();
  const std::size_t nn = mesh_.numNodes();
  SaddlePointSystem system;
  system.jacobian = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    applySaddlePoint(v, y);
  };
  system.schurPreconditioner = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    amg_->precondition(r, y);
  };
  system.coupling = [&](const ConstDeviceVector &v, const DeviceVector &w) {
    applyCouplingTransposeBlock(v, w);
  };
  system.stressSolve = [&](const ConstDeviceVector &w, const DeviceVector &z, double tolerance) {
    return solveCompliance(w, z, tolerance, options_.preconditionerTolerance);
  };
  system.stressTolerance = options_.preconditionerTolerance;
  system.constrained = constrained5_;
  system.constrainedDisplacement = isConstrained_;
  system.constrainedDiagonal = constrainedDiagonal5_;
  system.stressRowScale = stressRowScale_;
  // f = [lambda F; 0], the prescribed rows reach lambda g.
  DeviceVector f("mixcon::mixed::rhs5", kMixed * nn), target("mixcon::mixed::target5", kMixed * nn),
      x(Kokkos::view_alloc(Kokkos::WithoutInitializing, "mixcon::mixed::x5"), kMixed * nn);
  scatter<double>(scaledCopy(load_, loadFactor), kMixed, 0, kDisp, f, false);
  scatter<double>(scaledCopy(prescribed_, loadFactor), kMixed, 0, kDisp, target, false);
  KrylovOptions ko;
  ko.tolerance = options_.linear.tolerance;
  ko.backwardErrorFloor = true; // slender parts: the relative residual has a floor
  ko.maxIterations = amg_->iterationsPerAttempt(options_.linear.maxIterations);
  ko.restart = options_.restart;
  long inner = 0;
  const KrylovStats ks = blockTriangularSolve(system, ko, ConstDeviceVector(f),
                                              ConstDeviceVector(target), x, inner, &outerWork_);
  innerIterations_ = inner;
  gather(x, kMixed, 0, kDisp, u_);
  gather(x, kMixed, kStressAt, kStress, s_);
  Exec().fence();

  return statsOf(ks, start, solverSetupSeconds_);
}

LinearSolveStats MixedModel::solveSchur(double loadFactor) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = u_.extent(0);
  const Kokkos::View<const int *, Memory> flags(isConstrained_);
  const ConstDeviceVector diag(constrainedDiagonal_);
  // b = P (lambda f - A lambda g) + D_c lambda g
  auto g = scaledCopy(prescribed_, loadFactor);
  auto f = scaledCopy(load_, loadFactor);
  DeviceVector ag("mixcon::mixed::Ag", n), b("mixcon::mixed::b", n);
  applySchur(ConstDeviceVector(g), ag); // g is zero off the constraints
  constrainedRhs(Exec(), flags, diag, ConstDeviceVector(f), ConstDeviceVector(g),
                 ConstDeviceVector(ag), b);

  DeviceVector tmp("mixcon::mixed::Px", n);
  LinearMap op;
  if (options_.compliance == ComplianceMass::Lumped &&
      options_.preconditioner == SchurPreconditioner::LumpedSchur && initialStress_.empty()) {
    op = [&](const ConstDeviceVector &x, const DeviceVector &y) {
      ++operatorApplications_;
      multiply(Exec(), precMatrix_, x, y); // the assembled S_a,L with constraints is A_c
    };
  } else {
    op = [&](const ConstDeviceVector &x, const DeviceVector &y) {
      maskConstrained(Exec(), flags, x, tmp);
      applySchur(tmp, y);
      finishConstrained(Exec(), flags, diag, x, y);
    };
  }
  const LinearMap prec = [&](const ConstDeviceVector &x, const DeviceVector &y) {
    amg_->precondition(x, y);
  };
  KrylovOptions ko;
  ko.method = options_.krylov;
  ko.tolerance = options_.linear.tolerance;
  ko.backwardErrorFloor = true; // slender parts: the relative residual has a floor
  ko.maxIterations = amg_->iterationsPerAttempt(options_.linear.maxIterations);
  // Initial guess: the prescribed values (exact on constrained rows), zero elsewhere.
  Kokkos::deep_copy(u_, g);
  const KrylovStats ks = krylovSolve(ko, op, prec, ConstDeviceVector(b), u_);

  // Stresses from the displacements with the same M as the solve (tight inner tolerance).
  // (not counted in innerIterations(), which reports the Schur products' inner iterations)
  applyCouplingTransposeBlock(ConstDeviceVector(u_), workStressRhs_);
  solveCompliance(ConstDeviceVector(workStressRhs_), s_, std::min(options_.innerTolerance, 1e-12));
  Exec().fence();

  return statsOf(ks, start, solverSetupSeconds_);
}

void MixedModel::setupDirect() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size != 1)
    throw std::runtime_error("the direct mixed solver runs on one MPI rank only; use solver: amg");
  const double a = options_.stabilization;
  const bool lumped = options_.compliance == ComplianceMass::Lumped;
  const LocalIndex ne = mesh_.numElements(), nn = mesh_.numNodes();
  const int npe = mesh_.nodesPerElement;
  const int nu = 2 * npe, ns = 3 * npe;
  Kokkos::View<double ***, Memory> k12("k12", ne, nu, ns), k22("k22", ne, ns, ns),
      k22l("k22l", ne, ns, ns), kd("kd", ne, nu, nu), kg("kg", ne, nu, nu);
  const auto tau = initialStressOnDevice();
  dispatchPlaneElement(mesh_.elementType, "the mixed model", [&](auto elem) {
    using Elem = decltype(elem);
    computeMixedElementMatrices<Elem>(Exec(), mixed_, k12, k22, k22l);
    computeLinearStiffness<Elem>(Exec(), data_, kd);
    if (!initialStress_.empty()) // kg stays zero otherwise
      computeMixedGeometricStiffness<Elem>(Exec(), data_, ConstDeviceVector(tau), kg);
  });
  auto h12 = copyToHost(k12);
  auto h22 = copyToHost(lumped ? k22l : k22);
  auto hd = copyToHost(kd);
  auto hg = copyToHost(kg);
  auto hc = copyToHost(isConstrained_);
  auto hp = copyToHost(prescribed_);
  auto hf = copyToHost(load_);

  const std::int64_t nU = 2 * static_cast<std::int64_t>(nn), n = 5 * static_cast<std::int64_t>(nn);
  direct_ = std::make_unique<Direct>();
  std::vector<double> &rhs = direct_->rhs;
  rhs.assign(n, 0.0);
  for (std::int64_t i = 0; i < nU; ++i)
    rhs[i] = hc(i) ? hp(i) : hf(i);
  std::vector<SparseEntry> t;
  t.reserve(static_cast<std::size_t>(ne) * (nu * nu + 2 * nu * ns + ns * ns));
  // Constrained displacement unknowns: unit row and column; the column moves to the rhs.
  auto add = [&](std::int64_t i, std::int64_t j, double v) {
    const bool ci = i < nU && hc(i), cj = j < nU && hc(j);
    if (ci)
      return;
    if (cj) {
      rhs[i] -= v * hp(j);
      return;
    }
    t.push_back({i, j, v});
  };
  for (LocalIndex e = 0; e < ne; ++e) {
    for (int p = 0; p < npe; ++p) {
      const LocalIndex np = mesh_.node(e, p);
      for (int q = 0; q < npe; ++q) {
        const LocalIndex nq = mesh_.node(e, q);
        for (int i = 0; i < 2; ++i) {
          for (int j = 0; j < 2; ++j)
            add(2 * np + i, 2 * nq + j,
                a * hd(e, 2 * p + i, 2 * q + j) + hg(e, 2 * p + i, 2 * q + j));
          for (int j = 0; j < 3; ++j) {
            const double v = (1.0 - a) * h12(e, 2 * p + i, 3 * q + j);
            add(2 * np + i, nU + 3 * nq + j, v);
            add(nU + 3 * nq + j, 2 * np + i, v);
          }
        }
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            add(nU + 3 * np + i, nU + 3 * nq + j, -(1.0 - a) * h22(e, 3 * p + i, 3 * q + j));
      }
    }
  }
  for (std::int64_t i = 0; i < nU; ++i)
    if (hc(i))
      t.push_back({i, i, 1.0});
  if (!direct_->lu.factor(n, t))
    throw std::runtime_error("mixed direct solver: the saddle-point matrix is singular (a "
                             "rigid-body mode not restrained, or a singular compliance?)");
}

LinearSolveStats MixedModel::solveDirect(double loadFactor) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> b(direct_->rhs), x;
  for (double &v : b)
    v *= loadFactor;
  LinearSolveStats s;
  s.relativeResidual = direct_->lu.solve(b, x);
  const LocalIndex nn = mesh_.numNodes();
  auto hu = hostMirror(u_);
  auto hs = hostMirror(s_);
  for (LocalIndex i = 0; i < 2 * nn; ++i)
    hu(i) = x[i];
  for (LocalIndex i = 0; i < 3 * nn; ++i)
    hs(i) = x[2 * nn + i];
  copyToDevice(u_, hu);
  copyToDevice(s_, hs);
  s.converged = std::isfinite(s.relativeResidual) && s.relativeResidual < 1e-8;
  s.iterations = 1;
  s.setupSeconds = solverSetupSeconds_;
  s.solveSeconds = secondsSince(start);
  return s;
}

std::vector<std::pair<std::string, std::size_t>> MixedModel::deviceViewBytes() const {
  std::vector<std::pair<std::string, std::size_t>> b;
  auto add = [&](const std::string &name, const auto &v) {
    b.emplace_back(name, v.span() * sizeof(typename std::decay_t<decltype(v)>::value_type));
  };
  add("mesh.coordinates", data_.mesh.coordinates);
  add("mesh.connectivity", data_.mesh.connectivity);
  add("material", data_.material);
  add("load", load_);
  add("u", u_);
  add("isConstrained", isConstrained_);
  add("prescribed", prescribed_);
  add("stress", s_);
  add("constrainedDiagonal", constrainedDiagonal_);
  add("workStressRhs", workStressRhs_);
  add("workStress", workStress_);
  add("constrained5", constrained5_);
  add("constrainedDiagonal5", constrainedDiagonal5_);
  add("splitU", splitU_);
  add("splitJu", splitJu_);
  add("splitS", splitS_);
  add("splitJs", splitJs_);
  add("graph.rowOffsets", ops_.graph.rowOffsets);
  add("graph.columns", ops_.graph.columns);
  add("graph.transpose", ops_.graph.transpose);
  add("coupling", ops_.coupling);
  add("compliance", ops_.compliance);
  add("lumped", ops_.lumped);
  add("lumpedInverse", ops_.lumpedInverse);
  add("matrixFree.weight", matrixFree_.geometry.weight);
  add("matrixFree.gradient", matrixFree_.geometry.gradient);
  add("matrixFree.coloredElements", matrixFree_.coloredElements);
  for (const auto &[name, m] :
       {std::pair<const char *, const CsrMatrix<Memory> *>{"stiffness", &stiffness_},
        {"preconditioner", &precMatrix_}}) {
    add(std::string(name) + ".rowOffsets", m->rowOffsets);
    add(std::string(name) + ".columns", m->columns);
    add(std::string(name) + ".values", m->values);
  }
  return b;
}

std::vector<double> MixedModel::nodalStressHost() const { return toHost(s_); }

std::vector<double> MixedModel::reactionHost(double loadFactor) const {
  // (1-a) K12 S + a Kd u + K11 u - lambda F
  DeviceVector f("mixcon::mixed::internalForce", u_.extent(0));
  multiply(Exec(), stiffness_, ConstDeviceVector(u_), f);
  applyCouplingBlock(1.0 - options_.stabilization, ConstDeviceVector(s_), 1.0, f);
  return reactionFrom(f, loadFactor);
}

} // namespace mixcon
