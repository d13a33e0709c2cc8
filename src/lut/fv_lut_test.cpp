#include "shaderfit/lut/fv_lut.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "image/test_readers.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/lut/fv_compare.hpp"
#include "shaderfit/lut/fv_output.hpp"
#include "shaderfit/reference/fv_reference.hpp"

namespace shaderfit::lut {
namespace {

FvLutOptions small() {
  FvLutOptions o;
  o.size = 16;
  o.fit_samples = 45;
  o.eval_samples = 90;
  o.endpoint_grid = 12;
  return o;
}

const FvBake& baked() {
  static const FvBake bake = bake_fv_luts(small(), kAllFvVariants);
  return bake;
}

double model(const FvCell& c, double f0, double d) {
  const double x = 1 - d;
  return f0 * std::exp2((c.a * x + c.b) * x + c.c);
}

// Rounding of the float shader's fma(fma(P0, 1, P1), 1, P2) and exp2: the sums carry the
// magnitude of the coefficients, so FV(1) is f0 to within float rounding of |P0| + |P1| + |P2|.
double float_bound(const float* t) {
  const double magnitude = std::abs(t[0]) + std::abs(t[1]) + std::abs(t[2]);
  return std::log(2.0) * magnitude * 0x1p-24 + 4 * 0x1p-24;
}

TEST(FvLut, BakesAllFourVariantsWithoutFailures) {
  const FvBake& b = baked();
  ASSERT_EQ(b.tables.size(), 4u);
  for (const FvTable& t : b.tables) {
    EXPECT_TRUE(t.failures.empty()) << variant_name(t.variant) << ": " << t.failures.front();
    EXPECT_EQ(t.texels.size(), 16u * 16u * 4u);
    EXPECT_GT(t.summary.mean_log2, 0);
    EXPECT_LT(t.summary.mean_log2, 1.0) << variant_name(t.variant);
  }
  // Least squares in log2 without a constraint beats the constrained fits on the mean log error,
  // and every fit beats endpoint matching.
  EXPECT_LT(b.tables[1].summary.mean_log2, b.tables[2].summary.mean_log2);
  EXPECT_LT(b.tables[2].summary.mean_log2, b.tables[0].summary.mean_log2);
}

// Every cell of every table is counted once; on one thread each count is reported.
TEST(FvLut, ReportsProgressInCells) {
  FvLutOptions o;
  o.size = 4;
  o.fit_samples = 12;
  o.eval_samples = 12;
  o.endpoint_grid = 4;
  o.threads = 1;
  std::vector<std::size_t> seen;
  o.on_progress = [&](const Progress& p) {
    EXPECT_EQ(p.total, 64u);
    EXPECT_EQ(p.unit, "cells");
    seen.push_back(p.done);
  };
  (void)bake_fv_luts(o, kAllFvVariants);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back(), 64u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  seen.clear();
  o.on_progress = [&](const Progress& p) { seen.push_back(p.done * 1000 + p.total); };
  (void)compare_with_exact(o, FvVariant::clamped);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back() / 1000, seen.back() % 1000);  // ends at its total
}

TEST(FvLut, ConstrainedVariantsReproduceF0AtNormalIncidence) {
  const FvLutOptions o = small();
  for (const FvTable& t : baked().tables) {
    if (!variant_is_constrained(t.variant)) continue;
    for (std::size_t k = 0; k < t.cells.size(); ++k) {
      EXPECT_EQ(t.cells[k].c, 0.0);
      const float* p = &t.texels[4 * k];
      const float e = std::fma(std::fma(p[0], 1.0f, p[1]), 1.0f, p[2]);  // the shader, in float
      const double f0 = cell_f0(k / o.size, o.size);
      EXPECT_LE(std::abs(std::exp2(e) / f0 - 1), float_bound(p))
          << variant_name(t.variant) << " cell " << k;
    }
    EXPECT_LT(t.f0_deviation, 2e-6) << variant_name(t.variant);
  }
}

TEST(FvLut, TexelsRebuildTheFittedModel) {
  const FvLutOptions o = small();
  for (const FvTable& t : baked().tables)
    for (std::size_t k = 0; k < t.cells.size(); ++k) {
      const double f0 = cell_f0(k / o.size, o.size);
      for (double d : {1.0, 0.8, 0.5, 0.2, 0.05}) {
        const double want = model(t.cells[k], f0, d);
        EXPECT_NEAR(fv_from_texel(&t.texels[4 * k], d) / want, 1.0, 2e-5)
            << variant_name(t.variant) << " " << k;
        // Half precision keeps ~11 bits of coefficients up to ~40: a few percent.
        EXPECT_NEAR(fv_from_texel(&t.texels_half[4 * k], d) / want, 1.0, 0.08)
            << variant_name(t.variant) << " " << k;
      }
    }
}

TEST(FvLut, EndpointAdjustmentFollowsTheSeed) {
  // Too bright at low roughness (s < 1), too dark around 0.5-0.6 (s > 1).
  const EndpointAdjustment& a = baked().adjustment;
  EXPECT_LT(a(0.05), 0.8);
  EXPECT_GT(a(0.55), 1.0);
  EXPECT_GT(a(0.9), 1.0);
}

TEST(FvLut, FailedCellsAreReportedByCoordinates) {
  FvLutOptions o = small();
  o.size = 4;
  o.function = [](double d, double f0, double r) {
    return f0 > 0.5 && r < 0.3 ? NAN : reference::fv_schlick_smith_lh(d, f0, r);
  };
  const std::array<FvVariant, 1> v = {FvVariant::constrained};
  const FvBake b = bake_fv_luts(o, v);
  const FvTable& t = b.tables[0];
  // Rows j = 3 (f0 = 0.766) at roughness 0.125 only: cell (0, 3).
  ASSERT_EQ(t.failures.size(), 1u);
  EXPECT_EQ(t.failures[0].rfind("cell (0, 3) roughness=0.125 f0=0.765625: the reference is nan", 0),
            0u)
      << t.failures[0];
  EXPECT_EQ(t.texels[4 * 12 + 3], 0.0f);  // alpha 0: not fitted
  EXPECT_EQ(t.texels[4 * 13 + 3], 1.0f);
}

TEST(FvLut, OneCellsConstrainedFitInClosedForm) {
  // At roughness 0.5, F0 0.04 the fit follows the reference within a quarter of a stop over
  // dot(L,H) in [0.05, 1] and meets f0 at dot(L,H) = 1 exactly.
  const auto [a, b] = fit_fv_constrained(0.5, 0.04);
  for (double lh = 0.05; lh <= 1.0; lh += 0.05) {
    const double x = 1 - lh;
    const double fit = 0.04 * std::exp2(a * x * x + b * x);
    EXPECT_LT(std::abs(std::log2(fit / reference::fv_schlick_smith_lh(lh, 0.04, 0.5))), 0.25) << lh;
  }
  EXPECT_THROW((void)fit_fv_constrained(0.0, 0.04), Error);
  EXPECT_THROW((void)fit_fv_constrained(0.5, 1.0), Error);
}

TEST(FvLut, BadOptions) {
  FvLutOptions o = small();
  o.size = 0;
  std::string why;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_NE(why.find("grid size must be at least 1"), std::string::npos);
  EXPECT_THROW(bake_fv_luts(o, kAllFvVariants), Error);
  o = small();
  o.reference = "nope";
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_NE(why.find("unknown FV reference 'nope'"), std::string::npos);
}

TEST(FvLut, WrittenFilesReadBackAndMatchTheModel) {
  const FvLutOptions o = small();
  const auto dir = std::filesystem::temp_directory_path() / "shaderfit_lut_test";
  const std::vector<std::string> files = write_fv_bake(baked(), o, dir.string());
  EXPECT_EQ(files.size(), 4u * 5u + 3u);
  for (const FvTable& t : baked().tables) {
    const std::string v(variant_name(t.variant));
    test_readers::Image dds32, dds16, exr;
    std::uint32_t dxgi = 0;
    std::map<std::string, std::string> strings;
    std::string why;
    ASSERT_TRUE(
        test_readers::read_dds((dir / ("fv_" + v + "_rgba32f.dds")).string(), &dds32, &dxgi, &why))
        << why;
    ASSERT_TRUE(
        test_readers::read_dds((dir / ("fv_" + v + "_rgba16f.dds")).string(), &dds16, &dxgi, &why))
        << why;
    ASSERT_TRUE(test_readers::read_exr((dir / ("fv_" + v + ".exr")).string(), &exr, &strings, &why))
        << why;
    EXPECT_EQ(strings["shaderfit.variant"], v);
    ASSERT_EQ(dds32.width, o.size);
    ASSERT_EQ(exr.height, o.size);
    for (std::size_t k = 0; k < t.cells.size(); ++k) {
      const double f0 = cell_f0(k / o.size, o.size);
      for (double d : {1.0, 0.6, 0.1}) {
        const double want = model(t.cells[k], f0, d);
        EXPECT_NEAR(fv_from_texel(&dds32.rgba[4 * k], d) / want, 1.0, 2e-5);
        EXPECT_NEAR(fv_from_texel(&exr.rgba[4 * k], d) / want, 1.0, 2e-5);
        EXPECT_NEAR(fv_from_texel(&dds16.rgba[4 * k], d) / want, 1.0, 0.08);
      }
    }
    const HeatmapGrid maps = fv_error_maps(t);
    ASSERT_EQ(maps.panels.size(), 4u);
    for (const Heatmap& m : maps.panels) {
      EXPECT_FALSE(m.title.empty() || m.x_label.empty() || m.y_label.empty() ||
                   m.value_label.empty());
      EXPECT_TRUE(m.log_values);
      ASSERT_EQ(m.values.size(), t.cells.size());
    }
    if (t.cells[5].ok) {
      EXPECT_EQ(maps.panels[1].values[5], t.errors[5].max_log2);
    }
    const std::string errors_png = (dir / ("fv_" + v + "_errors.png")).string();
    if (gnuplot_available()) {
      // The labelled maps: a HeatmapGrid's default size.
      const std::vector<std::uint8_t> b = test_readers::slurp(errors_png);
      ASSERT_GE(b.size(), 24u);
      EXPECT_EQ(test_readers::be32(&b[16]), static_cast<std::uint32_t>(HeatmapGrid{}.width));
      EXPECT_EQ(test_readers::be32(&b[20]), static_cast<std::uint32_t>(HeatmapGrid{}.height));
    } else {
      std::size_t w = 0, h = 0;
      std::vector<std::uint8_t> rgb;
      ASSERT_TRUE(test_readers::read_png(errors_png, &w, &h, &rgb, &why)) << why;
      EXPECT_EQ(h, 128u);
    }
  }
}

}  // namespace
}  // namespace shaderfit::lut
