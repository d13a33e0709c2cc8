// Internal: float32 constants as text.
#pragma once

#include <charconv>
#include <cmath>
#include <string>

namespace shaderfit::cost_detail {

// The shortest decimal text that reads back to exactly `v` as a float32 ("0.5", "1", "1e-05",
// "0.693147182"); "nan", "inf", "-inf" for the special values.
inline std::string float_text(float v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  (void)ec;
  return std::string(buf, end);
}

}  // namespace shaderfit::cost_detail
