#include "shaderfit/data/fresnel_seed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "shaderfit/data/csv.hpp"
#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit {
namespace {

Dataset seed_data(std::uint64_t seed, std::size_t rows = 4096, bool half = false) {
  Rng rng(seed);
  return make_fresnel_seed_dataset(rng, {rows, half});
}

TEST(DataFresnelSeed, ColumnsAndSource) {
  Dataset d = seed_data(1);
  EXPECT_EQ(d.source, "fresnel-seed");
  EXPECT_EQ(d.rows(), 4096u);
  EXPECT_EQ(d.names(), (std::vector<std::string>{"r0", "cos_theta", "x", "R", "ior_n", "ior_k",
                                                 "kind", "material"}));
  for (const char* name : {"r0", "cos_theta", "x", "R", "ior_n", "ior_k"}) {
    EXPECT_TRUE(d.column(name).numeric()) << name;
  }
  EXPECT_FALSE(d.column("kind").numeric());
  EXPECT_FALSE(d.column("material").numeric());
  EXPECT_EQ(seed_data(1, 10, true).source, "fresnel-seed-half");
}

TEST(DataFresnelSeed, ReproducibleForASeed) {
  std::string a = to_csv(seed_data(1, 500));
  EXPECT_EQ(a, to_csv(seed_data(1, 500)));
  EXPECT_NE(a, to_csv(seed_data(2, 500)));
  EXPECT_NE(a, to_csv(seed_data(1, 500, true)));
}

TEST(DataFresnelSeed, ColumnsAreConsistent) {
  for (bool half : {false, true}) {
    Dataset d = seed_data(3, 4096, half);
    const auto& r0 = d.numeric("r0").values;
    const auto& c = d.numeric("cos_theta").values;
    const auto& x = d.numeric("x").values;
    const auto& r = d.numeric("R").values;
    const auto& n = d.numeric("ior_n").values;
    const auto& k = d.numeric("ior_k").values;
    const auto& kind = d.column("kind").labels;
    const auto& material = d.column("material").labels;
    double mean_cos = 0.0;
    for (std::size_t i = 0; i < d.rows(); ++i) {
      ASSERT_GE(c[i], 0.0);
      ASSERT_LE(c[i], 1.0);
      EXPECT_EQ(x[i], 1.0 - c[i]);
      mean_cos += c[i] / static_cast<double>(d.rows());
      if (kind[i] == "metal") {
        EXPECT_GT(k[i], 0.0);
        EXPECT_EQ(material[i].rfind("metal ", 0), 0u) << material[i];
        EXPECT_EQ(r0[i], reference::r0_from_complex_ior(n[i], k[i]));
        EXPECT_EQ(r[i], reference::fresnel_conductor(c[i], n[i], k[i]));
      } else {
        ASSERT_EQ(kind[i], "dielectric");
        EXPECT_EQ(k[i], 0.0);
        if (material[i] == "ior1.5") {
          EXPECT_EQ(n[i], 1.5);
        } else {
          ASSERT_EQ(material[i], "ior1.34-1.7");
          EXPECT_GE(n[i], 1.34);
          EXPECT_LT(n[i], 1.7);
        }
        EXPECT_EQ(r0[i], reference::r0_from_ior(n[i]));
        EXPECT_EQ(r[i], reference::fresnel_dielectric(c[i], n[i]));
      }
    }
    // |cos| of theta uniform in [0, pi] has the distribution of cos of theta uniform in
    // [0, pi/2]: mean 2 / pi either way.
    EXPECT_NEAR(mean_cos, 2 / std::numbers::pi, 0.02) << half;
  }
}

TEST(DataFresnelSeed, ProportionsFollowTheSeedScheme) {
  Dataset d = seed_data(5, 100000);
  std::map<std::string, double> share;
  for (const std::string& m : d.column("material").labels) share[m] += 1e-5;
  EXPECT_NEAR(share["ior1.5"], 0.4, 0.01);
  EXPECT_NEAR(share["ior1.34-1.7"], 0.4, 0.01);
  const char* metals[] = {"metal 0.3+3i",     "metal 0.15+4i", "metal 0.3+3.35i", "metal 1.4+7i",
                          "metal 1.84+3.73i", "metal 2.1+4i",  "metal 2.9+3.1i"};
  double metal_share = 0.0;
  for (const char* m : metals) {
    EXPECT_NEAR(share[m], 0.2 / 7, 0.004) << m;
    metal_share += share[m];
  }
  EXPECT_NEAR(metal_share, 0.2, 0.01);
  EXPECT_EQ(share.size(), 9u);  // no other names
}

TEST(DataFresnelSeed, CsvRoundTripIsExact) {
  Dataset d = seed_data(9, 1000);
  Dataset back = parse_csv(to_csv(d), "seed.csv");
  ASSERT_EQ(back.names(), d.names());
  for (const Column& c : d.columns) {
    if (c.numeric()) {
      EXPECT_EQ(back.numeric(c.name).values, c.values) << c.name;
    } else {
      EXPECT_EQ(back.column(c.name).labels, c.labels) << c.name;
    }
  }
}

// Seed post 001: the formula r0 + (x - r0) x^4 has "34% less" MSE than Schlick overall, "almost
// 50%" less for metals, and "essentially match[es]" Schlick for dielectrics.
TEST(DataFresnelSeed, SeedPostClaimReproduces) {
  Dataset d = seed_data(1);
  const auto& r0 = d.numeric("r0").values;
  const auto& c = d.numeric("cos_theta").values;
  const auto& r = d.numeric("R").values;
  const auto& kind = d.column("kind").labels;
  struct Sums {
    double schlick = 0, seed = 0;
  };
  std::map<std::string, Sums> sums;
  for (std::size_t i = 0; i < d.rows(); ++i) {
    double e_schlick = reference::fresnel_schlick(r0[i], c[i]) - r[i];
    double e_seed = reference::fresnel_seed(r0[i], c[i]) - r[i];
    for (const std::string& group : {std::string("all"), kind[i]}) {
      sums[group].schlick += e_schlick * e_schlick;
      sums[group].seed += e_seed * e_seed;
    }
  }
  auto reduction = [&](const std::string& g) { return 1.0 - sums[g].seed / sums[g].schlick; };
  RecordProperty("mse_reduction_all", std::to_string(reduction("all")));
  RecordProperty("mse_reduction_metal", std::to_string(reduction("metal")));
  RecordProperty("mse_reduction_dielectric", std::to_string(reduction("dielectric")));
  EXPECT_GE(reduction("all"), 0.25);
  EXPECT_LE(reduction("all"), 0.45);
  EXPECT_GE(reduction("metal"), 0.40);
  EXPECT_LE(reduction("metal"), 0.60);
  EXPECT_NEAR(reduction("dielectric"), 0.0, 0.10);
}

TEST(DataFresnelSeed, BuiltinByName) {
  EXPECT_EQ(builtin_dataset_names(),
            (std::vector<std::string>{"fresnel-seed", "fresnel-seed-half"}));
  Rng a(4), b(4);
  auto d = make_builtin_dataset("fresnel-seed-half", a, 100);
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(to_csv(*d), to_csv(make_fresnel_seed_dataset(b, {100, true})));
  EXPECT_EQ(make_builtin_dataset("fresnel-seed", a)->rows(), 4096u);
  EXPECT_FALSE(make_builtin_dataset("fresnel", a).has_value());
  try {
    (void)builtin_dataset("x", a, 10, {"dataset"});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "unknown data set 'x' (built-in: fresnel-seed, fresnel-seed-half)");
    EXPECT_EQ(e.where().source, "dataset");
  }
}

}  // namespace
}  // namespace shaderfit
