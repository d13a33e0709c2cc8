#include "data/number.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

namespace shaderfit::data_detail {

NumberParse parse_number(std::string_view cell, double& out) {
  if (cell.size() >= 2 && cell[0] == '+' && cell[1] != '+' && cell[1] != '-') cell.remove_prefix(1);
  if (cell.empty()) return NumberParse::kNotNumber;
  const char* end = cell.data() + cell.size();
  double value = 0.0;
  auto [ptr, ec] = std::from_chars(cell.data(), end, value, std::chars_format::general);
  if (ptr != end) return NumberParse::kNotNumber;
  if (ec == std::errc::result_out_of_range) return NumberParse::kOutOfRange;
  if (ec != std::errc()) return NumberParse::kNotNumber;
  if (std::isnan(value)) return NumberParse::kNaN;
  if (std::isinf(value)) return NumberParse::kInfinite;
  out = value;
  return NumberParse::kNumber;
}

std::string format_number(double value) {
  char buffer[32];  // the shortest round-trip form of a double needs at most 24 characters
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  (void)ec;  // cannot fail: the buffer is large enough
  return std::string(buffer, ptr);
}

std::string format_count(std::size_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

}  // namespace shaderfit::data_detail
