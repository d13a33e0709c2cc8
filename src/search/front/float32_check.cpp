#include "search/front/float32_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/evaluate_in.hpp"

namespace shaderfit::search_detail {

Float32Check::Float32Check(const SearchProblem& problem) : problem_(problem) {
  for (const auto& c : problem.inputs) inputs32_.emplace_back(c.begin(), c.end());
  scale_ = 0;
  for (double t : problem.target) scale_ = std::max(scale_, std::abs(t));
  if (!(scale_ > 0)) scale_ = 1;
}

Float32Check::Errors Float32Check::errors(const Expression& e) const {
  const std::size_t rows = problem_.target.size();
  std::vector<const double*> cols64(e.variables.size(), nullptr);
  std::vector<const float*> cols32(e.variables.size(), nullptr);
  for (std::size_t i = 0; i < e.variables.size(); ++i) {
    const auto& names = problem_.input_names;
    const auto it = std::find(names.begin(), names.end(), e.variables[i]);
    if (it == names.end()) continue;  // evaluate() reports the missing column
    const auto k = static_cast<std::size_t>(it - names.begin());
    cols64[i] = problem_.inputs[k].data();
    cols32[i] = inputs32_[k].data();
  }
  std::vector<double> f64(rows);
  std::vector<float> f32(rows);
  evaluate(e, cols64, f64, {.threads = 1});
  evaluate(e, cols32, f32, {.threads = 1});
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Errors out;
  for (std::size_t i = 0; i < rows; ++i) {
    const double y = f32[i];
    const double d = std::abs(y - f64[i]);
    out.max_abs_diff = std::isfinite(d) ? std::max(out.max_abs_diff, d) : kInf;
    const double t = problem_.target[i];
    const double err = std::isfinite(y) ? std::abs(y - t) : kInf;
    out.max_abs = std::max(out.max_abs, err);
    if (t != 0) out.max_rel = std::max(out.max_rel, err / std::abs(t));
  }
  std::vector<double> half(rows);
  evaluate_in(Precision::Half, e, cols64, half);
  for (std::size_t i = 0; i < rows; ++i) {
    const double t = problem_.target[i];
    const double err = std::isfinite(half[i]) ? std::abs(half[i] - t) : kInf;
    out.half_max_abs = std::max(out.half_max_abs, err);
    if (t != 0) out.half_max_rel = std::max(out.half_max_rel, err / std::abs(t));
  }
  return out;
}

double Float32Check::max_abs_diff(const Expression& e) const { return errors(e).max_abs_diff; }

double Float32Check::bound(const FrontMember& m) const {
  const double own = std::isfinite(m.metrics.max_abs) ? m.metrics.max_abs : 0.0;
  return std::max(kFloat32ScaleShare * scale_, kFloat32ErrorShare * own);
}

void Float32Check::apply(FrontMember& m) const {
  const Errors e = errors(m.expression);
  m.float32_max_abs_diff = e.max_abs_diff;
  m.float32_stable = m.float32_max_abs_diff <= bound(m);
  m.float32_max_abs = e.max_abs;
  m.float32_max_rel = e.max_rel;
  m.half_max_abs = e.half_max_abs;
  m.half_max_rel = e.half_max_rel;
}

}  // namespace shaderfit::search_detail
