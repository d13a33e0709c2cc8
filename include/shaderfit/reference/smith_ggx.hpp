// Reference GGX (Trowbridge-Reitz) microfacet terms: the distribution D, Smith masking G1 and
// shadowing-masking G2, the Schlick-Smith visibility used in games, and Hable's
// approximations that depend on dot(L, H) alone.
//
//   double alpha = roughness * roughness;
//   double f = reference::ggx_distribution(n_dot_h, alpha) *
//              reference::smith_ggx_g2_height_correlated(n_dot_l, n_dot_v, alpha) /
//              (4 * n_dot_l * n_dot_v);  // times Fresnel: the Cook-Torrance specular BRDF
//
// Conventions: alpha = roughness^2 (the GGX width; alpha = 1 is the roughest). Dot products are
// cosines with the geometric normal n; l and v are the light and view directions, h the half
// vector. Terms are 0 where a cosine is <= 0. Schlick-Smith takes k directly: k = alpha / 2 here
// (after Karis's UE4 notes); Karis uses k = (roughness + 1)^2 / 8 for analytic lights.
// Header-only templates for the CPU and, under nvcc, the GPU (see fresnel.hpp).
#pragma once

#include <cmath>

#include "shaderfit/core.hpp"
#include "shaderfit/reference/fresnel.hpp"

namespace shaderfit::reference {

// GGX normal distribution: D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2), for n.h > 0.
// Normalized so that the projected microfacet area is one: integral of D(h) (n.h) dw_h = 1.
template <typename T>
SF_CPU_GPU T ggx_distribution(T n_dot_h, T alpha) {
  T a2 = alpha * alpha;
  T d = n_dot_h * n_dot_h * (a2 - T(1)) + T(1);
  return choose(n_dot_h > T(0), a2 / (T(3.14159265358979323846) * d * d), T(0));
}

}  // namespace shaderfit::reference

namespace shaderfit::reference_detail {

// sqrt(alpha^2 + (1 - alpha^2) c^2) = c sqrt(1 + alpha^2 tan^2): Smith's Lambda(c) for GGX is
// (ggx_root(c) / c - 1) / 2.
template <typename T>
SF_CPU_GPU T ggx_root(T c, T alpha) {
  using std::sqrt;
  T a2 = alpha * alpha;
  return sqrt(a2 + (T(1) - a2) * c * c);
}

}  // namespace shaderfit::reference_detail

namespace shaderfit::reference {

// Smith masking for GGX: G1(v) = 1 / (1 + Lambda(v)) = 2 (n.v) / (n.v + sqrt(alpha^2 +
// (1 - alpha^2) (n.v)^2)). 1 at normal incidence, 0 at grazing.
template <typename T>
SF_CPU_GPU T smith_ggx_g1(T n_dot_v, T alpha) {
  if (!(n_dot_v > T(0))) return T(0);
  return T(2) * n_dot_v / (n_dot_v + reference_detail::ggx_root(n_dot_v, alpha));
}

// Separable Smith shadowing-masking: G2 = G1(l) G1(v).
template <typename T>
SF_CPU_GPU T smith_ggx_g2_separable(T n_dot_l, T n_dot_v, T alpha) {
  return smith_ggx_g1(n_dot_l, alpha) * smith_ggx_g1(n_dot_v, alpha);
}

// Height-correlated Smith shadowing-masking (Heitz 2014): G2 = 1 / (1 + Lambda(l) + Lambda(v))
//   = 2 (n.l)(n.v) / ((n.v) sqrt(alpha^2 + (1 - alpha^2)(n.l)^2) + (n.l) sqrt(alpha^2 +
//     (1 - alpha^2)(n.v)^2)).
// Never below the separable form, since 1 + La + Lv <= (1 + La)(1 + Lv): knowing a point is
// visible from v makes it likely to be high, hence also visible from l, so correlating the two
// removes some of the double-counted shadowing.
template <typename T>
SF_CPU_GPU T smith_ggx_g2_height_correlated(T n_dot_l, T n_dot_v, T alpha) {
  T den = n_dot_v * reference_detail::ggx_root(n_dot_l, alpha) +
          n_dot_l * reference_detail::ggx_root(n_dot_v, alpha);
  return choose(n_dot_l > T(0), choose(n_dot_v > T(0), T(2) * n_dot_l * n_dot_v / den, T(0)), T(0));
}

// Schlick's approximation of Smith masking: G1(v) ~ (n.v) / ((n.v)(1 - k) + k).
template <typename T>
SF_CPU_GPU T smith_schlick_g1(T n_dot_v, T k) {
  if (!(n_dot_v > T(0))) return T(0);
  return n_dot_v / (n_dot_v * (T(1) - k) + k);
}

// Schlick-Smith visibility: 1 / (((n.l)(1 - k) + k) ((n.v)(1 - k) + k)), which is
// G_schlick(l) G_schlick(v) / ((n.l)(n.v)) with the cosines cancelled (visibility_lh uses
// k = alpha / 2).
// Factor convention (as in Hable's "Optimizing GGX Shaders with dot(L,H)", which this follows):
// the 1/4 of the Cook-Torrance BRDF D F G / (4 (n.l)(n.v)) is NOT folded in, so the visibility is
// 1 at n = l = v and 1/k^2 at grazing, and the BRDF is D F visibility / 4. (Hable's shaders return
// (n.l) D F visibility, i.e. 4x the usual radiance; UE4's and Filament's V include the 1/4.)
template <typename T>
SF_CPU_GPU T visibility_schlick_smith(T n_dot_l, T n_dot_v, T k) {
  return T(1) / ((n_dot_l * (T(1) - k) + k) * (n_dot_v * (T(1) - k) + k));
}

// Hable's visibility in terms of dot(L, H) alone, with k = alpha / 2:
//   V(l.h) = 1 / ((l.h)^2 (1 - k^2) + k^2).
// Same convention as visibility_schlick_smith (no 1/4 folded in), and it matches it at both
// ends: 1 at l.h = 1 (n = l = v = h) and 1/k^2 at l.h = 0 (grazing). In between it is an
// approximation: the Schlick-Smith value also depends on n.l and n.v, which this drops.
template <typename T>
SF_CPU_GPU T visibility_lh(T l_dot_h, T alpha) {
  T k = alpha * T(0.5);
  T k2 = k * k;
  return T(1) / (l_dot_h * l_dot_h * (T(1) - k2) + k2);
}

// The combined Fresnel-visibility term FV(l.h): Schlick F(l.h) with f0, times visibility_lh.
// FV(1) = f0 and FV(0) = 4 / alpha^2 (the "V90" endpoint). Same factor convention as above.
template <typename T>
SF_CPU_GPU T fv_lh(T l_dot_h, T f0, T alpha) {
  return fresnel_schlick(f0, l_dot_h) * visibility_lh(l_dot_h, alpha);
}

}  // namespace shaderfit::reference
