#include "shaderfit/plot/sphere.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace shaderfit {
namespace {

TEST(Sphere, ReferenceAndApproximationOnTheSphereOnly) {
  SphereScene scene;
  scene.size = 32;
  scene.light = {0, 0, 1};  // from the camera: n = h at the centre
  const double f0 = scene.f0, alpha = scene.roughness * scene.roughness;
  const SphereImages im =
      render_sphere(scene, [&](double lh) { return reference::fresnel_schlick(f0, lh); });
  ASSERT_EQ(im.size, 32);
  ASSERT_EQ(im.reference.size(), 32u * 32u);
  EXPECT_TRUE(std::isnan(im.reference[0]));  // a corner: off the sphere
  EXPECT_TRUE(std::isnan(im.approximation[0]));
  // Near the centre (half a pixel off) n.l = n.v = n.h = l.h = 1: D(1) F(1) V(1, 1) n.l = f0 / (pi
  // alpha^2).
  const std::size_t centre = 16 * 32 + 16;
  const double peak = f0 / (std::numbers::pi * alpha * alpha);
  EXPECT_NEAR(im.reference[centre], peak, 0.1 * peak);
  // The approximation drops V, which is 1 where n.l = n.v = 1 and above 1 elsewhere.
  EXPECT_NEAR(im.approximation[centre], im.reference[centre], 0.02 * peak);
  for (std::size_t i = 0; i < im.reference.size(); ++i)
    if (!std::isnan(im.reference[i])) EXPECT_GE(im.reference[i], im.approximation[i]) << i;
}

TEST(Sphere, BadScenesNameTheField) {
  auto where = [](SphereScene s) {
    try {
      (void)render_sphere(s, [](double) { return 0.0; });
    } catch (const Error& e) {
      return e.where().source;
    }
    return std::string("no error");
  };
  SphereScene s;
  s.roughness = 0;
  EXPECT_EQ(where(s), "SphereScene::roughness");
  s = {};
  s.f0 = 1;
  EXPECT_EQ(where(s), "SphereScene::f0");
  s = {};
  s.light = {0, 0, 0};
  EXPECT_EQ(where(s), "SphereScene::light");
  s = {};
  s.size = 4;
  EXPECT_EQ(where(s), "SphereScene::size");
}

}  // namespace
}  // namespace shaderfit
