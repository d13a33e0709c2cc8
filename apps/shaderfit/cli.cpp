#include "shaderfit/cli.hpp"

#include <unistd.h>

#include <iostream>

#include "shaderfit/core/error.hpp"

namespace shaderfit::cli {

namespace {

void print_error(std::ostream& err, const std::string& text) {
  // One line, whatever the message holds.
  std::string line = text;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  err << "shaderfit: error: " << line << '\n';
}

}  // namespace

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
    print_error(err, e.what());
    return 2;
  } catch (const std::exception& e) {
    print_error(err, std::string("internal: ") + e.what());
    return 1;
  }
  return 0;
}

}  // namespace shaderfit::cli
