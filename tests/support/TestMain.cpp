// GoogleTest main for mixcon: starts MPI, Kokkos and hypre once for all tests.
#include <solver/Environment.hpp>

#include <gtest/gtest.h>

int main(int argc, char **argv) {
  ::testing::InitGoogleTest(&argc, argv);
  mixcon::Environment env(argc, argv);
  return RUN_ALL_TESTS();
}
