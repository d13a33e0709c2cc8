#include "shaderfit/verify/worst_case.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "shaderfit/core/error.hpp"
#include "shaderfit/data/sampling.hpp"
#include "shaderfit/eval/evaluate.hpp"

namespace shaderfit {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// |f - t| and |f - t| / |t| as eval/metrics.hpp defines them: the relative error counts only
// where the reference is not 0.
ErrorPoint error_at(std::vector<double> point, double f, double t) {
  ErrorPoint e;
  e.point = std::move(point);
  e.abs_error = std::isfinite(f) ? std::abs(f - t) : kInf;
  e.rel_error = t != 0 ? e.abs_error / std::abs(t) : 0;
  return e;
}

// The dense design: the problem's own with `density` times its points, or for grids given by
// counts, each axis refined so that the whole grid has about `density` times the points.
SampleColumns dense_design(const std::vector<reference::DomainAxis>& domain,
                           const WorstCaseOptions& o) {
  const bool counted = std::all_of(domain.begin(), domain.end(),
                                   [](const reference::DomainAxis& a) { return a.count > 0; });
  if (!counted) return sample_domain(domain, o.samples, std::max<std::size_t>(o.density, 1));
  // Each axis's count times density^(1 / axes), rounded (rounding up would make a grid of many
  // axes 2^axes times denser: 256 times for 8).
  const double per_axis = std::pow(static_cast<double>(std::max<std::size_t>(o.density, 1)),
                                   1.0 / static_cast<double>(domain.size()));
  std::vector<reference::DomainAxis> axes = domain;
  for (reference::DomainAxis& a : axes) {
    a.count = std::max(a.count, static_cast<std::size_t>(
                                    std::lround(static_cast<double>(a.count) * per_axis)));
    a.spacing = reference::Spacing::Endpoints;  // the ends are where errors often peak
  }
  return sample_domain(axes, 0, 1);
}

}  // namespace

WorstCaseSearch::WorstCaseSearch(const reference::ReferenceFunction& reference,
                                 std::vector<std::string> inputs, const WorstCaseOptions& options)
    : reference_(reference), input_names_(std::move(inputs)), options_(options) {
  reference_.validate();
  input_outputs_ = reference_.output_indices(input_names_);
  target_output_ = reference_.program.find_output(reference_.target);
  dense_domain_ = dense_design(reference_.domain, options_);
  std::vector<std::span<const double>> columns(dense_domain_.begin(), dense_domain_.end());
  std::vector<std::vector<double>> outputs = reference_.program.evaluate_columns(columns);
  // Points where the reference itself is not finite are outside what is approximated (a
  // problem drops them only on request); the check leaves them out too.
  const std::vector<double>& t = outputs[static_cast<std::size_t>(target_output_)];
  std::vector<std::size_t> keep;
  keep.reserve(t.size());
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::isfinite(t[i])) keep.push_back(i);
  auto pick = [&](const std::vector<double>& c) {
    std::vector<double> out(keep.size());
    for (std::size_t k = 0; k < keep.size(); ++k) out[k] = c[keep[k]];
    return out;
  };
  for (std::vector<double>& c : dense_domain_) c = pick(c);
  for (const int o : input_outputs_)
    dense_inputs_.push_back(pick(outputs[static_cast<std::size_t>(o)]));
  dense_target_ = pick(t);
  for (const std::vector<double>& c : dense_inputs_)
    dense_inputs32_.emplace_back(c.begin(), c.end());
}

std::size_t WorstCaseSearch::dense_points() const { return dense_target_.size(); }

ErrorPoint WorstCaseSearch::certified_worst(const Expression& formula,
                                            const Certificate& certificate) const {
  ErrorPoint met{certificate.attained_point, certificate.attained, 0};
  if (!certificate.trouble_point.empty()) {
    ErrorPoint near = refine(formula, certificate.trouble_point);
    if (!(near.abs_error <= met.abs_error)) met = std::move(near);
  }
  return met;
}

