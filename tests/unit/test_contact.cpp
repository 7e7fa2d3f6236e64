// Rigid-obstacle geometry and detection (contact/RigidObstacle.hpp) against plain host formulas,
// and the nodal local frames (solver/LocalFrames.hpp) against dense R^T A R, for 2 and 5 unknowns
// per node; the seating of a force-driven obstacle against a host ray cast; the rigid correction
// through its constraint set (solver/ConstraintSet.hpp) against the dense constrained solve;
// where in an increment a candidate crossed the other surface (contact/ContactStatus.hpp).
#include <contact/ContactStatus.hpp>
#include <contact/RigidContact.hpp>
#include <contact/RigidObstacle.hpp>
#include <core/Transfer.hpp>
#include <solver/ConstraintSet.hpp>
#include <solver/DofMap.hpp>
#include <solver/LocalFrames.hpp>
#include <support/KernelFixture.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

using namespace mixcon;
using namespace mixcon::test;
using Exec = Kokkos::DefaultExecutionSpace;

namespace contact_tests {

RigidObstacle circle(double cx, double cy, double r) {
  RigidObstacle o;
  o.kind = ObstacleKind::Circle;
  o.point[0] = cx;
  o.point[1] = cy;
  o.radius = r;
  return o;
}

RigidObstacle halfPlane(double px, double py, double angle) {
  RigidObstacle o;
  o.kind = ObstacleKind::HalfPlane;
  o.point[0] = px;
  o.point[1] = py;
  o.normal[0] = std::cos(angle);
  o.normal[1] = std::sin(angle);
  return o;
}

} // namespace contact_tests
using namespace contact_tests;

TEST(RigidObstacle, CircleProjection) {
  const RigidObstacle pin = circle(0.3, -0.2, 0.49);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1.5, 1.5);
  for (int k = 0; k < 200; ++k) {
    const double x = d(rng), y = d(rng);
    const ObstacleProjection p = projectOntoObstacle(pin, x, y);
    const double r = std::hypot(x - 0.3, y + 0.2);
    EXPECT_NEAR(p.gap, r - 0.49, 1e-14);
    EXPECT_NEAR(std::hypot(p.closest[0] - 0.3, p.closest[1] + 0.2), 0.49, 1e-14);
    // x = closest + gap n, n unit, t unit and orthogonal, counter-clockwise.
    EXPECT_NEAR(p.closest[0] + p.gap * p.normal[0], x, 1e-13);
    EXPECT_NEAR(p.closest[1] + p.gap * p.normal[1], y, 1e-13);
    EXPECT_NEAR(std::hypot(p.normal[0], p.normal[1]), 1.0, 1e-14);
    EXPECT_NEAR(p.normal[0] * p.tangent[0] + p.normal[1] * p.tangent[1], 0.0, 1e-14);
    EXPECT_NEAR(p.normal[0] * p.tangent[1] - p.normal[1] * p.tangent[0], 1.0, 1e-14);
    EXPECT_NEAR(p.angle, std::atan2(y + 0.2, x - 0.3), 1e-14);
  }
  const ObstacleProjection c = projectOntoObstacle(pin, 0.3, -0.2); // the centre itself
  EXPECT_DOUBLE_EQ(c.gap, -0.49);
  EXPECT_DOUBLE_EQ(c.normal[0], 1.0);
}

TEST(RigidObstacle, HalfPlaneProjection) {
  const RigidObstacle plane = halfPlane(1.0, 2.0, 0.4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-3.0, 3.0);
  for (int k = 0; k < 200; ++k) {
    const double x = d(rng), y = d(rng);
    const ObstacleProjection p = projectOntoObstacle(plane, x, y);
    EXPECT_NEAR(p.gap, (x - 1.0) * std::cos(0.4) + (y - 2.0) * std::sin(0.4), 1e-14);
    // The closest point lies on the boundary line.
    EXPECT_NEAR((p.closest[0] - 1.0) * std::cos(0.4) + (p.closest[1] - 2.0) * std::sin(0.4), 0.0,
                1e-13);
    EXPECT_NEAR(p.arcCoordinate, -(x - 1.0) * std::sin(0.4) + (y - 2.0) * std::cos(0.4), 1e-13);
  }
}

