#include "search/starts/descent.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "search/evolution/constant_fit.hpp"
#include "search/evolution/rewrites.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/fit/fit.hpp"

namespace shaderfit::search_detail {

using Column = std::vector<double>;

Expression refit_on_rows(Expression e, const SearchOptions& options, const SearchProblem& rows) {
  if (e.parameters.empty()) return e;
  std::vector<const double*> cols;
  for (const Column& c : rows.inputs) cols.push_back(c.data());
  Column w = rows.weights;
  if (options.loss == Loss::Relative) {
    w.resize(rows.target.size(), 1.0);
    for (std::size_t r = 0; r < w.size(); ++r) w[r] /= rows.target[r] * rows.target[r];
  }
  FitOptions fo;
  fo.max_iterations = kDescentFitSteps;
  FitSummary fs;
  try {
    fit_parameters(fo, {&e, cols, rows.target, w}, &fs);
  } catch (const Error&) {
    return e;  // more parameters than a fit takes (kMaxFitParameters): the values stay
  }
  if (std::all_of(fs.parameters.begin(), fs.parameters.end(),
                  [](double v) { return std::isfinite(v); }))
    e.parameter_values = fs.parameters;
  fit_minimax(&e, options.loss, cols, rows.target, rows.weights, kDescentFitSteps, 4);
  return e;
}

std::vector<Expression> descend(SearchContext& ctx, std::span<const Expression> starts,
                                double until_s, std::uint64_t max_candidates) {
  const SearchOptions& options = ctx.options;
  const SearchProblem rows = descent_rows(ctx.problem);
  const std::uint64_t first = ctx.candidates.load();
  struct Kept {
    Expression e;
    double loss;
    bool expanded = false;
  };
  std::map<double, std::vector<Kept>> kept;  // by cost
  std::set<std::uint64_t> known;
  const auto keep = [&](const Expression& e, double loss) {
    if (!known.insert(structural_hash(e)).second) return;
    std::vector<Kept>& level = kept[formula_cost(e, options)];
    level.push_back({e, loss});
    std::stable_sort(level.begin(), level.end(),
                     [](const Kept& a, const Kept& b) { return a.loss < b.loss; });
    if (level.size() > kDescentKeptPerCost && !level.back().expanded) level.pop_back();
  };
  for (const Expression& start : starts) keep(start, loss_value(options.loss, ctx.score(start)));
  const auto out_of_budget = [&] {
    return ctx.should_stop() || ctx.elapsed() >= until_s ||
           ctx.candidates.load() - first >= max_candidates;
  };
  while (!out_of_budget()) {
    // In rounds: the best not yet rewritten at each cost, then the second best, ...; within a
    // round the most expensive first.
    Kept* next = nullptr;
    std::size_t round = kDescentKeptPerCost;
    for (auto it = kept.rbegin(); it != kept.rend(); ++it)
      for (std::size_t k = 0; k < it->second.size() && k < round; ++k)
        if (!it->second[k].expanded) {
          next = &it->second[k];
          round = k;
          break;
        }
    if (next == nullptr) break;
    next->expanded = true;
    const Expression from = next->e;
    std::vector<Expression> rewrites = cheaper_rewrites(from, options, rows, out_of_budget);
    ctx.candidates.fetch_add(rewrites.size(), std::memory_order_relaxed);
    // Screened on the rows; the best few at each cost go on.
    std::map<double, std::vector<std::pair<double, std::size_t>>> screened;
    for (std::size_t k = 0; k < rewrites.size(); ++k) {
      const double l = scaled_rows_loss(rewrites[k], options.loss, rows);
      if (std::isfinite(l)) screened[formula_cost(rewrites[k], options)].push_back({l, k});
    }
    for (auto& [cost, level] : screened) {
      std::sort(level.begin(), level.end());
      if (level.size() > kDescentRefitsPerCost) level.resize(kDescentRefitsPerCost);
      for (const auto& [l, k] : level) {
        if (out_of_budget()) break;
        const Expression& as_fitted = rewrites[k];
        Expression refitted =
            refit_on_rows(with_shared_literal_parameters(as_fitted), options, rows);
        for (const Expression* x : {&as_fitted, static_cast<const Expression*>(&refitted)}) {
          if (!std::isfinite(rows_loss(*x, options.loss, rows))) continue;
          const double loss = loss_value(options.loss, ctx.score(*x));
          if (!std::isfinite(loss)) continue;
          ctx.candidates.fetch_add(1, std::memory_order_relaxed);
          ctx.offer(*x, loss, SearchPhase::Rewrite);
          keep(*x, loss);
        }
      }
    }
    ctx.maybe_progress(SearchPhase::Rewrite);
  }
  std::vector<Expression> seeds;
  for (auto& [cost, level] : kept)
    if (!level.empty()) seeds.push_back(level.front().e);
  return seeds;
}

}  // namespace shaderfit::search_detail