ErrorPoint WorstCaseSearch::refine(const Expression& formula, std::span<const double> point) const {
  const std::size_t dims = reference_.domain.size();
  std::vector<double> in(input_names_.size());
  auto error_of = [&](const std::vector<double>& p) {
    double t = 0;
    at(p, in, &t);
    if (!std::isfinite(t)) return ErrorPoint{p, 0, 0};  // outside what is approximated
    return error_at(p, evaluate_scalar(formula, in), t);
  };
  std::vector<double> start(point.begin(), point.end());
  start.resize(dims);
  std::vector<double> h(dims);
  for (std::size_t d = 0; d < dims; ++d) {
    const reference::DomainAxis& a = reference_.domain[d];
    start[d] = std::clamp(start[d], a.lo, a.hi);
    h[d] = 1e-6 * (a.hi - a.lo);
  }
  ErrorPoint best = error_of(start);
  for (int round = 0; round < 40 && std::isfinite(best.abs_error); ++round) {
    bool improved = false;
    for (std::size_t d = 0; d < dims; ++d) {
      for (const double dir : {1.0, -1.0}) {
        std::vector<double> p = best.point;
        p[d] = std::clamp(p[d] + dir * h[d], reference_.domain[d].lo, reference_.domain[d].hi);
        if (p[d] == best.point[d]) continue;
        ErrorPoint e = error_of(p);
        if (!(e.abs_error <= best.abs_error)) {
          best = std::move(e);
          improved = true;
        }
      }
    }
    if (!improved)
      for (double& v : h) v *= 0.5;
  }
  return best;
}

void WorstCaseSearch::at(std::span<const double> point, std::span<double> inputs,
                         double* target) const {
  std::vector<double> out(reference_.program.outputs.size());
  reference_.program.evaluate_all(point, out);
  for (std::size_t i = 0; i < input_outputs_.size(); ++i)
    inputs[i] = out[static_cast<std::size_t>(input_outputs_[i])];
  *target = out[static_cast<std::size_t>(target_output_)];
}

