#include "shaderfit/eval/loss.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shaderfit/eval/metrics.hpp"

namespace shaderfit {
namespace {

constexpr Loss kLosses[] = {Loss::Mse,      Loss::Rmse, Loss::MaxAbs, Loss::MaxRel,
                            Loss::Relative, Loss::Log,  Loss::Display};

TEST(Loss, Definitions) {
  const std::vector<double> p = {1.0, 2.0, 4.0}, t = {1.0, 1.0, 2.0}, w = {1.0, 1.0, 2.0};
  const ErrorMetrics m = error_metrics(p, t);
  EXPECT_DOUBLE_EQ(m.mse, (0 + 1 + 4) / 3.0);
  EXPECT_DOUBLE_EQ(m.rmse, std::sqrt(5 / 3.0));
  EXPECT_DOUBLE_EQ(m.max_abs, 2.0);
  EXPECT_DOUBLE_EQ(m.rel, (0 + 1 + 1) / 3.0);
  EXPECT_NEAR(m.log, (0 + std::log(2.0) * std::log(2.0) * 2) / 3.0, 1e-15);
  const ErrorMetrics mw = error_metrics(p, t, {}, w);
  EXPECT_DOUBLE_EQ(mw.mse, (0 + 1 + 2 * 4) / 4.0);
  EXPECT_EQ(loss_value(Loss::MaxAbs, m), 2.0);
  EXPECT_EQ(loss_value(Loss::MaxRel, m), 1.0);
  // Non-finite predictions make every metric infinite; a zero target leaves rel undefined.
  EXPECT_TRUE(std::isinf(error_metrics(std::vector<double>{1, NAN, 2}, t).mse));
  EXPECT_TRUE(std::isnan(error_metrics(p, std::vector<double>{0, 1, 2}).rel));
  EXPECT_EQ(loss_from_name("max"), Loss::MaxAbs);
  EXPECT_EQ(loss_from_name("relative"), Loss::Relative);
  EXPECT_FALSE(loss_from_name("l1").has_value());
  EXPECT_EQ(loss_name(Loss::Log), "log");
}

// The display loss is the MSE of rows weighed by a scene's display (search_problem weighs them).
TEST(Loss, DisplayIsTheWeightedMse) {
  const std::vector<double> p = {1.0, 2.0, 4.0}, t = {1.0, 1.0, 2.0}, w = {1.0, 1.0, 2.0};
  EXPECT_EQ(loss_from_name("display"), Loss::Display);
  EXPECT_EQ(loss_name(Loss::Display), "display");
  const ErrorMetrics mw = error_metrics(p, t, {}, w);
  EXPECT_EQ(loss_value(Loss::Display, mw), mw.mse);
  EXPECT_EQ(loss_of(Loss::Display, p, t, w), loss_of(Loss::Mse, p, t, w));
}

TEST(Loss, NamesRoundTrip) {
  for (Loss k : kLosses) EXPECT_EQ(loss_from_name(loss_name(k)), k) << loss_name(k);
}

TEST(Loss, LossOfAgreesWithTheMetrics) {
  const std::vector<double> p = {1.0, 2.5, 4.0, 0.5}, t = {1.5, 1.0, 2.0, 0.25},
                            w = {1.0, 0.0, 2.0, 1.0};
  for (Loss k : kLosses) {
    EXPECT_DOUBLE_EQ(loss_of(k, p, t), loss_value(k, error_metrics(p, t))) << loss_name(k);
    EXPECT_DOUBLE_EQ(loss_of(k, p, t, w), loss_value(k, error_metrics(p, t, {}, w)))
        << loss_name(k);
  }
}

TEST(Loss, ZeroWeightRowsAreNotTaken) {
  // Row 1 has weight 0: it counts in no metric, not even the maxima.
  const std::vector<double> p = {1.0, 9.0, 3.0}, t = {2.0, 1.0, 2.0}, w = {1.0, 0.0, 1.0};
  const ErrorMetrics m = error_metrics(p, t, {}, w);
  EXPECT_EQ(m.rows, 2u);
  EXPECT_DOUBLE_EQ(m.mse, 1.0);
  EXPECT_DOUBLE_EQ(m.max_abs, 1.0);
  EXPECT_DOUBLE_EQ(m.max_rel, 0.5);
  EXPECT_DOUBLE_EQ(m.rel, (0.25 + 0.25) / 2);
}

}  // namespace
}  // namespace shaderfit
