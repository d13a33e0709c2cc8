// A sphere lit by one light with a GGX specular lobe, as the scene renders it (scene/scene.hpp,
// LobeLighting), shaded twice: with the full reference terms and with a combined
// Fresnel-visibility approximation in dot(L,H) alone: reference, approximation and difference
// images.
//
//   SphereScene scene;                 // roughness 0.5, F0 0.04, light from the upper right
//   SphereImages im = render_sphere(scene, [](double l_dot_h) { return my_fv(l_dot_h); });
//
// Reference: D(n.h) * F_schlick(l.h) * V_schlick_smith(n.l, n.v) * n.l (k = alpha / 2, alpha =
// roughness^2, the 1/4 of Cook-Torrance folded out as in reference/smith_ggx.hpp); approximation:
// D(n.h) * FV(l.h) * n.l. The view is orthographic along +z; pixels off the sphere are NaN.
#pragma once

#include <array>
#include <functional>
#include <vector>

namespace shaderfit {

struct SphereScene {
  double roughness = 0.5;  // perceptual roughness; alpha = roughness^2
  double f0 = 0.04;
  std::array<double, 3> light = {0.8, 0.45, 0.4};  // towards the light; normalised inside
  int size = 256;                                    // pixels per side

  // Throws shaderfit::Error for roughness outside (0, 1], F0 outside (0, 1), a zero light vector
  // or a size outside [8, 4096].
  void validate() const;
};

struct SphereImages {
  int size = 0;
  std::vector<double> reference, approximation;  // row-major, row 0 at the bottom
};

// Throws as SphereScene::validate.
SphereImages render_sphere(const SphereScene& scene, const std::function<double(double)>& fv);

}  // namespace shaderfit
