#include "shaderfit/cli.hpp"

#include <unistd.h>

#include <iostream>

#include "field_flags.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/search/options.hpp"

namespace shaderfit::cli {

namespace {

// Library locations and the flags that set them, for errors that reach run_cli with the
// library's location (fit and rational translate theirs with with_flags, field_flags.hpp).
// Search options not listed take --<field name> (search_option_flag).
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
    // Other commands.
    {"ComputeDevice", "--device"},
    {"CodegenOptions::name", "--name"},
    {"Expression::variables", "--inputs"},
    {"Expression::parameters", "--params"},
    {"SphereScene::roughness", "--roughness"},
    {"SphereScene::f0", "--f0"},
    {"SphereScene::light", "--light"},
    {"SphereScene::size", "--size"},
    {"Material", "--material"},
    {"fresnel_sweep::materials", "--material"},
    {"fresnel_sweep::angles", "--angles"},
    {"compare_with_exact", "--compare-exact"},
    {"RationalProblem::conditions", "--cond"},
    {"RationalForm", "--form"},
    {"Transform", "--transform"},
    {"SearchReportOptions::choose", "--choose"},
};

constexpr std::string_view kSearchOptions = "SearchOptions::";

// e.what() with the library's location replaced by its flag.
std::string error_text(const shaderfit::Error& e) {
  const std::string flag = flag_for_location(e.where().source);
  if (flag.empty()) return e.what();
  SourceLocation where = e.where();
  where.source = flag;
  return where.to_string() + ": " + e.message();
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

std::string flag_for_location(std::string_view location) {
  for (const FieldFlag& f : kFlags)
    if (f.field == location) return std::string(f.flag);
  if (location.starts_with(kSearchOptions) &&
      find_search_option(location.substr(kSearchOptions.size())) != nullptr)
    return search_option_flag(location.substr(kSearchOptions.size()));
  return {};
}

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  CLI::App app{"shaderfit: cheap formulas for expensive shading functions", "shaderfit"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "shaderfit 0.1.0");
  Context ctx{out, err, isatty(STDERR_FILENO) != 0};

  register_eval_command(app, ctx);
  register_search_command(app, ctx);
  register_cost_command(app, ctx);
  register_codegen_command(app, ctx);
  register_plot_command(app, ctx);
  register_report_command(app, ctx);
  register_fit_command(app, ctx);
  register_lut_command(app, ctx);
  register_rational_command(app, ctx);

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
