# shaderfit-mpi: searches across MPI ranks (docs/distributed.md), with Open MPI from Debian
# (scripts/install-deps). SHADERFIT_MPI: AUTO (default) builds it when MPI is found, ON requires
# MPI, OFF never builds it. The library does not link MPI: the program implements the library's
# Communicator (shaderfit/search/communicator.hpp) over it.
set(SHADERFIT_MPI AUTO CACHE STRING "shaderfit-mpi: AUTO (when MPI is found), ON or OFF")
set_property(CACHE SHADERFIT_MPI PROPERTY STRINGS AUTO ON OFF)

set(SHADERFIT_HAVE_MPI OFF)
if(NOT SHADERFIT_MPI STREQUAL "OFF")
  if(SHADERFIT_MPI STREQUAL "ON")
    find_package(MPI REQUIRED COMPONENTS CXX)
  else()
    find_package(MPI QUIET COMPONENTS CXX)
  endif()
  if(MPI_CXX_FOUND)
    set(SHADERFIT_HAVE_MPI ON)
  else()
    message(STATUS "shaderfit: no shaderfit-mpi (needs MPI: scripts/install-deps)")
  endif()
endif()

if(SHADERFIT_HAVE_MPI)
  add_executable(shaderfit_mpi apps/shaderfit-mpi/main.cpp apps/shaderfit-mpi/mpi_communicator.cpp)
  set_target_properties(shaderfit_mpi PROPERTIES OUTPUT_NAME shaderfit-mpi
                        RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR})
  target_link_libraries(shaderfit_mpi PRIVATE shaderfit_cli_lib MPI::MPI_CXX)
  shaderfit_warnings(shaderfit_mpi)
  if(SHADERFIT_BUILD_TESTS)
    # Runs mpirun itself (each test skips with "skipped: mpirun not found" without it).
    add_executable(shaderfit_mpi_tests apps/shaderfit-mpi/mpi_search_test.cpp
                                      apps/shaderfit-mpi/mpi_batch_test.cpp)
    target_link_libraries(shaderfit_mpi_tests PRIVATE shaderfit GTest::gtest_main
                          nlohmann_json::nlohmann_json)
    target_compile_definitions(shaderfit_mpi_tests PRIVATE
      SHADERFIT_CLI_PATH="$<TARGET_FILE:shaderfit_cli>"
      SHADERFIT_MPI_PATH="$<TARGET_FILE:shaderfit_mpi>"
      SHADERFIT_MPIEXEC="${MPIEXEC_EXECUTABLE}")
    add_dependencies(shaderfit_mpi_tests shaderfit_mpi shaderfit_cli)
    shaderfit_warnings(shaderfit_mpi_tests)
    gtest_discover_tests(shaderfit_mpi_tests DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 300)
  endif()
endif()
