// Symbolic regression: the Pareto front of formulas, error against GPU cost.
//
//   SearchProblem problem;
//   problem.input_names = {"r0", "x"};
//   problem.inputs = {r0_column, x_column};
//   problem.target = reflectance_column;
//   SearchOptions options;                 // defaults work on the seed's Fresnel task
//   options.time_limit_s = 2.0;
//   std::string why;
//   if (!options.is_valid(&why)) { ... }
//   SearchSummary summary;
//   run_search(options, problem, &summary);
//   std::cout << summary.brief_report();   // and summary.front, cheapest first
//
// Two strategies run one after the other (docs/search.md):
//  1. exhaustive bottom-up enumeration by cost over cached value columns, with candidates that
//     compute the same values deduplicated, which finds the small formulas in milliseconds;
//  2. an island-model NSGA-II evolution seeded from that front, for larger formulas and formulas
//     with free constants (fitted by linear least squares or Levenberg-Marquardt).
// With one thread, a seed and an evaluation budget (or no time cut-off) give identical results.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/gpu/device.hpp"

namespace shaderfit {

// The data: input columns and the target. Formulas name the inputs by `input_names`.
struct SearchProblem {
  std::vector<std::string> input_names;
  std::vector<std::vector<double>> inputs;  // inputs[i][row], one column per name
  std::vector<double> target;
  std::vector<double> weights;  // empty: every row weighs 1

  // Throws shaderfit::Error for: no inputs, a count of names and columns that differ, duplicate
  // names, columns of unequal length, fewer than 2 rows, a NaN or infinite value, a negative
  // weight, or weights that sum to 0.
  void validate() const;
};

// One formula of the Pareto front.
struct FrontMember {
  Expression expression;  // variables: the problem's input names; parameters hold fitted values
  std::string formula;    // infix that parse_formula reads (fitted constants written as numbers)
  double cost = 0;        // expression_cost(expression, options.cost)
  std::size_t nodes = 0;  // expression.size()
  ErrorMetrics metrics;   // on every row of the problem
  double loss = 0;        // the metric options.loss names
  double time_s = 0;      // when it was found, seconds since the search started
  std::string origin;     // "enumeration" or "evolution"
  // Float32 against float64 on every row (docs/reliability.md): the largest absolute
  // difference (+inf when float32 is not finite on a row), and whether it is within
  // max(1e-4 * max |target|, 0.01 * metrics.max_abs). Filled in for the final front.
  double float32_max_abs_diff = 0;
  bool float32_stable = true;
};

struct SearchProgress {
  double elapsed_s = 0;
  std::uint64_t candidates = 0;  // formulas evaluated so far
  double candidates_per_s = 0;
  std::size_t front_size = 0;
  std::string_view phase;  // "enumeration" or "evolution"
};

// Stop as soon as the front has a member with loss <= max_loss and cost <= max_cost.
struct SearchTarget {
  double max_loss = 0;
  double max_cost = 0;
};

struct SearchOptions {
  // Budgets. The search stops at whichever comes first; at least the time limit is always set.
  double time_limit_s = 10.0;                  // wall clock, > 0
  std::optional<std::int64_t> max_candidates;  // formulas evaluated, > 0 when set
  std::optional<SearchTarget> stop_at;         // for benchmarks: stop when this is met

  std::uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads
  // Where the evolution scores each generation's children on the fit rows: Auto = the GPU when
  // cuda_available(), else the CPU. Cuda without a usable GPU makes run_search throw Error
  // (docs/gpu.md). The GPU scores in float32, so fronts may differ from CPU runs in the last
  // digits of the fit-row losses that rank individuals; front members are scored in float64.
  ComputeDevice device = ComputeDevice::Auto;

  Loss loss = Loss::Mse;  // mse, rmse, max_abs, rel or log (eval/loss.hpp); not max_rel
  CostTarget cost = CostTarget::Instructions;

  // Operators formulas may use (Op::IPow stands for x^2 .. x^max_power) and literal constants
  // (their negatives come free with negation).
  std::vector<Op> operators = {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::IPow};
  // Operators the evolution may use besides `operators` (the enumeration keeps to those): the
  // larger formulas gain most from a fitted exponent or exponential.
  std::vector<Op> evolution_operators = {Op::Pow, Op::Exp2};
  int max_power = 5;
  std::vector<double> literals = {0.5, 1.0, 2.0};

  // Enumeration. `screen_rows` random rows are cached per distinct candidate (float32) and used
  // to deduplicate and to screen; candidates that pass are scored on every row.
  bool enumerate = true;
  std::size_t screen_rows = 64;  // multiple of 8, >= 16; stratified by the target
  // Distinct candidates kept. It bounds the search's memory, which peaks in the enumeration at
  // about max_classes * (6 * screen_rows + 130) bytes (770 MB by default; docs/reliability.md).
  std::size_t max_classes = 1'500'000;
  double max_enumeration_share = 0.1;  // fraction of the time limit the enumeration may use
  int max_enumeration_cost = 12;       // highest cost level enumerated

