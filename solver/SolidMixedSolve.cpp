// SolidMixedSolve (solver/SolidMixedSolve.hpp). Layer: solver.
#include <solver/BlockTriangular.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/SolidMixedSolve.hpp>

#include <kernels/Material.hpp>

#include <chrono>
#include <sstream>
#include <stdexcept>

namespace mixcon {

using namespace fieldops;

namespace {
constexpr int kDim = FieldLayout<3>::kNumDisplacements;      // 3
constexpr int kStresses = FieldLayout<3>::kNumStresses;      // 6
constexpr int kUnknowns = FieldLayout<3>::kMixedUnknowns;    // 9
constexpr int kStressOffset = FieldLayout<3>::kStressOffset; // 3
} // namespace

void invertStressBlocks(const Kokkos::View<const SolidMatrix *, DeviceSpace> &blocks,
                        const Kokkos::View<SolidMatrix *, DeviceSpace> &inverse) {
  Kokkos::parallel_for(
      "mixcon::mixed3d::invertStressBlocks", Kokkos::RangePolicy<Exec>(0, inverse.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        const SolidMatrix b = blocks(p);
        SolidMatrix inv{};
        if (!invertConstitutive(b, inv)) // not expected (M is SPD): Jacobi for that node
          for (int i = 0; i < kStresses; ++i)
            inv.m[i][i] = b.m[i][i] != 0.0 ? 1.0 / b.m[i][i] : 0.0;
        inverse(p) = inv;
      });
}

namespace {
/// blocks(p): the nodal 6 x 6 diagonal block p of m (6 unknowns per node).
void nodalStressBlocks(const CsrMatrix<DeviceSpace> &m,
                       const Kokkos::View<SolidMatrix *, DeviceSpace> &blocks) {
  auto ro = m.rowOffsets;
  auto co = m.columns;
  auto va = m.values;
  Kokkos::parallel_for(
      "mixcon::mixed3d::nodalStressBlocks", Kokkos::RangePolicy<Exec>(0, blocks.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        SolidMatrix b{};
        for (int i = 0; i < kStresses; ++i)
          for (Offset k = ro(kStresses * p + i); k < ro(kStresses * p + i + 1); ++k)
            if (co(k) / kStresses == p)
              b.m[i][co(k) % kStresses] = va(k);
        blocks(p) = b;
      });
}

/// d(6 p + i) = blocks(p)(i, i).
void stressBlockDiagonal(const Kokkos::View<const SolidMatrix *, DeviceSpace> &blocks,
                         const Kokkos::View<double *, DeviceSpace> &d) {
  Kokkos::parallel_for(
      "mixcon::mixed3d::stressDiagonal", Kokkos::RangePolicy<Exec>(0, blocks.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        for (int i = 0; i < kStresses; ++i)
          d(kStresses * p + i) = blocks(p).m[i][i];
      });
}
} // namespace

void invertStressBlocks(const CsrMatrix<DeviceSpace> &m,
                        const Kokkos::View<SolidMatrix *, DeviceSpace> &inverse) {
  Kokkos::View<SolidMatrix *, DeviceSpace> blocks("mixcon::mixed3d::stressBlocks",
                                                  inverse.extent(0));
  nodalStressBlocks(m, blocks);
  invertStressBlocks(Kokkos::View<const SolidMatrix *, DeviceSpace>(blocks), inverse);
}

void applyStressBlocks(const Kokkos::View<const SolidMatrix *, DeviceSpace> &inverse,
                       const Kokkos::View<const double *, DeviceSpace> &a,
                       const Kokkos::View<double *, DeviceSpace> &y) {
  Kokkos::parallel_for(
      "mixcon::mixed3d::applyStressBlocks", Kokkos::RangePolicy<Exec>(0, inverse.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        for (int i = 0; i < kStresses; ++i) {
          double v = 0.0;
          for (int j = 0; j < kStresses; ++j)
            v += inverse(p).m[i][j] * a(kStresses * p + j);
          y(kStresses * p + i) = v;
        }
      });
}

SolidMixedMatrixFree::SolidMixedMatrixFree(const Mesh &mesh, const ElementData<Memory, 3> &solid,
                                           const Kokkos::View<SolidMatrix *, Memory> &compliance,
                                           double stabilization, bool currentForm,
                                           const ConstVec &prestress)
    : type_(mesh.elementType), solid_(solid), compliance_(compliance),
      stabilization_(stabilization), current_(currentForm), tau_(prestress) {
  const std::size_t nn = mesh.numNodes(), ne = mesh.numElements();
  colors_ = mixedElementColors<Memory>(mesh, kDefaultMixedScatter<Exec>);
  x_ = Vec("mixcon::mixed3d::matrixFreeState", kUnknowns * nn);
  if (!current_ && tau_.extent(0) == 0)
    tau_ = Vec("mixcon::mixed3d::zeroPrestress", kStresses * nn);
  const int points = dispatchSolidElement(
      type_, "the 3D mixed model", [](auto elem) { return MixedRule<decltype(elem)>::kNumQp; });
  pointCoupling_ = Kokkos::View<double ***, Memory>("mixcon::mixed3d::pointCoupling", ne, points,
                                                    kStresses * kDim * kDim);
  pointMass_ = Kokkos::View<double ***, Memory>("mixcon::mixed3d::pointStressMass", ne, points,
                                                kStresses * kStresses);
  blocks_ = Kokkos::View<SolidMatrix *, Memory>("mixcon::mixed3d::stressBlocks", nn);
}

template <class F> void SolidMixedMatrixFree::dispatch(const F &f) const {
  dispatchSolidElement(type_, "the 3D mixed model", [&](auto elem) {
    using Rule = MixedRule<decltype(elem)>;
    if (current_)
      f(Rule{},
        MixedCurrentLaw<Memory, 3>{solid_.material, solid_.stiffness, compliance_, stabilization_});
    else
      f(Rule{}, MixedIncrementLaw<Memory, 3>{solid_.material, solid_.stiffness, compliance_,
                                             stabilization_});
  });
}

void SolidMixedMatrixFree::update(const Kokkos::View<const double *, Memory> &x) {
  Kokkos::deep_copy(x_, x);
  dispatch([&](auto rule, const auto &law) {
    assembleMixedStressRowsPartial<decltype(rule)>(Exec(), solid_.mesh, 1.0, law, ConstVec(x_),
                                                   ConstVec(tau_), pointCoupling_, pointMass_,
                                                   blocks_);
  });
  Exec().fence();
}

void SolidMixedMatrixFree::applyJacobian(const ConstVec &v, const Vec &y) const {
  dispatch([&](auto rule, const auto &law) {
    applyMixedJacobian<decltype(rule)>(Exec(), solid_.mesh, 1.0, law, ConstVec(x_), tau_, v, y,
                                       colors_);
  });
}

void SolidMixedMatrixFree::applyCoupling(const ConstVec &v, const Vec &w) const {
  const Kokkos::View<const double ***, Memory> pc(pointCoupling_);
  dispatch([&](auto rule, const auto &) {
    using Rule = decltype(rule);
    if (current_)
      applyMixedCouplingPartial<Rule, true>(Exec(), solid_.mesh, ConstVec(x_), pc, v, w, colors_);
    else
      applyMixedCouplingPartial<Rule, false>(Exec(), solid_.mesh, ConstVec(x_), pc, v, w, colors_);
  });
}

void SolidMixedMatrixFree::applyStressBlock(const ConstVec &z, const Vec &y) const {
  dispatch([&](auto rule, const auto &) {
    applyMixedStressMass<decltype(rule)>(
        Exec(), solid_.mesh, Kokkos::View<const double ***, Memory>(pointMass_), z, y, colors_);
  });
}

SolidMixedOperators SolidMixedMatrixFree::operators() const {
  SolidMixedOperators o;
  o.jacobian = [this](const ConstDeviceVector &v, const DeviceVector &y) { applyJacobian(v, y); };
  o.coupling = [this](const ConstDeviceVector &v, const DeviceVector &w) { applyCoupling(v, w); };
  o.stressBlock = [this](const ConstDeviceVector &z, const DeviceVector &y) {
    applyStressBlock(z, y);
  };
  o.stressBlocks = blocks_;
  return o;
}

SolidMixedSolve::SolidMixedSolve(const NodeGraph &graph, const LinearSolverOptions &options,
                                 double preconditionerTolerance, int restart, const DofMap &dofs,
                                 MPI_Comm comm,
                                 const Kokkos::View<const double **, Memory> &positions,
                                 bool assembledJacobian)
    : options_(options), preconditionerTolerance_(preconditionerTolerance), restart_(restart),
      assembled_(assembledJacobian) {
  stiffness_ = expandGraph<Memory>(graph, kDim);
  if (assembled_) {
    coupling_ = expandGraph<Memory>(graph, kStresses, kDim);
    stressBlock_ = expandGraph<Memory>(graph, kStresses);
  }
  const std::size_t nn = graph.numNodes();
  diag3_ = Vec("mixcon::mixed3d::constrainedDiagonal", kDim * nn);
  diag9_ = Vec("mixcon::mixed3d::constrainedDiagonal9", kUnknowns * nn);
  stressDiagonal_ = Vec("mixcon::mixed3d::stressDiagonal", kStresses * nn);
  stressBlockInverse_ =
      Kokkos::View<SolidMatrix *, Memory>("mixcon::mixed3d::stressBlockInverses", nn);
  if (assembled_)
    stressBlocks_ = Kokkos::View<SolidMatrix *, Memory>("mixcon::mixed3d::stressBlocks", nn);
  LinearSolverOptions amg = options;
  amg.type = LinearSolverType::Amg;
  amg.symmetric = true; // K^L
  // A fresh hierarchy at every refresh(), on K^L and the rigid-body modes of the configuration
  // of that tangent: the kept-hierarchy rule of reuse_hierarchy watches solve(), which this
  // class does not call (it only applies V-cycles). Setups were 7 % of a Newton step at 1e6
  // Hex8 unknowns (docs/performance.md).
  amg.reuseHierarchy = false;
  amg_ = makeLinearSolver(amg, dofs, comm);
  amg_->setNearNullSpace(positions);
}

SolidMixedSolve::~SolidMixedSolve() = default;

void SolidMixedSolve::zeroStiffness() { Kokkos::deep_copy(stiffness_.values, 0.0); }

void SolidMixedSolve::refresh(const CsrMatrix<Memory> &jacobian,
                              const Kokkos::View<const int *, Memory> &flags3) {
  if (!assembled_)
    throw std::logic_error("SolidMixedSolve: set up for a Jacobian that is not assembled");
  const auto start = std::chrono::steady_clock::now();
  extractFieldBlock(jacobian, kUnknowns, kStressOffset, kStresses, 0, kDim, coupling_, 1.0);
  extractFieldBlock(jacobian, kUnknowns, kStressOffset, kStresses, kStressOffset, kStresses,
                    stressBlock_, -1.0);
  nodalStressBlocks(stressBlock_, stressBlocks_);
  const CsrMatrix<Memory> j = jacobian, c = coupling_, m = stressBlock_;
  jacobian_.jacobian = [j](const ConstDeviceVector &v, const DeviceVector &y) {
    multiply(Exec(), j, v, y);
  };
  jacobian_.coupling = [c](const ConstDeviceVector &v, const DeviceVector &w) {
    multiply(Exec(), c, v, w);
  };
  jacobian_.stressBlock = [m](const ConstDeviceVector &a, const DeviceVector &y) {
    multiply(Exec(), m, a, y);
  };
  jacobian_.stressBlocks = stressBlocks_;
  setupSeconds_ += seconds(start);
  finishRefresh(flags3);
}

void SolidMixedSolve::refresh(const SolidMixedOperators &jacobian,
                              const Kokkos::View<const int *, Memory> &flags3) {
  jacobian_ = jacobian;
  finishRefresh(flags3);
}

void SolidMixedSolve::finishRefresh(const Kokkos::View<const int *, Memory> &flags3) {
  const auto start = std::chrono::steady_clock::now();
  Vec zero("mixcon::mixed3d::zero", diag3_.extent(0)),
      scratch("mixcon::mixed3d::scratch", diag3_.extent(0));
  applyDirichlet(Exec(), stiffness_, flags3, ConstVec(zero), scratch);
  constrainedDiagonal(Exec(), stiffness_, flags3, diag3_);
  scatter<double>(ConstVec(diag3_), kUnknowns, 0, kDim, diag9_, true);
  // M's diagonal and the inverses of its 6 x 6 nodal diagonal blocks (the six stress components
  // coupled through the compliance at a node), the CG's preconditioner.
  stressBlockDiagonal(jacobian_.stressBlocks, stressDiagonal_);
  invertStressBlocks(jacobian_.stressBlocks, stressBlockInverse_);
  Vec da("mixcon::mixed3d::diagK", diag3_.extent(0));
  fieldDiagonal(stiffness_, 1, 0, 1, da, 1.0);
  stressRowScale_ = blockTriangularScale(ConstVec(da), ConstVec(stressDiagonal_));
  Exec().fence();
  amg_->setup(stiffness_);
  setupSeconds_ += seconds(start);
}

LinearSolveStats SolidMixedSolve::solve(const Kokkos::View<const int *, Memory> &flags9,
                                        const Kokkos::View<const int *, Memory> &flags3,
                                        const ConstVec &f, const ConstVec &target, const Vec &x,
                                        const DirectInstead &directInstead) {
  const auto start = std::chrono::steady_clock::now();
  // M z = w: CG on M (SPD: the compliance mass of the current configuration) preconditioned by
  // the inverses of its nodal 6 x 6 blocks.
  const LinearMap jacobi = [&](const ConstDeviceVector &a, const DeviceVector &y) {
    applyStressBlocks(stressBlockInverse_, a, y);
  };
  SaddlePointSystem system;
  system.displacements = kDim;
  system.stresses = kStresses;
  system.jacobian = jacobian_.jacobian;
  system.schurPreconditioner = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    amg_->precondition(r, y);
  };
  system.coupling = jacobian_.coupling;
  system.stressSolve = [&](const ConstDeviceVector &w, const DeviceVector &z, double tolerance) {
    return stressBlockSolve(jacobian_.stressBlock, jacobi, w, z, tolerance, stressWork_,
                            "3D mixed model", preconditionerTolerance_);
  };
  system.stressTolerance = preconditionerTolerance_;
  system.constrained = flags9;
  system.constrainedDisplacement = flags3;
  system.constrainedDiagonal = diag9_;
  system.stressRowScale = stressRowScale_;
  KrylovOptions ko;
  ko.tolerance = options_.tolerance;
  ko.backwardErrorFloor = true; // slender parts: the relative residual has a floor
  ko.restart = restart_;
  inner_ = 0;
  const auto once = [&] {
    ko.maxIterations = amg_->iterationsPerAttempt(options_.maxIterations);
    return statsOf(blockTriangularSolve(system, ko, f, target, x, inner_, &outerWork_), start);
  };
  // The AMG on K^L is a preconditioner here: where the method around it fails, the AMG's
  // escalation ladder (its coarse space, larger coarsest levels, its direct solver) is climbed
  // step by step, each step reported, as in the 2D mixed models.
  LinearSolveStats s = solveOnLadder(*amg_, once, directInstead);
  s.solveSeconds = seconds(start);
  return s;
}

std::string SolidMixedSolve::name() const {
  std::ostringstream s;
  s << "flexible GMRES(" << restart_ << ") on the "
    << (assembled_ ? "assembled Jacobian"
                   : "Jacobian applied matrix-free (C and M by partial assembly)")
    << ", block-triangular preconditioner: one BoomerAMG V-cycle on K^L (" << amg_->name()
    << "), block-Jacobi CG on the stress block to " << preconditionerTolerance_ << " or tighter";
  return s.str();
}

} // namespace mixcon
