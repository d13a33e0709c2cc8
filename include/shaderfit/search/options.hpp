// The search's options, and their description: one entry per field with its name, help, kind,
// check and role, from which validation, the checkpoint's record of the options, the JSON's
// "options" object, the command line's flags and the Python keywords
// (python/shaderfit/_options.py) are generated.
//
//   SearchOptions o;                       // the defaults are the members' initializers
//   set_search_option(o, "max_nodes", "30");             // from text; throws Error at the field
//   for (const SearchOptionField& f : search_option_fields())
//     std::cout << f.name << " = " << search_option_text(o, f) << "  # " << f.help << '\n';
//   o.validate();                          // throws Error located at SearchOptions::<field>
//
// Adding an option: the member below and its entry in src/search/options.cpp (name, help, role,
// check); then the code that uses it. The CLI flag is --<name with '-' for '_'> unless
// apps/shaderfit/cli.cpp renames it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/cost_model.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/expr/op.hpp"
#include "shaderfit/expr/precision.hpp"
#include "shaderfit/gpu/device.hpp"
#include "shaderfit/search/communicator.hpp"
#include "shaderfit/search/front_member.hpp"

namespace shaderfit {

struct SearchProgress {
  double elapsed_s = 0;
  std::uint64_t candidates = 0;  // formulas evaluated so far
  double candidates_per_s = 0;
  std::size_t front_size = 0;
  SearchPhase phase = SearchPhase::Enumeration;
};

// Stop as soon as the front has a member with loss <= max_loss and cost <= max_cost.
struct SearchTarget {
  double max_loss = 0;
  double max_cost = 0;
};

// The operator list that stands for "auto" (text "auto", `--ops auto`): resolved from the data
// by resolve_auto_operators (search.hpp) before any search work; never seen by the enumeration
// or the evolution.
inline const std::vector<Op> kAutoOperators = {Op::Count_};
inline bool is_auto_operators(const std::vector<Op>& ops) { return ops == kAutoOperators; }

struct SearchOptions {
  // Out of line (options.cpp): the defaults below are built in one place rather than in every
  // caller (GCC 12 also warns falsely, -Wmaybe-uninitialized, on the inlined operator lists).
  SearchOptions();

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

  // Display needs the display weights of a scene problem (search_problem puts them in the rows'
  // weights); the search then minimises the weighted MSE.
  Loss loss = Loss::Mse;
  CostTarget cost = CostTarget::Instructions;
  // The arithmetic the shader computes the formula in (eval/evaluate_in.hpp). Half: every front
  // member's loss and metrics are those of its half evaluation, so the front ranks what a half
  // shader computes; the search's own fits and screens stay in float64 and float32. Float32 and
  // half errors are reported for every member whatever the precision.
  Precision precision = Precision::Double;

  // Operators formulas may use (Op::IPow stands for x^2 .. x^max_power) and literal constants
  // (their negatives come free with negation). Either list may be kAutoOperators ("auto", the
  // default): a set chosen from the data when the search starts (resolve_auto_operators,
  // search.hpp). A built-in data set may come with its own (problem/problem.hpp:
  // Problem::operators; fresnel-seed's: + - * / ^, and pow exp2 for the evolution).
  std::vector<Op> operators = kAutoOperators;
  // Operators the evolution may use besides `operators` (the enumeration keeps to those): the
  // larger formulas gain most from a fitted exponent or exponential.
  std::vector<Op> evolution_operators = kAutoOperators;
  int max_power = 5;
  std::vector<double> literals = {0.5, 1.0, 2.0};
  // The user's own approximations, over the problem's inputs (docs/search.md, "Starting from a
  // formula"): each enters the front as written and with its number literals refitted for
  // `loss` (pi and integer exponents stay exact), and the refitted form seeds the evolution.
  // run_search throws Error located at "SearchOptions::start", line = the formula's position
  // (1-based), for a formula that does not parse or names a variable that is not an input.
  std::vector<std::string> start;
  // When the data is even, odd or point-symmetric in an input (detect_symmetry, checked on the
  // rows), search the half where it is >= 0 and report each formula with the reflection added
  // and costed (docs/search.md, "Symmetric data"). False: search the data as it is.
  bool symmetry = true;
  // Per-material inputs (cost/per_material.hpp): inputs constant over a draw's pixels. The cost
  // the front ranks is then the per-pixel count: what reads only these inputs, literals and fitted
  // constants is computed once per material, and the search offers such values (1/alpha^2,
  // log2(alpha), ...) as free terminals. run_search throws Error located at
  // "SearchOptions::uniform" for a name that is not an input or when every input is uniform.
  std::vector<std::string> uniform;

  // Enumeration. `screen_rows` random rows are cached per distinct candidate (float32) and used
  // to deduplicate and to screen; candidates that pass are scored on every row.
  bool enumerate = true;
  std::size_t screen_rows = 64;  // multiple of 8, >= 16; stratified by the target
  // Distinct candidates kept. It bounds the search's memory, which peaks in the enumeration at
  // about max_classes * (6 * screen_rows + 130) bytes (770 MB by default; docs/reliability.md).
  std::size_t max_classes = 1'500'000;
  // Fraction of the time limit the enumeration may use, counted in process CPU time per search
  // thread, so that other processes on the cores do not cut it short.
  double max_enumeration_share = 0.1;
  int max_enumeration_cost = 12;  // highest cost level enumerated

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
  // When set (and of more than one rank), the search runs across the ranks, each calling
  // run_search with the same data and options (docs/distributed.md): the enumeration's work and
  // the evolution's islands (islands >= ranks) are shared out, the front is kept at rank 0, and
  // rank 0's summary holds the result: under a count budget and a seed, the same on the same
  // number of ranks.
  // Only rank 0 writes checkpoints and calls on_new_member and on_progress.
  Communicator* communicator = nullptr;

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

