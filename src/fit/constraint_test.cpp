#include "shaderfit/fit/constraint.hpp"

#include <gtest/gtest.h>

#include "shaderfit/core/error.hpp"
#include "shaderfit/expr/parse.hpp"

namespace shaderfit {
namespace {

Expression seed_formula() {
  ParseOptions po;
  po.variables = {"f0", "x"};
  po.parameters = {"A", "B", "C"};
  return parse_formula("f0 * exp2(A*x^2 + B*x + C)", po);
}

TEST(Constraint, Kinds) {
  const Expression f = seed_formula();
  const Constraint p = parse_constraint("A + B == 2.5", f);
  EXPECT_EQ(p.kind, Constraint::Kind::parameters);
  EXPECT_EQ(p.lhs.parameters, f.parameters);
  const Constraint v = parse_constraint("f(x = 0) = f0", f);
  EXPECT_EQ(v.kind, Constraint::Kind::value);
  ASSERT_EQ(v.point.size(), 1u);
  EXPECT_EQ(v.point[0], (std::pair<std::string, double>("x", 0.0)));
  EXPECT_EQ(v.rhs.variables, std::vector<std::string>{"f0"});
  const Constraint d = parse_constraint("df/dx(x = 1, f0 = pi/4) = 0", f);
  EXPECT_EQ(d.kind, Constraint::Kind::derivative);
  EXPECT_EQ(d.variable, "x");
  ASSERT_EQ(d.point.size(), 2u);
  EXPECT_NEAR(d.point[1].second, 0.7853981633974483, 1e-15);
}

void expect_error(const char* text, const char* message) {
  try {
    (void)parse_constraint(text, seed_formula(), "constraint 1");
    ADD_FAILURE() << "no error for " << text;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(Constraint, Errors) {
  expect_error("C", "needs '='");
  expect_error("C + x = 0", "cannot use the variable 'x'");
  expect_error("D = 0", "constraint 1:1:1: unknown variable 'D'");
  expect_error("f(y = 0) = 1", "'y' is not a variable of the formula");
  expect_error("df/dy(x = 0) = 1", "cannot differentiate by 'y'");
  expect_error("C = A", "cannot use the parameter 'A'");
  expect_error("C = x", "must be a number");
  expect_error("f(x = 0) = 1 +", "constraint 1:1:");
  expect_error("2 = 1", "names no parameter");
}

}  // namespace
}  // namespace shaderfit
