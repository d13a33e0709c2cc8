#include "shaderfit/reference/domain.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "shaderfit/core/error.hpp"

namespace shaderfit::reference {
namespace {

std::string message_of(const std::string& text) {
  try {
    (void)parse_domain_axis(text, "domain");
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "domain");
    return e.message();
  }
  ADD_FAILURE() << text << " parsed";
  return "";
}

TEST(DomainAxis, ParsesTheShapes) {
  const DomainAxis x = parse_domain_axis("x=-1:1", "domain");
  EXPECT_EQ(x.name, "x");
  EXPECT_EQ(x.lo, -1.0);
  EXPECT_EQ(x.hi, 1.0);
  EXPECT_EQ(x.count, 0u);  // the sample design chooses
  EXPECT_EQ(x.width(), 2.0);
  EXPECT_TRUE(x.contains(1.0));
  EXPECT_FALSE(x.contains(1.5));
  const DomainAxis t = parse_domain_axis(" theta = 0 : pi/2 : 90 ", "domain");
  EXPECT_EQ(t.name, "theta");
  EXPECT_EQ(t.hi, std::numbers::pi / 2);
  EXPECT_EQ(t.count, 90u);
  EXPECT_EQ(t.spacing, Spacing::Midpoints);
  const DomainAxis u = parse_domain_axis("u=0:1:33:endpoints", "domain");
  EXPECT_EQ(u.spacing, Spacing::Endpoints);
  EXPECT_EQ(parse_domain_axis("u=0:1:3:midpoints", "domain").spacing, Spacing::Midpoints);
  EXPECT_EQ(parse_domain_axis("a=85*pi/180:acos(-1)", "domain").lo, 85 * std::numbers::pi / 180);
}

TEST(DomainAxis, GridPoints) {
  const DomainAxis m = parse_domain_axis("x=0:1:4", "domain");
  EXPECT_EQ(m.at(0), 0.125);
  EXPECT_EQ(m.at(3), 0.875);
  const DomainAxis e = parse_domain_axis("x=0.1:0.7:7:endpoints", "domain");
  EXPECT_EQ(e.at(0), 0.1);
  EXPECT_EQ(e.at(6), 0.7);  // the end itself, whatever the rounding of lo + (hi - lo)
  EXPECT_NEAR(e.at(3), 0.4, 1e-16);
  for (std::size_t i = 1; i < 7; ++i) EXPECT_LT(e.at(i - 1), e.at(i));
  const DomainAxis one = parse_domain_axis("x=2:4:1:endpoints", "domain");
  EXPECT_EQ(one.at(0), 3.0);
  const DomainAxis wide = parse_domain_axis("x=-1e307:1e307:3:endpoints", "domain");
  EXPECT_EQ(wide.at(1), 0.0);
}

TEST(DomainAxis, BadInputsSayWhat) {
  EXPECT_EQ(message_of("x=1:1"), "the domain of 'x' is empty: lo = hi = 1; lo must be below hi");
  EXPECT_EQ(message_of("x=1:-1"),
            "the domain of 'x' is reversed: lo 1 is above hi -1; write x=-1:1");
  EXPECT_EQ(message_of("x=0:1/0"),
            "the upper bound of 'x', '1/0', is not a finite number: '1/0' is not a finite number "
            "(inf)");
  EXPECT_EQ(message_of("x=0:y"),
            "the upper bound of 'x', 'y', is not a finite number: a constant cannot name a "
            "variable ('y'); pi is the one named constant");
  EXPECT_EQ(message_of("x=:1"), "the lower bound of 'x' is missing");
  EXPECT_EQ(message_of("x=-1e308:1e308"), "the domain of 'x' is too wide for a double");
  EXPECT_EQ(message_of("x 0:1"),
            "expected 'name=lo:hi[:count[:midpoints|endpoints]]', got 'x 0:1'");
  EXPECT_EQ(message_of("x=0"), "expected 'name=lo:hi[:count[:midpoints|endpoints]]', got 'x=0'");
  EXPECT_EQ(message_of("x=0:1:2:3:4"),
            "expected 'name=lo:hi[:count[:midpoints|endpoints]]', got 'x=0:1:2:3:4'");
  EXPECT_EQ(message_of("2x=0:1"),
            "the domain's variable '2x' is not a name (letters, digits and '_')");
  EXPECT_EQ(message_of("x=0:1:0"), "the sample count of 'x' must be at least 1, got 0");
  EXPECT_EQ(message_of("x=0:1:2.5"), "the sample count of 'x', '2.5', is not a whole number");
  EXPECT_EQ(message_of("x=0:1:-3"), "the sample count of 'x', '-3', is not a whole number");
  EXPECT_EQ(message_of("x=0:1:endpoints"),
            "the sample count of 'x', 'endpoints', is not a whole number");
  EXPECT_EQ(message_of("x=0:1:5:edges"), "unknown spacing 'edges' (midpoints, endpoints)");
}

}  // namespace
}  // namespace shaderfit::reference
