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
#include "shaderfit/report/command_json.hpp"

namespace shaderfit::cli {

namespace {

struct CostArgs {
  std::string formula;
  std::string target = "sass";
  std::vector<std::string> inputs, params, uniform;
  std::string json_path;
};

void run_cost(const CostArgs& a, Context& ctx) {
  const InstructionTarget target = parse_instruction_target(a.target, SourceLocation{"--target"});
  ParseOptions po;
  po.variables = a.inputs;
  po.parameters = a.params;
  const Expression e = parse_formula(a.formula, po);
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
  ctx.out << "formula: " << to_infix(e, print) << '\n';
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
         "the formula; every identifier is an input unless --inputs/--params say otherwise")
      ->required();
  cmd->add_option("--target", args->target,
                  "listing to print: sass (default), ptx, generic or sass-half2 (the __half2 "
                  "code of codegen --precision half, per call of two values)");
  add_name_options(cmd, args->inputs, args->params);
  add_uniform_option(cmd, args->uniform);
  cmd->add_option("--json", args->json_path,
                  "write the counts and listing as JSON to PATH ('-' for stdout)");
  cmd->footer(
      "Examples:\n  shaderfit cost 'r0 + (1 - r0) * (1 - cos_theta)^5'\n"
      "  shaderfit cost --uniform alpha '1/(3.14159*alpha^2) * pow(NoH, 2/alpha^2 - 2)'");
  cmd->callback([args, &ctx] { run_cost(*args, ctx); });
}

}  // namespace shaderfit::cli
