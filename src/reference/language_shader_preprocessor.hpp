// The C preprocessor of a GLSL or HLSL source, as the shader front end reads it (internal to
// src/reference/): conditional groups (#if, #ifdef, #ifndef, #elif, #else, #endif; a group not
// taken is skipped unread), function-like macros expanded where they are called, #undef, #error,
// and the lines ignored (#version, #extension, #pragma). Object-like macros stay names: the file
// makes each a file-scope constant (language_shader.hpp), in order with its declarations, so the
// preprocessor hands their #define lines over; #if expands them in place.
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "language_internal.hpp"

namespace shaderfit::reference_detail {

// An object-like macro's definition, or its end, where it stands among the source's tokens.
struct MacroLine {
  // The index, in PreprocessedSource::tokens, of the first token after the line.
  std::size_t position = 0;
  Token name;              // the macro's name in its #define
  bool undefine = false;   // the definition at `name` ends (#undef, or a function-like #define)
  bool has_value = false;  // #define NAME value, not #define NAME
  // The value's tokens, function-like macros expanded, ending with an End token.
  std::span<const Token> value;
  std::optional<Error> error;  // why the value cannot be read: raised where the macro is used
};

struct PreprocessedSource {
  std::vector<Token> tokens;  // ending with End; no Directive tokens
  std::vector<MacroLine> macro_lines;
  std::deque<std::vector<Token>> storage;  // what MacroLine::value spans
};

// Throws Error at the directive or token for a directive outside the subset (#include among
// them), an unbalanced conditional, an #if expression that is not an integer one, #error, a
// macro called with the wrong number of arguments, and a macro whose definition cannot be read,
// where it is used. A UTF-8 byte-order mark that starts the source is skipped. Token texts view
// `source`, which must outlive them; `path` names the source in errors.
PreprocessedSource preprocess(std::string_view source, const std::string& path);

}  // namespace shaderfit::reference_detail
