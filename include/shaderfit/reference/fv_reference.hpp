// Combined Fresnel-visibility functions FV of dot(L, H) alone, Schlick-based, and the ground
// truth they approximate.
//
//   double fv = reference::fv_schlick_smith_lh(0.3, 0.04, 0.5);  // Schlick x Hable's visibility
//   double gt = reference::fv_exact_dielectric(0.3, 0.04, 0.5);  // exact Fresnel x exact Smith GGX
//
// Arguments: l_dot_h = dot(L, H) in (0, 1]; f0 = normal-incidence reflectance; roughness, with
// alpha = roughness^2 (smith_ggx.hpp). Visibility follows smith_ggx.hpp's convention
// (no 1/4 folded in): every FV here is f0 at dot(L, H) = 1.
//
// "Exact" in dot(L, H) alone: fv_schlick_smith_lh's visibility is Hable's dot(L, H) form of
// Schlick-Smith. Its exact counterpart here is Smith GGX with height-correlated masking-shadowing
// evaluated at the peak of the specular lobe, where the half vector is the normal (n = h), so
// that n.l = n.v = l.h = c:  V(c) = G2(c, c) / c^2 = 1 / (c sqrt(alpha^2 + (1 - alpha^2) c^2)).
// It is 1 at c = 1 and, unlike the Schlick forms, unbounded as c -> 0 (V ~ 1 / (alpha c)); fits
// and comparisons against it sample angles short of 90 degrees.
#pragma once

#include <cmath>

#include "shaderfit/core.hpp"
#include "shaderfit/reference/fresnel.hpp"
#include "shaderfit/reference/smith_ggx.hpp"

namespace shaderfit::reference {

// fv-schlick-smith-lh: Schlick Fresnel x Hable's dot(L, H) visibility, k = alpha / 2.
template <typename T>
SF_CPU_GPU T fv_schlick_smith_lh(T l_dot_h, T f0, T roughness) {
  return fv_lh(l_dot_h, f0, roughness * roughness);
}

// Schlick Fresnel x Schlick-Smith visibility (k = alpha / 2) at n = h.
template <typename T>
SF_CPU_GPU T fv_schlick_smith_peak(T l_dot_h, T f0, T roughness) {
  const T k = roughness * roughness * T(0.5);
  return fresnel_schlick(f0, l_dot_h) * visibility_schlick_smith(l_dot_h, l_dot_h, k);
}

// Exact height-correlated Smith GGX visibility at n = h (see above).
template <typename T>
SF_CPU_GPU T visibility_exact_peak(T l_dot_h, T roughness) {
  return smith_ggx_g2_height_correlated(l_dot_h, l_dot_h, roughness * roughness) /
         (l_dot_h * l_dot_h);
}

// The dielectric whose normal-incidence reflectance is f0 (< 1): eta = (1 + sqrt f0) / (1 - sqrt
// f0).
template <typename T>
SF_CPU_GPU T ior_from_f0(T f0) {
  using std::sqrt;
  const T s = sqrt(f0);
  return (T(1) + s) / (T(1) - s);
}

// Exact dielectric Fresnel (eta from f0) x exact visibility.
template <typename T>
SF_CPU_GPU T fv_exact_dielectric(T l_dot_h, T f0, T roughness) {
  return fresnel_dielectric(l_dot_h, ior_from_f0(f0)) * visibility_exact_peak(l_dot_h, roughness);
}

// Exact conductor Fresnel (complex IOR n + ik) x exact visibility.
template <typename T>
SF_CPU_GPU T fv_exact_conductor(T l_dot_h, T n, T k, T roughness) {
  return fresnel_conductor(l_dot_h, n, k) * visibility_exact_peak(l_dot_h, roughness);
}

}  // namespace shaderfit::reference
