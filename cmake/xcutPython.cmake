# The Python package (import xcut; docs/python.md): the compiled module _xcut (pybind11, Debian's
# pybind11-dev and python3-dev) and the pure-Python package around it (tools/python/xcut: the
# Simulation class, the Gymnasium-style environments, the dask sweep). Built into
# <build>/python/xcut, so PYTHONPATH=<build>/python imports it from the build tree; installed by
# cmake --install to <prefix>/${XCUT_PYTHON_INSTALL_DIR}. On by default when pybind11, the Python
# headers and numpy are found.
#
# The interpreter is Debian's /usr/bin/python3 unless Python3_EXECUTABLE says otherwise: its
# numpy, pytest and dask come from Debian's packages (tools/install-deps.sh), where a Python earlier
# on PATH (a pyenv or a venv) may have none of them.
# Stops the configuration unless `python` imports every module of `modules` ("a, b"); `need` says
# what needs them and which packages hold them.
function(xcut_require_python_modules python modules need)
  execute_process(COMMAND ${python} -c "import ${modules}" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${need} (${python} cannot import ${modules}; tools/install-deps.sh installs them)")
  endif()
endfunction()

if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the xcut module is built for")
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module QUIET)
find_package(pybind11 2.6 CONFIG QUIET)
set(xcut_python_found OFF)
if(Python3_Development.Module_FOUND AND pybind11_FOUND)
  execute_process(COMMAND ${Python3_EXECUTABLE} -c "import numpy" RESULT_VARIABLE xcut_numpy_rc OUTPUT_QUIET ERROR_QUIET)
  if(xcut_numpy_rc EQUAL 0)
    set(xcut_python_found ON)
  endif()
endif()
option(XCUT_PYTHON "Build the Python module (import xcut)" ${xcut_python_found})
if(NOT XCUT_PYTHON)
  return()
endif()
if(NOT xcut_python_found)
  message(FATAL_ERROR "XCUT_PYTHON needs pybind11-dev, python3-dev and python3-numpy for ${Python3_EXECUTABLE} "
    "(tools/install-deps.sh)")
endif()

# The module is a shared object: the core it links is compiled position-independent.
set_target_properties(xcut_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
set(XCUT_PYTHON_DIR ${CMAKE_BINARY_DIR}/python)
pybind11_add_module(_xcut MODULE NO_EXTRAS ${CMAKE_SOURCE_DIR}/tools/python/module.cpp
  ${CMAKE_SOURCE_DIR}/tools/python/py_simulation.cpp ${CMAKE_SOURCE_DIR}/tools/xcut_run_summary.cpp)
target_compile_options(_xcut PRIVATE ${XCUT_WARNINGS})
target_link_libraries(_xcut PRIVATE xcut_core)
set_target_properties(_xcut PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${XCUT_PYTHON_DIR}/xcut)

# The package's Python files beside the module (copied again whenever one changes).
file(GLOB_RECURSE xcut_python_files RELATIVE ${CMAKE_SOURCE_DIR}/tools/python/xcut CONFIGURE_DEPENDS
  ${CMAKE_SOURCE_DIR}/tools/python/xcut/*.py ${CMAKE_SOURCE_DIR}/tools/python/xcut/*.pyi
  ${CMAKE_SOURCE_DIR}/tools/python/xcut/py.typed)
foreach(f ${xcut_python_files})
  configure_file(${CMAKE_SOURCE_DIR}/tools/python/xcut/${f} ${XCUT_PYTHON_DIR}/xcut/${f} COPYONLY)
endforeach()

# Debian's Python looks in <prefix>/lib/python3.X/dist-packages (/usr/local, the default prefix);
# another Python in site-packages.
execute_process(COMMAND ${Python3_EXECUTABLE} -c "import sys; print('dist-packages' if any(p.endswith('dist-packages') for p in sys.path) else 'site-packages')"
  OUTPUT_VARIABLE xcut_python_packages OUTPUT_STRIP_TRAILING_WHITESPACE)
set(XCUT_PYTHON_INSTALL_DIR "lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/${xcut_python_packages}"
  CACHE STRING "Where cmake --install puts the xcut package, under the prefix")
install(TARGETS _xcut LIBRARY DESTINATION ${XCUT_PYTHON_INSTALL_DIR}/xcut)
install(DIRECTORY ${CMAKE_SOURCE_DIR}/tools/python/xcut/ DESTINATION ${XCUT_PYTHON_INSTALL_DIR}/xcut
  FILES_MATCHING PATTERN "*.py" PATTERN "*.pyi" PATTERN "py.typed" PATTERN "__pycache__" EXCLUDE)
