// Contact corrections on one kept factorization (solver/CapacitanceSolve.hpp), against the dense
// host solution of each constrained problem (the KKT system [A C^T; C 0] [x; l] = [b; d] with
// every condition as a row of C: the fixed Dirichlet unknowns, the normal and tangential
// components of framed nodes, a prescribed global component) and against solveConstrained's
// elimination on the same system:
//  - a sequence of changing conditions (nodes closing, a stick node, a node whose normal turns,
//    a node held in x whose y takes a contact condition), stride 2 and 3 (a stress-like third
//    unknown with a fixed one among them), is solved on one factorization of A0 after the first
//    call, which records the matrix and leaves it to the elimination;
//  - a changed matrix is left to the elimination once and then factorized anew;
//  - the method declines (b untouched) with reuse_factorization off, with multipoint rows
//    without their conditions, with more than kMaxConditions conditions, and for a body held
//    only by its conditions (A0 singular);
//  - node-to-segment contact (multipoint rows with their conditions: stick, slip, a contactor
//    on a symmetry line) on two blocks, and the shipped Hertz example (rigid plane), give the
//    results of the elimination with one factorization for all their corrections.
#include <apps/Analysis.hpp>
#include <contact/SurfaceContact.hpp>
#include <core/Transfer.hpp>
#include <io/Problem.hpp>
#include <mesh/Generators.hpp>
#include <solver/CapacitanceSolve.hpp>
#include <solver/DofMap.hpp>
#include <solver/Nonlinear.hpp>
#include <support/KernelFixture.hpp>
#include <support/Program.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace mixcon;

namespace capacitance_tests {

using Memory = Kokkos::DefaultExecutionSpace::memory_space;

/// One correction's contact conditions: framed nodes (normal angle, normal and tangential
/// components held with their values) and prescribed global components.
struct Framed {
  int node;
  double angle;
  bool tangent; ///< stick: the tangential component held too
  double normalValue, tangentValue;
};
struct Component {
  int unknown;
  double value;
};
struct Conditions {
  std::vector<Framed> framed;
  std::vector<Component> components;
};

/// The fixed Dirichlet unknowns and their values.
struct Base {
  std::vector<int> unknowns;
  std::vector<double> values;
};

/// Dense KKT solution of A x = b under the base and the conditions.
Eigen::VectorXd reference(const Eigen::MatrixXd &a, const Eigen::VectorXd &b, int stride,
                          const Base &base, const Conditions &c) {
  const int n = static_cast<int>(a.rows());
  std::vector<Eigen::VectorXd> rows;
  std::vector<double> d;
  const auto unit = [&](int i) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    r(i) = 1.0;
    return r;
  };
  for (std::size_t k = 0; k < base.unknowns.size(); ++k) {
    rows.push_back(unit(base.unknowns[k]));
    d.push_back(base.values[k]);
  }
  for (const Framed &f : c.framed) {
    const double nx = std::cos(f.angle), ny = std::sin(f.angle);
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    r(stride * f.node) = nx;
    r(stride * f.node + 1) = ny;
    rows.push_back(r);
    d.push_back(f.normalValue);
    if (f.tangent) {
      Eigen::VectorXd t = Eigen::VectorXd::Zero(n);
      t(stride * f.node) = -ny;
      t(stride * f.node + 1) = nx;
      rows.push_back(t);
      d.push_back(f.tangentValue);
    }
  }
  for (const Component &p : c.components) {
    rows.push_back(unit(p.unknown));
    d.push_back(p.value);
  }
  const int m = static_cast<int>(rows.size());
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n + m, n + m);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + m);
  kkt.topLeftCorner(n, n) = a;
  rhs.head(n) = b;
  for (int k = 0; k < m; ++k) {
    kkt.block(n + k, 0, 1, n) = rows[k].transpose();
    kkt.block(0, n + k, n, 1) = rows[k];
    rhs(n + k) = d[k];
  }
  return kkt.fullPivLu().solve(rhs).head(n);
}

