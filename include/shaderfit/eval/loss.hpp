// The losses shaderfit minimises or ranks by: one vocabulary for the search, the fits and the
// rational approximations. Each loss is the metric of the same name in ErrorMetrics
// (eval/metrics.hpp, where the definitions are).
//
//   std::optional<Loss> k = loss_from_name("rmse");
//   ErrorMetrics m = error_metrics(prediction, target, {}, weights);  // all metrics at once
//   double l = loss_value(*k, m);                                     // the one k minimises
//
// Not every caller minimises every loss; each documents which it takes and refuses the others
// with an Error naming its field:
//   search    SearchOptions::loss: mse, rmse, max_abs, max_rel, rel, log, display
//   fit       FixedFormOptions::loss: mse, log (in log2 space), max_abs (weighted minimax)
//   rational  RationalOptions::rank_by: rmse, max_abs, max_rel
#pragma once

#include <optional>
#include <span>
#include <string_view>

namespace shaderfit {

struct ErrorMetrics;

// Display: the error of the displayed pixels (docs/scenes.md), the weighted MSE of the term with
// a scene's display weights (scene/scene.hpp, display_weights) as the row weights. The weights
// belong to the problem (Problem::display_weights, set for a scene): whoever turns a problem and
// a loss into rows (search_problem) weighs them so; the metric itself is the MSE.
enum class Loss { Mse, Rmse, MaxAbs, MaxRel, Relative, Log, Display };

// "mse", "rmse", "max_abs" (also "max"), "max_rel", "rel" (also "relative"), "log", "display";
// nullopt otherwise.
std::optional<Loss> loss_from_name(std::string_view name);
std::string_view loss_name(Loss loss);

// The metric that `loss` minimises (for Display the MSE, over rows weighted as it says).
double loss_value(Loss loss, const ErrorMetrics& m);

// That metric alone, over every row with weight > 0, computed directly:
// loss_of(k, p, t, w) == loss_value(k, error_metrics(p, t, {}, w)).
double loss_of(Loss loss, std::span<const double> prediction, std::span<const double> target,
               std::span<const double> weights = {});

}  // namespace shaderfit
