// State shared by the strategies of one search: data, front, clock, counters, stop rules
// (internal).
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "search/distributed.hpp"
#include "search/pareto.hpp"
#include "shaderfit/core/random.hpp"
#include "shaderfit/search/search.hpp"
#include "shaderfit/search/symmetry.hpp"

namespace shaderfit::search_detail {

class Checkpointer;

// How the enumeration's screening scores a search loss, and a row's weight there and in the
// minimax fits (w the row's weight, y its target; the squared losses' weights are then
// normalised to sum 1): rel keeps w (its screens divide by y row by row), max_abs counts the rows
// of non-zero weight alike, and max_rel is max_abs with weights 1/|y| (rows with y = 0 do not
// count, as in the metric).
Loss screen_loss(Loss loss);

// The cost the front ranks: expression_cost for options.cost, per pixel with options.uniform.
inline double formula_cost(const Expression& e, const SearchOptions& options) {
  return expression_cost(e, options.cost, options.uniform);
}
double screen_weight(Loss loss, double w, double y);

// `wanted` of `rows` (indices into target) stratified by the target: the rows sorted by target
// value, cut into `wanted` strata of equal size, one row drawn uniformly from each; returned in
// increasing order. All of `rows` (sorted) when there are no more than `wanted`. The large errors
// sit at the large targets (grazing angles), so the loss on such a sample has far less sampling
// noise than on a plain one.
std::vector<std::size_t> stratified_rows(std::span<const double> target,
                                         std::vector<std::size_t> rows, std::size_t wanted,
                                         Rng& rng);

class SearchContext {
 public:
  SearchContext(const SearchOptions& options, const SearchProblem& problem);

  const SearchOptions& options;
  const SearchProblem& problem;
  std::vector<const double*> columns;  // the input columns, in problem order
  // The per-material values offered as free terminals (uniform_terminals.hpp); empty without
  // uniform inputs.
  std::vector<Expression> terminals;
  std::size_t rows = 0;
  int threads = 1;
  ComputeDevice device = ComputeDevice::Cpu;  // options.device resolved (Auto decided)
  ParetoFront front;
  // Set when `problem` is the half of symmetric data (run_search); the checkpoints record it.
  std::optional<DataSymmetry> symmetry;
  // The ranks of a distributed search (one process: not distributed).
  RankGroup ranks;
  // Set by a distributed evolution: should_stop() then leaves the clock and the interrupt flag to
  // the ranks' joint decision (Evolution's synchronisation), so that every rank stops together.
  bool joint_stop = false;

  std::atomic<std::uint64_t> candidates{0};
  std::atomic<std::uint64_t> node_evaluations{0};

  // Seconds since the search started (including, when resumed, the time its checkpoint had
  // consumed).
  [[nodiscard]] double elapsed() const;
  // Resuming: the clock continues from `elapsed_s`.
  void resume_clock(double elapsed_s) { clock_offset_s_ = elapsed_s; }

  // Takes the checkpoints when options.checkpoint_path is set (null otherwise); maybe_progress
  // gives it the enumeration's ticks.
  Checkpointer* checkpointer = nullptr;

  // True once a budget is spent, the interrupt flag is set, or the stop target was met; the first
  // reason is kept. Cheap enough to call per batch of candidates.
  bool should_stop();
  [[nodiscard]] bool stopped() const { return stopped_.load(std::memory_order_relaxed); }
  void stop(Termination reason);
  // Termination::Done until stop() is called.
  [[nodiscard]] Termination stop_reason() const;

  // Calls options.on_progress when progress_interval_s has passed since the last call.
  void maybe_progress(SearchPhase phase);

  // e on every row (double precision; out has `rows` entries), counting its node evaluations.
  void predict(const Expression& e, std::span<double> out);
  // e on every row in options.precision (eval/evaluate_in.hpp): what a front member shows. The
  // same as predict() in double precision.
  void predict_shown(const Expression& e, std::span<double> out);
  [[nodiscard]] ErrorMetrics metrics_of(std::span<const double> prediction) const;
  // The loss metrics of e on every row: a candidate's, whose loss is all that is read (the log
  // error only for the log loss; offer() scores what enters the front in full).
  ErrorMetrics score(const Expression& e);
  // Fills in a front member for e (which must be over the problem's inputs) and offers it.
  // Returns whether it entered the front. `loss_estimate` (the caller's full-data loss of e or
  // of an equivalent form, e.g. before simplification) only pre-selects: a formula that may
  // enter is scored again as it will be shown, and never enters when its loss is not finite or
  // it is not finite_everywhere.
  // `entered`, when given, receives a copy of the member when it enters.
  bool offer(Expression e, double loss_estimate, SearchPhase origin,
             std::vector<FrontMember>* entered = nullptr);
  // Whether e and every subexpression of it is finite on every row (weight-0 rows included),
  // in float64. GLSL leaves x / 0, logs of 0 or less, square roots of negatives and whatever
  // is computed from an infinity or a NaN unspecified (and min, max, saturate and rcp can turn
  // those back into finite values), so a formula that passes through one would not compute
  // what the search scored in every shader. A select's branch counts only on the rows where it
  // is chosen.
  bool finite_everywhere(const Expression& e) { return !non_finite_row(e); }
  // Where finite_everywhere fails: the first row on which a subexpression is not finite
  // (kAnyRow for a constant or parameter that is not), nullopt where it holds. With
  // `infinities_allowed`, a part may be infinite (IEEE arithmetic, which every GPU follows
  // there, gives what follows from it: rcp(inf) = 0, inf >= 1 is true) and only a NaN part
  // counts: the user's reference, as written, is judged so (origin Reference).
  static constexpr std::size_t kAnyRow = static_cast<std::size_t>(-1);
  std::optional<std::size_t> non_finite_row(const Expression& e, bool infinities_allowed = false);

 private:
  std::chrono::steady_clock::time_point start_;
  double clock_offset_s_ = 0;
  std::atomic<bool> stopped_{false};
  mutable std::mutex reason_mutex_;
  Termination reason_ = Termination::Done;
  std::atomic<double> last_progress_{0.0};
  std::mutex progress_mutex_;
};

}  // namespace shaderfit::search_detail