TEST(RigidObstacle, BatchedDetectionMatchesHostProjection) {
  const Fixture f = makeFixture(ElementType::Quad8, 4, 3);
  const LocalIndex nn = f.mesh.numNodes();
  const std::vector<RigidObstacle> obstacles{circle(1.5, -0.3, 0.5), halfPlane(0.0, 0.1, 1.7)};
  Kokkos::View<RigidObstacle *, Memory> obs("obstacles", obstacles.size());
  auto ho = Kokkos::create_mirror_view(obs);
  for (std::size_t i = 0; i < obstacles.size(); ++i)
    ho(i) = obstacles[i];
  Kokkos::deep_copy(obs, ho);
  for (int stride : {2, 5}) {
    const Eigen::VectorXd u = 0.2 * randomVector(stride * nn, 7 + stride);
    std::vector<LocalIndex> nodes;
    std::vector<int> which;
    for (LocalIndex n = 0; n < nn; ++n) {
      nodes.push_back(n);
      which.push_back(n % 2);
    }
    Kokkos::View<LocalIndex *, Memory> dn("nodes", nodes.size());
    Kokkos::View<int *, Memory> dw("which", which.size());
    auto hn = Kokkos::create_mirror_view(dn);
    auto hw = Kokkos::create_mirror_view(dw);
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      hn(k) = nodes[k];
      hw(k) = which[k];
    }
    Kokkos::deep_copy(dn, hn);
    Kokkos::deep_copy(dw, hw);
    ContactDetection<Memory> out(static_cast<LocalIndex>(nodes.size()));
    const LocalIndex count = detectContact(
        Exec(), Kokkos::View<const RigidObstacle *, Memory>(obs),
        Kokkos::View<const LocalIndex *, Memory>(dn), Kokkos::View<const int *, Memory>(dw),
        Kokkos::View<const double *[2], Memory>(f.data.mesh.coordinates),
        Kokkos::View<const double *, Memory>(toView(u)), stride, out);
    auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out.gap);
    auto nor = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out.normal);
    LocalIndex expected = 0;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const LocalIndex n = nodes[k];
      const ObstacleProjection p = projectOntoObstacle(
          obstacles[which[k]], f.mesh.x(n) + u(stride * n), f.mesh.y(n) + u(stride * n + 1));
      EXPECT_DOUBLE_EQ(gap(k), p.gap);
      EXPECT_DOUBLE_EQ(nor(k, 0), p.normal[0]);
      EXPECT_DOUBLE_EQ(nor(k, 1), p.normal[1]);
      expected += p.gap < 0.0;
    }
    EXPECT_EQ(count, expected);
    EXPECT_GT(expected, 0); // the case has penetrating and clear nodes
    EXPECT_LT(expected, static_cast<LocalIndex>(nodes.size()));
  }
}