/// The device constraint set of `base` and `c` (views owned by the caller's holder).
struct DeviceSet {
  Kokkos::View<int *, Memory> flags, framed;
  Kokkos::View<double *, Memory> values;
  Kokkos::View<double *[2], Memory> normal;
  Kokkos::View<int *, Memory> baseFlags;
  ConstraintSet set;
};

DeviceSet deviceSet(int nodes, int stride, const Base &base, const Conditions &c) {
  const int n = nodes * stride;
  std::vector<int> flags(n, 0), framed(nodes, 0), baseFlags(n, 0);
  std::vector<double> values(n, 0.0), normal(2 * nodes, 0.0);
  for (std::size_t k = 0; k < base.unknowns.size(); ++k) {
    flags[base.unknowns[k]] = baseFlags[base.unknowns[k]] = 1;
    values[base.unknowns[k]] = base.values[k];
  }
  for (const Framed &f : c.framed) {
    const int i0 = stride * f.node;
    framed[f.node] = 1;
    normal[2 * f.node] = std::cos(f.angle);
    normal[2 * f.node + 1] = std::sin(f.angle);
    flags[i0] = 1;
    values[i0] = f.normalValue;
    if (f.tangent) {
      flags[i0 + 1] = 1;
      values[i0 + 1] = f.tangentValue;
    }
  }
  for (const Component &p : c.components) {
    flags[p.unknown] = 1;
    values[p.unknown] = p.value;
  }
  DeviceSet d;
  d.flags = Kokkos::View<int *, Memory>("flags", n);
  d.baseFlags = Kokkos::View<int *, Memory>("base", n);
  d.values = Kokkos::View<double *, Memory>("values", n);
  d.framed = Kokkos::View<int *, Memory>("framed", nodes);
  d.normal = Kokkos::View<double *[2], Memory>("normal", nodes);
  copyToDevice(d.flags, flags);
  copyToDevice(d.baseFlags, baseFlags);
  copyToDevice(d.values, values);
  copyToDevice(d.framed, framed);
  auto hn = hostMirror(d.normal);
  for (int p = 0; p < nodes; ++p)
    for (int i = 0; i < 2; ++i)
      hn(p, i) = normal[2 * p + i];
  copyToDevice(d.normal, hn);
  d.set.stride = stride;
  d.set.flags = d.flags;
  d.set.values = d.values;
  d.set.framed = d.framed;
  d.set.normal = d.normal;
  return d;
}

