#include "shaderfit/rational/target.hpp"

#include <algorithm>
#include <array>
#include <string>

#include "rational/quadrature.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/jet.hpp"
#include "shaderfit/reference/builtin_evaluate.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/reference/program_evaluate.hpp"

namespace shaderfit::rational {

namespace {

using reference::BuiltinFunction;

bool is_target(const BuiltinFunction& f) { return f.listed_in(reference::RationalTarget); }

// The built-in at x, its parameters (the arguments after the variable) held as constants of T.
template <typename T>
T eval_builtin(const BuiltinFunction& f, const T& x, std::span<const double> p) {
  std::array<T, 4> args{};
  args[0] = x;
  for (std::size_t i = 0; i + 1 < f.arguments.size(); ++i) args[i + 1] = T(p[i]);
  return reference::evaluate_builtin<T>(f.id, std::span<const T>(args.data(), f.arguments.size()));
}

}  // namespace

Target Target::builtin(std::string_view name, const std::string& source) {
  if (const BuiltinFunction* f = reference::find_builtin(name, reference::RationalTarget)) {
    const auto symbols = f->symbol_names();
    Target t;
    t.name_ = f->name;
    t.variable_ = symbols.front();
    t.parameters_.assign(symbols.begin() + 1, symbols.end());
    t.natural_domain_ = {f->domain.lo, f->domain.hi};
    t.builtin_ = f;
    return t;
  }
  std::string known;
  for (const BuiltinFunction& f : reference::builtin_functions())
    if (is_target(f)) known += (known.empty() ? "" : ", ") + std::string(f.name);
  throw Error("unknown target '" + std::string(name) + "' (built-ins: " + known +
                  "; or a formula in the variable)",
              {source});
}

bool Target::is_builtin(std::string_view name) {
  return reference::find_builtin(name, reference::RationalTarget) != nullptr;
}

std::vector<std::string> Target::builtin_target_names() {
  std::vector<std::string> out;
  for (const BuiltinFunction& f : reference::builtin_functions()) {
    if (!is_target(f)) continue;
    const auto symbols = f.symbol_names();
    std::string params;
    for (std::size_t i = 1; i < symbols.size(); ++i)
      params += (params.empty() ? "" : ", ") + std::string(symbols[i]);
    out.push_back(std::string(f.name) + "(" + std::string(symbols.front()) +
                  (params.empty() ? "" : "; " + params) + "): " + std::string(f.description));
  }
  return out;
}

Target Target::from_program(reference::Program program, std::size_t variable) {
  Target t;
  t.name_ = program.description;
  t.variable_ = program.inputs[variable];
  for (std::size_t i = 0; i < program.inputs.size(); ++i)
    if (i != variable) t.parameters_.push_back(program.inputs[i]);
  t.program_ = std::move(program);
  t.variable_input_ = variable;
  return t;
}

Target Target::formula(std::string_view text, const std::string& variable,
                       const std::vector<std::string>& parameters, const std::string& source) {
  reference::ReferenceText r;
  r.formula = std::string(text);
  r.variables = {variable};
  r.variables.insert(r.variables.end(), parameters.begin(), parameters.end());
  r.formula_source = source;
  return from_program(reference::compile_reference(r), 0);
}

Target Target::shader(const std::string& text, const std::string& path, const std::string& function,
                      const std::string& variable, const std::vector<std::string>& given,
                      const std::string& source) {
  reference::ReferenceText r;
  r.shader_source = text;
  r.shader_path = path;
  r.function = function;
  reference::Program p = reference::compile_reference(r);
  const std::vector<std::string>& inputs = p.inputs;
  if (inputs.empty()) throw Error(p.description + " has no parameter to be the variable", {source});
  if (const int v = p.find_input(variable); v >= 0)
    return from_program(std::move(p), static_cast<std::size_t>(v));
  std::vector<std::size_t> open;  // the parameters without a value
  std::string names;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    names += (names.empty() ? "" : ", ") + inputs[i];
    if (std::find(given.begin(), given.end(), inputs[i]) == given.end()) open.push_back(i);
  }
  if (open.size() != 1)
    throw Error(p.description + " has the parameters " + names + ": name the variable (" +
                    std::to_string(open.size()) +
                    " have no value; the others are parameters with values)",
                {source});
  return from_program(std::move(p), open.front());
}

template <typename T>
T Target::evaluate(const T& x, std::span<const double> params) const {
  if (params.size() < parameters_.size())
    throw Error(name_ + " takes " + std::to_string(parameters_.size()) + " parameter values, got " +
                std::to_string(params.size()));
  if (builtin_) return eval_builtin(*builtin_, x, params);
  std::vector<T> inputs;
  inputs.reserve(program_.inputs.size());
  std::size_t next = 0;
  for (std::size_t i = 0; i < program_.inputs.size(); ++i)
    inputs.push_back(i == variable_input_ ? x : T(params[next++]));
  std::vector<T> registers;
  reference::evaluate_program<T>(program_, inputs, registers);
  return registers[program_.outputs.back()];
}

double Target::value(double x, std::span<const double> params) const { return evaluate(x, params); }

std::vector<double> Target::derivatives(double x, int order, std::span<const double> params) const {
  if (order < 0 || order > kMaxDerivativeOrder)
    throw Error("derivative order " + std::to_string(order) + " outside [0, " +
                std::to_string(kMaxDerivativeOrder) + "]");
  const Jet r = evaluate(Jet::variable(x, order), params);
  std::vector<double> out(static_cast<std::size_t>(order) + 1);
  for (int k = 0; k <= order; ++k) out[static_cast<std::size_t>(k)] = r.derivative(k);
  return out;
}

double Target::integral(double a, double b, std::span<const double> params) const {
  return rational_detail::integrate([&](double x) { return value(x, params); }, a, b);
}

}  // namespace shaderfit::rational
