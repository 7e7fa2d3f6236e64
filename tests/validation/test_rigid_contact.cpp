// Contact with a rigid half-plane through the nested equilibrium / contact iterations
// (contact/RigidContact.hpp, LoadStepper): an elastic block (W = 2, H = 1, plane strain,
// E = 21000, nu = 0.3, small-displacement kinematics) pushed onto a rigid plane by a prescribed
// top displacement delta, symmetric about x = 0.
// Reference (uniaxial plane-strain compression with free lateral expansion, frictionless base):
// sigma_yy = -E delta / (H (1 - nu^2)) uniformly, so the total contact force is that times W and
// every base node closes; with a large friction coefficient the base sticks (no lateral motion
// there) and |T| <= mu N; pulling the block back up opens every node.
#include <contact/RigidContact.hpp>
#include <mesh/Generators.hpp>
#include <solver/Nonlinear.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

using namespace mixcon;

namespace rigid_contact_tests {

constexpr double kE = 21000.0, kNu = 0.3, kW = 2.0, kH = 1.0, kDelta = 0.01;

struct Block {
  Mesh mesh;
  std::unique_ptr<NonlinearModel> model;
  std::unique_ptr<RigidContact> contact;
};

enum class Kinematics { SmallDisplacement, FiniteDisplacement, FiniteMixed, SmallMixed };

Block makeBlock(double friction, Kinematics kind = Kinematics::SmallDisplacement) {
  Block b;
  b.mesh = rectangleMesh(kW, kH, 8, 4, ElementType::Quad8);
  const std::vector<PlaneMatrix> c{isotropicStiffness(kE, kNu, PlaneAnalysis::PlaneStrain)};
  const std::vector<int> material(b.mesh.numElements(), 0);
  if (kind == Kinematics::FiniteMixed || kind == Kinematics::SmallMixed)
    b.model = std::make_unique<NonlinearMixedModel>(b.mesh, material, c, 1.0);
  else
    b.model = std::make_unique<NonlinearDisplacementModel>(b.mesh, material, c, 1.0);
  b.model->setSmallDisplacements(kind == Kinematics::SmallDisplacement ||
                                 kind == Kinematics::SmallMixed);
  for (LocalIndex n : b.mesh.nodesOf("left"))
    b.model->prescribe(n, 0, 0.0);
  for (LocalIndex n : b.mesh.nodesOf("top"))
    b.model->prescribe(n, 1, -kDelta);
  RigidContactSpec spec;
  spec.obstacle.kind = ObstacleKind::HalfPlane;
  spec.obstacle.point[0] = spec.obstacle.point[1] = 0.0;
  spec.obstacle.normal[0] = 0.0;
  spec.obstacle.normal[1] = 1.0;
  spec.nodes = b.mesh.nodesOf("bottom");
  spec.friction = friction;
  spec.name = "bottom";
  b.contact =
      std::make_unique<RigidContact>(b.mesh.numNodes(), std::vector<RigidContactSpec>{spec});
  b.model->setContact(b.contact.get());
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  b.model->setup(o, MPI_COMM_WORLD);
  return b;
}

/// Total vertical reaction at the top (compression positive).
double topForce(const Block &b) {
  const auto g = b.model->residualVectorHost();
  const int stride = b.model->unknownsPerNode();
  double f = 0.0;
  for (LocalIndex n : b.mesh.nodesOf("top"))
    f -= g[stride * n + 1];
  return f;
}

} // namespace rigid_contact_tests
using namespace rigid_contact_tests;

