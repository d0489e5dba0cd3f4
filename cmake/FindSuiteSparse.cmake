# Finds CHOLMOD from Debian's libsuitesparse-dev (5.x ships no CMake config).
# Defines SuiteSparse::cholmod.
find_path(SuiteSparse_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(SuiteSparse_CHOLMOD_LIBRARY cholmod)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse
  REQUIRED_VARS SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_INCLUDE_DIR)
if(SuiteSparse_FOUND AND NOT TARGET SuiteSparse::cholmod)
  add_library(SuiteSparse::cholmod UNKNOWN IMPORTED)
  set_target_properties(SuiteSparse::cholmod PROPERTIES
    IMPORTED_LOCATION ${SuiteSparse_CHOLMOD_LIBRARY}
    INTERFACE_INCLUDE_DIRECTORIES ${SuiteSparse_INCLUDE_DIR})
endif()
