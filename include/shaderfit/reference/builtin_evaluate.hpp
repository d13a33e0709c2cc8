// The built-in reference functions (reference/builtin.hpp) for any number type T with the usual
// operators and ADL-visible elementary functions: double, or Taylor jets for exact derivatives of
// every order.
//
//   const T args[] = {x, T(0.04)};  // the variable, then the parameters
//   T r = reference::evaluate_builtin<T>(reference::BuiltinId::FresnelSchlick, args);
//
// Kept apart from builtin.hpp so that only the few sources that instantiate it for a new type
// compile these templates.
#pragma once

#include <cmath>
#include <span>

#include "shaderfit/reference/builtin.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/fv_reference.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace shaderfit::reference {

// `args` holds the entry's arguments in call order. The reference templates are used as they
// are, except Smith G1, written without the guard that returns 0 for v <= 0, so that its
// derivatives at v = 0 are those of the analytic expression (the guard would make them all zero).
template <typename T>
T evaluate_builtin(BuiltinId id, std::span<const T> args) {
  using std::atan, std::cos, std::exp, std::exp2, std::log, std::log2, std::sin, std::sqrt;
  const T& x = args[0];
  switch (id) {
    case BuiltinId::FresnelSchlick: return fresnel_schlick(args[1], x);
    case BuiltinId::FresnelSeed: return fresnel_seed(args[1], x);
    case BuiltinId::FresnelDielectric: return fresnel_dielectric(x, args[1]);
    case BuiltinId::FresnelDielectricF0: return fresnel_dielectric(x, ior_from_f0(args[1]));
    case BuiltinId::FresnelConductor: return fresnel_conductor(x, args[1], args[2]);
    case BuiltinId::FresnelExact: {
      // k == 0, written with the comparisons every T has.
      const T conductor = fresnel_conductor(x, args[1], args[2]);
      return choose(args[2] <= T(0),
                    choose(args[2] >= T(0), fresnel_dielectric(x, args[1]), conductor), conductor);
    }
    case BuiltinId::FvSchlickSmithLh: return fv_schlick_smith_lh(x, args[1], args[2]);
    case BuiltinId::FvSchlickSmith: return fv_schlick_smith_peak(x, args[1], args[2]);
    case BuiltinId::FvExact: return fv_exact_dielectric(x, args[1], args[2]);
    case BuiltinId::FvExactConductor: return fv_exact_conductor(x, args[1], args[2], args[3]);
    case BuiltinId::SmithGgxG1: return T(2.0) * x / (x + reference_detail::ggx_root(x, args[1]));
    case BuiltinId::GgxDistribution: return ggx_distribution(x, args[1]);
    case BuiltinId::Exp: return exp(x);
    case BuiltinId::Exp2: return exp2(x);
    case BuiltinId::Log: return log(x);
    case BuiltinId::Log2: return log2(x);
    case BuiltinId::Atan: return atan(x);
    case BuiltinId::Sin: return sin(x);
    case BuiltinId::Cos: return cos(x);
    case BuiltinId::Sqrt: return sqrt(x);
    case BuiltinId::Rsqrt: return T(1.0) / sqrt(x);
    case BuiltinId::Rcp: return T(1.0) / x;
  }
  return x;
}

}  // namespace shaderfit::reference
