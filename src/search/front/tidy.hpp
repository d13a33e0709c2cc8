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

// The simple values a constant may snap to, ascending: 0, p / q for q <= 4 and |p / q| <= 32;
// r pi and 1 / (r pi) for r = k / q, k <= 8, q <= 4; r ln 2 and 1 / (r ln 2) for r = k / q,
// k <= 4, q <= 4; sqrt(2), sqrt(pi), sqrt(2 pi) and their reciprocals; and the negatives of all.
std::span<const double> simple_values();
// The simple value nearest v (the smaller one on a tie).
double nearest_simple_value(double v);

// A tidied form of a member with loss L may have a loss of at most
//   L + kTidyRelativeLoss * L + (the loss of a prediction off by kTidyRoundingNoise * |y| on
//   every row, the float64 rounding noise of exact data),
// so that on exact data (L near 0) the floor decides and otherwise the 1e-9 share of L.
inline constexpr double kTidyRelativeLoss = 1e-9;
inline constexpr double kTidyRoundingNoise = 1e-12;

// The noise level: a member is at the noise level of float64 evaluation when its rmse is at most
// kNoiseLevel times the target's rms (both over the rows as the search weighs them). Rounding
// in float64 leaves a few ulp (1e-15) per operation, which cancellation in a formula (or in the
// data's own formula) amplifies by its condition number; 1e-9 leaves room for condition numbers
// up to about 1e6, while float32-rounded data (rms relative noise 2^-24 / sqrt(3) = 3.4e-8) and
// any formula a float32 shader could tell from the truth stay above it: an approximation that
// reaches it (about 9 correct digits) counts as exact, losing nothing a float32 shader shows.
inline constexpr double kNoiseLevel = 1e-9;
// The rmse at or below which a member is at noise level on `problem` (0 when the target is 0).
double noise_level_rmse(const SearchProblem& problem);

// Each member tidied (docs/search.md, "Tidy front"): its parameters written as literals and the
// formula simplified with regroup_constants and merge_calls (the cost model choosing between
// equal forms); on that regrouped form, the constants near a simple value (within 1e-6,
// relative; near 0: 1e-6 of the largest constant or of 1) are snapped at once: all of them, else those near 0 alone, else
// the others alone; then each remaining constant, one at a time, set to its nearest simple value
// (a constant set to 0 or 1 drops its term or factor). Each step is simplified again and kept
// when the cost does not rise, the formula stays finite everywhere and its error stays
// acceptable: for a member at noise level (before or after the steps above; then they run again)
// the error must stay at noise level, for any other the loss within the bound above (against the
// member's original loss). Constants that came from fitted parameters and were not snapped
// become parameters p0, p1, ... again. A changed member is rescored on every row, its cost
// recounted and its float32 check redone; then the front is recomputed from all members (a
// tidied member may now dominate others), cheapest first, and ends at its first member at noise
// level (costlier ones only trade float64 noise). Unchanged members are returned as they were;
// deterministic. Adds the nodes times rows evaluated to *node_evaluations.
std::vector<FrontMember> tidy_front(const SearchOptions& options, const SearchProblem& problem,
                                    std::vector<FrontMember> front,
                                    std::uint64_t* node_evaluations);

// Each member whose exact text (FrontMember::formula) reads back to a formula of fewer
// instructions takes that formula and its cost, so that what is shown is what is counted: the
// printer moves signs out of groups, which the instruction model may count one fewer. The same
// values (up to the sign of a zero), so no other field changes; a member it makes dominated
// leaves the front.
void count_as_printed(std::vector<FrontMember>& front, const SearchOptions& options);

// Marks FrontMember::minor_step, cheapest first: a member is shown when its loss is at most
// (1 - min_step) times that of the last member shown (the cheapest is shown), so that no two
// members shown differ by less than the margin; with min_step 0 only equal losses are minor.
void mark_minor_steps(std::vector<FrontMember>& front, double min_step);

}  // namespace shaderfit::search_detail
