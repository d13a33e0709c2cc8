#include "shaderfit/search/options.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <set>

#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/eval/loss.hpp"
#include "shaderfit/search/search.hpp"

namespace shaderfit {
namespace {

TEST(SearchOptions, DefaultsAreValid) {
  std::string why;
  EXPECT_TRUE(SearchOptions{}.is_valid(&why)) << why;
}

TEST(SearchOptions, InvalidValuesSayWhy) {
  auto reason = [](auto edit) {
    SearchOptions o;
    edit(o);
    std::string why;
    EXPECT_FALSE(o.is_valid(&why));
    return why;
  };
  EXPECT_NE(reason([](SearchOptions& o) { o.time_limit_s = 0; }).find("time budget"),
            std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.time_limit_s = -1; }).find("time budget"),
            std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.max_candidates = 0; }).find("evaluation budget"),
            std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.threads = -2; }).find("threads"), std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.operators.clear(); }).find("operators"),
            std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.operators = {Op::Fma}; }).find("fma"),
            std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.max_power = 17; }).find("max_power"),
            std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.screen_rows = 100; }).find("screen_rows"),
            std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.population = 2; }).find("population"),
            std::string::npos);
  EXPECT_NE(reason([](SearchOptions& o) { o.checkpoint_interval_s = -1; }).find("checkpoint"),
            std::string::npos);
}

TEST(SearchOptions, TheSeedDataSetsOperators) {
  // The built-in data sets' own operators read and print back as the search's lists.
  for (const std::string& name : builtin_dataset_names()) {
    const std::optional<BuiltinDatasetInfo> data_set = builtin_dataset_info(name);
    ASSERT_TRUE(data_set.has_value()) << name;
    (void)parse_operator_list(data_set->operators);
    (void)parse_operator_list(data_set->evolution_operators);
  }
  const std::optional<BuiltinDatasetInfo> info = builtin_dataset_info("fresnel-seed");
  ASSERT_TRUE(info.has_value());
  EXPECT_EQ(parse_operator_list(info->operators),
            (std::vector<Op>{Op::Add, Op::Sub, Op::Mul, Op::Div, Op::IPow}));
  EXPECT_EQ(parse_operator_list(info->evolution_operators), (std::vector<Op>{Op::Pow, Op::Exp2}));
  EXPECT_EQ(operator_list_name(parse_operator_list(info->operators)), info->operators);
  EXPECT_EQ(operator_list_name(parse_operator_list(info->evolution_operators)),
            info->evolution_operators);
}

TEST(SearchOptions, OperatorLists) {
  EXPECT_EQ(parse_operator_list("+,-,*,/,^"),
            (std::vector<Op>{Op::Add, Op::Sub, Op::Mul, Op::Div, Op::IPow}));
  EXPECT_EQ(parse_operator_list("add, mul ,sqrt,exp2,pow"),
            (std::vector<Op>{Op::Add, Op::Mul, Op::Sqrt, Op::Exp2, Op::Pow}));
  EXPECT_EQ(operator_list_name({Op::Add, Op::IPow, Op::Sqrt}), "+,^,sqrt");
  try {
    parse_operator_list("+,frobnicate");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown operator 'frobnicate'"), std::string::npos);
    EXPECT_EQ(e.where().source, "SearchOptions::operators");
  }
  EXPECT_THROW(parse_operator_list(""), Error);
}

