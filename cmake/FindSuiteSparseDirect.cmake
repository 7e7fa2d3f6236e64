# Finds the two SuiteSparse direct solvers mixcon uses, CHOLMOD (supernodal Cholesky) and UMFPACK
# (sparse LU), and defines the imported targets SuiteSparse::CHOLMOD and SuiteSparse::UMFPACK.
# Prefers SuiteSparse's own CMake packages (SuiteSparse 7 ships them); otherwise searches for the
# headers and libraries (Debian 12's libsuitesparse-dev 5.12: /usr/include/suitesparse).
# Hints: SuiteSparseDirect_ROOT or CMAKE_PREFIX_PATH, or CHOLMOD_DIR and UMFPACK_DIR for the
# CMake packages.
if(TARGET SuiteSparse::CHOLMOD AND TARGET SuiteSparse::UMFPACK)
  set(SuiteSparseDirect_FOUND TRUE)
  return()
endif()
find_package(CHOLMOD CONFIG QUIET)
find_package(UMFPACK CONFIG QUIET)
if(TARGET SuiteSparse::CHOLMOD AND TARGET SuiteSparse::UMFPACK)
  set(SuiteSparseDirect_FOUND TRUE)
  return()
endif()
find_path(SuiteSparse_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse include/suitesparse)
foreach(lib cholmod umfpack amd colamd camd ccolamd suitesparseconfig)
  string(TOUPPER ${lib} upper)
  find_library(SuiteSparse_${upper}_LIBRARY NAMES ${lib})
  mark_as_advanced(SuiteSparse_${upper}_LIBRARY)
endforeach()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparseDirect
  REQUIRED_VARS SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_UMFPACK_LIBRARY
                SuiteSparse_SUITESPARSECONFIG_LIBRARY SuiteSparse_INCLUDE_DIR)
if(SuiteSparseDirect_FOUND)
  if(NOT TARGET SuiteSparse::SuiteSparseConfig)
    add_library(SuiteSparse::SuiteSparseConfig UNKNOWN IMPORTED)
    set_target_properties(SuiteSparse::SuiteSparseConfig PROPERTIES
      IMPORTED_LOCATION "${SuiteSparse_SUITESPARSECONFIG_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}")
  endif()
  # The orderings CHOLMOD and UMFPACK call (a static SuiteSparse needs them on the link line).
  set(_suitesparse_orderings)
  foreach(lib AMD COLAMD CAMD CCOLAMD)
    if(SuiteSparse_${lib}_LIBRARY)
      list(APPEND _suitesparse_orderings "${SuiteSparse_${lib}_LIBRARY}")
    endif()
  endforeach()
  foreach(lib CHOLMOD UMFPACK)
    if(NOT TARGET SuiteSparse::${lib})
      add_library(SuiteSparse::${lib} UNKNOWN IMPORTED)
      set_target_properties(SuiteSparse::${lib} PROPERTIES
        IMPORTED_LOCATION "${SuiteSparse_${lib}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}"
        INTERFACE_LINK_LIBRARIES "${_suitesparse_orderings};SuiteSparse::SuiteSparseConfig")
    endif()
  endforeach()
endif()
mark_as_advanced(SuiteSparse_INCLUDE_DIR)
