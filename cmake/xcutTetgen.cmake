# TetGen's library (Debian: libtet1.5-dev) as the imported target xcut::tetgen. Used by the build
# and, installed beside xcutConfig.cmake, by find_package(xcut).
if(NOT TARGET xcut::tetgen)
  find_library(TETGEN_LIBRARY NAMES tet REQUIRED)
  find_path(TETGEN_INCLUDE_DIR tetgen.h REQUIRED)
  add_library(xcut::tetgen UNKNOWN IMPORTED)
  set_target_properties(xcut::tetgen PROPERTIES
    IMPORTED_LOCATION "${TETGEN_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${TETGEN_INCLUDE_DIR}"
    INTERFACE_COMPILE_DEFINITIONS TETLIBRARY)
endif()
