#include "shaderfit/plot/sphere.hpp"

#include <cmath>

#include "shaderfit/core/error.hpp"
#include "shaderfit/fit/linear.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace shaderfit {

namespace {

void check(const SphereScene& s) {
  if (!(s.roughness > 0 && s.roughness <= 1))
    throw Error("roughness must be in (0, 1], got " + std::to_string(s.roughness),
                {"SphereScene::roughness"});
  if (!(s.f0 > 0 && s.f0 < 1))
    throw Error("F0 must be in (0, 1), got " + std::to_string(s.f0), {"SphereScene::f0"});
  const double len2 = s.light[0] * s.light[0] + s.light[1] * s.light[1] + s.light[2] * s.light[2];
  if (!(len2 > 0) || !std::isfinite(len2))
    throw Error("the light direction must be a non-zero vector", {"SphereScene::light"});
  if (s.size < 8) throw Error("the image needs at least 8 pixels per side", {"SphereScene::size"});
}

}  // namespace

SphereImages render_sphere(const SphereScene& scene, const std::function<double(double)>& fv) {
  check(scene);
  const double alpha = scene.roughness * scene.roughness;
  const double k = alpha / 2;
  const double len = std::sqrt(scene.light[0] * scene.light[0] + scene.light[1] * scene.light[1] +
                               scene.light[2] * scene.light[2]);
  const double l[3] = {scene.light[0] / len, scene.light[1] / len, scene.light[2] / len};
  SphereImages im;
  im.size = scene.size;
  const std::size_t n = static_cast<std::size_t>(scene.size) * static_cast<std::size_t>(scene.size);
  im.reference.assign(n, NAN);
  im.approximation.assign(n, NAN);
  for (int py = 0; py < scene.size; ++py) {
    for (int px = 0; px < scene.size; ++px) {
      const double x = (px + 0.5) / scene.size * 2 - 1, y = (py + 0.5) / scene.size * 2 - 1;
      const double r2 = x * x + y * y;
      if (r2 >= 1) continue;
      const double nrm[3] = {x, y, std::sqrt(1 - r2)};
      const double v[3] = {0, 0, 1};
      double h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
      const double hl = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
      for (double& c : h) c /= hl;
      const double nl = nrm[0] * l[0] + nrm[1] * l[1] + nrm[2] * l[2];
      const double nv = nrm[2];
      const double nh = nrm[0] * h[0] + nrm[1] * h[1] + nrm[2] * h[2];
      const double lh = l[0] * h[0] + l[1] * h[1] + l[2] * h[2];
      const std::size_t i = static_cast<std::size_t>(py) * static_cast<std::size_t>(scene.size) +
                            static_cast<std::size_t>(px);
      if (nl <= 0) {
        im.reference[i] = im.approximation[i] = 0;
        continue;
      }
      const double d = reference::ggx_distribution(nh, alpha);
      im.reference[i] = d * reference::fresnel_schlick(scene.f0, lh) *
                        reference::visibility_schlick_smith(nl, nv, k) * nl;
      im.approximation[i] = d * fv(lh) * nl;
    }
  }
  return im;
}

std::array<double, 2> fit_fv_constrained(double roughness, double f0) {
  SphereScene probe;
  probe.roughness = roughness;
  probe.f0 = f0;
  check(probe);
  const double alpha = roughness * roughness;
  constexpr int kSamples = 256;
  std::vector<double> x2(kSamples), x1(kSamples), y(kSamples);
  for (int s = 0; s < kSamples; ++s) {
    const double x = (s + 0.5) / kSamples;
    x2[s] = x * x;
    x1[s] = x;
    y[s] = std::log2(reference::fv_lh(1 - x, f0, alpha) / f0);
  }
  const double* cols[] = {x2.data(), x1.data()};
  const std::vector<double> c = solve_least_squares(cols, y);
  return {c[0], c[1]};
}

}  // namespace shaderfit
