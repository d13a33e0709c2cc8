// JSON that reads back bit for bit (internal): doubles, checked integers and expressions node by
// node, for checkpoints and the exact form of a front member.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit::search_detail {

// A JSON value that does not hold what the exact format says.
struct BadExactJson : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Shortest text that reads back exactly; NaN and infinities as "nan", "inf", "-inf".
nlohmann::json exact_number(double v);
// Reads what exact_number writes; throws BadExactJson otherwise.
double exact_number_from(const nlohmann::json& j);

// An integer that fits T exactly. nlohmann's get<T> converts a fraction or an out-of-range value
// without a word (and a float beyond T's range is undefined behaviour), so a field that must be a
// count or an index is checked here.
template <class T>
T exact_integer_from(const nlohmann::json& j, std::string_view field) {
  if (j.is_number_unsigned()) {
    const auto v = j.get<std::uint64_t>();
    if (std::in_range<T>(v)) return static_cast<T>(v);
  } else if (j.is_number_integer()) {
    const auto v = j.get<std::int64_t>();
    if (std::in_range<T>(v)) return static_cast<T>(v);
  }
  throw BadExactJson("an integer in range was expected for '" + std::string(field) + "'");
}

// {"variables", "parameters", "values", "nodes": [[op, index, value], ...]}.
nlohmann::json exact_expression_json(const Expression& e);
// Throws BadExactJson (or a nlohmann exception) for anything but a well-formed expression.
Expression exact_expression_from(const nlohmann::json& j);

}  // namespace shaderfit::search_detail
