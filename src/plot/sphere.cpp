#include "shaderfit/plot/sphere.hpp"

#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/smith_ggx.hpp"
#include "shaderfit/scene/scene.hpp"

namespace shaderfit {

void SphereScene::validate() const {
  if (!(roughness > 0 && roughness <= 1))
    throw Error("roughness must be in (0, 1], got " + std::to_string(roughness),
                {"SphereScene::roughness"});
  if (!(f0 > 0 && f0 < 1))
    throw Error("F0 must be in (0, 1), got " + std::to_string(f0), {"SphereScene::f0"});
  const double len2 = light[0] * light[0] + light[1] * light[1] + light[2] * light[2];
  if (!(len2 > 0) || !std::isfinite(len2))
    throw Error("the light direction must be a non-zero vector", {"SphereScene::light"});
  if (size < 8) throw Error("the image needs at least 8 pixels per side", {"SphereScene::size"});
  if (size > 4096) throw Error("the image has at most 4096 pixels per side", {"SphereScene::size"});
}

SphereImages render_sphere(const SphereScene& scene, const std::function<double(double)>& fv) {
  scene.validate();
  SceneSpec spec;
  spec.kind = SceneKind::Sphere;
  spec.term = ShadingTerm::FV;
  spec.size = scene.size;
  spec.materials = {{scene.roughness, scene.f0}};
  // Irradiance 4: the pixels hold (n.l) D F V, the radiance with the 1/4 of Cook-Torrance folded
  // out (reference/smith_ggx.hpp), as the images always showed it.
  spec.lobe = LobeLighting{scene.light, 4.0};
  const SceneSamples s = render_scene(spec);
  const std::span<const double> nl = s.column("n_dot_l"), nv = s.column("n_dot_v"),
                                lh = s.column("l_dot_h");
  const double k = scene.roughness * scene.roughness / 2;
  std::vector<double> reference(s.samples()), approximation(s.samples());
  for (std::size_t i = 0; i < s.samples(); ++i) {
    reference[i] = reference::fresnel_schlick(scene.f0, lh[i]) *
                   reference::visibility_schlick_smith(nl[i], nv[i], k);
    approximation[i] = fv(lh[i]);
  }
  // The scene's radiance, base plus coefficient times term per sample, in one channel (the
  // highlights are white) and with row 0 at the bottom; unlike shade(), a term that is not finite
  // leaves its pixel NaN.
  SphereImages im;
  im.size = scene.size;
  const auto n = static_cast<std::size_t>(scene.size);
  im.reference.resize(n * n);
  for (std::size_t row = 0; row < n; ++row)
    for (std::size_t col = 0; col < n; ++col)
      im.reference[row * n + col] = s.base[3 * ((n - 1 - row) * n + col)];
  im.approximation = im.reference;
  for (std::size_t i = 0; i < s.samples(); ++i) {
    const std::size_t row = n - 1 - s.pixel[i] / n, col = s.pixel[i] % n;
    im.reference[row * n + col] += s.coefficient[i] * reference[i];
    im.approximation[row * n + col] += s.coefficient[i] * approximation[i];
  }
  return im;
}

}  // namespace shaderfit
