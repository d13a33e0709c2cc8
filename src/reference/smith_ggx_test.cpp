#include "shaderfit/reference/smith_ggx.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace shaderfit::reference {
namespace {

constexpr double kPi = std::numbers::pi;

const std::vector<double> kAlphas = {0.05, 0.1, 0.3, 0.5, 0.8, 1.0};

std::vector<double> cosines(int steps = 40) {
  std::vector<double> c;
  for (int i = 0; i <= steps; ++i) c.push_back(std::cos(0.5 * kPi * i / steps));
  c.back() = 0.0;
  return c;
}

TEST(ReferenceSmithGgx, DistributionAtTheNormal) {
  for (double alpha : kAlphas) {
    double peak = 1.0 / (kPi * alpha * alpha);  // relative tolerance: (a^2 - 1) + 1 cancels
    EXPECT_NEAR(ggx_distribution(1.0, alpha), peak, 1e-12 * peak);
    EXPECT_EQ(ggx_distribution(0.0, alpha), 0.0);
    EXPECT_EQ(ggx_distribution(-0.5, alpha), 0.0);
  }
  EXPECT_NEAR(ggx_distribution(0.3, 1.0), 1.0 / kPi, 1e-15);  // alpha = 1 is uniform
}

// The projected area of the microfacets is the macro-surface's: integral of D(h) (n.h) dw_h = 1,
// i.e. 2 pi * integral_0^1 D(mu) mu dmu with mu = n.h. Simpson's rule in mu.
TEST(ReferenceSmithGgx, DistributionIsNormalized) {
  for (double alpha : {0.1, 0.2, 0.5, 0.8, 1.0}) {
    const int n = 20000;  // even
    double h = 1.0 / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      double mu = i * h;
      double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
      sum += w * ggx_distribution(mu, alpha) * mu;
    }
    EXPECT_NEAR(2.0 * kPi * sum * h / 3.0, 1.0, 1e-6) << "alpha " << alpha;
  }
}

// The weak white furnace test ties Smith's G1 to D: for every view direction v,
//   G1(v) * integral over h of D(h) max(0, v.h) dw_h = n.v.
// Midpoint rule over mu = n.h and the azimuth phi (symmetric about phi = 0, so [0, pi] twice).
TEST(ReferenceSmithGgx, G1PassesTheWeakWhiteFurnace) {
  const int n_mu = 3000, n_phi = 600;
  for (double alpha : {0.2, 0.5, 1.0}) {
    for (double degrees : {0.0, 30.0, 60.0, 80.0}) {
      double theta = degrees * kPi / 180;
      double sin_v = std::sin(theta), cos_v = std::cos(theta);
      double integral = 0.0;
      for (int i = 0; i < n_mu; ++i) {
        double mu = (i + 0.5) / n_mu;
        double sin_h = std::sqrt(1 - mu * mu);
        double d = ggx_distribution(mu, alpha);
        double ring = 0.0;
        for (int j = 0; j < n_phi; ++j) {
          double phi = kPi * (j + 0.5) / n_phi;
          ring += std::max(0.0, sin_v * sin_h * std::cos(phi) + cos_v * mu);
        }
        integral += d * ring;
      }
      integral *= 2.0 * (kPi / n_phi) * (1.0 / n_mu);
      EXPECT_NEAR(smith_ggx_g1(cos_v, alpha) * integral, cos_v, 1e-4 * cos_v + 1e-6)
          << "alpha " << alpha << " theta " << degrees;
    }
  }
}

TEST(ReferenceSmithGgx, G1IsOneAtNormalIncidenceAndZeroAtGrazing) {
  for (double alpha : kAlphas) {
    EXPECT_DOUBLE_EQ(smith_ggx_g1(1.0, alpha), 1.0);
    EXPECT_EQ(smith_ggx_g1(0.0, alpha), 0.0);
    EXPECT_DOUBLE_EQ(smith_ggx_g2_separable(1.0, 1.0, alpha), 1.0);
    EXPECT_DOUBLE_EQ(smith_ggx_g2_height_correlated(1.0, 1.0, alpha), 1.0);
    EXPECT_EQ(smith_ggx_g2_height_correlated(0.0, 0.0, alpha), 0.0);
    // G1 falls monotonically towards grazing.
    double previous = 1.0;
    for (double c : cosines()) {
      double g = smith_ggx_g1(c, alpha);
      EXPECT_LE(g, previous + 1e-15);
      previous = g;
    }
  }
  // A smooth surface does not mask: G1 -> 1 as alpha -> 0.
  EXPECT_NEAR(smith_ggx_g1(0.2, 1e-6), 1.0, 1e-9);
}

