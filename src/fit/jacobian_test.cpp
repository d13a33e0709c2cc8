// The Jacobian's duals and the Taylor jets both derive from expr/op.hpp's definitions: their
// first derivatives agree for every operator.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shaderfit/expr/forward.hpp"
#include "shaderfit/expr/jet.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/fit/fit.hpp"

namespace shaderfit {
namespace {

TEST(Jacobian, AgreesWithJetsForEveryOperator) {
  const char* formulas[] = {"-(a * x)",        "(a * x)^3",        "(a * x)^-2",
                            "sqrt(a * x)",     "rsqrt(a * x)",     "rcp(a * x)",
                            "exp2(a * x)",     "log2(a * x)",      "exp(a * x)",
                            "log(a * x)",      "abs(a * x - 0.3)", "saturate(a * x)",
                            "sin(a * x)",      "cos(a * x)",       "a * x + x",
                            "x - a * x",       "a * x * x",        "a / x",
                            "x / a",           "min(a * x, 0.5)",  "max(a * x, 0.5)",
                            "pow(a * x, 1.7)", "pow(1.7, a * x)",  "fma(a, x, a * a)",
                            "sign(a * x - 0.3) * a",
                            "copysign(a * x, x - 0.5)",
                            "copysign(x - 0.5, a - 0.8) + copysign(x, a * x - 0.3)",
                            "select(a * x - 0.3 >= 0, a * a, x / a)",
                            "select(x < a * 0.5, a * x, 2)",
                            "asin(a * x)",
                            "acos(a * x)",
                            "atan(a * x - 0.3)",
                            "atan2(a * x, x - 0.5) + atan2(x, a)",
                            "tanh(a * x)",
                            "erf(a * x - 0.3)"};
  const std::vector<double> xs = {0.1, 0.35, 0.6, 0.9};
  const double a = 0.8;
  for (const char* text : formulas) {
    ParseOptions po;
    po.variables = {"x"};
    po.parameters = {"a"};
    po.parameter_values = {a};
    const Expression e = parse_formula(text, po);
    std::vector<double> values(xs.size()), jacobian(xs.size());
    const double* columns[] = {xs.data()};
    evaluate_with_jacobian(e, columns, xs.size(), values, jacobian);
    ParseOptions pj;
    pj.variables = {"x", "a"};
    const Expression ej = parse_formula(text, pj);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const Jet at[] = {Jet(xs[i]), Jet::variable(a, 1)};
      const Jet r = evaluate_at<Jet>(ej, at, {});
      EXPECT_NEAR(values[i], r.value(), 1e-12 * (1 + std::abs(r.value()))) << text;
      EXPECT_NEAR(jacobian[i], r.derivative(1), 1e-12 * (1 + std::abs(r.derivative(1)))) << text;
    }
  }
}

}  // namespace
}  // namespace shaderfit