TEST(LocalFrames, RotationEqualsDenseProductForTwoAndFiveUnknownsPerNode) {
  const Fixture f = makeFixture(ElementType::Quad8, 3, 2);
  const LocalIndex nn = f.mesh.numNodes();
  const NodeGraph g = buildNodeGraph(f.mesh);
  for (int ndof : {2, 5}) {
    auto a = expandGraph<Memory>(g, ndof);
    Kokkos::deep_copy(a.values, toView(randomVector(a.numNonzeros(), 11 + ndof)));
    const Eigen::MatrixXd before = toDense(a);
    Kokkos::View<int *, Memory> framed("framed", nn);
    Kokkos::View<double *[2], Memory> normal("normal", nn);
    auto hf = Kokkos::create_mirror_view(framed);
    auto hn = Kokkos::create_mirror_view(normal);
    Eigen::MatrixXd t = Eigen::MatrixXd::Identity(ndof * nn, ndof * nn);
    for (LocalIndex p = 0; p < nn; ++p) {
      hf(p) = p % 3 == 0;
      const double th = 0.37 * p;
      hn(p, 0) = std::cos(th);
      hn(p, 1) = std::sin(th);
      if (hf(p)) {
        t(ndof * p, ndof * p) = hn(p, 0);
        t(ndof * p + 1, ndof * p) = hn(p, 1);
        t(ndof * p, ndof * p + 1) = -hn(p, 1);
        t(ndof * p + 1, ndof * p + 1) = hn(p, 0);
      }
    }
    Kokkos::deep_copy(framed, hf);
    Kokkos::deep_copy(normal, hn);
    const Eigen::VectorXd b = randomVector(ndof * nn, 13);
    auto db = toView(b);
    const auto cf = Kokkos::View<const int *, Memory>(framed);
    const auto cn = Kokkos::View<const double *[2], Memory>(normal);
    rotateToLocalFrames(Exec(), a, ndof, cf, cn, db);
    EXPECT_LT(relativeError(toDense(a), t.transpose() * before * t), 1e-14);
    EXPECT_LT((toEigen(db) - t.transpose() * b).cwiseAbs().maxCoeff(), 1e-14);
    // Vectors: local -> global is the inverse of global -> local.
    auto v = toView(b);
    toLocalFrames(Exec(), ndof, cf, cn, v);
    EXPECT_LT((toEigen(v) - t.transpose() * b).cwiseAbs().maxCoeff(), 1e-14);
    fromLocalFrames(Exec(), ndof, cf, cn, v);
    EXPECT_LT((toEigen(v) - b).cwiseAbs().maxCoeff(), 1e-14);
  }
}

// A force-driven pin below a row of nodes, pushed up and to the side: seatForceDriven moves it
// along its force until the first node touches. Reference: the smallest t >= 0 with
// |p - (c + t d)| = R over the nodes, solved here by bisection on the host.
TEST(RigidContact, SeatingMovesAForceDrivenPinOntoTheFirstNodeInItsPath) {
  const Fixture f = makeFixture(ElementType::Quad4, 6, 2);
  const LocalIndex nn = f.mesh.numNodes();
  RigidContactSpec spec;
  spec.obstacle = circle(0.3, -0.8, 0.5);
  spec.nodes = f.mesh.nodesOf("bottom");
  spec.forceDriven[0] = spec.forceDriven[1] = true;
  spec.force[0] = 0.6;
  spec.force[1] = 0.8; // direction (0.6, 0.8)
  spec.name = "bottom";
  RigidContact contact(nn, {spec});
  contact.setLoadFactor(1.0);
  Kokkos::View<double *, Memory> u("u", 2 * nn);
  contact.detect(Kokkos::View<const double *[2], Memory>(f.data.mesh.coordinates), u, 2);
  ASSERT_EQ(contact.seatForceDriven(), 1);
  double best = 1e300;
  for (LocalIndex n : spec.nodes) {
    const auto inside = [&](double t) {
      return std::hypot(f.mesh.x(n) - 0.3 - 0.6 * t, f.mesh.y(n) + 0.8 - 0.8 * t) < 0.5;
    };
    // First entry: scan in steps of 1e-3, then bisect the bracketing step.
    double lo = 0.0, hi = -1.0;
    for (double t = 1e-3; t < 3.0 && hi < 0.0; t += 1e-3) {
      if (inside(t))
        hi = t;
      else
        lo = t;
    }
    if (hi < 0.0)
      continue;
    for (int it = 0; it < 200; ++it)
      (inside(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
    best = std::min(best, hi);
  }
  const double *motion = contact.obstacleMotion(0);
  EXPECT_NEAR(motion[0], 0.6 * best, 1e-12);
  EXPECT_NEAR(motion[1], 0.8 * best, 1e-12);
  contact.detect(Kokkos::View<const double *[2], Memory>(f.data.mesh.coordinates), u, 2);
  double minGap = 1e300;
  for (LocalIndex k = 0; k < contact.numCandidates(); ++k)
    minGap = std::min(minGap, contact.gap(k));
  EXPECT_NEAR(minGap, 0.0, 1e-12);
  // Pulled away from the nodes instead, nothing lies in its path: a clear error.
  spec.force[0] = 0.0;
  spec.force[1] = -1.0;
  RigidContact away(nn, {spec});
  away.setLoadFactor(1.0);
  away.detect(Kokkos::View<const double *[2], Memory>(f.data.mesh.coordinates), u, 2);
  EXPECT_THROW(away.seatForceDriven(), InputError);
}

namespace contact_tests {

/// A symmetric positive definite matrix on the node graph's pattern (2 unknowns per node):
/// symmetric off-diagonal values, diagonally dominant.
CsrMatrix<Memory> spdOnGraph(const Mesh &mesh) {
  auto a = expandGraph<Memory>(buildNodeGraph(mesh), 2);
  auto ro = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.rowOffsets);
  auto co = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.columns);
  auto va = Kokkos::create_mirror_view(a.values);
  for (LocalIndex i = 0; i < a.numRows; ++i) {
    double off = 0.0;
    Offset diag = -1;
    for (Offset k = ro(i); k < ro(i + 1); ++k) {
      const LocalIndex j = co(k);
      if (j == i) {
        diag = k;
        continue;
      }
      const double lo = std::min(i, j), hi = std::max(i, j);
      va(k) = 0.4 * std::cos(1.3 * (lo + hi) + 0.017 * lo * hi);
      off += std::abs(va(k));
    }
    va(diag) = off + 1.0 + 0.1 * (i % 3);
  }
  Kokkos::deep_copy(a.values, va);
  return a;
}

} // namespace contact_tests

