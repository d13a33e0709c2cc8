// Error metrics of an approximation against a target, overall and per group of rows.
//
//   ErrorMetrics m = error_metrics(predicted, target);
//   m.mse, m.rmse, m.max_abs, m.max_rel
#pragma once

#include <cstddef>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace shaderfit {

struct ErrorMetrics {
  std::size_t rows = 0;
  double mse = 0;      // mean of (p - t)^2
  double rmse = 0;     // sqrt(mse)
  double max_abs = 0;  // max |p - t|
  double max_rel = 0;  // max |p - t| / |t| over rows with t != 0 (0 when there are none)
  std::size_t nonfinite = 0;  // rows where p is NaN or infinite; they make mse and max_abs infinite
};

// Metrics over the rows selected by `rows` (all rows when empty). Weights, when given, weight
// the mean squared error (normalised by their sum); the max errors ignore them.
ErrorMetrics error_metrics(std::span<const double> predicted, std::span<const double> target,
                           std::span<const std::size_t> rows = {},
                           std::span<const double> weights = {});

// The row indices of each distinct label, labels in sorted order.
std::map<std::string, std::vector<std::size_t>> group_rows(std::span<const std::string> labels);

// (candidate - baseline) / baseline, e.g. -0.34 for "34% less"; 0 when baseline is 0.
double relative_change(double candidate, double baseline);

}  // namespace shaderfit
