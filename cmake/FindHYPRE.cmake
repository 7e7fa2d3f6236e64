# Finds hypre and defines the imported target HYPRE::HYPRE.
# Prefers hypre's own CMake package (HYPREConfig.cmake); otherwise searches for HYPRE.h and libHYPRE
# (Debian: /usr/include/hypre, libHYPRE.so). Hints: HYPRE_ROOT, HYPRE_DIR.
if(TARGET HYPRE::HYPRE)
  set(HYPRE_FOUND TRUE)
  return()
endif()
find_package(HYPRE CONFIG QUIET)
if(HYPRE_FOUND AND TARGET HYPRE::HYPRE)
  return()
endif()
find_path(HYPRE_INCLUDE_DIR HYPRE.h PATH_SUFFIXES hypre include include/hypre)
find_library(HYPRE_LIBRARY NAMES HYPRE)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(HYPRE REQUIRED_VARS HYPRE_LIBRARY HYPRE_INCLUDE_DIR)
if(HYPRE_FOUND AND NOT TARGET HYPRE::HYPRE)
  add_library(HYPRE::HYPRE UNKNOWN IMPORTED)
  set_target_properties(HYPRE::HYPRE PROPERTIES IMPORTED_LOCATION "${HYPRE_LIBRARY}"
                                                INTERFACE_INCLUDE_DIRECTORIES "${HYPRE_INCLUDE_DIR}")
  if(TARGET MPI::MPI_CXX)
    set_property(TARGET HYPRE::HYPRE APPEND PROPERTY INTERFACE_LINK_LIBRARIES MPI::MPI_CXX)
  endif()
endif()
mark_as_advanced(HYPRE_INCLUDE_DIR HYPRE_LIBRARY)