// A rigid pin pressed into the bottom of a block (3 closed nodes, one of them also held along x:
// a symmetry line), top nodes prescribed: the rigid correction through its constraint set
// (local frames, held normal / stick components, Dirichlet steps) equals the dense host solution
// of the same constrained problem, in stick (friction) and slip (frictionless); the model's path
// (constraintSet + solveConstrained) gives the provider's correct() bit for bit; the held
// components take their steps (n . dx = -gap, in stick t . dx = the stick step) and a slip node's
// tangential residual vanishes; building the set copies nothing between host and device. A
// force-driven pin hands out no set (its motion is an unknown).
TEST(RigidContact, CorrectionThroughTheConstraintSetEqualsTheDenseConstrainedSolve) {
  const Fixture f = makeFixture(ElementType::Quad4, 6, 2);
  const LocalIndex nn = f.mesh.numNodes();
  const int n = 2 * nn;
  const auto a = spdOnGraph(f.mesh);
  const Eigen::MatrixXd ad = toDense(a);
  const double lambda = 0.7;
  // Dirichlet: the top nodes fully, the bottom node at x = 1.5 along x (within the pin contact).
  std::vector<int> flags(n, 0);
  std::vector<double> presc(n, 0.0);
  for (LocalIndex p : f.mesh.nodesOf("top")) {
    flags[2 * p] = flags[2 * p + 1] = 1;
    presc[2 * p] = 0.01;
    presc[2 * p + 1] = -0.02;
  }
  LocalIndex symmetric = -1;
  for (LocalIndex p : f.mesh.nodesOf("bottom"))
    if (std::abs(f.mesh.x(p) - 1.5) < 1e-12)
      symmetric = p;
  ASSERT_GE(symmetric, 0);
  flags[2 * symmetric] = 1;
  presc[2 * symmetric] = 0.003;
  const Eigen::VectorXd u = 1e-3 * randomVector(n, 21), g = randomVector(n, 22);
  Kokkos::View<int *, Memory> fv("flags", n);
  copyToDevice(fv, flags);
  Kokkos::View<double *, Memory> pv("prescribed", n), rhs("rhs", n), target("target", n),
      dx("dx", n), dx2("dx2", n);
  copyToDevice(pv, presc);
  const auto uv = toView(u), gv = toView(g);
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  auto solver = makeLinearSolver(o, DofMap::serial(nn, 2), MPI_COMM_WORLD);

  for (double mu : {0.3, 0.0}) {
    RigidContactSpec spec;
    spec.obstacle = circle(1.5, -0.5, 0.75); // the bottom nodes at x = 1, 1.5, 2 penetrate
    spec.nodes = f.mesh.nodesOf("bottom");
    spec.friction = mu;
    spec.name = "bottom";
    RigidContact contact(nn, {spec});
    contact.setLoadFactor(lambda);
    contact.detect(Kokkos::View<const double *[2], Memory>(f.data.mesh.coordinates), uv, 2);
    ASSERT_EQ(contact.closeTouching(0.0), 3);
    for (LocalIndex k = 0; k < contact.numCandidates(); ++k) {
      if (contact.status(k) != ContactStatus::Open) {
        EXPECT_EQ(contact.status(k), mu > 0.0 ? ContactStatus::Stick : ContactStatus::Slip);
      }
    }
    ASSERT_TRUE(contact.constrains());

    CsrMatrix<Memory> work, work2;
    double setup = 0.0;
    ContactCorrection sys;
    sys.lambda = lambda;
    sys.stride = 2;
    sys.tangent = &a;
    sys.work = &work;
    sys.flags = fv;
    sys.g = gv;
    sys.prescribed = pv;
    sys.displacement = uv;
    sys.rhs = rhs;
    sys.target = target;
    sys.solver = solver.get();
    sys.stiffnessScale = 1.0;
    sys.setupSeconds = &setup;
    contact.correct(sys, dx);
    const Eigen::VectorXd x = toEigen(dx);
    // The model's path: the provider's constraint set solved by the caller.
    resetTransferCounts(); // the set is built on the device from the uploaded contact entries
    const ConstraintSet *set = contact.constraintSet(sys);
    const TransferCounts moved = transferCounts();
    EXPECT_EQ(moved.toHostCalls + moved.toDeviceCalls, 0u);
    ASSERT_NE(set, nullptr);
    EXPECT_TRUE(set->hasFrames());
    EXPECT_FALSE(set->hasMultipoint());
    Kokkos::deep_copy(rhs, toView(Eigen::VectorXd(-g)));
    ConstraintElimination elimination;
    solveConstrained(*set, a, work2, elimination, rhs, *solver, dx2);
    const Eigen::VectorXd x2 = toEigen(dx2);
    for (int i = 0; i < n; ++i)
      EXPECT_EQ(x2(i), x(i)) << i;

    // Host reference from the host constraints: R = [n t] at framed nodes free of Dirichlet
    // conditions, held local components with their values, the rest solving the rotated system.
    const ContactConstraints &c = contact.constraints();
    Eigen::MatrixXd rot = Eigen::MatrixXd::Identity(n, n);
    std::vector<int> held(flags);
    Eigen::VectorXd value = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < n; ++i)
      if (flags[i])
        value(i) = lambda * presc[i] - u(i);
    int framedCount = 0;
    for (LocalIndex p = 0; p < nn; ++p) {
      if (!c.framed[p])
        continue;
      const double nx = c.normal[2 * p], ny = c.normal[2 * p + 1];
      if (flags[2 * p] || flags[2 * p + 1]) { // a symmetry line: n along the free axis
        const int fixed = flags[2 * p] ? 0 : 1, other = 1 - fixed;
        const double nd[2] = {nx, ny};
        held[2 * p + other] = 1;
        value(2 * p + other) = (c.normalStep[p] - nd[fixed] * value(2 * p + fixed)) / nd[other];
        continue;
      }
      ++framedCount;
      rot(2 * p, 2 * p) = nx;
      rot(2 * p + 1, 2 * p) = ny;
      rot(2 * p, 2 * p + 1) = -ny;
      rot(2 * p + 1, 2 * p + 1) = nx;
      EXPECT_TRUE(c.normalFixed[p]);
      EXPECT_EQ(c.tangentFixed[p] != 0, mu > 0.0);
      held[2 * p] = 1;
      value(2 * p) = c.normalStep[p];
      if (c.tangentFixed[p]) {
        held[2 * p + 1] = 1;
        value(2 * p + 1) = c.tangentStep[p];
      }
    }
    ASSERT_EQ(framedCount, 2);
    std::vector<int> free;
    for (int i = 0; i < n; ++i)
      if (!held[i])
        free.push_back(i);
    Eigen::MatrixXd pm = Eigen::MatrixXd::Zero(n, static_cast<long>(free.size()));
    for (std::size_t k = 0; k < free.size(); ++k)
      pm(free[k], static_cast<long>(k)) = 1.0;
    const Eigen::MatrixXd map = rot * pm;
    const Eigen::VectorXd shift = rot * value;
    const Eigen::VectorXd z =
        (map.transpose() * ad * map).llt().solve(map.transpose() * (-g - ad * shift));
    const Eigen::VectorXd xRef = map * z + shift;
    EXPECT_LT((x - xRef).norm(), 1e-10 * xRef.norm()) << "mu " << mu;

    // The held components directly: normal (and stick tangential) steps, slip free of force.
    const Eigen::VectorXd r = ad * x + g;
    for (LocalIndex p = 0; p < nn; ++p) {
      if (!c.framed[p] || flags[2 * p] || flags[2 * p + 1])
        continue;
      const double nx = c.normal[2 * p], ny = c.normal[2 * p + 1];
      EXPECT_NEAR(nx * x(2 * p) + ny * x(2 * p + 1), c.normalStep[p], 1e-12) << p;
      const double dt = -ny * x(2 * p) + nx * x(2 * p + 1), rt = -ny * r(2 * p) + nx * r(2 * p + 1);
      if (mu > 0.0) {
        EXPECT_NEAR(dt, c.tangentStep[p], 1e-12) << p;
      } else {
        EXPECT_NEAR(rt, 0.0, 1e-10 * g.norm()) << p;
      }
    }
    EXPECT_NEAR(x(2 * symmetric), lambda * presc[2 * symmetric] - u(2 * symmetric), 1e-14);
  }

  // A force-driven pin: its motion is an unknown of the correction, so no set.
  RigidContactSpec spec;
  spec.obstacle = circle(1.5, -0.5, 0.75);
  spec.nodes = f.mesh.nodesOf("bottom");
  spec.forceDriven[1] = true;
  spec.force[1] = 1.0;
  spec.name = "bottom";
  RigidContact driven(nn, {spec});
  driven.setLoadFactor(lambda);
  driven.detect(Kokkos::View<const double *[2], Memory>(f.data.mesh.coordinates), uv, 2);
  driven.closeTouching(0.0);
  ContactCorrection sys;
  sys.stride = 2;
  sys.flags = fv;
  sys.prescribed = pv;
  sys.displacement = uv;
  sys.target = target;
  EXPECT_EQ(driven.constraintSet(sys), nullptr);
}

// The gap goes linearly from g0 to g over an increment: it is zero at g0 / (g0 - g). Only an
// open start (g0 > 0) and a penetrating end (g < 0) cross; an unknown gap (NaN, a restart file
// without it) does not.
TEST(ContactStatus, CrossingFractionIsWhereTheGapVanishes) {
  EXPECT_DOUBLE_EQ(crossingFraction(0.025, -0.0125), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(crossingFraction(1e-3, -3e-3), 0.25);
  const double nan = std::nan("");
  const std::pair<double, double> none[] = {{0.0, -1.0}, {-0.1, -0.2}, {0.1, 0.05},
                                            {0.1, 0.0},  {nan, -0.1},  {0.1, nan}};
  for (const auto &[g0, g] : none)
    EXPECT_EQ(crossingFraction(g0, g), -1.0) << g0 << " -> " << g;
}
