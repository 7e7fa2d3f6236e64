// Device <-> host transfers inside the Newton and Krylov loops (issue 16, item 6), counted by the
// transfer API (core/Transfer.hpp), which counts every copy whether or not the backend's memory
// is host-accessible, so these assertions mean the same under OpenMP as under CUDA:
//  - the counters themselves against the views' sizes;
//  - without contact, the geometrically nonlinear displacement model (hypre GMRES + BoomerAMG)
//    and the mixed model (flexible GMRES, block-triangular preconditioner, BoomerAMG on K^L)
//    make at most a small constant number of device -> host copies per Newton iteration, and
//    the same number on two mesh sizes (a per-node copy would grow with the mesh);
//  - with a rigid obstacle, the bytes moved per iteration grow with the contact candidate nodes,
//    not with the mesh: two blocks with the same contact boundary and 4x the interior rows;
//  - with node-to-segment contact between two blocks, likewise with the contactor and target
//    nodes (positions, flags and search results of those nodes only; the constraint
//    elimination and the condensed residual norm on the device);
//  - the copies a host library needs (hypre built for the CPU reading a GPU's vectors and matrix
//    values) count apart, as staging: none where the memory is host-accessible, some under CUDA
//    (printed, and documented in docs/gpu.md); the bounds above hold for the rest.
#include <contact/RigidContact.hpp>
#include <contact/SurfaceContact.hpp>
#include <core/Transfer.hpp>
#include <mesh/Generators.hpp>
#include <solver/LoadStepper.hpp>
#include <solver/Nonlinear.hpp>

#include <gtest/gtest.h>

#include <memory>
#include <set>

using namespace mixcon;

namespace {

using Space = Kokkos::DefaultExecutionSpace::memory_space;

struct PerIteration {
  double toHostCalls = 0, toHostBytes = 0, toDeviceCalls = 0, toDeviceBytes = 0;
  double stagingBytes = 0; ///< both ways, for the host solver library
  int iterations = 0;
};

/// Runs a first load step (setup done lazily at the first correction, e.g. the mixed model's
/// coupling-block pattern, happens there), then `increments` more to load factor 1, and returns
/// the transfers per Newton iteration counted in those.
PerIteration countPerIteration(NonlinearModel &model, int increments) {
  LoadStepper stepper(model, NonlinearOptions{});
  const double first = 1.0 / (increments + 1);
  EXPECT_TRUE(stepper.advance(first).converged);
  resetTransferCounts();
  PerIteration p;
  for (int k = 1; k <= increments; ++k) {
    const IncrementOutcome o = stepper.advance(first * (k + 1));
    EXPECT_TRUE(o.converged) << o.message;
    p.iterations += o.iterations;
  }
  const TransferCounts c = transferCounts();
  EXPECT_GT(p.iterations, 0);
  const double n = std::max(1, p.iterations);
  p.toHostCalls = c.toHostCalls / n;
  p.toHostBytes = c.toHostBytes / n;
  p.toDeviceCalls = c.toDeviceCalls / n;
  p.toDeviceBytes = c.toDeviceBytes / n;
  p.stagingBytes = (c.stagingToHostBytes + c.stagingToDeviceBytes) / n;
  std::printf("    %d Newton iterations; per iteration: device->host %.2f copies, %.0f bytes; "
              "host->device %.2f copies, %.0f bytes; host solver staging %.2f copies, %.0f "
              "bytes\n",
              p.iterations, p.toHostCalls, p.toHostBytes, p.toDeviceCalls, p.toDeviceBytes,
              (c.stagingToHostCalls + c.stagingToDeviceCalls) / n, p.stagingBytes);
  // hypre (a CPU build) works on host-accessible views in place; a GPU's it must copy.
  if constexpr (kHostAccessible<Space>)
    EXPECT_EQ(c.stagingToHostCalls + c.stagingToDeviceCalls, 0u);
  else
    EXPECT_GT(c.stagingToHostCalls, 0u);
  return p;
}

/// A cantilever (L = 10, h = 1, clamped at x = 0) bending under a tip-side shear large enough
/// for a few Newton iterations per increment; `nx` x `nx / 10` Quad4 elements.
std::unique_ptr<NonlinearModel> cantilever(Mesh &mesh, int nx, bool mixed) {
  mesh = rectangleMesh(10.0, 1.0, nx, std::max(1, nx / 10), ElementType::Quad4, 0.0, -0.5);
  const std::vector<PlaneMatrix> c{isotropicStiffness(1.2e4, 0.2, PlaneAnalysis::PlaneStress)};
  const std::vector<int> material(mesh.numElements(), 0);
  std::unique_ptr<NonlinearModel> model;
  if (mixed) {
    auto m = std::make_unique<NonlinearMixedModel>(mesh, material, c, 1.0);
    MixedNewtonSolverOptions so;
    so.method = MixedNewtonSolver::BlockTriangular;
    m->setIterativeSolver(so);
    model = std::move(m);
  } else {
    model = std::make_unique<NonlinearDisplacementModel>(mesh, material, c, 1.0);
  }
  for (LocalIndex n : mesh.nodesOf("left")) {
    model->prescribe(n, 0, 0.0);
    model->prescribe(n, 1, 0.0);
  }
  model->addEdgeLoad(mesh.boundaries.at("right"), 0.0, -10.0, 0.0);
  LinearSolverOptions o;
  o.type = LinearSolverType::Amg;
  o.tolerance = 1e-10;
  model->setup(o, MPI_COMM_WORLD);
  return model;
}

} // namespace