TEST(RigidContact, FrictionlessBlockTransmitsUniformCompression) {
  Block b = makeBlock(0.0);
  LoadStepper stepper(*b.model, NonlinearOptions{});
  const IncrementOutcome o = stepper.advance(1.0);
  ASSERT_TRUE(o.converged) << o.message;
  EXPECT_GT(o.contactIterations, 0);
  const double expected = kE * kDelta / (kH * (1 - kNu * kNu)) * kW;
  EXPECT_NEAR(topForce(b), expected, 1e-8 * expected);
  double sumN = 0.0;
  for (LocalIndex k = 0; k < b.contact->numCandidates(); ++k) {
    EXPECT_EQ(b.contact->status(k), ContactStatus::Slip) << "node " << b.contact->candidateNode(k);
    EXPECT_GT(b.contact->gap(k), -1e-12); // no penetration left
    sumN += b.contact->normalForce(k);
  }
  EXPECT_NEAR(sumN, expected, 1e-8 * expected);
  // Free lateral expansion: the base moves outward like the top, u_x(W) = nu delta W / ((1-nu) H)
  // for plane strain.
  const auto u = b.model->displacementHost();
  for (LocalIndex n : b.mesh.nodesOf("right"))
    EXPECT_NEAR(u[2 * n], kNu / (1 - kNu) * kDelta * kW / kH, 1e-9);
}

// A linear body (small displacements) against a flat obstacle: the linearized constraints are
// exact, so each contact iteration is one linear solve (the residual criterion alone decides);
// with finite kinematics the equilibrium iterations go on until |du|/|u| is small as well.
// Both models: the linear mixed model (small displacements, Jacobian at the origin; its
// equal-order Quad8 stresses hold the uniform state exactly) too.
TEST(RigidContact, LinearBodyOnFlatObstacleSolvesOncePerContactIteration) {
  for (const Kinematics kind : {Kinematics::SmallDisplacement, Kinematics::SmallMixed}) {
    Block linear = makeBlock(0.0, kind);
    EXPECT_TRUE(linear.model->linearResponse());
    EXPECT_TRUE(linear.contact->linearConstraints());
    LoadStepper stepper(*linear.model, NonlinearOptions{});
    const IncrementOutcome o = stepper.advance(1.0);
    ASSERT_TRUE(o.converged) << o.message;
    // One solve before the first status update, one after each update that changed a status.
    EXPECT_EQ(o.iterations, o.contactIterations);
    const double expected = kE * kDelta / (kH * (1 - kNu * kNu)) * kW;
    EXPECT_NEAR(topForce(linear), expected, 1e-8 * expected);
  }

  Block finite = makeBlock(0.0, Kinematics::FiniteDisplacement);
  EXPECT_FALSE(finite.model->linearResponse());
  LoadStepper fs(*finite.model, NonlinearOptions{});
  const IncrementOutcome of = fs.advance(1.0);
  ASSERT_TRUE(of.converged) << of.message;
  EXPECT_GT(of.iterations, of.contactIterations);
}

TEST(RigidContact, LargeFrictionSticksTheBaseAndOpensOnUnloading) {
  Block b = makeBlock(1.0);
  LoadStepper stepper(*b.model, NonlinearOptions{});
  for (double lambda : {0.5, 1.0}) {
    const IncrementOutcome o = stepper.advance(lambda);
    ASSERT_TRUE(o.converged) << o.message;
  }
  const auto u = b.model->displacementHost();
  for (LocalIndex k = 0; k < b.contact->numCandidates(); ++k) {
    const LocalIndex n = b.contact->candidateNode(k);
    EXPECT_EQ(b.contact->status(k), ContactStatus::Stick) << "node " << n;
    EXPECT_NEAR(u[2 * n], 0.0, 1e-12) << "node " << n; // held where it touched
    EXPECT_LE(std::abs(b.contact->tangentForce(k)), 1.0 * b.contact->normalForce(k) + 1e-9);
  }
  // The stuck base restrains the lateral expansion: stiffer than the frictionless block.
  const double frictionless = kE * kDelta / (kH * (1 - kNu * kNu)) * kW;
  EXPECT_GT(topForce(b), 1.01 * frictionless);
  // Lift the block off: every base node opens, the contact forces vanish.
  const IncrementOutcome up = stepper.advance(-0.5);
  ASSERT_TRUE(up.converged) << up.message;
  for (LocalIndex k = 0; k < b.contact->numCandidates(); ++k) {
    EXPECT_EQ(b.contact->status(k), ContactStatus::Open);
    EXPECT_GT(b.contact->gap(k), 0.0);
  }
  EXPECT_NEAR(topForce(b), 0.0, 1e-8 * frictionless);
}

