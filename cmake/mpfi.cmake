# MPFI over MPFR over GMP: the interval arithmetic of certified error bounds (src/verify/certify.cpp,
# docs/reference.md "Certification"). Debian ships no CMake or pkg-config files for MPFI, so the
# headers and libraries are found directly; `shaderfit::mpfi` carries all three.
find_path(MPFI_INCLUDE_DIR mpfi.h)
find_path(MPFR_INCLUDE_DIR mpfr.h)
find_path(GMP_INCLUDE_DIR gmp.h)
find_library(MPFI_LIBRARY mpfi)
find_library(MPFR_LIBRARY mpfr)
find_library(GMP_LIBRARY gmp)
foreach(var MPFI_INCLUDE_DIR MPFR_INCLUDE_DIR GMP_INCLUDE_DIR MPFI_LIBRARY MPFR_LIBRARY GMP_LIBRARY)
  if(NOT ${var})
    message(FATAL_ERROR "${var} not found: install libmpfi-dev libmpfr-dev libgmp-dev "
                        "(scripts/install-deps)")
  endif()
endforeach()
add_library(shaderfit_mpfi INTERFACE IMPORTED)
target_include_directories(shaderfit_mpfi INTERFACE ${MPFI_INCLUDE_DIR} ${MPFR_INCLUDE_DIR}
                           ${GMP_INCLUDE_DIR})
target_link_libraries(shaderfit_mpfi INTERFACE ${MPFI_LIBRARY} ${MPFR_LIBRARY} ${GMP_LIBRARY})
add_library(shaderfit::mpfi ALIAS shaderfit_mpfi)
