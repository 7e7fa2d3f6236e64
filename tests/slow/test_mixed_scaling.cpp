// Slow: the default mixed solver (consistent M, default stabilization, flexible CG on the
// matrix-free Schur complement, BoomerAMG as chosen by `preconditioner: auto`) keeps its Krylov
// iteration count nearly mesh independent: from about 1e4 to about 1e6 unknowns (5 per node) on the
// DESIGN-NOTES strip, the count grows by less than 1.5x. Iteration counts only; the timings belong
// to bench/bench_mixed_solver.cpp.
#include <mesh/Generators.hpp>
#include <solver/MixedModel.hpp>

#include <support/Params.hpp>

#include <gtest/gtest.h>

using namespace mixcon;

namespace {
struct StripRun {
  long unknowns = 0;
  int iterations = 0;
  bool converged = false;
};

StripRun solveStrip(ElementType type, int ny) {
  const Mesh mesh = rectangleMesh(4.0, 1.0, 4 * ny, ny, type);
  MixedModel model(mesh, std::vector<int>(mesh.numElements(), 0),
                   {isotropicStiffness(1.0, 0.3, PlaneAnalysis::PlaneStress)}, 1.0);
  for (LocalIndex n : mesh.nodesOf("left")) {
    model.prescribe(n, 0, 0.0);
    model.prescribe(n, 1, 0.0);
  }
  model.addEdgeLoad(mesh.boundaries.at("right"), 0.0, 1e-3, 0.0);
  MixedOptions o; // the defaults under test
  o.linear.tolerance = 1e-8;
  model.setup(o, MPI_COMM_WORLD);
  const auto st = model.solve(1.0);
  return {5L * mesh.numNodes(), st.iterations, st.converged};
}
} // namespace

class MixedScalingTest : public ::testing::TestWithParam<ElementType> {};
INSTANTIATE_TEST_SUITE_P(Elements, MixedScalingTest, test::bothElements(), test::elementName);

TEST_P(MixedScalingTest, DefaultSolverIterationsGrowLessThanHalfFrom1e4To1e6Unknowns) {
  const bool q8 = GetParam() == ElementType::Quad8;
  const StripRun small = solveStrip(GetParam(), q8 ? 12 : 22);
  const StripRun large = solveStrip(GetParam(), q8 ? 128 : 224);
  ASSERT_TRUE(small.converged);
  ASSERT_TRUE(large.converged);
  EXPECT_GT(small.unknowns, 8000);
  EXPECT_LT(small.unknowns, 15000);
  EXPECT_GT(large.unknowns, 900000);
  std::printf("unknowns %ld: %d iterations; unknowns %ld: %d iterations (ratio %.2f)\n",
              small.unknowns, small.iterations, large.unknowns, large.iterations,
              static_cast<double>(large.iterations) / small.iterations);
  EXPECT_LT(large.iterations, 1.5 * small.iterations);
}
