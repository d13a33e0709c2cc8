// `--ops auto`: the representation in the options, and the sets chosen from the data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "shaderfit/core/random.hpp"
#include "shaderfit/search/options.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {
namespace {

bool has(const std::vector<Op>& ops, Op op) {
  return std::find(ops.begin(), ops.end(), op) != ops.end();
}

SearchProblem one_input(double lo, double hi, double (*f)(double)) {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs.assign(1, {});
  for (int i = 0; i <= 256; ++i) {
    const double x = lo + (hi - lo) * i / 256.0;
    p.inputs[0].push_back(x);
    p.target.push_back(f(x));
  }
  return p;
}

TEST(AutoOperators, AutoIsAnOptionValueThatReadsBack) {
  SearchOptions o;
  set_search_option(o, "operators", "auto");
  set_search_option(o, "evolution_operators", "auto");
  EXPECT_TRUE(is_auto_operators(o.operators));
  EXPECT_TRUE(is_auto_operators(o.evolution_operators));
  EXPECT_EQ(search_option_text(o, *find_search_option("operators")), "auto");
  EXPECT_EQ(search_option_text(o, *find_search_option("evolution_operators")), "auto");
  std::string why;
  EXPECT_TRUE(o.is_valid(&why)) << why;
  // "auto" is the whole list or nothing.
  EXPECT_THROW(set_search_option(o, "operators", "auto,sqrt"), Error);
  o.operators = {Op::Count_, Op::Add};
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_NE(why.find("'auto' must be the only operator"), std::string::npos) << why;
}

TEST(AutoOperators, TheShadingSetAndPowForAHighDynamicRange) {
  SearchOptions o;
  o.operators = kAutoOperators;
  o.evolution_operators = kAutoOperators;
  // A smooth curve of one sign: the shading set, and the evolution's three.
  const SearchOptions smooth =
      resolve_auto_operators(o, one_input(0, 1, [](double x) { return std::sqrt(x) + 0.1; }));
  EXPECT_EQ(operator_list_name(smooth.operators), "+,-,*,/,^,sqrt,exp2,log2,abs,min,max");
  EXPECT_EQ(operator_list_name(smooth.evolution_operators), "pow,rsqrt,saturate");
  // A sharp peak (max |y| > 100 median |y|): pow joins the enumeration, so not the evolution's.
  const SearchOptions peak =
      resolve_auto_operators(o, one_input(0, 1, [](double x) { return std::pow(x, 40.0); }));
  EXPECT_TRUE(has(peak.operators, Op::Pow));
  EXPECT_EQ(operator_list_name(peak.evolution_operators), "rsqrt,saturate");
  // An input of both signs: sign and copysign in the enumeration, select in the evolution.
  const SearchOptions both =
      resolve_auto_operators(o, one_input(-1, 1, [](double x) { return std::exp(x); }));
  EXPECT_EQ(operator_list_name(both.operators),
            "+,-,*,/,^,sqrt,exp2,log2,abs,min,max,sign,copysign");
  EXPECT_EQ(operator_list_name(both.evolution_operators), "pow,rsqrt,saturate,select");
  // Odd data is searched on its half x >= 0 (symmetry.hpp), where x has one sign; with the
  // folding off the sign operators are back. (Data of one input never gets atan itself:
  // search/library_operators.hpp.)
  const auto atan_data = one_input(-1, 1, [](double x) { return std::atan(x); });
  const SearchOptions odd = resolve_auto_operators(o, atan_data);
  EXPECT_EQ(operator_list_name(odd.operators), "+,-,*,/,^,sqrt,exp2,log2,abs,min,max");
  EXPECT_EQ(operator_list_name(odd.evolution_operators), "pow,rsqrt,saturate");
  SearchOptions unfolded = o;
  unfolded.symmetry = false;
  EXPECT_EQ(operator_list_name(resolve_auto_operators(unfolded, atan_data).operators),
            "+,-,*,/,^,sqrt,exp2,log2,abs,min,max,sign,copysign");
  // Lists that are not auto stay as given.
  SearchOptions given;
  given.operators = parse_operator_list("+,-,*,/,^");
  given.evolution_operators = parse_operator_list("pow,exp2");
  const SearchOptions same =
      resolve_auto_operators(given, one_input(0, 1, [](double x) { return std::pow(x, 40.0); }));
  EXPECT_EQ(same.operators, given.operators);
  EXPECT_EQ(same.evolution_operators, given.evolution_operators);
}

TEST(AutoOperators, LibraryOperatorsForTheirData) {
  // asin ... erf join the enumeration where the data is one of them of a simple function of the
  // inputs (search/library_operators.hpp has the rule and its tests); the search prints the
  // choice ("operators (auto): ...").
  SearchOptions o;
  o.operators = kAutoOperators;
  o.evolution_operators = kAutoOperators;
  SearchProblem p;
  p.input_names = {"lambda", "n", "d"};
  p.inputs.assign(3, {});
  Rng rng(5);
  for (int i = 0; i < 500; ++i) {
    const double lambda = uniform(rng, 0.5, 1.0), n = uniform(rng, 1.0, 2.0),
                 d = uniform(rng, 1.0, 2.0);
    p.inputs[0].push_back(lambda);
    p.inputs[1].push_back(n);
    p.inputs[2].push_back(d);
    p.target.push_back(std::asin(lambda / (n * d)));
  }
  const SearchOptions r = resolve_auto_operators(o, p);
  EXPECT_TRUE(has(r.operators, Op::Asin)) << operator_list_name(r.operators);
  EXPECT_FALSE(has(r.operators, Op::Acos) || has(r.operators, Op::Erf));
  // Not on data that does not ask for them, and never in a list that is not auto.
  const SearchOptions smooth =
      resolve_auto_operators(o, one_input(0, 1, [](double x) { return std::sqrt(x) + 0.1; }));
  EXPECT_EQ(operator_list_name(smooth.operators), "+,-,*,/,^,sqrt,exp2,log2,abs,min,max");
  SearchOptions given = o;
  given.operators = parse_operator_list("+,-,*,/");
  EXPECT_EQ(operator_list_name(resolve_auto_operators(given, p).operators), "+,-,*,/");
  EXPECT_EQ(operator_list_name(parse_operator_list("asin,acos,atan,atan2,tanh,erf")),
            "asin,acos,atan,atan2,tanh,erf");
}

TEST(AutoOperators, ASearchWithAutoOperatorsRuns) {
  SearchOptions o;
  o.operators = kAutoOperators;
  o.evolution_operators = kAutoOperators;
  o.threads = 1;
  o.evolve = false;
  o.max_enumeration_cost = 2;
  o.time_limit_s = 60;  // a bound: the level cap stops it
  SearchSummary s;
  run_search(o, one_input(0, 1, [](double x) { return std::sqrt(x) + 0.5; }), &s);
  ASSERT_FALSE(s.front.empty());
  EXPECT_LE(s.front.back().metrics.max_abs, 1e-12) << s.brief_report();
}

}  // namespace
}  // namespace shaderfit
