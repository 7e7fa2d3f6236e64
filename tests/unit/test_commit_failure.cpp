// A converged increment whose commit fails (the mixed models' stress projection onto the moved
// configuration): the committed state stays as it was, and the load stepper cuts the increment
// as for a failed Newton iteration instead of ending the run.
#include <kernels/LinearElasticity.hpp>
#include <kernels/SparseMatrix.hpp>
#include <mesh/Generators.hpp>
#include <solver/IncrementalUpdate.hpp>
#include <solver/LoadStepper.hpp>
#include <solver/NonlinearDisplacementModel.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace mixcon;

namespace {
using Memory = DeviceSpace;

/// The node coordinates, node by node.
std::vector<double> coordinatesHost(const Kokkos::View<double *[2], Memory> &v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  std::vector<double> out;
  for (std::size_t i = 0; i < h.extent(0); ++i)
    out.insert(out.end(), {h(i, 0), h(i, 1)});
  return out;
}

Kokkos::View<double *, Memory> filled(const std::string &name, std::size_t n, double scale) {
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i)
    h[i] = scale * std::sin(0.7 * static_cast<double>(i) + 0.3);
  Kokkos::View<double *, Memory> v(name, n);
  ModelBase::fromHost(h, v);
  return v;
}

/// An incremental state on a 4 x 2 Quad4 mesh: the increment x (5 unknowns per node) with
/// `poison` as node 4's ux, the nodal stress tau, the total displacement and c1.
struct IncrementalState {
  explicit IncrementalState(double poison)
      : mesh(rectangleMesh(2.0, 1.0, 4, 2, ElementType::Quad4)), c1(toDevice<Memory>(mesh)),
        graph(buildNodeGraph(mesh)), map(elementScatterMap<Memory>(mesh, graph)),
        x(filled("x", 5 * mesh.numNodes(), 1e-3)), tau(filled("tau", 3 * mesh.numNodes(), 10.0)),
        displacement(filled("u", 2 * mesh.numNodes(), 1e-2)) {
    Kokkos::deep_copy(Kokkos::subview(x, 5 * 4), poison);
  }
  void commit() {
    detail::commitIncrementalState<2>(
        [&](const auto &f) { dispatchPlaneElement(mesh.elementType, "the test's model", f); }, c1,
        1.0, StressUpdate::Projected, graph, map, mass, x, tau, displacement);
  }
  Mesh mesh;
  MeshView<Memory, 2> c1;
  NodeGraph graph;
  Kokkos::View<int ***, Kokkos::LayoutRight, Memory> map;
  CsrMatrix<Memory> mass;
  Kokkos::View<double *, Memory> x, tau, displacement;
};
} // namespace

