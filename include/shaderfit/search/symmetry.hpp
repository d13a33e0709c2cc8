// Symmetry of the data in one input, found on the rows, so that a search can fit the half
// x >= 0 and add the reflection (docs/search.md, "Symmetric data").
//
//   std::optional<DataSymmetry> s = detect_symmetry(problem);    // e.g. odd in x
//   SearchProblem half = symmetric_half(problem, *s);             // rows with x >= 0
//   Expression full = reflect_expression(g, *s, problem.input_names);  // copysign(g(|x|), x)
//   Expression plain = unreflected_expression(g, *s);  // g as it is on every row
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/expr/expression.hpp"

namespace shaderfit {

struct SearchOptions;
struct SearchProblem;

// g is fitted on the half x >= 0 to t: y, or -y for odd data with s = DataSymmetry::sign = -1;
// G = g with x replaced by |x|. The formula for every row:
enum class SymmetryKind {
  Even,   // y(-x) = y(x):          G
  Odd,    // y(-x) = -y(x):         copysign(G, s x), or G * sign(x) where s = 0
  Point,  // y(-x) = 2 m - y(x):    m + copysign(G - m, x) (s = 1), m - copysign(m - G, x)
          //                        (s = -1), or m + (G - m) * sign(x) where s = 0
};
// "even", "odd", "point" (and back; nullopt for anything else).
std::string_view symmetry_kind_name(SymmetryKind kind);
std::optional<SymmetryKind> symmetry_kind_from_name(std::string_view name);

struct DataSymmetry {
  std::size_t input = 0;   // index into the problem's inputs
  std::string input_name;  // its name
  SymmetryKind kind = SymmetryKind::Even;
  double center = 0;  // m: Point only (0 otherwise)
  // Odd and Point: 1 when y - m >= 0 on the half, -1 when it is <= 0 (within the tolerance), so
  // that copysign carries the sign of s (y - m) >= 0 (|t - g| <= |t + g| wherever t >= 0 > g, so
  // copysign never adds error); 0 when it changes sign (the slower form with sign). Even: 1.
  int sign = 1;

  friend bool operator==(const DataSymmetry&, const DataSymmetry&) = default;
};

// Relative to the target's range (max - min): float64 references of an exactly symmetric
// function meet it; measured or float32 data generally do not, and are searched as they are.
inline constexpr double kSymmetryTolerance = 1e-9;

// The first input (in problem order) in which the data is symmetric, or nullopt. The data is
// symmetric in x when
//  - the rows come in mirrored pairs: for each row with x != 0 exactly one row with -x and every
//    other input equal (bit for bit), rows with x = 0 pairing with themselves, no two rows alike;
//  - at least 8 pairs have x != 0;
//  - paired rows have the same weight;
//  - the target satisfies, on every pair, within tolerance * (max - min of the target):
//    y(-x) = y(x) (even, tried first), y(-x) = -y(x) (odd) or y(-x) + y(x) = 2 m (point; m is
//    the mean target of the rows with x = 0, or without such rows the mean of the pairs'
//    midpoints).
// A constant target is not taken as symmetric. `problem` must be valid (SearchProblem::validate).
std::optional<DataSymmetry> detect_symmetry(const SearchProblem& problem,
                                            double tolerance = kSymmetryTolerance);

// The symmetry a search with `options` folds the problem by: none when options.symmetry is off;
// otherwise detect_symmetry's, except a point symmetry under the rel, max_rel and log losses (the
// half's target y - m would change what they measure).
std::optional<DataSymmetry> search_symmetry(const SearchOptions& options,
                                            const SearchProblem& problem);

// The rows with x >= 0 (x = -0 included), in their order, with the target t (above).
SearchProblem symmetric_half(const SearchProblem& problem, const DataSymmetry& symmetry);

// g (over `input_names`, fitted on the half) as the formula for every row (above), with |x|^2k
// written x^2k. Variables are `input_names`. Throws Error located at "reflect_expression" when g
// names a variable that is not among them.
Expression reflect_expression(const Expression& g, const DataSymmetry& symmetry,
                              const std::vector<std::string>& input_names);

// g as it is on every row: g, or -g for odd data with s = -1.
Expression unreflected_expression(const Expression& g, const DataSymmetry& symmetry);

// For odd data, g = x * h, h * x or x / h (x the symmetric input as the whole operand) extended
// as x * h(|x|) (or x / h(|x|)), which is odd without a copysign (negated for s = -1); nullopt
// for other g and for even and point-symmetric data.
std::optional<Expression> factored_expression(const Expression& g, const DataSymmetry& symmetry,
                                              const std::vector<std::string>& input_names);

// "odd in x", "even in x", "point-symmetric in x about 1.5707963267948966".
std::string describe_symmetry(const DataSymmetry& symmetry);

}  // namespace shaderfit
