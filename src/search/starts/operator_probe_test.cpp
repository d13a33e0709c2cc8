// `auto`'s optional operator groups: suggested where the data shows them, not elsewhere.
#include "search/starts/operator_probe.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "search/run/drawn_problem_test_util.hpp"

namespace shaderfit::search_detail {
namespace {

SearchProblem drawn(std::vector<std::string> names, double lo, double hi,
                    const std::function<double(const std::vector<double>&)>& f) {
  const std::vector<std::pair<double, double>> ranges(names.size(), {lo, hi});
  return test::drawn_problem(std::move(names), ranges, f, 5, 1000);
}

bool has(const std::vector<Op>& ops, Op op) {
  return std::find(ops.begin(), ops.end(), op) != ops.end();
}

const std::vector<Op> kArithmetic = {Op::Add, Op::Sub, Op::Mul, Op::Div, Op::IPow, Op::Sqrt};

TEST(OperatorProbe, TrigonometryWhereTheDataTurnsLikeASine) {
  SearchOptions o;
  o.time_limit_s = 2;
  // r F sin(theta), theta over [1, 5]: the one-input trace.
  const auto torque = drawn({"r", "F", "theta"}, 1, 5, [](const std::vector<double>& v) {
    return v[0] * v[1] * std::sin(v[2]);
  });
  const std::vector<Op> extra =
      probe_operator_groups(o, torque, kArithmetic, probed_operator_groups());
  EXPECT_TRUE(has(extra, Op::Sin) && has(extra, Op::Cos));
  // Rational and power functions: none.
  const auto lens = drawn({"d1", "d2", "n"}, 1, 5, [](const std::vector<double>& v) {
    return 1 / (1 / v[0] + v[2] / v[1]);
  });
  EXPECT_TRUE(probe_operator_groups(o, lens, kArithmetic, probed_operator_groups()).empty());
  const auto mass = drawn({"m", "v", "c"}, 1, 2, [](const std::vector<double>& v) {
    return v[0] / std::sqrt(1 - v[1] * v[1] / (9 * v[2] * v[2]));
  });
  EXPECT_TRUE(probe_operator_groups(o, mass, kArithmetic, probed_operator_groups()).empty());
  // Operators the base has already are not repeated.
  std::vector<Op> with_trig = kArithmetic;
  with_trig.push_back(Op::Sin);
  with_trig.push_back(Op::Cos);
  EXPECT_TRUE(probe_operator_groups(o, torque, with_trig, probed_operator_groups()).empty());
}

TEST(OperatorProbe, AnglesThatArePartsOfTheTarget) {
  const auto periodic = [](std::vector<std::string> names,
                           std::vector<std::pair<double, double>> ranges,
                           const std::function<double(const std::vector<double>&)>& f) {
    return probed_operator_groups()[0].signal(
        test::drawn_problem(std::move(names), std::move(ranges), f, 7, 2000));
  };
  // cos(theta) over [1, 3], less than the half period the target alone would need.
  EXPECT_TRUE(periodic({"eps", "p", "theta", "r"}, {{1, 3}, {1, 3}, {1, 3}, {1, 3}},
                       [](const std::vector<double>& v) {
                         return v[1] * std::cos(v[2]) / (4 * std::numbers::pi * v[0] * v[3] * v[3]);
                       }));
  // An angle that is a product, and one that is a ratio with an unknown frequency.
  EXPECT_TRUE(periodic({"U", "k", "d"}, {{1, 5}, {1, 5}, {1, 5}}, [](const std::vector<double>& v) {
    return 2 * v[0] * (1 - std::cos(v[1] * v[2]));
  }));
  EXPECT_TRUE(periodic({"E", "t", "h"}, {{1, 2}, {1, 2}, {1, 4}}, [](const std::vector<double>& v) {
    const double s = std::sin(2 * std::numbers::pi * v[0] * v[1] / v[2]);
    return s * s;
  }));
  // Two harmonics of a product, beside an input that adds.
  EXPECT_TRUE(periodic({"x1", "w", "t", "a"}, {{1, 3}, {1, 3}, {1, 3}, {1, 3}},
                       [](const std::vector<double>& v) {
                         const double c = std::cos(v[1] * v[2]);
                         return v[0] * (c + v[3] * c * c);
                       }));
  // Smooth monotone functions over less than half a period, a pole and powers: none.
  EXPECT_FALSE(periodic({"x", "y"}, {{-1.5, 1.5}, {1, 3}},
                        [](const std::vector<double>& v) { return v[1] * std::atan(v[0]); }));
  EXPECT_FALSE(periodic({"n", "a"}, {{0, 1}, {0, 1}}, [](const std::vector<double>& v) {
    return 1 + v[0] * v[1] / (1 - v[0] * v[1] / 3);
  }));
  EXPECT_FALSE(
      periodic({"m", "v", "c"}, {{1, 5}, {1, 2}, {3, 10}}, [](const std::vector<double>& v) {
        return v[0] * v[2] * v[2] / std::sqrt(1 - v[1] * v[1] / (v[2] * v[2]));
      }));
  EXPECT_FALSE(periodic({"h", "w", "kb", "T"}, {{1, 5}, {1, 5}, {1, 5}, {1, 5}},
                        [](const std::vector<double>& v) {
                          const double hbar = v[0] / (2 * std::numbers::pi);
                          return hbar * v[1] / (std::exp(hbar * v[1] / (v[2] * v[3])) - 1);
                        }));
}

TEST(OperatorProbe, SameAnswerEveryTime) {
  SearchOptions o;
  o.time_limit_s = 1;
  const auto wave = drawn(
      {"x", "t"}, 0, 6, [](const std::vector<double>& v) { return std::cos(v[0] - v[1]) + v[1]; });
  const std::vector<Op> a = probe_operator_groups(o, wave, kArithmetic, probed_operator_groups());
  EXPECT_EQ(a, probe_operator_groups(o, wave, kArithmetic, probed_operator_groups()));
}

}  // namespace
}  // namespace shaderfit::search_detail