Eigen::MatrixXd randomSpd(int n, std::mt19937 &rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd r(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      r(i, j) = u(rng);
  return r * r.transpose() + n * Eigen::MatrixXd::Identity(n, n);
}

class CapacitanceSolveStrides : public ::testing::TestWithParam<int> {};

TEST_P(CapacitanceSolveStrides, ChangingConditionsOnOneFactorizationSolveTheConstrainedProblem) {
  const int stride = GetParam(), nodes = 14, n = nodes * stride;
  std::mt19937 rng(17 + stride);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd a = randomSpd(n, rng);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i)
    b(i) = u(rng);
  // Node 0 held, node 1 held in x (its y takes a contact condition below); with stride 3 a
  // stress-like unknown of node 2 is fixed too.
  Base base{{0, 1, stride}, {0.01, -0.02, 0.03}};
  if (stride == 3)
    base.unknowns.push_back(2 * stride + 2), base.values.push_back(0.5);
  const std::vector<Conditions> sequence = {
      {{{5, 0.3, false, 0.010, 0.0}}, {}},
      {{{5, 0.3, false, 0.012, 0.0}, {6, -1.2, true, -0.004, 0.002}}, {{stride + 1, 0.007}}},
      {{{6, 2.0, false, 0.001, 0.0}, {9, 0.9, true, 0.003, -0.001}}, {{stride + 1, 0.005}}},
      {{{5, 0.31, false, 0.02, 0.0}, {6, 2.1, false, 0.001, 0.0}, {9, 0.9, false, 0.0, 0.0}}, {}}};

  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  auto solver = makeLinearSolver(o, DofMap::serial(nodes, stride), MPI_COMM_WORLD);
  const auto am = test::denseToCsr(a);
  CsrMatrix<Memory> work;
  ConstraintElimination elimination;
  CapacitanceSolve cap;
  Kokkos::View<double *, Memory> x("x", n);
  const auto correction = [&](const Conditions &c, bool expectKept) {
    const Eigen::VectorXd xRef = reference(a, b, stride, base, c);
    DeviceSet d = deviceSet(nodes, stride, base, c);
    const auto bv = test::toView(b);
    LinearSolveStats s;
    const bool kept = cap.solve(d.set, d.baseFlags, am, bv, *solver, x, s);
    EXPECT_EQ(kept, expectKept);
    if (!kept) {
      EXPECT_LT((test::toEigen(bv) - b).norm(), 1e-300) << "b changed by a declined call";
      solveConstrained(d.set, am, work, elimination, bv, *solver, x);
    } else {
      EXPECT_TRUE(s.converged);
      EXPECT_EQ(s.iterations, 1);
    }
    const Eigen::VectorXd xs = test::toEigen(x);
    EXPECT_LT((xs - xRef).norm(), 1e-10 * xRef.norm()) << "kept " << kept;
    // The same system through the elimination, for the comparison the models rely on.
    Kokkos::View<double *, Memory> xe("xe", n);
    LinearSolverOptions oe = o;
    oe.reuseFactorization = false;
    auto other = makeLinearSolver(oe, DofMap::serial(nodes, stride), MPI_COMM_WORLD);
    CsrMatrix<Memory> w2;
    ConstraintElimination e2;
    DeviceSet d2 = deviceSet(nodes, stride, base, c);
    solveConstrained(d2.set, am, w2, e2, test::toView(b), *other, xe);
    EXPECT_LT((test::toEigen(xe) - xs).norm(), 1e-11 * xRef.norm());
  };
  // The first matrix is recorded and left to the elimination; from then on one factorization.
  correction(sequence[0], false);
  for (std::size_t k = 1; k < sequence.size(); ++k)
    correction(sequence[k], true);
  EXPECT_EQ(cap.factorizations(), 1);
  EXPECT_EQ(cap.solves(), 3);
  EXPECT_EQ(solver->builds(), 1); // the caller's factorization: only the elimination's

  // A changed matrix (same pattern): elimination once, then factorized anew.
  const Eigen::MatrixXd extra = randomSpd(n, rng) * 0.1;
  a += extra;
  Kokkos::deep_copy(am.values, test::denseToCsr(a).values);
  correction(sequence[1], false);
  correction(sequence[2], true);
  EXPECT_EQ(cap.factorizations(), 2);
  EXPECT_EQ(cap.solves(), 4);

  // The caller's solver factorizing another system in between leaves the kept one alone.
  {
    DeviceSet d = deviceSet(nodes, stride, base, sequence[3]);
    solveConstrained(d.set, am, work, elimination, test::toView(b), *solver, x);
  }
  correction(sequence[3], true);
  EXPECT_EQ(cap.factorizations(), 2);
  EXPECT_EQ(cap.solves(), 5);
}

INSTANTIATE_TEST_SUITE_P(Strides, CapacitanceSolveStrides, ::testing::Values(2, 3));

