#include "shaderfit/search/loss.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shaderfit {

std::optional<LossKind> loss_from_name(std::string_view name) {
  if (name == "mse") return LossKind::Mse;
  if (name == "rmse") return LossKind::Rmse;
  if (name == "max_abs" || name == "max") return LossKind::MaxAbs;
  if (name == "rel" || name == "relative") return LossKind::Relative;
  if (name == "log") return LossKind::Log;
  return std::nullopt;
}

std::string_view loss_name(LossKind kind) {
  switch (kind) {
    case LossKind::Mse: return "mse";
    case LossKind::Rmse: return "rmse";
    case LossKind::MaxAbs: return "max_abs";
    case LossKind::Relative: return "rel";
    case LossKind::Log: return "log";
  }
  return "mse";
}

LossMetrics loss_metrics(std::span<const double> prediction, std::span<const double> target,
                         std::span<const double> weights) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kLogFloor = 1e-30;
  double sw = 0, se = 0, srel = 0, slog = 0, max_abs = 0;
  bool rel_ok = true, log_ok = true;
  for (std::size_t i = 0; i < target.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (!(w > 0)) continue;
    const double p = prediction[i];
    const double t = target[i];
    if (!std::isfinite(p)) return {kInf, kInf, kInf, kInf, kInf};
    const double d = p - t;
    sw += w;
    se += w * d * d;
    max_abs = std::max(max_abs, std::abs(d));
    if (t != 0) {
      const double r = d / t;
      srel += w * r * r;
    } else {
      rel_ok = false;
    }
    if (t > 0) {
      const double l = std::log(std::max(p, kLogFloor) / t);  // one log a row, not two
      slog += w * l * l;
    } else {
      log_ok = false;
    }
  }
  if (sw == 0) return {};
  LossMetrics m;
  m.mse = se / sw;
  m.rmse = std::sqrt(m.mse);
  m.max_abs = max_abs;
  m.rel = rel_ok ? srel / sw : kNaN;
  m.log = log_ok ? slog / sw : kNaN;
  return m;
}

double loss_value(LossKind kind, const LossMetrics& m) {
  switch (kind) {
    case LossKind::Mse: return m.mse;
    case LossKind::Rmse: return m.rmse;
    case LossKind::MaxAbs: return m.max_abs;
    case LossKind::Relative: return m.rel;
    case LossKind::Log: return m.log;
  }
  return m.mse;
}

double loss_of(LossKind kind, std::span<const double> prediction, std::span<const double> target,
               std::span<const double> weights) {
  if (kind == LossKind::Relative || kind == LossKind::Log)
    return loss_value(kind, loss_metrics(prediction, target, weights));
  double sw = 0, se = 0, mx = 0;
  for (std::size_t i = 0; i < target.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (!(w > 0)) continue;
    const double d = prediction[i] - target[i];
    if (!std::isfinite(d)) return std::numeric_limits<double>::infinity();
    sw += w;
    se += w * d * d;
    mx = std::max(mx, std::abs(d));
  }
  if (sw == 0) return 0.0;
  if (kind == LossKind::MaxAbs) return mx;
  return kind == LossKind::Rmse ? std::sqrt(se / sw) : se / sw;
}

}  // namespace shaderfit
