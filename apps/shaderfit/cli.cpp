#include "cli.hpp"

#include <unistd.h>

#include <csignal>
#include <iostream>

#include "shaderfit/core/error.hpp"
#include "shaderfit/search/options.hpp"

namespace shaderfit::cli {

namespace {

// A library location (a field such as "FitSetup::grid", or a concept such as "Material") and
// the flag that sets it.
struct FieldFlag {
  std::string_view field;
  std::string_view flag;
};

// The one table of library locations and the flags that set them, for every command. Search
// options not listed take --<field name> (search_option_flag).
constexpr FieldFlag kFlags[] = {
    // shaderfit search: historical names.
    {"SearchOptions::time_limit_s", "--time"},
    {"SearchOptions::max_candidates", "--evals"},
    {"SearchOptions::operators", "--ops"},
    {"SearchOptions::evolution_operators", "--evolve-ops"},
    {"SearchOptions::enumerate", "--strategy"},
    {"SearchOptions::evolve", "--strategy"},
    {"SearchOptions::stop_at", "--stop-loss"},
    {"SearchOptions::checkpoint_path", "--checkpoint"},
    {"SearchOptions::checkpoint_interval_s", "--checkpoint-every"},
    {"SearchOptions::resume_path", "--resume"},
    {"SearchOptions::certify_time_limit_s", "--certify-time"},
    {"SearchReportOptions::formula", "--choose"},
    // What to approximate (problem/problem.hpp), for every command that reads data.
    {"ProblemSource::drop_nonfinite", "--drop-nonfinite"},
    {"ProblemSource::drop_missing_rows", "--drop-missing"},
    {"CsvOptions::drop_missing_rows", "--drop-missing"},
    {"ProblemSource::dataset_seed", "--data-seed"},
    {"ProblemSource::reference", "--reference"},
    {"ReferenceText::shader_path", "--reference-file"},
    {"ProblemSource::csv_path", "--data"},
    {"ProblemSource::dataset", "--dataset"},
    {"ProblemSource::samples", "--samples"},
    {"ProblemSource::domain", "--domain"},
    {"ProblemSource::inputs", "--inputs"},
    {"ProblemSource::target", "--target"},
    {"ProblemSource::scene", "--scene"},
    {"ProblemSource::materials", "--material"},
    {"ProblemSource::angles", "--angles"},
    {"SceneSpec::kind", "--scene"},
    {"SceneSpec::size", "--scene-size"},
    {"SceneSpec::term", "--term"},
    {"SceneSpec::exposure", "--exposure"},
    {"ReferenceText::function", "--function"},
    {"ReferenceText::definitions", "--define"},
    {"ChoiceRule", "--choose"},
    // shaderfit fit.
    {"FitSetup::random_samples", "--random-samples"},
    {"FitSetup::definitions", "--define"},
    {"FitSetup::constraints", "--constraint"},
    {"FitSetup::parameters", "--param"},
    {"FitSetup::reference_source", "--reference-file"},
    {"FitSetup::reference_path", "--reference-file"},
    {"FitSetup::reference", "--reference"},
    {"FitSetup::function", "--function"},
    {"FitSetup::samples", "--samples"},
    {"FitSetup::transform", "--transform"},
    {"FitSetup::baselines", "--baseline"},
    {"FitSetup::per_group", "--per-group"},
    {"FitSetup::per_cell", "--per-cell"},
    {"FitSetup::rng_seed", "--rng-seed"},
    {"FitSetup::formula", "formula"},
    {"FitSetup::domain", "--domain"},
    {"FitSetup::target", "--target"},
    {"FitSetup::weight", "--weight"},
    {"FitSetup::grid", "--grid"},
    {"FitSetup::data", "--data"},
    {"FitSetup::inputs", "--inputs"},
    {"FitSetup::drop_nonfinite", "--drop-nonfinite"},
    // shaderfit rational.
    {"RationalProblem::parameter_values", "--param"},
    {"RationalProblem::parameter_names", "--param"},
    {"RationalProblem::conditions", "--cond"},
    {"RationalProblem::target", "--target"},
    {"RationalProblem::domain", "--domain"},
    {"RationalSetup::conditions", "--cond"},
    {"RationalSetup::parameters", "--param"},
    {"RationalSetup::transforms", "--transform"},
    {"RationalSetup::target", "--target"},
    {"RationalSetup::domain", "--domain"},
    {"RationalSetup::count", "--count"},
    {"RationalSetup::reference_source", "--reference-file"},
    {"RationalSetup::function", "--function"},
    {"RationalSetup::variable", "--var"},
    {"RationalSetup::forms", "--form"},
    {"RationalOptions::fit = Fit::LeastSquares", "--fit lsq"},
    {"Fit::Minimax", "--minimax"},
    {"RationalForm", "--form"},
    {"Transform", "--transform"},
    // Other commands.
    {"ComputeDevice", "--device"},
    {"CodegenOptions::name", "--name"},
    {"CodegenOptions::precision", "--precision"},
    {"CodegenOptions::uniform", "--uniform"},
    {"Expression::variables", "--inputs"},
    {"Expression::parameters", "--params"},
    {"UniformInputs", "--uniform"},
    {"SphereScene::roughness", "--roughness"},
    {"SphereScene::f0", "--f0"},
    {"SphereScene::light", "--light"},
    {"SphereScene::size", "--size"},
    {"Material", "--material"},
    {"fresnel_sweep::materials", "--material"},
    {"fresnel_sweep::angles", "--angles"},
    {"compare_with_exact", "--compare-exact"},
    {"PrintOptions::digits", "--digits"},
};

constexpr std::string_view kSearchOptions = "SearchOptions::";

// The message with every field the table names ("declare it with FitSetup::parameters")
// written as its flag. Only qualified names (Type::field) are replaced: a bare concept such as
// "Material" is also an ordinary word.
std::string message_in_flags(std::string text) {
  for (const FieldFlag& f : kFlags) {
    if (f.field.find("::") == std::string_view::npos) continue;
    for (std::size_t at = text.find(f.field); at != std::string::npos;
         at = text.find(f.field, at + f.flag.size()))
      text.replace(at, f.field.size(), f.flag);
  }
  return text;
}

// e.what() with the library's location and the fields in its message written as flags.
std::string error_text(const shaderfit::Error& e) {
  SourceLocation where = e.where();
  const std::string flag = flag_for_location(where.source);
  // A location with more than the field ("FitSetup::constraints 1": the first constraint) keeps
  // the rest.
  where.source = flag.empty() ? message_in_flags(where.source) : flag;
  return shaderfit::Error(message_in_flags(e.message()), where).what();
}

void print_error(std::ostream& err, const std::string& text) {
  // One line, whatever the message holds.
  std::string line = text;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  err << "shaderfit: error: " << line << '\n';
}

}  // namespace

std::string search_option_flag(std::string_view field_name) {
  for (const auto& [location, flag] : kFlags)
    if (location.starts_with(kSearchOptions) &&
        location.substr(kSearchOptions.size()) == field_name)
      return std::string(flag);
  std::string flag = "--" + std::string(field_name);
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

std::string flag_with_aliases(const std::string& flag) {
  // --cost-target: the name cost, eval and the Python layer use for the same choice.
  if (flag == "--cost") return flag + ",--cost-target";
  return flag;
}

std::string flag_for_location(std::string_view location) {
  for (const FieldFlag& f : kFlags)
    if (f.field == location) return std::string(f.flag);
  if (location.starts_with(kSearchOptions) &&
      find_search_option(location.substr(kSearchOptions.size())) != nullptr)
    return search_option_flag(location.substr(kSearchOptions.size()));
  return {};
}

const char* const kChooseHelp =
    "which front member is the chosen formula: knee (default: the knee of the front, where more "
    "cost stops buying much accuracy), cost=N (the most accurate costing at most N) or error=E "
    "(the cheapest with error at most E)";

std::string chosen_formula_lines(const std::string& formula, const std::string& how,
                                 const std::string& why, bool by_rule) {
  std::string s = "chosen: " + formula + "\n  how: " + how;
  if (by_rule) s += " (--choose knee, cost=N or error=E)";
  return s + "\n  why: " + why + "\n";
}

void add_name_options(CLI::App* cmd, std::vector<std::string>& inputs,
                      std::vector<std::string>& params) {
  cmd->add_option("--inputs", inputs, "input names in argument order (comma-separated)")
      ->delimiter(',')
      ->allow_extra_args(false);
  cmd->add_option("--params", params, "names that are free parameters (comma-separated)")
      ->delimiter(',')
      ->allow_extra_args(false);
}

void add_uniform_option(CLI::App* cmd, std::vector<std::string>& uniform) {
  cmd->add_option("--uniform", uniform,
                  "inputs constant per material (comma-separated): what reads only them is "
                  "computed once per material, and the cost is per pixel")
      ->delimiter(',')
      ->allow_extra_args(false);
}

void add_digits_option(CLI::App* cmd, int& digits) {
  cmd->add_option("--digits", digits,
                  "print constants with this many significant digits (default: the shortest text "
                  "that reads back to the same float32)");
}

void add_precision_option(CLI::App* cmd, std::string& precision, const std::string& what,
                          const std::string& default_note) {
  cmd->add_option("--precision", precision,
                  "double, float or half: the arithmetic " + what +
                      ", every operation rounded as a shader does (default " + default_note + ")");
}

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_stop_signal(int) { g_stop.store(true); }
}  // namespace

StopSignals::StopSignals()
    : previous_int_(std::signal(SIGINT, on_stop_signal)),
      previous_term_(std::signal(SIGTERM, on_stop_signal)) {
  g_stop.store(false);
}

StopSignals::~StopSignals() {
  std::signal(SIGINT, previous_int_);
  std::signal(SIGTERM, previous_term_);
}

const std::atomic<bool>* StopSignals::flag() const { return &g_stop; }

Precision precision_option(const std::string& text) {
  return parse_precision(text, SourceLocation{"--precision"});
}

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err,
            Communicator* communicator) {
  CLI::App app{"shaderfit: cheap formulas for expensive shading functions", "shaderfit"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "shaderfit 0.1.0");
  // Progress bars only on a terminal: stderr itself (not a stream a caller passed), a tty.
  Context ctx{out, err, &err == &std::cerr && isatty(STDERR_FILENO) != 0, communicator};

  register_eval_command(app, ctx);
  register_search_command(app, ctx);
  register_cost_command(app, ctx);
  register_codegen_command(app, ctx);
  register_plot_command(app, ctx);
  register_report_command(app, ctx);
  register_fit_command(app, ctx);
  register_lut_command(app, ctx);
  register_rational_command(app, ctx);
  register_batch_command(app, ctx);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    out << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion& e) {
    out << e.what() << '\n';
    return 0;
  } catch (const CLI::ParseError& e) {
    // Subcommand help goes through here too (CLI11 raises it from the subcommand).
    if (e.get_exit_code() == 0) {
      CLI::App* sub = app.get_subcommands().empty() ? &app : app.get_subcommands().front();
      out << sub->help();
      return 0;
    }
    print_error(err, e.what());
    return 2;
  } catch (const shaderfit::Error& e) {
    print_error(err, error_text(e));
    return 2;
  } catch (const std::exception& e) {
    print_error(err, std::string("internal: ") + e.what());
    return 1;
  }
  return 0;
}

}  // namespace shaderfit::cli