TEST(CapacitanceSolve, DeclinesWhereItDoesNotApply) {
  const int nodes = 8, stride = 2, n = nodes * stride;
  std::mt19937 rng(3);
  const Eigen::MatrixXd a = randomSpd(n, rng);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
  const auto am = test::denseToCsr(a);
  const Base base{{0, 1}, {0.0, 0.0}};
  const Conditions c{{{4, 0.5, false, 0.01, 0.0}}, {}};
  Kokkos::View<double *, Memory> x("x", n);
  LinearSolveStats s;
  // reuse_factorization: false (and the AMG solver, which keeps no exact factorization).
  for (const auto type : {LinearSolverType::Direct, LinearSolverType::Amg}) {
    LinearSolverOptions o;
    o.type = type;
    o.reuseFactorization = false;
    auto solver = makeLinearSolver(o, DofMap::serial(nodes, stride), MPI_COMM_WORLD);
    CapacitanceSolve cap;
    DeviceSet d = deviceSet(nodes, stride, base, c);
    for (int k = 0; k < 3; ++k)
      EXPECT_FALSE(cap.solve(d.set, d.baseFlags, am, test::toView(b), *solver, x, s));
    EXPECT_EQ(cap.factorizations(), 0);
  }
  // Multipoint rows.
  {
    LinearSolverOptions o;
    o.type = LinearSolverType::Direct;
    auto solver = makeLinearSolver(o, DofMap::serial(nodes, stride), MPI_COMM_WORLD);
    MultiPointConstraints mp;
    mp.addRow(6, {{8, 1.0}}, 0.0);
    mp.slaves.push_back(6);
    const auto dm = toDevice(mp, n);
    DeviceSet d = deviceSet(nodes, stride, base, c);
    d.set.multipoint = &dm;
    CapacitanceSolve cap;
    for (int k = 0; k < 3; ++k)
      EXPECT_FALSE(cap.solve(d.set, d.baseFlags, am, test::toView(b), *solver, x, s));
  }
  // A body held only by its conditions: a chain of springs in x and in y, node 0 held in y,
  // node 5's x held by a contact condition. A0 keeps the translation in x (singular): declined
  // once, for this matrix, without a factorization; the elimination solves it.
  {
    Eigen::MatrixXd chain = Eigen::MatrixXd::Zero(n, n);
    for (int p = 0; p + 1 < nodes; ++p)
      for (int i = 0; i < 2; ++i) {
        const int u = stride * p + i, v = stride * (p + 1) + i;
        chain(u, u) += 1.0;
        chain(v, v) += 1.0;
        chain(u, v) -= 1.0;
        chain(v, u) -= 1.0;
      }
    const auto cm = test::denseToCsr(chain);
    const Base held{{1}, {0.0}};
    const Conditions contact{{{5, 0.0, false, 0.02, 0.0}}, {}};
    LinearSolverOptions o;
    o.type = LinearSolverType::Direct;
    auto solver = makeLinearSolver(o, DofMap::serial(nodes, stride), MPI_COMM_WORLD);
    DeviceSet d = deviceSet(nodes, stride, held, contact);
    CapacitanceSolve cap;
    CsrMatrix<Memory> work;
    ConstraintElimination elimination;
    for (int k = 0; k < 3; ++k) {
      const auto bv = test::toView(b);
      EXPECT_FALSE(cap.solve(d.set, d.baseFlags, cm, bv, *solver, x, s)) << k;
      solveConstrained(d.set, cm, work, elimination, bv, *solver, x);
      const Eigen::VectorXd ref = reference(chain, b, stride, held, contact);
      EXPECT_LT((test::toEigen(x) - ref).norm(), 1e-9 * ref.norm()) << k;
    }
    EXPECT_EQ(cap.factorizations(), 0);
    EXPECT_EQ(cap.solves(), 0);
  }
  // More conditions than kMaxConditions: a diagonal system with every unknown but the base held.
  {
    const int big = CapacitanceSolve::kMaxConditions + 10, nb = 2 * big;
    const Eigen::MatrixXd diag = Eigen::VectorXd::LinSpaced(nb, 1.0, 2.0).asDiagonal();
    const auto dm = test::denseToCsr(diag);
    Conditions many;
    for (int i = 2; i < nb; ++i)
      many.components.push_back({i, 0.001 * i});
    LinearSolverOptions o;
    o.type = LinearSolverType::Direct;
    auto solver = makeLinearSolver(o, DofMap::serial(big, stride), MPI_COMM_WORLD);
    DeviceSet d = deviceSet(big, stride, base, many);
    CapacitanceSolve cap;
    Kokkos::View<double *, Memory> xb("xb", nb);
    for (int k = 0; k < 2; ++k)
      EXPECT_FALSE(cap.solve(d.set, d.baseFlags, dm, test::toView(Eigen::VectorXd::Ones(nb)),
                             *solver, xb, s));
  }
}

} // namespace capacitance_tests

