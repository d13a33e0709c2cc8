#include "shaderfit/fit/fit_blocks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shaderfit/core/error.hpp"
#include "shaderfit/data/sampling.hpp"
#include "shaderfit/fit/builtin_reference.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/fv_reference.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit {
namespace {

TEST(Sampling, AxesAndCells) {
  const reference::DomainAxis t = reference::parse_domain_axis("theta=0:pi/2:4", "domain");
  EXPECT_DOUBLE_EQ(t.at(0), std::numbers::pi / 16);
  const GridAxis g = parse_grid_axis("f0=0:1:4:sqrt", "grid");
  EXPECT_DOUBLE_EQ(g.centre(1), 0.375 * 0.375);
  EXPECT_EQ(g.cell_of(0.375 * 0.375), 1);
  EXPECT_EQ(g.cell_of(1.5), -1);
  Rng rng(1);
  std::vector<GridCell> cells = sample_grid({parse_grid_axis("r=0:1:2", "g"), g}, {t}, 0, 0, rng);
  ASSERT_EQ(cells.size(), 8u);
  EXPECT_EQ(cells[5].index, (std::vector<std::size_t>{1, 1}));  // last axis fastest
  EXPECT_EQ(cells[5].label(), "r=0.75 f0=0.140625");
  EXPECT_EQ(cells[5].data.names(), (std::vector<std::string>{"r", "f0", "theta"}));
  // Derived columns by a reference program: its definitions, in order, and the reference.
  reference::ReferenceText text;
  text.formula = "erf(d) + atan2(theta, 1)";
  text.variables = {"r", "f0", "theta"};
  text.definitions = {"d = cos(theta)", "e = acos(d)"};
  const std::vector<double> ref =
      add_program_columns(cells[5].data, reference::compile_reference(text));
  const double c = std::cos(std::numbers::pi / 16);
  EXPECT_DOUBLE_EQ(cells[5].data.numeric("d").values[0], c);
  EXPECT_DOUBLE_EQ(cells[5].data.numeric("e").values[0], std::acos(c));
  ASSERT_EQ(ref.size(), 4u);
  EXPECT_DOUBLE_EQ(ref[0], std::erf(c) + std::atan2(std::numbers::pi / 16, 1.0));
}

// Without counts the domain takes data/sampling.hpp's default design, the same in every cell.
TEST(Sampling, DomainWithoutCountsTakesTheDefaultDesign) {
  const std::vector<reference::DomainAxis> x = {reference::parse_domain_axis("x=-1:1", "d")};
  Rng rng(1);
  const std::vector<GridCell> one = sample_grid({}, x, 0, 0, rng);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].data.numeric("x").values, sample_domain(x, 0)[0]);
  EXPECT_EQ(one[0].data.rows(), default_sample_count(1));
  const std::vector<GridCell> small =
      sample_grid({parse_grid_axis("r=0:1:3", "g")}, x, 101, 0, rng);
  ASSERT_EQ(small.size(), 3u);
  for (const GridCell& c : small) EXPECT_EQ(c.data.numeric("x").values, sample_domain(x, 101)[0]);
  // Random points: uniform in the box, counts not used.
  const std::vector<GridCell> random = sample_grid({}, x, 0, 50, rng);
  EXPECT_EQ(random[0].data.rows(), 50u);
  for (double v : random[0].data.numeric("x").values) EXPECT_TRUE(v >= -1 && v <= 1);
  // Axes with and without counts do not mix (sample_domain's rule), located where asked.
  const std::vector<reference::DomainAxis> mixed = {reference::parse_domain_axis("x=0:1", "d"),
                                                    reference::parse_domain_axis("y=0:1:4", "d")};
  try {
    (void)sample_grid({}, mixed, 0, 0, rng, {"FitSetup::domain"});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "FitSetup::domain");
  }
}

TEST(Sampling, Errors) {
  EXPECT_THROW(parse_grid_axis("r=0:1:0", "grid"), Error);
  EXPECT_THROW(parse_grid_axis("r=1:0:4", "grid"), Error);
  EXPECT_THROW(parse_grid_axis("r=0:1", "grid"), Error);
  EXPECT_THROW(parse_grid_axis("r=0:1:x", "grid"), Error);
  EXPECT_THROW(parse_grid_axis("r=0:1:3:sideways", "grid"), Error);
  // Found by fuzzing (fuzz/regressions/options/grid_infinite_lo): an infinite bound made cell_of
  // convert NaN to long. Bounds must be finite numbers, and so must their difference.
  EXPECT_THROW(parse_grid_axis("r=-1/0:12:6", "grid"), Error);
  EXPECT_THROW(parse_grid_axis("r=-1e308:1e308:6", "grid"), Error);
  EXPECT_THROW(parse_grid_axis("r=0:0/0:3", "grid"), Error);
  // Bounds are constants of the reference language, as a domain's are.
  EXPECT_DOUBLE_EQ(parse_grid_axis("a=0:acos(-1)/2:4", "grid").hi, std::numbers::pi / 2);
  const GridAxis wide{"w", -1e308, 1e308, 4, false};
  EXPECT_EQ(wide.cell_of(1e308), 3);
  EXPECT_EQ(wide.cell_of(-1e308), 0);
  EXPECT_EQ(wide.cell_of(0.0), 2);
  try {
    parse_grid_axis("roughness=0:1:0", "grid");
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "grid: grid size must be at least 1, got 0");
  }
}

TEST(BuiltinReference, ValuesAndConventions) {
  const reference::BuiltinFunction* r = find_builtin_reference("fresnel-exact");
  ASSERT_NE(r, nullptr);
  const double glass[] = {1.0, 1.5, 0.0};
  EXPECT_NEAR(reference::evaluate_builtin(*r, glass), 0.04, 1e-15);
  const double metal[] = {1.0, 0.3, 3.0};
  EXPECT_NEAR(reference::evaluate_builtin(*r, metal), reference::r0_from_complex_ior(0.3, 3.0),
              1e-15);
  // FV at dot(L,H) = 1 is f0 for every FV reference (the visibility is 1 there).
  for (const char* name : {"fv-schlick-smith-lh", "fv-schlick-smith", "fv-exact"}) {
    const double a[] = {1.0, 0.04, 0.3};
    EXPECT_NEAR(reference::evaluate_builtin(*find_builtin_reference(name), a), 0.04, 1e-12) << name;
  }
  // The exact visibility at n = h is 1 / (c sqrt(alpha^2 + (1 - alpha^2) c^2)).
  const double c = 0.3, alpha = 0.25;
  EXPECT_NEAR(reference::visibility_exact_peak(c, 0.5),
              1 / (c * std::sqrt(alpha * alpha + (1 - alpha * alpha) * c * c)), 1e-12);
  EXPECT_NEAR(reference::ior_from_f0(0.04), 1.5, 1e-12);
  EXPECT_EQ(find_builtin_reference("nope"), nullptr);
  EXPECT_NE(describe_builtin_references().find("fv-exact(dot_lh, f0, roughness)"),
            std::string::npos);
}

}  // namespace
}  // namespace shaderfit
