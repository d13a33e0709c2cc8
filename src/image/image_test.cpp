#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "image/test_readers.hpp"
#include "shaderfit/core/error.hpp"
#include "shaderfit/image/dds.hpp"
#include "shaderfit/image/exr.hpp"
#include "shaderfit/image/half.hpp"
#include "shaderfit/image/png.hpp"

namespace shaderfit {
namespace {

std::string scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "shaderfit_image_test";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

std::vector<float> pattern(std::size_t w, std::size_t h) {
  std::vector<float> v(w * h * 4);
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = std::ldexp(static_cast<float>(i % 37) - 18.5f, static_cast<int>(i % 11) - 5);
  v[5] = -35.171875f;
  v[6] = 1e-7f;  // a half subnormal
  return v;
}

TEST(Half, EveryHalfRoundTripsAndMatchesTheDefinition) {
  for (std::uint32_t h = 0; h < 65536; ++h) {
    const float f = half_to_float(static_cast<std::uint16_t>(h));
    const float d = test_readers::decode_half(static_cast<std::uint16_t>(h));
    if (std::isnan(f)) {
      EXPECT_TRUE(std::isnan(d));
      EXPECT_TRUE(std::isnan(half_to_float(float_to_half(f))));
      continue;
    }
    EXPECT_EQ(f, d) << h;
    EXPECT_EQ(float_to_half(f), h) << h;
  }
}

TEST(Half, RoundsToNearestEven) {
  EXPECT_EQ(float_to_half(1.0f + 0x1p-11f), float_to_half(1.0f));                 // tie: to even
  EXPECT_EQ(float_to_half(1.0f + 0x1p-11f + 0x1p-20f), float_to_half(1.0f) + 1);  // above the tie
  EXPECT_EQ(float_to_half(65519.0f), 0x7bff);  // the largest half
  EXPECT_EQ(float_to_half(65520.0f), 0x7c00);  // rounds to infinity
  EXPECT_EQ(float_to_half(0x1p-25f), 0);       // tie with 0
  EXPECT_EQ(float_to_half(0x1.8p-25f), 1);     // smallest subnormal
}

TEST(Dds, BothFormatsReadBackWithAnIndependentParser) {
  const std::size_t w = 7, h = 5;
  const std::vector<float> v = pattern(w, h);
  for (DdsFormat f : {DdsFormat::rgba32f, DdsFormat::rgba16f}) {
    const std::string path = scratch(f == DdsFormat::rgba32f ? "t32.dds" : "t16.dds");
    write_dds(path, w, h, v, f);
    test_readers::Image img;
    std::uint32_t dxgi = 0;
    std::string why;
    ASSERT_TRUE(test_readers::read_dds(path, &img, &dxgi, &why)) << why;
    EXPECT_EQ(dxgi, f == DdsFormat::rgba32f ? 2u : 10u);
    ASSERT_EQ(img.width, w);
    ASSERT_EQ(img.height, h);
    for (std::size_t i = 0; i < v.size(); ++i)
      EXPECT_EQ(img.rgba[i], f == DdsFormat::rgba32f ? v[i] : half_to_float(float_to_half(v[i])))
          << i;
  }
}

TEST(Exr, ReadsBackWithAnIndependentParser) {
  const std::size_t w = 6, h = 9;
  const std::vector<float> v = pattern(w, h);
  const std::string path = scratch("t.exr");
  write_exr(path, w, h, v, {{"shaderfit.variant", "clamped"}});
  test_readers::Image img;
  std::map<std::string, std::string> strings;
  std::string why;
  ASSERT_TRUE(test_readers::read_exr(path, &img, &strings, &why)) << why;
  ASSERT_EQ(img.width, w);
  ASSERT_EQ(img.height, h);
  EXPECT_EQ(strings["shaderfit.variant"], "clamped");
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(img.rgba[i], v[i]) << i;
}

TEST(Png, ReadsBackWithAnIndependentParser) {
  const std::size_t w = 300, h = 250;  // more than one stored block (65535 bytes)
  std::vector<std::uint8_t> rgb(w * h * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>(i * 7 + i / 13);
  const std::string path = scratch("t.png");
  write_png(path, w, h, rgb);
  std::size_t rw = 0, rh = 0;
  std::vector<std::uint8_t> back;
  std::string why;
  ASSERT_TRUE(test_readers::read_png(path, &rw, &rh, &back, &why)) << why;
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
  EXPECT_EQ(back, rgb);
  const std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(crc32(check), 0xcbf43926u);  // the standard check value
}

TEST(Images, BadSizesAndPathsAreErrors) {
  const std::vector<float> v(16);
  EXPECT_THROW(encode_dds(0, 4, {}, DdsFormat::rgba32f), Error);
  EXPECT_THROW(encode_dds(2, 3, v, DdsFormat::rgba32f), Error);
  EXPECT_THROW(write_dds("/nonexistent/dir/x.dds", 2, 2, v, DdsFormat::rgba16f), Error);
  EXPECT_THROW(write_exr("/nonexistent/dir/x.exr", 2, 2, v), Error);
  EXPECT_THROW(encode_png(0, 0, {}), Error);
}

}  // namespace
}  // namespace shaderfit
