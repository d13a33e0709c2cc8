#include "search/front/tidy.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "search/front/float32_check.hpp"
#include "search/pareto.hpp"
#include "search/search_context.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/parse.hpp"
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
  // r b and 1 / (r b) for r = k / q: pi's multiples and fractions (angles, 4 pi epsilon), ln 2's
  // (exp and log written with exp2 and log2). In long double, so that each is the double nearest
  // its real value.
  using Real = long double;
  const auto multiples = [&v](Real b, int k_max) {
    for (int q = 1; q <= 4; ++q)
      for (int k = 1; k <= k_max; ++k) {
        v.push_back(static_cast<double>(k * b / q));
        v.push_back(static_cast<double>(q / (k * b)));
      }
  };
  multiples(std::numbers::pi_v<Real>, 8);
  multiples(std::numbers::ln2_v<Real>, 4);
  for (Real x : {Real{2}, std::numbers::pi_v<Real>, 2 * std::numbers::pi_v<Real>}) {
    v.push_back(static_cast<double>(std::sqrt(x)));
    v.push_back(static_cast<double>(1 / std::sqrt(x)));
  }
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

// What the formula's exact text reads back to (the printer moves signs out of groups and into
// sums, which the instruction model may count one fewer).
Expression exact_text_form(const Expression& e) {
  ParseOptions o;
  o.variables = e.variables;
  o.parameters = e.parameters;
  o.parameter_values = e.parameter_values;
  Expression back = parse_formula(to_infix(e), o);
  back.variables = e.variables;
  return back;
}

class Tidier {
 public:
  Tidier(const SearchOptions& options, const SearchProblem& problem)
      : ctx_(options, problem), options_(options), noise_rmse_(noise_level_rmse(problem)) {
    simplify_options_.regroup_constants = true;
    simplify_options_.merge_calls = true;
    simplify_options_.cost = [this](const Expression& e) { return formula_cost(e, options_); };
    std::vector<double> noisy(problem.target.begin(), problem.target.end());
    for (double& y : noisy) y += kTidyRoundingNoise * std::abs(y);
    floor_ = loss_value(options.loss, ctx_.metrics_of(noisy));
    if (!std::isfinite(floor_)) floor_ = 0;
  }

