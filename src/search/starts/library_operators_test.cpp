// Which of asin, acos, atan, atan2, tanh and erf `auto` adds (search/library_operators.hpp): for
// references that call them, for data that is one of them of a simple function of the inputs,
// and not for data that merely lies in their ranges.
#include "search/starts/library_operators.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <numbers>

#include "shaderfit/core/random.hpp"
#include "shaderfit/data/fresnel_seed.hpp"
#include "shaderfit/reference/language.hpp"
#include "shaderfit/search/options.hpp"

namespace shaderfit::search_detail {
namespace {

// Rows drawn uniformly from the boxes [lo, hi] of the inputs, the target f of them.
SearchProblem sampled(const std::vector<std::pair<double, double>>& box,
                      const std::function<double(const std::vector<double>&)>& f,
                      std::size_t rows = 2000) {
  Rng rng(11);
  SearchProblem p;
  p.inputs.assign(box.size(), {});
  for (std::size_t k = 0; k < box.size(); ++k) p.input_names.push_back("x" + std::to_string(k));
  std::vector<double> x(box.size());
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t k = 0; k < box.size(); ++k) {
      x[k] = uniform(rng, box[k].first, box[k].second);
      p.inputs[k].push_back(x[k]);
    }
    p.target.push_back(f(x));
  }
  return p;
}

std::string names(const std::vector<Op>& ops) { return ops.empty() ? "" : operator_list_name(ops); }

TEST(LibraryOperators, InverseErf) {
  for (double y : {0.0, 1e-300, 1e-8, 0.3, 0.5, 0.500001, 0.9, 0.999, 1 - 1e-12, 1 - 0x1p-53}) {
    const double x = inverse_erf(y);
    EXPECT_NEAR(std::erf(x), y, 2e-16) << y;
    EXPECT_EQ(inverse_erf(-y), -x);
  }
  for (double x : {0.01, 0.4, 1.0, 2.5, 5.0})
    EXPECT_NEAR(inverse_erf(std::erf(x)), x, 1e-13 * x + (x > 4 ? 1e-3 : 0)) << x;
  EXPECT_EQ(inverse_erf(1.0), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(inverse_erf(1.5)));
}

TEST(LibraryOperators, DataThatIsOneOfThemOfASimpleFunction) {
  using V = std::vector<double>;
  // AI-Feynman's arcsin(lambda / (n d)) and tanh(m B / (k T)): monomials inside.
  EXPECT_EQ(
      names(suggested_library_operators(sampled(
          {{0.5, 1}, {1, 2}, {1, 2}}, [](const V& x) { return std::asin(x[0] / (x[1] * x[2])); }))),
      "asin");
  EXPECT_EQ(names(suggested_library_operators(
                sampled({{1, 5}, {1, 5}, {1, 5}, {1, 5}},
                        [](const V& x) { return std::tanh(x[0] * x[1] / (x[2] * x[3])); }))),
            "tanh");
  // Snell's arcsin(n sin(theta)): a monomial of an input and another's sine.
  EXPECT_EQ(names(suggested_library_operators(sampled(
                {{0, 1}, {1, 5}}, [](const V& x) { return std::asin(x[0] * std::sin(x[1])); }))),
            "asin");
  // Linear insides; a function of one input is left to be approximated without them.
  EXPECT_EQ(names(suggested_library_operators(
                sampled({{-3, 3}, {0, 1}}, [](const V& x) { return std::atan(x[0] - x[1]); }))),
            "atan");
  EXPECT_EQ(names(suggested_library_operators(
                sampled({{-3, 3}}, [](const V& x) { return std::atan(x[0]); }))),
            "");
  EXPECT_EQ(names(suggested_library_operators(
                sampled({{-1, 1}}, [](const V& x) { return std::acos(x[0]); }))),
            "");
  EXPECT_EQ(names(suggested_library_operators(
                sampled({{-3, 3}, {0, 1}}, [](const V& x) { return std::erf(x[0] / 2 + x[1]); }))),
            "erf");
  // atan2 over all four quadrants: beyond atan's range, y / x a monomial in magnitude.
  EXPECT_EQ(names(suggested_library_operators(
                sampled({{-1, 1}, {-1, 1}}, [](const V& x) { return std::atan2(x[0], x[1]); }))),
            "atan2");
}

