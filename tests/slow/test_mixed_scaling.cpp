// Slow: the default mixed solver (consistent M, default stabilization, block-triangular
// preconditioned GMRES on the saddle point since issue 20, BoomerAMG as chosen by
// `preconditioner: auto`) keeps its Krylov
// iteration count nearly mesh independent: from about 1e4 to about 1e6 unknowns (5 per node) on the
// DESIGN-NOTES strip, the count grows by less than 1.5x. Iteration counts only; the timings belong
// to bench/bench_mixed_solver.cpp.
#include <mesh/Generators.hpp>
#include <solver/MixedModel.hpp>

#include <support/MixedSolution.hpp>
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
  MixedOptions o; // the defaults under test
  o.linear.tolerance = 1e-8;
  const test::StripSolve r = test::solveShearedStrip(type, ny, o);
  return {r.unknowns, r.stats.iterations, r.stats.converged};
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
