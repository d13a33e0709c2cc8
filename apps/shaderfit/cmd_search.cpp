// shaderfit search: symbolic regression, the Pareto front of error against GPU cost. The JSON
// schema and the method are in docs/search.md.
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <memory>
#include <ostream>
#include <sstream>

#include "data_source.hpp"
#include "shaderfit/cli.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/search/report.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::cli {

namespace {

struct SearchArgs {
  DataSource data;
  std::string inputs = "r0,x";
  std::string target = "R";
  std::string weights;
  double time_s = 10.0;
  std::int64_t evals = 0;
  bool evals_given = false;
  std::uint64_t seed = 1;
  int threads = 0;
  std::string device = "auto";
  std::string loss = "mse";
  std::string cost = "instructions";
  std::string ops = "+,-,*,/,^";
  std::string evolve_ops = "pow,exp2";
  std::string literals = "0.5,1,2";
  int max_power = 5;
  std::size_t max_nodes = 25;
  std::size_t population = 128;
  std::size_t max_classes = 1'500'000;
  std::string strategy = "both";
  std::string json_path;
  bool quiet = false;
  double stop_loss = -1, stop_cost = -1;
  std::string checkpoint_path;
  double checkpoint_every_s = 60;
  std::string resume_path;
};

// SIGINT and SIGTERM set this; the search polls it, writes its checkpoint (with --checkpoint)
// and returns the front found so far.
std::atomic<bool> g_interrupted{false};
extern "C" void on_stop_signal(int) { g_interrupted.store(true); }

std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    while (!item.empty() && item.front() == ' ') item.erase(item.begin());
    while (!item.empty() && item.back() == ' ') item.pop_back();
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

std::vector<double> parse_literals(const std::string& list) {
  std::vector<double> out;
  for (const std::string& s : split_names(list)) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || !std::isfinite(v))
      throw Error("not a number: '" + s + "'", {"--literals"});
    out.push_back(v);
  }
  return out;
}

const std::vector<double>& numeric_column(const Dataset& d, const std::string& name,
                                          const char* option) {
  const Column* c = d.find(name);
  if (c == nullptr) {
    std::string names;
    for (const auto& n : d.names()) names += (names.empty() ? "" : ", ") + n;
    throw Error("no column '" + name + "' in " + (d.source.empty() ? "the data" : d.source) +
                    " (columns: " + names + ")",
                {option});
  }
  return d.numeric(name).values;
}

SearchOptions make_options(const SearchArgs& a) {
  SearchOptions o;
  if (!(a.time_s > 0))
    throw Error("the time budget must be positive (got " + fmt::format("{:g}", a.time_s) + ")",
                {"--time"});
  if (a.evals_given && a.evals <= 0)
    throw Error("the evaluation budget must be positive (got " + std::to_string(a.evals) + ")",
                {"--evals"});
  if (a.threads < 0) throw Error("threads must be >= 0 (0: all cores)", {"--threads"});
  o.time_limit_s = a.time_s;
  if (a.evals_given) o.max_candidates = a.evals;
  o.seed = a.seed;
  o.threads = a.threads;
  const auto device = device_from_name(a.device);
  if (!device)
    throw Error("unknown device '" + a.device + "' (known: auto, cpu, cuda)", {"--device"});
  o.device = resolve_device(*device, {"--device"});  // --device cuda without a GPU stops here
  const auto loss = loss_from_name(a.loss);
  if (!loss || *loss == Loss::MaxRel)  // max_rel ranks rational forms; the search cannot use it
    throw Error("unknown loss '" + a.loss + "' (known: mse, rmse, max_abs, rel, log)", {"--loss"});
  o.loss = *loss;
  const auto cost = cost_target_from_name(a.cost);
  if (!cost) throw Error("unknown cost '" + a.cost + "' (known: instructions, nodes)", {"--cost"});
  o.cost = *cost;
  o.operators = parse_operator_list(a.ops, {"--ops"});
  o.evolution_operators.clear();
  if (!a.evolve_ops.empty() && a.evolve_ops != "none")
    o.evolution_operators = parse_operator_list(a.evolve_ops, {"--evolve-ops"});
  o.literals = parse_literals(a.literals);
  o.max_power = a.max_power;
  o.max_nodes = a.max_nodes;
  o.population = a.population;
  o.max_classes = a.max_classes;
  if (a.strategy == "enumerate")
    o.evolve = false;
  else if (a.strategy == "evolve")
    o.enumerate = false;
  else if (a.strategy != "both")
    throw Error("unknown strategy '" + a.strategy + "' (known: both, enumerate, evolve)",
                {"--strategy"});
  if (!(a.checkpoint_every_s >= 0) || !std::isfinite(a.checkpoint_every_s))
    throw Error("the checkpoint interval must be a number of seconds >= 0", {"--checkpoint-every"});
  o.resume_path = a.resume_path;
  // A resumed run keeps its checkpoint current unless told to write another.
  o.checkpoint_path = a.checkpoint_path.empty() ? a.resume_path : a.checkpoint_path;
  o.checkpoint_interval_s = a.checkpoint_every_s;
  if (a.stop_loss >= 0 || a.stop_cost >= 0) {
    o.stop_at = SearchTarget{a.stop_loss >= 0 ? a.stop_loss : 1e300,
                             a.stop_cost >= 0 ? a.stop_cost : 1e300};
  }
  std::string why;
  if (!o.is_valid(&why)) throw Error(why, {"search options"});
  return o;
}