TEST(LibraryOperators, NotForDataThatMerelyLiesInTheirRanges) {
  using V = std::vector<double>;
  const auto none = [](const SearchProblem& p) { return names(suggested_library_operators(p)); };
  // The seed's Fresnel task: a target in [0, 1].
  Rng rng(1);
  const Dataset d = make_fresnel_seed_dataset(rng);
  SearchProblem fresnel;
  fresnel.input_names = {"r0", "x"};
  fresnel.inputs = {d.numeric("r0").values, d.numeric("cos_theta").values};
  fresnel.target = d.numeric("R").values;
  EXPECT_EQ(none(fresnel), "");
  EXPECT_EQ(none(sampled({{0, 1}, {0.02, 0.1}},
                         [](const V& x) { return x[1] + (1 - x[1]) * std::pow(1 - x[0], 5); })),
            "");
  EXPECT_EQ(none(sampled({{0, 1}}, [](const V& x) { return std::sqrt(x[0]) + 0.1; })), "");
  EXPECT_EQ(none(sampled({{-1, 1}}, [](const V& x) { return std::exp(x[0]); })), "");
  EXPECT_EQ(none(sampled({{0, 1}}, [](const V& x) { return std::pow(x[0], 40.0); })), "");
  EXPECT_EQ(none(sampled({{0, 1}}, [](const V& x) { return x[0] / (1 + x[0]); })), "");
  EXPECT_EQ(none(sampled({{0, 3}}, [](const V& x) { return std::sin(x[0]) * 0.9; })), "");
  EXPECT_EQ(none(sampled({{-1, 1}, {0, 1}}, [](const V& x) { return 0.3 * x[0] - x[1]; })), "");
  EXPECT_EQ(none(sampled({{-2, 2}}, [](const V& x) { return std::exp(-x[0] * x[0]); })), "");
  EXPECT_EQ(none(sampled({{0, 1}}, [](const V&) { return 0.5; })), "");  // constant
}

TEST(LibraryOperators, ReferencesThatCallThem) {
  SearchProblem p =
      sampled({{0, 1}, {0, 1}}, [](const std::vector<double>& x) { return x[0] + x[1]; });
  auto f = std::make_shared<reference::ReferenceFunction>();
  f->program = reference::compile_reference(
      {.formula = "erfc(x0) + atan2(x0, 2) * x1", .variables = {"x0", "x1"}});
  f->domain = {reference::parse_domain_axis("x0=0:1", "domain"),
               reference::parse_domain_axis("x1=0:1", "domain")};
  p.reference = f;
  EXPECT_EQ(names(suggested_library_operators(p)), "atan2,erf");
  f->program = reference::compile_reference({.formula = "x0 * x1", .variables = {"x0", "x1"}});
  EXPECT_EQ(names(suggested_library_operators(p)), "");
  // acos(x) in one input: approximated without acos.
  SearchProblem one =
      sampled({{-1, 1}}, [](const std::vector<double>& x) { return std::acos(x[0]); });
  auto g = std::make_shared<reference::ReferenceFunction>();
  g->program = reference::compile_reference({.formula = "acos(x0)", .variables = {"x0"}});
  g->domain = {reference::parse_domain_axis("x0=-1:1", "domain")};
  one.reference = g;
  EXPECT_EQ(names(suggested_library_operators(one)), "");
}

// Ten inputs and a hundred thousand rows: the probe reads 2000 of them and still finds tanh. (Its
// time is part of every search's; the benchmarks in bench/ measure it, not this test: the machines
// are shared.)
TEST(LibraryOperators, TheProbeFindsItOnASampleOfManyRows) {
  std::vector<std::pair<double, double>> box(10, {0.5, 2.0});
  const SearchProblem p = sampled(
      box, [](const std::vector<double>& x) { return std::tanh(x[0] * x[3] / x[7]); }, 100000);
  EXPECT_EQ(names(suggested_library_operators(p)), "tanh");
}

}  // namespace
}  // namespace shaderfit::search_detail
