# Finds mixcon's dependencies for the build tree (the installed config repeats the public ones).
find_package(Kokkos REQUIRED)
include(MixconKokkosFixups)
find_package(MPI REQUIRED COMPONENTS CXX)
find_package(HYPRE REQUIRED)
# The installed mixconConfig.cmake finds this same hypre: its CMake package directory, or for a
# header-search hypre (Debian's libhypre-dev) its header directory and library.
if(HYPRE_DIR AND EXISTS "${HYPRE_DIR}/HYPREConfig.cmake")
  set(MIXCON_HYPRE_DIR "${HYPRE_DIR}")
  set(MIXCON_HYPRE_INCLUDE_DIR "")
  set(MIXCON_HYPRE_LIBRARY "")
else()
  set(MIXCON_HYPRE_DIR "")
  set(MIXCON_HYPRE_INCLUDE_DIR "${HYPRE_INCLUDE_DIR}")
  set(MIXCON_HYPRE_LIBRARY "${HYPRE_LIBRARY}")
endif()
message(STATUS "mixcon: hypre ${MIXCON_HYPRE_DIR}${MIXCON_HYPRE_LIBRARY}")
# SuiteSparse's CHOLMOD and UMFPACK: the direct solver, the coarse space's factorization
# (solver/SparseDirect.hpp); private to the library.
find_package(SuiteSparseDirect REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
# Eigen is host-only in mixcon (ctest repo.eigen_host_only): without this, nvcc (the CUDA build
# compiles every source as CUDA) would annotate Eigen __host__ __device__ and warn about it.
set_property(TARGET Eigen3::Eigen APPEND PROPERTY INTERFACE_COMPILE_DEFINITIONS EIGEN_NO_CUDA)
find_package(HDF5 REQUIRED COMPONENTS C)
if(NOT TARGET hdf5::hdf5)
  add_library(hdf5::hdf5 INTERFACE IMPORTED)
  target_include_directories(hdf5::hdf5 INTERFACE ${HDF5_C_INCLUDE_DIRS} ${HDF5_INCLUDE_DIRS})
  target_link_libraries(hdf5::hdf5 INTERFACE ${HDF5_C_LIBRARIES} ${HDF5_LIBRARIES})
  target_compile_definitions(hdf5::hdf5 INTERFACE ${HDF5_DEFINITIONS})
endif()
find_package(yaml-cpp REQUIRED)
if(NOT TARGET yaml-cpp AND TARGET yaml-cpp::yaml-cpp)
  add_library(yaml-cpp ALIAS yaml-cpp::yaml-cpp)
endif()
