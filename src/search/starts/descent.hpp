// Downward from the reference (internal; docs/search.md, "Downward from the reference"): from a
// formula the front holds (the reference written in the operators, reference/program_formula.hpp),
// cheaper formulas made by rewrites, each with its constants refitted for the loss:
//  - an integer power lowered (x^5 -> x^4, ..., x);
//  - a term of a sum or a factor of a product dropped, an operation dropped (saturate(x) -> x,
//    min(x, c) -> x, a select -> one branch);
//  - a subexpression replaced by a constant, or by a + b y for y one of its operands or of the
//    inputs it reads;
//  - a subexpression of one or two inputs replaced by a cheaper form fitted to the values it
//    takes on the rows: a polynomial, a rational, exp2 of a polynomial, (a + b x)^p;
//  - constants folded (simplify).
// A rewrite replaces every copy of the subexpression at once (the cost model counts a repeated
// subexpression once, so replacing one copy saves nothing). Rewrites are screened on a sample of
// the rows; the best at each cost are refitted (every literal free, copies of a subexpression
// keeping one set of constants) and offered to the front (SearchPhase::Rewrite). The members so
// found are rewritten in turn, the most expensive first, until the descent's budget is spent.
#pragma once

#include <cstddef>
#include <vector>

#include "search/search_context.hpp"

namespace shaderfit::search_detail {

// The share of the time limit (and of a candidate budget) the descent may use.
inline constexpr double kDescentShare = 0.3;
// Rows the rewrites are screened and refitted on (evenly spread; all when there are fewer).
inline constexpr std::size_t kDescentRows = 512;
// Rewrites refitted per cost level and expansion, and formulas kept per cost level to rewrite.
inline constexpr std::size_t kDescentRefitsPerCost = 6;
inline constexpr std::size_t kDescentKeptPerCost = 3;
// Levenberg-Marquardt steps (and Lawson passes) of a rewrite's refit.
inline constexpr int kDescentFitSteps = 30;

// The rows the descent works on: at most `count` of the problem's, evenly spread (both ends kept).
SearchProblem descent_rows(const SearchProblem& problem, std::size_t count = kDescentRows);

// The rewrites of e (over the problem's inputs) that cost less than e under `options`, each with
// the constants it introduces fitted to the part it replaces on `rows`; e's own constants as they
// are. Deterministic.
std::vector<Expression> cheaper_rewrites(const Expression& e, const SearchOptions& options,
                                         const SearchProblem& rows);

// e with each number literal a parameter at its value; literals of copies of one subexpression
// share their parameters, so the copies stay one subexpression to the cost model.
Expression with_shared_literal_parameters(const Expression& e);

// Runs the descent from `start` (a formula already offered to ctx's front) until ctx stops,
// nothing is left to rewrite, ctx.elapsed() passes `until_s` or `max_candidates` more
// candidates have been counted. Returns the formulas it kept (seeds for the evolution), cheapest
// first.
std::vector<Expression> descend(SearchContext& ctx, const Expression& start, double until_s,
                                std::uint64_t max_candidates);

}  // namespace shaderfit::search_detail
