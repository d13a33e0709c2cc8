// Symmetry of the data in one input, found on mirrored pairs of rows or, for any sampling, by
// interpolation, so that a search can fit the half x >= 0 and add the reflection (docs/search.md,
// "Symmetric data").
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

// How a symmetry was found (detect_symmetry): on mirrored pairs of rows, or by comparing each
// row with an interpolant of the data on the other side of 0.
enum class SymmetryMethod { MirroredPairs, Interpolation };
// "mirrored_pairs", "interpolation" (and back; nullopt for anything else).
std::string_view symmetry_method_name(SymmetryMethod method);
std::optional<SymmetryMethod> symmetry_method_from_name(std::string_view name);

// What the decision rests on, relative to the target's range (max - min).
struct SymmetryEvidence {
  SymmetryMethod method = SymmetryMethod::MirroredPairs;
  std::size_t rows_compared = 0;  // rows with x != 0 compared with their mirror's value
  double max_residual = 0;        // the largest |mirror residual| (below) / range
  // Interpolation: the data's noise, a robust standard deviation of the leave-one-out
  // residuals of the same-side interpolant, / range; 0 for mirrored pairs.
  double noise = 0;

  friend bool operator==(const SymmetryEvidence&, const SymmetryEvidence&) = default;
};

struct DataSymmetry {
  std::size_t input = 0;   // index into the problem's inputs
  std::string input_name;  // its name
  SymmetryKind kind = SymmetryKind::Even;
  double center = 0;  // m: Point only (0 otherwise)
  // Odd and Point: 1 when y - m >= 0 on the half, -1 when it is <= 0 (within the tolerance), so
  // that copysign carries the sign of s (y - m) >= 0 (|t - g| <= |t + g| wherever t >= 0 > g, so
  // copysign never adds error); 0 when it changes sign (the slower form with sign). Even: 1.
  int sign = 1;
  SymmetryEvidence evidence;

  friend bool operator==(const DataSymmetry&, const DataSymmetry&) = default;
};

// Relative to the target's range (max - min): the asymmetry accepted whatever the data's noise.
// float64 references of an exactly symmetric function meet it on mirrored pairs.
inline constexpr double kSymmetryTolerance = 1e-9;

// Interpolation (below): the fewest rows compared on each side of 0, over all slices.
inline constexpr std::size_t kSymmetryMinSideRows = 64;

// The first input in which the data is symmetric, or nullopt. Every input (in problem order) is
// tried on mirrored pairs first, then every input whose rows are not mirrored by interpolation.
// A constant target is not taken as symmetric. Residuals: y(x) - y(-x) (even), y(x) + y(-x)
// (odd), y(x) + y(-x) - 2 m (point). Tried in that order, even first.
//
// Mirrored pairs (exact, cheap): the data is symmetric in x when
//  - the rows come in mirrored pairs: for each row with x != 0 exactly one row with -x and every
//    other input equal (bit for bit), rows with x = 0 pairing with themselves, no two rows alike;
//  - at least 8 pairs have x != 0;
//  - paired rows have the same weight;
//  - every pair's residual is within tolerance * (max - min of the target), and for odd data
//    y = 0, for point data y = m, at x = 0 (m is the mean target of the rows with x = 0, or
//    without such rows the mean of the pairs' midpoints).
// Rows that are mirrored in x are decided by this rule alone.
//
// Interpolation (any sampling), in slices of rows whose other inputs are equal bit for bit
// (all rows in one input; a grid in the other inputs otherwise; scattered rows in several inputs
// make slices of one row, and the data is then not taken as symmetric). In each slice the rows of
// each side (x < 0, x > 0) are a function of |x| on nodes: the distinct |x| with their mean
// target, less any node closer to the previous one than a quarter of the local spacing. y(-x) for
// a row at x is the cubic through the four nearest nodes of the other side. The noise is 1.4826
// times the median |leave-one-out residual| of the nodes (each from the cubic through its four
// neighbours), the local scale that median over 17 nodes. A row's error estimate is the largest
// of the cubic's next term at the mirror (|quartic - cubic|), the local scale there times the
// cubic's noise gain (the sum of its |Lagrange weights|), the local scale at the row, and the
// noise. A row is compared when its mirror lies within the other side's nodes (the overlap |x| <=
// min(max x, -min x): rows beyond it are not compared, but the fold still fits the half x >= 0
// and scores each reflected formula on every row) and its error estimate is at most R = max(1e-6,
// tolerance) * range (where it is larger, the data does not resolve the function). The data is
// symmetric in x when
//  - every slice has at least 8 nodes on each side, and its shorter side reaches at least half as
//    far from 0 as its longer side;
//  - on each side at least kSymmetryMinSideRows rows, and at least half of the rows in the
//    overlap, are compared;
//  - the noise is at most R: float64 and float32-rounded data pass, measured data with noise 1e-3
//    does not (as on mirrored pairs);
//  - every compared row's residual is within 10 times its error estimate plus a few float64
//    roundings, or within tolerance * range;
//  - for odd and point data, rows at x = 0 are within 10 times the noise of 0 and m (m: the mean
//    target at x = 0, or without such rows the median over compared rows of (y(x) + y(-x)) / 2).
// Weights play no part in this rule. `problem` must be valid (SearchProblem::validate).
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

// Whether g, as written, is odd (Odd data) or even (Even data) in the symmetric input by the
// rules of its operators alone (x^3, x * (c + x^2), sin(x), x / (1 + x^2) are odd; cos(x),
// exp(-x^2) even); never for point-symmetric data. Where it holds, g is its own symmetric
// extension: unreflected_expression(g) equals reflect_expression(g) on every row.
bool symmetric_as_written(const Expression& g, const DataSymmetry& symmetry);

// The forms of a half's formula g on every row: reflect_expression's, factored_expression's
// where there is one, and unreflected_expression's where symmetric_as_written or `scored` (the
// caller scores each form on every row, so a g the rules miss still gets its chance).
std::vector<Expression> whole_data_forms(const Expression& g, const DataSymmetry& symmetry,
                                         const std::vector<std::string>& input_names, bool scored);

// "odd in x", "even in x", "point-symmetric in x about 1.5707963267948966".
std::string describe_symmetry(const DataSymmetry& symmetry);

// The evidence in a few words: "512 mirrored pairs, largest residual 0 of the range", or
// "19873 rows against the other side's interpolant, largest residual 2.1e-14 of the range,
// noise 3.4e-16".
std::string describe_symmetry_evidence(const DataSymmetry& symmetry);

}  // namespace shaderfit
