// Fuzz target: a formula as users type it (shaderfit eval/cost/codegen/fit arguments, --baseline).
// The parse must succeed or throw shaderfit::Error; a parsed formula must print and read back node
// for node (print.hpp's contract), and cost, code generation, simplification and evaluation must
// accept it without a crash.
#include <array>
#include <cstring>
#include <vector>

#include "fuzz_targets.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/eval/evaluate.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/expr/simplify.hpp"

namespace shaderfit::fuzz {

namespace {

void check_reads_back(const Expression& e) {
  ParseOptions again;
  again.variables = e.variables;
  again.parameters = e.parameters;
  again.parameter_values = e.parameter_values;
  const std::string printed = to_infix(e);
  Expression back;
  try {
    back = parse_formula(printed, again);
  } catch (const Error& err) {
    throw FuzzFailure("printed formula '" + printed + "' does not read back: " + err.what());
  }
  // A sum's doubled sign is folded (a - -c prints a + c), so `back` may differ from e in that
  // node alone; printed again it reads back node for node.
  const std::string reprinted = to_infix(back);
  if (reprinted != printed)
    throw FuzzFailure("printed formula '" + printed + "' reprints as '" + reprinted + "'");
  if (!(parse_formula(reprinted, again) == back))
    throw FuzzFailure("printed formula '" + printed + "' reads back differently");
}

// A few rows of every variable, in float and double, one thread (the fuzzer owns the process).
void evaluate_rows(const Expression& e) {
  constexpr std::size_t kRows = 5;
  constexpr std::array<double, kRows> kValues = {0.0, 0.5, -1.25, 3.0, 1e-3};
  std::vector<double> column_d(kValues.begin(), kValues.end());
  std::vector<float> column_f(kValues.begin(), kValues.end());
  std::vector<const double*> cols_d(e.variables.size(), column_d.data());
  std::vector<const float*> cols_f(e.variables.size(), column_f.data());
  std::array<double, kRows> out_d{};
  std::array<float, kRows> out_f{};
  evaluate(e, cols_d, out_d, {.threads = 1});
  evaluate(e, cols_f, out_f, {.threads = 1});
  const std::vector<double> point(e.variables.size(), 0.5);
  (void)evaluate_scalar(e, point);
}

}  // namespace

void formula(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = as_text(data, size);
  // Every identifier becomes a variable, except `s` and `k`, which are parameters (as `fit`
  // declares them), so Param nodes are exercised too.
  ParseOptions options;
  options.parameters = {"s", "k"};
  options.parameter_values = {0.25, 2.0};
  // For a quarter of the inputs, number literals become parameters too (search --start).
  options.literals_as_parameters = size % 4 == 1;
  Expression e;
  try {
    e = parse_formula(text, options);
  } catch (const Error&) {
    return;  // the expected outcome for bad input
  }
  check_reads_back(e);
  (void)to_latex(e);
  (void)to_infix(e, {.substitute_parameters = true});
  // One cost target and one language per input (chosen by its size), to keep executions fast;
  // the fuzzer's many inputs cover them all.
  (void)format_listing(instruction_cost(e, static_cast<InstructionTarget>(size % 3)));
  CodegenOptions co;
  co.language = static_cast<Language>(size % 5);
  co.bake_parameters = size % 2 == 0;
  try {
    (void)generate_function(e, co);
  } catch (const Error&) {
    // A name the language reserves (a variable called `float`) is a documented error.
  }
  evaluate_rows(e);
  const Expression simple = simplify(e);
  check_reads_back(simple);
  evaluate_rows(simple);
}

}  // namespace shaderfit::fuzz

SHADERFIT_FUZZ_ENTRY(formula)
