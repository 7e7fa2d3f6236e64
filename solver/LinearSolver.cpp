// hypre (IJ -> ParCSR, PCG + BoomerAMG) and SuiteSparse (CHOLMOD, UMFPACK) implementations.
#include <core/Transfer.hpp>
#include <kernels/SymmetricBlocks.hpp>
#include <solver/AmgCycle.hpp>
#include <solver/HierarchyCheck.hpp>
#include <solver/HypreMatrix.hpp>
#include <solver/Krylov.hpp>
#include <solver/LinearSolver.hpp>
#include <solver/RigidCoarseSpace.hpp>
#include <solver/RigidRotation.hpp>
#include <solver/Rules.hpp>
#include <solver/SparseDirect.hpp>

#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <_hypre_parcsr_ls.h> // SetSmoothInterpVectors, SetInterpRefine (not in HYPRE_parcsr_ls.h)
#include <_hypre_parcsr_mv.h> // hypre_ParVectorLocalVector, hypre_VectorData (BorrowedVector)

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace mixcon {

namespace {

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

void check(HYPRE_Int err, const char *what) {
  if (err != 0) {
    char msg[256] = {};
    HYPRE_DescribeError(err, msg);
    HYPRE_ClearAllErrors();
    throw std::runtime_error(std::string("hypre: ") + what + " failed: " + msg);
  }
}

/// The convergence decision every path shares, on the true relative residual: met within the
/// tolerance, or within `slack` times the tolerance when the method itself reported success.
/// Krylov (slack 10): the recursive residual drifts from the true one by rounding (hypre GMRES
/// ends at 3.1e-10 for 1e-10). Direct (slack 100): its residual is about eps * cond(A) and
/// cannot be iterated down (refinement with the same factors gains little: 1.2e-7 -> 6.8e-8 on a
/// strip at L/h = 100; the slender_displacement example's tangents give 2.3e-7 for 1e-8).
/// Or at the accuracy floor, whatever the method said: backward error (||A|| the row-sum norm)
/// at most kBackwardErrorFloor (LinearSolver.hpp).
/// Never for a NaN or a zero iterate (x = 0 for a nonzero b is what a breakdown leaves).
double backwardError(double residualNorm, double matrixNorm, double xNorm, double bNorm) {
  const double scale = matrixNorm * xNorm + bNorm;
  if (!(scale > 0.0) || matrixNorm * xNorm > kGrowthLimit * bNorm)
    return std::numeric_limits<double>::infinity(); // see kGrowthLimit
  return residualNorm / scale;
}

bool trueResidualConverged(double relativeResidual, double xNormSquared, double tolerance,
                           bool methodConverged, double slack, double backward) {
  if (!std::isfinite(relativeResidual) || !(xNormSquared > 0.0) || !std::isfinite(xNormSquared))
    return false;
  return relativeResidual <= tolerance ||
         (methodConverged && relativeResidual <= slack * tolerance) ||
         backward <= kBackwardErrorFloor;
}

/// The row-sum norm of the owned rows (on the host's threads).
double rowSumNorm(const CsrMatrix<DeviceSpace> &a) {
  const auto ro = hostReadable(a.rowOffsets);
  const auto va = hostReadable(a.values);
  double norm = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::solver::rowSumNorm", HostRange(0, a.numRows),
      [=](LocalIndex i, double &largest) {
        double sum = 0.0;
        for (Offset k = ro(i); k < ro(i + 1); ++k)
          sum += std::fabs(va(k));
        largest = std::max(largest, sum);
      },
      Kokkos::Max<double, Kokkos::HostSpace>(norm));
  return norm;
}

/// Where the Kokkos memory is host-accessible (the OpenMP and Serial builds), hypre (a CPU build)
/// works on the views' memory directly: for the duration of one call, the local data of a hypre
/// vector is the view's array (the vector's own array is put back afterwards, so hypre frees
/// only what it allocated). No copy, nothing counted: the preconditioner applied once per Krylov
/// iteration and every solve stay off the transfer counts. Where it is not (a CUDA Kokkos with a
/// CPU hypre), the wrapper copies b to the host and x back through the counted transfer API
/// (core/Transfer.hpp); a GPU hypre would take the device pointers instead.
/// Up to this size the coarsest level is solved by hypre's Gaussian elimination, which factors
/// it at every V-cycle; larger ones (the escalation ladder) by the inverse formed at setup (relax
/// type 199): 1.1 s against 27 s per load step of the L/h = 100 cantilever with 4000.
constexpr int kGaussEliminationSize = 100;

constexpr bool kHypreReadsKokkosMemory = kHostAccessible<DeviceSpace>;

/// hypre built for a GPU keeps its hierarchy in device memory (AmgCycle reads it on the host).
#if defined(HYPRE_USING_GPU)
constexpr bool kGpuHypre = true;
#else
constexpr bool kGpuHypre = false;
#endif

class BorrowedVector {
public:
  BorrowedVector(HYPRE_ParVector v, const double *data)
      : local_(hypre_ParVectorLocalVector(v)), own_(hypre_VectorData(local_)) {
    hypre_VectorData(local_) = const_cast<double *>(data); // hypre only reads b
  }
  ~BorrowedVector() { hypre_VectorData(local_) = own_; }
  BorrowedVector(const BorrowedVector &) = delete;
  BorrowedVector &operator=(const BorrowedVector &) = delete;

private:
  hypre_Vector *local_;
  HYPRE_Complex *own_;
};

class DirectSolver final : public LinearSolver {
public:
  DirectSolver(MPI_Comm comm, const LinearSolverOptions &o)
      : options_(o), comm_(comm), symmetric_(o.symmetric), saddle_(o.indefinite),
        indefinite_(o.indefinite), tolerance_(o.tolerance) {
    int size = 1;
    MPI_Comm_size(comm, &size);
    if (size != 1)
      throw std::runtime_error("the direct solver runs on one MPI rank only; use solver: amg");
  }

  void setup(const CsrMatrix<DeviceSpace> &a) override {
    // Every copy this file makes is for a host library (SuiteSparse, hypre): each entry point of
    // the LinearSolver interface that can copy counts them as staging (core/Transfer.hpp).
    const HostLibraryStaging staging;
    const auto start = std::chrono::steady_clock::now();
    // SuiteSparse reads the CSR arrays in place where the memory is host-accessible (as hypre).
    Kokkos::fence();
    const auto ro = hostReadable(a.rowOffsets);
    const auto co = hostReadable(a.columns);
    const auto va = hostReadable(a.values);
    const HostCsr csr{a.numRows, ro.data(), co.data(), va.data()};
    normInf_ = rowSumNorm(a);
    // Cholesky reads one triangle: a nonsymmetric matrix goes to LU directly, and so does a
    // symmetric one that is not positive definite (a pivot <= 0), then and in the later setups
    // (a saddle point stays indefinite; each switch of method analyses the pattern anew). A
    // matrix said to be nonsymmetric (the exact tangent) that is symmetric to round-off (linear
    // kinematics, frictionless contact) takes the Cholesky too: half the work of the LU.
    const bool symmetric = symmetric_ || SparseDirect::isSymmetric(csr, kSymmetryTolerance,
                                                                   kSymmetryTolerance * normInf_);
    SparseDirect::Outcome outcome = SparseDirect::Outcome::NotPositiveDefinite;
    if (symmetric && !indefinite_) {
      outcome = factors_.factor(SparseDirect::Method::Cholesky, csr);
      indefinite_ = outcome == SparseDirect::Outcome::NotPositiveDefinite;
    }
    if (outcome == SparseDirect::Outcome::NotPositiveDefinite)
      outcome = factors_.factor(SparseDirect::Method::Lu, csr);
    // An exactly zero pivot, or one at round-off relative to the largest: in the Cholesky, or
    // in the LU of a matrix the caller said is symmetric positive definite (a free rigid-body
    // mode can leave a pivot of either sign at round-off level).
    const bool cholesky = factors_.method() == SparseDirect::Method::Cholesky;
    if (outcome != SparseDirect::Outcome::Factored ||
        ((cholesky || (symmetric_ && !saddle_)) && !(factors_.pivotRatio() > kSingularPivot)))
      throw std::runtime_error(kSingular);
    factored_ = true;
    ++builds_;
    setupSeconds_ = seconds(start);
  }

  LinearSolveStats solve(const Kokkos::View<const double *, DeviceSpace> &b,
                         const Kokkos::View<double *, DeviceSpace> &x) override {
    const HostLibraryStaging staging;
    const auto start = std::chrono::steady_clock::now();
    Kokkos::fence(); // b may come from a kernel still running
    const auto hb = hostReadable(b);
    const std::size_t n = hb.extent(0);
    LinearSolveStats s;
    double bn = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      bn += hb(i) * hb(i);
    bn = std::sqrt(bn);
    std::vector<double> hx(n, 0.0);
    double xn = 0.0;
    if (bn > 0.0) { // b = 0: x = 0, exactly
      // Iterative refinement with the same factorization while the true residual misses the
      // tolerance (ill-conditioned slender systems)
      s.relativeResidual =
          factors_.solveRefined(hb.data(), hx.data(), kRefinements, tolerance_ * bn) / bn;
      for (double v : hx)
        xn += v * v;
    }
    if constexpr (kHostAccessible<DeviceSpace>) {
      std::copy(hx.begin(), hx.end(), x.data());
    } else {
      auto hxm = hostMirror(x);
      for (std::size_t i = 0; i < n; ++i)
        hxm(i) = hx[i];
      copyToDevice(x, hxm);
    }
    s.converged =
        bn == 0.0 ||
        trueResidualConverged(s.relativeResidual, xn, tolerance_, true, 100.0,
                              backwardError(s.relativeResidual * bn, normInf_, std::sqrt(xn), bn));
    s.iterations = 1;
    s.solveSeconds = seconds(start);
    s.setupSeconds = setupSeconds_;
    return s;
  }

  void precondition(const Kokkos::View<const double *, DeviceSpace> &b,
                    const Kokkos::View<double *, DeviceSpace> &x) override {
    solve(b, x);
  }

  std::string name() const override {
    // Before the first setup: the method a symmetric (nonsymmetric) matrix starts with.
    const auto method = factored_    ? factors_.method()
                        : symmetric_ ? SparseDirect::Method::Cholesky
                                     : SparseDirect::Method::Lu;
    return std::string("direct (") + SparseDirect::name(method) + ")";
  }
  double setupSeconds() const override { return setupSeconds_; }
  int builds() const override { return builds_; }
  bool keepsFactorization() const override { return options_.reuseFactorization; }
  std::unique_ptr<LinearSolver> another() const override {
    return std::make_unique<DirectSolver>(comm_, options_);
  }

private:
  LinearSolverOptions options_; ///< as given (another() starts from them)
  MPI_Comm comm_;
  SparseDirect factors_;
  /// A pivot at rounding level relative to the largest: the matrix is singular to working
  /// precision. Measured min/max |pivot| (with Eigen's LDL^T, before SuiteSparse): 9e-16 for the
  /// Lame quarter annulus left free to translate in x (test_singular), 2.5e-13 for a clamped
  /// Quad8 strip at L/h = 10000 (3.6e-11 at L/h = 1000), so 1e-14 separates them.
  static constexpr double kSingularPivot = 1e-14;
  /// |a_ij - a_ji| below this times the larger of the two (or times the matrix's norm) is
  /// round-off: such a matrix is factored by Cholesky (its error is corrected by the refinement).
  static constexpr double kSymmetryTolerance = 1e-12;
  static constexpr const char *kSingular =
      "direct solver: the stiffness matrix is singular (a zero pivot): the displacement "
      "conditions probably leave a rigid-body mode free (a translation or a rotation of a body "
      "that no support holds)";

  static constexpr int kRefinements = 3;
  double normInf_ = 0.0; ///< row-sum norm of the matrix (backward error)
  bool symmetric_ = true;
  bool saddle_ = false; ///< LinearSolverOptions::indefinite
  bool factored_ = false;
  bool indefinite_ = false; ///< said so, or the Cholesky met a pivot <= 0: LU from then on
  double tolerance_ = 1e-8;
  double setupSeconds_ = 0.0;
  int builds_ = 0; ///< factorizations
};

class HypreAmgSolver final : public LinearSolver {
public:
  HypreAmgSolver(const LinearSolverOptions &o, const DofMap &dofs, MPI_Comm comm)
      : options_(o), dofs_(dofs), comm_(comm), coarsest_(o.coarsestSize),
        variant_(o.interpolationVectorVariant) {
    MPI_Comm_size(comm, &ranks_);
  }
  ~HypreAmgSolver() override { release(); }

  void setup(const CsrMatrix<DeviceSpace> &a) override {
    const HostLibraryStaging staging;
    const auto start = std::chrono::steady_clock::now();
    Kokkos::fence();
    ++setups_;
    upper_ = {}; // the old values' copy, released before the new setup's allocations
    if (directNext_ && !direct_) { // an earlier solve found the AMG no cheaper than it
      matrix_ = a;
      ++patterns_;
      directNext_ = false;
      std::string why;
      if (fallBackToDirect(why)) {
        ++builds_;
      } else {
        appendNote(setupNote_, why);
        build();
      }
    } else if (direct_) { // the fall back of an earlier solve stays for the run
      direct_->setup(a);
      matrix_ = a;
      ++patterns_;
      ++builds_;
    } else if (options_.reuseHierarchy && (amg_ || cycle_) && !rebuild_ && samePattern(a)) {
      // the hierarchy stays (hypre's, or mixcon's copy of it); its fine level takes the values
      if (ij_)
        setValues(a, "IJMatrixSetValues (kept hierarchy)");
      else if (parA_)
        detail::fillSerialParCsr(parA_, a, 0);
      if (ijP_) {
        std::vector<HYPRE_Int> counts = componentCounts(a);
        setComponentValues(a, counts, "IJMatrixSetValues (kept hierarchy, separate components)");
      } else if (parP_) {
        detail::fillSerialParCsr(parP_, a, dofs_.dofsPerNode);
      }
      normInf_ = rowSumNorm(a);
      MPI_Allreduce(MPI_IN_PLACE, &normInf_, 1, MPI_DOUBLE, MPI_MAX, comm_);
      matrix_ = a;
      if (cycle_) // the copy's fine level follows, as hypre's level 0 did
        cycle_->setFineMatrix(a);
      buildCoarseSpace(); // its Galerkin operator follows the values
      ++reuses_;
      kept_ = true;
    } else {
      matrix_ = a;
      ++patterns_;
      build();
    }
    setupSeconds_ = seconds(start);
  }

  LinearSolveStats solve(const Kokkos::View<const double *, DeviceSpace> &b,
                         const Kokkos::View<double *, DeviceSpace> &x) override {
    const HostLibraryStaging staging;
    const auto start = std::chrono::steady_clock::now();
    std::string note;
    LinearSolveStats s = direct_ ? direct_->solve(b, x) : iterate(b, x);
    int total = s.iterations;
    // A kept hierarchy that no longer converges: redo the solve with a fresh one.
    if (!direct_ && kept_ && !s.converged) {
      note = "AMG hierarchy rebuilt (the kept one did not converge in " +
             std::to_string(s.iterations) + " iterations)";
      build();
      s = iterate(b, x);
      total += s.iterations;
    }
    // The escalation ladder: the coarse space, a stronger AMG, then the direct solver. Before
    // each step, the direct solver where it is estimated to factor the system in less time than
    // the AMG has spent on it: no step would pay then (small and slender parts, whose factors
    // are almost banded). A refused factorization (singular) leaves the ladder to go on.
    bool directTaken = false;
    const DirectInstead directInstead = [&](std::string &why) {
      if (direct_ || !directCheaper(start, why))
        return false;
      std::string step;
      directTaken = fallBackToDirect(step);
      why = "AMG stalled (" + why + ")";
      appendNote(why, step);
      return directTaken;
    };
    const auto attempt = [&] { return direct_ ? direct_->solve(b, x) : iterate(b, x); };
    s = climbLadder(*this, s, attempt, note, total, directInstead);
    if (directTaken) { // the ladder stopped for the direct solver
      s = attempt();
      total += s.iterations;
    }
    if (!direct_ && kept_ && s.iterations > options_.reuseIterationGrowth * freshIterations_)
      rebuild_ = true; // the next setup builds a fresh hierarchy
    // Converged, but slowly: the next setups take the next step of the ladder (the coarse space,
    // a larger coarsest level or, where that would hold the whole problem, the direct solver).
    if (!direct_ && s.converged && 2 * s.iterations > options_.escalationIterations) {
      const std::string took = "AMG took " + std::to_string(s.iterations) + " iterations";
      std::string cheaper;
      if (directCheaper(start, cheaper)) {
        directNext_ = true;
        appendNote(note, took + " (" + cheaper + "): the next setups use the direct solver");
      } else if (coarseStepLeft()) {
        coarseOn_ = true;
        appendNote(note, took + ": the next setups add a rigid-body coarse space");
      } else if (directBeforeNextStep()) {
        directNext_ = true;
        appendNote(note, took + " on " + std::to_string(dofs_.numGlobal) +
                             " unknowns: the next setups use the direct solver");
      } else if (nextCoarsest() > coarsest_) {
        coarsest_ = nextCoarsest();
        rebuild_ = true;
        appendNote(note, took + ": the next hierarchies stop at " + std::to_string(coarsest_) +
                             " unknowns");
      }
    }
    if (!direct_ && !kept_)
      freshIterations_ = std::max(s.iterations, 1);
    if (!setupNote_.empty()) { // what the last setup was asked for and did not build, and why
      appendNote(note, setupNote_);
      setupNote_.clear();
    }
    s.iterations = total;
    s.note = note;
    s.solveSeconds = seconds(start);
    s.setupSeconds = setupSeconds_;
    return s;
  }

  void precondition(const Kokkos::View<const double *, DeviceSpace> &b,
                    const Kokkos::View<double *, DeviceSpace> &x) override {
    const HostLibraryStaging staging;
    if (direct_) {
      direct_->precondition(b, x);
      return;
    }
    if (coarse_)
      twoLevel(b, x);
    else
      vcycle(b, x);
  }

  /// x = B b: one BoomerAMG V-cycle from a zero initial guess.
  void vcycle(const Kokkos::View<const double *, DeviceSpace> &b,
              const Kokkos::View<double *, DeviceSpace> &x) {
    if (cycle_) { // mixcon's kernels on the copy of the hierarchy
      cycle_->apply(b, x);
      return;
    }
    // Once per iteration of the Krylov method around it: on the views' memory where hypre can.
    const HYPRE_Int n = dofs_.numOwned();
    if constexpr (kHypreReadsKokkosMemory) {
      Kokkos::deep_copy(x, 0.0);
      Kokkos::fence();
      const BorrowedVector borrowB(parb_, b.data()), borrowX(parx_, x.data());
      HYPRE_BoomerAMGSolve(amg_, hierarchyMatrix(), parb_, parx_);
    } else {
      const auto hb = copyToHost(b);
      auto hx = hostMirror(x);
      HYPRE_IJVectorSetValues(ijb_, n, rows_.data(), hb.data());
      HYPRE_IJVectorSetValues(ijx_, n, rows_.data(), zero_.data());
      HYPRE_BoomerAMGSolve(amg_, hierarchyMatrix(), parb_, parx_);
      HYPRE_IJVectorGetValues(ijx_, n, rows_.data(), hx.data());
      copyToDevice(x, hx);
    }
  }

  bool strengthen(std::string &note) override {
    const HostLibraryStaging staging;
    if (direct_ || matrix_.numRows == 0)
      return false;
    // First the rigid-body coarse space, the remedy for what stalls BoomerAMG most (slender
    // parts); where it cannot be built, why, and the next step.
    if (coarseStepLeft()) {
      std::string why;
      if (makeCoarseSpace(why)) {
        coarseOn_ = true;
        appendNote(note, "AMG stalled: a rigid-body coarse space of " +
                             std::to_string(coarse_->size()) + " unknowns added");
        return true;
      }
      coarseRefused_ = true;
      appendNote(note, "no rigid-body coarse space: " + why);
    }
    // A step whose coarsest level would hold the whole problem is a dense direct solve behind
    // a hierarchy that hypre still coarsens once: the sparse direct solver instead, where allowed.
    if (nextCoarsest() > coarsest_ && !directBeforeNextStep()) {
      std::ostringstream o;
      o << "AMG rebuilt with a coarsest level of up to " << nextCoarsest() << " unknowns (was "
        << coarsest_ << ")";
      coarsest_ = nextCoarsest();
      build();
      appendNote(note, o.str());
      return true;
    }
    if (directFallbackAllowed()) {
      std::string step;
      const bool taken = fallBackToDirect(step);
      appendNote(note, step);
      return taken;
    }
    return false;
  }

  void setNearNullSpace(const Kokkos::View<const double **, DeviceSpace> &positions) override {
    positions_ = positions;
  }

  int iterationsPerAttempt(int maxIterations) const override {
    return !direct_ && coarseStepLeft() ? std::min(maxIterations, options_.escalationIterations)
                                        : maxIterations;
  }

  std::string name() const override {
    if (direct_)
      return direct_->name() + " (fallen back from AMG)";
    // Before the first setup, the coarse space asked for; after it, the one built (or none).
    const bool coarse = coarse_ || (options_.coarseSpace == CoarseSpace::RigidBody && builds_ == 0);
    std::string n = coarse ? (options_.symmetric ? "CG + BoomerAMG" : "GMRES + BoomerAMG")
                    : options_.symmetric ? "hypre PCG + BoomerAMG"
                                         : "hypre GMRES + BoomerAMG";
    n += " (" + smootherLabel() + ")";
    // Before the first setup, the cycle asked for (or the one auto takes where it applies); after
    // it, the one taken.
    if (cycle_ || (builds_ == 0 && cycleExpected()))
      n = std::string(options_.symmetric ? "CG" : "GMRES") + " + BoomerAMG (" + smootherLabel() +
          "; its V-cycle by mixcon in " +
          (cycle_ ? amgCyclePrecisionName(cycle_->precision())
           : options_.cycle == AmgCycleKind::MixconDouble ? "double"
                                                          : "single") +
          " precision)";
    else if (!cycleRefusal_.empty())
      n += " (hypre's V-cycle: mixcon's takes " + cycleRefusal_ + ")";
    if (separate())
      n += " on the separate displacement components";
    else if (!rotations_.empty() || willUseRotations())
      n += " with rigid-body modes";
    if (coarse_)
      n += " and a rigid-body coarse space of " + std::to_string(coarse_->size()) + " unknowns";
    else if (coarse)
      n += " and a rigid-body coarse space";
    return n;
  }
  double setupSeconds() const override { return setupSeconds_; }
  int builds() const override { return builds_; }
  int reuses() const override { return reuses_; }

private:
  /// The smoother taken, with the Chebyshev smoother's order.
  std::string smootherLabel() const {
    std::string s = smootherName(options_.smoother);
    if (resolvedSmoother(options_.smoother) == AmgSmoother::Chebyshev)
      s += " of order " + std::to_string(options_.chebyshevOrder);
    return s;
  }

  /// hypre's setup with interpolation vectors can end in an argument error (GM2 on the Lame
  /// quarter annulus: error 12, an argument check inside the vector fitting) where GM1 does not:
  /// then the hierarchy is built again with GM1, then without the vectors. True when it was (the
  /// caller's build is over); throws for an error without vectors.
  bool retried(HYPRE_Int err, const char *what) {
    if (err == 0)
      return false;
    if (rotations_.empty())
      check(err, what);
    HYPRE_ClearAllErrors();
    variant_ = variant_ == 1 ? 0 : 1; // 0: no interpolation vectors
    build();
    return true;
  }

  /// Why the hierarchy just built with interpolation vectors is unsound, or empty
  /// (detail::unsoundDiagonals over each level's diagonal, reduced over the ranks). With hypre's GM
  /// variants the coarse matrices of some meshes (thin Hex8 and Hex20 plates, the Lame sphere and
  /// cylinders: docs/performance.md, issue 20 section 1c) come out with diagonals from 2e-31 to
  /// 1e6 and stored zeros: a V-cycle on them loses everything in single precision (CG ends on a
  /// NaN) and converges slowly in double. Called right after hypre's setup, while every level
  /// (K's too, detail::DiagonalFirst) has each row's diagonal first: a row is read up to its first
  /// entry (0.009 s on the cube N = 48). Collective: every rank takes part, with or without local
  /// rows. Host-resident hierarchies only (a GPU hypre keeps its levels in device memory: not
  /// checked there).
  std::string unsoundInterpolation() const {
    int vectors = rotations_.empty() ? 0 : 1; // the same on every rank, made sure of
    MPI_Allreduce(MPI_IN_PLACE, &vectors, 1, MPI_INT, MPI_MAX, comm_);
    if (vectors == 0 || kGpuHypre)
      return {};
    auto *data = reinterpret_cast<hypre_ParAMGData *>(amg_);
    const int nl = hypre_ParAMGDataNumLevels(data);
    hypre_ParCSRMatrix **levels = hypre_ParAMGDataAArray(data);
    std::vector<detail::DiagonalRange> ranges(nl);
    // per level: -smallest, largest, whether improper, whether it has rows: one MAX reduction
    std::vector<double> local(4 * static_cast<std::size_t>(nl));
    for (int l = 0; l < nl; ++l) {
      detail::DiagonalRange &r = ranges[l];
      const hypre_CSRMatrix *d = hypre_ParCSRMatrixDiag(levels[l]);
      const HYPRE_Int *ro = hypre_CSRMatrixI(d);
      const HYPRE_Int *co = hypre_CSRMatrixJ(d);
      const HYPRE_Complex *va = hypre_CSRMatrixData(d);
      for (HYPRE_Int i = 0; i < hypre_CSRMatrixNumRows(d); ++i) {
        double aii = 0.0;                             // a row without its diagonal: a zero
        for (HYPRE_Int k = ro[i]; k < ro[i + 1]; ++k) // hypre's order: the diagonal first
          if (co[k] == i) {
            aii = va[k];
            break;
          }
        r.add(aii);
      }
      local[4 * l] = -r.smallest;
      local[4 * l + 1] = r.largest;
      local[4 * l + 2] = r.improper ? 1.0 : 0.0;
      local[4 * l + 3] = r.rows > 0 ? 1.0 : 0.0;
    }
    MPI_Allreduce(MPI_IN_PLACE, local.data(), 4 * nl, MPI_DOUBLE, MPI_MAX, comm_);
    for (int l = 0; l < nl; ++l) {
      ranges[l].smallest = -local[4 * l];
      ranges[l].largest = local[4 * l + 1];
      ranges[l].improper = local[4 * l + 2] > 0.0;
      ranges[l].rows = local[4 * l + 3] > 0.0 ? 1 : 0;
    }
    return detail::unsoundDiagonals(ranges);
  }

  bool willUseRotations() const {
    const int dim = dofs_.dofsPerNode;
    return options_.rigidBodyModes && !separate() && variant_ > 0 && (dim == 2 || dim == 3) &&
           positions_.extent(0) > 0 && static_cast<int>(positions_.extent(1)) == dim &&
           static_cast<LocalIndex>(positions_.extent(0)) == dofs_.numLocalNodes;
  }

  /// Same rows and columns as the matrix of the last setup, matrix_ (the same views, or equal
  /// arrays).
  bool samePattern(const CsrMatrix<DeviceSpace> &a) const {
    if (a.numRows != builtRows_ || a.columns.extent(0) != matrix_.columns.extent(0))
      return false;
    if (a.rowOffsets.data() == matrix_.rowOffsets.data() &&
        a.columns.data() == matrix_.columns.data())
      return true;
    const auto ro = hostReadable(a.rowOffsets);
    const auto co = hostReadable(a.columns);
    const auto built = hostReadable(matrix_.columns);
    for (LocalIndex i = 0; i < a.numRows; ++i)
      if (ncols_[i] != static_cast<HYPRE_Int>(ro(i + 1) - ro(i)))
        return false;
    for (std::size_t k = 0; k < co.extent(0); ++k)
      if (built(k) != co(k))
        return false;
    return true;
  }

  /// HYPRE_IJMatrixSetValues of all rows of `a` into ij_. The global column numbers are the
  /// matrix's own array where they coincide with its local ones (one rank, and hypre's integer
  /// type is LocalIndex), else a temporary copy: none is kept (it was 1 GB for the 3.1M-unknown
  /// cube, docs/performance.md).
  void setValues(const CsrMatrix<DeviceSpace> &a, const char *what) {
    const auto co = hostReadable(a.columns);
    const auto va = hostReadable(a.values);
    const HYPRE_BigInt lo = dofs_.ownedBegin;
    if constexpr (std::is_same_v<HYPRE_BigInt, LocalIndex>) {
      if (lo == 0) {
        check(HYPRE_IJMatrixSetValues(ij_, a.numRows, ncols_.data(), rows_.data(), co.data(),
                                      va.data()),
              what);
        return;
      }
    }
    std::vector<HYPRE_BigInt> global(co.extent(0));
    for (std::size_t k = 0; k < global.size(); ++k)
      global[k] = lo + co(k); // serial numbering: local column + first owned row
    check(HYPRE_IJMatrixSetValues(ij_, a.numRows, ncols_.data(), rows_.data(), global.data(),
                                  va.data()),
          what);
  }

  /// The hypre matrix, vectors and a fresh BoomerAMG hierarchy with its Krylov method, from
  /// matrix_. Where it throws, nothing of it is kept (hypre's matrix may read matrix_'s own
  /// arrays, which a kept hierarchy's new values would then be written into): the next setup()
  /// builds afresh.
  void build() {
    try {
      buildHierarchy();
    } catch (...) {
      release();
      rebuild_ = true;
      throw;
    }
  }

  void buildHierarchy() {
    release();
    const CsrMatrix<DeviceSpace> &a = matrix_;
    const HYPRE_BigInt lo = dofs_.ownedBegin, hi = dofs_.ownedEnd() - 1;
    const HYPRE_Int n = a.numRows;
    const auto ro = hostReadable(a.rowOffsets);

    ncols_.resize(n);
    rows_.resize(n); // owned global rows, reused by every solve() and precondition()
    zero_.assign(n, 0.0);
    for (HYPRE_Int i = 0; i < n; ++i) {
      ncols_[i] = static_cast<HYPRE_Int>(ro(i + 1) - ro(i));
      rows_[i] = lo + i;
    }
    builtRows_ = n;
    normInf_ = rowSumNorm(a);
    MPI_Allreduce(MPI_IN_PLACE, &normInf_, 1, MPI_DOUBLE, MPI_MAX, comm_);
    // hypre's copy of A: the hierarchy's matrix, or (separate components) only for hypre's
    // Krylov method, which mixcon's cycle does not need (built below where that is not taken)
    // (on one rank in host memory, BoomerAMG reads K itself, its rows in hypre's order until
    // the hierarchy is built: detail::borrowedParCsr)
    std::optional<detail::DiagonalFirst> borrowed;
    if (separate()) {
      buildComponentMatrix(a);
    } else if (borrowsMatrix()) {
      borrowed.emplace(a);
      parA_ = detail::borrowedParCsr(comm_, a);
    } else {
      buildHypreMatrix(a);
    }

    for (HYPRE_IJVector *v : {&ijb_, &ijx_, &ijr_}) {
      check(HYPRE_IJVectorCreate(comm_, lo, hi, v), "IJVectorCreate");
      check(HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR), "IJVectorSetObjectType");
      check(HYPRE_IJVectorInitialize(*v), "IJVectorInitialize");
      check(HYPRE_IJVectorAssemble(*v), "IJVectorAssemble");
    }
    HYPRE_IJVectorGetObject(ijb_, reinterpret_cast<void **>(&parb_));
    HYPRE_IJVectorGetObject(ijx_, reinterpret_cast<void **>(&parx_));
    HYPRE_IJVectorGetObject(ijr_, reinterpret_cast<void **>(&parr_));

    HYPRE_BoomerAMGCreate(&amg_);
    HYPRE_BoomerAMGSetCoarsenType(amg_, 10); // HMIS
    HYPRE_BoomerAMGSetInterpType(amg_, 6);   // extended+i
    HYPRE_BoomerAMGSetPMaxElmts(amg_, options_.interpolationMaxElements);
    HYPRE_BoomerAMGSetStrongThreshold(amg_, options_.strongThreshold);
    const AmgSmoother smoother = resolvedSmoother(options_.smoother);
    HYPRE_BoomerAMGSetRelaxType(amg_, smoother == AmgSmoother::L1Jacobi    ? 18
                                      : smoother == AmgSmoother::Chebyshev ? 16
                                                                           : 8);
    // Chebyshev's eigenvalue bound: hypre's Lanczos (CG) estimate, 10 steps per level, where
    // the loaded hypre has mixcon's fix of it; otherwise Gershgorin's discs, looser but safe (the
    // unfixed estimate never returned on NAFEMS LE10 and the 3D mixed model's Lame sphere:
    // docs/performance.md 3b).
    if (smoother == AmgSmoother::Chebyshev) {
      HYPRE_BoomerAMGSetChebyEigEst(amg_, detail::hypreChebyshevEstimateIsSafe() ? 10 : 0);
      HYPRE_BoomerAMGSetChebyOrder(amg_, options_.chebyshevOrder);
    }
    HYPRE_BoomerAMGSetNumSweeps(amg_, 1);
    HYPRE_BoomerAMGSetNumFunctions(amg_, dofs_.dofsPerNode); // interleaved nodal unknowns
    if (options_.nodalCoarsening)
      HYPRE_BoomerAMGSetNodal(amg_, 1); // coarsen nodes by the Frobenius norm of their blocks
    HYPRE_BoomerAMGSetAggNumLevels(amg_, options_.aggressiveLevels);
    HYPRE_BoomerAMGSetMaxCoarseSize(amg_, coarsest_);
    if (coarsest_ > kGaussEliminationSize) // a large coarsest level: inverted once, at setup
      HYPRE_BoomerAMGSetCycleRelaxType(amg_, 199, 3);
    HYPRE_BoomerAMGSetMaxIter(amg_, 1); // one V-cycle as preconditioner
    HYPRE_BoomerAMGSetTol(amg_, 0.0);
    HYPRE_BoomerAMGSetPrintLevel(amg_, options_.printLevel);
    if (setRotations())
      check(HYPRE_BoomerAMGSetInterpVectors(amg_, static_cast<HYPRE_Int>(rotations_.size()),
                                            rotations_.data()),
            "BoomerAMGSetInterpVectors");

    // BoomerAMG's hierarchy on A or, with separate components, on their matrix; then either
    // mixcon's copy of it (copyCycle: mixcon's Krylov method on matrix_, no hypre A needed with
    // separate components) or hypre's Krylov method around hypre's V-cycle (on the filtered
    // matrix: componentVcycle), whose setup leaves the hierarchy as it is (noSetup).
    const HYPRE_Int setupError = HYPRE_BoomerAMGSetup(amg_, hierarchyMatrix(), parb_, parx_);
    // checked while every level, K's too, has each row's diagonal first
    const std::string unsound = setupError == 0 ? unsoundInterpolation() : std::string();
    if (borrowed) // K is mixcon's again (the cycle's copy reads it in its own order)
      borrowed->restore();
    if (retried(setupError, parP_ ? "BoomerAMG setup (separate components)" : "BoomerAMG setup"))
      return;
    if (const std::string &why = unsound; !why.empty()) {
      appendNote(setupNote_, "BoomerAMG's hierarchy with rigid-body interpolation vectors " + why +
                                 ": built without them");
      variant_ = 0; // for the rest of the run (GM1 is skipped: sound but no faster there)
      build();
      return;
    }
    copyCycle();
    if (cycle_) {
      finishBuild(); // releases parA_, which never held a copy
      return;
    }
    if (borrowed) // hypre's Krylov method and V-cycle read it at every solve: its own copy
      detail::ownParCsrData(parA_, a);
    auto precondSolve = reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSolve);
    const HYPRE_PtrToSolverFcn precondSetup = &noSetup;
    HYPRE_Solver precondData = amg_;
    if (parP_) {
      buildHypreMatrix(a);
      precondSolve = &componentVcycle;
      precondData = reinterpret_cast<HYPRE_Solver>(this);
    }
    if (options_.symmetric) {
      HYPRE_ParCSRPCGCreate(comm_, &pcg_);
      HYPRE_PCGSetTol(pcg_, options_.tolerance);
      HYPRE_PCGSetAbsoluteTol(pcg_, 0.0);
      HYPRE_PCGSetMaxIter(pcg_, options_.maxIterations);
      HYPRE_PCGSetTwoNorm(pcg_, 1);
      HYPRE_PCGSetPrintLevel(pcg_, options_.printLevel);
      HYPRE_PCGSetPrecond(pcg_, precondSolve, precondSetup, precondData);
      if (retried(HYPRE_ParCSRPCGSetup(pcg_, parA_, parb_, parx_), "PCG/BoomerAMG setup"))
        return;
    } else {
      HYPRE_ParCSRGMRESCreate(comm_, &gmres_);
      HYPRE_GMRESSetKDim(gmres_, options_.gmresRestart);
      HYPRE_GMRESSetTol(gmres_, options_.tolerance);
      HYPRE_GMRESSetAbsoluteTol(gmres_, 0.0);
      HYPRE_GMRESSetMaxIter(gmres_, options_.maxIterations);
      HYPRE_GMRESSetPrintLevel(gmres_, options_.printLevel);
      HYPRE_GMRESSetPrecond(gmres_, precondSolve, precondSetup, precondData);
      if (retried(HYPRE_ParCSRGMRESSetup(gmres_, parA_, parb_, parx_), "GMRES/BoomerAMG setup"))
        return;
    }
    finishBuild();
  }

  /// What every build ends with: hypre's objects released where mixcon's cycle took a copy of
  /// the hierarchy (from then on it holds what the solves need: the copy and matrix_; 3 GB of
  /// hypre's A and its hierarchy at 3.1M unknowns), the coarse space, the counts.
  void finishBuild() {
    if (cycle_)
      releaseHypre();
    buildCoarseSpace();
    ++builds_;
    kept_ = false;
    rebuild_ = false;
  }

  /// parA_: hypre's copy of `a` (matrix_), built in place on one rank (detail::serialParCsr), else
  /// through ij_.
  void buildHypreMatrix(const CsrMatrix<DeviceSpace> &a) {
    if (serialBuild()) {
      parA_ = detail::serialParCsr(comm_, a, ncols_, 0);
      return;
    }
    const HYPRE_BigInt lo = dofs_.ownedBegin, hi = dofs_.ownedEnd() - 1;
    const std::vector<HYPRE_Int> offdSizes(a.numRows, 0);
    check(HYPRE_IJMatrixCreate(comm_, lo, hi, lo, hi, &ij_), "IJMatrixCreate");
    check(HYPRE_IJMatrixSetObjectType(ij_, HYPRE_PARCSR), "IJMatrixSetObjectType");
    // the rows of one SetValues call are distinct (each owned row once): hypre may fill them on
    // its threads (hypre_IJMatrixSetValuesOMPParCSR; serial in a hypre without OpenMP)
    check(HYPRE_IJMatrixSetOMPFlag(ij_, 1), "IJMatrixSetOMPFlag");
    check(HYPRE_IJMatrixSetDiagOffdSizes(ij_, ncols_.data(), offdSizes.data()),
          "IJMatrixSetDiagOffdSizes");
    check(HYPRE_IJMatrixInitialize(ij_), "IJMatrixInitialize");
    setValues(a, "IJMatrixSetValues");
    check(HYPRE_IJMatrixAssemble(ij_), "IJMatrixAssemble");
    check(HYPRE_IJMatrixGetObject(ij_, reinterpret_cast<void **>(&parA_)), "IJMatrixGetObject");
  }

  /// Before a setup: mixcon's cycle is asked for, or left to auto where it will apply (one rank,
  /// the Chebyshev smoother, a CPU hypre).
  bool cycleExpected() const {
    switch (options_.cycle) {
    case AmgCycleKind::MixconDouble:
    case AmgCycleKind::MixconSingle:
      return true;
    case AmgCycleKind::Automatic:
      return !kGpuHypre && ranks_ == 1 &&
             resolvedSmoother(options_.smoother) == AmgSmoother::Chebyshev;
    default:
      return false;
    }
  }

  /// cycle_: BoomerAMG's hierarchy copied for mixcon's V-cycle (LinearSolverOptions::cycle),
  /// where it is asked for (or left automatic) and the hierarchy is one this copy applies as
  /// hypre would; otherwise hypre's cycle stays and, where the copy was asked for by name,
  /// cycleRefusal_ says why (in the solver's name).
  void copyCycle() {
    cycle_.reset();
    cycleRefusal_.clear();
    if (options_.cycle == AmgCycleKind::Hypre)
      return;
    std::vector<HostAmgLevel> levels;
    cycleRefusal_ = hostLevels(levels);
    if (cycleRefusal_.empty()) {
      const AmgCyclePrecision precision = options_.cycle == AmgCycleKind::MixconDouble
                                              ? AmgCyclePrecision::Double
                                              : AmgCyclePrecision::Single;
      try {
        cycle_ = std::make_unique<AmgCycle>(matrix_, separate() ? dofs_.dofsPerNode : 0, levels,
                                            precision, matrixBlocks());
      } catch (const std::runtime_error &e) {
        cycleRefusal_ = e.what();
      }
    }
    if (options_.cycle == AmgCycleKind::Automatic)
      cycleRefusal_.clear(); // hypre's cycle where the copy does not apply, said nowhere
  }

  /// matrix_'s upper block triangle (d = 0 where there is none: a matrix not said to be symmetric
  /// (LinearSolverOptions::symmetric, the word the Cholesky factorization takes too), several
  /// ranks, device memory, fewer chunks than the host has threads: a small mesh or a wide
  /// numbering; whether it is used so depends on the thread count, its sums do not), copied at the
  /// first solve after each setup. The CG's product from it reads half the bytes of K's (the
  /// cube's N = 100: 1.1 of 2.2 GB per product, docs/performance.md table 3l).
  const SymmetricBlocks<DeviceSpace> &upperBlocks() {
    if (upperSetup_ != setups_ && options_.symmetric && ranks_ == 1)
      upper_ = symmetricBlocks(matrixBlocks(), ConstDeviceVector(matrix_.values),
                               Kokkos::DefaultHostExecutionSpace().concurrency());
    upperSetup_ = setups_;
    return upper_;
  }

  /// matrix_'s node blocks (d = 0 where its pattern has none), found once per pattern.
  const NodeBlocks<DeviceSpace> &matrixBlocks() {
    if (blocksPattern_ != patterns_) {
      blocks_ = nodeBlocks(Kokkos::DefaultExecutionSpace(), matrix_, dofs_.dofsPerNode);
      blocksPattern_ = patterns_;
    }
    return blocks_;
  }

  /// The levels of amg_'s hierarchy as AmgCycle takes them; empty where they all could be
  /// described, else why not.
  std::string hostLevels(std::vector<HostAmgLevel> &levels) const {
    static_assert(std::is_same_v<HYPRE_Int, int>, "AmgCycle reads hypre's int indices");
    if (ranks_ != 1)
      return "one rank only";
    if (kGpuHypre)
      return "a CPU hypre (this one keeps its hierarchy in device memory)";
    if (resolvedSmoother(options_.smoother) != AmgSmoother::Chebyshev)
      return "the Chebyshev smoother only";
    auto *data = reinterpret_cast<hypre_ParAMGData *>(amg_);
    const int nl = hypre_ParAMGDataNumLevels(data);
    const HYPRE_Int *relax = hypre_ParAMGDataGridRelaxType(data);
    const HYPRE_Int *sweeps = hypre_ParAMGDataNumGridSweeps(data);
    if (nl < 2)
      return "a hierarchy of one level";
    if (relax[1] != 16 || relax[2] != 16 || sweeps[1] != 1 || sweeps[2] != 1 || sweeps[3] != 1 ||
        !(relax[3] == 9 || relax[3] == 99 || relax[3] == 199 || relax[3] == 16) ||
        hypre_ParAMGDataCycleType(data) != 1 || hypre_ParAMGDataFCycle(data) ||
        hypre_ParAMGDataRestriction(data) != 0 || hypre_ParAMGDataBlockMode(data) ||
        hypre_ParAMGDataPartialCycleCoarsestLevel(data) >= 0 ||
        hypre_ParAMGDataSmoothNumLevels(data) > 0 || hypre_ParAMGDataChebyScale(data) != 1 ||
        hypre_ParAMGDataChebyVariant(data) != 0 ||
        (hypre_ParAMGDataAdditive(data) >= 0 && hypre_ParAMGDataAdditive(data) < nl) ||
        (hypre_ParAMGDataMultAdditive(data) >= 0 && hypre_ParAMGDataMultAdditive(data) < nl) ||
        (hypre_ParAMGDataSimple(data) >= 0 && hypre_ParAMGDataSimple(data) < nl))
      return "a V-cycle other than one scaled Chebyshev sweep per level";
    const int order = std::clamp(static_cast<int>(hypre_ParAMGDataChebyOrder(data)), 1, 4);
    const auto local = [](hypre_ParCSRMatrix *m) {
      hypre_CSRMatrix *d = hypre_ParCSRMatrixDiag(m);
      AmgHostCsr h;
      h.rowOffsets = hypre_CSRMatrixI(d);
      h.columns = hypre_CSRMatrixJ(d);
      h.values = hypre_CSRMatrixData(d);
      h.rows = hypre_CSRMatrixNumRows(d);
      h.columnsCount = hypre_CSRMatrixNumCols(d);
      return h;
    };
    levels.resize(nl);
    for (int l = 0; l < nl; ++l) {
      HostAmgLevel &h = levels[l];
      h.a = local(hypre_ParAMGDataAArray(data)[l]);
      if (l + 1 < nl)
        h.p = local(hypre_ParAMGDataPArray(data)[l]);
      // the coarsest level too where hypre smooths it (relax type 16 there: its coarsening
      // stopped early, e.g. HMIS on 16 threads at the cube's N = 100, docs/performance.md)
      if (l + 1 < nl || relax[3] == 16) {
        if (!hypre_ParAMGDataChebyDS(data)[l] || !hypre_ParAMGDataChebyCoefs(data)[l])
          return "Chebyshev coefficients on every level";
        h.ds = hypre_VectorData(hypre_ParAMGDataChebyDS(data)[l]);
        const HYPRE_Real *c = hypre_ParAMGDataChebyCoefs(data)[l];
        h.coefficients.assign(c, c + order);
      }
    }
    return {};
  }

  /// The rigid-body coarse space of LinearSolverOptions::coarseSpace on matrix_, where it is
  /// asked for or the ladder took it; where it cannot be had, why goes to the next solve's note
  /// (and the ladder's step is given up).
  void buildCoarseSpace() {
    coarse_.reset();
    if (!(options_.coarseSpace == CoarseSpace::RigidBody || coarseOn_))
      return;
    std::string why;
    if (!makeCoarseSpace(why)) {
      if (options_.coarseSpace == CoarseSpace::OnStall) { // the ladder goes on without it
        coarseOn_ = false;
        coarseRefused_ = true;
      }
      // Said once per reason (a Newton run sets up every iteration), in the next solve's note.
      if (why != coarseRefusal_)
        appendNote(setupNote_, "no rigid-body coarse space: " + why);
    }
    coarseRefusal_ = why;
  }

  /// coarse_ on matrix_ (one rank, node positions given); false, with why, where it cannot be
  /// built.
  bool makeCoarseSpace(std::string &why) {
    coarse_.reset();
    if (!coarseSpacePossible())
      why = ranks_ != 1 ? "it needs one rank"
                        : "it needs the node positions of 2 or 3 displacement unknowns per node";
    else {
      auto c = std::make_unique<RigidCoarseSpace>(
          matrix_, positions_, rigidCoarseSpaceLimit(dofs_.dofsPerNode), options_.symmetric);
      if (c->ok())
        coarse_ = std::move(c);
      else
        why = c->why();
    }
    return coarse_ != nullptr;
  }

  bool coarseSpacePossible() const {
    return ranks_ == 1 && static_cast<LocalIndex>(positions_.extent(0)) == dofs_.numLocalNodes &&
           static_cast<int>(positions_.extent(1)) == dofs_.dofsPerNode;
  }

  /// The ladder's first step, the coarse space (CoarseSpace::OnStall), is still to be taken.
  bool coarseStepLeft() const {
    return options_.coarseSpace == CoarseSpace::OnStall && !coarseOn_ && !coarseRefused_ &&
           coarseSpacePossible();
  }

  /// z = M^-1 r with the balancing preconditioner of the coarse space around one V-cycle B:
  /// c = C r, y = B (r - A c), z = c + y - C A y (solver/RigidCoarseSpace.hpp).
  void twoLevel(const ConstDeviceVector &r, const DeviceVector &z) {
    const std::size_t n = r.extent(0);
    for (DeviceVector *v : {&cw_, &sw_, &yw_, &qw_})
      if (v->extent(0) != n)
        *v = DeviceVector("mixcon::amg::twoLevel", n);
    coarseApply(r, cw_);
    product(ConstDeviceVector(cw_), sw_);
    axpby(1.0, r, -1.0, sw_);
    vcycle(sw_, yw_);
    product(ConstDeviceVector(yw_), qw_);
    coarseApply(qw_, sw_);
    Kokkos::deep_copy(z, cw_);
    axpby(1.0, yw_, 1.0, z);
    axpby(-1.0, sw_, 1.0, z);
  }

  /// z = C r on the host (solver/RigidCoarseSpace.cpp): the views' own memory where the host can
  /// read it.
  void coarseApply(const ConstDeviceVector &r, const DeviceVector &z) {
    Kokkos::fence();
    if constexpr (kHostAccessible<DeviceSpace>) {
      coarse_->apply(r.data(), z.data());
    } else {
      const auto hr = copyToHost(r);
      auto hz = hostMirror(z);
      coarse_->apply(hr.data(), hz.data());
      copyToDevice(z, hz);
    }
  }

  /// y = matrix_ x for iterateOwn() and twoLevel(): from its upper block triangle where it has
  /// one (half the traffic), else by its node blocks (a third less than the CSR's, the same sums).
  void product(const ConstDeviceVector &x, const DeviceVector &y) {
    const SymmetricBlocks<DeviceSpace> &upper = upperBlocks();
    const NodeBlocks<DeviceSpace> &blocks = matrixBlocks();
    if (upper.d > 0)
      multiply(upper, x, y);
    else if (blocks.d > 0)
      multiply(Kokkos::DefaultExecutionSpace(), blocks, ConstDeviceVector(matrix_.values), x, y);
    else
      multiply(matrix_, x, y);
  }

  /// iterate() with the coarse space or the copied cycle: mixcon's CG (GMRES for a nonsymmetric
  /// matrix) around twoLevel() or the V-cycle, on matrix_; the same convergence decision as
  /// hypre's Krylov methods.
  LinearSolveStats iterateOwn(const Kokkos::View<const double *, DeviceSpace> &b,
                              const Kokkos::View<double *, DeviceSpace> &x, double bnorm, int cap) {
    KrylovOptions ko;
    ko.method = options_.symmetric ? KrylovMethod::Cg : KrylovMethod::Gmres;
    ko.tolerance = options_.tolerance;
    ko.maxIterations = cap;
    ko.restart = options_.gmresRestart;
    ko.backwardErrorFloor = true; // stops there; converged or not is decided below
    const LinearMap a = [&](const ConstDeviceVector &v, const DeviceVector &y) { product(v, y); };
    const LinearMap p = [&](const ConstDeviceVector &r, const DeviceVector &z) {
      if (coarse_)
        twoLevel(r, z);
      else
        vcycle(r, z);
    };
    Kokkos::deep_copy(x, 0.0);
    const KrylovStats k = krylovSolve(ko, a, p, b, x, &workspace_);
    const double xx = dot(ConstDeviceVector(x), ConstDeviceVector(x));
    LinearSolveStats s;
    s.iterations = k.iterations;
    s.relativeResidual = k.relativeResidual;
    s.converged =
        trueResidualConverged(s.relativeResidual, xx, options_.tolerance, k.converged, 10.0,
                              backwardError(k.relativeResidual * std::sqrt(bnorm), normInf_,
                                            std::sqrt(xx), std::sqrt(bnorm)));
    return s;
  }

  /// One Krylov solve of A x = b with the current hierarchy, judged on the true residual. While
  /// a stronger level is left, at most escalationIterations iterations.
  LinearSolveStats iterate(const Kokkos::View<const double *, DeviceSpace> &b,
                           const Kokkos::View<double *, DeviceSpace> &x) {
    LinearSolveStats s;
    const HYPRE_Int n = dofs_.numOwned();
    const ConstDeviceVector owned = Kokkos::subview(b, std::make_pair(0, static_cast<int>(n)));
    double bnorm = dot(owned, owned); // a device reduction (b stays where it is)
    MPI_Allreduce(MPI_IN_PLACE, &bnorm, 1, MPI_DOUBLE, MPI_SUM, comm_);
    if (bnorm == 0.0) { // hypre divides by ||b||; the answer is x = 0, exactly
      Kokkos::deep_copy(x, 0.0);
      s.converged = true;
      return s;
    }
    const int cap = canStrengthen()
                        ? std::min(options_.maxIterations, options_.escalationIterations)
                        : options_.maxIterations;
    if (coarse_ || cycle_)
      return iterateOwn(b, x, bnorm, cap);
    if (pcg_)
      HYPRE_PCGSetMaxIter(pcg_, cap);
    else
      HYPRE_GMRESSetMaxIter(gmres_, cap);
    std::optional<BorrowedVector> borrowB, borrowX;
    if constexpr (kHypreReadsKokkosMemory) {
      Kokkos::deep_copy(x, 0.0); // the zero initial guess, written where hypre iterates
      Kokkos::fence();
      borrowB.emplace(parb_, b.data());
      borrowX.emplace(parx_, x.data());
    } else {
      const auto hb = copyToHost(b);
      HYPRE_IJVectorSetValues(ijb_, n, rows_.data(), hb.data());
      HYPRE_IJVectorSetValues(ijx_, n, rows_.data(), zero_.data());
    }
    HYPRE_Int err = 0, its = 0;
    const auto run = [&] { // one hypre solve from the current x; adds its iterations
      HYPRE_Int e = 0, k = 0;
      if (pcg_) {
        e = HYPRE_ParCSRPCGSolve(pcg_, parA_, parb_, parx_);
        HYPRE_PCGGetNumIterations(pcg_, &k);
      } else {
        e = HYPRE_ParCSRGMRESSolve(gmres_, parA_, parb_, parx_);
        HYPRE_GMRESGetNumIterations(gmres_, &k);
      }
      if (e != 0)
        HYPRE_ClearAllErrors(); // non-convergence is reported through stats
      its += k;
      return e;
    };
    // hypre's final residual is its recursively updated one: a breakdown (a singular matrix, an
    // indefinite preconditioner) can end as "1 iteration, residual 0" with x still 0. Decide from
    // the true residual ||b - A x|| / ||b|| of the system as posed.
    double rr = 0.0, xx = 0.0;
    const auto trueResidual = [&] {
      HYPRE_ParVectorCopy(parb_, parr_);
      HYPRE_ParCSRMatrixMatvec(-1.0, parA_, parx_, 1.0, parr_);
      HYPRE_ParVectorInnerProd(parr_, parr_, &rr);
      HYPRE_ParVectorInnerProd(parx_, parx_, &xx);
      return std::sqrt(rr / bnorm);
    };
    err = run();
    double relative = trueResidual();
    // At tight tolerances the recursive residual drifts below the true one (attainable accuracy):
    // where hypre stopped on it, restart from x with the true residual (residual replacement).
    for (int restart = 0; restart < 2 && err == 0 && relative > options_.tolerance && its < cap;
         ++restart) {
      err = run();
      relative = trueResidual();
    }
    if constexpr (!kHypreReadsKokkosMemory) {
      auto hx = hostMirror(x);
      HYPRE_IJVectorGetValues(ijx_, n, rows_.data(), hx.data());
      copyToDevice(x, hx);
    }
    s.iterations = its;
    s.relativeResidual = relative;
    s.converged = trueResidualConverged(
        s.relativeResidual, xx, options_.tolerance, err == 0, 10.0,
        backwardError(std::sqrt(rr), normInf_, std::sqrt(xx), std::sqrt(bnorm)));
    return s;
  }

  /// The next coarsest size of the ladder (the current one at its end).
  int nextCoarsest() const {
    for (int size : options_.escalationCoarsestSizes)
      if (size > coarsest_)
        return size;
    return coarsest_;
  }

  /// For solve() (a method around the AMG as a preconditioner has its own measure), where the
  /// direct fall back is allowed (LinearSolverOptions::directWhenCheaper): whether the direct
  /// solver's factorization of matrix_ is estimated (detail::estimatedDirectSeconds, from the
  /// pattern's analysis, done once per pattern) to take less than the AMG's seconds on the solve
  /// that began at `start`, its hierarchy's setup included. `why` gets both figures.
  bool directCheaper(std::chrono::steady_clock::time_point start, std::string &why) {
    return options_.directWhenCheaper && directFallbackAllowed() &&
           directCost_.cheaperThan(matrix_, options_.symmetric, setupSeconds_ + seconds(start),
                                   why);
  }

  /// One rank, few enough unknowns, and no singular matrix found by an earlier attempt.
  bool directFallbackAllowed() const {
    return !fallbackRefused_ && ranks_ == 1 && dofs_.numGlobal <= options_.directFallbackUnknowns;
  }

  bool canStrengthen() const {
    return coarseStepLeft() || nextCoarsest() > coarsest_ || directFallbackAllowed();
  }

  /// The ladder's next coarsest size is not below the problem's size, and the direct solver may
  /// take that step instead.
  bool directBeforeNextStep() const {
    return nextCoarsest() > coarsest_ && nextCoarsest() >= dofs_.numGlobal &&
           directFallbackAllowed();
  }

  /// Factorizes matrix_ with the direct solver, which serves the rest of the run; false, with
  /// why in `note`, where the matrix is singular (the AMG's answer stands then).
  bool fallBackToDirect(std::string &note) {
    auto direct = std::make_unique<DirectSolver>(comm_, options_);
    try {
      direct->setup(matrix_);
    } catch (const std::runtime_error &e) {
      fallbackRefused_ = true;
      note = std::string("no fall back to the direct solver: ") + e.what();
      return false;
    }
    direct_ = std::move(direct);
    release();
    note = "the AMG did not converge: falling back to the direct solver (" +
           std::to_string(dofs_.numGlobal) + " unknowns)";
    return true;
  }

  /// The rigid-body rotations of the positions as BoomerAMG interpolation vectors (the
  /// translations are the constants the systems AMG interpolates anyway): in 2D (-y, x), in 3D
  /// the three rotations about the axes, about the centroid. With nodal coarsening, as hypre's
  /// interpolation-vector variants require. False (nothing set) where they do not apply.
  bool setRotations() {
    if (!willUseRotations())
      return false;
    const int dim = dofs_.dofsPerNode;
    const auto x = hostReadable(positions_);
    const LocalIndex nn = dofs_.numLocalNodes;
    double centroid[3] = {0.0, 0.0, 0.0};
    for (LocalIndex k = 0; k < nn; ++k)
      for (int i = 0; i < dim; ++i)
        centroid[i] += x(k, i) / nn;
    const HYPRE_BigInt lo = dofs_.ownedBegin, hi = dofs_.ownedEnd() - 1;
    std::vector<double> values(dofs_.numOwned());
    for (int r = 0; r < rigidRotations(dim); ++r) {
      for (LocalIndex k = 0; k < nn; ++k) {
        double p[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < dim; ++i)
          p[i] = x(k, i) - centroid[i];
        for (int c = 0; c < dim; ++c)
          values[dim * k + c] = rigidRotation(dim, r, c, p);
      }
      HYPRE_IJVector v = nullptr;
      check(HYPRE_IJVectorCreate(comm_, lo, hi, &v), "IJVectorCreate");
      rotationVectors_.push_back(v);
      check(HYPRE_IJVectorSetObjectType(v, HYPRE_PARCSR), "IJVectorSetObjectType");
      check(HYPRE_IJVectorInitialize(v), "IJVectorInitialize");
      check(HYPRE_IJVectorSetValues(v, dofs_.numOwned(), rows_.data(), values.data()),
            "IJVectorSetValues");
      check(HYPRE_IJVectorAssemble(v), "IJVectorAssemble");
      HYPRE_ParVector par = nullptr;
      HYPRE_IJVectorGetObject(v, reinterpret_cast<void **>(&par));
      rotations_.push_back(par);
    }
    // Settings measured on the slender strips (docs/performance.md): nodal coarsening by the
    // row-sum norm of the node blocks, GM2 with at most 4 added entries per row, the vectors
    // smoothed and the interpolation refined once.
    HYPRE_BoomerAMGSetNodal(amg_, 4);
    HYPRE_BoomerAMGSetInterpVecVariant(amg_, variant_);
    HYPRE_BoomerAMGSetInterpVecQMax(amg_, 4);
    HYPRE_BoomerAMGSetSmoothInterpVectors(amg_, 1);
    HYPRE_BoomerAMGSetInterpRefine(amg_, 1);
    return true;
  }

  /// LinearSolverOptions::separateComponents where it changes anything (2 or more unknowns per
  /// node).
  bool separate() const { return options_.separateComponents && dofs_.dofsPerNode > 1; }

  /// The matrix BoomerAMG's hierarchy is built on and every V-cycle smooths with.
  HYPRE_ParCSRMatrix hierarchyMatrix() const { return parP_ ? parP_ : parA_; }

  /// The Krylov methods' preconditioner with separate components: one V-cycle on the filtered
  /// matrix (hypre's BoomerAMGSolve smooths with the matrix it is given, not its own), whose
  /// hierarchy build() set up; the method's own setup leaves it as it is (noSetup).
  static HYPRE_Int componentVcycle(HYPRE_Solver solver, HYPRE_Matrix, HYPRE_Vector b,
                                   HYPRE_Vector x) {
    const auto *s = reinterpret_cast<const HypreAmgSolver *>(solver);
    return HYPRE_BoomerAMGSolve(s->amg_, s->parP_, reinterpret_cast<HYPRE_ParVector>(b),
                                reinterpret_cast<HYPRE_ParVector>(x));
  }
  static HYPRE_Int noSetup(HYPRE_Solver, HYPRE_Matrix, HYPRE_Vector, HYPRE_Vector) { return 0; }

  /// The entries per row of the filtered matrix of `a` (sameComponent).
  std::vector<HYPRE_Int> componentCounts(const CsrMatrix<DeviceSpace> &a) const {
    const auto ro = hostReadable(a.rowOffsets);
    const auto co = hostReadable(a.columns);
    const int d = dofs_.dofsPerNode;
    std::vector<HYPRE_Int> counts(a.numRows, 0);
    Kokkos::parallel_for("mixcon::solver::componentCounts", HostRange(0, a.numRows),
                         [&](LocalIndex i) {
                           HYPRE_Int c = 0;
                           for (auto k = ro(i); k < ro(i + 1); ++k)
                             c += detail::sameComponent(i, co(k), d);
                           counts[i] = c;
                         });
    Kokkos::DefaultHostExecutionSpace().fence();
    return counts;
  }

  /// Hands the entries of `a` that couple equal components (sameComponent) to ijP_, in chunks of
  /// rows so that the copy stays small (its global columns and values: 1/d of A's entries at
  /// once would be 1.3 GB for the 3.1M-unknown cube).
  /// counts: componentCounts(a) (not const: hypre's SetValues takes them so).
  void setComponentValues(const CsrMatrix<DeviceSpace> &a, std::vector<HYPRE_Int> &counts,
                          const char *what) {
    const auto ro = hostReadable(a.rowOffsets);
    const auto co = hostReadable(a.columns);
    const auto va = hostReadable(a.values);
    const int d = dofs_.dofsPerNode;
    const HYPRE_BigInt lo = dofs_.ownedBegin;
    const LocalIndex n = a.numRows;
    constexpr LocalIndex kChunk = 1 << 16;
    std::vector<std::size_t> at; // where each row's entries start in cols and vals
    std::vector<HYPRE_BigInt> cols;
    std::vector<double> vals;
    for (LocalIndex first = 0; first < n; first += kChunk) {
      const LocalIndex last = std::min(n, first + kChunk);
      at.assign(last - first + 1, 0);
      for (LocalIndex i = first; i < last; ++i)
        at[i - first + 1] = at[i - first] + static_cast<std::size_t>(counts[i]);
      cols.resize(at.back());
      vals.resize(at.back());
      Kokkos::parallel_for( // the rows are independent (on the host's threads)
          "mixcon::solver::componentValues", HostRange(first, last), [&](LocalIndex i) {
            std::size_t q = at[i - first];
            for (auto k = ro(i); k < ro(i + 1); ++k)
              if (detail::sameComponent(i, co(k), d)) {
                cols[q] = lo + co(k); // serial numbering, as setValues()
                vals[q++] = va(k);
              }
          });
      Kokkos::DefaultHostExecutionSpace().fence();
      check(HYPRE_IJMatrixSetValues(ijP_, last - first, counts.data() + first, rows_.data() + first,
                                    cols.data(), vals.data()),
            what);
    }
  }

  /// parP_: the filtered matrix of LinearSolverOptions::separateComponents, built in place on one
  /// rank (detail::serialParCsr), else through ijP_.
  void buildComponentMatrix(const CsrMatrix<DeviceSpace> &a) {
    const HYPRE_BigInt lo = dofs_.ownedBegin, hi = dofs_.ownedEnd() - 1;
    std::vector<HYPRE_Int> counts = componentCounts(a);
    if (serialBuild()) {
      parP_ = detail::serialParCsr(comm_, a, counts, dofs_.dofsPerNode);
      return;
    }
    const std::vector<HYPRE_Int> offdSizes(counts.size(), 0);
    check(HYPRE_IJMatrixCreate(comm_, lo, hi, lo, hi, &ijP_), "IJMatrixCreate");
    check(HYPRE_IJMatrixSetObjectType(ijP_, HYPRE_PARCSR), "IJMatrixSetObjectType");
    check(HYPRE_IJMatrixSetOMPFlag(ijP_, 1), "IJMatrixSetOMPFlag"); // as buildHypreMatrix's
    check(HYPRE_IJMatrixSetDiagOffdSizes(ijP_, counts.data(), offdSizes.data()),
          "IJMatrixSetDiagOffdSizes");
    check(HYPRE_IJMatrixInitialize(ijP_), "IJMatrixInitialize");
    setComponentValues(a, counts, "IJMatrixSetValues (separate components)");
    check(HYPRE_IJMatrixAssemble(ijP_), "IJMatrixAssemble");
    check(HYPRE_IJMatrixGetObject(ijP_, reinterpret_cast<void **>(&parP_)), "IJMatrixGetObject");
  }

  /// Whether BoomerAMG's hierarchy is built on K's own arrays (detail::borrowedParCsr) rather
  /// than on a copy: where the copy would be built in place (serialBuild) and K lies in host
  /// memory.
  bool borrowsMatrix() const { return serialBuild() && kHostAccessible<DeviceSpace>; }

  /// Whether hypre's matrices are built in place (detail::serialParCsr) rather than through its
  /// IJ interface: one rank and a CPU hypre.
  bool serialBuild() const { return ranks_ == 1 && !kGpuHypre; }

  void release() {
    cycle_.reset();
    coarse_.reset();
    releaseHypre();
  }

  /// hypre's matrices, vectors, hierarchy and Krylov method.
  void releaseHypre() {
    if (ijP_)
      HYPRE_IJMatrixDestroy(ijP_);
    else if (parP_) // detail::serialParCsr's
      hypre_ParCSRMatrixDestroy(parP_);
    ijP_ = nullptr;
    parP_ = nullptr;
    if (pcg_)
      HYPRE_ParCSRPCGDestroy(pcg_);
    if (gmres_)
      HYPRE_ParCSRGMRESDestroy(gmres_);
    if (amg_)
      HYPRE_BoomerAMGDestroy(amg_);
    if (ij_)
      HYPRE_IJMatrixDestroy(ij_);
    else if (parA_) // detail::serialParCsr's
      hypre_ParCSRMatrixDestroy(parA_);
    if (ijb_)
      HYPRE_IJVectorDestroy(ijb_);
    if (ijx_)
      HYPRE_IJVectorDestroy(ijx_);
    if (ijr_)
      HYPRE_IJVectorDestroy(ijr_);
    for (HYPRE_IJVector v : rotationVectors_) // the AMG does not own the level-0 vectors
      HYPRE_IJVectorDestroy(v);
    rotationVectors_.clear();
    rotations_.clear();
    pcg_ = gmres_ = amg_ = nullptr;
    ij_ = nullptr;
    ijb_ = ijx_ = ijr_ = nullptr;
    parA_ = nullptr;
    parb_ = parx_ = parr_ = nullptr;
  }

  LinearSolverOptions options_;
  DofMap dofs_;
  MPI_Comm comm_;
  int ranks_ = 1;
  int coarsest_ = 9; ///< the coarsest size in use (grows along the escalation ladder)
  std::unique_ptr<RigidCoarseSpace> coarse_; ///< LinearSolverOptions::coarseSpace, when built
  std::unique_ptr<AmgCycle> cycle_;          ///< LinearSolverOptions::cycle, when it applies
  std::string cycleRefusal_; ///< why the last build kept hypre's cycle although asked not to
  /// Why a setup did not build what it was asked for (the coarse space, the direct solver), for
  /// the next solve's note.
  std::string setupNote_;
  std::string coarseRefusal_;      ///< the last reason, said once
  bool coarseOn_ = false;          ///< the ladder took the coarse space (CoarseSpace::OnStall)
  bool coarseRefused_ = false;     ///< it could not be built: the ladder goes on without it
  DeviceVector cw_, sw_, yw_, qw_; ///< twoLevel()'s work vectors
  KrylovWorkspace workspace_;      ///< iterateOwn()'s Krylov vectors
  /// matrix_'s node blocks for iterateOwn()'s products and the copied cycle's fine level (d = 0:
  /// its pattern has none), found for the pattern numbered blocksPattern_; patterns_ counts the
  /// setups that may change it (matrixBlocks()).
  NodeBlocks<DeviceSpace> blocks_;
  int patterns_ = 0, blocksPattern_ = -1;
  /// matrix_'s upper block triangle for iterateOwn()'s products on the host's threads (d = 0:
  /// none), built at the first solve after each setup (upperBlocks()); setups_ counts them.
  SymmetricBlocks<DeviceSpace> upper_;
  int setups_ = 0, upperSetup_ = -1;
  int variant_ = 2;             ///< interpolation-vector variant in use (0: none; see retried())
  HYPRE_IJMatrix ij_ = nullptr; ///< parA_'s IJ matrix (none where detail::serialParCsr built it)
  HYPRE_IJVector ijb_ = nullptr, ijx_ = nullptr, ijr_ = nullptr; ///< b, x, the residual
  HYPRE_ParCSRMatrix parA_ = nullptr;
  HYPRE_IJMatrix ijP_ = nullptr;      ///< LinearSolverOptions::separateComponents' matrix
  HYPRE_ParCSRMatrix parP_ = nullptr; ///< its ParCSR object (the hierarchy's fine level)
  HYPRE_ParVector parb_ = nullptr, parx_ = nullptr, parr_ = nullptr;
  HYPRE_Solver pcg_ = nullptr, gmres_ = nullptr, amg_ = nullptr;
  CsrMatrix<DeviceSpace> matrix_;  ///< the matrix of the last setup (for rebuilds)
  std::vector<HYPRE_BigInt> rows_; ///< owned global row numbers
  std::vector<HYPRE_Int> ncols_;   ///< entries per row of the built matrix
  LocalIndex builtRows_ = -1;
  std::vector<double> zero_;                             ///< zero initial guess
  Kokkos::View<const double **, DeviceSpace> positions_; ///< see setNearNullSpace()
  std::vector<HYPRE_IJVector> rotationVectors_;          ///< owned by this solver
  std::vector<HYPRE_ParVector> rotations_;               ///< their ParCSR views, for hypre
  std::unique_ptr<LinearSolver> direct_;                 ///< the direct fall back, once taken
  bool fallbackRefused_ = false; ///< the direct solver found the matrix singular
  bool kept_ = false;            ///< the hierarchy was built on an earlier matrix
  bool rebuild_ = false;         ///< the kept hierarchy slowed down: build afresh at the next setup
  bool directNext_ = false; ///< the ladder's next step holds the problem: direct at the next setup
  DirectCostEstimate directCost_; ///< directCheaper()'s estimate
  int freshIterations_ = 1;       ///< iterations of the last solve with a fresh hierarchy
  int builds_ = 0, reuses_ = 0;
  double setupSeconds_ = 0.0;
  double normInf_ = 0.0;
};

} // namespace

