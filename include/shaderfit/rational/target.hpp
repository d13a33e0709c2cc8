// The function a rational approximation is built for: one variable, optional named parameters.
//
//   Target f = Target::builtin("fresnel-dielectric-f0");   // variable "cos", parameter "F0"
//   std::vector<double> p = {0.04};
//   double r = f.value(0.5, p);
//   std::vector<double> d = f.derivatives(1.0, 4, p);      // f(1), f'(1), ..., f''''(1)
//   double area = f.integral(0.0, 1.0, p);
//
//   Target g = Target::formula("F0 + (1 - F0) * (1 - x)^5", "x", {"F0"});
//   Target e = Target::formula("erf(x / sqrt(2))", "x", {});    // any reference formula
//   Target s = Target::shader(text, "g1.glsl", "G1", "x", {"roughness"});  // G1(NdotV, roughness)
//
// Formulas and shader functions are compiled by the reference language (reference/language.hpp:
// the C math library, the built-in references by call, GLSL and HLSL functions) to a
// reference::Program. Derivatives of every order are exact to rounding: the function is
// evaluated on truncated Taylor series (Taylor-mode automatic differentiation, expr/jet.hpp
// through reference/program_evaluate.hpp), so no step size is involved and high orders are as
// accurate as low ones. Integrals use adaptive Gauss-Legendre quadrature to about 1e-13 of the
// integrand's scale. Parameter values are passed in the order of parameters().
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/reference/builtin.hpp"
#include "shaderfit/reference/program.hpp"

namespace shaderfit::rational {

inline constexpr int kMaxDerivativeOrder = 24;

struct Interval {
  double lo = 0.0, hi = 1.0;
  [[nodiscard]] bool contains(double x) const { return x >= lo && x <= hi; }
  [[nodiscard]] double width() const { return hi - lo; }
};

class Target {
 public:
  // A built-in reference function by name (reference/builtin.hpp, those listed as rational
  // targets): its first argument is the variable, the others its parameters, under their
  // symbol names. Throws shaderfit::Error naming the known names, located at `source`, when
  // `name` is not one of them.
  static Target builtin(std::string_view name,
                        const std::string& source = "RationalProblem::target");
  // A formula of the reference language in `variable` whose other names are `parameters`.
  // Throws the language's shaderfit::Error (an unknown function or name, a syntax error) located
  // at `source`, line and column.
  static Target formula(std::string_view text, const std::string& variable,
                        const std::vector<std::string>& parameters,
                        const std::string& source = "RationalProblem::target");
  // The function `function` of a GLSL or HLSL source `text` (read from `path`, which errors
  // name): its parameter named `variable` is the variable, or else the one parameter not among
  // `given` (the names that have values); the others are the target's parameters. Throws the
  // language's Error at the file's line and column, and Error located at `source` when no
  // parameter, or more than one, can be the variable.
  static Target shader(const std::string& text, const std::string& path,
                       const std::string& function, const std::string& variable,
                       const std::vector<std::string>& given,
                       const std::string& source = "RationalProblem::target");

  // Built-in names, each with a one-line description ("fresnel-schlick: F0 + (1 - F0)(1 - cos)^5").
  static std::vector<std::string> builtin_target_names();
  static bool is_builtin(std::string_view name);

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::string& variable() const { return variable_; }
  [[nodiscard]] const std::vector<std::string>& parameters() const { return parameters_; }
  // The domain the function is meant for (for example [0, 1] for a cosine); a default only.
  [[nodiscard]] Interval natural_domain() const { return natural_domain_; }

  [[nodiscard]] double value(double x, std::span<const double> params) const;
  // f(x), f'(x), ..., f^(order)(x); order in [0, kMaxDerivativeOrder].
  [[nodiscard]] std::vector<double> derivatives(double x, int order,
                                                std::span<const double> params) const;
  [[nodiscard]] double integral(double a, double b, std::span<const double> params) const;

 private:
  Target() = default;
  // A compiled formula or shader function whose input `variable` is the variable.
  static Target from_program(reference::Program program, std::size_t variable);
  // The function at x (with its derivatives when T is a jet), the parameters constants of T.
  template <typename T>
  [[nodiscard]] T evaluate(const T& x, std::span<const double> params) const;

  std::string name_, variable_;
  std::vector<std::string> parameters_;
  Interval natural_domain_;
  const reference::BuiltinFunction* builtin_ = nullptr;  // or nullptr for a program
  reference::Program program_;      // inputs: the variable and the parameters, in some order
  std::size_t variable_input_ = 0;  // the variable's input of program_
};

}  // namespace shaderfit::rational
