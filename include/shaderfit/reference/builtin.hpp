// The built-in reference functions by name: one registry for every consumer (a fit's reference
// over data columns, a rational approximation's target).
//
//   const reference::BuiltinFunction* f = reference::find_builtin("fresnel-conductor");
//   const double args[] = {0.5, 0.3, 3.0};  // cos_theta, ior_n, ior_k
//   double r = reference::evaluate_builtin(*f, args);
//
// Each entry is written once: its name, a description, its argument names in call order (the
// first argument is the function's variable, the others its parameters), the natural domain of
// the variable and which name lists offer it. Arguments have one spelling as data columns
// (`arguments`, read by a fit) and, for three Fresnel entries, a shorter one in a target's
// conditions (`symbols`: cos, F0, eta, kappa), kept because command lines and documents use both.
// For any number type T (double, Taylor jets for exact derivatives) evaluate_builtin<T> is in
// reference/builtin_evaluate.hpp; this header stays light.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace shaderfit::reference {

enum class BuiltinId {
  FresnelSchlick,
  FresnelSeed,
  FresnelDielectric,
  FresnelDielectricF0,
  FresnelConductor,
  FresnelExact,
  FvSchlickSmithLh,
  FvSchlickSmith,
  FvExact,
  FvExactConductor,
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

// The name lists that offer an entry: a fit's reference functions (FitReference) and the targets
// of rational approximations (RationalTarget). Each list is documented as it stands.
enum BuiltinList : unsigned { FitReference = 1u, RationalTarget = 2u };

struct BuiltinDomain {
  double lo = 0.0, hi = 1.0;
};

struct BuiltinFunction {
  BuiltinId id;
  std::string_view name;
  std::string_view description;
  std::span<const std::string_view> arguments;  // in call order; the first is the variable
  std::span<const std::string_view> symbols;    // the same arguments in conditions; empty: as above
  BuiltinDomain domain;                         // natural domain of the variable
  unsigned lists = 0;                           // BuiltinList bits

  [[nodiscard]] bool listed_in(BuiltinList l) const { return (lists & l) != 0; }
  // symbols where given, else arguments.
  [[nodiscard]] std::span<const std::string_view> symbol_names() const {
    return symbols.empty() ? arguments : symbols;
  }
};

// Every entry, in listing order.
std::span<const BuiltinFunction> builtin_functions();

// The entry with this name offered in `list`, or nullptr.
const BuiltinFunction* find_builtin(std::string_view name, BuiltinList list);

// The function at `args` (arguments.size() values, in call order).
double evaluate_builtin(const BuiltinFunction& f, std::span<const double> args);

}  // namespace shaderfit::reference
