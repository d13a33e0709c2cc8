// The losses a search can minimise, and every metric reported for a formula.
//
//   std::optional<LossKind> k = loss_from_name("rmse");
//   LossMetrics m = loss_metrics(prediction, target, weights);   // all metrics at once
//   double l = loss_value(*k, m);
//
// Definitions (w = sample weights, all 1 when none are given; sums over rows with w > 0):
//   mse      sum w (p - t)^2 / sum w
//   rmse     sqrt(mse)
//   max_abs  max |p - t|                       (weights only select rows)
//   rel      sum w ((p - t) / t)^2 / sum w     mean squared relative error; needs t != 0
//   log      sum w (ln p - ln t)^2 / sum w     mean squared log error (seed 002); needs t > 0,
//            and p <= 0 is scored as p = 1e-30 (a large but finite penalty)
// A prediction that is NaN or infinite on some row makes every metric +infinity.
#pragma once

#include <optional>
#include <span>
#include <string_view>

namespace shaderfit {

enum class LossKind { Mse, Rmse, MaxAbs, Relative, Log };

struct LossMetrics {
  double mse = 0;
  double rmse = 0;
  double max_abs = 0;
  double rel = 0;  // NaN when some weighted target is 0
  double log = 0;  // NaN when some weighted target is <= 0
};

// "mse", "rmse", "max_abs" (also "max"), "rel" (also "relative"), "log"; nullopt otherwise.
std::optional<LossKind> loss_from_name(std::string_view name);
std::string_view loss_name(LossKind kind);

// All metrics of `prediction` against `target` (same length); `weights` empty or the same length.
LossMetrics loss_metrics(std::span<const double> prediction, std::span<const double> target,
                         std::span<const double> weights = {});

// The metric that `kind` minimises.
double loss_value(LossKind kind, const LossMetrics& m);

// That metric alone, computed directly: loss_of(k, p, t, w) == loss_value(k, loss_metrics(p, t,
// w)).
double loss_of(LossKind kind, std::span<const double> prediction, std::span<const double> target,
               std::span<const double> weights = {});

}  // namespace shaderfit
