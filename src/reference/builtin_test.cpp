#include "shaderfit/reference/builtin.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit::reference {
namespace {

TEST(BuiltinRegistry, EachNameOnceWithItsArguments) {
  std::set<std::string_view> names;
  for (const BuiltinFunction& f : builtin_functions()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_FALSE(f.arguments.empty()) << f.name;
    EXPECT_NE(f.lists, 0u) << f.name;
    EXPECT_LT(f.domain.lo, f.domain.hi) << f.name;
    if (!f.symbols.empty()) {
      EXPECT_EQ(f.symbols.size(), f.arguments.size()) << f.name;
    }
  }
}

TEST(BuiltinRegistry, ListsAndLookups) {
  const BuiltinFunction* fit = find_builtin("fresnel-conductor", FitReference);
  const BuiltinFunction* target = find_builtin("fresnel-conductor", RationalTarget);
  ASSERT_NE(fit, nullptr);
  EXPECT_EQ(fit, target);  // one entry, offered by both lists
  EXPECT_EQ(fit->arguments[1], "ior_n");
  EXPECT_EQ(fit->symbol_names()[1], "eta");
  EXPECT_EQ(find_builtin("fv-exact", RationalTarget), nullptr);
  EXPECT_EQ(find_builtin("exp", FitReference), nullptr);
  EXPECT_NE(find_builtin("exp", RationalTarget), nullptr);
}

TEST(BuiltinRegistry, EvaluatesTheReferenceTemplates) {
  const double conductor[] = {0.5, 0.3, 3.0};
  EXPECT_EQ(evaluate_builtin(*find_builtin("fresnel-conductor", FitReference), conductor),
            fresnel_conductor(0.5, 0.3, 3.0));
  const double schlick[] = {0.25, 0.04};  // the variable first, then r0
  EXPECT_EQ(evaluate_builtin(*find_builtin("fresnel-schlick", FitReference), schlick),
            fresnel_schlick(0.04, 0.25));
  const double f0[] = {1.0, 0.04};
  EXPECT_NEAR(evaluate_builtin(*find_builtin("fresnel-dielectric-f0", RationalTarget), f0), 0.04,
              1e-15);
  // Smith G1 is the analytic expression (no guard at v <= 0).
  const double g1[] = {-0.0, 0.5};
  EXPECT_EQ(evaluate_builtin(*find_builtin("smith-ggx-g1", RationalTarget), g1), -0.0);
}

}  // namespace
}  // namespace shaderfit::reference