namespace capacitance_tests {

// The shipped Hertz example (rigid plane, linear kinematics, the direct solver) with the kept
// factorization (the default) and without it (`reuse_factorization: false`, every correction
// factorized after elimination): the same corrections and results to round-off, and all
// corrections after the first with contact on one factorization.
TEST(CapacitanceSolve, HertzExampleGivesTheEliminationsResultsOnOneFactorization) {
  test::ScratchDir dir("capacitance");
  std::vector<RunResult> runs;
  for (const bool reuse : {true, false}) {
    Problem p = readProblem(std::string(MIXCON_SOURCE_DIR) + "/examples/hertz/hertz_report.yaml");
    ASSERT_EQ(p.solver.type, LinearSolverType::Direct);
    p.solver.reuseFactorization = reuse;
    RunOptions o;
    o.outputDirectory = (dir.path() / (reuse ? "kept" : "eliminated")).string();
    o.verbosity = Verbosity::Quiet;
    runs.push_back(runAnalysis(p, o, MPI_COMM_WORLD));
    ASSERT_TRUE(runs.back().converged);
  }
  const RunResult &kept = runs[0], &eliminated = runs[1];
  ASSERT_EQ(kept.steps.size(), eliminated.steps.size());
  int corrections = 0;
  for (std::size_t k = 0; k < kept.steps.size(); ++k) {
    EXPECT_EQ(kept.steps[k].iterations, eliminated.steps[k].iterations) << "step " << k + 1;
    EXPECT_EQ(kept.steps[k].contactClosed, eliminated.steps[k].contactClosed) << "step " << k + 1;
    corrections += kept.steps[k].iterations;
  }
  double du = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < kept.displacement.size(); ++i) {
    du = std::max(du, std::abs(kept.displacement[i] - eliminated.displacement[i]));
    scale = std::max(scale, std::abs(eliminated.displacement[i]));
  }
  EXPECT_LT(du, 1e-10 * scale);
  double ds = 0.0, sscale = 0.0;
  for (std::size_t i = 0; i < kept.stress.size(); ++i) {
    ds = std::max(ds, std::abs(kept.stress[i] - eliminated.stress[i]));
    sscale = std::max(sscale, std::abs(eliminated.stress[i]));
  }
  EXPECT_LT(ds, 1e-10 * sscale);
  // The first correction with a closed node records the stiffness; every later one is kept.
  EXPECT_EQ(kept.keptFactorizations, 1);
  EXPECT_EQ(kept.keptFactorizationCorrections, corrections - 1);
  EXPECT_EQ(eliminated.keptFactorizationCorrections, 0);
}

} // namespace capacitance_tests