TEST(Transfers, CountersCountCallsAndBytesOnEveryBackend) {
  resetTransferCounts();
  Kokkos::View<double *, Space> d("d", 7);
  Kokkos::View<int *[2], Space> e("e", 5);
  auto h = hostMirror(d);
  for (int i = 0; i < 7; ++i)
    h(i) = i;
  EXPECT_EQ(transferCounts().toDeviceCalls, 0u); // a mirror alone is no copy
  copyToDevice(d, h);
  const auto back = toHostVector(d);
  const auto he = copyToHost(e);
  copyToHost(he, e);
  copyToDevice(d, std::vector<double>(7, 2.0));
  const TransferCounts c = transferCounts();
  EXPECT_EQ(c.toDeviceCalls, 2u);
  EXPECT_EQ(c.toDeviceBytes, 2u * 7 * sizeof(double));
  EXPECT_EQ(c.toHostCalls, 3u);
  EXPECT_EQ(c.toHostBytes, 7 * sizeof(double) + 2u * 10 * sizeof(int));
  EXPECT_EQ(back[6], 6.0);
  EXPECT_EQ(toHostVector(d)[3], 2.0);
  resetTransferCounts();
  EXPECT_EQ(transferCounts().toHostCalls, 0u);
  EXPECT_EQ(transferCounts().toDeviceBytes, 0u);
}

TEST(Transfers, NonlinearDisplacementModelWithAmgKeepsNewtonOnTheDevice) {
  PerIteration p[2];
  for (int k = 0; k < 2; ++k) {
    Mesh mesh;
    auto model = cantilever(mesh, k == 0 ? 20 : 80, false);
    p[k] = countPerIteration(*model, 2);
  }
  for (const PerIteration &q : p) {
    EXPECT_LE(q.toHostCalls, 1.0); // ideally 0; scalar reductions are not transfers
    EXPECT_LE(q.toDeviceCalls, 1.0);
  }
  // Independent of the mesh: 16x the nodes moves no more bytes per iteration.
  EXPECT_LE(p[1].toHostBytes, p[0].toHostBytes);
  EXPECT_LE(p[1].toDeviceBytes, p[0].toDeviceBytes);
}

