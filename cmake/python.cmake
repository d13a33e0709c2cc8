# The Python package (docs/python.md): the extension module shaderfit._shaderfit, built with
# nanobind, and the package's pure-Python files beside it in ${CMAKE_BINARY_DIR}/python, so that
# ctest runs the pytest suite against this build (PYTHONPATH=build/<preset>/python).
#
# SHADERFIT_PYTHON: AUTO (default) builds the module when Python's headers and nanobind are found
# (scripts/install-deps installs nanobind with pip), ON requires them, OFF never builds it.
# `pip install .` (pyproject.toml, scikit-build-core) builds only this target, with ON.
set(SHADERFIT_PYTHON AUTO CACHE STRING "Python module: AUTO (when nanobind is found), ON or OFF")
set_property(CACHE SHADERFIT_PYTHON PROPERTY STRINGS AUTO ON OFF)

set(SHADERFIT_HAVE_PYTHON OFF)
if(NOT SHADERFIT_PYTHON STREQUAL "OFF")
  if(SHADERFIT_PYTHON STREQUAL "ON")
    set(_sf_required REQUIRED)
  endif()
  # The python3 on PATH, the one scripts/install-deps installs nanobind and the test packages
  # into (pip install . sets Python_EXECUTABLE itself).
  if(NOT DEFINED Python_EXECUTABLE)
    find_program(SHADERFIT_PYTHON3 python3)
    if(SHADERFIT_PYTHON3)
      set(Python_EXECUTABLE "${SHADERFIT_PYTHON3}")
    endif()
  endif()
  find_package(Python 3.9 COMPONENTS Interpreter Development.Module ${_sf_required})
  if(Python_FOUND AND NOT nanobind_DIR)
    execute_process(COMMAND "${Python_EXECUTABLE}" -m nanobind --cmake_dir
                    OUTPUT_VARIABLE _sf_nanobind_dir OUTPUT_STRIP_TRAILING_WHITESPACE
                    ERROR_QUIET RESULT_VARIABLE _sf_nanobind_rc)
    if(_sf_nanobind_rc EQUAL 0)
      set(nanobind_ROOT "${_sf_nanobind_dir}")
    endif()
  endif()
  if(Python_FOUND)
    find_package(nanobind CONFIG ${_sf_required} QUIET)
  endif()
  if(Python_FOUND AND nanobind_FOUND)
    set(SHADERFIT_HAVE_PYTHON ON)
  else()
    message(STATUS "shaderfit: no Python module (needs Python's headers and nanobind: "
                   "scripts/install-deps)")
  endif()
endif()

if(SHADERFIT_HAVE_PYTHON)
  nanobind_add_module(_shaderfit NB_STATIC python/src/module.cpp)
  target_include_directories(_shaderfit PRIVATE python/src)
  target_link_libraries(_shaderfit PRIVATE shaderfit nlohmann_json::nlohmann_json)
  set(_sf_package "${CMAKE_BINARY_DIR}/python/shaderfit")
  set_target_properties(_shaderfit PROPERTIES LIBRARY_OUTPUT_DIRECTORY "${_sf_package}")
  # The package's .py files beside the module, refreshed at every build.
  file(GLOB _sf_py CONFIGURE_DEPENDS python/shaderfit/*.py)
  add_custom_target(shaderfit_python_files ALL
    COMMAND ${CMAKE_COMMAND} -E make_directory "${_sf_package}"
    COMMAND ${CMAKE_COMMAND} -E copy_if_different ${_sf_py} "${_sf_package}"
    DEPENDS ${_sf_py} COMMENT "shaderfit Python files")
  add_dependencies(_shaderfit shaderfit_python_files)
  if(SKBUILD)
    install(TARGETS _shaderfit LIBRARY DESTINATION shaderfit)
  endif()
  if(SHADERFIT_BUILD_TESTS)
    add_test(NAME python COMMAND "${Python_EXECUTABLE}" -m pytest -q -p no:cacheprovider
             "${PROJECT_SOURCE_DIR}/python/tests")
    set_tests_properties(python PROPERTIES TIMEOUT 900
      ENVIRONMENT "PYTHONPATH=${CMAKE_BINARY_DIR}/python;SHADERFIT_CLI=$<TARGET_FILE:shaderfit_cli>"
      SKIP_RETURN_CODE 77)
  endif()
endif()
