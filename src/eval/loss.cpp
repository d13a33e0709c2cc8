#include "shaderfit/eval/loss.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shaderfit/eval/metrics.hpp"

namespace shaderfit {

std::optional<Loss> loss_from_name(std::string_view name) {
  if (name == "mse") return Loss::Mse;
  if (name == "rmse") return Loss::Rmse;
  if (name == "max_abs" || name == "max") return Loss::MaxAbs;
  if (name == "max_rel") return Loss::MaxRel;
  if (name == "rel" || name == "relative") return Loss::Relative;
  if (name == "log") return Loss::Log;
  if (name == "display") return Loss::Display;
  return std::nullopt;
}

std::string_view loss_name(Loss loss) {
  switch (loss) {
    case Loss::Mse: return "mse";
    case Loss::Rmse: return "rmse";
    case Loss::MaxAbs: return "max_abs";
    case Loss::MaxRel: return "max_rel";
    case Loss::Relative: return "rel";
    case Loss::Log: return "log";
    case Loss::Display: return "display";
  }
  return "mse";
}

double loss_value(Loss loss, const ErrorMetrics& m) {
  switch (loss) {
    case Loss::Mse:
    case Loss::Display: return m.mse;
    case Loss::Rmse: return m.rmse;
    case Loss::MaxAbs: return m.max_abs;
    case Loss::MaxRel: return m.max_rel;
    case Loss::Relative: return m.rel;
    case Loss::Log: return m.log;
  }
  return m.mse;
}

double loss_of(Loss loss, std::span<const double> prediction, std::span<const double> target,
               std::span<const double> weights) {
  if (loss == Loss::Display) loss = Loss::Mse;
  if (loss != Loss::Mse && loss != Loss::Rmse && loss != Loss::MaxAbs)
    return loss_value(loss, error_metrics(prediction, target, {}, weights));
  // The squared and absolute losses in one pass without the divisions and logarithms.
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
  if (loss == Loss::MaxAbs) return mx;
  return loss == Loss::Rmse ? std::sqrt(se / sw) : se / sw;
}

}  // namespace shaderfit