TEST(Transfers, NonlinearMixedModelIterativeSolveKeepsNewtonOnTheDevice) {
  PerIteration p[2];
  for (int k = 0; k < 2; ++k) {
    Mesh mesh;
    auto model = cantilever(mesh, k == 0 ? 12 : 36, true);
    p[k] = countPerIteration(*model, 2);
  }
  for (const PerIteration &q : p) {
    EXPECT_LE(q.toHostCalls, 1.0);
    EXPECT_LE(q.toDeviceCalls, 1.0);
  }
  EXPECT_LE(p[1].toHostBytes, p[0].toHostBytes);
  EXPECT_LE(p[1].toDeviceBytes, p[0].toDeviceBytes);
}

namespace {

/// An elastic block (W = 2, H = 1, Quad8, finite displacements, hypre AMG) pressed by its top onto
/// a rigid half-plane with friction: `ny` element rows, 8 columns whatever `ny`, so the contact
/// candidates (the bottom nodes) are the same on every mesh.
struct Block {
  Mesh mesh;
  std::unique_ptr<NonlinearDisplacementModel> model;
  std::unique_ptr<RigidContact> contact;
};

Block pressedBlock(int ny) {
  Block b;
  b.mesh = rectangleMesh(2.0, 1.0, 8, ny, ElementType::Quad8);
  const std::vector<PlaneMatrix> c{isotropicStiffness(21000.0, 0.3, PlaneAnalysis::PlaneStrain)};
  b.model = std::make_unique<NonlinearDisplacementModel>(
      b.mesh, std::vector<int>(b.mesh.numElements(), 0), c, 1.0);
  for (LocalIndex n : b.mesh.nodesOf("left"))
    b.model->prescribe(n, 0, 0.0);
  for (LocalIndex n : b.mesh.nodesOf("top"))
    b.model->prescribe(n, 1, -0.02);
  RigidContactSpec spec;
  spec.obstacle.kind = ObstacleKind::HalfPlane;
  spec.obstacle.point[0] = spec.obstacle.point[1] = 0.0;
  spec.obstacle.normal[0] = 0.0;
  spec.obstacle.normal[1] = 1.0;
  spec.nodes = b.mesh.nodesOf("bottom");
  spec.friction = 0.3;
  spec.name = "bottom";
  b.contact =
      std::make_unique<RigidContact>(b.mesh.numNodes(), std::vector<RigidContactSpec>{spec});
  b.model->setContact(b.contact.get());
  LinearSolverOptions o;
  o.type = LinearSolverType::Amg;
  o.tolerance = 1e-10;
  b.model->setup(o, MPI_COMM_WORLD);
  return b;
}

} // namespace

TEST(Transfers, RigidContactMovesBytesOfTheContactNodesNotOfTheMesh) {
  PerIteration p[2];
  LocalIndex nodes[2] = {0, 0}, candidates[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    Block b = pressedBlock(k == 0 ? 2 : 8);
    nodes[k] = b.mesh.numNodes();
    candidates[k] = b.contact->numCandidates();
    p[k] = countPerIteration(*b.model, 2);
  }
  ASSERT_EQ(candidates[0], candidates[1]);
  ASSERT_GT(nodes[1], 3 * nodes[0]);
  std::printf("    %d / %d nodes, %d contact candidates\n", nodes[0], nodes[1], candidates[0]);
  // Per iteration, bytes bounded by a constant times the candidates (gap, normal, angle, arc
  // per candidate and the like), and no more on the mesh with 3.3x the nodes.
  for (const PerIteration &q : p) {
    EXPECT_LE(q.toHostBytes, 64.0 * sizeof(double) * candidates[0]);
    EXPECT_LE(q.toDeviceBytes, 64.0 * sizeof(double) * candidates[0]);
  }
  EXPECT_LE(p[1].toHostBytes, 1.25 * p[0].toHostBytes);
  EXPECT_LE(p[1].toDeviceBytes, 1.25 * p[0].toDeviceBytes);
}

