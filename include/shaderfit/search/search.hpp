// Symbolic regression: the Pareto front of formulas, error against GPU cost.
//
//   SearchProblem problem;
//   problem.input_names = {"r0", "x"};
//   problem.inputs = {r0_column, x_column};
//   problem.target = reflectance_column;
//   SearchOptions options;                 // defaults work on this Fresnel task
//   options.time_limit_s = 2.0;            // (options.hpp describes every option)
//   options.validate();                    // throws Error at SearchOptions::<field>
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
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/core.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/eval/metrics.hpp"
#include "shaderfit/expr/expression.hpp"
#include "shaderfit/gpu/device.hpp"
#include "shaderfit/reference/function.hpp"
#include "shaderfit/reference/program_formula.hpp"
#include "shaderfit/search/front_member.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/symmetry.hpp"

namespace shaderfit {

// The data: input columns and the target. Formulas name the inputs by `input_names`.
struct SearchProblem {
  std::vector<std::string> input_names;
  std::vector<std::vector<double>> inputs;  // inputs[i][row], one column per name
  std::vector<double> target;
  std::vector<double> weights;  // empty: every row weighs 1
  // The function behind the data, when the rows are its samples (a reference sampled by
  // problem/problem.hpp): the inputs are its outputs of the same names. Each front member's max
  // error is then also searched for between the samples (the points found join the rows and
  // the constants are refitted until the error is stable), and with SearchOptions::certify
  // bounded over the whole domain (docs/reference.md). reference_samples: the size of the
  // sample design the rows came from (data/sampling.hpp; 0: its default).
  std::shared_ptr<const reference::ReferenceFunction> reference;
  std::size_t reference_samples = 0;

  // Throws shaderfit::Error for: no inputs, a count of names and columns that differ, duplicate
  // names, columns of unequal length, fewer than 2 rows, a NaN or infinite value, a negative
  // weight, or weights that sum to 0.
  void validate() const;
};

// The search's view of a loaded problem (problem/problem.hpp) for `loss`: its input and target
// columns, its reference, and the row weights: with Loss::Display the problem's display weights
// (a scene's), else those of `weights_column` (else the problem's own; else none). Throws
// shaderfit::Error located at "SearchOptions::loss" for the display loss on a problem without a
// scene, at `weights_where` for weights with it or a weights column that is missing or not
// numeric, and as SearchProblem::validate.
SearchProblem search_problem(const Problem& problem, Loss loss = Loss::Mse,
                             const std::string& weights_column = "",
                             const SourceLocation& weights_where = {"SearchProblem::weights"});

// Why a search stopped.
enum class Termination { Done, TimeLimit, CandidateLimit, TargetReached, Interrupted };
// "done", "time limit", "candidate limit", "target reached", "interrupted".
std::string_view termination_name(Termination termination);

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
  Termination termination = Termination::Done;
  bool interrupted = false;  // termination == Termination::Interrupted
  // Set when the search fitted the half of symmetric data (SearchOptions::symmetry); the front's
  // formulas include the reflection and are scored on every row.
  std::optional<DataSymmetry> symmetry;
  // Across ranks (SearchOptions::communicator): their number, and the bytes of the messages all
  // of them sent (each rank's payloads, before MPI's own framing).
  int ranks = 1;
  std::uint64_t bytes_sent = 0;
  // Per rank, in rank order: the bytes it sent and received (payloads); empty for one process.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> bytes_per_rank;
  // With a reference: members whose formula is NaN or infinite somewhere between the samples,
  // and with SearchOptions::certify those for which no finite bound was found (each dropped
  // from the front; dropped_notes says where, one line each), and the seconds spent checking
  // and certifying the front.
  std::size_t dropped_not_finite = 0;
  std::size_t dropped_no_bound = 0;
  std::vector<std::string> dropped_notes;
  double check_time_s = 0;

  // A few lines: termination, times, counts, and the front as a table.
  [[nodiscard]] std::string brief_report() const;
};

// The reference's own formula over the problem's inputs (reference/program_formula.hpp), or why
// it has none; nothing (no formula, no why) without a reference. Where there is one, run_search
// offers it to the front as written and with its constants refitted (origin "reference"), seeds
// the evolution with it and descends from it to cheaper formulas (docs/search.md, "Downward from
// the reference").
reference::ProgramFormula reference_formula(const SearchProblem& problem);

// Why the reference's own formula cannot join the front, in a few words for one line: it does
// not lower (reference_formula's why), or it is not finite on a row, or a part of it is NaN
// there (named by its inputs' values; SearchContext::offer). Parts that are infinite where the
// value is finite, as the code computes them (a cutoff on x * rsqrt(1 - x^2) at x = 1), are the
// reference's own: it joins; the search's other formulas may have none. Empty where it can join
// or where there is no reference. The search descends from a formula that lowers either way.
std::string reference_off_front(const SearchOptions& options, const SearchProblem& problem);

// The reference's cost as written in options.cost (per pixel under options.uniform), where the
// cost model can count it: also where its formula is too large a tree for the search
// (reference::kMaxCostedFormulaNodes); nothing where it does not lower.
std::optional<double> reference_cost(const SearchOptions& options, const SearchProblem& problem);

// Runs the search. Throws shaderfit::Error when the problem is invalid (SearchProblem::validate)
// or the options are (SearchOptions::validate); for the log or rel loss, also when a target is
// <= 0 or 0; when the checkpoint cannot be written; and when the checkpoint to resume from cannot
// be read, is damaged, comes from another shaderfit version or was made for other data or
// options (the message says which).
void run_search(const SearchOptions& options, const SearchProblem& problem, SearchSummary* summary);

// `options` with each "auto" operator list (kAutoOperators, `--ops auto`) replaced by the set
// chosen from the problem's data; other lists are returned unchanged. run_search does this
// itself; a caller that shows or records the options (the CLI's JSON) does it first.
// The choice (docs/search.md, "Operators"): the enumeration gets + - * / ^ sqrt exp2 log2 abs
// min max, pow when the target has a high dynamic range (max |y| > 100 median |y|), and sign
// and copysign when an input takes both signs, sin and cos where the data turns like a sine
// (search/operator_probe.hpp), asin acos atan atan2 tanh erf for problems of two inputs or more
// where a reference calls them or the target is one of them of a simple function of the inputs
// (search/library_operators.hpp); the evolution gets pow rsqrt saturate besides,
// and select when an input takes both signs. "Takes both signs" is judged on the rows the search
// will see: the half x >= 0 where it folds symmetric data (search_symmetry, symmetry.hpp).
SearchOptions resolve_auto_operators(SearchOptions options, const SearchProblem& problem);

// The device run_search computes on: options.device with Auto decided (the CPU for the max_rel
// loss, which the GPU does not score). Throws Error located at SearchOptions::device when it is
// Cuda and no GPU can be used, or the loss is max_rel.
ComputeDevice search_device(const SearchOptions& options);

// What a checkpoint file holds, to announce a resumed run. Throws shaderfit::Error as run_search
// does for a file that cannot be read, is damaged or comes from another version.
struct CheckpointInfo {
  SearchPhase phase = SearchPhase::Enumeration;  // Enumeration: resuming runs it again
  double elapsed_s = 0;
  std::uint64_t candidates = 0;
  std::uint64_t generations = 0;
  std::size_t front_size = 0;
  int ranks = 1;  // that wrote it (SearchOptions::communicator)
};
CheckpointInfo read_checkpoint_info(const std::string& path);

}  // namespace shaderfit
