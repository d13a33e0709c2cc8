// The front as it is shown: noise constants removed or snapped, constants regrouped (internal;
// docs/search.md, "Tidy front").
//
//   summary.front = tidy_front(options, problem, std::move(summary.front), &evaluations);
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

// The simple values a constant may snap to, ascending: 0, p / q for q <= 4 and |p / q| <= 32,
// pi / 4, pi / 2, pi, 2 pi, 4 pi, 1 / pi, 1 / (2 pi), 1 / (4 pi), ln 2, and their negatives.
std::span<const double> simple_values();
// The simple value nearest v (the smaller one on a tie).
double nearest_simple_value(double v);

// A tidied form of a member with loss L may have a loss of at most
//   L + kTidyRelativeLoss * L + (the loss of a prediction off by kTidyRoundingNoise * |y| on
//   every row, the float64 rounding noise of exact data),
// so that on exact data (L near 0) the floor decides and otherwise the 1e-9 share of L.
inline constexpr double kTidyRelativeLoss = 1e-9;
inline constexpr double kTidyRoundingNoise = 1e-12;

// Each member tidied (docs/search.md, "Tidy front"): its parameters written as literals and the
// formula simplified with regroup_constants (the cost model choosing between equal forms); on
// that regrouped form, every constant within 1e-6 (relative; near 0: 1e-6 of the largest constant
// or of 1) of its nearest simple value snapped at once; then each remaining constant, one at a
// time, set to its nearest simple value (a constant set to 0 or 1 drops its term or factor). Each
// step is simplified again and kept when the cost does not rise, the formula stays finite
// everywhere and the loss stays within the bound above (against the member's original loss).
// Constants that came from fitted parameters and were not snapped become parameters p0, p1, ...
// again. A changed member is rescored on every row, its cost recounted and its float32 check
// redone; then the front is recomputed from all members (a tidied member may now dominate
// others), cheapest first. Unchanged members are returned as they were; deterministic. Adds the
// nodes times rows evaluated to *node_evaluations.
std::vector<FrontMember> tidy_front(const SearchOptions& options, const SearchProblem& problem,
                                    std::vector<FrontMember> front,
                                    std::uint64_t* node_evaluations);

}  // namespace shaderfit::search_detail