// Finite kinematics, both models: the block's deformation is homogeneous, so the displacement
// model (Almansi law) and the mixed model (the same law imposed weakly, stick/slip/release from
// its nodal stresses) must transmit the same force; frictionless, every base node closes.
TEST(RigidContact, MixedModelMatchesDisplacementModelOnTheBlock) {
  double force[2] = {};
  for (int k = 0; k < 2; ++k) {
    Block b = makeBlock(0.0, k == 0 ? Kinematics::FiniteDisplacement : Kinematics::FiniteMixed);
    LoadStepper stepper(*b.model, NonlinearOptions{});
    for (double lambda : {0.5, 1.0}) {
      const IncrementOutcome o = stepper.advance(lambda);
      ASSERT_TRUE(o.converged) << o.message;
    }
    for (LocalIndex c = 0; c < b.contact->numCandidates(); ++c) {
      EXPECT_EQ(b.contact->status(c), ContactStatus::Slip);
      EXPECT_GT(b.contact->gap(c), -1e-12);
    }
    force[k] = topForce(b);
  }
  const double small = kE * kDelta / (kH * (1 - kNu * kNu)) * kW;
  EXPECT_NEAR(force[1], force[0], 1e-6 * force[0]);
  EXPECT_NEAR(force[0], small, 0.02 * small);          // 1 % strain: close to the linear value
  EXPECT_GT(std::abs(force[0] - small), 1e-6 * small); // but finite kinematics differ
}

// The mixed model with friction: the base sticks (decided from its nodal stresses).
TEST(RigidContact, MixedModelSticksWithLargeFriction) {
  Block b = makeBlock(1.0, Kinematics::FiniteMixed);
  LoadStepper stepper(*b.model, NonlinearOptions{});
  ASSERT_TRUE(stepper.advance(1.0).converged);
  const auto u = b.model->displacementHost();
  for (LocalIndex c = 0; c < b.contact->numCandidates(); ++c) {
    EXPECT_EQ(b.contact->status(c), ContactStatus::Stick);
    EXPECT_NEAR(u[2 * b.contact->candidateNode(c)], 0.0, 1e-12);
  }
}

// A block resting on the plane (gap 0) under a downward traction q on its top and held only by
// the plane and the symmetry line: the touching nodes close before the first correction, the
// base carries q W (equilibrium), uniformly for the frictionless plane. Lifted by 1e-3 instead,
// it is not supported at all: the increment fails with a message naming the rigid-body mode.
TEST(RigidContact, RestingBodyIsSupportedAndAFloatingOneIsReported) {
  for (double lift : {0.0, 1e-3}) {
    Mesh mesh = rectangleMesh(kW, kH, 6, 3, ElementType::Quad8, 0.0, lift);
    const std::vector<PlaneMatrix> c{isotropicStiffness(kE, kNu, PlaneAnalysis::PlaneStrain)};
    NonlinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), c, 1.0);
    model.setSmallDisplacements(true);
    for (LocalIndex n : mesh.nodesOf("left"))
      model.prescribe(n, 0, 0.0);
    const double q = 50.0;
    model.addEdgeLoad(mesh.boundaries.at("top"), 0.0, -q, 0.0);
    RigidContactSpec spec;
    spec.obstacle.kind = ObstacleKind::HalfPlane;
    spec.obstacle.normal[0] = 0.0;
    spec.obstacle.normal[1] = 1.0;
    spec.nodes = mesh.nodesOf("bottom");
    spec.name = "bottom";
    RigidContact contact(mesh.numNodes(), {spec});
    model.setContact(&contact);
    LinearSolverOptions o;
    o.type = LinearSolverType::Direct;
    model.setup(o, MPI_COMM_WORLD);
    NonlinearOptions opts;
    opts.maxCuts = 1;
    LoadStepper stepper(model, opts);
    const IncrementOutcome out = stepper.advance(1.0);
    if (lift == 0.0) {
      ASSERT_TRUE(out.converged) << out.message;
      double sumN = 0.0;
      for (LocalIndex k = 0; k < contact.numCandidates(); ++k)
        sumN += contact.normalForce(k);
      EXPECT_NEAR(sumN, q * kW, 1e-8 * q * kW);
    } else {
      EXPECT_FALSE(out.converged);
      EXPECT_NE(out.message.find("rigid-body"), std::string::npos) << "message: " << out.message;
    }
  }
}

