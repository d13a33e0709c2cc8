// Library errors name the fields of the library's structs ("FitSetup::grid"); the commands show
// the flags that set them ("--grid"). A command lists its pairs and runs the library under
// with_flags, which rewrites a shaderfit::Error's location and message from field names to flag
// names, so what the user reads is in the command line's words.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "shaderfit/core/error.hpp"

namespace shaderfit::cli {

struct FieldFlag {
  std::string_view field;  // "FitSetup::grid"
  std::string_view flag;   // "--grid"
};

// `text` with every field of `pairs` replaced by its flag.
inline std::string fields_to_flags(std::string text, std::span<const FieldFlag> pairs) {
  for (const FieldFlag& p : pairs)
    for (std::size_t at = text.find(p.field); at != std::string::npos;
         at = text.find(p.field, at + p.flag.size()))
      text.replace(at, p.field.size(), p.flag);
  return text;
}

// Runs `f`, translating any shaderfit::Error it throws.
template <typename F>
decltype(auto) with_flags(std::span<const FieldFlag> pairs, F&& f) {
  try {
    return f();
  } catch (const Error& e) {
    SourceLocation where = e.where();
    where.source = fields_to_flags(where.source, pairs);
    throw Error(fields_to_flags(e.message(), pairs), where);
  }
}

}  // namespace shaderfit::cli
