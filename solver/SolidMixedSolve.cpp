// SolidMixedSolve (solver/SolidMixedSolve.hpp). Layer: solver.
#include <solver/BlockTriangular.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/SolidMixedSolve.hpp>

#include <kernels/Material.hpp>

#include <chrono>
#include <stdexcept>

namespace mixcon {

using namespace fieldops;

namespace {
constexpr int kDim = FieldLayout<3>::kNumDisplacements;      // 3
constexpr int kStresses = FieldLayout<3>::kNumStresses;      // 6
constexpr int kUnknowns = FieldLayout<3>::kMixedUnknowns;    // 9
constexpr int kStressOffset = FieldLayout<3>::kStressOffset; // 3
} // namespace

void invertStressBlocks(const CsrMatrix<DeviceSpace> &m,
                        const Kokkos::View<SolidMatrix *, DeviceSpace> &inverse) {
  auto ro = m.rowOffsets;
  auto co = m.columns;
  auto va = m.values;
  Kokkos::parallel_for(
      "mixcon::mixed3d::invertStressBlocks", Kokkos::RangePolicy<Exec>(0, inverse.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        SolidMatrix b{};
        for (int i = 0; i < kStresses; ++i)
          for (Offset k = ro(kStresses * p + i); k < ro(kStresses * p + i + 1); ++k)
            if (co(k) / kStresses == p)
              b.m[i][co(k) % kStresses] = va(k);
        SolidMatrix inv{};
        if (!invertConstitutive(b, inv)) // not expected (M is SPD): Jacobi for that node
          for (int i = 0; i < kStresses; ++i)
            inv.m[i][i] = b.m[i][i] != 0.0 ? 1.0 / b.m[i][i] : 0.0;
        inverse(p) = inv;
      });
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

SolidMixedSolve::SolidMixedSolve(const NodeGraph &graph, const LinearSolverOptions &options,
                                 double preconditionerTolerance, int restart, const DofMap &dofs,
                                 MPI_Comm comm,
                                 const Kokkos::View<const double **, Memory> &positions)
    : options_(options), preconditionerTolerance_(preconditionerTolerance), restart_(restart) {
  stiffness_ = expandGraph<Memory>(graph, kDim);
  coupling_ = expandGraph<Memory>(graph, kStresses, kDim);
  stressBlock_ = expandGraph<Memory>(graph, kStresses);
  const std::size_t nn = graph.numNodes();
  diag3_ = Vec("mixcon::mixed3d::constrainedDiagonal", kDim * nn);
  diag9_ = Vec("mixcon::mixed3d::constrainedDiagonal9", kUnknowns * nn);
  stressDiagonal_ = Vec("mixcon::mixed3d::stressDiagonal", kStresses * nn);
  stressBlockInverse_ = Kokkos::View<SolidMatrix *, Memory>("mixcon::mixed3d::stressBlocks", nn);
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
  const auto start = std::chrono::steady_clock::now();
  Vec zero("mixcon::mixed3d::zero", diag3_.extent(0)),
      scratch("mixcon::mixed3d::scratch", diag3_.extent(0));
  applyDirichlet(Exec(), stiffness_, flags3, ConstVec(zero), scratch);
  constrainedDiagonal(Exec(), stiffness_, flags3, diag3_);
  scatter<double>(ConstVec(diag3_), kUnknowns, 0, kDim, diag9_, true);
  extractFieldBlock(jacobian, kUnknowns, kStressOffset, kStresses, 0, kDim, coupling_, 1.0);
  extractFieldBlock(jacobian, kUnknowns, kStressOffset, kStresses, kStressOffset, kStresses,
                    stressBlock_, -1.0);
  fieldDiagonal(stressBlock_, 1, 0, 1, stressDiagonal_, 1.0);
  // The inverses of M's 6 x 6 nodal diagonal blocks (the six stress components coupled through
  // the compliance at a node), the CG's preconditioner.
  invertStressBlocks(stressBlock_, stressBlockInverse_);
  Vec da("mixcon::mixed3d::diagK", diag3_.extent(0));
  fieldDiagonal(stiffness_, 1, 0, 1, da, 1.0);
  stressRowScale_ = blockTriangularScale(ConstVec(da), ConstVec(stressDiagonal_));
  Exec().fence();
  amg_->setup(stiffness_);
  setupSeconds_ += seconds(start);
}

LinearSolveStats SolidMixedSolve::solve(const CsrMatrix<Memory> &jacobian,
                                        const Kokkos::View<const int *, Memory> &flags9,
                                        const Kokkos::View<const int *, Memory> &flags3,
                                        const ConstVec &f, const ConstVec &target, const Vec &x) {
  const auto start = std::chrono::steady_clock::now();
  // M z = w: CG on M (SPD: the compliance mass of the current configuration) preconditioned by
  // the inverses of its nodal 6 x 6 blocks.
  const LinearMap applyM = [&](const ConstDeviceVector &a, const DeviceVector &y) {
    multiply(Exec(), stressBlock_, a, y);
  };
  const LinearMap jacobi = [&](const ConstDeviceVector &a, const DeviceVector &y) {
    applyStressBlocks(stressBlockInverse_, a, y);
  };
  SaddlePointSystem system;
  system.displacements = kDim;
  system.stresses = kStresses;
  system.jacobian = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    multiply(Exec(), jacobian, v, y);
  };
  system.schurPreconditioner = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    amg_->precondition(r, y);
  };
  system.coupling = [&](const ConstDeviceVector &v, const DeviceVector &w) {
    multiply(Exec(), coupling_, v, w);
  };
  system.stressSolve = [&](const ConstDeviceVector &w, const DeviceVector &z) {
    return stressBlockSolve(applyM, jacobi, w, z, preconditionerTolerance_, stressWork_,
                            "3D mixed model");
  };
  system.constrained = flags9;
  system.constrainedDisplacement = flags3;
  system.constrainedDiagonal = diag9_;
  system.stressRowScale = stressRowScale_;
  KrylovOptions ko;
  ko.tolerance = options_.tolerance;
  ko.backwardErrorFloor = true; // slender parts: the relative residual has a floor
  ko.maxIterations = options_.maxIterations;
  ko.restart = restart_;
  inner_ = 0;
  const KrylovStats ks = blockTriangularSolve(system, ko, f, target, x, inner_, &outerWork_);
  return statsOf(ks, start);
}

std::string SolidMixedSolve::name() const {
  return "flexible GMRES(" + std::to_string(restart_) +
         ") on the assembled Jacobian, block-triangular preconditioner: one BoomerAMG V-cycle on "
         "K^L (" +
         amg_->name() + "), block-Jacobi CG on the stress block to " +
         std::to_string(preconditionerTolerance_);
}

} // namespace mixcon
