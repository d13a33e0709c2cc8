#include "shaderfit/data/sampling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <numbers>
#include <set>
#include <string>
#include <vector>

namespace shaderfit {
namespace {

using reference::DomainAxis;

// Runs `f`, which must throw Error with this message at this location.
void expect_error(const std::function<void()>& f, const std::string& message,
                  const std::string& source) {
  try {
    f();
    ADD_FAILURE() << "no error; expected: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), message);
    EXPECT_EQ(e.where().source, source) << message;
  }
}

DomainAxis axis(const std::string& name, double lo, double hi, std::size_t count = 0) {
  DomainAxis a;
  a.name = name;
  a.lo = lo;
  a.hi = hi;
  a.count = count;
  return a;
}

// The rows of a design, each as its coordinates' bit patterns.
std::set<std::vector<std::uint64_t>> row_set(const SampleColumns& s) {
  std::set<std::vector<std::uint64_t>> rows;
  for (std::size_t r = 0; r < s[0].size(); ++r) {
    std::vector<std::uint64_t> row;
    for (const auto& c : s) row.push_back(std::bit_cast<std::uint64_t>(c[r]));
    rows.insert(row);
  }
  return rows;
}

TEST(SamplingSobol, FirstEightPointsOfThreeDimensions) {
  // scipy.stats.qmc.Sobol(d=3, scramble=False).random(8)
  const std::vector<std::vector<double>> expected = {{0, 0, 0},
                                                     {0.5, 0.5, 0.5},
                                                     {0.75, 0.25, 0.25},
                                                     {0.25, 0.75, 0.75},
                                                     {0.375, 0.375, 0.625},
                                                     {0.875, 0.875, 0.125},
                                                     {0.625, 0.125, 0.875},
                                                     {0.125, 0.625, 0.375}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(sobol_point(3, i), expected[i]) << "point " << i;
  }
}

TEST(SamplingSobol, LaterPointsOfEightDimensions) {
  // scipy.stats.qmc.Sobol(d=8, scramble=False, bits=32): points 100, 1000 and 4096, which use
  // every dimension's polynomial recurrence beyond its initial direction numbers.
  EXPECT_EQ(sobol_point(8, 100), (std::vector<double>{0.4140625, 0.2578125, 0.7734375, 0.7265625,
                                                      0.8828125, 0.7421875, 0.0234375, 0.4765625}));
  EXPECT_EQ(sobol_point(8, 1000),
            (std::vector<double>{0.2197265625, 0.0966796875, 0.5185546875, 0.6767578125,
                                 0.2802734375, 0.9072265625, 0.0458984375, 0.8994140625}));
  EXPECT_EQ(
      sobol_point(8, 4096),
      (std::vector<double>{0.0003662109375, 0.4705810546875, 0.8358154296875, 0.6204833984375,
                           0.1649169921875, 0.5428466796875, 0.7086181640625, 0.8367919921875}));
  // A prefix of the dimensions is the lower-dimensional sequence.
  std::vector<double> p8 = sobol_point(8, 12345);
  EXPECT_EQ(sobol_point(3, 12345), std::vector<double>(p8.begin(), p8.begin() + 3));
}

TEST(SamplingSobol, FirstPowerOfTwoPointsAreStratified) {
  // The first 2^k points put one point in each interval [j/2^k, (j+1)/2^k) of every dimension.
  for (std::size_t d = 1; d <= 8; ++d) {
    for (std::size_t j = 0; j < d; ++j) {
      std::set<int> cells;
      for (std::uint64_t i = 0; i < 256; ++i)
        cells.insert(static_cast<int>(sobol_point(d, i)[j] * 256));
      EXPECT_EQ(cells.size(), 256u) << "dimension " << j << " of " << d;
    }
  }
}

TEST(SamplingSobol, Errors) {
  expect_error([] { (void)sobol_point(0, 1); }, "Sobol points have 1 to 8 dimensions, not 0",
               "sobol_point");
  expect_error([] { (void)sobol_point(9, 1); }, "Sobol points have 1 to 8 dimensions, not 9",
               "sobol_point");
  expect_error([] { (void)sobol_point(2, std::uint64_t{1} << 32); },
               "Sobol point 4294967296 is beyond the 2^32 points of 32 bits", "sobol_point");
}

TEST(SamplingDesign, DefaultCounts) {
  EXPECT_EQ(default_sample_count(1), 10'001u);
  EXPECT_EQ(default_sample_count(2), 4'096u);
  for (std::size_t d = 3; d <= 6; ++d) EXPECT_EQ(default_sample_count(d), 8'192u);
}

TEST(SamplingDesign, OneDimensionIsAnEvenGridWithBothEnds) {
  const std::vector<DomainAxis> box = {axis("x", -1, 1)};
  SampleColumns s = sample_domain(box, 0);
  ASSERT_EQ(s.size(), 1u);
  const std::vector<double>& x = s[0];
  ASSERT_EQ(x.size(), 10'001u);
  EXPECT_EQ(x.front(), -1.0);
  EXPECT_EQ(x.back(), 1.0);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(x[5000]), std::bit_cast<std::uint64_t>(0.0));
  for (std::size_t i = 1; i < x.size(); ++i) {
    ASSERT_LT(x[i - 1], x[i]);
    ASSERT_NEAR(x[i] - x[i - 1], 2e-4, 1e-15);
  }
}

TEST(SamplingDesign, OneDimensionMirrorsExactlyAboutZero) {
  for (double hi : {1.0, 0.1, std::numbers::pi / 2, 3.0, 1e-3, 7.25}) {
    for (std::size_t n : {2, 3, 4, 5, 10, 11, 100, 101, 1000, 1001, 10'001}) {
      const std::vector<DomainAxis> box = {axis("x", -hi, hi)};
      const std::vector<double> x = sample_domain(box, n)[0];
      ASSERT_EQ(x.size(), n);
      EXPECT_EQ(x.front(), -hi);
      EXPECT_EQ(x.back(), hi);
      for (std::size_t i = 0; i < n; ++i) {
        if (2 * i + 1 == n) continue;  // the middle point: +0, checked below
        ASSERT_EQ(std::bit_cast<std::uint64_t>(x[n - 1 - i]), std::bit_cast<std::uint64_t>(-x[i]))
            << "hi " << hi << ", n " << n << ", i " << i;
      }
      if (n % 2 == 1) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(x[n / 2]), std::bit_cast<std::uint64_t>(0.0));
      }
    }
  }
}

TEST(SamplingDesign, OneDimensionKeepsInsideTheBounds) {
  for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{
           {0, 1}, {0.1, 0.7}, {-3, 1e-9}, {1e10, 1e10 + 1}, {-std::numbers::pi, 1}}) {
    const std::vector<DomainAxis> box = {axis("x", lo, hi)};
    const std::vector<double> x = sample_domain(box, 1001)[0];
    EXPECT_EQ(x.front(), lo);
    EXPECT_EQ(x.back(), hi);
    EXPECT_TRUE(std::is_sorted(x.begin(), x.end()));
    EXPECT_GE(*std::min_element(x.begin(), x.end()), lo);
    EXPECT_LE(*std::max_element(x.begin(), x.end()), hi);
  }
}

TEST(SamplingDesign, DenserGridHoldsTheSamples) {
  for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{
           {-1, 1}, {0, std::numbers::pi / 2}, {0.1, 0.7}, {-2.5, 2.5}}) {
    const std::vector<DomainAxis> box = {axis("x", lo, hi)};
    for (std::size_t n : {2, 11, 10'001}) {
      const std::vector<double> x = sample_domain(box, n)[0];
      for (std::size_t density : {2, 3, 10}) {
        const std::vector<double> dense = sample_domain(box, n, density)[0];
        ASSERT_EQ(dense.size(), (n - 1) * density + 1);
        for (std::size_t i = 0; i < n; ++i) {
          ASSERT_EQ(std::bit_cast<std::uint64_t>(dense[i * density]),
                    std::bit_cast<std::uint64_t>(x[i]))
              << lo << ":" << hi << ", n " << n << ", density " << density << ", i " << i;
        }
      }
    }
  }
}

TEST(SamplingDesign, TwoDimensionsHaveCornersEdgesAndInterior) {
  const std::vector<DomainAxis> box = {axis("x", -1, 2), axis("y", 0.5, 4)};
  SampleColumns s = sample_domain(box, 0);
  ASSERT_EQ(s.size(), 2u);
  const std::size_t per_edge = 64;  // 4096^(1/2)
  ASSERT_EQ(s[0].size(), 4 + 4 * per_edge + 4096);
  ASSERT_EQ(s[1].size(), s[0].size());
  const auto rows = row_set(s);
  EXPECT_EQ(rows.size(), s[0].size()) << "no two points alike";
  for (double x : {-1.0, 2.0}) {
    for (double y : {0.5, 4.0}) {
      EXPECT_TRUE(rows.contains({std::bit_cast<std::uint64_t>(x), std::bit_cast<std::uint64_t>(y)}))
          << "corner " << x << ", " << y;
    }
  }
  std::size_t x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0, inside = 0;
  for (std::size_t r = 0; r < s[0].size(); ++r) {
    const double x = s[0][r], y = s[1][r];
    ASSERT_TRUE(x >= -1 && x <= 2 && y >= 0.5 && y <= 4);
    const bool corner = (x == -1 || x == 2) && (y == 0.5 || y == 4);
    if (corner) continue;
    if (x == -1)
      ++x_lo;
    else if (x == 2)
      ++x_hi;
    else if (y == 0.5)
      ++y_lo;
    else if (y == 4)
      ++y_hi;
    else
      ++inside;
  }
  EXPECT_EQ(x_lo, per_edge);
  EXPECT_EQ(x_hi, per_edge);
  EXPECT_EQ(y_lo, per_edge);
  EXPECT_EQ(y_hi, per_edge);
  EXPECT_EQ(inside, 4096u);
  // The interior points are Sobol points 1, 2, ... scaled to the box.
  const std::vector<double> p1 = sobol_point(2, 1);
  EXPECT_TRUE(rows.contains({std::bit_cast<std::uint64_t>(-1 + 3 * p1[0]),
                             std::bit_cast<std::uint64_t>(0.5 + 3.5 * p1[1])}));
}

TEST(SamplingDesign, HigherDimensionsCoverCornersAndFaces) {
  for (std::size_t d = 2; d <= 6; ++d) {
    std::vector<DomainAxis> box;
    for (std::size_t j = 0; j < d; ++j) {
      box.push_back(axis("v" + std::to_string(j), -1.0 - j, 1.0 + 2 * j));
    }
    const std::size_t samples = 500;
    SampleColumns s = sample_domain(box, samples);
    const auto per_face = static_cast<std::size_t>(
        std::round(std::pow(500.0, static_cast<double>(d - 1) / static_cast<double>(d))));
    ASSERT_EQ(s.size(), d);
    ASSERT_EQ(s[0].size(), (std::size_t{1} << d) + 2 * d * per_face + samples) << d;
    EXPECT_EQ(row_set(s).size(), s[0].size()) << "no two points alike, d " << d;
    std::size_t corners = 0;
    std::vector<std::size_t> on_face(2 * d, 0);
    for (std::size_t r = 0; r < s[0].size(); ++r) {
      std::size_t at_bound = 0;
      for (std::size_t j = 0; j < d; ++j) {
        const double v = s[j][r];
        ASSERT_TRUE(v >= box[j].lo && v <= box[j].hi);
        if (v == box[j].lo || v == box[j].hi) ++at_bound;
      }
      if (at_bound == d) ++corners;
      if (at_bound != 1) continue;
      for (std::size_t j = 0; j < d; ++j) {
        if (s[j][r] == box[j].lo) ++on_face[2 * j];
        if (s[j][r] == box[j].hi) ++on_face[2 * j + 1];
      }
    }
    EXPECT_EQ(corners, std::size_t{1} << d);
    for (std::size_t f = 0; f < 2 * d; ++f) EXPECT_EQ(on_face[f], per_face) << d << " face " << f;
  }
}

TEST(SamplingDesign, DenserSobolDesignHoldsTheSamples) {
  for (std::size_t d : {2, 3, 6}) {
    std::vector<DomainAxis> box;
    for (std::size_t j = 0; j < d; ++j) box.push_back(axis("v" + std::to_string(j), 0, 1 + j));
    const auto base = row_set(sample_domain(box, 300));
    const SampleColumns dense = sample_domain(box, 300, 10);
    const auto rows = row_set(dense);
    EXPECT_EQ(rows.size(), dense[0].size());
    EXPECT_GE(dense[0].size(), 9 * base.size()) << d;
    for (const auto& row : base) ASSERT_TRUE(rows.contains(row)) << d;
  }
}

TEST(SamplingDesign, DeterministicAndDefaultSize) {
  const std::vector<DomainAxis> box = {axis("a", 0, 1), axis("b", 0, 1), axis("c", 0, 1)};
  SampleColumns s = sample_domain(box, 0);
  EXPECT_EQ(s, sample_domain(box, 0));
  EXPECT_EQ(s[0].size(), 8u + 6 * 406 + 8192);  // 8192^(2/3) = 406.4
}

TEST(SamplingDesign, CountedAxesGiveTheirProduct) {
  DomainAxis a = axis("a", 0, 1, 3);
  DomainAxis b = axis("b", -1, 1, 2);
  b.spacing = reference::Spacing::Endpoints;
  const std::vector<DomainAxis> box = {a, b};
  SampleColumns s = sample_domain(box, 12345, 10);  // samples and density are not used
  ASSERT_EQ(s.size(), 2u);
  ASSERT_EQ(s[0].size(), 6u);
  const std::vector<double> a_values = {a.at(0), a.at(0), a.at(1), a.at(1), a.at(2), a.at(2)};
  EXPECT_EQ(s[0], a_values);  // the first axis slowest
  EXPECT_EQ(s[1], (std::vector<double>{-1, 1, -1, 1, -1, 1}));
  EXPECT_NEAR(a.at(0), 1.0 / 6, 1e-15);  // midpoints
}

TEST(SamplingDesign, Errors) {
  expect_error([] { (void)sample_domain({}, 0); },
               "no domain: give each variable an interval (x=lo:hi)", "domain");
  std::vector<DomainAxis> seven;
  for (int j = 0; j < 7; ++j) seven.push_back(axis("v" + std::to_string(j), 0, 1));
  expect_error([&] { (void)sample_domain(seven, 0); },
               "7 variables: the sample design covers 1 to 6 (a grid of more takes a number of "
               "points for each, x=lo:hi:count)",
               "domain");
  const std::vector<DomainAxis> mixed = {axis("x", 0, 1), axis("y", 0, 1, 5)};
  expect_error([&] { (void)sample_domain(mixed, 0, 1, {"ProblemSource::domain"}); },
               "'y' has a number of points and 'x' has none: give every variable one (a grid) "
               "or none (the sample design)",
               "ProblemSource::domain");
  const std::vector<DomainAxis> one = {axis("x", 0, 1)};
  expect_error([&] { (void)sample_domain(one, 1); },
               "one variable needs at least 2 samples (both ends), not 1", "domain");
  expect_error([&] { (void)sample_domain(one, 0, 0); },
               "a design's density must be at least 1, not 0", "domain");
  expect_error([&] { (void)sample_domain(one, kMaxDesignPoints / 2, 3); },
               "the sample design would have more than 100,000,000 points", "domain");
  const std::vector<DomainAxis> big = {axis("x", 0, 1, 100'000), axis("y", 0, 1, 10'000)};
  expect_error([&] { (void)sample_domain(big, 0); },
               "the sample design would have more than 100,000,000 points", "domain");
  const std::vector<DomainAxis> two = {axis("x", 0, 1), axis("y", 0, 1)};
  expect_error([&] { (void)sample_domain(two, kMaxDesignPoints); },
               "the sample design would have more than 100,000,000 points", "domain");
}

}  // namespace
}  // namespace shaderfit
