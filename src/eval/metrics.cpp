#include "shaderfit/eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shaderfit {

ErrorMetrics error_metrics(std::span<const double> prediction, std::span<const double> target,
                           std::span<const std::size_t> rows, std::span<const double> weights,
                           MetricSet set) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kLogFloor = 1e-30;
  ErrorMetrics m;
  const std::size_t n = rows.empty() ? target.size() : rows.size();
  double sw = 0, se = 0, srel = 0, slog = 0;
  const bool want_log = set == MetricSet::All;
  bool rel_ok = true, log_ok = want_log;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = rows.empty() ? j : rows[j];
    const double w = weights.empty() ? 1.0 : weights[i];
    if (!(w > 0)) continue;
    ++m.rows;
    const double p = prediction[i], t = target[i];
    if (!std::isfinite(p)) {
      ++m.nonfinite;
      continue;
    }
    const double d = p - t;
    const double ad = std::abs(d);
    sw += w;
    se += w * d * d;
    if (ad > m.max_abs) m.max_abs = ad;
    if (t != 0) {
      const double r = d / t;
      srel += w * r * r;
      const double q = ad / std::abs(t);
      if (q > m.max_rel) m.max_rel = q;
    } else {
      rel_ok = false;
    }
    if (want_log && t > 0) {
      const double l = std::log(std::max(p, kLogFloor) / t);  // one log a row, not two
      slog += w * l * l;
    } else {
      log_ok = false;
    }
  }
  if (m.nonfinite > 0) {
    m.mse = m.rmse = m.max_abs = m.rel = kInf;
    m.log = want_log ? kInf : kNaN;
  } else if (sw > 0) {
    m.mse = se / sw;
    m.rmse = std::sqrt(m.mse);
    m.rel = rel_ok ? srel / sw : kNaN;
    m.log = log_ok ? slog / sw : kNaN;
  }
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
