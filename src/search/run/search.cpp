#include "shaderfit/search/search.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <set>

#include "search/checkpoint.hpp"
#include "search/distributed.hpp"
#include "search/enumeration/enumerator.hpp"
#include "search/evolution/constant_fit.hpp"
#include "search/evolution/evolution.hpp"
#include "search/exact_json.hpp"
#include "search/front/float32_check.hpp"
#include "search/front/symmetry_front.hpp"
#include "search/front/tidy.hpp"
#include "search/front/verify_front.hpp"
#include "search/search_context.hpp"
#include "search/starts/descent.hpp"
#include "search/starts/polynomial_starts.hpp"
#include "search/starts/power_sum.hpp"
#include "search/starts/shape_starts.hpp"
#include "search/starts/start.hpp"
#include "search/starts/uniform_starts.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/eval/evaluate_in.hpp"

namespace shaderfit {

std::string_view termination_name(Termination t) {
  switch (t) {
    case Termination::Done: return "done";
    case Termination::TimeLimit: return "time limit";
    case Termination::CandidateLimit: return "candidate limit";
    case Termination::TargetReached: return "target reached";
    case Termination::Interrupted: return "interrupted";
  }
  return "done";
}

ComputeDevice search_device(const SearchOptions& options) {
  if (options.loss == Loss::MaxRel) {
    if (options.device == ComputeDevice::Cuda)
      throw Error("the max_rel loss is scored on the CPU only", {"SearchOptions::device"});
    return ComputeDevice::Cpu;
  }
  return resolve_device(options.device, {"SearchOptions::device"});
}

namespace {

// How a value that is not finite is named in messages.
std::string nonfinite_text(double v) { return std::isnan(v) ? "NaN" : v > 0 ? "+inf" : "-inf"; }

}  // namespace

void SearchProblem::validate() const {
  const SourceLocation where{"data"};
  if (inputs.empty() || input_names.empty())
    throw Error("the search needs at least one input", where);
  if (inputs.size() != input_names.size())
    throw Error("got " + std::to_string(input_names.size()) + " input names but " +
                    std::to_string(inputs.size()) + " input columns",
                where);
  std::set<std::string> seen;
  for (const auto& n : input_names)
    if (!seen.insert(n).second) throw Error("input '" + n + "' is given twice", where);
  const std::size_t rows = target.size();
  if (rows < 2)
    throw Error("the data has " + std::to_string(rows) + " row" + (rows == 1 ? "" : "s") +
                    "; a search needs at least 2",
                where);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (inputs[i].size() != rows)
      throw Error("input '" + input_names[i] + "' has " + std::to_string(inputs[i].size()) +
                      " rows but the target has " + std::to_string(rows),
                  where);
    for (std::size_t r = 0; r < rows; ++r)
      if (!std::isfinite(inputs[i][r]))
        throw Error("input '" + input_names[i] + "' is " + nonfinite_text(inputs[i][r]) +
                        " in row " + std::to_string(r + 1) + " (rows counted from 1)",
                    where);
  }
  for (std::size_t r = 0; r < rows; ++r)
    if (!std::isfinite(target[r]))
      throw Error("the target is " + nonfinite_text(target[r]) + " in row " +
                      std::to_string(r + 1) + " (rows counted from 1)",
                  where);
  if (!weights.empty()) {
    if (weights.size() != rows)
      throw Error("the weights have a different number of rows than the target", where);
    double sum = 0;
    for (double w : weights) {
      if (!(w >= 0) || !std::isfinite(w)) throw Error("weights must be finite and >= 0", where);
      sum += w;
    }
    if (!(sum > 0)) throw Error("every weight is zero (the weights sum to 0)", where);
  }
}

CheckpointInfo read_checkpoint_info(const std::string& path) {
  const search_detail::Checkpoint c = search_detail::read_checkpoint(path);
  CheckpointInfo info;
  info.phase = c.phase;
  info.elapsed_s = c.elapsed_s;
  info.candidates = c.candidates;
  info.generations = c.evolution.generations;
  info.front_size = c.front.size();
  info.ranks = c.ranks;
  return info;
}

