#include "shaderfit/search/search.hpp"

#include <algorithm>
#include <cmath>
#include <locale>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "search/checkpoint.hpp"
#include "search/enumerator.hpp"
#include "search/evolution.hpp"
#include "search/float32_check.hpp"
#include "search/search_context.hpp"

namespace shaderfit {

namespace {

constexpr Op kSearchable[] = {Op::Add,  Op::Sub,   Op::Mul, Op::Div,      Op::IPow,
                              Op::Sqrt, Op::Rsqrt, Op::Rcp, Op::Exp2,     Op::Log2,
                              Op::Exp,  Op::Log,   Op::Abs, Op::Saturate, Op::Sin,
                              Op::Cos,  Op::Min,   Op::Max, Op::Pow};

std::string_view list_name(Op op) {
  switch (op) {
    case Op::IPow: return "^";
    default: return op_info(op).name;
  }
}

std::string known_operators() {
  std::string s;
  for (Op op : kSearchable) {
    if (!s.empty()) s += ' ';
    s += list_name(op);
  }
  return s;
}

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
    for (double v : inputs[i])
      if (!std::isfinite(v))
        throw Error("input '" + input_names[i] + "' holds a NaN or infinite value", where);
  }
  for (double v : target)
    if (!std::isfinite(v)) throw Error("the target holds a NaN or infinite value", where);
  if (!weights.empty()) {
    if (weights.size() != rows)
      throw Error("the weights have a different number of rows than the target", where);
    double sum = 0;
    for (double w : weights) {
      if (!(w >= 0) || !std::isfinite(w)) throw Error("weights must be finite and >= 0", where);
      sum += w;
    }
    if (!(sum > 0)) throw Error("the weights sum to 0", where);
  }
}

bool SearchOptions::is_valid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why != nullptr) *why = std::move(msg);
    return false;
  };
  if (!(time_limit_s > 0) || !std::isfinite(time_limit_s))
    return fail("the time budget must be a positive number of seconds");
  if (max_candidates && *max_candidates <= 0) return fail("the evaluation budget must be positive");
  if (threads < 0) return fail("threads must be >= 0 (0: all hardware threads)");
  if (loss == Loss::MaxRel) return fail("loss must be mse, rmse, max_abs, rel or log");
  if (operators.empty()) return fail("no operators given");
  for (const auto* list : {&operators, &evolution_operators}) {
    for (Op op : *list) {
      if (std::find(std::begin(kSearchable), std::end(kSearchable), op) == std::end(kSearchable))
        return fail("operator '" + std::string(op_info(op).name) + "' cannot be searched");
    }
  }
  if (max_power < 2 || max_power > kMaxIntegerPower) return fail("max_power must be in [2, 16]");
  if (literals.size() > 100) return fail("at most 100 literal constants");
  for (double v : literals)
    if (!std::isfinite(v)) return fail("literal constants must be finite");
  if (screen_rows < 16 || screen_rows % 8 != 0)
    return fail("screen_rows must be a multiple of 8, at least 16");
  if (max_classes < 1024) return fail("max_classes must be at least 1024");
  if (!(max_enumeration_share >= 0 && max_enumeration_share <= 1))
    return fail("max_enumeration_share must be in [0, 1]");
  if (max_enumeration_cost < 0 || max_enumeration_cost > 60)
    return fail("max_enumeration_cost must be in [0, 60]");
  if (max_nodes < 1) return fail("max_nodes must be at least 1");
  if (population < 4) return fail("population must be at least 4");
  if (islands < 1) return fail("islands must be at least 1");
  if (migration_interval < 1) return fail("migration_interval must be at least 1");
  if (max_parameters < 0 || max_parameters > 8) return fail("max_parameters must be in [0, 8]");
  if (fit_rows < 8) return fail("fit_rows must be at least 8");
  if (!(progress_interval_s > 0)) return fail("progress_interval_s must be positive");
  if (!(checkpoint_interval_s >= 0) || !std::isfinite(checkpoint_interval_s))
    return fail("the checkpoint interval must be a number of seconds >= 0");
  return true;
}

CheckpointInfo read_checkpoint_info(const std::string& path) {
  const search_detail::Checkpoint c = search_detail::read_checkpoint(path);
  CheckpointInfo info;
  info.phase = c.phase;
  info.elapsed_s = c.elapsed_s;
  info.candidates = c.candidates;
  info.generations = c.evolution.generations;
  info.front_size = c.front.size();
  return info;
}

