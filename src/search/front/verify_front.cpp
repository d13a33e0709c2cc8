#include "search/front/verify_front.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "search/front/float32_check.hpp"
#include "search/starts/start.hpp"
#include "shaderfit/core/parallel.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/verify/certify.hpp"
#include "shaderfit/verify/worst_case.hpp"

namespace shaderfit::search_detail {

namespace {

std::vector<double> values_on(const Expression& e, const SearchProblem& p) {
  std::vector<const double*> columns;
  for (const std::vector<double>& c : p.inputs) columns.push_back(c.data());
  std::vector<double> f(p.target.size());
  evaluate(e, columns, f, {.threads = 1});
  return f;
}

ErrorMetrics metrics_on(const Expression& e, const SearchProblem& p) {
  return error_metrics(values_on(e, p), p.target, {}, p.weights);
}

// The metrics on the rows, with max_abs and max_rel raised to what the check found.
ErrorMetrics with_check(ErrorMetrics m, const WorstCase& c) {
  m.max_abs = std::max(m.max_abs, c.max_abs);
  m.max_rel = std::max(m.max_rel, c.max_rel);
  return m;
}

// The rows a refit sees: every k-th row of the problem (at most about kRefitRows), every row
// where e's error is within half of its largest (where a minimax fit is decided), then the
// given domain points (weight 1).
constexpr std::size_t kRefitRows = 2048;
SearchProblem refit_rows(const Expression& e, const SearchProblem& p, const WorstCaseSearch& w,
                         const std::vector<ErrorPoint>& points) {
  const std::vector<double> f = values_on(e, p);
  double worst = 0;
  for (std::size_t i = 0; i < f.size(); ++i) worst = std::max(worst, std::abs(f[i] - p.target[i]));
  const std::size_t stride = std::max<std::size_t>(1, p.target.size() / kRefitRows);
  SearchProblem r;
  r.input_names = p.input_names;
  r.inputs.resize(p.inputs.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (i % stride != 0 && !(std::abs(f[i] - p.target[i]) >= 0.5 * worst)) continue;
    for (std::size_t k = 0; k < p.inputs.size(); ++k) r.inputs[k].push_back(p.inputs[k][i]);
    r.target.push_back(p.target[i]);
    if (!p.weights.empty()) r.weights.push_back(p.weights[i]);
  }
  std::vector<double> in(p.inputs.size());
  for (const ErrorPoint& point : points) {
    double t = 0;
    w.at(point.point, in, &t);
    for (std::size_t k = 0; k < in.size(); ++k) r.inputs[k].push_back(in[k]);
    r.target.push_back(t);
    if (!p.weights.empty()) r.weights.push_back(1.0);
  }
  return r;
}

struct Checked {
  Expression expression;
  ErrorMetrics metrics;  // on the problem's rows, max_abs and max_rel from the check too
  WorstCase check;
  double loss = 0;
  bool refitted = false;
};

Checked check_member(const Expression& e, const SearchOptions& options,
                     const SearchProblem& problem, const WorstCaseSearch& w) {
  Checked best{e, {}, w.check(e), 0};
  const ErrorMetrics at_rows = metrics_on(e, problem);
  best.metrics = with_check(at_rows, best.check);
  best.loss = loss_value(options.loss, best.metrics);
  if (!best.check.finite || e.parameters.empty()) return best;
  // The points found so far between the samples; each refit sees all of them.
  std::vector<ErrorPoint> found;
  double sampled = at_rows.max_abs;
  for (int round = 0; round < kMaxRefits; ++round) {
    if (!(best.check.max_abs > sampled * (1 + kRefitExcess))) break;
    for (const ErrorPoint& p : best.check.points)
      if (p.abs_error > sampled) found.push_back(p);
    const SearchProblem rows = refit_rows(best.expression, problem, w, found);
    Checked next{refit_for_loss(best.expression, options, rows), {}, {}, 0, true};
    next.check = w.check(next.expression);
    if (!next.check.finite) break;
    const ErrorMetrics next_rows = metrics_on(next.expression, problem);
    next.metrics = with_check(next_rows, next.check);
    next.loss = loss_value(options.loss, next.metrics);
    if (!(next.loss < best.loss)) break;
    best = std::move(next);
    sampled = next_rows.max_abs;
  }
  return best;
}

}  // namespace

std::vector<FrontMember> verify_front(const SearchOptions& options, const SearchProblem& problem,
                                      std::vector<FrontMember> front, SearchSummary* summary) {
  if (!problem.reference) return front;
  const auto t0 = std::chrono::steady_clock::now();
  WorstCaseOptions wo;
  wo.samples = problem.reference_samples;
  wo.threads = 1;  // the members are checked in parallel
  const WorstCaseSearch w(*problem.reference, problem.input_names, wo);
  const Float32Check float32(problem);
  // Members in parallel, each on one thread (a member's check and refits are independent).
  std::vector<std::optional<Checked>> checked(front.size());
  parallel_for(
      front.size(), 1,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
          checked[i] = check_member(front[i].expression, options, problem, w);
      },
      options.threads);
  std::vector<FrontMember> kept;
  for (std::size_t i = 0; i < front.size(); ++i) {
    FrontMember& m = front[i];
    Checked& c = *checked[i];
    if (!c.check.finite) {
      ++summary->dropped_not_finite;
      continue;
    }
    if (c.refitted) {
      m.expression = std::move(c.expression);
      m.formula = to_infix(m.expression, {.substitute_parameters = true});
    }
    m.metrics = c.metrics;
    m.loss = c.loss;
    if (options.precision != Precision::Double) {
      // The error in the shader's precision at the samples; between them the float64 check's.
      std::vector<const double*> columns;
      for (const std::vector<double>& col : problem.inputs) columns.push_back(col.data());
      std::vector<double> f(problem.target.size());
      evaluate_in(options.precision, m.expression, columns, f);
      m.metrics = with_check(error_metrics(f, problem.target, {}, problem.weights), c.check);
      m.loss = loss_value(options.loss, m.metrics);
    }
    m.checked_between_samples = true;
    m.worst_point =
        c.check.max_abs >= c.metrics.max_abs ? c.check.worst_abs.point : std::vector<double>{};
    float32.apply(m);
    m.float32_max_abs = std::max(m.float32_max_abs, c.check.float32_max_abs);
    m.float32_max_rel = std::max(m.float32_max_rel, c.check.float32_max_rel);
    kept.push_back(std::move(m));
  }
  if (options.certify) {
    CertifyOptions co;
    co.time_limit_s = options.certify_time_limit_s;
    std::vector<char> undefined(kept.size(), 0);
    parallel_for(
        kept.size(), 1,
        [&](std::size_t begin, std::size_t end) {
          for (std::size_t i = begin; i < end; ++i) {
            FrontMember& m = kept[i];
            const Certificate cert =
                certify(m.expression, problem.input_names, *problem.reference, co);
            m.certified_max_abs = cert.bound;
            m.certified_converged = cert.converged;
            m.certify_time_s = cert.time_s;
            m.certify_note = cert.note;
            // What the certification met is attained too (a pole between the samples blows up
            // near where it found no finite bound).
            const ErrorPoint met = w.certified_worst(m.expression, cert);
            // With certification asked for, a member with no finite bound is not kept: its
            // error may be unbounded (a pole between the samples) or undefined somewhere.
            if (!std::isfinite(met.abs_error) || !std::isfinite(cert.bound)) undefined[i] = 1;
            if (met.abs_error > m.metrics.max_abs && std::isfinite(met.abs_error)) {
              m.metrics.max_abs = met.abs_error;
              m.worst_point = met.point;
              m.loss = loss_value(options.loss, m.metrics);
            }
          }
        },
        options.threads);
    std::vector<FrontMember> defined;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      if (undefined[i] != 0) {
        ++summary->dropped_no_bound;
        summary->dropped_notes.push_back(
            fmt::format("cost {:g}: {}", kept[i].cost, kept[i].certify_note));
      } else {
        defined.push_back(std::move(kept[i]));
      }
    }
    kept = std::move(defined);
  }
  // The front again: cheapest first, each member strictly better than every cheaper one.
  std::stable_sort(kept.begin(), kept.end(),
                   [](const FrontMember& a, const FrontMember& b) { return a.cost < b.cost; });
  std::vector<FrontMember> out;
  for (FrontMember& m : kept) {
    while (!out.empty() && out.back().cost == m.cost && m.loss < out.back().loss) out.pop_back();
    if (out.empty() || m.loss < out.back().loss) out.push_back(std::move(m));
  }
  summary->check_time_s +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace shaderfit::search_detail
