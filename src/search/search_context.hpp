// State shared by the strategies of one search: data, front, clock, counters, stop rules
// (internal).
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "search/pareto.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::search_detail {

class SearchContext {
 public:
  SearchContext(const SearchOptions& options, const SearchProblem& problem);

  const SearchOptions& options;
  const SearchProblem& problem;
  std::vector<const double*> columns;  // the input columns, in problem order
  std::size_t rows = 0;
  int threads = 1;
  ParetoFront front;

  std::atomic<std::uint64_t> candidates{0};
  std::atomic<std::uint64_t> node_evaluations{0};

  // Seconds since the search started.
  [[nodiscard]] double elapsed() const;

  // True once a budget is spent, the interrupt flag is set, or the stop target was met; the first
  // reason is kept. Cheap enough to call per batch of candidates.
  bool should_stop();
  [[nodiscard]] bool stopped() const { return stopped_.load(std::memory_order_relaxed); }
  void stop(std::string_view reason);
  [[nodiscard]] std::string stop_reason() const;

  // Calls options.on_progress when progress_interval_s has passed since the last call.
  void maybe_progress(std::string_view phase);

  // e on every row (double precision; out has `rows` entries), counting its node evaluations.
  void predict(const Expression& e, std::span<double> out);
  [[nodiscard]] LossMetrics metrics_of(std::span<const double> prediction) const;
  // The loss metrics of e on every row.
  LossMetrics score(const Expression& e);
  // Fills in a front member for e (which must be over the problem's inputs) and offers it.
  // Returns whether it entered the front. `metrics` are e's full-data metrics.
  bool offer(Expression e, const LossMetrics& metrics, std::string_view origin);

 private:
  std::chrono::steady_clock::time_point start_;
  std::atomic<bool> stopped_{false};
  mutable std::mutex reason_mutex_;
  std::string reason_;
  std::atomic<double> last_progress_{0.0};
  std::mutex progress_mutex_;
};

}  // namespace shaderfit::search_detail
