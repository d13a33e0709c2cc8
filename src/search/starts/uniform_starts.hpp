// Per-material starts (internal; docs/search.md, "Per-material inputs"): with uniform inputs,
// after the enumeration unless the search is over, forms whose coefficients are functions of the
// uniform inputs u, fitted by linear least squares (or minimax, for max_abs and max_rel):
//   y = a0(u) + a1(u) b1(x) [+ a2(u) b2(x)]          (linear)
//   y = exp2(a0(u) + a1(u) b1(x) [+ a2(u) b2(x)])    (exponential; a target that is > 0)
// where each b is a per-pixel basis of one varying input (x, x^2, 1/x, 1/x^2, sqrt(x),
// rsqrt(x), log2(x), where finite) and each coefficient a_k(u) = sum_j c_kj t_j(u) over the same
// few coefficient functions t_j (1, and up to two of the uniform inputs and the uniform terminals,
// uniform_terminals.hpp). The coefficients cost nothing per pixel, so these are the forms the
// published approximations hoist into (Blinn-Phong for Beckmann: exp2(a1(alpha) log2(nh) +
// a0(alpha))), which the evolution seldom assembles. They are offered to the front with their
// constants free (the final polish refines them) and seed the evolution (origin
// SearchPhase::Material).
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/expr/expression.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

// The fits read at most this many rows, evenly spread over the problem's rows.
inline constexpr std::size_t kUniformStartRows = 2048;
// Per shape, the basis sets refitted with every choice of coefficient functions: the best by the
// fit with all of them.
inline constexpr std::size_t kUniformStartBases = 6;

// The share of a time-limited search's time the fits may take (they stop early, with the fits
// made so far, where `over` says so; with many inputs and coefficient functions they are
// seconds of least squares).
inline constexpr double kUniformStartShare = 0.1;

// Formulas over x0, x1, ... (input k is xk) with constants in full precision, cheapest first;
// empty without uniform inputs or without a varying input. `terminals` over problem.input_names.
// `over`, when given, is asked between fits whether to stop.
std::vector<std::string> uniform_starts(const SearchProblem& problem, const SearchOptions& options,
                                        std::span<const Expression> terminals,
                                        const std::function<bool()>& over = {});

}  // namespace shaderfit::search_detail