std::unique_ptr<LinearSolver> makeLinearSolver(const LinearSolverOptions &options,
                                               const DofMap &dofs, MPI_Comm comm) {
  if (const auto why = rules::iterationLimit(options.maxIterations))
    throw std::invalid_argument("linear solver: max_iterations " + *why + " (got " +
                                std::to_string(options.maxIterations) + ")");
  if (options.chebyshevOrder < 1 || options.chebyshevOrder > 4)
    throw std::invalid_argument("linear solver: the Chebyshev order must be 1 to 4 (got " +
                                std::to_string(options.chebyshevOrder) + ")");
  if (options.type == LinearSolverType::Direct)
    return std::make_unique<DirectSolver>(comm, options);
  return std::make_unique<HypreAmgSolver>(options, dofs, comm);
}

std::string coarseSpacePhrase(const LinearSolver *solver) {
  const std::string name = solver ? solver->name() : std::string();
  const std::size_t at = name.find("a rigid-body coarse space");
  return at == std::string::npos ? std::string() : " with " + name.substr(at);
}

void appendNote(std::string &note, const std::string &more) {
  if (more.empty())
    return;
  if (!note.empty())
    note += "; ";
  note += more;
}

LinearSolveStats climbLadder(LinearSolver &solver, LinearSolveStats s,
                             const std::function<LinearSolveStats()> &attempt, std::string &note,
                             int &total, const DirectInstead &directInstead) {
  while (!s.converged) {
    if (directInstead) {
      std::string why;
      const bool instead = directInstead(why);
      appendNote(note, why); // also a refusal: why the ladder goes on
      if (instead)
        break;
    }
    std::string step;
    const bool stronger = solver.strengthen(step);
    if (!step.empty())
      appendNote(note, step);
    if (!stronger)
      break;
    s = attempt();
    total += s.iterations;
  }
  return s;
}

