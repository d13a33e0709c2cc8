// Reading a search front (JSON) for code generation.
//
//   { "inputs": ["r0", "cos_theta"],            // optional: the argument order
//     "front": [ { "formula": "r0 + (1 - r0) * (1 - cos_theta)^5" },
//                { "formula": "r0 + (1 - r0 - s*cos_theta) * (1 - cos_theta)^4",
//                  "parameters": {"s": 0.25} },  // or ["s"]: a run-time argument
//                ... ] }
// Parameters given with values are baked into the function as named constants; parameters given
// by name only become arguments after the inputs.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

struct FrontFormula {
  std::string formula;     // as written in the file
  Expression expression;   // parsed, with parameter values when the file gave them
  bool parameters_have_values = false;
};

struct FrontReadOptions {
  std::vector<std::string> inputs;      // overrides the file's "inputs" when not empty
  std::vector<std::string> parameters;  // names that are parameters in every formula
};

// Throws shaderfit::Error located at the file (and member) for: a file that cannot be read, JSON
// that does not parse, no "front" list, a member without a "formula" string, a formula that does
// not parse, or "parameters" that is neither a list of names nor an object of numbers.
std::vector<FrontFormula> read_front(const std::string& path, const FrontReadOptions& options = {});

// The same for JSON text already in memory; `source` names it in error locations.
std::vector<FrontFormula> parse_front(std::string_view json, const std::string& source,
                                      const FrontReadOptions& options = {});

}  // namespace shaderfit