  // The tidied member, or nullopt when no step was kept.
  std::optional<FrontMember> tidy(const FrontMember& m) {
    limit_ = m.loss + kTidyRelativeLoss * std::abs(m.loss) + floor_;
    noise_ = m.metrics.rmse <= noise_rmse_;
    original_ = &m.expression;
    current_ = baked(m.expression);
    cost_ = m.cost;
    metrics_ = m.metrics;
    changed_ = false;
    keep(simplify(current_, simplify_options_));
    drop_idle_branches();
    snap_constants();
    if (!noise_ && metrics_.rmse <= noise_rmse_) {
      // Tidied to noise level (a constant snapped to the value the data was made with): the
      // noise-level rule from here on.
      noise_ = true;
      snap_constants();
    }
    if (Expression back = exact_text_form(current_);
        formula_cost(lifted(back, *original_), options_) < cost_)
      keep(std::move(back));
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
  // and its error is acceptable: at noise level for a member at noise level, else its loss
  // within the limit.
  bool keep(Expression candidate) {
    if (candidate == current_) return false;
    const double cost = formula_cost(lifted(candidate, *original_), options_);
    if (!(cost <= cost_)) return false;
    std::vector<double> prediction(ctx_.rows);
    ctx_.predict_shown(candidate, prediction);
    for (double v : prediction)
      if (!std::isfinite(v)) return false;
    const ErrorMetrics metrics = ctx_.metrics_of(prediction);
    const bool acceptable =
        noise_ ? metrics.rmse <= noise_rmse_ : loss_value(ctx_.options.loss, metrics) <= limit_;
    if (!acceptable || !ctx_.finite_everywhere(candidate)) return false;
    current_ = std::move(candidate);
    cost_ = cost;
    metrics_ = metrics;
    changed_ = true;
    return true;
  }

  // A min, max, saturate, abs or select whose own result on the rows is one of its operands (or
  // saturate's bound 1, or abs's operand negated; idle()) is replaced by it: a clamp that never
  // acts on the data is no part of the function it shows, and outside the rows (a wider
  // domain) it would cut it. Repeated while one is dropped; each replacement passes keep().
  void drop_idle_branches() {
    for (int step = 0; step < kMaxSteps; ++step) {
      const Expression base = current_;
      bool dropped = false;
      for (std::size_t i = 0; i < base.nodes.size() && !dropped; ++i) {
        const Op op = base.nodes[i].op;
        if (op != Op::Min && op != Op::Max && op != Op::Saturate && op != Op::Abs &&
            op != Op::Select)
          continue;
        std::vector<std::vector<Node>> options;
        // The operands, last first: each ends where the next one starts.
        std::size_t end = i;
        std::vector<std::vector<Node>> operands;
        for (int k = 0; k < arity(op); ++k) {
          const std::size_t last = end - 1;
          const std::size_t first = last - base.nodes[last].length;
          operands.insert(operands.begin(), std::vector<Node>(base.nodes.begin() + first,
                                                              base.nodes.begin() + last + 1));
          end = first;
        }
        if (op == Op::Select) {
          options = {operands[1], operands[2]};
        } else {
          options = operands;
          if (op == Op::Saturate) options.push_back({Node::constant(1.0)});
          if (op == Op::Abs) {  // abs(a) = -a where a <= 0 on every row
            options.push_back(operands[0]);
            options.back().push_back(Node::op_node(Op::Neg));
          }
        }
        for (const std::vector<Node>& with : options) {
          if (!idle(base, end, i, with)) continue;
          Expression t = base;
          t.nodes.erase(t.nodes.begin() + static_cast<std::ptrdiff_t>(end),
                        t.nodes.begin() + static_cast<std::ptrdiff_t>(i) + 1);
          t.nodes.insert(t.nodes.begin() + static_cast<std::ptrdiff_t>(end), with.begin(),
                         with.end());
          t.update_lengths();
          if (keep(simplify(t, simplify_options_))) {
            dropped = true;
            break;
          }
        }
      }
      if (!dropped) return;
    }
  }

  // Whether the subexpression nodes [begin, last] of `e` equals `with` on every row: the clamp
  // there never acts, as such (not only where the rest of the formula hides what it does: a
  // max(a, 0) whose 0 a zero numerator masks is no idle clamp, and without it the quotient is
  // 0 / 0 on a plane between the rows).
  bool idle(const Expression& e, std::size_t begin, std::size_t last,
            const std::vector<Node>& with) {
    auto values = [&](std::vector<Node> nodes) {
      Expression part = e;
      part.nodes = std::move(nodes);
      part.update_lengths();
      std::vector<double> v(ctx_.rows);
      ctx_.predict_shown(part, v);
      return v;
    };
    const std::vector<double> a = values(std::vector<Node>(
        e.nodes.begin() + static_cast<std::ptrdiff_t>(begin),
        e.nodes.begin() + static_cast<std::ptrdiff_t>(last) + 1));
    const std::vector<double> b = values(with);
    for (std::size_t r = 0; r < a.size(); ++r)
      if (!(a[r] == b[r] || (std::isnan(a[r]) && std::isnan(b[r])))) return false;
    return true;
  }

  void snap_constants() {
    snap_near_constants();
    for (int step = 0; step < kMaxSteps && snap_one_constant(); ++step) {
    }
  }

  // Which constants snap_near_constants snaps.
  enum class Near { All, Zero, NonZero };

  // The constants near a simple value snapped at once: all of them, else those near 0 alone
  // (noise terms), else the others alone. Noise terms of an exact fit compensate each other (and
  // a near-simple constant's own noise), so that one at a time each raises the error while all
  // at once they do not. Snapping works on the regrouped form even when that alone was not kept:
  // regrouping can leave a residue (k - d / c of a cancelled offset) that is only noise once
  // snapped with the rest.
  void snap_near_constants() {
    const Expression base = simplify(current_, simplify_options_);
    double scale = 1;
    for (const Node& n : base.nodes)
      if (n.op == Op::Const) scale = std::max(scale, std::abs(n.value));
    for (const Near which : {Near::All, Near::Zero, Near::NonZero}) {
      Expression snapped = base;
      bool any = false;
      for (Node& n : snapped.nodes) {
        if (n.op != Op::Const) continue;
        const double s = nearest_simple_value(n.value);
        if (s == n.value || (which == Near::Zero && s != 0) || (which == Near::NonZero && s == 0) ||
            std::abs(n.value - s) > kNearRelative * (s == 0 ? scale : std::abs(s)))
          continue;
        n.value = s;
        any = true;
      }
      if (any && keep(simplify(snapped, simplify_options_))) return;
    }
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
  const SearchOptions& options_;
  SimplifyOptions simplify_options_;
  double noise_rmse_ = 0;
  double floor_ = 0;
  double limit_ = 0;
  bool noise_ = false;  // whether the member is at noise level: the rule keep() applies
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

double noise_level_rmse(const SearchProblem& problem) {
  const std::vector<double> zero(problem.target.size(), 0.0);
  const double rms = error_metrics(zero, problem.target, {}, problem.weights).rmse;
  return std::isfinite(rms) ? kNoiseLevel * rms : 0.0;
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
  std::vector<FrontMember> out = tidied.members();
  const double noise_rmse = noise_level_rmse(problem);
  const auto first = std::find_if(
      out.begin(), out.end(), [&](const FrontMember& m) { return m.metrics.rmse <= noise_rmse; });
  if (first != out.end()) out.erase(first + 1, out.end());
  return out;
}

void count_as_printed(std::vector<FrontMember>& front, const SearchOptions& options) {
  bool changed = false;
  for (FrontMember& m : front) {
    Expression back = exact_text_form(m.expression);
    if (const double cost = formula_cost(back, options); cost < m.cost) {
      m.expression = std::move(back);
      m.formula = to_infix(m.expression, {.substitute_parameters = true});
      m.cost = cost;
      m.nodes = m.expression.size();
      changed = true;
    }
    // The text's constants are literals, which the model may count fewer than parameters (a
    // divisor's reciprocal is folded): what the shader is given is the text.
    const double shown = formula_cost(
        parse_formula(m.formula, {.variables = m.expression.variables}), options);
    if (shown < m.cost) {
      m.cost = shown;
      changed = true;
    }
  }
  if (!changed) return;
  ParetoFront pareto;  // a member now cheaper may dominate another
  for (FrontMember& m : front) pareto.offer(std::move(m));
  front = pareto.members();
}

void mark_minor_steps(std::vector<FrontMember>& front, double min_step) {
  std::vector<std::size_t> order(front.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return front[a].cost < front[b].cost; });
  const FrontMember* shown = nullptr;
  for (std::size_t i : order) {
    FrontMember& m = front[i];
    m.minor_step = shown != nullptr && std::isfinite(m.loss) && std::isfinite(shown->loss) &&
                   !(m.loss < (1 - min_step) * shown->loss);
    if (!m.minor_step) shown = &m;
  }
}

}  // namespace shaderfit::search_detail
