// The shaderfit command-line tool as a library: tests call run_cli in-process.
//
// Each command lives in its own file (cmd_<name>.cpp) and registers itself through a
// register_<name>_command function listed in cli.cpp. A command's callback reads its options,
// calls the library, and writes to ctx.out / ctx.err. Bad input surfaces as shaderfit::Error
// (thrown from the library or the command), which run_cli prints as one line on ctx.err:
//   shaderfit: error: <location>: <message>
// and turns into exit status 2. The library locates errors at its own names (a field such as
// SearchOptions::operators, a concept such as Material); flag_for_location maps them to the
// flags a user typed (--ops, --material), in one table in cli.cpp.
#pragma once

#include <CLI/CLI.hpp>
#include <atomic>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/expr/precision.hpp"
#include "shaderfit/search/communicator.hpp"

namespace shaderfit::cli {

struct Context {
  std::ostream& out;
  std::ostream& err;
  // Progress bars on err (progress_bar.hpp): true only when err is stderr and a terminal.
  bool progress = true;
  // shaderfit-mpi's ranks (apps/shaderfit-mpi/): `search` runs across them, and only rank 0
  // reports and writes files. Null in shaderfit itself.
  Communicator* communicator = nullptr;
};

void register_eval_command(CLI::App& app, Context& ctx);
void register_search_command(CLI::App& app, Context& ctx);
void register_cost_command(CLI::App& app, Context& ctx);
void register_codegen_command(CLI::App& app, Context& ctx);
void register_plot_command(CLI::App& app, Context& ctx);
void register_report_command(CLI::App& app, Context& ctx);
void register_fit_command(CLI::App& app, Context& ctx);
void register_lut_command(CLI::App& app, Context& ctx);
void register_rational_command(CLI::App& app, Context& ctx);
void register_batch_command(CLI::App& app, Context& ctx);

// The command-line flag for a library location ("SearchOptions::max_nodes" -> "--max-nodes",
// "SearchOptions::operators" -> "--ops"), or "" when the location is not one the CLI sets by
// a flag (a file, "formula", "data").
std::string flag_for_location(std::string_view location);
// The flag of a described search option (options.hpp): --<name with '-' for '_'>, unless the
// table renames it (historical flags such as --time, --evals, --ops).
std::string search_option_flag(std::string_view field_name);
// The flag and the other names it answers to, as CLI11 takes them: "--cost,--cost-target".
std::string flag_with_aliases(const std::string& flag);

// --inputs and --params: the names of a formula's inputs, in argument order, and of its free
// parameters (comma-separated or repeated), for the commands that read a formula without data.
void add_name_options(CLI::App* cmd, std::vector<std::string>& inputs,
                      std::vector<std::string>& params);

// --uniform: the per-material inputs (cost/per_material.hpp), for cost, codegen, eval and report
// (search takes it from its option table).
void add_uniform_option(CLI::App* cmd, std::vector<std::string>& uniform);

// --choose for search and report: "knee" (the default), "cost=N" or "error=E" (the rule in
// shaderfit/search/front/choice.hpp); the help text, and the closing lines that name the chosen
// formula, how it was chosen (with the flag that changes it) and why.
extern const char* const kChooseHelp;
std::string chosen_formula_lines(const std::string& formula, const std::string& how,
                                 const std::string& why, bool by_rule = true);
// --digits: how many significant digits the formulas for people show (PrintOptions::for_people;
// 0, the default: as many as float32 needs).
void add_digits_option(CLI::App* cmd, int& digits);

// --precision double|float|half (expr/precision.hpp): the text, read by precision_option, which
// throws Error at "--precision" for an unknown name. `what` says what is computed in it ("the
// formulas are computed in"), `default_note` the default ("double").
void add_precision_option(CLI::App* cmd, std::string& precision, const std::string& what,
                          const std::string& default_note);
Precision precision_option(const std::string& text);

// Ctrl-C and SIGTERM, while one exists, set flag() instead of ending the process, so that a
// long command stops its work and still writes what it has (search: the front so far; batch:
// the finished entries). The handlers before it are restored when it goes.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  [[nodiscard]] const std::atomic<bool>* flag() const;
  [[nodiscard]] bool stopped() const { return flag()->load(); }

 private:
  void (*previous_int_)(int);
  void (*previous_term_)(int);
};

// Exit status: 0 success, 1 internal failure, 2 bad input (usage or data). `communicator`:
// Context::communicator.
int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err,
            Communicator* communicator = nullptr);

}  // namespace shaderfit::cli