LinearSolveStats solveOnLadder(LinearSolver &solver,
                               const std::function<LinearSolveStats()> &attempt,
                               const DirectInstead &directInstead) {
  LinearSolveStats s = attempt();
  std::string note;
  int iterations = s.iterations;
  s = climbLadder(solver, s, attempt, note, iterations, directInstead);
  s.iterations = iterations;
  s.note = note;
  return s;
}

bool directFallbackFits(MPI_Comm comm, long unknowns, long limit) {
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  return ranks == 1 && unknowns <= limit;
}

DirectInstead luWhenCheaper(bool allowed, DirectCostEstimate &cost,
                            const CsrMatrix<DeviceSpace> &matrix,
                            std::chrono::steady_clock::time_point start, const std::string &what) {
  if (!allowed)
    return {};
  return [&cost, &matrix, start, what](std::string &why) {
    if (!cost.cheaperThan(matrix, false, seconds(start), why))
      return false;
    why = what + " stalled (" + why + ")";
    return true;
  };
}

bool DirectCostEstimate::cheaperThan(const CsrMatrix<DeviceSpace> &a, bool symmetric,
                                     double spentSeconds, std::string &why) {
  const HostLibraryStaging staging;
  Kokkos::fence();
  const auto ro = hostReadable(a.rowOffsets);
  const auto co = hostReadable(a.columns);
  // The pattern's identity: FNV-1a over its row offsets and columns (a contact correction can
  // change the pattern and keep its size).
  std::uint64_t hash = 14695981039346656037ull;
  const auto mix = [&](std::uint64_t v) {
    hash ^= v;
    hash *= 1099511628211ull;
  };
  for (std::size_t i = 0; i < ro.extent(0); ++i)
    mix(static_cast<std::uint64_t>(ro(i)));
  for (std::size_t k = 0; k < co.extent(0); ++k)
    mix(static_cast<std::uint64_t>(co(k)));
  if (!analysed_ || hash != pattern_) {
    try {
      flops_ =
          SparseDirect::estimateCholesky(HostCsr{a.numRows, ro.data(), co.data(), nullptr}).flops;
    } catch (const std::runtime_error &) { // no estimate (out of memory): the ladder as it was
      flops_ = std::numeric_limits<double>::infinity();
    }
    pattern_ = hash;
    analysed_ = true;
  }
  const double direct = detail::estimatedDirectSeconds(a.numNonzeros(), flops_, symmetric);
  if (!(direct < spentSeconds))
    return false;
  std::ostringstream o;
  o.precision(2);
  o << spentSeconds << " s; the direct solver's factorization is estimated at " << direct << " s";
  why = o.str();
  return true;
}

