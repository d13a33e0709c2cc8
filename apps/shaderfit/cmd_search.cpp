// shaderfit search: symbolic regression, the Pareto front of error against GPU cost. The JSON
// schema and the method are in docs/search.md.
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>
#include <type_traits>
#include <variant>

#include "data_source.hpp"
#include "progress_bar.hpp"
#include "cli.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/report/scene_report.hpp"
#include "shaderfit/report/search_json.hpp"
#include "shaderfit/search/front/choice.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/front/front_table.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit::cli {

namespace {

// The search's options come from their description (shaderfit/search/options.hpp): one flag per
// described field, named by search_option_flag, with the field's help and its default. A few
// fields are set through flags of their own: --strategy (enumerate, evolve), --stop-loss and
// --stop-cost (stop_at).
struct SearchArgs {
  DataSource data;
  std::string weights;
  SearchOptions options;  // plain fields are bound to their flags directly
  // The other fields' flags, read after parsing: optional integers, and the text of lists,
  // choices and the like.
  std::map<std::string_view, std::int64_t> integers;
  std::map<std::string_view, std::string> texts;
  std::string strategy = "both";
  std::string json_path;
  std::string choose = "knee";  // the rule for the closing "chosen:" lines (search/choice.hpp)
  bool quiet = false;
  int digits = 0;
  double stop_loss = -1, stop_cost = -1;
};

// `problem`: a built-in data set's own operators apply unless the user names others.
SearchOptions make_options(const SearchArgs& a, const CLI::App& cmd, const Problem& problem) {
  SearchOptions o = a.options;
  if (!problem.operators.empty()) set_search_option(o, "operators", problem.operators);
  if (!problem.evolution_operators.empty())
    set_search_option(o, "evolution_operators", problem.evolution_operators);
  for (const SearchOptionField& f : search_option_fields()) {
    if (cmd.count(search_option_flag(f.name)) == 0) continue;
    if (const auto i = a.integers.find(f.name); i != a.integers.end())
      set_search_option(o, f, std::to_string(i->second));
    if (const auto text = a.texts.find(f.name); text != a.texts.end())
      set_search_option(o, f, text->second);
  }
  if (a.strategy == "enumerate")
    o.evolve = false;
  else if (a.strategy == "evolve")
    o.enumerate = false;
  else if (a.strategy != "both")
    throw Error("unknown strategy '" + a.strategy + "' (known: both, enumerate, evolve)",
                {"--strategy"});
  // A resumed run keeps its checkpoint current unless told to write another.
  if (o.checkpoint_path.empty()) o.checkpoint_path = o.resume_path;
  if (a.stop_loss >= 0 || a.stop_cost >= 0) {
    o.stop_at = SearchTarget{a.stop_loss >= 0 ? a.stop_loss : 1e300,
                             a.stop_cost >= 0 ? a.stop_cost : 1e300};
  }
  o.validate();
  o.device = search_device(o);  // a device that cannot be used stops here, before any work
  return o;
}

// Each member in the scene: the displayed pixels' errors and FLIP against the reference's picture.
std::string scene_table(const Problem& source, const std::vector<FrontMember>& front,
                        Precision precision, const PrintOptions& print) {
  std::string out = fmt::format(
      "in the {} scene (display: exposure, ACES tonemap, sRGB):\n{:>6} {:>12} {:>12} {:>10} {:>9}  "
      "{}\n",
      scene_kind_name(source.scene->spec.kind), "cost", "display rmse", "display max", "mean FLIP",
      "visible", "formula");
  for (const FrontMember& m : front) {
    const SceneImages im = formula_scene_images(source, m.expression, precision);
    out += fmt::format("{:>6g} {:>12.4g} {:>12.4g} {:>10.4g} {:>8.2f}%  {}\n", m.cost,
                       im.display_rmse, im.display_max, im.flip.mean, 100 * im.visible_share,
                       to_infix(m.expression, print));
  }
  out += fmt::format("visible: the share of pixels with FLIP above {:g}\n", kFlipVisible);
  return out;
}

void run(const SearchArgs& a, const CLI::App& cmd, Context& ctx) {
  const ChoiceRule choice = parse_choice_rule(a.choose, {"ChoiceRule"});
  const PrintOptions print = PrintOptions::for_people(a.digits);
  const auto t0 = std::chrono::steady_clock::now();
  ProblemSource recorded;
  const Problem source = load_problem(a.data, &recorded);
  SearchOptions options = make_options(a, cmd, source);
  options.communicator = ctx.communicator;
  const bool leader = ctx.communicator == nullptr || ctx.communicator->rank() == 0;
  const Dataset& d = source.data;
  SearchProblem problem = search_problem(source, options.loss, a.weights, {"--weights"});
  problem.reference_samples = a.data.problem.samples;
  // Before anything is printed, so that a bad list is the only line.
  check_uniform_inputs(options.uniform, problem.input_names, {"--uniform"});
  const double load_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // "auto" operator lists become concrete here, so that the JSON and checkpoints name them.
  const bool auto_ops =
      is_auto_operators(options.operators) || is_auto_operators(options.evolution_operators);
  options = resolve_auto_operators(options, problem);

  // With the JSON on stdout, everything for people goes to stderr.
  const bool json_stdout = a.json_path == "-";
  std::ostream& human = json_stdout ? ctx.err : ctx.out;
  std::string inputs;
  for (const std::string& n : problem.input_names) inputs += (inputs.empty() ? "" : ",") + n;
  human << fmt::format(
      "shaderfit search: {}, inputs {}, target {}, loss {}, cost {}, device {} "
      "(data ready in {:.1f} ms)\n",
      // A reference's description counts its samples already.
      source.reference ? source.description
                       : fmt::format("{}, {} rows", source.description, d.rows()),
      inputs, source.target, loss_name(options.loss), cost_target_name(options.cost),
      options.device == ComputeDevice::Cuda ? "cuda (" + cuda_device_name() + ")" : "cpu",
      load_s * 1e3);
  human << problem_notes(source, "");
  if (options.loss == Loss::Display)
    human << "display loss: each sample weighted by its pixel's squared display slope (exposure, "
             "tonemap, sRGB)\n";
  if (auto_ops)
    human << fmt::format(
        "operators (auto): {}; the evolution also {}\n", operator_list_name(options.operators),
        options.evolution_operators.empty() ? "none"
                                            : operator_list_name(options.evolution_operators));
  // The reference's own formula: the front's first member, or one line on why it is not.
  if (const reference::ProgramFormula own = reference_formula(problem); own.formula) {
    const std::string off = reference_off_front(options, problem);
    human << fmt::format("reference: {} {}{} as written, {}; the search descends from it\n",
                         expression_cost(*own.formula, options.cost, options.uniform),
                         cost_target_name(options.cost),
                         options.uniform.empty() ? "" : " per pixel",
                         off.empty() ? "the front's first member" : "not on the front: " + off);
  } else if (!own.why.empty()) {
    human << "reference: not on the front as written: " << own.why;
    if (const std::optional<double> cost = reference_cost(options, problem))
      human << fmt::format(" (it costs {} {}{})", *cost, cost_target_name(options.cost),
                           options.uniform.empty() ? "" : " per pixel");
    human << "\n";
  }
  ProgressBar bar(ctx, "search");
  if (!a.quiet) {
    options.on_new_member = [&](const FrontMember& m) {
      bar.clear();
      human << front_member_line(m, options.loss, print) << '\n' << std::flush;
    };
  }
  if (bar.active()) {
    // Done: the larger share of the time budget or of the candidate budget.
    options.on_progress = [&](const SearchProgress& p) {
      double done = p.elapsed_s / options.time_limit_s;
      if (options.max_candidates)
        done = std::max(
            done, static_cast<double>(p.candidates) / static_cast<double>(*options.max_candidates));
      bar.update(done, fmt::format("{}, front {}, {:.3g} candidates ({:.3g}/s)",
                                   search_phase_name(p.phase), p.front_size,
                                   static_cast<double>(p.candidates), p.candidates_per_s));
    };
  }
  if (!options.resume_path.empty() && leader) {  // rank 0 reads the file for all ranks
    const CheckpointInfo c = read_checkpoint_info(options.resume_path);
    const int ranks = ctx.communicator != nullptr ? ctx.communicator->size() : 1;
    human << fmt::format(
        "resuming from {}: {} after {:.3g} s, {} generations, {} candidates, front of {}{}{}\n",
        options.resume_path, search_phase_name(c.phase), c.elapsed_s, c.generations, c.candidates,
        c.front_size, c.phase == SearchPhase::Enumeration ? " (the enumeration runs again)" : "",
        c.ranks != ranks ? fmt::format("; written by {} rank{}, resumed on {}: the islands are "
                                       "shared out again, and the run goes on as it would have",
                                       c.ranks, c.ranks == 1 ? "" : "s", ranks)
                         : "");
  }
  SearchSummary summary;
  {
    const StopSignals stop;
    options.interrupt = stop.flag();
    run_search(options, problem, &summary);
  }
  bar.clear();
  if (!leader) return;  // rank 0 reports and writes the files

  human << search_summary_lines(summary) << front_table(summary, options.loss, print);
  if (source.scene) human << scene_table(source, summary.front, options.precision, print);
  if (!summary.front.empty()) {
    const Choice c = choose_member(summary.front, choice, loss_name(options.loss));
    human << chosen_formula_lines(to_infix(summary.front[c.index].expression, print),
                                  choice_rule_description(choice), c.why);
  }
  if (summary.interrupted)
    ctx.err << "shaderfit: interrupted; the front found so far is above"
            << (options.checkpoint_path.empty()
                    ? std::string()
                    : "; resume with --resume " + options.checkpoint_path)
            << '\n';
  if (!a.json_path.empty()) {
    SearchDataInfo info{source.description, source.target, load_s, d.rows(), problem.input_names};
    info.problem = recorded;
    const std::string text = search_json(summary, options, info);
    if (json_stdout) {
      ctx.out << text;
    } else {
      std::ofstream f(a.json_path, std::ios::binary);
      if (!(f << text)) throw Error("cannot write '" + a.json_path + "'", {"--json"});
    }
  }
}

// Help lines the command line words differently from the library (they name flags).
std::string_view help_for(const SearchOptionField& f) {
  if (f.name == "checkpoint_path")
    return "write the search's state to this file (atomically) every --checkpoint-every seconds "
           "and when it stops (Ctrl-C, SIGTERM, a budget)";
  if (f.name == "resume_path")
    return "continue the search a checkpoint recorded (same data and options; the budgets may "
           "differ); it keeps that file current unless --checkpoint names another";
  if (f.name == "loss")
    return "mse, rmse, max_abs, max_rel, rel or log; or display, with --scene: the error of the "
           "displayed pixels (docs/scenes.md)";
  return f.help;
}

void add_search_option(CLI::App* cmd, SearchArgs& a, const SearchOptionField& f) {
  const std::string flag = search_option_flag(f.name);
  const std::string shown = search_option_text(SearchOptions{}, f);
  std::string help(help_for(f));
  if (!shown.empty() && search_option_kind(f) != OptionKind::Bool)
    help += " (default " + shown + std::string(f.default_note) + ")";
  std::visit(
      [&](auto m) {
        using T = std::remove_reference_t<decltype(a.options.*m)>;
        if constexpr (std::is_same_v<T, bool>) {
          const std::string negated = "--no-" + flag.substr(2);
          cmd->add_flag(flag + ",!" + negated, a.options.*m,
                        help + (a.options.*m ? " (default; " + negated + " turns it off)" : ""));
        } else if constexpr (std::is_arithmetic_v<T> || std::is_same_v<T, std::string>) {
          cmd->add_option(flag, a.options.*m, help);
        } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
          // Names: comma-separated or repeated; formulas: repeatable, one per flag (they hold
          // commas).
          CLI::Option* o = cmd->add_option(flag, a.options.*m, help)->allow_extra_args(false);
          if (f.names) o->delimiter(',');
        } else if constexpr (std::is_same_v<T, std::optional<std::int64_t>>) {
          cmd->add_option(flag, a.integers[f.name], help);
        } else {
          cmd->add_option(flag_with_aliases(flag), a.texts[f.name], help);
        }
      },
      f.member);
}

}  // namespace

