// Cost-lowering rewrites of a formula (internal; docs/search.md, "Downward from the reference"),
// for the descent from the reference (search/starts/descent.hpp) and as a mutation of the
// evolution:
//  - an operand alone: a term of a sum, a factor of a product, an operation (saturate(x) -> x,
//    max(x, eps) -> x, a select -> one branch) dropped; a lower integer power;
//  - a subexpression replaced by a constant, or by a + b y for y an operand, an operand's operand
//    or an input it reads;
//  - a subexpression of one or two inputs replaced by a form fitted to the values it takes on the
//    rows: a polynomial (of two inputs also p0 + x (p1 + y) and p0 + x (p1 x + y)), a rational,
//    exp2 of a polynomial; any subexpression by a power
//    exp2(a + p log2 y) of a part y below it (rsqrt(d)^3 = d^-1.5);
//  - each also with its products and sums regrouped by the inputs their parts read (so that
//    ((t (1-x)^2) (1-x)^2) (1-x) shows the part (1-x)^5, and a per-material part is one factor),
//    with a positive per-material scale moved into an exponential (a exp2(u) = exp2(u + log2 a))
//    and with its constants folded and its calls merged (SimplifyOptions::merge_calls),
//    whichever costs least.
// A rewrite replaces every copy of the subexpression at once: the cost model counts a repeated
// subexpression once, so replacing one copy saves nothing. The constants a rewrite introduces
// are fitted to the part it replaces; the formula's own stay as they are.
#pragma once

#include <functional>

#include <cstddef>
#include <vector>

#include "search/search_context.hpp"
#include "shaderfit/core/random.hpp"

namespace shaderfit::search_detail {

// The rows rewrites are fitted and screened on: at most `count` of the problem's, evenly spread
// (both ends kept).
inline constexpr std::size_t kRewriteRows = 512;
SearchProblem descent_rows(const SearchProblem& problem, std::size_t count = kRewriteRows);

// Every rewrite of e (over the problem's inputs) that costs less than e under `options`, the
// introduced constants fitted on `rows`. Deterministic. `stop`, when given, is asked between
// subexpressions whether to end early, with the rewrites made so far (a large formula's are
// many fits).
std::vector<Expression> cheaper_rewrites(const Expression& e, const SearchOptions& options,
                                         const SearchProblem& rows,
                                         const std::function<bool()>& stop = {});

// One rewrite of a random subexpression of e, chosen by `rng`, in its cheapest form; empty when
// none applies. It may cost as much as e or more (a mutation).
Expression random_rewrite(Rng& rng, const Expression& e, const SearchOptions& options,
                          const SearchProblem& rows);

// The cheapest of e, e simplified with its calls merged, with its products and sums regrouped by
// the inputs their parts read, and with its positive per-material scales moved into exponentials.
Expression cheapest_form(Expression e, const SearchOptions& options, const SearchProblem& rows);

// e with each number literal a parameter at its value; literals of copies of one subexpression
// share their parameters, so the copies stay one subexpression to the cost model.
Expression with_shared_literal_parameters(const Expression& e);

// The rows' loss of e for `loss` (+inf where e is not finite on a row), and that of a e + b with
// a and b fitted by least squares: how good e may be once its constants are refitted.
double rows_loss(const Expression& e, Loss loss, const SearchProblem& rows);
double scaled_rows_loss(const Expression& e, Loss loss, const SearchProblem& rows);

}  // namespace shaderfit::search_detail
