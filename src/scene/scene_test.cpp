#include "shaderfit/scene/scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "shaderfit/core/error.hpp"

namespace shaderfit {
namespace {

SceneSpec spec(SceneKind kind, ShadingTerm term, int size = 32) {
  SceneSpec s;
  s.kind = kind;
  s.term = term;
  s.size = size;
  return s;
}

TEST(Scene, NamesRoundTrip) {
  for (SceneKind k : {SceneKind::Sphere, SceneKind::Plane})
    EXPECT_EQ(scene_kind_from_name(scene_kind_name(k)), k);
  for (ShadingTerm t : {ShadingTerm::F, ShadingTerm::V, ShadingTerm::D, ShadingTerm::FV})
    EXPECT_EQ(shading_term_from_name(shading_term_name(t)), t);
  EXPECT_FALSE(scene_kind_from_name("teapot"));
  EXPECT_FALSE(shading_term_from_name("G"));
}

// Every quantity is a cosine in [0, 1] (or a material value), the samples light their pixels,
// and both scenes cover the grazing half vectors where Fresnel rises.
TEST(Scene, QuantitiesAreThoseOfThePicture) {
  for (SceneKind k : {SceneKind::Sphere, SceneKind::Plane}) {
    const SceneSamples s = render_scene(spec(k, ShadingTerm::F));
    ASSERT_GT(s.samples(), 500u) << scene_kind_name(k);
    EXPECT_EQ(s.base.size(),
              3u * static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height));
    for (const char* q : {"n_dot_l", "n_dot_v", "n_dot_h", "v_dot_h", "l_dot_h"}) {
      const auto c = s.column(q);
      EXPECT_GE(*std::min_element(c.begin(), c.end()), 0.0) << q;
      EXPECT_LE(*std::max_element(c.begin(), c.end()), 1.0) << q;
    }
    const auto vh = s.column("v_dot_h");
    EXPECT_LT(*std::min_element(vh.begin(), vh.end()), 0.5) << scene_kind_name(k);
    EXPECT_GT(*std::max_element(vh.begin(), vh.end()), 0.85) << scene_kind_name(k);
    for (std::size_t i = 0; i < s.samples(); ++i) {
      ASSERT_LT(s.pixel[i], static_cast<std::uint32_t>(s.width * s.height));
      ASSERT_GE(s.coefficient[i], 0.0);
      ASSERT_NEAR(s.column("alpha")[i], s.column("roughness")[i] * s.column("roughness")[i], 1e-15);
    }
    EXPECT_THROW((void)s.column("n_dot_x"), Error);
  }
}

TEST(Scene, DefaultsAreFiveMaterialsOf96Pixels) {
  SceneSpec s;
  s.term = ShadingTerm::F;
  const SceneSamples r = render_scene(s);
  EXPECT_EQ(r.width, 5 * 96);
  EXPECT_EQ(r.height, 96);
  ASSERT_EQ(r.spec.materials.size(), 5u);
  EXPECT_DOUBLE_EQ(r.spec.materials.front().f0, 0.02);
  EXPECT_DOUBLE_EQ(r.spec.materials.back().roughness, 0.8);
}

TEST(Scene, BadSpecsNameTheField) {
  auto where = [](const SceneSpec& s) {
    try {
      (void)render_scene(s);
    } catch (const Error& e) {
      return e.where().source + ":" + std::to_string(e.where().line);
    }
    return std::string("no error");
  };
  SceneSpec s = spec(SceneKind::Sphere, ShadingTerm::F);
  s.term.reset();
  EXPECT_EQ(where(s), "SceneSpec::term:0");
  s = spec(SceneKind::Sphere, ShadingTerm::F, 8);
  EXPECT_EQ(where(s), "SceneSpec::size:0");
  s = spec(SceneKind::Sphere, ShadingTerm::F);
  s.materials = {{0.5, 0.04}, {1.5, 0.04}};
  EXPECT_EQ(where(s), "SceneSpec::materials:2");
  s.materials = {{0.5, 1.0}};
  EXPECT_EQ(where(s), "SceneSpec::materials:1");
  s = spec(SceneKind::Plane, ShadingTerm::F);
  s.exposure = 0;
  EXPECT_EQ(where(s), "SceneSpec::exposure:0");
}

TEST(Scene, LobeLightingShowsTheSpecularLobeAlone) {
  SceneSpec s = spec(SceneKind::Sphere, ShadingTerm::FV, 16);
  s.materials = {{0.5, 0.04}};
  s.lobe = LobeLighting{{0.0, 0.0, 1.0}, 4.0};  // light from the camera: n.l = n.v
  const SceneSamples r = render_scene(s);
  ASSERT_EQ(r.width, 16);
  ASSERT_EQ(r.height, 16);
  // The sphere touches the picture's edges: the corners see nothing (NaN), the centre the sphere.
  EXPECT_TRUE(std::isnan(r.base[0]));
  const std::size_t centre = 3 * (8 * 16 + 8);
  EXPECT_EQ(r.base[centre], 0.0);
  std::size_t on_sphere = 0;
  for (std::size_t p = 0; p < r.base.size(); p += 3) on_sphere += r.base[p] == 0.0;
  EXPECT_EQ(r.samples(), on_sphere);  // one light, lighting every pixel the camera sees
  const std::span<const double> nl = r.column("n_dot_l"), nv = r.column("n_dot_v");
  for (std::size_t i = 0; i < r.samples(); ++i) {
    EXPECT_DOUBLE_EQ(nl[i], nv[i]);
    // Irradiance 4 cancels the 1/4 of D F V / 4: the coefficient is D (n.l), D at n.h = n.l.
    const double alpha = 0.25, d = nl[i] * nl[i] * (alpha * alpha - 1) + 1;
    EXPECT_NEAR(r.coefficient[i], alpha * alpha / (std::numbers::pi * d * d) * nl[i], 1e-12) << i;
  }
}

TEST(Scene, BadLobeLightingNamesTheField) {
  SceneSpec s = spec(SceneKind::Plane, ShadingTerm::FV);
  s.lobe = LobeLighting{};
  EXPECT_THROW((void)render_scene(s), Error);
  s.kind = SceneKind::Sphere;
  s.lobe->direction = {0, 0, 0};
  try {
    (void)render_scene(s);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.where().source, "SceneSpec::lobe");
  }
  s.lobe = LobeLighting{};
  s.size = 8;  // lobe pictures may be as small as 8 pixels
  EXPECT_NO_THROW((void)render_scene(s));
}