void register_search_command(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<SearchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "search", "Find the Pareto front of error against GPU cost (symbolic regression)");
  add_data_options(cmd, args->data, DataFiles | References | Scenes | InputsTarget);
  cmd->add_option("--seed-data", args->data.problem.dataset_seed,
                  "seed of the built-in data set (same as --data-seed)");
  cmd->add_option("--weights", args->weights, "column of sample weights (default: all 1)");
  for (const SearchOptionField& f : search_option_fields()) {
    if (f.name == "enumerate") {
      cmd->add_option("--strategy", args->strategy, "both, enumerate or evolve (default both)");
    } else if (f.name == "stop_at") {
      cmd->add_option("--stop-loss", args->stop_loss,
                      "stop once a formula has at most this loss (and --stop-cost)");
      cmd->add_option("--stop-cost", args->stop_cost,
                      "stop once a formula has at most this cost (and --stop-loss)");
      cmd->add_option("--json", args->json_path,
                      "write the result as JSON to this file ('-' for stdout)");
      cmd->add_flag("--quiet", args->quiet, "do not print front members as they are found");
      cmd->add_option("--choose", args->choose, kChooseHelp);
      add_digits_option(cmd, args->digits);
    } else if (f.name != "evolve") {
      add_search_option(cmd, *args, f);
    }
  }
  cmd->callback([args, cmd, &ctx] { run(*args, *cmd, ctx); });
}

}  // namespace shaderfit::cli