  // Where the problem has a reference (SearchProblem::reference): a rigorous bound of each
  // front member's |error| over the whole domain (verify/certify.hpp), at most
  // certify_time_limit_s seconds per member (a looser but still rigorous bound when it ends).
  bool certify = false;
  double certify_time_limit_s = 10.0;

  // The front as shown: a costlier member is shown only where its loss is at most (1 - min_step)
  // times that of the member shown before it, cheaper; the others stay in the summary marked
  // FrontMember::minor_step (docs/search.md, "Tidy front"). 0 shows every step.
  double min_step = 0.01;

  // Each field's check from search_option_fields(), in that order. validate() throws Error
  // located at the first field that fails ("SearchOptions::max_power"); is_valid() returns
  // false instead, with "SearchOptions::max_power: must be in [2, 16]" in *why.
  void validate() const;
  bool is_valid(std::string* why) const;
};

// What an option is for, which decides whether a resumed search may change it.
enum class OptionRole {
  Search,  // decides what the search does: recorded in checkpoints, must match on resume
  Budget,  // when to stop (time, evaluations, target): may differ on resume
  Run,     // how it runs (threads, device, progress, checkpoint files): not recorded
};

// A pointer to the described member; its type is the option's kind. (std::uint64_t, the seed's
// type, is std::size_t on the 64-bit platforms shaderfit builds on.)
static_assert(std::is_same_v<std::uint64_t, std::size_t>);
using SearchOptionMember =
    std::variant<double SearchOptions::*, int SearchOptions::*, std::size_t SearchOptions::*,
                 bool SearchOptions::*, std::string SearchOptions::*,
                 std::optional<std::int64_t> SearchOptions::*,
                 std::optional<SearchTarget> SearchOptions::*, std::vector<double> SearchOptions::*,
                 std::vector<std::string> SearchOptions::*, std::vector<Op> SearchOptions::*,
                 Loss SearchOptions::*, CostTarget SearchOptions::*, ComputeDevice SearchOptions::*,
                 Precision SearchOptions::*>;

// The kinds, as a Python binding or a form would name them.
enum class OptionKind {
  Real,
  Integer,  // int, std::size_t, std::uint64_t, std::optional<std::int64_t>
  Bool,
  Text,        // a path
  StopTarget,  // std::optional<SearchTarget>
  Reals,       // a list of numbers
  Formulas,    // a list of formulas (std::vector<std::string>)
  Names,       // a list of input names (std::vector<std::string> with `names` set)
  Operators,   // a list of operators
  Choice,      // one of `choices`
};

struct SearchOptionField {
  std::string_view name;  // the member's name: JSON and checkpoint key, error location
  SearchOptionMember member;
  OptionRole role;
  std::string_view help;          // one line, without the default
  std::string_view default_note;  // follows the default where the help shows it ("; 0: ...")
  std::string_view choices;       // Choice: the names, "mse, rmse, max_abs, rel, log"
  bool may_be_empty = false;      // an optional value, or an operator list that may be empty
  bool names = false;             // a std::vector<std::string> of names, comma-separated
  // Why the value is not acceptable (without the field's name), or "" when it is.
  std::string (*check)(const SearchOptions&) = nullptr;
};

// Every described option, in the order `shaderfit search --help` lists them (the callbacks and
// the interrupt flag are not options).
std::span<const SearchOptionField> search_option_fields();
// nullptr for a name that is not described.
const SearchOptionField* find_search_option(std::string_view name);
OptionKind search_option_kind(const SearchOptionField& field);
std::string_view option_kind_name(OptionKind kind);  // "real", "integer", ...
// "SearchOptions::max_nodes": where errors about the field are located.
std::string search_option_location(const SearchOptionField& field);

// The value as text: numbers shortest round-trip, booleans true/false, lists comma-separated
// ("+,-,*,/,^", "0.5,1,2", "alpha,f0"; formulas, which hold commas, separated by "; "), choices by
// name, an unset optional as "", kAutoOperators as "auto". set_search_option reads it back (and
// "none" for an empty operator list); it throws Error located at the field for text that does not
// parse. The checkpoint records Search options in this form.
std::string search_option_text(const SearchOptions& options, const SearchOptionField& field);
void set_search_option(SearchOptions& options, const SearchOptionField& field,
                       std::string_view text);
void set_search_option(SearchOptions& options, std::string_view name, std::string_view text);

// Parses a comma-separated operator list: + - * / ^ (integer powers; also "ipow"), and the
// function names sqrt rsqrt rcp exp2 log2 exp log abs saturate sin cos min max pow. Throws
// Error "unknown operator 'foo' (known: ...)" located at `where`.
std::vector<Op> parse_operator_list(std::string_view list,
                                    const SourceLocation& where = {"SearchOptions::operators"});

// "+,-,*,/,^": the names parse_operator_list reads back ("auto" for kAutoOperators).
std::string operator_list_name(const std::vector<Op>& ops);

}  // namespace shaderfit