namespace {

using search_detail::Checkpoint;

// A rank of a distributed search other than rank 0: it evolves its islands and returns nothing.
bool follower(const SearchOptions& o) {
  return o.communicator != nullptr && o.communicator->size() > 1 && o.communicator->rank() != 0;
}

// Across ranks: what rank 0's enumeration (and start formulas, and a resumed checkpoint's front)
// left, so that every rank starts the evolution from the same front, seeds, counts and generator.
void share_enumeration(search_detail::SearchContext& ctx, SearchSummary* s,
                       std::vector<Expression>* seeds, Rng* rng) {
  using nlohmann::json;
  json j;
  if (ctx.ranks.leader()) {
    json front = json::array(), seed = json::array();
    for (const FrontMember& m : ctx.front.members())
      front.push_back(front_member_json(m, FrontJson::Exact));
    for (const Expression& e : *seeds) seed.push_back(search_detail::exact_expression_json(e));
    j = {{"front", front},
         {"seeds", seed},
         {"candidates", ctx.candidates.load()},
         {"distinct", s->distinct_candidates},
         {"cost_completed", s->enumeration_cost_completed},
         {"elapsed", search_detail::exact_number(ctx.elapsed())},
         {"rng", rng_text(*rng)},
         {"stopped", ctx.stopped()},
         {"reason", termination_name(ctx.stop_reason())}};
  }
  j = ctx.ranks.broadcast(j, 0);
  if (ctx.ranks.leader()) return;
  std::vector<FrontMember> front;
  for (const json& m : j.at("front"))
    front.push_back(front_member_from_json(m, ctx.problem.input_names, {}, "rank 0").member);
  ctx.front.assign(std::move(front));
  seeds->clear();
  for (const json& e : j.at("seeds")) seeds->push_back(search_detail::exact_expression_from(e));
  ctx.candidates.store(j.at("candidates").get<std::uint64_t>());
  // The node evaluations stay each rank's own: they are summed at the end.
  s->distinct_candidates = j.at("distinct").get<std::uint64_t>();
  s->enumeration_cost_completed = j.at("cost_completed").get<int>();
  ctx.resume_clock(search_detail::exact_number_from(j.at("elapsed")) - ctx.elapsed());
  if (!rng_from_text(j.at("rng").get<std::string>(), rng))
    throw Error("rank 0 sent a generator state that does not read back", {"communicator"});
  if (j.at("stopped").get<bool>()) {
    for (Termination t : {Termination::Done, Termination::TimeLimit, Termination::CandidateLimit,
                          Termination::TargetReached, Termination::Interrupted})
      if (termination_name(t) == j.at("reason").get<std::string>()) ctx.stop(t);
  }
}

// The formulas derived from the data, not found by search: an exact power sum
// (search/power_sum.hpp), or else the per-material starts of a problem with uniform inputs
// (search/uniform_starts.hpp) and the polynomials of a one-input problem
// (search/polynomial_starts.hpp), offered to ctx's front; returns their refitted forms.
std::vector<Expression> offer_derived_starts(search_detail::SearchContext& ctx,
                                             const SearchProblem& problem,
                                             const std::optional<DataSymmetry>& symmetry) {
  using search_detail::start_over_indexed_inputs;
  const std::vector<std::string>& names = problem.input_names;
  if (const auto sum = search_detail::exact_power_sum(problem))
    return search_detail::offer_start_formulas(
        ctx, {start_over_indexed_inputs(*sum, names, "power sum", SearchPhase::PowerSum)});
  std::vector<search_detail::StartFormula> material;
  // A time-limited search gives the fits their share of the time; a count-budgeted one all of
  // them (so that it stays reproducible).
  const double deadline =
      ctx.elapsed() + search_detail::kUniformStartShare * ctx.options.time_limit_s;
  const auto over = [&] {
    return ctx.should_stop() || (!ctx.options.max_candidates && ctx.elapsed() > deadline);
  };
  for (const std::string& text :
       search_detail::uniform_starts(problem, ctx.options, ctx.terminals, over)) {
    material.push_back(
        start_over_indexed_inputs(text, names, "per-material start", SearchPhase::Material));
    material.back().fitted = true;
  }
  std::vector<Expression> seeds = search_detail::offer_start_formulas(ctx, material);
  std::vector<search_detail::StartFormula> polynomials;
  for (const std::string& text :
       search_detail::polynomial_starts(problem, symmetry, ctx.options.loss)) {
    polynomials.push_back(
        start_over_indexed_inputs(text, names, "polynomial", SearchPhase::Polynomial));
    polynomials.back().fitted = true;
  }
  for (Expression& e : search_detail::offer_start_formulas(ctx, polynomials))
    seeds.push_back(std::move(e));
  return seeds;
}

// The search proper, on `problem`: the data, or its half when `symmetry` is set.
void search_on(const SearchOptions& options, const SearchProblem& problem,
               const std::vector<search_detail::StartFormula>& starts,
               std::optional<Checkpoint> resumed, const std::optional<DataSymmetry>& symmetry,
               SearchSummary* summary) {
  if (resumed)
    search_detail::check_checkpoint_matches(*resumed, options, problem, options.resume_path);
  // Before any work, so that a device that cannot be used fails at once.
  const ComputeDevice device = search_device(options);
  search_detail::SearchContext ctx(options, problem);
  ctx.device = device;
  ctx.symmetry = symmetry;
  const bool distributed = ctx.ranks.distributed();
  std::unique_ptr<search_detail::Checkpointer> checkpoints;
  if (!options.checkpoint_path.empty() && ctx.ranks.leader()) {
    checkpoints = std::make_unique<search_detail::Checkpointer>(ctx);
    ctx.checkpointer = checkpoints.get();
  }
  Rng rng(options.seed);
  SearchSummary s;
  if (resumed && resumed->phase == SearchPhase::Evolution) {
    // From the generation boundary the checkpoint recorded: the enumeration is not run again.
    ctx.resume_clock(resumed->elapsed_s);
    ctx.candidates.store(resumed->candidates);
    ctx.node_evaluations.store(resumed->node_evaluations);
    for (FrontMember& m : resumed->front) ctx.front.offer(std::move(m));
    s.distinct_candidates = resumed->distinct_candidates;
    s.enumeration_cost_completed = resumed->enumeration_cost_completed;
    s.enumeration_time_s = resumed->enumeration_time_s;
    rng_from_text(resumed->rng, &rng);  // checked when the checkpoint was read
    if (checkpoints)
      checkpoints->begin_evolution(s.enumeration_time_s, s.distinct_candidates,
                                   s.enumeration_cost_completed, rng);
    search_detail::Evolution evolution(ctx, rng);
    evolution.resume(resumed->evolution);
    s.generations = evolution.generations();
  } else {
    // Afresh, or from a checkpoint taken during the enumeration: the enumeration runs again
    // (with count stops it finds the same classes), then the checkpoint's front joins.
    // The start formulas first, so that they seed the evolution whatever the enumeration finds.
    // Across ranks rank 0 does this part alone, except the enumeration, which the ranks share
    // (its front and seeds join rank 0's); then the others take what rank 0 has.
    std::vector<Expression> seeds;
    if (ctx.ranks.leader()) {
      seeds = search_detail::offer_start_formulas(ctx, starts);
      // Downward from the reference's own formula and the shading shapes fitted to the data
      // (search/starts/descent.hpp, shape_starts.hpp), before the enumeration so that a
      // candidate budget leaves them their share: their seeds after the starts.
      for (const search_detail::StartFormula& start : starts) {
        if (start.origin != SearchPhase::Reference || ctx.should_stop()) continue;
        // The reference's descent first, with its own share, then the shapes' with theirs, so
        // that the shapes never take the reference's rewrites' time.
        const auto descend_for = [&](std::span<const Expression> from, double share) {
          const std::uint64_t budget =
              options.max_candidates
                  ? static_cast<std::uint64_t>(share * static_cast<double>(*options.max_candidates))
                  : std::numeric_limits<std::uint64_t>::max();
          return search_detail::descend(ctx, from, ctx.elapsed() + share * options.time_limit_s,
                                        budget);
        };
        std::vector<Expression> found =
            descend_for({&start.written, 1}, search_detail::kDescentShare);
        if (!ctx.should_stop()) {
          const std::vector<Expression> shapes = search_detail::offer_start_formulas(
              ctx, search_detail::shape_starts(
                       ctx, ctx.elapsed() + search_detail::kShapeShare * options.time_limit_s));
          for (Expression& e : descend_for(shapes, search_detail::kShapeDescentShare))
            found.push_back(std::move(e));
        }
        seeds.insert(seeds.begin() + static_cast<std::ptrdiff_t>(starts.size()),
                     std::make_move_iterator(found.begin()), std::make_move_iterator(found.end()));
      }
    }
    if (options.enumerate) {
      search_detail::Enumerator enumerator(ctx, rng);
      enumerator.run();
      s.distinct_candidates = enumerator.classes();
      s.enumeration_cost_completed = enumerator.cost_completed();
      std::vector<Expression> found = distributed
                                          ? enumerator.gather_at_leader(options.population)
                                          : enumerator.seeds(options.population);
      if (options.evolve)
        for (Expression& e : found) seeds.push_back(std::move(e));
    }
    if (ctx.ranks.leader()) {
      if (options.enumerate) {
        // An exact power sum where the data is one, or the polynomials of a one-input problem,
        // where the search goes on (a target the enumeration reached ends it first): seeds
        // after the user's starts.
        if (!ctx.should_stop()) {
          std::vector<Expression> found = offer_derived_starts(ctx, problem, symmetry);
          seeds.insert(seeds.begin() + static_cast<std::ptrdiff_t>(starts.size()),
                       std::make_move_iterator(found.begin()),
                       std::make_move_iterator(found.end()));
        }
      }
      if (resumed)
        for (FrontMember& m : resumed->front) ctx.front.offer(std::move(m));
    }
    if (distributed) share_enumeration(ctx, &s, &seeds, &rng);
    s.enumeration_time_s = ctx.elapsed();
    if (options.evolve && !ctx.should_stop()) {
      if (checkpoints)
        checkpoints->begin_evolution(s.enumeration_time_s, s.distinct_candidates,
                                     s.enumeration_cost_completed, rng);
      search_detail::Evolution evolution(ctx, rng);
      evolution.run(seeds);
      s.generations = evolution.generations();
    } else if (checkpoints) {
      checkpoints->write_enumeration();
    }
  }
  if (distributed) {
    // Every rank's bytes sent and work, summed; then the other ranks are done.
    const std::vector<nlohmann::json> counts =
        ctx.ranks.gather({ctx.ranks.bytes_sent(), ctx.node_evaluations.load(),
                          ctx.ranks.bytes_received()});
    s.ranks = ctx.ranks.size();
    std::uint64_t others = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      s.bytes_sent += counts[r].at(0).get<std::uint64_t>();
      s.bytes_per_rank.emplace_back(counts[r].at(0).get<std::uint64_t>(),
                                    counts[r].at(2).get<std::uint64_t>());
      if (r != 0) others += counts[r].at(1).get<std::uint64_t>();
    }
    ctx.node_evaluations.fetch_add(others);
    if (!ctx.ranks.leader()) {
      s.termination = ctx.stop_reason();
      s.interrupted = s.termination == Termination::Interrupted;
      *summary = std::move(s);
      return;
    }
  }
  // The best constant for the loss (the polynomial of degree 0) is the front's cost-0
  // baseline, which the enumeration's literals and the evolution need not hit. Offered last, so
  // that what the search explores is as without it.
  (void)search_detail::offer_start_formulas(
      ctx, {search_detail::start_over_indexed_inputs("0.5", problem.input_names, "constant",
                                                     SearchPhase::Polynomial)});
  // At most this share of the time budget goes to the final minimax polish.
  constexpr double kPolishShare = 0.05;
  if (ctx.stop_reason() != Termination::Interrupted)
    search_detail::polish_front_minimax(ctx, kPolishShare * options.time_limit_s);
  s.total_time_s = ctx.elapsed();
  s.evolution_time_s = s.total_time_s - s.enumeration_time_s;
  s.front = ctx.front.members();
  const search_detail::Float32Check float32(problem);
  for (FrontMember& m : s.front) float32.apply(m);
  s.candidates = ctx.candidates.load();
  s.node_evaluations = ctx.node_evaluations.load();
  s.termination = ctx.stop_reason();
  s.interrupted = s.termination == Termination::Interrupted;
  *summary = std::move(s);
}

