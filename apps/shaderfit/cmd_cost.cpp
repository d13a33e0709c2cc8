// shaderfit cost: the instruction count of a formula per target, and the listing the model
// assumed (docs/cost-model.md).
#include <fmt/format.h>

#include <fstream>
#include <memory>
#include <optional>
#include <ostream>

#include "cli.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/instruction_model.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/reference/program_formula.hpp"
#include "shaderfit/report/command_json.hpp"

namespace shaderfit::cli {

namespace {

struct CostArgs {
  std::string formula;
  std::string target = "sass";
  std::vector<std::string> inputs, params, uniform;
  std::string json_path;
  std::string reference_file, function;  // a shader function, costed as written
};

// The formula to cost: the positional one, or the shader function of --reference-file as its
// author wrote it (reference/program_formula.hpp), over its own parameters.
Expression formula_to_cost(const CostArgs& a) {
  if (a.reference_file.empty()) {
    if (!a.function.empty())
      throw Error("--function names a function of --reference-file, which is not given",
                  SourceLocation{"--function"});
    if (a.formula.empty())
      throw Error("give a formula, or --reference-file with --function", SourceLocation{"formula"});
    ParseOptions po;
    po.variables = a.inputs;
    po.parameters = a.params;
    return parse_formula(a.formula, po);
  }
  if (!a.formula.empty())
    throw Error("give a formula or --reference-file, not both", SourceLocation{"--reference-file"});
  if (a.function.empty())
    throw Error("name the function of the reference file to cost (--function NAME)",
                SourceLocation{"--function"});
  reference::ReferenceText t;
  t.shader_source = reference::read_shader_file(a.reference_file);
  t.shader_path = a.reference_file;
  t.function = a.function;
  t.variables = a.inputs;  // the parameters' order, and which of an overloaded name
  const reference::Program p = reference::compile_reference(t);
  const reference::ProgramFormula f =
      reference::program_formula(p, p.inputs, reference::kMaxCostedFormulaNodes);
  if (!f.formula)
    throw Error(a.function + " cannot be costed as written: " + f.why,
                SourceLocation{"--reference-file"});
  return *f.formula;
}

void run_cost(const CostArgs& a, Context& ctx) {
  const InstructionTarget target = parse_instruction_target(a.target, SourceLocation{"--target"});
  const Expression e = formula_to_cost(a);
  const CostTable table = cost_table(e, target, a.uniform, SourceLocation{"UniformInputs"});
  const std::vector<InstructionCost>& costs = table.costs;
  const MaterialCosts* m = table.material ? &*table.material : nullptr;
  const InstructionCost& shown = costs[table.shown];
  if (a.json_path == "-") {
    ctx.out << cost_json(e, table) << '\n';
    return;
  }
  PrintOptions print = PrintOptions::for_people();  // parameters by name, as the listing
  print.substitute_parameters = false;
  // A tree the search would not take (an unrolled Newton iteration) is too long to read.
  if (e.size() <= reference::kMaxProgramFormulaNodes) {
    ctx.out << "formula: " << to_infix(e, print) << '\n';
  } else {
    ctx.out << "formula: not shown: " << e.size()
            << " nodes written out (the listing computes each value once)\n";
  }
  ctx.out << "inputs: " << fmt::format("{}", fmt::join(e.variables, ", "));
  if (!e.parameters.empty())
    ctx.out << "; parameters: " << fmt::format("{}", fmt::join(e.parameters, ", "));
  if (m != nullptr) {
    ctx.out << "; uniform: " << fmt::format("{}", fmt::join(a.uniform, ", "));
    ctx.out << "\nper material:";
    for (const MaterialValue& v : m->split.values)
      ctx.out << (&v == &m->split.values.front() ? " " : "; ") << v.name << " = "
              << to_infix(v.value, print);
    ctx.out << "\nper pixel: " << to_infix(m->split.per_pixel, print);
  }
  ctx.out << fmt::format("\n\n{:<10} {:>12} {:>5} {:>7} {:>5} {:>9}", "target",
                         m ? "per pixel" : "instructions", "fp32", "minmax", "mufu", "weighted");
  ctx.out << (m ? fmt::format(" {:>12}\n", "per material") : "\n");
  for (std::size_t k = 0; k < costs.size(); ++k) {
    const InstructionCost& c = costs[k];
    ctx.out << fmt::format("{:<10} {:>12} {:>5} {:>7} {:>5} {:>9g}",
                           instruction_target_name(c.target), c.instructions, c.fp32, c.minmax,
                           c.mufu, c.weighted);
    ctx.out << (m ? fmt::format(" {:>12}\n", m->material[k].instructions) : "\n");
  }
  for (const auto& [none, why] : table.unavailable)
    ctx.out << fmt::format("{:<10} {:>12}  ({})\n", instruction_target_name(none), "-", why);
  if (m != nullptr) {
    ctx.out << "\n"
            << instruction_target_name(shown.target) << " listing, per material:\n"
            << format_listing(m->material[table.shown]);
  }
  ctx.out << "\n"
          << instruction_target_name(shown.target) << (m ? " listing, per pixel:\n" : " listing:\n")
          << format_listing(shown);
  if (!a.json_path.empty()) {
    std::ofstream f(a.json_path);
    if (!f) throw Error("cannot write '" + a.json_path + "'", SourceLocation{"--json"});
    f << cost_json(e, table) << '\n';
  }
}

}  // namespace

void register_cost_command(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<CostArgs>();
  CLI::App* cmd = app.add_subcommand(
      "cost", "GPU instruction count of a formula per target, with the instruction listing");
  cmd->add_option(
      "formula", args->formula,
      "the formula; every identifier is an input unless --inputs/--params say otherwise");
  cmd->add_option("--reference-file", args->reference_file,
                  "instead of a formula, a GLSL or HLSL file whose function (--function) is "
                  "costed as written: helpers inlined, constants folded, branches as selects "
                  "(--inputs: its parameters in order, which picks one of an overloaded name)");
  cmd->add_option("--function", args->function, "the function of --reference-file to cost");
  cmd->add_option("--target", args->target,
                  "listing to print: sass (default), ptx, generic, sass-half2 (the __half2 "
                  "code of codegen --precision half, per call of two values), rdna2 or rdna3 "
                  "(AMD gfx1030, gfx1100)");
  add_name_options(cmd, args->inputs, args->params);
  add_uniform_option(cmd, args->uniform);
  cmd->add_option("--json", args->json_path,
                  "write the counts and listing as JSON to PATH ('-' for stdout)");
  cmd->footer(
      "Examples:\n  shaderfit cost 'r0 + (1 - r0) * (1 - cos_theta)^5'\n"
      "  shaderfit cost --uniform alpha '1/(3.14159*alpha^2) * pow(NoH, 2/alpha^2 - 2)'\n"
      "  shaderfit cost --reference-file burley.hlsl --function Fd_Burley");
  cmd->callback([args, &ctx] { run_cost(*args, ctx); });
}

}  // namespace shaderfit::cli
