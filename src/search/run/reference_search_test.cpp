// The search on a shader function (docs/search.md, "Downward from the reference"): the function
// is the front's first member at its own cost, the descent finds cheaper exact forms, and a
// function the operators cannot write is said in one line while the search goes on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "shaderfit/problem/problem.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {
namespace {

// The issue's own Henyey-Greenstein shader, as bench/shaders holds it.
std::string henyey_greenstein() {
  std::ifstream in(std::string(SHADERFIT_SOURCE_DIR) + "/bench/shaders/hg.glsl");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

SearchProblem shader_problem(const std::string& source, const std::string& function,
                             std::vector<std::string> domain) {
  ProblemSource s;
  s.reference.shader_source = source;
  s.reference.shader_path = "test.glsl";
  s.reference.function = function;
  s.domain = std::move(domain);
  s.samples = 1500;
  return search_problem(load_problem(s));
}

SearchOptions budgeted() {
  SearchOptions o;
  o.threads = 1;
  o.time_limit_s = 120;
  o.max_candidates = 400'000;
  o.seed = 3;
  return o;
}

// The cheapest member whose RMS error is at most 1e-6 of the target's standard deviation.
std::optional<FrontMember> cheapest_exact(const SearchSummary& s, const SearchProblem& p) {
  double mean = 0, var = 0;
  for (double t : p.target) mean += t / static_cast<double>(p.target.size());
  for (double t : p.target) var += (t - mean) * (t - mean) / static_cast<double>(p.target.size());
  for (const FrontMember& m : s.front)
    if (m.metrics.rmse <= 1e-6 * std::sqrt(var)) return m;
  return std::nullopt;
}

TEST(ReferenceSearch, TheFunctionIsOnTheFrontAtItsOwnCostOrBelow) {
  const SearchProblem p =
      shader_problem(henyey_greenstein(), "phaseHG", {"cosTheta=-1:1", "g=0:0.9"});
  const reference::ProgramFormula own = reference_formula(p);
  ASSERT_TRUE(own.formula.has_value()) << own.why;
  SearchOptions o = budgeted();
  const double own_cost = expression_cost(*own.formula, o.cost);
  EXPECT_EQ(own_cost, 10);  // nvcc --use_fast_math -arch=sm_90 counts 10 as well
  SearchSummary s;
  run_search(o, p, &s);
  const auto exact = cheapest_exact(s, p);
  ASSERT_TRUE(exact.has_value());
  // The max(denom, 1e-6) never binds on the domain: dropping it is exact and one cheaper.
  EXPECT_LE(exact->cost, 9) << exact->formula;
  EXPECT_TRUE(exact->origin == SearchPhase::Reference || exact->origin == SearchPhase::Rewrite);
}

TEST(ReferenceSearch, PerMaterialTheFunctionIsAPowerAtFourPerPixel) {
  const SearchProblem p =
      shader_problem(henyey_greenstein(), "phaseHG", {"cosTheta=-1:1", "g=0:0.9"});
  SearchOptions o = budgeted();
  o.uniform = {"g"};
  SearchSummary s;
  run_search(o, p, &s);
  const auto exact = cheapest_exact(s, p);
  ASSERT_TRUE(exact.has_value());
  EXPECT_LE(exact->cost, 4) << exact->formula;
}

TEST(ReferenceSearch, AFunctionTheOperatorsCannotWriteIsSaidAndSearched) {
  const char* banded = R"(
float bands(float x) { return floor(x * 4.0) / 4.0 + 0.1 * x; }
)";
  const SearchProblem p = shader_problem(banded, "bands", {"x=0:1"});
  const reference::ProgramFormula own = reference_formula(p);
  EXPECT_FALSE(own.formula.has_value());
  EXPECT_NE(own.why.find("floor"), std::string::npos) << own.why;
  SearchOptions o = budgeted();
  o.max_candidates = 50'000;
  SearchSummary s;
  run_search(o, p, &s);
  EXPECT_FALSE(s.front.empty());
  for (const FrontMember& m : s.front) {
    EXPECT_NE(m.origin, SearchPhase::Reference);
    EXPECT_NE(m.origin, SearchPhase::Rewrite);
  }
}

TEST(ReferenceSearch, AFunctionNotFiniteWhereTheGpuComputesItIsSaidWithTheRow) {
  // pow(0, 0) is 1 in C and NaN on a GPU (exp2(0 * log2(0))): the corner x = y = 0.
  const SearchProblem p = shader_problem("float f(float x, float y) { return pow(x, y); }", "f",
                                         {"x=0:1", "y=0:1"});
  ASSERT_TRUE(reference_formula(p).formula.has_value());
  const std::string why = reference_off_front(budgeted(), p);
  EXPECT_EQ(why.rfind("it is not finite at x = 0, y = 0 (", 0), 0u) << why;
  // min(1, 0 / 0) is finite, its operand not: the search allows no such part.
  const SearchProblem q = shader_problem(
      "float f(float x, float y) { return min(1.0, x / y); }", "f", {"x=0:1", "y=0:1"});
  const std::string part = reference_off_front(budgeted(), q);
  EXPECT_EQ(part.rfind("a part of it is NaN at x = ", 0), 0u) << part;
  SearchOptions o = budgeted();
  o.max_candidates = 20'000;
  SearchSummary s;
  run_search(o, q, &s);
  for (const FrontMember& m : s.front) EXPECT_NE(m.origin, SearchPhase::Reference);
  // A function finite everywhere joins: nothing to say.
  EXPECT_EQ(reference_off_front(budgeted(), shader_problem(henyey_greenstein(), "phaseHG",
                                                           {"cosTheta=-1:1", "g=0:0.9"})),
            "");
}

TEST(ReferenceSearch, InfinitePartsOfTheCodeAsWrittenJoinTheFront) {
  // Walter's Smith-Beckmann cutoff: a = x rsqrt(1 - x^2) is +inf at x = 1, where a >= 1.6 picks
  // 1 in IEEE arithmetic; saturate(1 / x) at x = 0; Smith-Beckmann's G1 as written. Each joins
  // at its own cost.
  for (const char* source :
       {"float f(float x) { float a = x * inversesqrt(1.0 - x * x);\n"
        "  return a >= 1.6 ? 1.0 : 0.5 * a; }",
        "float f(float x) { return saturate(1.0 / x) * x; }",
        // The rational in the branch not taken is inf / inf = NaN at x = 1; the select that
        // holds it is itself in the branch not taken there.
        "float g1(float v, float a) { if (v <= 0.0) return 0.0;\n"
        "  float t = v * inversesqrt(1.0 - v * v) / a; if (t >= 1.6) return 1.0;\n"
        "  return (3.535 * t + 2.181 * t * t) / (1.0 + 2.276 * t + 2.577 * t * t); }\n"
        "float f(float x) { return g1(x, 0.5); }"}) {
    const SearchProblem p = shader_problem(source, "f", {"x=0:1"});
    EXPECT_EQ(reference_off_front(budgeted(), p), "") << source;
    SearchOptions o = budgeted();
    o.max_candidates = 20'000;
    SearchSummary s;
    run_search(o, p, &s);
    const double own = expression_cost(*reference_formula(p).formula, o.cost, o.uniform);
    bool itself = false;
    for (const FrontMember& m : s.front) itself = itself || (m.cost <= own && m.loss == 0);
    EXPECT_TRUE(itself) << source;
  }
}

TEST(ReferenceSearch, NoReferenceNoFormula) {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs = {{0, 1, 2}};
  p.target = {0, 1, 4};
  const reference::ProgramFormula own = reference_formula(p);
  EXPECT_FALSE(own.formula.has_value());
  EXPECT_TRUE(own.why.empty());
  EXPECT_EQ(reference_off_front(SearchOptions{}, p), "");
}

}  // namespace
}  // namespace shaderfit
