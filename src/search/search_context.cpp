#include "search/search_context.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <thread>

#include "search/checkpoint.hpp"
#include "search/uniform_terminals.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/eval/evaluate_in.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit::search_detail {

Loss screen_loss(Loss loss) { return loss == Loss::MaxRel ? Loss::MaxAbs : loss; }

double screen_weight(Loss loss, double w, double y) {
  switch (loss) {
    case Loss::MaxAbs: return w > 0 ? 1.0 : 0.0;
    case Loss::MaxRel: return w > 0 && y != 0 ? 1 / std::abs(y) : 0.0;
    default: return w;
  }
}

std::vector<std::size_t> stratified_rows(std::span<const double> target,
                                         std::vector<std::size_t> rows, std::size_t wanted,
                                         Rng& rng) {
  if (rows.size() <= wanted) {
    std::sort(rows.begin(), rows.end());
    return rows;
  }
  std::stable_sort(rows.begin(), rows.end(),
                   [&](std::size_t a, std::size_t b) { return target[a] < target[b]; });
  std::vector<std::size_t> picked;
  const std::size_t n = rows.size();
  for (std::size_t k = 0; k < wanted; ++k) {
    const std::size_t lo = k * n / wanted, hi = (k + 1) * n / wanted;
    picked.push_back(rows[lo + static_cast<std::size_t>(uniform_index(rng, hi - lo))]);
  }
  std::sort(picked.begin(), picked.end());
  return picked;
}

