# `cmake --build <dir> --target lint`: clang-format check over the sources, then clang-tidy with
# the compile database. `format` rewrites the sources in place.
find_program(CLANG_FORMAT NAMES clang-format clang-format-14)
find_program(CLANG_TIDY NAMES clang-tidy clang-tidy-14)
file(GLOB_RECURSE SHADERFIT_LINT_FILES CONFIGURE_DEPENDS
  ${PROJECT_SOURCE_DIR}/include/*.hpp ${PROJECT_SOURCE_DIR}/src/*.cpp ${PROJECT_SOURCE_DIR}/src/*.hpp
  ${PROJECT_SOURCE_DIR}/apps/*.cpp ${PROJECT_SOURCE_DIR}/apps/*.hpp ${PROJECT_SOURCE_DIR}/bench/*.cpp
  ${PROJECT_SOURCE_DIR}/fuzz/*.cpp ${PROJECT_SOURCE_DIR}/fuzz/*.hpp
  ${PROJECT_SOURCE_DIR}/python/src/*.cpp ${PROJECT_SOURCE_DIR}/python/src/*.hpp)
if(CLANG_FORMAT)
  add_custom_target(format-check
    COMMAND ${CLANG_FORMAT} --dry-run --Werror ${SHADERFIT_LINT_FILES}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} COMMENT "clang-format check")
  add_custom_target(format
    COMMAND ${CLANG_FORMAT} -i ${SHADERFIT_LINT_FILES}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} COMMENT "clang-format in place")
endif()
if(CLANG_TIDY)
  set(SHADERFIT_TIDY_FILES ${SHADERFIT_LINT_FILES})
  list(FILTER SHADERFIT_TIDY_FILES INCLUDE REGEX "\\.cpp$")
  add_custom_target(tidy
    COMMAND ${CLANG_TIDY} -p ${CMAKE_BINARY_DIR} --quiet ${SHADERFIT_TIDY_FILES}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} COMMENT "clang-tidy")
endif()
add_custom_target(lint)
if(TARGET format-check)
  add_dependencies(lint format-check)
endif()
if(TARGET tidy)
  add_dependencies(lint tidy)
endif()
