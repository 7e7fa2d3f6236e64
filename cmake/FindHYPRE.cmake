# Finds hypre and defines the imported target HYPRE::HYPRE.
# Prefers hypre's own CMake package (HYPREConfig.cmake); otherwise searches for HYPRE.h and libHYPRE
# (Debian: /usr/include/hypre, libHYPRE.so). Hints: HYPRE_ROOT, HYPRE_DIR (cmake/build-hypre.sh's
# threaded hypre is found through its HYPREConfig.cmake: -DHYPRE_ROOT=<its prefix>).
if(TARGET HYPRE::HYPRE)
  set(HYPRE_FOUND TRUE)
  return()
endif()
# Given HYPRE_INCLUDE_DIR and HYPRE_LIBRARY (the installed mixconConfig.cmake pins a header-search
# hypre such as Debian's this way), no CMake package is looked for.
if(NOT (HYPRE_INCLUDE_DIR AND HYPRE_LIBRARY))
  find_package(HYPRE CONFIG QUIET)
  if(HYPRE_FOUND AND TARGET HYPRE::HYPRE)
    return()
  endif()
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
