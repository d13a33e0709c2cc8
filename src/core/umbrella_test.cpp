// The umbrella header compiles on its own and exposes the main entry points.
#include "shaderfit/shaderfit.hpp"

#include <gtest/gtest.h>

TEST(Umbrella, SeedFormulaEndToEnd) {
  shaderfit::Rng rng(1);
  shaderfit::Dataset d = shaderfit::make_fresnel_seed_dataset(rng);
  shaderfit::Expression e = shaderfit::parse_formula_on("r0 + (x - r0) * x^4", d);
  std::vector<double> p = shaderfit::evaluate_on(e, d);
  shaderfit::ErrorMetrics m = shaderfit::error_metrics(p, d.numeric("R").values);
  EXPECT_GT(m.mse, 0.0);
  EXPECT_LT(m.mse, 1e-3);
}