SearchContext::SearchContext(const SearchOptions& opts, const SearchProblem& prob)
    : options(opts),
      problem(prob),
      front(opts.on_new_member),
      ranks(opts.communicator),
      start_(std::chrono::steady_clock::now()) {
  for (const auto& c : problem.inputs) columns.push_back(c.data());
  rows = problem.target.size();
  terminals = uniform_terminals(problem, options);
  threads = options.threads > 0
                ? options.threads
                : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

double SearchContext::elapsed() const {
  return clock_offset_s_ +
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void SearchContext::stop(Termination reason) {
  std::lock_guard lock(reason_mutex_);
  if (!stopped()) reason_ = reason;
  stopped_.store(true, std::memory_order_relaxed);
}

Termination SearchContext::stop_reason() const {
  std::lock_guard lock(reason_mutex_);
  return reason_;
}

bool SearchContext::should_stop() {
  if (stopped()) return true;
  // With joint_stop the clock and the interrupt flag are the ranks' joint decision (stop() is
  // called for them); the counts are the same on every rank.
  const bool interrupted =
      options.interrupt != nullptr && options.interrupt->load(std::memory_order_relaxed);
  if (!joint_stop && interrupted) {
    stop(Termination::Interrupted);
  } else if (!joint_stop && elapsed() >= options.time_limit_s) {
    stop(Termination::TimeLimit);
  } else if (options.max_candidates && candidates.load(std::memory_order_relaxed) >=
                                           static_cast<std::uint64_t>(*options.max_candidates)) {
    stop(Termination::CandidateLimit);
  }
  return stopped();
}

void SearchContext::maybe_progress(SearchPhase phase) {
  if (checkpointer != nullptr && phase == SearchPhase::Enumeration)
    checkpointer->enumeration_tick();
  if (!options.on_progress) return;
  const double now = elapsed();
  if (now - last_progress_.load(std::memory_order_relaxed) < options.progress_interval_s) return;
  std::unique_lock lock(progress_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  last_progress_.store(now, std::memory_order_relaxed);
  SearchProgress p;
  p.elapsed_s = now;
  p.candidates = candidates.load(std::memory_order_relaxed);
  p.candidates_per_s = now > 0 ? static_cast<double>(p.candidates) / now : 0.0;
  p.front_size = front.size();
  p.phase = phase;
  options.on_progress(p);
}

void SearchContext::predict(const Expression& e, std::span<double> out) {
  std::vector<const double*> cols(e.variables.size(), nullptr);
  for (std::size_t i = 0; i < e.variables.size(); ++i) {
    auto it = std::find(problem.input_names.begin(), problem.input_names.end(), e.variables[i]);
    if (it != problem.input_names.end())
      cols[i] = columns[static_cast<std::size_t>(it - problem.input_names.begin())];
  }
  evaluate(e, cols, out, {.threads = 1});
  node_evaluations.fetch_add(e.size() * rows, std::memory_order_relaxed);
}

void SearchContext::predict_shown(const Expression& e, std::span<double> out) {
  if (options.precision == Precision::Double) {
    predict(e, out);
    return;
  }
  std::vector<const double*> cols(e.variables.size(), nullptr);
  for (std::size_t i = 0; i < e.variables.size(); ++i) {
    auto it = std::find(problem.input_names.begin(), problem.input_names.end(), e.variables[i]);
    if (it != problem.input_names.end())
      cols[i] = columns[static_cast<std::size_t>(it - problem.input_names.begin())];
  }
  evaluate_in(options.precision, e, cols, out);
  node_evaluations.fetch_add(e.size() * rows, std::memory_order_relaxed);
}

ErrorMetrics SearchContext::metrics_of(std::span<const double> prediction) const {
  return error_metrics(prediction, problem.target, {}, problem.weights);
}

ErrorMetrics SearchContext::score(const Expression& e) {
  std::vector<double> out(rows);
  predict(e, out);
  return error_metrics(out, problem.target, {}, problem.weights,
                       options.loss == Loss::Log ? MetricSet::All : MetricSet::NoLog);
}

std::optional<std::size_t> SearchContext::non_finite_row(const Expression& e,
                                                         bool infinities_allowed) {
  const auto bad = [&](double v) { return infinities_allowed ? std::isnan(v) : !std::isfinite(v); };
  for (const Node& n : e.nodes) {
    if (n.op == Op::Const && bad(n.value)) return kAnyRow;
  }
  for (double v : e.parameter_values)
    if (bad(v)) return kAnyRow;
  // The root is the caller's prediction; below it only the operands of absorbing operators
  // need a look (anything non-finite elsewhere would show in an operand of one, or the root).
  // A select's branch needs to be finite only where it is chosen, on the rows where the select
  // itself is used (the shader computes both and keeps one, as for `c ? (1 - exp(-x)) / x : 1 -
  // x / 2`, and a select nested in the branch not taken does not matter there): `used` holds,
  // node by node from the root down (postfix: parents after their children), those rows.
  std::vector<std::vector<char>> used(e.size());
  used[e.size() - 1].assign(rows, 1);
  std::vector<double> values;
  std::array<std::size_t, 3> children{};
  for (std::size_t i = e.size(); i-- > 0;) {
    const Node& n = e.nodes[i];
    const std::size_t k = arity(n.op);
    if (k == 0) continue;
    e.child_indices(i, std::span<std::size_t>(children.data(), k));
    for (std::size_t c = 0; c < k; ++c) used[children[c]] = used[i];
    if (n.op == Op::Select) {
      std::vector<double> condition(rows);
      predict(e.subtree(children[0]), condition);
      for (std::size_t r = 0; r < rows; ++r) {
        const bool first = condition[r] >= 0;
        used[children[1]][r] = static_cast<char>(used[i][r] && first);
        used[children[2]][r] = static_cast<char>(used[i][r] && !first);
      }
    }
    if (!absorbs_non_finite(n.op, n.index)) continue;
    for (std::size_t c = 0; c < k; ++c) {
      if (arity(e.nodes[children[c]].op) == 0) continue;  // leaves were checked above
      values.resize(rows);
      predict(e.subtree(children[c]), values);
      const std::vector<char>& rows_used = used[children[c]];
      for (std::size_t r = 0; r < rows; ++r)
        if (rows_used[r] && bad(values[r])) return r;
    }
    used[i].clear();
    used[i].shrink_to_fit();
  }
  return std::nullopt;
}

bool SearchContext::offer(Expression e, double loss_estimate, SearchPhase origin,
                          std::vector<FrontMember>* entered) {
  FrontMember m;
  m.cost = formula_cost(e, options);
  m.loss = loss_estimate;
  if (!std::isfinite(m.loss) || !front.would_enter(m.cost, m.loss)) return false;
  // On a symmetric half, the cost of the cheapest form on every row (whole_data_forms), which is
  // what the whole data's front will show: at least e's own, so checked only where that enters.
  if (symmetry) {
    m.cost = std::numeric_limits<double>::infinity();
    for (const Expression& f : whole_data_forms(e, *symmetry, problem.input_names, false))
      m.cost = std::min(m.cost, formula_cost(f, options));
    if (!front.would_enter(m.cost, m.loss)) return false;
  }
  // What the front shows is what was scored: e itself, in options.precision, on every row.
  // (Only formulas that would enter get this far, so the extra evaluation is rare.)
  std::vector<double> prediction(rows);
  predict_shown(e, prediction);
  for (double v : prediction)
    if (!std::isfinite(v)) return false;
  m.metrics = metrics_of(prediction);
  m.loss = loss_value(options.loss, m.metrics);
  if (!std::isfinite(m.loss) || !front.would_enter(m.cost, m.loss)) return false;
  if (non_finite_row(e, origin == SearchPhase::Reference)) return false;
  m.nodes = e.size();
  m.formula = to_infix(e, {.substitute_parameters = true});
  m.expression = std::move(e);
  m.time_s = elapsed();
  m.origin = origin;
  const double cost = m.cost, loss = m.loss;
  if (entered != nullptr) {
    FrontMember copy = m;
    if (!front.offer(std::move(m))) return false;
    entered->push_back(std::move(copy));
  } else if (!front.offer(std::move(m))) {
    return false;
  }
  if (options.stop_at && loss <= options.stop_at->max_loss && cost <= options.stop_at->max_cost) {
    stop(Termination::TargetReached);
  }
  return true;
}

}  // namespace shaderfit::search_detail
