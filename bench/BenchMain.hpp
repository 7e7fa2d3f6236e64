// Shared main of the Google Benchmark programs: initializes MPI/Kokkos/hypre (Environment) and
// records the Kokkos backend, hypre version and git commit in the benchmark context.
#pragma once

#include <solver/Environment.hpp>
#include <solver/LinearSolver.hpp>

#include <benchmark/benchmark.h>

namespace mixcon {

inline int runBenchmarks(int argc, char **argv) {
  Environment env(argc, argv);
  benchmark::Initialize(&argc, argv);
  benchmark::AddCustomContext("kokkos", Environment::describe());
  benchmark::AddCustomContext("hypre", hypreVersion());
  benchmark::AddCustomContext("git", MIXCON_GIT_HASH);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

} // namespace mixcon
