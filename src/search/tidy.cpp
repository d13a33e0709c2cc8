#include "search/tidy.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "search/float32_check.hpp"
#include "search/pareto.hpp"
#include "search/search_context.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit::search_detail {

namespace {

// A constant this close to a simple value (relative) is snapped with all the others at once.
constexpr double kNearRelative = 1e-6;
// At most this many accepted single snaps per member (each removes a non-simple constant).
constexpr int kMaxSteps = 64;

std::vector<double> make_simple_values() {
  std::vector<double> v = {0.0};
  for (int q = 1; q <= 4; ++q)
    for (int p = 1; p <= 32 * q; ++p) v.push_back(static_cast<double>(p) / q);
  constexpr double pi = std::numbers::pi;
  for (double x :
       {pi / 4, pi / 2, pi, 2 * pi, 4 * pi, 1 / pi, 1 / (2 * pi), 1 / (4 * pi), std::numbers::ln2})
    v.push_back(x);
  const std::size_t positive = v.size();
  for (std::size_t i = 1; i < positive; ++i) v.push_back(-v[i]);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

bool is_simple(double v) {
  const std::span<const double> s = simple_values();
  return std::binary_search(s.begin(), s.end(), v);
}

// e with each parameter written as a literal at its value.
Expression baked(const Expression& e) {
  Expression out = e;
  for (Node& n : out.nodes)
    if (n.op == Op::Param) {
      n.value = e.parameter_values[static_cast<std::size_t>(n.index)];
      n.op = Op::Const;
      n.index = 0;
    }
  out.parameters.clear();
  out.parameter_values.clear();
  return out;
}

// The inverse of baked() for a tidied form of `original`: when the original had parameters,
// each literal that is neither simple nor one of the original's literals becomes a parameter
// p0, p1, ... in order of appearance.
Expression lifted(Expression e, const Expression& original) {
  if (original.parameters.empty()) return e;
  std::vector<double> literals;
  for (const Node& n : original.nodes)
    if (n.op == Op::Const) literals.push_back(n.value);
  for (Node& n : e.nodes) {
    if (n.op != Op::Const || is_simple(n.value) ||
        std::find(literals.begin(), literals.end(), n.value) != literals.end())
      continue;
    std::string name = "p" + std::to_string(e.parameters.size());
    while (std::find(e.variables.begin(), e.variables.end(), name) != e.variables.end())
      name += "_";
    const double value = n.value;
    const std::uint32_t length = n.length;
    n = Node::parameter(static_cast<int>(e.parameters.size()));
    n.length = length;
    e.parameters.push_back(std::move(name));
    e.parameter_values.push_back(value);
  }
  return e;
}

class Tidier {
 public:
  Tidier(const SearchOptions& options, const SearchProblem& problem)
      : ctx_(options, problem), cost_target_(options.cost) {
    simplify_options_.regroup_constants = true;
    simplify_options_.cost = [this](const Expression& e) {
      return expression_cost(e, cost_target_);
    };
    std::vector<double> noisy(problem.target.begin(), problem.target.end());
    for (double& y : noisy) y += kTidyRoundingNoise * std::abs(y);
    floor_ = loss_value(options.loss, ctx_.metrics_of(noisy));
    if (!std::isfinite(floor_)) floor_ = 0;
  }

  // The tidied member, or nullopt when no step was kept.
  std::optional<FrontMember> tidy(const FrontMember& m) {
    limit_ = m.loss + kTidyRelativeLoss * std::abs(m.loss) + floor_;
    original_ = &m.expression;
    current_ = baked(m.expression);
    cost_ = m.cost;
    changed_ = false;
    keep(simplify(current_, simplify_options_));
    snap_near_constants();
    for (int step = 0; step < kMaxSteps && snap_one_constant(); ++step) {
    }
    if (!changed_) return std::nullopt;
    FrontMember t = m;
    t.expression = lifted(current_, m.expression);
    t.formula = to_infix(t.expression, {.substitute_parameters = true});
    t.cost = cost_;
    t.nodes = t.expression.size();
    t.metrics = metrics_;
    t.loss = loss_value(ctx_.options.loss, metrics_);
    return t;
  }

  std::uint64_t node_evaluations() const { return ctx_.node_evaluations.load(); }

 private:
  // Keeps `candidate` as the current form when it differs, costs no more, is finite everywhere
  // and its loss is within the limit.
  bool keep(Expression candidate) {
    if (candidate == current_) return false;
    const double cost = expression_cost(lifted(candidate, *original_), cost_target_);
    if (!(cost <= cost_)) return false;
    std::vector<double> prediction(ctx_.rows);
    ctx_.predict(candidate, prediction);
    for (double v : prediction)
      if (!std::isfinite(v)) return false;
    const ErrorMetrics metrics = ctx_.metrics_of(prediction);
    const double loss = loss_value(ctx_.options.loss, metrics);
    if (!(loss <= limit_) || !ctx_.finite_everywhere(candidate)) return false;
    current_ = std::move(candidate);
    cost_ = cost;
    metrics_ = metrics;
    changed_ = true;
    return true;
  }

  // Snapping works on the regrouped form even when that alone was not kept: regrouping can
  // leave a residue (k - d / c of a cancelled offset) that is only noise once snapped with the
  // rest.
  void snap_near_constants() {
    const Expression base = simplify(current_, simplify_options_);
    double scale = 1;
    for (const Node& n : base.nodes)
      if (n.op == Op::Const) scale = std::max(scale, std::abs(n.value));
    Expression all = base;
    bool any = false;
    for (Node& n : all.nodes) {
      if (n.op != Op::Const) continue;
      const double s = nearest_simple_value(n.value);
      if (s == n.value || std::abs(n.value - s) > kNearRelative * (s == 0 ? scale : std::abs(s)))
        continue;
      n.value = s;
      any = true;
    }
    if (any) keep(simplify(all, simplify_options_));
  }

  bool snap_one_constant() {
    const Expression base = simplify(current_, simplify_options_);
    for (std::size_t i = 0; i < base.nodes.size(); ++i) {
      const Node& n = base.nodes[i];
      if (n.op != Op::Const) continue;
      const double s = nearest_simple_value(n.value);
      if (s == n.value) continue;
      Expression t = base;
      t.nodes[i].value = s;
      if (keep(simplify(t, simplify_options_))) return true;
    }
    return false;
  }

  SearchContext ctx_;
  CostTarget cost_target_;
  SimplifyOptions simplify_options_;
  double floor_ = 0;
  double limit_ = 0;
  const Expression* original_ = nullptr;
  Expression current_;
  double cost_ = 0;
  ErrorMetrics metrics_;
  bool changed_ = false;
};

}  // namespace

std::span<const double> simple_values() {
  static const std::vector<double> values = make_simple_values();
  return values;
}

double nearest_simple_value(double v) {
  const std::span<const double> s = simple_values();
  if (!std::isfinite(v)) return v;
  const auto above = std::lower_bound(s.begin(), s.end(), v);
  if (above == s.begin()) return *above;
  if (above == s.end()) return s.back();
  const double lo = *(above - 1), hi = *above;
  return v - lo <= hi - v ? lo : hi;
}

std::vector<FrontMember> tidy_front(const SearchOptions& options, const SearchProblem& problem,
                                    std::vector<FrontMember> front,
                                    std::uint64_t* node_evaluations) {
  if (front.empty()) return front;
  Tidier tidier(options, problem);
  std::optional<Float32Check> float32;
  ParetoFront tidied;
  for (FrontMember& m : front) {
    if (std::optional<FrontMember> t = tidier.tidy(m)) {
      if (!float32) float32.emplace(problem);
      float32->apply(*t);
      tidied.offer(std::move(*t));
    } else {
      tidied.offer(std::move(m));
    }
  }
  if (node_evaluations != nullptr) *node_evaluations += tidier.node_evaluations();
  return tidied.members();
}

}  // namespace shaderfit::search_detail