double detail::estimatedDirectSeconds(std::int64_t nonzeros, double choleskyFlops, bool symmetric) {
  return kDirectSecondsPerNonzero * static_cast<double>(nonzeros) +
         (symmetric ? 1.0 : 2.0) * choleskyFlops / kDirectFlopsPerSecond;
}

bool detail::hypreChebyshevEstimateIsSafe() {
#if defined(HYPRE_USING_GPU)
  return false; // the patch fixes the host code only
#else
  static const bool safe = [] {
    hypre_CSRMatrix *a = hypre_CSRMatrixCreate(1, 1, 1);
    hypre_CSRMatrixInitialize_v2(a, 0, HYPRE_MEMORY_HOST);
    hypre_CSRMatrixI(a)[0] = 0;
    hypre_CSRMatrixI(a)[1] = 1;
    hypre_CSRMatrixJ(a)[0] = 0;
    hypre_CSRMatrixData(a)[0] = 0.0;
    HYPRE_Complex d = -1.0;
    hypre_CSRMatrixExtractDiagonal(a, &d, 4); // 1 / sqrt(|a_ii|), the Chebyshev scaling
    hypre_CSRMatrixDestroy(a);
    HYPRE_ClearAllErrors(); // a newer hypre flags the zero diagonal; the next setup must not see it
    return d == 0.0;
  }();
  return safe;
#endif
}

AmgSmoother resolvedSmoother(AmgSmoother smoother) {
  if (smoother != AmgSmoother::Automatic)
    return smoother;
#if defined(HYPRE_USING_OPENMP) || defined(HYPRE_USING_GPU)
  return AmgSmoother::Chebyshev;
#else
  return AmgSmoother::L1GaussSeidel;
#endif
}

std::string smootherName(AmgSmoother smoother) {
  switch (resolvedSmoother(smoother)) {
  case AmgSmoother::L1Jacobi:
    return "l1-Jacobi";
  case AmgSmoother::Chebyshev:
    return "Chebyshev";
  default:
    return "l1-Gauss-Seidel";
  }
}

std::string hypreVersion() {
#ifdef HYPRE_RELEASE_VERSION
  std::string version = std::string("hypre ") + HYPRE_RELEASE_VERSION;
#else
  std::string version = "hypre";
#endif
  // HYPRE_config.h of the install mixcon was compiled against: cmake/build-hypre.sh's threaded
  // build defines HYPRE_USING_OPENMP, Debian's libhypre-dev does not.
#ifdef HYPRE_USING_OPENMP
  return version + " (OpenMP)";
#else
  return version + " (sequential)";
#endif
}

} // namespace mixcon