// The target and the inputs must fit in half (check_fits_half).
void check_half_range(const SearchProblem& problem) {
  const SourceLocation where{"SearchOptions::precision"};
  check_fits_half(problem.target, "the target", where);
  for (std::size_t c = 0; c < problem.inputs.size(); ++c)
    check_fits_half(problem.inputs[c], "input '" + problem.input_names[c] + "'", where);
}

}  // namespace

reference::ProgramFormula reference_formula(const SearchProblem& problem) {
  if (!problem.reference) return {};
  return reference::program_formula(problem.reference->program, problem.input_names);
}

std::optional<double> reference_cost(const SearchOptions& options, const SearchProblem& problem) {
  if (!problem.reference) return std::nullopt;
  const reference::ProgramFormula f = reference::program_formula(
      problem.reference->program, problem.input_names, reference::kMaxCostedFormulaNodes);
  if (!f.formula) return std::nullopt;
  return expression_cost(*f.formula, options.cost, options.uniform);
}

std::string reference_off_front(const SearchOptions& options, const SearchProblem& problem) {
  const reference::ProgramFormula own = reference_formula(problem);
  if (!own.formula) return own.why;
  // As SearchContext::offer checks every formula: its values as shown, then its parts.
  search_detail::SearchContext ctx(options, problem);
  std::vector<double> values(ctx.rows);
  ctx.predict_shown(*own.formula, values);
  const auto bad =
      std::find_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); });
  const bool result = bad != values.end();
  const std::optional<std::size_t> row =
      result ? std::optional<std::size_t>(static_cast<std::size_t>(bad - values.begin()))
             : ctx.non_finite_row(*own.formula, true);
  if (!row) return {};
  if (*row == search_detail::SearchContext::kAnyRow)
    return "its formula holds a constant that is not finite";
  std::string at;
  for (std::size_t c = 0; c < problem.inputs.size(); ++c)
    at += (c == 0 ? "" : ", ") + problem.input_names[c] + " = " +
          fmt::format("{:g}", problem.inputs[c][*row]);
  return (result ? "it is not finite at " : "a part of it is NaN at ") + at +
         " (on a GPU pow(0, 0) and 0 / 0 are NaN)";
}