void run(const SearchArgs& a, Context& ctx) {
  SearchOptions options = make_options(a);
  const auto t0 = std::chrono::steady_clock::now();
  const Dataset d = load_data(a.data);
  SearchProblem problem;
  problem.input_names = split_names(a.inputs);
  if (problem.input_names.empty()) throw Error("no inputs given", {"--inputs"});
  for (const std::string& n : problem.input_names)
    problem.inputs.push_back(numeric_column(d, n, "--inputs"));
  problem.target = numeric_column(d, a.target, "--target");
  if (!a.weights.empty()) problem.weights = numeric_column(d, a.weights, "--weights");
  problem.validate();
  const double load_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // With the JSON on stdout, everything for people goes to stderr.
  const bool json_stdout = a.json_path == "-";
  std::ostream& human = json_stdout ? ctx.err : ctx.out;
  human << fmt::format(
      "shaderfit search: {}, {} rows, inputs {}, target {}, loss {}, cost {}, device {} "
      "(data ready in {:.1f} ms)\n",
      a.data.describe(), d.rows(), a.inputs, a.target, loss_name(options.loss),
      cost_target_name(options.cost),
      options.device == ComputeDevice::Cuda ? "cuda (" + cuda_device_name() + ")" : "cpu",
      load_s * 1e3);
  bool progress_shown = false;
  if (!a.quiet) {
    options.on_new_member = [&](const FrontMember& m) {
      if (progress_shown) ctx.err << "\r\033[K";
      progress_shown = false;
      human << front_member_line(m, options.loss) << '\n' << std::flush;
    };
  }
  if (ctx.progress) {
    options.on_progress = [&](const SearchProgress& p) {
      ctx.err << fmt::format("\r\033[K[{:.1f} s] {} {} candidates, {:.3g}/s, front {}", p.elapsed_s,
                             p.phase, p.candidates, p.candidates_per_s, p.front_size)
              << std::flush;
      progress_shown = true;
    };
  }
  if (!options.resume_path.empty()) {
    const CheckpointInfo c = read_checkpoint_info(options.resume_path);
    human << fmt::format(
        "resuming from {}: {} after {:.3g} s, {} generations, {} candidates, front of {}{}\n",
        options.resume_path, c.phase, c.elapsed_s, c.generations, c.candidates, c.front_size,
        c.phase == "enumeration" ? " (the enumeration runs again)" : "");
  }
  g_interrupted.store(false);
  options.interrupt = &g_interrupted;
  auto previous_int = std::signal(SIGINT, on_stop_signal);
  auto previous_term = std::signal(SIGTERM, on_stop_signal);
  auto restore_signals = [&] {
    std::signal(SIGINT, previous_int);
    std::signal(SIGTERM, previous_term);
  };
  SearchSummary summary;
  try {
    run_search(options, problem, &summary);
  } catch (...) {
    restore_signals();
    throw;
  }
  restore_signals();
  if (progress_shown) ctx.err << "\r\033[K" << std::flush;

  human << summary.brief_report();
  if (summary.interrupted)
    ctx.err << "shaderfit: interrupted; the front found so far is above"
            << (options.checkpoint_path.empty()
                    ? std::string()
                    : "; resume with --resume " + options.checkpoint_path)
            << '\n';
  if (!a.json_path.empty()) {
    SearchDataInfo info{a.data.describe(), a.target, load_s, d.rows(), problem.input_names};
    const std::string text = search_json(summary, options, info);
    if (json_stdout) {
      ctx.out << text;
    } else {
      std::ofstream f(a.json_path, std::ios::binary);
      if (!(f << text)) throw Error("cannot write '" + a.json_path + "'", {"--json"});
    }
  }
}

}  // namespace