TEST(Scene, DisplayTransformAndItsSlope) {
  EXPECT_DOUBLE_EQ(display_encode(0, 1), 0.0);
  EXPECT_DOUBLE_EQ(display_encode(1e6, 1), 1.0);  // the tonemap saturates, then clamps
  for (double v : {0.001, 0.01, 0.1, 0.5, 1.0, 2.0}) {
    const double h = 1e-6 * v;
    const double numeric = (display_encode(v + h, 1.5) - display_encode(v - h, 1.5)) / (2 * h);
    EXPECT_NEAR(display_slope(v, 1.5), numeric, 1e-5 * std::abs(numeric) + 1e-9) << v;
  }
}

TEST(Scene, PicturesAndFlip) {
  const SceneSamples s = render_scene(spec(SceneKind::Sphere, ShadingTerm::F));
  const std::vector<double> f(s.samples(), 0.04), g(s.samples(), 0.2);
  const SceneImages same = scene_images(s, f, f);
  EXPECT_EQ(same.flip.mean, 0.0);
  EXPECT_EQ(same.display_rmse, 0.0);
  const SceneImages other = scene_images(s, f, g);
  EXPECT_GT(other.flip.mean, 0.0);
  EXPECT_GT(other.display_max, 0.0);
  const std::vector<double> w = display_weights(s, f);
  ASSERT_EQ(w.size(), s.samples());
  EXPECT_GT(*std::max_element(w.begin(), w.end()), 0.0);
  EXPECT_THROW((void)scene_images(s, f, std::vector<double>(3, 0.0)), Error);
  std::vector<double> nan = f;
  nan[5] = std::nan("");
  EXPECT_THROW((void)shade(s, nan), Error);
}

TEST(Scene, BuiltinReferencesBindToQuantities) {
  const auto f = scene_reference("fresnel-dielectric-f0");
  ASSERT_TRUE(f);
  EXPECT_EQ(f->term, ShadingTerm::F);
  EXPECT_EQ(f->formula, "fresnel_dielectric_f0(v_dot_h, f0)");
  const auto fv = scene_reference("fv_exact");
  ASSERT_TRUE(fv);
  EXPECT_EQ(fv->term, ShadingTerm::FV);
  EXPECT_EQ(fv->formula, "fv_exact(l_dot_h, f0, roughness)");
  const auto d = scene_reference("ggx-d");
  ASSERT_TRUE(d);
  EXPECT_EQ(d->formula, "ggx_d(n_dot_h, alpha)");
  EXPECT_FALSE(scene_reference("fresnel-conductor"));  // ior_k: no scene quantity
  EXPECT_FALSE(scene_reference("acos(x)"));
}

}  // namespace
}  // namespace shaderfit
