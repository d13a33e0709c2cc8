// Internal: the one definition of "this CSV cell is a number", shared by the CSV reader and
// Dataset::numeric, and the matching writer; counts written for people.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace shaderfit::data_detail {

enum class NumberParse {
  kNumber,      // a finite number, the whole cell
  kNotNumber,   // anything else that is not one of the cases below (text, empty, "1.5x")
  kNaN,         // nan, NaN, nan(123), -nan
  kInfinite,    // inf, -inf, infinity (any case)
  kOutOfRange,  // a number too large or too small for a double, such as 1e999
};

// Parses a whole cell with std::from_chars (locale-independent, general format). A single
// leading '+' is accepted as well, as spreadsheets write it.
NumberParse parse_number(std::string_view cell, double& out);

// Shortest text that reads back as exactly `value` (std::to_chars). `value` must be finite.
std::string format_number(double value);

// A count for people, its digits grouped by commas: 10001 -> "10,001".
std::string format_count(std::size_t n);

}  // namespace shaderfit::data_detail
