// RAII start-up and shut-down of the runtime mixcon needs: MPI (unless the host code already
// initialized it), Kokkos (unless already initialized) and hypre. Programs and test mains create
// one Environment before anything else; embedding codes that manage these themselves need none.
#pragma once

#include <Kokkos_Core.hpp>
#include <mpi.h>
#include <string>

namespace mixcon {

class Environment {
public:
  Environment(int &argc, char **&argv);
  ~Environment();
  Environment(const Environment &) = delete;
  Environment &operator=(const Environment &) = delete;
  /// "Kokkos <version>, <backend> with <n> threads" for logs and benchmark contexts.
  static std::string describe();

private:
  bool ownsMpi_ = false;
  bool ownsKokkos_ = false;
};

} // namespace mixcon
