#include "shaderfit/eval/metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace shaderfit {
namespace {

TEST(Metrics, KnownValues) {
  std::vector<double> p = {1.0, 2.0, 3.5}, t = {1.0, 2.5, 3.0};
  ErrorMetrics m = error_metrics(p, t);
  EXPECT_EQ(m.rows, 3u);
  EXPECT_DOUBLE_EQ(m.mse, (0.25 + 0.25) / 3);
  EXPECT_DOUBLE_EQ(m.rmse, std::sqrt(0.5 / 3));
  EXPECT_DOUBLE_EQ(m.max_abs, 0.5);
  EXPECT_DOUBLE_EQ(m.max_rel, 0.5 / 2.5);
}

TEST(Metrics, SubsetsWeightsAndNonFinite) {
  std::vector<double> p = {1.0, 2.0, NAN}, t = {0.0, 2.5, 3.0};
  std::vector<std::size_t> first_two = {0, 1};
  std::vector<double> w = {3.0, 1.0, 1.0};
  ErrorMetrics m = error_metrics(p, t, first_two, w);
  EXPECT_DOUBLE_EQ(m.mse, (3.0 * 1.0 + 0.25) / 4.0);
  EXPECT_DOUBLE_EQ(m.max_rel, 0.2);  // the row with t = 0 has no relative error
  ErrorMetrics all = error_metrics(p, t);
  EXPECT_EQ(all.nonfinite, 1u);
  EXPECT_TRUE(std::isinf(all.mse));
}

TEST(Metrics, WithoutTheLogErrorTheOthersAreTheSame) {
  std::vector<double> p = {1.0, 2.0, 3.5, 0.5}, t = {1.0, 2.5, 3.0, 0.25};
  std::vector<double> w = {1.0, 2.0, 0.5, 1.0};
  const ErrorMetrics all = error_metrics(p, t, {}, w);
  const ErrorMetrics some = error_metrics(p, t, {}, w, MetricSet::NoLog);
  EXPECT_GT(all.log, 0);
  EXPECT_TRUE(std::isnan(some.log));
  EXPECT_EQ(some.rows, all.rows);
  EXPECT_EQ(some.mse, all.mse);
  EXPECT_EQ(some.rmse, all.rmse);
  EXPECT_EQ(some.max_abs, all.max_abs);
  EXPECT_EQ(some.max_rel, all.max_rel);
  EXPECT_EQ(some.rel, all.rel);
  p[1] = NAN;
  EXPECT_TRUE(std::isinf(error_metrics(p, t).log));
  EXPECT_TRUE(std::isnan(error_metrics(p, t, {}, {}, MetricSet::NoLog).log));
}

TEST(Metrics, GroupsAndRelativeChange) {
  std::vector<std::string> labels = {"metal", "dielectric", "metal"};
  auto g = group_rows(labels);
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g["metal"], (std::vector<std::size_t>{0, 2}));
  EXPECT_DOUBLE_EQ(relative_change(0.66, 1.0), -0.34);
  EXPECT_EQ(relative_change(1.0, 0.0), 0.0);
}

}  // namespace
}  // namespace shaderfit
