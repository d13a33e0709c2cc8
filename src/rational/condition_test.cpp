#include "shaderfit/rational/condition.hpp"

#include <gtest/gtest.h>

namespace shaderfit::rational {
namespace {

const std::vector<std::string> kParams = {"F0", "k"};

TEST(RationalCondition, ParsesValuesDerivativesAndIntegrals) {
  Condition a = parse_condition("f(0) = 1", kParams);
  EXPECT_EQ(a.kind, Condition::Kind::Derivative);
  EXPECT_EQ(a.order, 0);
  EXPECT_EQ(a.a, 0.0);
  EXPECT_FALSE(a.from_reference);
  Condition b = parse_condition("F'''(1)=0", kParams);
  EXPECT_EQ(b.order, 3);
  EXPECT_EQ(b.a, 1.0);
  Condition c = parse_condition(" f^(4)( 1 ) = ref ", kParams);
  EXPECT_EQ(c.order, 4);
  EXPECT_TRUE(c.from_reference);
  Condition d = parse_condition("G^2(pi/4)=1/k", kParams);
  EXPECT_EQ(d.order, 2);
  EXPECT_NEAR(d.a, 0.7853981633974483, 1e-16);
  ASSERT_EQ(d.value.parameters.size(), 2u);
  Condition e = parse_condition("int(0, 0.5) = F0 / 2", kParams);
  EXPECT_TRUE(e.is_integral());
  EXPECT_EQ(e.b, 0.5);
  EXPECT_EQ(e.point_column, 5);
  EXPECT_EQ(parse_condition("integral(0,1)=ref", kParams).b, 1.0);
}

// Each bad condition gives an error at RationalProblem::conditions with the column of the problem.
TEST(RationalCondition, ErrorsNameTheColumn) {
  struct Case {
    const char* text;
    int column;
    const char* words;
  };
  const Case cases[] = {
      {"f^(-1)(0) = 1", 4, "0 or more"},
      {"f^(40)(0) = 1", 4, "highest supported"},
      {"f(0) = q", 8, "unknown name 'q'"},
      {"f(x) = 1", 3, "unknown name 'x'"},
      {"f(0 = 1", 8, "expected ')'"},
      {"f(0) 1", 6, "expected '='"},
      {"f(0) = ", 8, "expected a value"},
      {"int(1, 0) = 1", 5, "lower bound"},
      {"(0) = 1", 1, "expected f("},
      {"f(0) = 1 +", 11, ""},
      // Found by fuzzing (fuzz/regressions/options): orders beyond a long, and beyond 24 in primes.
      {"f^99999999999999999999(0) = 1", 3, "highest supported"},
      {"f^(-99999999999999999999)(0) = 1", 4, "0 or more"},
      {"f'''''''''''''''''''''''''(0) = 1", 26, "more primes"},
  };
  for (const Case& c : cases) {
    try {
      (void)parse_condition(c.text, kParams, {"RationalProblem::conditions", 2, 0});
      ADD_FAILURE() << c.text;
    } catch (const Error& e) {
      EXPECT_EQ(e.where().source, "RationalProblem::conditions") << c.text;
      EXPECT_EQ(e.where().line, 2) << c.text;
      EXPECT_EQ(e.where().column, c.column) << c.text << ": " << e.what();
      EXPECT_NE(e.message().find(c.words), std::string::npos) << e.what();
    }
  }
}

TEST(RationalCondition, TextOfBuiltConditions) {
  EXPECT_EQ(condition_text(Condition::value_at(0, 1)), "f(0) = 1");
  EXPECT_EQ(condition_text(Condition::derivative(1, 2, 0)), "f''(1) = 0");
  EXPECT_EQ(condition_text(Condition::derivative_of_reference(1, 5)), "f^(5)(1) = ref");
  EXPECT_EQ(condition_text(Condition::integral(0, 1, 0.5)), "int(0, 1) = 0.5");
}

}  // namespace
}  // namespace shaderfit::rational
