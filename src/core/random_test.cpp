#include "shaderfit/core/random.hpp"

#include <gtest/gtest.h>

namespace shaderfit {
namespace {

TEST(Rng, StateTextReadsBackToTheSameSequence) {
  Rng a(42);
  for (int i = 0; i < 1000; ++i) (void)a();
  Rng b;
  ASSERT_TRUE(rng_from_text(rng_text(a), &b));
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a(), b());
}

TEST(Rng, TextThatIsNotAStateLeavesTheGeneratorAsItWas) {
  Rng a(7), untouched(7);
  EXPECT_FALSE(rng_from_text("not a state", &a));
  EXPECT_FALSE(rng_from_text("", &a));
  EXPECT_EQ(a(), untouched());
}

}  // namespace
}  // namespace shaderfit
