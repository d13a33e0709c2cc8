#include "shaderfit/reference/fresnel.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace shaderfit::reference {
namespace {

constexpr double kPi = std::numbers::pi;

double cos_deg(double degrees) { return std::cos(degrees * kPi / 180.0); }

// Cosines from normal to grazing, both ends included.
std::vector<double> cosines(int steps = 90) {
  std::vector<double> c;
  for (int i = 0; i <= steps; ++i) c.push_back(std::cos(0.5 * kPi * i / steps));
  c.back() = 0.0;
  return c;
}

const std::vector<double> kEtas = {1.0001, 1.2, 1.33, 1.5, 1.7, 2.42, 4.0, 1 / 1.5, 1 / 1.33};

struct Metal {
  double n, k;
};
// The metals of seed post 001.
const std::vector<Metal> kMetals = {{0.3, 3},     {0.15, 4}, {0.3, 3.35}, {1.4, 7},
                                    {1.84, 3.73}, {2.1, 4},  {2.9, 3.1}};

// Independent check of the conductor closed form: Fresnel amplitudes with complex arithmetic,
// where N cos_t = sqrt(N^2 - sin_i^2) is the principal root (the decaying wave in the metal).
struct Polarized {
  double s, p;
};
Polarized complex_fresnel(double c, double n, double k) {
  std::complex<double> big_n(n, k);
  std::complex<double> n_cos_t = std::sqrt(big_n * big_n - (1.0 - c * c));
  std::complex<double> rs = (c - n_cos_t) / (c + n_cos_t);
  std::complex<double> rp = (big_n * big_n * c - n_cos_t) / (big_n * big_n * c + n_cos_t);
  return {std::norm(rs), std::norm(rp)};
}

TEST(ReferenceFresnel, R0OfGlassIsFourPercent) {
  EXPECT_NEAR(r0_from_ior(1.5), 0.04, 1e-15);
  EXPECT_NEAR(r0_from_complex_ior(1.5, 0.0), 0.04, 1e-15);
  // ((0.3 - 1)^2 + 9) / ((1.3)^2 + 9) = 9.49 / 10.69
  EXPECT_NEAR(r0_from_complex_ior(0.3, 3.0), 9.49 / 10.69, 1e-15);
}

TEST(ReferenceFresnel, NormalIncidenceEqualsR0) {
  for (double eta : kEtas) {
    EXPECT_NEAR(fresnel_dielectric(1.0, eta), r0_from_ior(eta), 1e-15) << eta;
    EXPECT_NEAR(fresnel_dielectric_s(1.0, eta), r0_from_ior(eta), 1e-15) << eta;
    EXPECT_NEAR(fresnel_dielectric_p(1.0, eta), r0_from_ior(eta), 1e-15) << eta;
  }
  for (const Metal& m : kMetals) {
    double r0 = (std::pow(m.n - 1, 2) + m.k * m.k) / (std::pow(m.n + 1, 2) + m.k * m.k);
    EXPECT_NEAR(fresnel_conductor(1.0, m.n, m.k), r0, 1e-14) << m.n << "+" << m.k << "i";
    EXPECT_NEAR(r0_from_complex_ior(m.n, m.k), r0, 1e-15);
  }
}

TEST(ReferenceFresnel, GrazingIncidenceIsOne) {
  for (double eta : kEtas) {
    EXPECT_DOUBLE_EQ(fresnel_dielectric(0.0, eta), 1.0) << eta;
    EXPECT_DOUBLE_EQ(fresnel_dielectric_transmittance(0.0, eta), 0.0) << eta;
  }
  for (const Metal& m : kMetals) EXPECT_DOUBLE_EQ(fresnel_conductor(0.0, m.n, m.k), 1.0);
  EXPECT_DOUBLE_EQ(fresnel_conductor(0.0, 1.0, 0.0), 1.0);  // the degenerate 0/0 case
}

TEST(ReferenceFresnel, DielectricReflectancePlusTransmittanceIsOne) {
  for (double eta : kEtas) {
    for (double c : cosines()) {
      EXPECT_NEAR(fresnel_dielectric(c, eta) + fresnel_dielectric_transmittance(c, eta), 1.0, 1e-14)
          << "eta " << eta << " cos " << c;
      EXPECT_NEAR(fresnel_dielectric_s(c, eta) + fresnel_dielectric_transmittance_s(c, eta), 1.0,
                  1e-14);
      EXPECT_NEAR(fresnel_dielectric_p(c, eta) + fresnel_dielectric_transmittance_p(c, eta), 1.0,
                  1e-14);
    }
  }
}

TEST(ReferenceFresnel, SAndPAverageToUnpolarized) {
  for (double c : cosines()) {
    for (double eta : kEtas) {
      double mean = 0.5 * (fresnel_dielectric_s(c, eta) + fresnel_dielectric_p(c, eta));
      EXPECT_NEAR(fresnel_dielectric(c, eta), mean, 1e-15);
    }
    for (const Metal& m : kMetals) {
      double mean = 0.5 * (fresnel_conductor_s(c, m.n, m.k) + fresnel_conductor_p(c, m.n, m.k));
      EXPECT_NEAR(fresnel_conductor(c, m.n, m.k), mean, 1e-15);
    }
  }
}

TEST(ReferenceFresnel, BrewsterAngleHasNoPReflection) {
  for (double eta : kEtas) {
    double brewster_cos = 1.0 / std::sqrt(1.0 + eta * eta);  // tan(theta_B) = eta
    EXPECT_NEAR(fresnel_dielectric_p(brewster_cos, eta), 0.0, 1e-15) << eta;
    EXPECT_NEAR(fresnel_conductor_p(brewster_cos, eta, 0.0), 0.0, 1e-15) << eta;
    // s-polarized light still reflects there, more than at normal incidence.
    EXPECT_GT(fresnel_dielectric_s(brewster_cos, eta), r0_from_ior(eta)) << eta;
  }
  // Glass: Brewster's angle is 56.31 degrees.
  EXPECT_NEAR(std::atan(1.5) * 180 / kPi, 56.31, 0.005);
}

TEST(ReferenceFresnel, GlassAtFortyFiveDegrees) {
  // Textbook values for n = 1.5 at 45 degrees: R_s = 9.20 %, R_p = 0.847 %.
  EXPECT_NEAR(fresnel_dielectric_s(cos_deg(45), 1.5), 0.092013, 1e-6);
  EXPECT_NEAR(fresnel_dielectric_p(cos_deg(45), 1.5), 0.008466, 1e-6);
}

TEST(ReferenceFresnel, TotalInternalReflection) {
  double eta = 1.0 / 1.5;  // glass to air: critical angle asin(1 / 1.5) = 41.81 degrees
  for (double degrees : {41.9, 50.0, 70.0, 89.0}) {
    double c = cos_deg(degrees);
    EXPECT_EQ(fresnel_dielectric(c, eta), 1.0) << degrees;
    EXPECT_EQ(fresnel_dielectric_s(c, eta), 1.0);
    EXPECT_EQ(fresnel_dielectric_p(c, eta), 1.0);
    EXPECT_EQ(fresnel_dielectric_transmittance(c, eta), 0.0);
    EXPECT_DOUBLE_EQ(fresnel_conductor(c, eta, 0.0), 1.0);
  }
  EXPECT_LT(fresnel_dielectric(cos_deg(41.7), eta), 1.0);
}

TEST(ReferenceFresnel, ConductorWithoutAbsorptionIsDielectric) {
  for (double eta : kEtas) {
    for (double c : cosines()) {
      EXPECT_NEAR(fresnel_conductor(c, eta, 0.0), fresnel_dielectric(c, eta), 1e-14)
          << "eta " << eta << " cos " << c;
      EXPECT_NEAR(fresnel_conductor_s(c, eta, 0.0), fresnel_dielectric_s(c, eta), 1e-14);
      EXPECT_NEAR(fresnel_conductor_p(c, eta, 0.0), fresnel_dielectric_p(c, eta), 1e-14);
    }
  }
}

TEST(ReferenceFresnel, ConductorMatchesComplexArithmetic) {
  std::vector<Metal> metals = kMetals;
  metals.push_back({1.5, 0.01});  // weakly absorbing
  metals.push_back({0.7, 0.5});
  for (const Metal& m : metals) {
    for (double c : cosines()) {
      Polarized ref = complex_fresnel(c, m.n, m.k);
      EXPECT_NEAR(fresnel_conductor_s(c, m.n, m.k), ref.s, 1e-13) << m.n << "+" << m.k << "i " << c;
      EXPECT_NEAR(fresnel_conductor_p(c, m.n, m.k), ref.p, 1e-13) << m.n << "+" << m.k << "i " << c;
    }
  }
}

TEST(ReferenceFresnel, TabulatedMetalsAt633nm) {
  // Optical constants at 632.8 nm from the Filmetrics refractive-index database (Sopra material
  // library): gold 0.18104 + 3.068099i, aluminium 1.37289 + 7.617691i. The expected values were
  // computed separately with complex arithmetic (Python cmath); both metals reflect roughly
  // 90-95 % of red light at normal incidence, as these do.
  EXPECT_NEAR(fresnel_conductor(1.0, 0.18104, 3.068099), 0.932998, 1e-6);
  EXPECT_NEAR(fresnel_conductor(1.0, 1.37289, 7.617691), 0.913736, 1e-6);
  double c60 = cos_deg(60);
  EXPECT_NEAR(fresnel_conductor_s(c60, 0.18104, 3.068099), 0.967170, 1e-6);
  EXPECT_NEAR(fresnel_conductor_p(c60, 0.18104, 3.068099), 0.889170, 1e-6);
  EXPECT_NEAR(fresnel_conductor(c60, 1.37289, 7.617691), 0.897705, 1e-6);
}

TEST(ReferenceFresnel, SchlickAndSeedEndpoints) {
  for (double r0 : {0.0, 0.02, 0.04, 0.5, 0.95, 1.0}) {
    EXPECT_DOUBLE_EQ(fresnel_schlick(r0, 1.0), r0);
    EXPECT_DOUBLE_EQ(fresnel_schlick(r0, 0.0), 1.0);
    EXPECT_DOUBLE_EQ(fresnel_seed(r0, 1.0), r0);
    EXPECT_DOUBLE_EQ(fresnel_seed(r0, 0.0), 1.0);
    for (double s : {-0.5, 0.0, 0.5, 1.0, 2.0}) {
      EXPECT_DOUBLE_EQ(fresnel_seed_shape(r0, 1.0, s), r0);
      EXPECT_DOUBLE_EQ(fresnel_seed_shape(r0, 0.0, s), 1.0);
    }
  }
}

TEST(ReferenceFresnel, SeedFormulas) {
  for (double r0 : {0.04, 0.6, 0.9}) {
    for (double c : cosines(20)) {
      double x = 1 - c;
      EXPECT_NEAR(fresnel_schlick(r0, c), r0 + (1 - r0) * std::pow(x, 5), 1e-15);
      EXPECT_NEAR(fresnel_seed(r0, c), r0 + (x - r0) * std::pow(x, 4), 1e-15);
      // s = 1 is the seed formula, s = 0 Schlick with exponent 4.
      EXPECT_NEAR(fresnel_seed_shape(r0, c, 1.0), fresnel_seed(r0, c), 1e-15);
      EXPECT_NEAR(fresnel_seed_shape(r0, c, 0.0), r0 + (1 - r0) * std::pow(x, 4), 1e-15);
    }
  }
}

TEST(ReferenceFresnel, FloatInstantiation) {
  for (double c : cosines(10)) {
    auto cf = static_cast<float>(c);
    EXPECT_NEAR(fresnel_dielectric(cf, 1.5f), fresnel_dielectric(c, 1.5), 1e-6);
    EXPECT_NEAR(fresnel_conductor(cf, 0.3f, 3.0f), fresnel_conductor(c, 0.3, 3.0), 1e-5);
    EXPECT_NEAR(fresnel_seed(0.04f, cf), fresnel_seed(0.04, c), 1e-6);
  }
}

}  // namespace
}  // namespace shaderfit::reference
