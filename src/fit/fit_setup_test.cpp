#include "shaderfit/fit/fit_setup.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shaderfit/core/error.hpp"
#include "shaderfit/data/sampling.hpp"
#include "shaderfit/reference/builtin.hpp"

namespace shaderfit {
namespace {

// A fit of a line to `reference` over x sampled on `domain`.
FitSetup line_on(std::string reference, std::vector<std::string> domain) {
  FitSetup s;
  s.domain = std::move(domain);
  s.reference = std::move(reference);
  s.formula = "a + b*x";
  s.parameters = {"a", "b"};
  return s;
}

// The error prepare_fit throws, or a failure.
Error error_of(FitSetup s) {
  try {
    (void)prepare_fit(std::move(s));
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return Error("none");
}

TEST(FitSetup, ReferenceLanguageOnADomainWithTheDefaultDesign) {
  const PreparedFit p = prepare_fit(line_on("acos(x)", {"x=-1:1"}));
  ASSERT_EQ(p.problem.blocks.size(), 1u);
  const FitBlock& b = p.problem.blocks[0];
  const std::vector<reference::DomainAxis> axes = {reference::parse_domain_axis("x=-1:1", "d")};
  EXPECT_EQ(b.columns[0], sample_domain(axes, 0)[0]);  // 10,001 points, both ends
  ASSERT_EQ(b.target.size(), default_sample_count(1));
  for (std::size_t i = 0; i < b.target.size(); i += 997)
    EXPECT_EQ(b.target[i], std::acos(b.columns[0][i]));
  EXPECT_EQ(p.reference_description, "acos(x)");
  // --samples sizes the design.
  FitSetup small = line_on("erf(x) + atan2(x, 2)", {"x=0:3"});
  small.samples = 33;
  const PreparedFit q = prepare_fit(small);
  ASSERT_EQ(q.problem.blocks[0].target.size(), 33u);
  EXPECT_EQ(q.problem.blocks[0].target.back(), std::erf(3.0) + std::atan2(3.0, 2.0));
}

TEST(FitSetup, DefinitionsAreReferenceLanguageColumns) {
  FitSetup s = line_on("t^2", {"theta=0:pi/2:8"});
  s.definitions = {"c = cos(theta)", "x = erfc(c)", "t = hypot(x, c)"};
  const PreparedFit p = prepare_fit(s);
  const FitBlock& b = p.problem.blocks[0];
  ASSERT_EQ(b.target.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    const double theta = (static_cast<double>(i) + 0.5) * std::numbers::pi / 16;
    const double x = std::erfc(std::cos(theta));
    EXPECT_DOUBLE_EQ(b.columns[0][i], x);
    EXPECT_DOUBLE_EQ(b.target[i], std::pow(std::hypot(x, std::cos(theta)), 2));
  }
  // On data the definitions read the columns, and the formula and the reference read both.
  FitSetup d;
  Dataset data;
  data.add_numeric("u", {0.1, 0.5, 0.9, 0.3});
  data.add_text("kind", {"a", "b", "a", "b"});
  d.data = std::move(data);
  d.definitions = {"x = asin(u)"};
  d.reference = "x > 0.4 ? sqrt(u) : u";
  d.formula = "k*x";
  d.parameters = {"k"};
  const PreparedFit q = prepare_fit(d);
  EXPECT_DOUBLE_EQ(q.problem.blocks[0].columns[0][1], std::asin(0.5));
  EXPECT_DOUBLE_EQ(q.problem.blocks[0].target[1], std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(q.problem.blocks[0].target[3], 0.3);
}

TEST(FitSetup, BuiltinNamesStillReadTheirColumns) {
  FitSetup s;
  s.domain = {"cos_theta=0:1:5", "ior_n=1.2:1.8:2", "ior_k=0:2:2"};
  s.reference = "fresnel-exact";
  s.formula = "a + b*cos_theta";
  s.parameters = {"a", "b"};
  const PreparedFit p = prepare_fit(s);
  EXPECT_EQ(p.reference_description, "fresnel-exact");
  const FitBlock& b = p.problem.blocks[0];
  const Dataset& d = *p.sources[0].data;
  const reference::BuiltinFunction* f =
      reference::find_builtin("fresnel-exact", reference::FitReference);
  ASSERT_NE(f, nullptr);
  for (std::size_t i = 0; i < b.target.size(); ++i) {
    const double args[] = {d.numeric("cos_theta").values[i], d.numeric("ior_n").values[i],
                           d.numeric("ior_k").values[i]};
    EXPECT_EQ(b.target[i], reference::evaluate_builtin(*f, args)) << i;
  }
}

TEST(FitSetup, ShaderFunctionReference) {
  FitSetup s = line_on("", {"x=0:1:11:endpoints"});
  s.definitions = {"y = 1 - x"};
  s.reference_source =
      "float helper(float v) { return v * v; }\n"
      "float f(float y, float x) {\n"
      "  float r = x;\n"
      "  if (y < 0.5) r = helper(x);\n"
      "  return saturate(r);\n"
      "}\n";
  s.reference_path = "f.glsl";
  s.function = "f";
  const PreparedFit p = prepare_fit(s);
  EXPECT_EQ(p.reference_description, "f.glsl: f");
  const FitBlock& b = p.problem.blocks[0];
  ASSERT_EQ(b.target.size(), 11u);
  for (std::size_t i = 0; i < 11; ++i) {
    const double x = b.columns[0][i];
    EXPECT_DOUBLE_EQ(b.target[i], 1 - x < 0.5 ? x * x : x) << x;
  }
  // Its parameters must be columns; the shader's own errors are at the file's line and column.
  s.definitions.clear();
  Error e = error_of(s);
  EXPECT_EQ(e.where().source, "FitSetup::function");
  EXPECT_NE(e.message().find("'y'"), std::string::npos) << e.message();
  s.reference_source =
      "float f(float x) {\n  while (x < 2.0) x += 1.0;\n  return x;\n}\n";
  e = error_of(s);
  EXPECT_EQ(e.where().source, "f.glsl");
  EXPECT_EQ(e.where().line, 2);
  s.function.clear();
  EXPECT_EQ(error_of(s).where().source, "FitSetup::function");
}

TEST(FitSetup, ErrorsAreLocatedAtTheFields) {
  Error e = error_of(line_on("acoss(x)", {"x=-1:1"}));
  EXPECT_EQ(e.where().source, "FitSetup::reference");
  EXPECT_EQ(e.where().column, 1);
  EXPECT_NE(e.message().find("unknown function 'acoss'"), std::string::npos) << e.message();
  e = error_of(line_on("fv-exat", {"x=-1:1"}));
  EXPECT_NE(e.message().find("unknown reference 'fv-exat'"), std::string::npos) << e.message();
  FitSetup d = line_on("x", {"x=0:1"});
  d.definitions = {"c = cos(x)", "e = erf(q)"};
  e = error_of(d);
  EXPECT_EQ(e.where().source, "FitSetup::definitions");
  EXPECT_EQ(e.where().line, 2);
  e = error_of(line_on("x", {"x=0:1", "x=2:3"}));
  EXPECT_EQ(e.where().source, "FitSetup::domain");
  EXPECT_EQ(e.where().line, 2);
  e = error_of(line_on("x", {"x=1:-1"}));
  EXPECT_EQ(e.where().source, "FitSetup::domain");
  EXPECT_NE(e.message().find("reversed"), std::string::npos) << e.message();
  e = error_of(line_on("x + y", {"x=0:1", "y=0:1:4"}));
  EXPECT_EQ(e.where().source, "FitSetup::domain");
  FitSetup counted = line_on("x", {"x=0:1:8"});
  counted.samples = 100;
  EXPECT_EQ(error_of(counted).where().source, "FitSetup::samples");
  FitSetup two = line_on("x", {"x=0:1"});
  two.target = "x";
  EXPECT_EQ(error_of(two).where().source, "FitSetup::target");
}

TEST(FitSetup, InputsBoundTheColumnsTheFormulaReads) {
  FitSetup a = line_on("acos(x)", {"x=-1:1"});
  a.inputs = {"x"};
  EXPECT_NO_THROW(prepare_fit(a));
  a.inputs = {"y"};
  Error e = error_of(a);
  EXPECT_EQ(e.where().source, "FitSetup::inputs");
  EXPECT_NE(e.message().find("input 'y' is no column"), std::string::npos) << e.message();
  Dataset d;
  d.add_numeric("u", {0, 0.5, 1});
  d.add_numeric("v", {1, 2, 3});
  d.add_numeric("y", {0.5, 1.5, 2});
  FitSetup b;
  b.data = d;
  b.target = "y";
  b.formula = "p * u + q";
  b.parameters = {"p", "q"};
  b.inputs = {"v"};
  e = error_of(b);
  EXPECT_EQ(e.where().source, "FitSetup::inputs");
  EXPECT_NE(e.message().find("reads 'u', which is not among the inputs (v)"), std::string::npos)
      << e.message();
}

TEST(FitSetup, NonFiniteReferenceIsAnErrorOrLeftOut) {
  FitSetup a = line_on("sqrt(x)", {"x=-1:1:5"});
  Error e = error_of(a);
  EXPECT_EQ(e.where().source, "FitSetup::reference");
  EXPECT_NE(e.message().find("NaN or infinite at sampled point 1 (2 such"), std::string::npos)
      << e.message();
  a.drop_nonfinite = true;
  const PreparedFit p = prepare_fit(a);
  EXPECT_EQ(p.dropped_nonfinite, 2u);
  EXPECT_EQ(p.problem.blocks[0].target.size(), 3u);
  for (double t : p.problem.blocks[0].target) EXPECT_TRUE(std::isfinite(t));
  Dataset d;
  d.add_numeric("u", {0, 0.5, 1});
  d.add_numeric("y", {0.5, NAN, 2});
  FitSetup b;
  b.data = d;
  b.target = "y";
  b.formula = "p * u + q";
  b.parameters = {"p", "q"};
  e = error_of(b);
  EXPECT_EQ(e.where().source, "FitSetup::target");
  EXPECT_NE(e.message().find("at data row 2"), std::string::npos) << e.message();
  b.drop_nonfinite = true;
  EXPECT_EQ(prepare_fit(b).dropped_nonfinite, 1u);
}

}  // namespace
}  // namespace shaderfit
