// Downward from the reference (internal; docs/search.md, "Downward from the reference"): from
// the reference written in the operators (reference/program_formula.hpp), cheaper formulas by
// the rewrites of search/evolution/rewrites.hpp. Rewrites are screened on a sample of the rows;
// the best few at each cost are refitted there (every literal free, copies of a subexpression
// keeping one set of constants) and offered to the front (SearchPhase::Rewrite). The best at
// each cost are rewritten in turn, in rounds (the best at each cost, the most expensive first,
// then the second best, ...), until the descent's budget is spent.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "search/search_context.hpp"

namespace shaderfit::search_detail {

// The share of the time limit (and of a candidate budget) the descent may use.
inline constexpr double kDescentShare = 0.3;
// Rewrites refitted per cost level and expansion, and formulas kept per cost level to rewrite.
inline constexpr std::size_t kDescentRefitsPerCost = 8;
inline constexpr std::size_t kDescentKeptPerCost = 6;
// Levenberg-Marquardt steps (and Lawson passes) of a rewrite's refit.
inline constexpr int kDescentFitSteps = 30;

// e's parameters refitted on `rows` from their values for options.loss: damped least squares
// (weighted by 1 / y^2 for the rel loss), then Lawson's minimax for the minimax losses. Never
// worse than the start in least squares; a redundant pair of constants (c + y - d) does not stop
// it.
Expression refit_on_rows(Expression e, const SearchOptions& options, const SearchProblem& rows);

// Runs the descent from `starts` (formulas already offered to ctx's front) until ctx stops,
// nothing is left to rewrite, ctx.elapsed() passes `until_s` or `max_candidates` more
// candidates have been counted. Returns the formulas it kept (seeds for the evolution), cheapest
// first.
std::vector<Expression> descend(SearchContext& ctx, std::span<const Expression> starts,
                                double until_s, std::uint64_t max_candidates);

}  // namespace shaderfit::search_detail