TEST(SearchProblem, ValidationErrors) {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs = {{1.0, 2.0, 3.0}};
  p.target = {1.0, 2.0, 3.0};
  EXPECT_NO_THROW(p.validate());
  auto message = [](SearchProblem q) {
    try {
      q.validate();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SearchProblem one = p;
  one.inputs = {{1.0}};
  one.target = {1.0};
  EXPECT_NE(message(one).find("1 row"), std::string::npos);
  SearchProblem ragged = p;
  ragged.inputs = {{1.0, 2.0}};
  EXPECT_NE(message(ragged).find("rows"), std::string::npos);
  SearchProblem nan = p;
  nan.target[1] = std::nan("");
  EXPECT_NE(message(nan).find("the target is NaN in row 2"), std::string::npos);
  SearchProblem twice = p;
  twice.input_names = {"x", "x"};
  twice.inputs = {p.inputs[0], p.inputs[0]};
  EXPECT_NE(message(twice).find("twice"), std::string::npos);
  SearchProblem weights = p;
  weights.weights = {0, 0, 0};
  EXPECT_NE(message(weights).find("sum to 0"), std::string::npos);
}

TEST(Search, LossesCheckTheirTarget) {
  SearchProblem p;
  p.input_names = {"x"};
  p.inputs = {{1.0, 2.0, 3.0}};
  p.target = {0.0, 2.0, 3.0};
  SearchOptions o;
  o.loss = Loss::Log;
  SearchSummary s;
  EXPECT_THROW(run_search(o, p, &s), Error);
  o.loss = Loss::Relative;
  EXPECT_THROW(run_search(o, p, &s), Error);
  o.loss = Loss::MaxRel;
  EXPECT_THROW(run_search(o, p, &s), Error);
}

// max_rel is a search loss, scored on the CPU: Auto resolves to it, Cuda is refused.
TEST(SearchOptions, MaxRelIsScoredOnTheCpu) {
  SearchOptions o;
  o.loss = Loss::MaxRel;
  std::string why;
  EXPECT_TRUE(o.is_valid(&why)) << why;
  EXPECT_EQ(search_device(o), ComputeDevice::Cpu);
  o.device = ComputeDevice::Cuda;
  try {
    search_device(o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "SearchOptions::device");
  }
}

}  // namespace
}  // namespace shaderfit

namespace shaderfit {
namespace {

TEST(SearchOptions, DescriptionReadsBackItsText) {
  std::set<std::string_view> names;
  SearchOptions edited;
  edited.max_candidates = 1000;
  edited.stop_at = SearchTarget{1e-4, 4};
  edited.evolution_operators.clear();
  edited.literals = {0.1, 3.0};
  edited.start = {"r0 + (1 - r0)*x^5", "min(x, 0.5) + pow(r0, 2.5)"};
  edited.checkpoint_path = "run.ckpt";
  for (const SearchOptionField& f : search_option_fields()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name << " is described twice";
    EXPECT_FALSE(f.help.empty()) << f.name;
    EXPECT_EQ(find_search_option(f.name), &f);
    for (const SearchOptions& o : {SearchOptions{}, edited}) {
      SearchOptions back;
      set_search_option(back, f, search_option_text(o, f));
      EXPECT_EQ(search_option_text(back, f), search_option_text(o, f)) << f.name;
    }
  }
  // The operators default to the set chosen from the data (a data set may bring its own).
  EXPECT_EQ(search_option_text(SearchOptions{}, *find_search_option("operators")), "auto");
  EXPECT_EQ(search_option_text(SearchOptions{}, *find_search_option("evolution_operators")),
            "auto");
  EXPECT_EQ(search_option_kind(*find_search_option("max_nodes")), OptionKind::Integer);
  EXPECT_EQ(search_option_kind(*find_search_option("loss")), OptionKind::Choice);
  EXPECT_EQ(search_option_kind(*find_search_option("start")), OptionKind::Formulas);
  EXPECT_EQ(search_option_text(edited, *find_search_option("start")),
            "r0 + (1 - r0)*x^5; min(x, 0.5) + pow(r0, 2.5)");
  EXPECT_EQ(find_search_option("max_candidates")->role, OptionRole::Budget);
}

TEST(SearchOptions, ErrorsNameTheField) {
  SearchOptions o;
  o.max_power = 17;
  std::string why;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_EQ(why, "SearchOptions::max_power: must be in [2, 16]");
  try {
    o.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "SearchOptions::max_power");
  }
  try {
    set_search_option(o, "loss", "l7");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "SearchOptions::loss");
    EXPECT_EQ(e.message(), "unknown loss 'l7' (known: mse, rmse, max_abs, max_rel, rel, log, display)");
  }
}

}  // namespace
}  // namespace shaderfit