namespace {

/// Two stacked elastic blocks (W = 2, H = 1 each, Quad8, finite displacements, hypre AMG): the
/// lower one held at its base, the upper one's top pressed down and sideways, node-to-segment
/// contact with friction from the upper base (contactor) onto the lower top (target). 6 and 5
/// element columns whatever `ny` (element rows per block), so the surface nodes are the same on
/// every mesh.
struct TwoBlocks {
  Mesh mesh;
  std::unique_ptr<NonlinearDisplacementModel> model;
  std::unique_ptr<SurfaceContact> contact;
};

TwoBlocks pressedBlocks(int ny) {
  TwoBlocks b;
  MeshBody lower{"lower", rectangleMesh(2.0, 1.0, 6, ny, ElementType::Quad8), {0.0, 0.0}};
  MeshBody upper{"upper", rectangleMesh(2.0, 1.0, 5, ny, ElementType::Quad8), {0.0, 1.0}};
  b.mesh = mergeMeshes({lower, upper});
  const std::vector<PlaneMatrix> c{isotropicStiffness(21000.0, 0.3, PlaneAnalysis::PlaneStrain)};
  b.model = std::make_unique<NonlinearDisplacementModel>(
      b.mesh, std::vector<int>(b.mesh.numElements(), 0), c, 1.0);
  for (LocalIndex n : b.mesh.nodesOf("lower.bottom"))
    for (int i = 0; i < 2; ++i)
      b.model->prescribe(n, i, 0.0);
  for (LocalIndex n : b.mesh.nodesOf("upper.top")) {
    b.model->prescribe(n, 0, 0.004);
    b.model->prescribe(n, 1, -0.02);
  }
  SurfaceContactSpec spec;
  spec.contactor = b.mesh.nodesOf("upper.bottom");
  spec.target = boundarySegments(b.mesh, "lower.top");
  spec.friction = 0.3;
  spec.name = "upper.bottom -> lower.top";
  b.contact =
      std::make_unique<SurfaceContact>(b.mesh.numNodes(), std::vector<SurfaceContactSpec>{spec});
  b.model->setContact(b.contact.get());
  LinearSolverOptions o;
  o.type = LinearSolverType::Amg;
  o.tolerance = 1e-10;
  b.model->setup(o, MPI_COMM_WORLD);
  return b;
}

} // namespace

TEST(Transfers, SurfaceContactMovesBytesOfTheContactNodesNotOfTheMesh) {
  PerIteration p[2];
  LocalIndex nodes[2] = {0, 0}, surface[2] = {0, 0}, closed[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    TwoBlocks b = pressedBlocks(k == 0 ? 2 : 8);
    nodes[k] = b.mesh.numNodes();
    const auto spec = b.contact->specs().front();
    std::set<LocalIndex> s(spec.contactor.begin(), spec.contactor.end());
    for (const auto &seg : spec.target)
      for (LocalIndex n : seg)
        if (n >= 0)
          s.insert(n);
    surface[k] = static_cast<LocalIndex>(s.size());
    p[k] = countPerIteration(*b.model, 2);
    closed[k] = b.contact->numClosed();
  }
  ASSERT_EQ(surface[0], surface[1]);
  ASSERT_GT(nodes[1], 3 * nodes[0]);
  EXPECT_GT(closed[0], 0); // the contact constraints acted
  EXPECT_GT(closed[1], 0);
  std::printf("    %d / %d nodes, %d contactor and target nodes, %d / %d closed\n", nodes[0],
              nodes[1], surface[0], closed[0], closed[1]);
  // Per iteration, bytes bounded by a constant times the surface nodes, and no more on the
  // mesh with 3.7x the nodes (a per-node copy of the residual alone is 16 bytes per node).
  for (const PerIteration &q : p) {
    EXPECT_LE(q.toHostBytes, 64.0 * sizeof(double) * surface[0]);
    EXPECT_LE(q.toDeviceBytes, 64.0 * sizeof(double) * surface[0]);
  }
  EXPECT_LE(p[1].toHostBytes, 1.25 * p[0].toHostBytes);
  EXPECT_LE(p[1].toDeviceBytes, 1.25 * p[0].toDeviceBytes);
}
