// The reference language's entry points: compile_reference (formulas and definitions here, shader
// functions in language_shader.cpp), evaluate_constant and reference_function_names.
#include "shaderfit/reference/language.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "language_internal.hpp"

namespace shaderfit::reference {

namespace {

using reference_detail::Dialect;
using reference_detail::ExpressionParser;
using reference_detail::ProgramBuilder;
using reference_detail::Reg;
using reference_detail::Value;

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0) s.remove_suffix(1);
  return s;
}

bool is_identifier(std::string_view s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) != 0 || s[0] == '_'))
    return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
  });
}

bool is_function_name(std::string_view s) {
  return !reference_detail::find_library_function(s, reference_detail::kFormulaLibrary).empty() ||
         reference_detail::find_builtin_by_call_name(s) != nullptr;
}

// The names a formula may use besides functions: the variables (given, or found in order of
// use) and the definitions so far.
struct Scope {
  std::vector<std::string> variables;
  std::vector<Reg> variable_registers;  // the Input instruction of each
  bool fixed = false;                   // variables given: any other name is an error
  bool constants_only = false;          // evaluate_constant: no variables at all
  std::vector<std::pair<std::string, Reg>> definitions;
  Program* program = nullptr;  // its inputs grow with the variables found
};

class FormulaParser : public ExpressionParser {
 public:
  FormulaParser(std::span<const Token> tokens, ProgramBuilder& b, const std::string& source,
                int& nesting, Scope& scope)
      : ExpressionParser(tokens, 0, b, Dialect::Formula, source, nesting), scope_(scope) {}

  // The whole token range as one expression.
  Value run(const char* what) {
    if (peek().kind == Token::End) fail(std::string("empty ") + what, peek());
    const Value v = expression();
    if (peek().kind != Token::End) {
      const std::string found(peek().text);
      if (peek().is("="))
        fail("unexpected '=' (a definition is 'name = formula'; '==' compares)", peek());
      if (peek().is(":")) fail("unexpected ':' without a '?' before it", peek());
      fail("unexpected '" + found + "'", peek());
    }
    return v;
  }

 protected:
  Value name(const Token& t) override {
    const std::string s(t.text);
    const auto& vars = scope_.variables;
    if (const auto it = std::find(vars.begin(), vars.end(), s); it != vars.end())
      return {scope_.variable_registers[static_cast<std::size_t>(it - vars.begin())]};
    for (const auto& [name, reg] : scope_.definitions)
      if (name == s) return {reg};
    if (s == "pi") return {builder().constant(std::numbers::pi)};
    if (is_function_name(s)) fail("function '" + s + "' needs arguments in parentheses", t);
    if (scope_.constants_only)
      fail("a constant cannot name a variable ('" + s + "'); pi is the one named constant", t);
    if (scope_.fixed) {
      std::vector<std::string> known = vars;
      for (const auto& d : scope_.definitions) known.push_back(d.first);
      known.emplace_back("pi");
      fail("unknown variable '" + s + "' (known: " + reference_detail::join_names(known) + ")", t);
    }
    if (s == kReferenceOutput)
      fail("'" + s + "' names the reference's own output: give the variable another name", t);
    if (vars.size() >= 32767) fail("too many variables", t);
    scope_.variables.push_back(s);
    scope_.program->inputs.push_back(s);
    scope_.variable_registers.push_back(
        builder().input(static_cast<int>(scope_.program->inputs.size() - 1)));
    return {scope_.variable_registers.back()};
  }

 private:
  Scope& scope_;
};

// "name = formula" at position `line` of the definitions.
void add_definition(const std::string& text, int line, const ReferenceText& ref, ProgramBuilder& b,
                    Scope& scope) {
  const std::string& source = ref.definitions_source;
  const std::vector<Token> tokens =
      reference_detail::tokenize(text, Dialect::Formula, source, line, 1);
  if (tokens.size() < 3 || tokens[0].kind != Token::Ident || !tokens[1].is("=")) {
    reference_detail::fail_at("expected 'name = formula', got '" + std::string(trim(text)) + "'",
                              source, tokens[0]);
  }
  int nesting = 0;
  FormulaParser parser(std::span<const Token>(tokens).subspan(2), b, source, nesting, scope);
  const Value v = parser.run("definition");
  const Token& name = tokens[0];
  const std::string s(name.text);
  auto taken = [&](const std::string& why) {
    reference_detail::fail_at("definition '" + s + "' redefines " + why, source, name);
  };
  if (std::find(scope.variables.begin(), scope.variables.end(), s) != scope.variables.end())
    taken("the variable " + s);
  for (std::size_t i = 0; i < scope.definitions.size(); ++i)
    if (scope.definitions[i].first == s) taken("definition " + std::to_string(i + 1));
  if (s == "pi") taken("the constant pi");
  if (is_function_name(s)) taken("the function " + s);
  if (s == kReferenceOutput) taken("the reference's own output");
  scope.definitions.emplace_back(s, v.reg);
}

