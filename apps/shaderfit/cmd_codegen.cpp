// shaderfit codegen: a formula, or every member of a search front, as a function in GLSL, HLSL,
// CUDA, C++ or Metal, printed as a file that compiles on its own (docs/codegen.md).
#include <fmt/format.h>

#include <memory>
#include <ostream>
#include <vector>

#include "cli.hpp"
#include "shaderfit/codegen/codegen.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/cost/per_material.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"
#include "shaderfit/search/front_member.hpp"

namespace shaderfit::cli {

namespace {

struct CodegenArgs {
  std::string lang;
  std::string precision = "float";
  std::string name = "shaderfit_formula";
  std::string formula, front_path;
  std::vector<std::string> inputs, params, uniform;
};

// The comment above the function: the formula for people (parameters by name, as the code
// names them) and its cost (per pixel and per material with uniform inputs).
std::vector<std::string> describe(const Expression& e, const std::vector<std::string>& uniform,
                                  Precision precision) {
  PrintOptions print = PrintOptions::for_people();
  print.substitute_parameters = false;
  return {to_infix(e, print), cost_comment(e, uniform, precision)};
}

void run_codegen(const CodegenArgs& a, Context& ctx) {
  const auto lang = language_from_name(a.lang);
  if (!lang)
    throw Error("unknown language '" + a.lang + "' (known: glsl, hlsl, cuda, cpp, metal)",
                SourceLocation{"--lang"});
  const Precision precision = precision_option(a.precision);
  if (a.formula.empty() == a.front_path.empty()) {
    throw Error("give either a formula or --front FILE.json", SourceLocation{"codegen"});
  }
  // One file that compiles on its own (generate_source): the includes or #version line, then
  // the functions.
  std::vector<SourceFunction> functions;
  if (!a.formula.empty()) {
    ParseOptions po;
    po.variables = a.inputs;
    po.parameters = a.params;
    SourceFunction f{parse_formula(a.formula, po), {}};
    check_uniform_inputs(a.uniform, f.expression.variables);
    f.options.name = a.name;
    f.options.uniform = a.uniform;
    f.options.precision = precision;
    f.options.comment = describe(f.expression, a.uniform, precision);
    functions.push_back(std::move(f));
  } else {
    const FrontFile file = read_front_file(a.front_path, {a.inputs, a.params});
    // The file's per-material inputs (a search's), unless --uniform names others.
    const std::vector<std::string>& uniform = a.uniform.empty() ? file.uniform : a.uniform;
    if (!file.inputs.empty()) check_uniform_inputs(uniform, file.inputs);
    for (std::size_t i = 0; i < file.front.size(); ++i) {
      SourceFunction f{file.front[i].member.expression, {}};
      f.options.name = fmt::format("{}_{}", a.name, i);
      f.options.bake_parameters = file.front[i].parameters_have_values;
      f.options.uniform = uniform;
      f.options.precision = precision;
      f.options.comment = describe(f.expression, uniform, precision);
      functions.push_back(std::move(f));
    }
  }
  ctx.out << generate_source(functions, *lang);
}

}  // namespace

void register_codegen_command(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<CodegenArgs>();
  CLI::App* cmd = app.add_subcommand(
      "codegen",
      "Print a formula (or a search front) as a GLSL, HLSL, CUDA, C++ or Metal function, in a "
      "file that compiles as printed");
  cmd->add_option("--lang", args->lang, "glsl, hlsl, cuda, cpp or metal")->required();
  cmd->add_option(
      "--precision", args->precision,
      "float (default) or half: the arithmetic of the printed code (half: GLSL "
      "float16_t, HLSL and Metal half, CUDA __half and a __half2 twin NAME_x2; no C++)");
  cmd->add_option("--name", args->name,
                  "function name (a front's members get NAME_0, NAME_1, ...)");
  add_name_options(cmd, args->inputs, args->params);
  add_uniform_option(cmd, args->uniform);
  cmd->add_option("--front", args->front_path,
                  "a JSON file with a \"front\" list of {\"formula\": ...} members");
  cmd->add_option(
      "formula", args->formula,
      "the formula; every identifier is an input unless --inputs/--params say otherwise");
  cmd->footer(
      "Example:\n  shaderfit codegen --lang glsl --name fresnel 'r0 + (1 - cos_theta - r0) * (1 - "
      "cos_theta)^4'");
  cmd->callback([args, &ctx] { run_codegen(*args, ctx); });
}

}  // namespace shaderfit::cli