std::vector<Op> parse_operator_list(std::string_view list, const SourceLocation& where) {
  std::vector<Op> ops;
  std::size_t pos = 0;
  while (pos <= list.size()) {
    std::size_t end = list.find(',', pos);
    if (end == std::string_view::npos) end = list.size();
    std::string_view name = list.substr(pos, end - pos);
    while (!name.empty() && name.front() == ' ') name.remove_prefix(1);
    while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
    pos = end + 1;
    if (name.empty()) continue;
    Op op = Op::Count_;
    if (name == "^" || name == "ipow")
      op = Op::IPow;
    else if (name == "add")
      op = Op::Add;
    else if (name == "sub")
      op = Op::Sub;
    else if (name == "mul")
      op = Op::Mul;
    else if (name == "div")
      op = Op::Div;
    else
      op = op_from_name(name);
    if (std::find(std::begin(kSearchable), std::end(kSearchable), op) == std::end(kSearchable)) {
      throw Error("unknown operator '" + std::string(name) + "' (known: " + known_operators() + ")",
                  where);
    }
    if (std::find(ops.begin(), ops.end(), op) == ops.end()) ops.push_back(op);
  }
  if (ops.empty()) throw Error("no operators given (known: " + known_operators() + ")", where);
  return ops;
}

std::string operator_list_name(const std::vector<Op>& ops) {
  std::string s;
  for (Op op : ops) {
    if (!s.empty()) s += ',';
    s += list_name(op);
  }
  return s;
}

void run_search(const SearchOptions& options, const SearchProblem& problem,
                SearchSummary* summary) {
  problem.validate();
  std::string why;
  if (!options.is_valid(&why)) throw Error(why, {"options"});
  if (options.loss == Loss::Relative &&
      std::any_of(problem.target.begin(), problem.target.end(), [](double t) { return t == 0; }))
    throw Error("the rel loss needs a target that is never 0", {"--loss"});
  if (options.loss == Loss::Log &&
      std::any_of(problem.target.begin(), problem.target.end(), [](double t) { return !(t > 0); }))
    throw Error("the log loss needs a target that is always > 0", {"--loss"});

  using search_detail::Checkpoint;
  std::optional<Checkpoint> resumed;
  if (!options.resume_path.empty()) {
    resumed = search_detail::read_checkpoint(options.resume_path);
    search_detail::check_checkpoint_matches(*resumed, options, problem, options.resume_path);
  }
  // Before any work, so that --device cuda without a GPU fails at once.
  const ComputeDevice device = resolve_device(options.device, {"--device"});
  search_detail::SearchContext ctx(options, problem);
  ctx.device = device;
  std::unique_ptr<search_detail::Checkpointer> checkpoints;
  if (!options.checkpoint_path.empty()) {
    checkpoints = std::make_unique<search_detail::Checkpointer>(ctx);
    ctx.checkpointer = checkpoints.get();
  }
  Rng rng(options.seed);
  SearchSummary s;
  if (resumed && resumed->phase == "evolution") {
    // From the generation boundary the checkpoint recorded: the enumeration is not run again.
    ctx.resume_clock(resumed->elapsed_s);
    ctx.candidates.store(resumed->candidates);
    ctx.node_evaluations.store(resumed->node_evaluations);
    for (FrontMember& m : resumed->front) ctx.front.offer(std::move(m));
    s.distinct_candidates = resumed->distinct_candidates;
    s.enumeration_cost_completed = resumed->enumeration_cost_completed;
    s.enumeration_time_s = resumed->enumeration_time_s;
    std::istringstream state(resumed->rng);
    state.imbue(std::locale::classic());
    state >> rng;
    if (checkpoints)
      checkpoints->begin_evolution(s.enumeration_time_s, s.distinct_candidates,
                                   s.enumeration_cost_completed, rng);
    search_detail::Evolution evolution(ctx, rng);
    evolution.resume(resumed->evolution);
    s.generations = evolution.generations();
  } else {
    // Afresh, or from a checkpoint taken during the enumeration: the enumeration runs again
    // (with count stops it finds the same classes), then the checkpoint's front joins.
    std::vector<Expression> seeds;
    if (options.enumerate) {
      search_detail::Enumerator enumerator(ctx, rng);
      enumerator.run();
      s.distinct_candidates = enumerator.classes();
      s.enumeration_cost_completed = enumerator.cost_completed();
      if (options.evolve) seeds = enumerator.seeds(options.population);
    }
    if (resumed)
      for (FrontMember& m : resumed->front) ctx.front.offer(std::move(m));
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
  s.total_time_s = ctx.elapsed();
  s.evolution_time_s = s.total_time_s - s.enumeration_time_s;
  s.front = ctx.front.members();
  const search_detail::Float32Check float32(problem);
  for (FrontMember& m : s.front) float32.apply(m);
  s.candidates = ctx.candidates.load();
  s.node_evaluations = ctx.node_evaluations.load();
  s.termination = ctx.stop_reason();
  if (s.termination.empty()) s.termination = "done";
  s.interrupted = s.termination == "interrupted";
  *summary = std::move(s);
}

}  // namespace shaderfit
