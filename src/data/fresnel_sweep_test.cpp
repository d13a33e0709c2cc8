#include "shaderfit/data/fresnel_sweep.hpp"

#include <gtest/gtest.h>

#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit {
namespace {

TEST(DataFresnelSweep, MaterialsByNameAndIor) {
  EXPECT_EQ(parse_material("aluminium").k, 7.617691);
  Material glass = parse_material("1.5");
  EXPECT_EQ(glass.name, "ior1.5");
  EXPECT_EQ(glass.k, 0);
  Material metal = parse_material("0.3+3i");
  EXPECT_EQ(metal.name, "metal 0.3+3i");
  EXPECT_EQ(parse_material("metal 1.84+3.73i").n, 1.84);
  EXPECT_EQ(seed_materials().size(), 8u);
  for (const char* bad : {"unobtainium", "0.3+3", "-1.5", "1.5+-2i", ""}) {
    EXPECT_THROW(parse_material(bad), Error) << bad;
  }
}

TEST(DataFresnelSweep, ColumnsAndEndpoints) {
  Dataset d = make_fresnel_sweep({parse_material("1.5"), parse_material("aluminium")}, 91);
  ASSERT_EQ(d.rows(), 182u);
  const auto& deg = d.numeric("theta_deg").values;
  const auto& r = d.numeric("R").values;
  const auto& r0 = d.numeric("r0").values;
  EXPECT_EQ(deg[0], 0.0);
  EXPECT_EQ(deg[90], 90.0);
  EXPECT_NEAR(r[0], 0.04, 1e-12);
  EXPECT_NEAR(r[0], r0[0], 1e-12);
  EXPECT_NEAR(r[90], 1.0, 1e-12);
  EXPECT_NEAR(r[91], reference::r0_from_complex_ior(1.37289, 7.617691), 1e-12);
  EXPECT_EQ(d.column("material").labels[91], "aluminium");
  EXPECT_THROW(make_fresnel_sweep({parse_material("1.5")}, 1), Error);
  EXPECT_THROW(make_fresnel_sweep({}, 10), Error);
}

}  // namespace
}  // namespace shaderfit