TEST(ReferenceSmithGgx, G1MatchesLambda) {
  // G1 = 1 / (1 + Lambda), Lambda = (-1 + sqrt(1 + alpha^2 tan^2)) / 2.
  for (double alpha : kAlphas) {
    for (double c : cosines()) {
      if (c <= 0) continue;
      double tan2 = (1 - c * c) / (c * c);
      double lambda = 0.5 * (-1 + std::sqrt(1 + alpha * alpha * tan2));
      EXPECT_NEAR(smith_ggx_g1(c, alpha), 1 / (1 + lambda), 1e-13);
    }
  }
}

// 1 / (1 + La + Lv) >= 1 / ((1 + La)(1 + Lv)): the separable form double-counts shadowing, so
// the height-correlated G2 is never the smaller one (and never above min(G1(l), G1(v))).
TEST(ReferenceSmithGgx, HeightCorrelatedIsBetweenSeparableAndMinG1) {
  for (double alpha : kAlphas) {
    for (double cl : cosines(20)) {
      for (double cv : cosines(20)) {
        double correlated = smith_ggx_g2_height_correlated(cl, cv, alpha);
        double separable = smith_ggx_g2_separable(cl, cv, alpha);
        EXPECT_GE(correlated, separable - 1e-15) << alpha << " " << cl << " " << cv;
        EXPECT_LE(correlated, std::min(smith_ggx_g1(cl, alpha), smith_ggx_g1(cv, alpha)) + 1e-15);
        if (cl > 0 && cv > 0 && cl < 1 && cv < 1) {
          EXPECT_GT(correlated, separable);
        }
      }
      // With one direction at the normal the two forms agree.
      EXPECT_NEAR(smith_ggx_g2_height_correlated(1.0, cl, alpha),
                  smith_ggx_g2_separable(1.0, cl, alpha), 1e-15);
    }
  }
}

TEST(ReferenceSmithGgx, SchlickSmithVisibility) {
  for (double k : {0.01, 0.125, 0.5}) {
    EXPECT_DOUBLE_EQ(visibility_schlick_smith(1.0, 1.0, k), 1.0);
    EXPECT_DOUBLE_EQ(visibility_schlick_smith(0.0, 0.0, k), 1.0 / (k * k));
    for (double cl : cosines(10)) {
      for (double cv : cosines(10)) {
        // Visibility is G_schlick(l) G_schlick(v) / ((n.l)(n.v)), without the 1/4.
        EXPECT_NEAR(visibility_schlick_smith(cl, cv, k) * cl * cv,
                    smith_schlick_g1(cl, k) * smith_schlick_g1(cv, k), 1e-13);
      }
    }
  }
}

TEST(ReferenceSmithGgx, VisibilityLhMatchesSchlickSmithAtTheEnds) {
  for (double alpha : kAlphas) {
    double k = alpha / 2;
    EXPECT_DOUBLE_EQ(visibility_lh(1.0, alpha), 1.0);
    EXPECT_DOUBLE_EQ(visibility_lh(1.0, alpha), visibility_schlick_smith(1.0, 1.0, k));
    EXPECT_DOUBLE_EQ(visibility_lh(0.0, alpha), 1.0 / (k * k));
    EXPECT_DOUBLE_EQ(visibility_lh(0.0, alpha), visibility_schlick_smith(0.0, 0.0, k));
    for (double c : cosines(20)) {
      EXPECT_NEAR(visibility_lh(c, alpha), 1 / (c * c * (1 - k * k) + k * k), 1e-12);
    }
  }
}

TEST(ReferenceSmithGgx, CombinedFresnelVisibility) {
  for (double alpha : {0.1, 0.5, 1.0}) {
    for (double f0 : {0.02, 0.04, 0.9}) {
      EXPECT_DOUBLE_EQ(fv_lh(1.0, f0, alpha), f0);                       // FV(1) = F0
      EXPECT_NEAR(fv_lh(0.0, f0, alpha), 4.0 / (alpha * alpha), 1e-12);  // FV(0) = V90
      for (double c : cosines(10)) {
        EXPECT_DOUBLE_EQ(fv_lh(c, f0, alpha), fresnel_schlick(f0, c) * visibility_lh(c, alpha));
      }
    }
  }
}

TEST(ReferenceSmithGgx, FloatInstantiation) {
  EXPECT_NEAR(ggx_distribution(0.9f, 0.3f), ggx_distribution(0.9, 0.3), 1e-5);
  EXPECT_NEAR(smith_ggx_g2_height_correlated(0.4f, 0.7f, 0.3f),
              smith_ggx_g2_height_correlated(0.4, 0.7, 0.3), 1e-6);
  EXPECT_NEAR(fv_lh(0.5f, 0.04f, 0.3f), fv_lh(0.5, 0.04, 0.3), 1e-5);
}

}  // namespace
}  // namespace shaderfit::reference