  // Evolution (island-model NSGA-II).
  bool evolve = true;
  std::size_t max_nodes = 25;    // largest formula, in nodes
  std::size_t population = 128;  // per island
  int islands = 4;               // sub-populations; fixed, so results do not depend on threads
  int migration_interval = 10;   // generations between migrations (ring topology)
  int max_parameters = 5;        // free constants per formula
  std::size_t fit_rows = 256;    // rows used to fit constants and rank individuals
  bool linear_scaling = true;    // also try a * f + b for each formula (closed form)

  // Called on the thread that found it, one call at a time, for each new front member.
  std::function<void(const FrontMember&)> on_new_member;
  // Called about every progress_interval_s seconds.
  std::function<void(const SearchProgress&)> on_progress;
  double progress_interval_s = 0.2;
  // When set and it becomes true (e.g. from a SIGINT handler), the search stops soon and returns
  // the front found so far.
  const std::atomic<bool>* interrupt = nullptr;

  // Checkpoints (docs/reliability.md). With a path, the search writes its state there (to
  // PATH.tmp, then renamed) at the first generation boundary after every checkpoint_interval_s
  // seconds (0: every boundary), during the enumeration at that interval (the front so far), and
  // when it stops for any reason (the interrupt flag included).
  std::string checkpoint_path;
  double checkpoint_interval_s = 60.0;
  // With a path, the search continues from that checkpoint instead of starting afresh: from its
  // generation boundary, or by running the enumeration again when it was taken during it. With
  // one thread and no stop by the clock, the result is the one the checkpointed run would have
  // reached. The data and the options other than budgets, threads and checkpoint settings must
  // be those of the checkpointed run.
  std::string resume_path;

  // False, with the reason in *why, for: a time limit <= 0 or not finite, max_candidates <= 0,
  // threads < 0, no operators, a leaf or unsupported operator (in either list), max_power outside
  // [2, 16], a non-finite literal, screen_rows not a multiple of 8 or < 16, max_nodes < 1,
  // population < 4, islands < 0, migration_interval < 1, max_parameters < 0, fit_rows < 8,
  // checkpoint_interval_s < 0 or not finite.
  bool is_valid(std::string* why) const;
};

struct SearchSummary {
  std::vector<FrontMember> front;  // cheapest first; loss strictly decreasing along it
  double total_time_s = 0;
  double enumeration_time_s = 0;
  double evolution_time_s = 0;
  std::uint64_t candidates = 0;           // formulas evaluated (screened or fully)
  std::uint64_t node_evaluations = 0;     // operator applications times rows
  std::uint64_t distinct_candidates = 0;  // enumeration classes kept
  int enumeration_cost_completed = -1;    // every formula up to this cost was enumerated
  std::uint64_t generations = 0;
  std::string
      termination;  // "time limit", "candidate limit", "target reached", "interrupted", "done"
  bool interrupted = false;

  // A few lines: termination, times, counts, and the front as a table.
  [[nodiscard]] std::string brief_report() const;
};

// Runs the search. Throws shaderfit::Error when the problem is invalid (SearchProblem::validate)
// or the options are (with the is_valid reason); for the log or rel loss, also when a target is
// <= 0 or 0; when the checkpoint cannot be written; and when the checkpoint to resume from cannot
// be read, is damaged, comes from another shaderfit version or was made for other data or
// options (the message says which).
void run_search(const SearchOptions& options, const SearchProblem& problem, SearchSummary* summary);

// What a checkpoint file holds, to announce a resumed run. Throws shaderfit::Error as run_search
// does for a file that cannot be read, is damaged or comes from another version.
struct CheckpointInfo {
  std::string phase;  // "enumeration" (resuming runs it again) or "evolution"
  double elapsed_s = 0;
  std::uint64_t candidates = 0;
  std::uint64_t generations = 0;
  std::size_t front_size = 0;
};
CheckpointInfo read_checkpoint_info(const std::string& path);

// Parses a comma-separated operator list: + - * / ^ (integer powers; also "ipow"), and the
// function names sqrt rsqrt rcp exp2 log2 exp log abs saturate sin cos min max pow. Throws
// Error "unknown operator 'foo' (known: ...)" located at `where` (e.g. {"--ops"}).
std::vector<Op> parse_operator_list(std::string_view list, const SourceLocation& where = {"--ops"});

// "+,-,*,/,^": the names parse_operator_list reads back.
std::string operator_list_name(const std::vector<Op>& ops);

}  // namespace shaderfit
