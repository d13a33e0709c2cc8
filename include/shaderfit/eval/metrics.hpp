// Error metrics of an approximation against a target, overall and per group of rows: every
// number a loss (eval/loss.hpp) minimises or a report shows is defined here, once.
//
//   ErrorMetrics m = error_metrics(predicted, target);               // every row, unweighted
//   ErrorMetrics g = error_metrics(predicted, target, rows, weights);  // a subset, weighted
//   m.mse, m.rmse, m.max_abs, m.max_rel, m.rel, m.log
//
// Definitions. p = prediction, t = target, w = weight (1 when no weights are given). The rows
// taken are the selected ones (all when no selection is given) with w > 0; sums run over those
// where p is finite, in row order:
//   mse      sum w (p - t)^2 / sum w
//   rmse     sqrt(mse)
//   max_abs  max |p - t|                     (weights only select rows)
//   max_rel  max |p - t| / |t| over rows with t != 0 (weights only select rows); 0 if none
//   rel      sum w ((p - t) / t)^2 / sum w   mean squared relative error; NaN when some t == 0
//   log      sum w (ln p - ln t)^2 / sum w   mean squared log error (natural log); NaN when some
//            t <= 0, and p <= 0 is scored as p = 1e-30 (a large but finite penalty)
// A row where p is NaN or infinite counts in `nonfinite` and makes mse, rmse, max_abs, rel and
// log +infinity (max_rel stays the largest over the finite rows). With no row taken every metric
// is 0. With MetricSet::NoLog, log is NaN and not computed (a std::log a row, the dearest part:
// what scores many candidates by another loss asks for that).
#pragma once

#include <cstddef>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace shaderfit {

struct ErrorMetrics {
  std::size_t rows = 0;  // rows taken (selected, with weight > 0)
  double mse = 0;
  double rmse = 0;
  double max_abs = 0;
  double max_rel = 0;
  double rel = 0;
  double log = 0;
  std::size_t nonfinite = 0;  // rows taken where the prediction is NaN or infinite
};

// Which metrics error_metrics computes: all, or all but the log error (see above).
enum class MetricSet { All, NoLog };

// The metrics over the rows selected by `rows` (indices into prediction and target; all rows
// when empty), weighted by `weights` (empty: all 1; else one per row of prediction and target).
ErrorMetrics error_metrics(std::span<const double> prediction, std::span<const double> target,
                           std::span<const std::size_t> rows = {},
                           std::span<const double> weights = {}, MetricSet set = MetricSet::All);

// The row indices of each distinct label, labels in sorted order.
std::map<std::string, std::vector<std::size_t>> group_rows(std::span<const std::string> labels);

// (candidate - baseline) / baseline, e.g. -0.34 for "34% less"; 0 when baseline is 0.
double relative_change(double candidate, double baseline);

}  // namespace shaderfit
