#include "search/evolution/constant_fit.hpp"

#include <chrono>

#include "search/evolution/variation.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/fit/fit.hpp"

namespace shaderfit::search_detail {

namespace {

// The final polish: a full least-squares start is not needed (the member's values are already
// fitted), so its passes go to Lawson.
constexpr ConstantFitBudget kPolish{
    .least_squares_steps = 0, .minimax_passes = 200, .minimax_steps = 10};

}  // namespace

bool fits_minimax(Loss loss) { return loss == Loss::MaxAbs || loss == Loss::MaxRel; }

std::vector<double> minimax_weights(Loss loss, std::span<const double> target,
                                    std::span<const double> weights) {
  std::vector<double> w(target.size());
  for (std::size_t i = 0; i < w.size(); ++i)
    w[i] = screen_weight(loss, weights.empty() ? 1.0 : weights[i], target[i]);
  return w;
}

void fit_minimax(Expression* e, Loss loss, std::span<const double* const> columns,
                 std::span<const double> target, std::span<const double> weights, int passes,
                 int steps) {
  if (e->parameters.empty() || !fits_minimax(loss)) return;
  const std::vector<double> w = minimax_weights(loss, target, weights);
  FitOptions fo;
  fo.minimax = true;
  fo.max_iterations = steps;
  fo.minimax_iterations = passes;
  FitSummary fs;
  fit_parameters(fo, {e, {columns.begin(), columns.end()}, target, w}, &fs);
  e->parameter_values = fs.parameters;
}

Expression fit_on_all_rows(Expression e, const SearchContext& ctx,
                           const ConstantFitBudget& budget) {
  if (e.parameters.empty()) return e;
  const SearchProblem& p = ctx.problem;
  if (budget.least_squares_steps > 0) {
    FitOptions fo;
    fo.max_iterations = budget.least_squares_steps;
    FitSummary fs;
    fit_parameters(fo, {&e, ctx.columns, p.target, p.weights}, &fs);
    e.parameter_values = fs.parameters;
  }
  if (budget.minimax_passes > 0)
    fit_minimax(&e, ctx.options.loss, ctx.columns, p.target, p.weights, budget.minimax_passes,
                budget.minimax_steps);
  return e;
}

void polish_front_minimax(SearchContext& ctx, double seconds) {
  if (!fits_minimax(ctx.options.loss)) return;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<FrontMember> members = ctx.front.members();
  struct Refit {
    Expression expr;
    ErrorMetrics metrics;
    bool done = false;
  };
  std::vector<Refit> refits(members.size());
  parallel_for(
      members.size(), 1,
      [&](std::size_t b, std::size_t end) {
        for (std::size_t i = b; i < end; ++i) {
          const std::chrono::duration<double> spent = std::chrono::steady_clock::now() - start;
          if (spent.count() >= seconds) return;
          Expression free = with_literals_as_parameters(members[i].expression);
          if (free.parameters.empty()) continue;
          refits[i].expr = fit_on_all_rows(std::move(free), ctx, kPolish);
          refits[i].metrics = ctx.score(refits[i].expr);
          refits[i].done = true;
        }
      },
      ctx.threads);
  for (std::size_t i = 0; i < members.size(); ++i) {
    Refit& r = refits[i];
    if (!r.done) continue;
    const double loss = loss_value(ctx.options.loss, r.metrics);
    if (!(loss < members[i].loss) || formula_cost(r.expr, ctx.options) > members[i].cost) continue;
    ctx.offer(std::move(r.expr), loss, members[i].origin);
  }
}

}  // namespace shaderfit::search_detail