void register_search_command(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<SearchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "search", "Find the Pareto front of error against GPU cost (symbolic regression)");
  add_data_options(cmd, args->data, false);
  cmd->add_option("--seed-data", args->data.seed,
                  "seed of the built-in data set (same as --data-seed)");
  cmd->add_option("--inputs", args->inputs, "input columns, comma-separated (default r0,x)");
  cmd->add_option("--target", args->target, "target column (default R)");
  cmd->add_option("--weights", args->weights, "column of sample weights (default: all 1)");
  cmd->add_option("--time", args->time_s, "time budget in seconds (default 10)");
  cmd->add_option("--evals", args->evals, "budget of candidate formulas evaluated")
      ->each([a = args.get()](const std::string&) { a->evals_given = true; });
  cmd->add_option("--seed", args->seed, "seed of the search (default 1)");
  cmd->add_option("--threads", args->threads, "threads, 0 for all cores (default 0)");
  cmd->add_option("--device", args->device,
                  "cpu, cuda or auto: where the evolution scores its children (default auto: the "
                  "GPU when this build has CUDA and one is present)");
  cmd->add_option("--loss", args->loss, "mse, rmse, max_abs, rel or log (default mse)");
  cmd->add_option("--cost", args->cost, "instructions or nodes (default instructions)");
  cmd->add_option("--ops", args->ops,
                  "operators, comma-separated: + - * / ^ sqrt rsqrt rcp exp2 log2 exp log abs "
                  "saturate sin cos min max pow (default +,-,*,/,^)");
  cmd->add_option("--evolve-ops", args->evolve_ops,
                  "more operators for the evolution only, or 'none' (default pow,exp2)");
  cmd->add_option("--literals", args->literals,
                  "literal constants, comma-separated (default 0.5,1,2)");
  cmd->add_option("--max-power", args->max_power, "largest integer power x^k (default 5)");
  cmd->add_option("--max-nodes", args->max_nodes,
                  "largest formula of the evolution, in nodes (default 25)");
  cmd->add_option("--population", args->population,
                  "formulas per island of the evolution (default 128)");
  cmd->add_option("--max-classes", args->max_classes,
                  "distinct formulas the enumeration keeps; bounds the memory, about 500 bytes "
                  "each (default 1500000)");
  cmd->add_option("--strategy", args->strategy, "both, enumerate or evolve (default both)");
  cmd->add_option("--stop-loss", args->stop_loss,
                  "stop once a formula has at most this loss (and --stop-cost)");
  cmd->add_option("--stop-cost", args->stop_cost,
                  "stop once a formula has at most this cost (and --stop-loss)");
  cmd->add_option("--json", args->json_path,
                  "write the result as JSON to this file ('-' for stdout)");
  cmd->add_flag("--quiet", args->quiet, "do not print front members as they are found");
  cmd->add_option("--checkpoint", args->checkpoint_path,
                  "write the search's state to this file (atomically) every --checkpoint-every "
                  "seconds and when it stops (Ctrl-C, SIGTERM, a budget)");
  cmd->add_option("--checkpoint-every", args->checkpoint_every_s,
                  "seconds between checkpoints (default 60; 0: every generation)");
  cmd->add_option("--resume", args->resume_path,
                  "continue the search a checkpoint recorded (same data and options; the budgets "
                  "may differ); it keeps that file current unless --checkpoint names another");
  cmd->callback([args, &ctx] { run(*args, ctx); });
}

}  // namespace shaderfit::cli
