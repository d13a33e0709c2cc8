# Warnings every shaderfit target compiles with.
function(shaderfit_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wno-missing-field-initializers>
    $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)  # GCC 12 false positives in std::string concatenation
endfunction()