// A force-driven rigid plane: the block (held at the top, symmetric about x = 0) starts 1e-3
// above the plane, which is pushed up by F = q W. The plane first moves onto the block (seating),
// then compresses it: frictionless, the base carries F uniformly, so the plane's motion is
// 1e-3 + F H (1 - nu^2) / (E W) (uniaxial plane strain, free lateral expansion) and the contact
// forces sum to F. Driving the plane by that motion as a displacement gives the same force.
// The mixed model (finite kinematics) balances the plane's force too.
TEST(RigidContact, ForceDrivenPlaneCarriesItsForceAndMatchesTheDisplacementDrive) {
  const double q = 40.0, clearance = 1e-3, force = q * kW;
  const auto run = [&](Kinematics kind, bool byForce, double motion, double &sumN, double &moved) {
    Mesh mesh = rectangleMesh(kW, kH, 8, 4, ElementType::Quad8);
    const std::vector<PlaneMatrix> c{isotropicStiffness(kE, kNu, PlaneAnalysis::PlaneStrain)};
    const std::vector<int> material(mesh.numElements(), 0);
    std::unique_ptr<NonlinearModel> model;
    if (kind == Kinematics::FiniteMixed) {
      model = std::make_unique<NonlinearMixedModel>(mesh, material, c, 1.0);
    } else {
      auto d = std::make_unique<NonlinearDisplacementModel>(mesh, material, c, 1.0);
      d->setSmallDisplacements(kind == Kinematics::SmallDisplacement);
      model = std::move(d);
    }
    for (LocalIndex n : mesh.nodesOf("left"))
      model->prescribe(n, 0, 0.0);
    for (LocalIndex n : mesh.nodesOf("top"))
      model->prescribe(n, 1, 0.0);
    RigidContactSpec spec;
    spec.obstacle.kind = ObstacleKind::HalfPlane;
    spec.obstacle.point[1] = -clearance;
    spec.obstacle.normal[0] = 0.0;
    spec.obstacle.normal[1] = 1.0;
    spec.nodes = mesh.nodesOf("bottom");
    spec.name = "bottom";
    spec.forceDriven[1] = byForce;
    spec.force[1] = force;
    spec.drive[1] = byForce ? 0.0 : motion;
    RigidContact contact(mesh.numNodes(), {spec});
    model->setContact(&contact);
    LinearSolverOptions o;
    o.type = LinearSolverType::Direct;
    model->setup(o, MPI_COMM_WORLD);
    LoadStepper stepper(*model, NonlinearOptions{});
    const IncrementOutcome out = stepper.advance(1.0);
    ASSERT_TRUE(out.converged) << out.message;
    sumN = 0.0;
    for (LocalIndex k = 0; k < contact.numCandidates(); ++k) {
      EXPECT_NE(contact.status(k), ContactStatus::Open);
      sumN += contact.normalForce(k);
    }
    moved = contact.obstacleMotion(0)[1];
  };
  double sumN = 0.0, moved = 0.0;
  run(Kinematics::SmallDisplacement, true, 0.0, sumN, moved);
  EXPECT_NEAR(sumN, force, 1e-8 * force);
  const double expected = clearance + force * kH * (1 - kNu * kNu) / (kE * kW);
  EXPECT_NEAR(moved, expected, 1e-8 * expected);
  double sumByDisplacement = 0.0, unused = 0.0;
  run(Kinematics::SmallDisplacement, false, moved, sumByDisplacement, unused);
  EXPECT_NEAR(sumByDisplacement, force, 1e-6 * force);
  run(Kinematics::FiniteMixed, true, 0.0, sumN, moved);
  EXPECT_NEAR(sumN, force, 1e-6 * force);
  EXPECT_NEAR(moved, expected, 2e-2 * expected); // finite kinematics: close to the linear value
}
