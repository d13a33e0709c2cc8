#include "shaderfit/reference/function.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/language.hpp"

namespace shaderfit::reference {
namespace {

ReferenceFunction acos_on_unit() {
  ReferenceFunction f;
  ReferenceText t;
  t.formula = "acos(x) * s";
  t.variables = {"x"};
  t.definitions = {"s = 0.5"};
  f.program = compile_reference(t);
  f.domain = {parse_domain_axis("x=-1:1", "domain")};
  return f;
}

TEST(ReferenceFunction, TargetAndColumns) {
  const ReferenceFunction f = acos_on_unit();
  EXPECT_NO_THROW(f.validate());
  EXPECT_EQ(f.target_at(std::vector<double>{0.5}), std::acos(0.5) * 0.5);
  const std::vector<std::string> names = {"reference", "x", "s"};
  EXPECT_EQ(f.output_indices(names), (std::vector<int>{2, 0, 1}));
  const std::vector<std::string> bad = {"y"};
  try {
    (void)f.output_indices(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "'y' is not a column of the reference (its columns: x, s, reference)");
  }
  // Another output as the target.
  ReferenceFunction g = f;
  g.target = "s";
  EXPECT_EQ(g.target_at(std::vector<double>{0.1}), 0.5);
  EXPECT_THROW((void)f.target_at(std::vector<double>{0.1, 0.2}), Error);
}

TEST(ReferenceFunction, ValidateChecksTheDomainAndTheTarget) {
  ReferenceFunction f = acos_on_unit();
  f.domain.push_back(parse_domain_axis("y=0:1", "domain"));
  try {
    f.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "the reference has 1 variables and the domain 2");
  }
  f.domain = {parse_domain_axis("t=-1:1", "domain")};
  try {
    f.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), "domain 1 is for 't', the reference's variable 1 is 'x'");
  }
  f = acos_on_unit();
  f.target = "nope";
  EXPECT_THROW(f.validate(), Error);
  EXPECT_THROW((void)f.target_at(std::vector<double>{0.1}), Error);
}

}  // namespace
}  // namespace shaderfit::reference
