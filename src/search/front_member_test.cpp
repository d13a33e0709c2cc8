// The front member's JSON for people and tools: the exact formula, the text for people beside it,
// and readers that take files with or without that text.
#include "shaderfit/search/front_member.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "shaderfit/expr/parse.hpp"
#include "shaderfit/expr/print.hpp"

namespace shaderfit {
namespace {

FrontMember fitted_member() {
  FrontMember m;
  m.expression = parse_formula("x * p0 - p1",
                               {.variables = {"x"},
                                .parameters = {"p0", "p1"},
                                .parameter_values = {0.5829255932120166, -0.054242242592447185}});
  m.formula = to_infix(m.expression, {.substitute_parameters = true});
  m.cost = 1;
  m.nodes = m.expression.size();
  return m;
}

TEST(FrontMemberJson, KeepsTheExactFormulaAndAddsTheTextForPeople) {
  const FrontMember m = fitted_member();
  const nlohmann::json j = front_member_json(m, FrontJson::Result);
  EXPECT_EQ(j["formula"], "0.5829255932120166 * x + 0.054242242592447185");
  EXPECT_EQ(j["formula_display"], "0.5829256 * x + 0.054242242");
  EXPECT_EQ(j["formula_parametric"], "x * p0 - p1");
  EXPECT_EQ(j["fitted_parameters"]["p0"], 0.5829255932120166);
  EXPECT_FALSE(front_member_json(m, FrontJson::Exact).contains("formula_display"));
}

TEST(FrontMemberJson, ReadersTakeFilesWithAndWithoutTheTextForPeople) {
  nlohmann::json with = {{"inputs", {"x"}},
                         {"front", {front_member_json(fitted_member(), FrontJson::Result)}}};
  nlohmann::json without = with;
  without["front"][0].erase("formula_display");
  for (const nlohmann::json& doc : {with, without}) {
    const FrontFile f = front_file_from_json(doc, "run.json");
    ASSERT_EQ(f.front.size(), 1u);
    // The exact formula is what is read: the constants to the last bit.
    EXPECT_EQ(f.front[0].member.formula, "0.5829255932120166 * x + 0.054242242592447185");
    EXPECT_EQ(to_infix(f.front[0].member.expression), f.front[0].member.formula);
  }
}

}  // namespace
}  // namespace shaderfit
