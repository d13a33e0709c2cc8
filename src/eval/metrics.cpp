#include "shaderfit/eval/metrics.hpp"

#include <cmath>
#include <limits>

namespace shaderfit {

ErrorMetrics error_metrics(std::span<const double> predicted, std::span<const double> target,
                           std::span<const std::size_t> rows, std::span<const double> weights) {
  ErrorMetrics m;
  const std::size_t n = rows.empty() ? target.size() : rows.size();
  double sum = 0, wsum = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = rows.empty() ? j : rows[j];
    const double p = predicted[i], t = target[i];
    if (!std::isfinite(p)) {
      ++m.nonfinite;
      continue;
    }
    const double d = std::fabs(p - t);
    const double w = weights.empty() ? 1.0 : weights[i];
    sum += w * d * d;
    wsum += w;
    if (d > m.max_abs) m.max_abs = d;
    if (t != 0 && d / std::fabs(t) > m.max_rel) m.max_rel = d / std::fabs(t);
  }
  m.rows = n;
  if (m.nonfinite > 0) {
    m.mse = m.max_abs = std::numeric_limits<double>::infinity();
  } else {
    m.mse = wsum > 0 ? sum / wsum : 0.0;
  }
  m.rmse = std::sqrt(m.mse);
  return m;
}

std::map<std::string, std::vector<std::size_t>> group_rows(std::span<const std::string> labels) {
  std::map<std::string, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < labels.size(); ++i) groups[labels[i]].push_back(i);
  return groups;
}

double relative_change(double candidate, double baseline) {
  return baseline == 0 ? 0.0 : (candidate - baseline) / baseline;
}

}  // namespace shaderfit
