# The Python module cmc._core (pybind11) and the package around it (docs/user-guide/python.md).
#
# Built against /usr/bin/python3 (Debian's; a pyenv `python3` first on PATH may lack
# numpy). The package is assembled in BUILD/python/cmc/: the compiled _core beside links to
# python/cmc/'s files, so that
#   PYTHONPATH=BUILD/python /usr/bin/python3 -c "import cmc"
# imports both. Nothing is written into the source tree. `pip install .` (setup.py) and
# `cmake --install` (cmake/install.cmake) install the same package.
set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "the Python the module is built for")
if(CMC_SANITIZE OR CMC_FUZZ OR CMC_MPI OR CMC_CUDA)
  # A sanitized extension needs the sanitizer runtime preloaded into Python; the MPI and
  # CUDA builds run one process per rank and one GPU: the module is a serial CPU build's.
  message(STATUS "cmc: the Python module is built only in the plain build (not with CMC_SANITIZE, CMC_FUZZ, "
                 "CMC_MPI or CMC_CUDA)")
  return()
endif()
find_package(Python 3 QUIET COMPONENTS Interpreter Development.Module)
find_package(pybind11 CONFIG QUIET)
if(NOT Python_FOUND OR NOT pybind11_FOUND)
  message(STATUS "cmc: the Python module is not built: it needs ${Python_EXECUTABLE}'s headers and pybind11 "
                 "(Debian packages python3-dev, pybind11-dev, python3-pybind11: scripts/setup.sh installs them)")
  return()
endif()
message(STATUS "cmc: Python module for ${Python_EXECUTABLE} (${Python_VERSION}), pybind11 ${pybind11_VERSION}")

# The library goes into a shared object.
set_target_properties(cmclib PROPERTIES POSITION_INDEPENDENT_CODE ON)

set(CMC_PYTHON_DIR ${CMAKE_BINARY_DIR}/python)
file(GLOB CMC_PYTHON_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/python/src/*.cpp)
pybind11_add_module(cmc_python MODULE ${CMC_PYTHON_SOURCES})
set_target_properties(cmc_python PROPERTIES OUTPUT_NAME _core LIBRARY_OUTPUT_DIRECTORY ${CMC_PYTHON_DIR}/cmc)
target_link_libraries(cmc_python PRIVATE cmclib)
target_compile_options(cmc_python PRIVATE -Wall -Wextra)

# The pure-Python files, linked beside it (made at configure time; a new file under
# python/cmc/ re-runs the configuration through CONFIGURE_DEPENDS): an edit to python/cmc/
# is seen at once by everything that imports the build's package (the scripts, reports and
# tests), with no build in between.
file(GLOB_RECURSE CMC_PYTHON_FILES CONFIGURE_DEPENDS RELATIVE ${CMAKE_SOURCE_DIR}/python/cmc
     ${CMAKE_SOURCE_DIR}/python/cmc/*.py)
foreach(f ${CMC_PYTHON_FILES})
  get_filename_component(dir ${CMC_PYTHON_DIR}/cmc/${f} DIRECTORY)
  file(MAKE_DIRECTORY ${dir})
  file(CREATE_LINK ${CMAKE_SOURCE_DIR}/python/cmc/${f} ${CMC_PYTHON_DIR}/cmc/${f} SYMBOLIC)
endforeach()

# The module's tests (pytest, tests/python/), one ctest test per file.
if(CMC_BUILD_TESTS)
  file(GLOB CMC_PYTHON_TESTS CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/tests/python/test_*.py)
  foreach(t ${CMC_PYTHON_TESTS})
    get_filename_component(name ${t} NAME_WE)
    add_test(NAME python.${name}
             COMMAND ${Python_EXECUTABLE} -m pytest -q -p no:cacheprovider ${t}
             WORKING_DIRECTORY ${CMAKE_BINARY_DIR})
    set_tests_properties(python.${name} PROPERTIES LABELS "quick;python"
                         ENVIRONMENT "PYTHONPATH=${CMC_PYTHON_DIR};CMC_EXE=$<TARGET_FILE:cmc>;CMC_SOURCE=${CMAKE_SOURCE_DIR}")
  endforeach()
  # The documented example (docs/user-guide/python.md) runs as written: the challenge at 512².
  add_test(NAME python.example_challenge
           COMMAND ${Python_EXECUTABLE} ${CMAKE_SOURCE_DIR}/docs/examples/python_challenge.py
                   ${CMAKE_BINARY_DIR}/python-example/challenge_512.png)
  set_tests_properties(python.example_challenge PROPERTIES LABELS "quick;python"
                       ENVIRONMENT "PYTHONPATH=${CMC_PYTHON_DIR};MPLBACKEND=Agg")
  file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/python-example)
endif()
