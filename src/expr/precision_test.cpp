#include "shaderfit/expr/precision.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "shaderfit/image/half.hpp"

namespace shaderfit {
namespace {

TEST(PrecisionNames, RoundTrip) {
  for (Precision p : {Precision::Double, Precision::Float, Precision::Half})
    EXPECT_EQ(precision_from_name(precision_name(p)), p);
  EXPECT_EQ(precision_from_name("float16"), Precision::Half);
  EXPECT_FALSE(precision_from_name("quarter"));
}

// round_to_half equals the float path of image/half.hpp (itself tested against the IEEE
// encodings) on every float value that converts exactly, and the nearest half otherwise.
TEST(RoundToHalf, MatchesTheFloatConversionAndTheGrid) {
  EXPECT_EQ(round_to_half(0.1), 0.0999755859375);
  EXPECT_EQ(round_to_half(65504.0), 65504.0);
  EXPECT_EQ(round_to_half(65519.99), 65504.0);
  EXPECT_TRUE(std::isinf(round_to_half(65520.0)));
  EXPECT_EQ(round_to_half(std::ldexp(1.0, -25)), 0.0);  // a tie between 0 and 2^-24: even
  EXPECT_EQ(round_to_half(std::ldexp(1.5, -25)), std::ldexp(1.0, -24));
  EXPECT_EQ(round_to_half(-3.0), -3.0);
  EXPECT_TRUE(std::isnan(round_to_half(std::nan(""))));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> exponent(-26, 17), unit(-1, 1);
  for (int i = 0; i < 100000; ++i) {
    const double v = unit(rng) * std::exp2(exponent(rng));
    const double h = round_to_half(v);
    // Double -> float -> half can round twice; compare only where float holds v exactly.
    const auto f = static_cast<float>(v);
    if (static_cast<double>(f) == v) {
      ASSERT_EQ(h, static_cast<double>(half_to_float(float_to_half(f)))) << v;
    }
    if (std::isfinite(h)) {
      ASSERT_LE(std::abs(h - v), 0.5 * half_ulp(v) * (1 + 1e-12)) << v;
      ASSERT_EQ(round_to_half(h), h);
    }
  }
  EXPECT_EQ(half_ulp(1.0), std::ldexp(1.0, -10));
  EXPECT_EQ(half_ulp(0.999), std::ldexp(1.0, -11));
  EXPECT_EQ(half_ulp(1e-6), std::ldexp(1.0, -24));
  EXPECT_TRUE(std::isinf(half_ulp(7e4)));
}

// Every pair of neighbouring positive halves (subnormal, normal, up to 65504 and the overflow
// boundary): the midpoint goes to the one with an even significand, anything nearer to either to
// it; the same mirrored for negatives.
TEST(RoundToHalf, EveryMidpointTiesToEven) {
  std::vector<double> halves;
  for (int k = 0; k < 1024; ++k) halves.push_back(std::ldexp(k, -24));  // 0 and the subnormals
  for (int e = -14; e <= 15; ++e)
    for (int m = 0; m < 1024; ++m) halves.push_back(std::ldexp(1024 + m, e - 10));
  halves.push_back(65536.0);  // stands for infinity: 65520 and above round to it
  for (std::size_t k = 0; k + 1 < halves.size(); ++k) {
    const double lo = halves[k], hi = halves[k + 1], mid = (lo + hi) / 2;
    const double even = (k % 2 == 0) ? lo : hi;  // significands alternate, 0 even
    const auto want = [](double h) {
      return h == 65536.0 ? std::numeric_limits<double>::infinity() : h;
    };
    for (const double sign : {1.0, -1.0}) {
      ASSERT_EQ(round_to_half(sign * lo), sign * want(lo)) << lo;
      ASSERT_EQ(round_to_half(sign * mid), sign * want(even)) << mid;
      ASSERT_EQ(round_to_half(sign * std::nextafter(mid, 0.0)), sign * want(lo)) << mid;
      ASSERT_EQ(round_to_half(sign * std::nextafter(mid, 1e9)), sign * want(hi)) << mid;
    }
  }
}

}  // namespace
}  // namespace shaderfit
