// The user's start formulas, SearchOptions::start (internal; docs/search.md, "Starting from a
// formula").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "search/search_context.hpp"

namespace shaderfit::search_detail {

struct StartFormula {
  Expression written;   // as the user wrote it, over the problem's inputs
  Expression free;      // the same with its number literals as parameters, at their written values
  bool fitted = false;  // its literals are already the loss's best (no refit_for_loss)
  SearchPhase origin = SearchPhase::Start;  // what the front records it as
};

// options.start parsed over problem.input_names. Throws Error located at "SearchOptions::start",
// line k + 1 and the column, for the k-th formula when it does not parse or names a variable
// that is not an input.
std::vector<StartFormula> parse_start_formulas(const SearchOptions& options,
                                               const SearchProblem& problem);

// e (over the problem's inputs) with its parameters fitted on every row for options.loss: the
// (weighted) minimax by Lawson's reweighting for max_abs and max_rel (minimax_weights), least
// squares in the loss's own terms for mse and rmse, rel (weights 1 / target^2) and log (of the
// target). Where the fit fails, e keeps its values.
Expression refit_for_loss(Expression e, const SearchOptions& options, const SearchProblem& problem);

// Offers each start formula to ctx's front as written and refitted (with its origin; a `fitted`
// one only with its literals free, at their values), counting them as candidates; returns the
// refitted forms (a `fitted` one's `free`), which seed the evolution. A member at no more than a
// start's cost and loss is then on the front for the rest of the search, unless the start is not
// finite on every row (SearchContext::offer).
std::vector<Expression> offer_start_formulas(SearchContext& ctx,
                                             const std::vector<StartFormula>& starts);

// `text` over the variables x0, x1, ... (input k is xk, as search/power_sum.hpp and
// search/polynomial_starts.hpp write it), as written and with its literals free, over `names`;
// `source` names it in a parse error.
StartFormula start_over_indexed_inputs(const std::string& text,
                                       const std::vector<std::string>& names,
                                       const std::string& source, SearchPhase origin);

// The reference's own formula (reference_formula, search.hpp) as a start: written as the
// reference computes it, and with its literals free (copies of a subexpression sharing theirs);
// origin SearchPhase::Reference. nullopt when the problem has no reference or it does not lower.
std::optional<StartFormula> reference_start(const SearchProblem& problem);

}  // namespace shaderfit::search_detail