namespace capacitance_tests {

/// Node-to-segment contact (its multipoint rows given as conditions too) on two blocks: the
/// upper one (1 x 1, 3 x 2 Quad4) pressed on the lower (2 x 1, 4 x 2) and slid with friction
/// 0.3, both held at x = 0 (a symmetry line: the contactor's corner node takes the normal
/// condition on its free component, with its held component among the condition's entries).
/// Per step: displacements, statuses and contact forces.
struct SlideRun {
  std::vector<std::vector<double>> displacement, normal, tangent;
  std::vector<std::vector<int>> status;
  int keptCorrections = 0, keptFactorizations = 0, stick = 0, slip = 0;
};

SlideRun slideRun(bool reuse) {
  constexpr double kE = 1000.0, kNu = 0.3;
  MeshBody lower{"lower", rectangleMesh(2.0, 1.0, 4, 2, ElementType::Quad4), {0.0, 0.0}};
  MeshBody upper{"upper", rectangleMesh(1.0, 1.0, 3, 2, ElementType::Quad4), {0.0, 1.0}};
  const Mesh mesh = mergeMeshes({lower, upper});
  const std::vector<PlaneMatrix> c{isotropicStiffness(kE, kNu, PlaneAnalysis::PlaneStrain)};
  NonlinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), c, 1.0);
  model.setSmallDisplacements(true);
  const auto base = mesh.nodesOf("lower.bottom"), top = mesh.nodesOf("upper.top");
  for (LocalIndex n : base)
    for (int i = 0; i < 2; ++i)
      model.prescribe(n, i, 0.0);
  for (const char *b : {"lower.left", "upper.left"})
    for (LocalIndex n : mesh.nodesOf(b))
      model.prescribe(n, 0, 0.0);
  for (LocalIndex n : top)
    for (int i = 0; i < 2; ++i)
      model.prescribe(n, i, 0.0);
  SurfaceContactSpec spec;
  spec.contactor = mesh.nodesOf("upper.bottom");
  spec.target = boundarySegments(mesh, "lower.top");
  spec.friction = 0.3;
  spec.name = "upper.bottom -> lower.top";
  SurfaceContact contact(mesh.numNodes(), std::vector<SurfaceContactSpec>{spec});
  model.setContact(&contact);
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  o.tolerance = 1e-12;
  o.reuseFactorization = reuse;
  model.setup(o, MPI_COMM_WORLD);
  LoadStepper stepper(model, NonlinearOptions{}, nullptr);
  SlideRun r;
  const int steps = 6;
  const double delta = 0.01, travel = 0.004; // the top pressed, then moved away from x = 0
  for (int k = 1; k <= steps + 1; ++k) {
    const double lambda = k, ux = travel * (k - 1) / steps;
    std::vector<ModelBase::PrescribedValue> v;
    for (LocalIndex n : top) {
      v.push_back({n, 0, ux / lambda});
      v.push_back({n, 1, -delta / lambda});
    }
    model.updatePrescribed(v);
    const IncrementOutcome out = stepper.advance(lambda);
    EXPECT_TRUE(out.converged) << "step " << k << ": " << out.message;
    if (!out.converged)
      break;
    r.displacement.push_back(model.displacementHost());
    std::vector<double> nf, tf;
    std::vector<int> st;
    for (LocalIndex q = 0; q < contact.numCandidates(); ++q) {
      nf.push_back(contact.normalForce(q));
      tf.push_back(contact.tangentForce(q));
      st.push_back(static_cast<int>(contact.status(q)));
      r.stick += contact.status(q) == ContactStatus::Stick;
      r.slip += contact.status(q) == ContactStatus::Slip;
    }
    r.normal.push_back(nf);
    r.tangent.push_back(tf);
    r.status.push_back(st);
  }
  r.keptCorrections = model.keptFactorization().solves();
  r.keptFactorizations = model.keptFactorization().factorizations();
  return r;
}

double largestDifference(const std::vector<std::vector<double>> &a,
                         const std::vector<std::vector<double>> &b, double &scale) {
  double d = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    for (std::size_t i = 0; i < a[k].size(); ++i) {
      d = std::max(d, std::abs(a[k][i] - b[k][i]));
      scale = std::max(scale, std::abs(b[k][i]));
    }
  return d;
}

TEST(CapacitanceSolve, NodeToSegmentStickSlipAndASymmetryLineMatchTheElimination) {
  const SlideRun kept = slideRun(true), eliminated = slideRun(false);
  ASSERT_EQ(kept.displacement.size(), eliminated.displacement.size());
  EXPECT_EQ(kept.status, eliminated.status);
  double su = 0.0, sn = 0.0, st = 0.0;
  const double du = largestDifference(kept.displacement, eliminated.displacement, su);
  const double dn = largestDifference(kept.normal, eliminated.normal, sn);
  const double dt = largestDifference(kept.tangent, eliminated.tangent, st);
  ASSERT_GT(su, 0.0);
  ASSERT_GT(sn, 0.0);
  EXPECT_LT(du, 1e-10 * su);
  EXPECT_LT(dn, 1e-9 * sn);
  EXPECT_LT(dt, 1e-9 * sn); // friction forces up to 0.3 times the normal ones
  // Both statuses occur, and the corrections after the first ran on one factorization.
  EXPECT_GT(kept.stick, 0);
  EXPECT_GT(kept.slip, 0);
  EXPECT_EQ(kept.keptFactorizations, 1);
  EXPECT_GT(kept.keptCorrections, 10);
  EXPECT_EQ(eliminated.keptCorrections, 0);
}

} // namespace capacitance_tests
