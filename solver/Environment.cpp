// Runtime start-up: MPI, Kokkos, hypre.
#include <solver/Environment.hpp>

#include <HYPRE_utilities.h>

#include <cstdlib>
#include <sstream>

namespace mixcon {

Environment::Environment(int &argc, char **&argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    ownsMpi_ = true;
  }
  if (!Kokkos::is_initialized()) {
    // Thread binding is the user's choice (OMP_PROC_BIND=spread OMP_PLACES=threads is usually
    // fastest on a dedicated node); left unset, leave threads unbound, which is safe on shared
    // machines, and spare users Kokkos' warning about it.
    setenv("OMP_PROC_BIND", "false", 0);
    Kokkos::initialize(argc, argv);
    ownsKokkos_ = true;
  }
  HYPRE_Init();
}

Environment::~Environment() {
  HYPRE_Finalize();
  if (ownsKokkos_)
    Kokkos::finalize();
  if (ownsMpi_)
    MPI_Finalize();
}

std::string Environment::describe() {
  std::ostringstream s;
  s << "Kokkos " << KOKKOS_VERSION / 10000 << "." << (KOKKOS_VERSION / 100) % 100 << "."
    << KOKKOS_VERSION % 100 << ", " << Kokkos::DefaultExecutionSpace::name() << " with "
    << Kokkos::DefaultExecutionSpace().concurrency() << " threads";
  return s.str();
}

} // namespace mixcon
