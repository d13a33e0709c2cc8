#include "shaderfit/rational/rational_function.hpp"

#include <gtest/gtest.h>

#include "shaderfit/core/error.hpp"

namespace shaderfit::rational {
namespace {

TEST(RationalForm, ParsesDegreesAndRejectsTheRest) {
  EXPECT_EQ(parse_form("2/1"), (RationalForm{2, 1, Transform::identity()}));
  EXPECT_EQ(parse_form(" 5 "), (RationalForm{5, 0, Transform::identity()}));
  for (const char* bad : {"", "/1", "2/", "-1/1", "17/0", "2/1x",
                          // Found by fuzzing (fuzz/regressions/options): a degree beyond an int
                          // escaped as std::out_of_range.
                          "99999999999/1", "1/99999999999999999999"}) {
    try {
      (void)parse_form(bad);
      ADD_FAILURE() << "parsed: '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.where().source, "RationalForm") << e.what();
    }
  }
}

}  // namespace
}  // namespace shaderfit::rational