WorstCase WorstCaseSearch::check(const Expression& formula) const {
  if (formula.variables != input_names_)
    throw Error("the formula's variables differ from the inputs the check was built for",
                {"WorstCaseSearch::check"});
  const std::size_t n = dense_target_.size();
  const std::size_t dims = dense_domain_.size();
  WorstCase result;
  if (n == 0) return result;
  std::vector<const double*> columns;
  for (const std::vector<double>& c : dense_inputs_) columns.push_back(c.data());
  std::vector<double> f(n);
  evaluate(formula, columns, f, {.threads = options_.threads});
  result.evaluations = n;

  std::vector<double> err(n);
  std::size_t worst_abs = 0, worst_rel = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dense_target_[i];
    err[i] = std::isfinite(f[i]) ? std::abs(f[i] - t) : kInf;
    if (!(err[i] <= err[worst_abs])) worst_abs = i;  // the first non-finite point wins
    const double rel = t != 0 ? err[i] / std::abs(t) : 0;
    const double best_rel =
        dense_target_[worst_rel] != 0 ? err[worst_rel] / std::abs(dense_target_[worst_rel]) : 0;
    if (rel > best_rel) worst_rel = i;
  }
  {
    std::vector<const float*> columns32;
    for (const std::vector<float>& c : dense_inputs32_) columns32.push_back(c.data());
    std::vector<float> f_float(n);
    evaluate(formula, columns32, f_float, {.threads = options_.threads});
    for (std::size_t i = 0; i < n; ++i) {
      const double t = dense_target_[i];
      const double e =
          std::isfinite(f_float[i]) ? std::abs(static_cast<double>(f_float[i]) - t) : kInf;
      result.float32_max_abs = std::max(result.float32_max_abs, e);
      if (t != 0) result.float32_max_rel = std::max(result.float32_max_rel, e / std::abs(t));
    }
  }
  auto point_at = [&](std::size_t i) {
    std::vector<double> p(dims);
    for (std::size_t d = 0; d < dims; ++d) p[d] = dense_domain_[d][i];
    return p;
  };
  result.worst_abs = error_at(point_at(worst_abs), f[worst_abs], dense_target_[worst_abs]);
  result.worst_rel = error_at(point_at(worst_rel), f[worst_rel], dense_target_[worst_rel]);
  result.max_abs = result.worst_abs.abs_error;
  result.max_rel = result.worst_rel.rel_error;
  if (!std::isfinite(result.max_abs)) {
    result.finite = false;
    result.points.push_back(result.worst_abs);
    return result;
  }

  // One point, evaluated node by node (the batched evaluator's exp2, log2, ... are within a few
  // ulp of these).
  std::vector<double> in(input_names_.size());
  auto error_of = [&](const std::vector<double>& p) {
    double t = 0;
    at(p, in, &t);
    ++result.evaluations;
    if (!std::isfinite(t)) return ErrorPoint{p, 0, 0};  // outside what is approximated
    return error_at(p, evaluate_scalar(formula, in), t);
  };

  // Starting points: local maxima of |error| among the dense points, worst first, at most
  // `starts` of them (and every one within 10% of the worst in one dimension, where an
  // equioscillating fit has many peaks of nearly the same height), kept apart from each other.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::vector<double> lo(dims), hi(dims), step(dims);
  for (std::size_t d = 0; d < dims; ++d) {
    lo[d] = reference_.domain[d].lo;
    hi[d] = reference_.domain[d].hi;
    // The spacing of the dense design, as if it were a regular grid.
    step[d] = (hi[d] - lo[d]) /
              std::max(1.0, std::pow(static_cast<double>(n), 1.0 / static_cast<double>(dims)));
  }
  std::vector<std::size_t> starts;
  if (dims == 1) {
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return dense_domain_[0][a] < dense_domain_[0][b];
    });
    std::vector<std::size_t> peaks;
    for (std::size_t k = 0; k < n; ++k) {
      const double e = err[order[k]];
      if ((k == 0 || e >= err[order[k - 1]]) && (k + 1 == n || e >= err[order[k + 1]]))
        peaks.push_back(k);  // position in sorted order
    }
    std::sort(peaks.begin(), peaks.end(),
              [&](std::size_t a, std::size_t b) { return err[order[a]] > err[order[b]]; });
    constexpr std::size_t kMaxPeaks = 64;
    for (std::size_t j = 0; j < peaks.size() && starts.size() < kMaxPeaks; ++j) {
      if (j >= options_.starts && err[order[peaks[j]]] < 0.9 * result.max_abs) break;
      starts.push_back(peaks[j]);
    }
    // Golden-section search of |error| between the peak's neighbours.
    constexpr double kGolden = 0.6180339887498949;
    for (const std::size_t k : starts) {
      double a = k > 0 ? dense_domain_[0][order[k - 1]] : lo[0];
      double b = k + 1 < n ? dense_domain_[0][order[k + 1]] : hi[0];
      ErrorPoint best =
          error_at({dense_domain_[0][order[k]]}, f[order[k]], dense_target_[order[k]]);
      double c = b - kGolden * (b - a), d = a + kGolden * (b - a);
      ErrorPoint ec = error_of({c}), ed = error_of({d});
      for (int it = 0; it < 60 && b - a > 1e-15 * std::max(1.0, std::abs(a)); ++it) {
        if (ec.abs_error >= ed.abs_error) {
          b = d;
          d = c;
          ed = ec;
          c = b - kGolden * (b - a);
          ec = error_of({c});
        } else {
          a = c;
          c = d;
          ec = ed;
          d = a + kGolden * (b - a);
          ed = error_of({d});
        }
      }
      for (const ErrorPoint* e : {&ec, &ed})
        if (e->abs_error > best.abs_error) best = *e;
      result.points.push_back(std::move(best));
    }
  } else {
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return err[a] > err[b]; });
    // Kept apart by three design spacings in every axis (scaled).
    for (std::size_t k = 0; k < n && starts.size() < options_.starts; ++k) {
      const std::size_t i = order[k];
      bool apart = true;
      for (const std::size_t s : starts) {
        bool near = true;
        for (std::size_t d = 0; d < dims && near; ++d)
          near = std::abs(dense_domain_[d][i] - dense_domain_[d][s]) <= 3 * step[d];
        if (near) {
          apart = false;
          break;
        }
      }
      if (apart) starts.push_back(i);
    }
    // Compass search within the box: each axis up and down by the step, halved when nothing
    // improves, from the design's spacing down to a millionth of it.
    for (const std::size_t i : starts) {
      ErrorPoint best = error_at(point_at(i), f[i], dense_target_[i]);
      std::vector<double> h = step;
      for (int round = 0; round < 20; ++round) {
        bool improved = false;
        for (std::size_t d = 0; d < dims; ++d) {
          for (const double dir : {1.0, -1.0}) {
            std::vector<double> p = best.point;
            p[d] = std::clamp(p[d] + dir * h[d], lo[d], hi[d]);
            if (p[d] == best.point[d]) continue;
            ErrorPoint e = error_of(p);
            if (e.abs_error > best.abs_error) {
              best = std::move(e);
              improved = true;
            }
          }
        }
        if (!improved)
          for (double& v : h) v *= 0.5;
      }
      result.points.push_back(std::move(best));
    }
  }
  std::sort(result.points.begin(), result.points.end(),
            [](const ErrorPoint& a, const ErrorPoint& b) { return a.abs_error > b.abs_error; });
  for (const ErrorPoint& p : result.points) {
    if (!std::isfinite(p.abs_error)) result.finite = false;
    if (!(p.abs_error <= result.max_abs)) {
      result.max_abs = p.abs_error;
      result.worst_abs = p;
    }
    if (p.rel_error > result.max_rel) {
      result.max_rel = p.rel_error;
      result.worst_rel = p;
    }
  }
  return result;
}

}  // namespace shaderfit
