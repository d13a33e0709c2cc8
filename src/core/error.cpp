#include "shaderfit/core/error.hpp"

namespace shaderfit {

std::string SourceLocation::to_string() const {
  std::string s = source;
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (column > 0) s += ":" + std::to_string(column);
  }
  return s;
}

namespace {
std::string with_location(const std::string& message, const SourceLocation& where) {
  std::string prefix = where.to_string();
  return prefix.empty() ? message : prefix + ": " + message;
}
}  // namespace

Error::Error(const std::string& message, SourceLocation where)
    : std::runtime_error(with_location(message, where)), where_(std::move(where)), message_(message) {}

}  // namespace shaderfit
