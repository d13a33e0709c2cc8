#include "shaderfit/search/front/choice.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace shaderfit {
namespace {

std::vector<FrontMember> front(const std::vector<std::pair<double, double>>& cost_error) {
  std::vector<FrontMember> f;
  for (auto [c, e] : cost_error) {
    FrontMember m;
    m.cost = c;
    m.loss = e;
    m.formula = "f" + std::to_string(f.size());
    f.push_back(m);
  }
  return f;
}

// Error falls 1000x up to cost 4, then hardly at all.
const std::vector<std::pair<double, double>> kKneeAt4 = {{0, 1e-1}, {2, 1e-2}, {4, 1e-5},
                                                         {6, 8e-6}, {8, 7e-6}, {10, 6e-6}};

TEST(Choice, KneeIsWhereMoreCostStopsPaying) {
  const auto f = front(kKneeAt4);
  const Choice c = choose_member(f, ChoiceRule{}, "mse");
  EXPECT_EQ(c.index, 2u);
  EXPECT_NE(c.why.find("knee"), std::string::npos) << c.why;
  EXPECT_NE(c.why.find("cost 4"), std::string::npos) << c.why;
  EXPECT_NE(c.why.find("mse"), std::string::npos) << c.why;
}

TEST(Choice, NoKneeTakesTheMostAccurate) {
  EXPECT_EQ(choose_member(front({{1, 1e-2}, {5, 1e-3}}), ChoiceRule{}).index, 1u);
  EXPECT_EQ(choose_member(front({{3, 1e-2}}), ChoiceRule{}).index, 0u);
  // A straight line in log error: nothing below it.
  EXPECT_EQ(choose_member(front({{0, 1}, {1, 0.1}, {2, 0.01}}), ChoiceRule{}).index, 2u);
  // An exact fit (error 0) is far below any line: chosen, not lost as NaN.
  EXPECT_EQ(choose_member(front({{0, 1}, {2, 1e-3}, {3, 0}}), ChoiceRule{}).index, 2u);
}

TEST(Choice, TheKneePassesOverTheReferenceItself) {
  // The function as written, exact at cost 24, beside cheap approximations: the knee is one of
  // them; asked for by cost, the reference may be chosen.
  auto f = front({{0, 1}, {5, 0.1}, {10, 1e-3}, {16, 8e-4}, {24, 1e-30}});
  f.back().origin = SearchPhase::Reference;
  EXPECT_EQ(choose_member(f, ChoiceRule{}).index, 2u);
  EXPECT_EQ(choose_member(f, parse_choice_rule("cost=30", {"test"})).index, 4u);
  // Alone, it is chosen.
  auto alone = front({{24, 1e-30}});
  alone.back().origin = SearchPhase::Reference;
  EXPECT_EQ(choose_member(alone, ChoiceRule{}).index, 0u);
  // Beside one other member, less accurate (a constant): the reference, said so (fuzz3's
  // exposure at 1 instruction per pixel).
  auto two = front({{0, 7.7e4}, {1, 1.6e-27}});
  two.back().origin = SearchPhase::Reference;
  const Choice c = choose_member(two, ChoiceRule{}, "mse");
  EXPECT_EQ(c.index, 1u);
  EXPECT_EQ(c.why,
            "the only other member (cost 0) has mse 7.7e+04: the reference as written, mse "
            "1.6e-27 at cost 1");
  // A further cut larger than the knee's own is not "only".
  const Choice steep = choose_member(front({{0, 1}, {1, 1e-3}, {19, 1e-30}}), ChoiceRule{}, "mse");
  EXPECT_EQ(steep.index, 1u);
  EXPECT_EQ(steep.why.find("only"), std::string::npos) << steep.why;
}

// A minor step (less than the minimum step below the member shown before it) is never the knee;
// a cost limit still takes the most accurate member within it, minor or not.
TEST(Choice, MinorStepsAreNotTheKnee) {
  auto f = front({{0, 1e-1}, {4, 1e-3}, {8, 0.999e-3}, {12, 1e-9}});
  f[2].minor_step = true;
  EXPECT_EQ(choose_member(f, parse_choice_rule("cost=9", {})).index, 2u);
  auto knee = front({{0, 1e-1}, {2, 1e-2}, {4, 1e-5}, {6, 0.9999e-5}, {10, 0.99e-5}});
  knee[3].minor_step = true;
  EXPECT_NE(choose_member(knee, ChoiceRule{}).index, 3u);
}

TEST(Choice, CostAndErrorLimits) {
  const auto f = front(kKneeAt4);
  EXPECT_EQ(choose_member(f, parse_choice_rule("cost=7", {})).index, 3u);
  EXPECT_EQ(choose_member(f, parse_choice_rule("cost=100", {})).index, 5u);
  EXPECT_EQ(choose_member(f, parse_choice_rule("error=0.01", {})).index, 1u);
  EXPECT_EQ(choose_member(f, parse_choice_rule("error=7.5e-6", {})).index, 4u);
  // Limits nobody meets: the nearest, and the reason says so.
  const Choice cheap =
      choose_member(front({{3, 1e-2}, {5, 1e-3}}), parse_choice_rule("cost=1", {}));
  EXPECT_EQ(cheap.index, 0u);
  EXPECT_NE(cheap.why.find("no member costs at most 1"), std::string::npos) << cheap.why;
  const Choice exact = choose_member(f, parse_choice_rule("error=1e-9", {}));
  EXPECT_EQ(exact.index, 5u);
  EXPECT_NE(exact.why.find("no member has"), std::string::npos) << exact.why;
}

TEST(Choice, MembersWithoutNumbersArePassedOver) {
  auto f = front(kKneeAt4);
  f[1].loss = NAN;
  f[1].metrics.mse = NAN;
  f[3].loss = NAN;
  f[3].metrics.mse = 8e-6;  // the loss is missing: the mse stands in
  EXPECT_EQ(choose_member(f, ChoiceRule{}).index, 2u);
  EXPECT_EQ(choose_member(f, parse_choice_rule("cost=7", {})).index, 3u);
  auto none = front({{0, 1}, {1, 0.5}});
  for (auto& m : none) m.cost = NAN;
  EXPECT_EQ(choose_member(none, ChoiceRule{}).index, 1u);
  EXPECT_THROW(choose_member(std::vector<FrontMember>{}, ChoiceRule{}), Error);
}

TEST(Choice, RuleTextRoundTrips) {
  for (const char* text : {"knee", "cost=5", "error=0.001", "cost=2.5"}) {
    ASSERT_TRUE(is_choice_rule(text));
    EXPECT_EQ(choice_rule_text(parse_choice_rule(text, {})), text);
  }
  EXPECT_FALSE(is_choice_rule("r0 + x"));
  EXPECT_NE(choice_rule_description(ChoiceRule{}).find("knee"), std::string::npos);
}

TEST(Choice, BadRulesAreRefusedWithTheirLocation) {
  for (const char* text : {"", "kneee", "cheapest", "cost=", "cost=abc", "cost=-1", "cost=5x",
                           "error=inf", "error=nan", "error=-0.1"}) {
    try {
      parse_choice_rule(text, {"ChoiceRule"});
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.where().source, "ChoiceRule") << text;
    }
  }
}

}  // namespace
}  // namespace shaderfit
