#include "shaderfit/rational/target.hpp"

#include <cmath>
#include <string>

#include "rational/jet.hpp"
#include "rational/jet_eval.hpp"
#include "rational/quadrature.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace shaderfit::rational {

namespace {

enum class Builtin {
  FresnelSchlick,
  FresnelDielectric,
  FresnelDielectricF0,
  FresnelConductor,
  SmithGgxG1,
  GgxDistribution,
  Exp,
  Exp2,
  Log,
  Log2,
  Atan,
  Sin,
  Cos,
  Sqrt,
  Rsqrt,
  Rcp,
};

struct BuiltinInfo {
  Builtin kind;
  const char* name;
  const char* variable;
  std::vector<std::string> parameters;
  Interval domain;
  const char* description;
};

const std::vector<BuiltinInfo>& builtins() {
  static const std::vector<BuiltinInfo> table = {
      {Builtin::FresnelSchlick,
       "fresnel-schlick",
       "cos",
       {"F0"},
       {0, 1},
       "F0 + (1 - F0)(1 - cos)^5"},
      {Builtin::FresnelDielectric,
       "fresnel-dielectric",
       "cos",
       {"ior"},
       {0, 1},
       "exact unpolarized dielectric reflectance, relative index ior"},
      {Builtin::FresnelDielectricF0,
       "fresnel-dielectric-f0",
       "cos",
       {"F0"},
       {0, 1},
       "exact dielectric reflectance for the index with normal reflectance F0"},
      {Builtin::FresnelConductor,
       "fresnel-conductor",
       "cos",
       {"eta", "kappa"},
       {0, 1},
       "exact conductor reflectance, complex index eta + i kappa"},
      {Builtin::SmithGgxG1,
       "smith-ggx-g1",
       "v",
       {"alpha"},
       {0, 1},
       "Smith GGX masking 2v / (v + sqrt(alpha^2 + (1 - alpha^2) v^2))"},
      {Builtin::GgxDistribution,
       "ggx-d",
       "cos",
       {"alpha"},
       {0, 1},
       "GGX distribution alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2)"},
      {Builtin::Exp, "exp", "x", {}, {-1, 1}, "e^x"},
      {Builtin::Exp2, "exp2", "x", {}, {0, 1}, "2^x"},
      {Builtin::Log, "log", "x", {}, {1, 2}, "natural logarithm"},
      {Builtin::Log2, "log2", "x", {}, {1, 2}, "base-2 logarithm"},
      {Builtin::Atan, "atan", "x", {}, {-1, 1}, "arc tangent"},
      {Builtin::Sin, "sin", "x", {}, {0, 1.5707963267948966}, "sine"},
      {Builtin::Cos, "cos", "x", {}, {0, 1.5707963267948966}, "cosine"},
      {Builtin::Sqrt, "sqrt", "x", {}, {0.25, 1}, "square root"},
      {Builtin::Rsqrt, "rsqrt", "x", {}, {0.25, 1}, "reciprocal square root"},
      {Builtin::Rcp, "rcp", "x", {}, {1, 2}, "reciprocal"},
  };
  return table;
}

// The built-in functions for T = double or Jet. The reference templates are used as they are,
// except Smith G1, written without the guard that returns 0 for v <= 0, so that its derivatives
// at v = 0 are those of the analytic expression (the guard would make them all zero).
template <typename T>
T eval_builtin(Builtin kind, const T& x, std::span<const double> p) {
  using std::atan, std::cos, std::exp, std::exp2, std::log, std::log2, std::sin, std::sqrt;
  switch (kind) {
    case Builtin::FresnelSchlick: return reference::fresnel_schlick(T(p[0]), x);
    case Builtin::FresnelDielectric: return reference::fresnel_dielectric(x, T(p[0]));
    case Builtin::FresnelDielectricF0: {
      const double s = std::sqrt(p[0]);
      return reference::fresnel_dielectric(x, T((1.0 + s) / (1.0 - s)));
    }
    case Builtin::FresnelConductor: return reference::fresnel_conductor(x, T(p[0]), T(p[1]));
    case Builtin::SmithGgxG1: {
      const T a2 = T(p[0] * p[0]);
      return T(2.0) * x / (x + sqrt(a2 + (T(1.0) - a2) * x * x));
    }
    case Builtin::GgxDistribution: return reference::ggx_distribution(x, T(p[0]));
    case Builtin::Exp: return exp(x);
    case Builtin::Exp2: return exp2(x);
    case Builtin::Log: return log(x);
    case Builtin::Log2: return log2(x);
    case Builtin::Atan: return atan(x);
    case Builtin::Sin: return sin(x);
    case Builtin::Cos: return cos(x);
    case Builtin::Sqrt: return sqrt(x);
    case Builtin::Rsqrt: return T(1.0) / sqrt(x);
    case Builtin::Rcp: return T(1.0) / x;
  }
  return x;
}

}  // namespace

Target Target::builtin(std::string_view name) {
  const auto& table = builtins();
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (name != table[i].name) continue;
    Target t;
    t.name_ = table[i].name;
    t.variable_ = table[i].variable;
    t.parameters_ = table[i].parameters;
    t.natural_domain_ = table[i].domain;
    t.builtin_ = static_cast<int>(i);
    return t;
  }
  std::string known;
  for (const auto& b : table) known += std::string(known.empty() ? "" : ", ") + b.name;
  throw Error("unknown target '" + std::string(name) + "' (built-ins: " + known +
                  "; or a formula in the variable)",
              {"RationalProblem::target"});
}

bool Target::is_builtin(std::string_view name) {
  for (const auto& b : builtins())
    if (name == b.name) return true;
  return false;
}

std::vector<std::string> Target::builtin_target_names() {
  std::vector<std::string> out;
  for (const auto& b : builtins()) {
    std::string params;
    for (const auto& p : b.parameters) params += (params.empty() ? "" : ", ") + p;
    out.push_back(std::string(b.name) + "(" + b.variable + (params.empty() ? "" : "; " + params) +
                  "): " + b.description);
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
  if (builtin_ >= 0)
    return eval_builtin(builtins()[static_cast<std::size_t>(builtin_)].kind, x, params);
  return detail::evaluate_jet(formula_, Jet(x), params).value();
}

std::vector<double> Target::derivatives(double x, int order, std::span<const double> params) const {
  if (order < 0 || order > kMaxDerivativeOrder)
    throw Error("derivative order " + std::to_string(order) + " outside [0, " +
                std::to_string(kMaxDerivativeOrder) + "]");
  const Jet v = Jet::variable(x, order);
  const Jet r = builtin_ >= 0
                    ? eval_builtin(builtins()[static_cast<std::size_t>(builtin_)].kind, v, params)
                    : detail::evaluate_jet(formula_, v, params);
  std::vector<double> out(static_cast<std::size_t>(order) + 1);
  for (int k = 0; k <= order; ++k) out[static_cast<std::size_t>(k)] = r.derivative(k);
  return out;
}

double Target::integral(double a, double b, std::span<const double> params) const {
  return detail::integrate([&](double x) { return value(x, params); }, a, b);
}

}  // namespace shaderfit::rational
