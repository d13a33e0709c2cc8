#include "shaderfit/rational/target.hpp"

#include <array>
#include <string>

#include "rational/quadrature.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/forward.hpp"
#include "shaderfit/expr/jet.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/reference/builtin_evaluate.hpp"

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

Target Target::formula(std::string_view text, const std::string& variable,
                       const std::vector<std::string>& parameters, const std::string& source) {
  ParseOptions opts;
  opts.variables = {variable};
  opts.parameters = parameters;
  opts.source = source;
  Target t;
  t.formula_ = parse_formula(text, opts);
  t.name_ = std::string(text);
  t.variable_ = variable;
  t.parameters_ = parameters;
  return t;
}

double Target::value(double x, std::span<const double> params) const {
  if (builtin_) return eval_builtin(*builtin_, x, params);
  return evaluate_at(formula_, Jet(x), params).value();
}

std::vector<double> Target::derivatives(double x, int order, std::span<const double> params) const {
  if (order < 0 || order > kMaxDerivativeOrder)
    throw Error("derivative order " + std::to_string(order) + " outside [0, " +
                std::to_string(kMaxDerivativeOrder) + "]");
  const Jet v = Jet::variable(x, order);
  const Jet r = builtin_ ? eval_builtin(*builtin_, v, params) : evaluate_at(formula_, v, params);
  std::vector<double> out(static_cast<std::size_t>(order) + 1);
  for (int k = 0; k <= order; ++k) out[static_cast<std::size_t>(k)] = r.derivative(k);
  return out;
}

double Target::integral(double a, double b, std::span<const double> params) const {
  return detail::integrate([&](double x) { return value(x, params); }, a, b);
}

}  // namespace shaderfit::rational
