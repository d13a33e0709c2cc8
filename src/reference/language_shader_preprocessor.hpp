// The C preprocessor of a GLSL or HLSL source, as the shader front end reads it (internal to
// src/reference/): conditional groups (#if, #ifdef, #ifndef, #elif, #else, #endif; a group not
// taken is skipped unread), macros expanded where they are used (object-like and function-like,
// as C does: `#define real float` and `#define X2 (x * x)` are text), #undef, #error, simple
// typedefs as such macros, and the lines ignored (#version, #extension, #pragma).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "language_internal.hpp"

namespace shaderfit::reference_detail {

struct PreprocessedSource {
  std::vector<Token> tokens;  // ending with End; no Directive tokens
};

// Throws Error at the directive or token for a directive outside the subset (#include among
// them), an unbalanced conditional, an #if expression that is not an integer one, #error, a
// macro called with the wrong number of arguments, and a macro whose definition cannot be read,
// where it is used. A UTF-8 byte-order mark that starts the source is skipped. Token texts view
// `source`, which must outlive them; `path` names the source in errors.
PreprocessedSource preprocess(std::string_view source, const std::string& path);

}  // namespace shaderfit::reference_detail