// The formula itself, or the call of the built-in reference whose name it is.
std::string formula_text(std::string_view formula) {
  const std::string_view t = trim(formula);
  for (const BuiltinFunction& f : builtin_functions()) {
    if (t != f.name && t != reference_detail::builtin_call_name(f)) continue;
    std::string call = reference_detail::builtin_call_name(f) + "(";
    for (std::size_t i = 0; i < f.arguments.size(); ++i)
      call += (i == 0 ? "" : ", ") + std::string(f.arguments[i]);
    return call + ")";
  }
  return std::string(formula);
}

void check_variables(const ReferenceText& text) {
  const SourceLocation where{text.shader_source.empty() ? text.formula_source : text.shader_path};
  for (std::size_t i = 0; i < text.variables.size(); ++i) {
    const std::string& v = text.variables[i];
    if (!is_identifier(v)) throw Error("variable '" + v + "' is not an identifier", where);
    if (v == kReferenceOutput)
      throw Error("'" + v + "' names the reference's own output: give the variable another name",
                  where);
    for (std::size_t j = 0; j < i; ++j)
      if (text.variables[j] == v) throw Error("variable '" + v + "' is named twice", where);
  }
}

}  // namespace

Program compile_reference(const ReferenceText& text) {
  const bool shader = !text.shader_source.empty() || !text.function.empty();
  if (shader && !text.formula.empty()) {
    throw Error("give either a formula or a shader function as the reference, not both",
                SourceLocation{text.formula_source});
  }
  check_variables(text);
  Program program;
  const std::string path = text.shader_path.empty() ? "shader" : text.shader_path;
  ProgramBuilder b(program, shader ? path : text.formula_source);
  Scope scope;
  scope.program = &program;
  Reg reference = 0;
  if (shader) {
    const reference_detail::ShaderFunction f =
        reference_detail::compile_shader_function(text, b, program);
    scope.variables = program.inputs;
    scope.variable_registers = f.inputs;
    scope.fixed = true;
    reference = f.result;
    program.description = path + ": " + f.name;
  } else {
    scope.fixed = !text.variables.empty();
    for (const std::string& v : text.variables) {
      program.inputs.push_back(v);
      scope.variables.push_back(v);
      scope.variable_registers.push_back(b.input(static_cast<int>(program.inputs.size() - 1)));
    }
  }
  for (std::size_t i = 0; i < text.definitions.size(); ++i)
    add_definition(text.definitions[i], static_cast<int>(i + 1), text, b, scope);
  if (!shader) {
    const std::string formula = formula_text(text.formula);
    const std::vector<Token> tokens =
        reference_detail::tokenize(formula, Dialect::Formula, text.formula_source);
    int nesting = 0;
    FormulaParser parser(tokens, b, text.formula_source, nesting, scope);
    reference = parser.run("formula").reg;
    program.description = std::string(trim(text.formula));
  }
  for (std::size_t i = 0; i < scope.variables.size(); ++i) {
    program.output_names.push_back(scope.variables[i]);
    program.outputs.push_back(scope.variable_registers[i]);
  }
  for (const auto& [name, reg] : scope.definitions) {
    program.output_names.push_back(name);
    program.outputs.push_back(reg);
  }
  program.output_names.emplace_back(kReferenceOutput);
  program.outputs.push_back(reference);
  reference_detail::remove_dead_code(program);
  return program;
}

double evaluate_constant(std::string_view text, const std::string& source) {
  Program program;
  ProgramBuilder b(program, source);
  Scope scope;
  scope.constants_only = true;
  scope.program = &program;
  const std::vector<Token> tokens = reference_detail::tokenize(text, Dialect::Formula, source);
  int nesting = 0;
  FormulaParser parser(tokens, b, source, nesting, scope);
  program.outputs.push_back(parser.run("constant").reg);
  const double v = program.evaluate({});
  if (!std::isfinite(v)) {
    const char* value = std::isnan(v) ? "NaN" : (v > 0 ? "inf" : "-inf");
    throw Error("'" + std::string(trim(text)) + "' is not a finite number (" + value + ")",
                SourceLocation{source});
  }
  return v;
}

std::vector<std::string> reference_function_names() {
  return reference_detail::library_function_names(reference_detail::kFormulaLibrary);
}

std::string read_shader_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path + "'", SourceLocation{path});
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error("cannot read '" + path + "'", SourceLocation{path});
  return text.str();
}

}  // namespace shaderfit::reference