TEST(CommitFailure, FailedStressProjectionLeavesTheIncrementalStateUnchanged) {
  IncrementalState s(std::numeric_limits<double>::infinity()); // a non-finite increment
  const auto x0 = ModelBase::toHost(s.x), tau0 = ModelBase::toHost(s.tau),
             u0 = ModelBase::toHost(s.displacement), c0 = coordinatesHost(s.c1.coordinates);
  try {
    s.commit();
    ADD_FAILURE() << "the projection on a non-finite c2 was accepted";
  } catch (const CommitFailure &e) {
    EXPECT_NE(std::string(e.what()).find("mass projection"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ModelBase::toHost(s.x), x0);
  EXPECT_EQ(ModelBase::toHost(s.tau), tau0);
  EXPECT_EQ(ModelBase::toHost(s.displacement), u0);
  EXPECT_EQ(coordinatesHost(s.c1.coordinates), c0);

  IncrementalState ok(1e-3); // a finite increment commits: c1 moves by u, x is zeroed
  const auto okc0 = coordinatesHost(ok.c1.coordinates), okx = ModelBase::toHost(ok.x);
  ok.commit();
  const auto c = coordinatesHost(ok.c1.coordinates), x = ModelBase::toHost(ok.x);
  for (std::size_t n = 0; n < c.size() / 2; ++n)
    for (int d = 0; d < 2; ++d)
      EXPECT_NEAR(c[2 * n + d], okc0[2 * n + d] + okx[5 * n + d], 1e-15);
  EXPECT_EQ(x, std::vector<double>(x.size(), 0.0));
  EXPECT_NE(ModelBase::toHost(ok.tau), tau0);
}

namespace {
/// A displacement model whose first `failures` commits throw CommitFailure (what a failed stress
/// projection does) before changing anything; everything else is the wrapped model's.
class FailingCommits final : public NonlinearModel {
public:
  FailingCommits(NonlinearDisplacementModel &inner, const Mesh &mesh, int failures)
      : NonlinearModel(
            mesh, std::vector<int>(mesh.numElements(), 0),
            std::vector<PlaneMatrix>{isotropicStiffness(1.0, 0.3, PlaneAnalysis::PlaneStress)},
            1.0),
        inner_(inner), failures_(failures) {}
  void setup(const LinearSolverOptions &o, MPI_Comm comm) override { inner_.setup(o, comm); }
  double evaluate(double lambda, bool tangent) override { return inner_.evaluate(lambda, tangent); }
  LinearSolveStats correct(double lambda, double &increment) override {
    return inner_.correct(lambda, increment);
  }
  void commit() override {
    if (commits_++ < failures_)
      throw CommitFailure("the test's projection failed");
    inner_.commit();
  }
  void rollback() override { inner_.rollback(); }
  void saveCommitted(Checkpoint &state) const override { inner_.saveCommitted(state); }
  void restoreCommitted(const Checkpoint &state) override { inner_.restoreCommitted(state); }
  std::vector<double> residualVectorHost() const override { return inner_.residualVectorHost(); }
  std::vector<double> residualVectorHost(const std::vector<LocalIndex> &nodes) const override {
    return inner_.residualVectorHost(nodes);
  }
  int unknownsPerNode() const override { return inner_.unknownsPerNode(); }
  std::string solverName() const override { return inner_.solverName(); }
  std::vector<double> nodalStressHost() const override { return inner_.nodalStressHost(); }
  std::vector<double> reactionHost(double lambda) const override {
    return inner_.reactionHost(lambda);
  }

private:
  NonlinearDisplacementModel &inner_;
  int failures_;
  int commits_ = 0;
};

/// A cantilever of 8 x 2 Quad4 (4 x 0.5) under a tip load, bent by more than 0.1 at its tip.
std::vector<double> bentCantilever(int failures, IncrementOutcome &out, std::string &log) {
  const Mesh mesh = rectangleMesh(4.0, 0.5, 8, 2, ElementType::Quad4);
  const std::vector<PlaneMatrix> mats = {isotropicStiffness(1e4, 0.3, PlaneAnalysis::PlaneStress)};
  NonlinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), mats, 1.0);
  for (LocalIndex n : mesh.nodesOf("left")) {
    model.prescribe(n, 0, 0.0);
    model.prescribe(n, 1, 0.0);
  }
  model.addEdgeLoad(mesh.boundaries.at("right"), 0.0, -2.0, 0.0);
  LinearSolverOptions direct;
  direct.type = LinearSolverType::Direct;
  FailingCommits failing(model, mesh, failures);
  failing.setup(direct, MPI_COMM_WORLD);
  std::ostringstream o;
  LoadStepper stepper(failing, NonlinearOptions{}, &o, Verbosity::Normal);
  out = stepper.advance(1.0);
  log = o.str();
  return model.displacementHost();
}
} // namespace

TEST(CommitFailure, LoadStepperCutsTheIncrementAndGoesOn) {
  IncrementOutcome plain, cut;
  std::string plainLog, cutLog;
  const auto reference = bentCantilever(0, plain, plainLog);
  const auto u = bentCantilever(1, cut, cutLog);
  ASSERT_TRUE(plain.converged) << plain.message;
  EXPECT_EQ(plain.cuts, 0);
  EXPECT_GT(std::abs(reference[reference.size() - 1]), 0.1) << "not a large deflection";
  EXPECT_TRUE(cut.converged) << cut.message;
  EXPECT_EQ(cut.cuts, 1);
  EXPECT_EQ(cut.subincrements, 2);
  EXPECT_NE(cutLog.find("the test's projection failed; cutting the increment to 0.5"),
            std::string::npos)
      << cutLog;
  double d = 0.0, n = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    d = std::max(d, std::abs(u[i] - reference[i]));
    n = std::max(n, std::abs(reference[i]));
  }
  EXPECT_LT(d, 1e-5 * n); // the same equilibrium, reached in two increments
  // Failing every time: the run ends with the reason, after the allowed cuts, not with a throw.
  IncrementOutcome never;
  bentCantilever(1000, never, cutLog);
  EXPECT_FALSE(never.converged);
  EXPECT_NE(never.message.find("the test's projection failed; gave up after"), std::string::npos)
      << never.message;
}
