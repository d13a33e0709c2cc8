// Float32 stability of front members: ordinary formulas pass, cancellation and float32
// overflow are flagged, and the report shows the flag.
#include "search/front/float32_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "search/run/seed_problem_test_util.hpp"
#include "shaderfit/expr/parse.hpp"
#include "shaderfit/search/front/front_table.hpp"

namespace shaderfit::search_detail {
namespace {

SearchProblem ramp() {
  return test::unit_interval_problem(100, [](double x) { return x * x * x; });
}

FrontMember member(const char* text) {
  FrontMember m;
  m.expression = parse_formula(text, {.variables = {"x"}});
  m.formula = text;
  return m;
}

TEST(Float32Check, OrdinaryFormulasAreStable) {
  const SearchProblem p = ramp();
  const Float32Check check(p);
  FrontMember m = member("x * x * x + 0.5 * (x - x^2)");
  check.apply(m);
  EXPECT_TRUE(m.float32_stable);
  EXPECT_LT(m.float32_max_abs_diff, 1e-6);
}

TEST(Float32Check, CancellationAndOverflowAreFlagged) {
  const SearchProblem p = ramp();
  const Float32Check check(p);
  // x + 1e8 rounds to a multiple of 8 in float32: the difference loses x entirely.
  FrontMember cancel = member("(x + 100000000) - 100000000");
  check.apply(cancel);
  EXPECT_FALSE(cancel.float32_stable);
  EXPECT_NEAR(cancel.float32_max_abs_diff, 1.0, 1e-9);
  // 2^(200 x) overflows float32 (not float64) for x > 0.64.
  FrontMember overflow = member("exp2(x * 200)");
  check.apply(overflow);
  EXPECT_FALSE(overflow.float32_stable);
  EXPECT_TRUE(std::isinf(overflow.float32_max_abs_diff));
}

TEST(Float32Check, TheBoundGrowsWithTheMembersOwnError) {
  const SearchProblem p = ramp();  // max |target| = 1
  const Float32Check check(p);
  FrontMember m = member("x");
  m.metrics.max_abs = 0.0;
  EXPECT_DOUBLE_EQ(check.bound(m), kFloat32ScaleShare);
  m.metrics.max_abs = 1.0;
  EXPECT_DOUBLE_EQ(check.bound(m), kFloat32ErrorShare);
}

TEST(Float32Check, ReportsShowTheFlag) {
  SearchSummary s;
  FrontMember ok = member("x");
  FrontMember bad = member("(x + 100000000) - 100000000");
  bad.cost = 1;
  bad.float32_stable = false;
  bad.float32_max_abs_diff = 1.0;
  s.front = {ok, bad};
  const std::string table = front_table(s);
  // Constants as people read them: the shortest float32 text.
  EXPECT_NE(table.find("!x + 1e+08 - 1e+08"), std::string::npos) << table;
  EXPECT_NE(table.find("not stable in float32"), std::string::npos) << table;
  const auto j0 = front_member_json(s.front[0], FrontJson::Result);
  const auto j1 = front_member_json(s.front[1], FrontJson::Result);
  EXPECT_EQ(j0["float32_stable"], true);
  EXPECT_EQ(j1["float32_stable"], false);
  EXPECT_EQ(j1["float32_max_abs_diff"], 1.0);
}

}  // namespace
}  // namespace shaderfit::search_detail
