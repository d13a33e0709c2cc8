// Fitting a formula's constants on every row for the search's loss, and the minimax polish of
// the final front (internal; docs/search.md, "Constants").
#pragma once

#include <span>
#include <vector>

#include "search/search_context.hpp"

namespace shaderfit::search_detail {

// Whether the search fits constants minimax for this loss (max_abs, max_rel): its front members'
// fitted constants are then Lawson-refined from the least-squares fit.
bool fits_minimax(Loss loss);

// The rows' weights w of the minimax fit, max_i w_i |f_i - y_i|, for a minimax loss (as the
// screening weighs them, screen_weight): max_abs 1 on the rows of non-zero weight, max_rel
// 1/|y| there (0 where y = 0).
std::vector<double> minimax_weights(Loss loss, std::span<const double> target,
                                    std::span<const double> weights);

// *e's parameters fitted minimax for `loss` (nothing when not fits_minimax) on the rows given
// (one column per variable of *e; weights as the problem's, empty: all 1), from their values:
// at most `passes` Lawson passes of at most `steps` LM steps, never worse than the start.
void fit_minimax(Expression* e, Loss loss, std::span<const double* const> columns,
                 std::span<const double> target, std::span<const double> weights, int passes,
                 int steps);

struct ConstantFitBudget {
  int least_squares_steps = 10;  // Levenberg-Marquardt steps of the least-squares fit
  int minimax_passes = 0;        // Lawson passes after it, for minimax losses; 0: none
  int minimax_steps = 4;         // Levenberg-Marquardt steps per pass (linear formulas: a solve)
};

// e (over the problem's inputs, its parameter values the start) with its parameters fitted on
// every row: weighted least squares (the problem's weights), then, when fits_minimax and the
// budget has passes, the minimax with minimax_weights, never ending worse in it than the
// least-squares fit.
Expression fit_on_all_rows(Expression e, const SearchContext& ctx, const ConstantFitBudget& budget);

// For a minimax loss: every front member refitted minimax with its number literals and
// parameters free (at their values), in front order; a refit replaces its member when its cost
// is no higher and its loss lower. Each member's fit is bounded by passes, so the result
// depends only on the front; members not reached once `seconds` have passed stay as they are.
void polish_front_minimax(SearchContext& ctx, double seconds);

}  // namespace shaderfit::search_detail
