// LDR-FLIP: its contract, and golden means that NVIDIA's flip-evaluator gives for closed-form
// pairs made the same way as in python/tests/flip_agreement_test.py (which compares the two
// implementations pixel by pixel and re-checks these goldens).
#include "shaderfit/image/flip.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include "shaderfit/core/error.hpp"

namespace shaderfit {
namespace {

using Rgb = std::array<double, 3>;

float srgb_encode(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  return static_cast<float>(c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055);
}

RgbImage make_image(int w, int h, const std::function<Rgb(int x, int y)>& pixel) {
  RgbImage image{w, h, {}};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (double c : pixel(x, y)) image.rgb.push_back(static_cast<float>(c));
  return image;
}

Rgb normalize(Rgb v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

// A Blinn-Phong sphere of radius 0.8 over a vertical gradient, lit from `light`.
RgbImage sphere(int size, Rgb light, double shininess) {
  light = normalize(light);
  const Rgb half = normalize({light[0], light[1], light[2] + 1.0});
  return make_image(size, size, [&](int x, int y) {
    const double u = (x + 0.5) / size * 2 - 1, v = 1 - (y + 0.5) / size * 2, r2 = u * u + v * v;
    Rgb linear;
    if (r2 < 0.64) {
      const Rgb n = {u / 0.8, v / 0.8, std::sqrt(std::max(0.64 - r2, 0.0)) / 0.8};
      const double diffuse = std::max(n[0] * light[0] + n[1] * light[1] + n[2] * light[2], 0.0);
      const double specular =
          std::pow(std::max(n[0] * half[0] + n[1] * half[1] + n[2] * half[2], 0.0), shininess);
      const Rgb albedo = {0.8, 0.3, 0.2};
      for (int c = 0; c < 3; ++c) linear[c] = 0.03 + albedo[c] * diffuse + 0.3 * specular;
    } else {
      const Rgb tint = {0.6, 0.7, 1.0};
      for (int c = 0; c < 3; ++c) linear[c] = (0.2 + 0.1 * v) * tint[c];
    }
    return Rgb{srgb_encode(linear[0]), srgb_encode(linear[1]), srgb_encode(linear[2])};
  });
}

// A colour ramp (80 x 48), quantised to 16 levels or not.
RgbImage ramp(bool quantised) {
  return make_image(80, 48, [&](int x, int) {
    double t = (x + 0.5) / 80;
    if (quantised) t = std::floor(t * 16) / 15;
    return Rgb{t, t * t, 1 - t};
  });
}

// Coloured sine waves (72 x 56).
RgbImage waves(double phase, double blue) {
  return make_image(72, 56, [&](int x, int y) {
    return Rgb{0.5 + 0.4 * std::sin(0.35 * x + 0.2 * y + phase), 0.5 + 0.4 * std::cos(0.27 * y),
               blue * (0.5 + 0.4 * std::sin(0.19 * (x - y)))};
  });
}

RgbImage constant(int w, int h, Rgb colour) {
  return make_image(w, h, [&](int, int) { return colour; });
}

TEST(Flip, DefaultPixelsPerDegreeIsTheToolsViewingSetUp) {
  EXPECT_NEAR(FlipOptions{}.pixels_per_degree, 3840 * std::numbers::pi / 180, 1e-12);
  EXPECT_NEAR(FlipOptions{}.pixels_per_degree, 67.0206, 1e-4);
}

TEST(Flip, IdenticalImagesGiveZeroEverywhere) {
  const RgbImage a = waves(0.0, 1.0);
  const FlipResult r = ldr_flip(a, a);
  EXPECT_EQ(r.width, 72);
  EXPECT_EQ(r.height, 56);
  ASSERT_EQ(r.error.size(), 72u * 56u);
  for (float e : r.error) EXPECT_EQ(e, 0.0f);
  EXPECT_EQ(r.mean, 0.0);
  EXPECT_EQ(r.share_above(0.0), 0.0);
}

TEST(Flip, DifferencesLieInZeroToOne) {
  const FlipResult r = ldr_flip(sphere(64, {0.5, 0.6, 0.62}, 32.0), sphere(64, {-0.5, 0.2, 1}, 8));
  float lo = 1, hi = 0;
  for (float e : r.error) lo = std::min(lo, e), hi = std::max(hi, e);
  EXPECT_GE(lo, 0.0f);
  EXPECT_GT(hi, 0.0f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_GT(r.mean, 0.0);
  EXPECT_GT(r.share_above(0.0), r.share_above(0.5));
}

TEST(Flip, GreenAgainstBlueIsTheLargestError) {
  // The colour error's scale is the distance between green and blue; flat images add no features.
  const FlipResult r = ldr_flip(constant(20, 10, {0, 1, 0}), constant(20, 10, {0, 0, 1}));
  EXPECT_NEAR(r.mean, 1.0, 1e-6);
  EXPECT_EQ(r.share_above(0.99), 1.0);
}

TEST(Flip, MatchesFlipEvaluatorGoldens) {
  // flip-evaluator 1.7's LDR means at its default 67.02 pixels per degree.
  EXPECT_NEAR(
      ldr_flip(sphere(64, {0.5, 0.6, 0.62}, 32.0), sphere(64, {0.55, 0.6, 0.58}, 24.0)).mean,
      0.0544356, 1e-3);
  EXPECT_NEAR(ldr_flip(ramp(false), ramp(true)).mean, 0.1560945, 1e-3);
  EXPECT_NEAR(ldr_flip(waves(0.0, 1.0), waves(0.3, 0.9)).mean, 0.2712007, 1e-3);
}

TEST(Flip, ResolutionChangesTheError) {
  const RgbImage a = waves(0.0, 1.0), b = waves(0.3, 0.9);
  EXPECT_NE(ldr_flip(a, b, {30.0}).mean, ldr_flip(a, b).mean);
}

void expect_error_at(const std::function<void()>& f, const std::string& where) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one at " << where;
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, where) << e.what();
  }
}

TEST(Flip, BadInputsThrowNamingTheArgument) {
  const RgbImage good = constant(8, 6, {0.5, 0.5, 0.5});
  expect_error_at([&] { ldr_flip(good, constant(6, 8, {0.5, 0.5, 0.5})); }, "test");
  expect_error_at([&] { ldr_flip(RgbImage{}, good); }, "reference");
  expect_error_at([&] { ldr_flip(good, RgbImage{0, 6, {}}); }, "test");
  RgbImage short_rgb = good;
  short_rgb.rgb.pop_back();
  expect_error_at([&] { ldr_flip(short_rgb, good); }, "reference");
  RgbImage nan = good;
  nan.rgb[7] = std::numeric_limits<float>::quiet_NaN();
  expect_error_at([&] { ldr_flip(good, nan); }, "test");
  nan.rgb[7] = std::numeric_limits<float>::infinity();
  expect_error_at([&] { ldr_flip(nan, good); }, "reference");
  expect_error_at([&] { ldr_flip(good, good, {0.0}); }, "FlipOptions::pixels_per_degree");
  expect_error_at([&] { ldr_flip(good, good, {std::nan("")}); }, "FlipOptions::pixels_per_degree");
}

TEST(Flip, ColormapIsMagmaRoundedToTheNearestEntry) {
  FlipResult r{3, 1, {0.0f, 1.0f, 0.6f / 255}, 0.0};
  const std::vector<std::uint8_t> bytes = flip_colormap(r);
  const std::vector<std::uint8_t> expected = {0, 0, 4, 252, 253, 191, 1, 0, 5};
  EXPECT_EQ(bytes, expected);
}

}  // namespace
}  // namespace shaderfit