void run_search(const SearchOptions& given, const SearchProblem& problem, SearchSummary* summary) {
  problem.validate();
  given.validate();
  // From here on the operator lists are concrete (checkpoints record them so).
  SearchOptions options = resolve_auto_operators(given, problem);
  // The display loss is the MSE over rows that search_problem weighed by the scene's display.
  if (options.loss == Loss::Display) {
    if (problem.weights.empty())
      throw Error(
          "the display loss needs a scene's display weights: search a scene problem "
          "(search_problem)",
          {"SearchOptions::loss"});
    options.loss = Loss::Mse;
  }
  if ((options.loss == Loss::Relative || options.loss == Loss::MaxRel) &&
      std::any_of(problem.target.begin(), problem.target.end(), [](double t) { return t == 0; }))
    throw Error(
        "the " + std::string(loss_name(options.loss)) + " loss needs a target that is never 0",
        {"SearchOptions::loss"});
  if (options.loss == Loss::Log &&
      std::any_of(problem.target.begin(), problem.target.end(), [](double t) { return !(t > 0); }))
    throw Error("the log loss needs a target that is always > 0", {"SearchOptions::loss"});

  if (options.precision == Precision::Half) check_half_range(problem);
  check_uniform_inputs(options.uniform, problem.input_names, {"SearchOptions::uniform"});
  std::vector<search_detail::StartFormula> starts =
      search_detail::parse_start_formulas(options, problem);
  // The reference's own formula, where it lowers into the operators, is the first start.
  if (auto own = search_detail::reference_start(problem)) starts.insert(starts.begin(), *own);

  const search_detail::RankGroup ranks(options.communicator);
  if (ranks.distributed() && options.evolve && options.islands < ranks.size())
    throw Error(std::to_string(options.islands) + " islands for " + std::to_string(ranks.size()) +
                    " ranks: give every rank at least one island",
                {"SearchOptions::islands"});

  std::optional<Checkpoint> resumed;
  if (!options.resume_path.empty() && !ranks.distributed()) {
    resumed = search_detail::read_checkpoint(options.resume_path);
  } else if (!options.resume_path.empty()) {
    // Rank 0 reads the file (the others may not see it) and sends its bytes to all.
    std::string text;
    if (ranks.leader()) text = search_detail::read_checkpoint_text(options.resume_path);
    text = options.communicator->broadcast(text, 0);
    resumed = search_detail::parse_checkpoint(text, options.resume_path);
  }
  // A resumed search keeps the decision its checkpoint recorded (none in older checkpoints).
  std::optional<DataSymmetry> symmetry =
      resumed ? resumed->symmetry : search_symmetry(options, problem);
  if (!symmetry || symmetry->input >= problem.inputs.size()) {
    search_on(options, problem, starts, std::move(resumed), std::nullopt, summary);
  } else {
    // The half x >= 0; the start formulas, written for every row, join the whole data's front.
    search_detail::SymmetricFront whole(options, problem, *symmetry);
    const SearchProblem half = symmetric_half(problem, *symmetry);
    SearchOptions half_options = options;
    half_options.on_new_member = whole.forward_new_members();
    search_on(half_options, half, {}, std::move(resumed), symmetry, summary);
    if (follower(options)) return;
    whole.finish(starts, summary);
  }
  if (follower(options)) return;
  // The one place where the front is tidied before it is shown (docs/search.md, "Tidy front").
  summary->front = search_detail::tidy_front(options, problem, std::move(summary->front),
                                             &summary->node_evaluations);
  // Where the function behind the rows is known, the errors between them too (and bounds).
  summary->front =
      search_detail::verify_front(options, problem, std::move(summary->front), summary);
  search_detail::count_as_printed(summary->front, options);
  search_detail::mark_minor_steps(summary->front, options.min_step);
  if (!options.uniform.empty()) {
    for (FrontMember& m : summary->front) {
      m.uniform = options.uniform;
      m.material_cost =
          split_instruction_count(m.expression, options.uniform,
                                  instruction_target_of(options.cost).value_or(InstructionTarget::Sass))
              .per_material;
    }
  }
}

}  // namespace shaderfit
