# CHOLMOD (SuiteSparse; Debian: libsuitesparse-dev) as the imported target xcut::cholmod, for the
# Cholesky linear solver (systems/solver/linear_solver.h, through Eigen's CholmodSupport). Debian 12's
# SuiteSparse 5.12 ships no CMake config, so the libraries and headers are found directly. Used by
# the build and, installed beside xcutConfig.cmake, by find_package(xcut).
if(NOT TARGET xcut::cholmod)
  find_library(CHOLMOD_LIBRARY NAMES cholmod REQUIRED)
  # SuiteSparse_config: the allocation functions CHOLMOD calls (systems/solver/cholmod_pages.h).
  find_library(SUITESPARSE_CONFIG_LIBRARY NAMES suitesparseconfig REQUIRED)
  find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
  add_library(xcut::cholmod UNKNOWN IMPORTED)
  set_target_properties(xcut::cholmod PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${SUITESPARSE_CONFIG_LIBRARY}")
endif()
