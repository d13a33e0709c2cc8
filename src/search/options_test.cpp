#include "shaderfit/search/options.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <set>

#include "search/checkpoint.hpp"
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

// Every member of SearchOptions, in declaration order. A member added to SearchOptions breaks
// this binding at compile time: name it here, then describe it in options.cpp (which gives it its
// JSON and checkpoint key) or, for a callback or handle that nothing records, add it to
// kUnrecordedMembers below.
std::vector<const void*> member_addresses(const SearchOptions& o) {
  const auto& [time_limit_s, max_candidates, stop_at, seed, threads, device, loss, cost, precision,
               operators, evolution_operators, max_power, literals, start, symmetry, uniform,
               enumerate, screen_rows, max_classes, max_enumeration_share, max_enumeration_cost,
               evolve, max_nodes, population, islands, migration_interval, max_parameters, fit_rows,
               linear_scaling, on_new_member, on_progress, progress_interval_s, interrupt,
               communicator, checkpoint_path, checkpoint_interval_s, resume_path, certify,
               certify_time_limit_s, min_step] = o;
  return {&time_limit_s,
          &max_candidates,
          &stop_at,
          &seed,
          &threads,
          &device,
          &loss,
          &cost,
          &precision,
          &operators,
          &evolution_operators,
          &max_power,
          &literals,
          &start,
          &symmetry,
          &uniform,
          &enumerate,
          &screen_rows,
          &max_classes,
          &max_enumeration_share,
          &max_enumeration_cost,
          &evolve,
          &max_nodes,
          &population,
          &islands,
          &migration_interval,
          &max_parameters,
          &fit_rows,
          &linear_scaling,
          &on_new_member,
          &on_progress,
          &progress_interval_s,
          &interrupt,
          &communicator,
          &checkpoint_path,
          &checkpoint_interval_s,
          &resume_path,
          &certify,
          &certify_time_limit_s,
          &min_step};
}

// Every described field changed from its default.
SearchOptions every_field_edited() {
  SearchOptions o;
  o.time_limit_s = 2.5;
  o.max_candidates = 12345;
  o.stop_at = SearchTarget{1e-4, 4};
  o.seed = 7;
  o.threads = 3;
  o.device = ComputeDevice::Cpu;
  o.loss = Loss::MaxAbs;
  o.cost = CostTarget::Nodes;
  o.precision = Precision::Float;
  o.operators = {Op::Add, Op::Mul, Op::Div};
  o.evolution_operators = {Op::Sub};
  o.max_power = 7;
  o.literals = {0.1, 3.0};
  o.start = {"r0 + (1 - r0)*x^5", "min(x, 0.5) + pow(r0, 2.5)"};
  o.symmetry = false;
  o.uniform = {"r0"};
  o.enumerate = false;
  o.screen_rows = 128;
  o.max_classes = 1000;
  o.max_enumeration_share = 0.25;
  o.max_enumeration_cost = 9;
  o.evolve = false;
  o.max_nodes = 31;
  o.population = 64;
  o.islands = 3;
  o.migration_interval = 7;
  o.max_parameters = 3;
  o.fit_rows = 100;
  o.linear_scaling = false;
  o.progress_interval_s = 0.5;
  o.checkpoint_path = "run.ckpt";
  o.checkpoint_interval_s = 30;
  o.resume_path = "old.ckpt";
  o.certify = true;
  o.certify_time_limit_s = 3;
  o.min_step = 0.05;
  return o;
}

TEST(SearchOptions, EveryMemberIsDescribedOrNamedUnrecorded) {
  const SearchOptions o;
  // Callbacks and handles of the running search: no JSON or checkpoint can hold them.
  const std::set<const void*> kUnrecordedMembers = {&o.on_new_member, &o.on_progress, &o.interrupt,
                                                    &o.communicator};
  std::set<const void*> described;
  for (const SearchOptionField& f : search_option_fields())
    described.insert(std::visit([&](auto m) -> const void* { return &(o.*m); }, f.member));
  EXPECT_EQ(described.size(), search_option_fields().size()) << "a member is described twice";
  const std::vector<const void*> members = member_addresses(o);
  for (std::size_t k = 0; k < members.size(); ++k)
    EXPECT_NE(described.count(members[k]) + kUnrecordedMembers.count(members[k]), 0u)
        << "SearchOptions member " << k + 1 << " (declaration order) has no description";
  EXPECT_EQ(described.size() + kUnrecordedMembers.size(), members.size());
}

TEST(SearchOptions, EveryFieldChangedSurvivesTheRoundTrips) {
  const SearchOptions defaults, edited = every_field_edited();
  SearchOptions back;
  for (const SearchOptionField& f : search_option_fields()) {
    const std::string text = search_option_text(edited, f);
    EXPECT_NE(text, search_option_text(defaults, f)) << f.name << " is not changed by the test";
    set_search_option(back, f, text);
  }
  // Through the text of every field (the JSON and the command line write and read it).
  for (const SearchOptionField& f : search_option_fields())
    EXPECT_EQ(search_option_text(back, f), search_option_text(edited, f)) << f.name;
  // Through a checkpoint's options: every field that decides what the search does.
  SearchOptions resumed;
  for (const auto& [name, text] : search_detail::checkpoint_options(edited))
    set_search_option(resumed, name, text);
  std::size_t recorded = 0;
  for (const SearchOptionField& f : search_option_fields()) {
    if (f.role != OptionRole::Search) continue;
    ++recorded;
    EXPECT_EQ(search_option_text(resumed, f), search_option_text(edited, f)) << f.name;
  }
  EXPECT_EQ(search_detail::checkpoint_options(edited).size(), recorded);
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
