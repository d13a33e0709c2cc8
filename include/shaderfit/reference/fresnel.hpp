// Reference Fresnel reflectance: the exact equations that the fitted formulas approximate, and the
// cheap approximations they are compared with.
//
//   double r = reference::fresnel_dielectric(0.5, 1.5);         // glass, 60 degrees from normal
//   double m = reference::fresnel_conductor(0.5, 0.3, 3.0);     // a metal with IOR 0.3 + 3i
//   double s = reference::fresnel_schlick(reference::r0_from_ior(1.5), 0.5);
//
// Conventions, for every function here:
//  - cos_i is the cosine of the angle between the incident direction and the surface normal, in
//    [0, 1]. Back-facing directions are the caller's business (mirror them, or swap the media).
//  - eta = n_t / n_i, the transmitted side's index over the incident side's; eta < 1 can give total
//    internal reflection. A conductor's complex index n + ik is relative to the incident medium.
//  - Results are unpolarized (the mean of the s and p parts) unless the name ends in _s or _p.
// Header-only templates that compile for the CPU and, under nvcc, the GPU: no exceptions, no
// allocation, real arithmetic only. T is float, double, or any type with the usual operators and an
// ADL-visible sqrt.
#pragma once

#include <cmath>

#include "shaderfit/core.hpp"

namespace shaderfit::reference {

// condition ? a : b, for the branches of the reference templates: `condition` is a bool for
// float, double and jets. Number types whose comparisons may be undecided (the intervals of
// certified bounds, src/verify/interval.hpp) overload it, found by argument-dependent lookup, to
// join both values. Both operands are computed, so a double result is bit for bit the `?:` one.
template <typename C, typename T>
SF_CPU_GPU T choose(C condition, T a, T b) {
  return condition ? a : b;
}

}  // namespace shaderfit::reference

namespace shaderfit::reference_detail {

// The branches' choice (above), found with the number type's own by argument-dependent lookup.
using reference::choose;

template <typename T>
SF_CPU_GPU constexpr T sqr(T x) {
  return x * x;
}

// sqrt that treats a slightly negative argument (rounding) as zero.
template <typename T>
SF_CPU_GPU T sqrt0(T x) {
  using std::sqrt;
  return sqrt(choose(x > T(0), x, T(0)));
}

// cos of the refracted angle from Snell's law, sin_t = sin_i / eta; -1 under total internal
// reflection (sin_t >= 1).
template <typename T>
SF_CPU_GPU T refracted_cos(T cos_i, T eta) {
  T sin2_t = (T(1) - cos_i * cos_i) / (eta * eta);
  return choose(sin2_t >= T(1), T(-1), sqrt0(T(1) - sin2_t));
}

}  // namespace shaderfit::reference_detail

namespace shaderfit::reference {

// Dielectric, s-polarized (electric field perpendicular to the plane of incidence):
//   R_s = ((cos_i - eta cos_t) / (cos_i + eta cos_t))^2, and 1 under total internal reflection.
template <typename T>
SF_CPU_GPU T fresnel_dielectric_s(T cos_i, T eta) {
  T cos_t = reference_detail::refracted_cos(cos_i, eta);
  return choose(cos_t < T(0), T(1),
                reference_detail::sqr((cos_i - eta * cos_t) / (cos_i + eta * cos_t)));
}

// Dielectric, p-polarized (electric field in the plane of incidence):
//   R_p = ((eta cos_i - cos_t) / (eta cos_i + cos_t))^2, 0 at Brewster's angle tan(theta) = eta,
//   and 1 under total internal reflection.
template <typename T>
SF_CPU_GPU T fresnel_dielectric_p(T cos_i, T eta) {
  T cos_t = reference_detail::refracted_cos(cos_i, eta);
  return choose(cos_t < T(0), T(1),
                reference_detail::sqr((eta * cos_i - cos_t) / (eta * cos_i + cos_t)));
}

// Exact unpolarized dielectric reflectance R = (R_s + R_p) / 2. R(cos_i = 1) = r0_from_ior(eta),
// R(cos_i = 0) = 1.
template <typename T>
SF_CPU_GPU T fresnel_dielectric(T cos_i, T eta) {
  return T(0.5) * (fresnel_dielectric_s(cos_i, eta) + fresnel_dielectric_p(cos_i, eta));
}

// Dielectric transmittance (power), from the transmission amplitudes t_s = 2 cos_i /
// (cos_i + eta cos_t) and t_p = 2 cos_i / (eta cos_i + cos_t), each weighted by the beam-area and
// impedance factor eta cos_t / cos_i:
//   T_s = 4 eta cos_i cos_t / (cos_i + eta cos_t)^2,  T_p = 4 eta cos_i cos_t / (eta cos_i +
//   cos_t)^2
// and 0 under total internal reflection. Energy conservation makes R_s + T_s = R_p + T_p = 1; these
// are computed independently of R so that identity can be tested.
template <typename T>
SF_CPU_GPU T fresnel_dielectric_transmittance_s(T cos_i, T eta) {
  T cos_t = reference_detail::refracted_cos(cos_i, eta);
  if (cos_t < T(0)) return T(0);
  return T(4) * eta * cos_i * cos_t / reference_detail::sqr(cos_i + eta * cos_t);
}

template <typename T>
SF_CPU_GPU T fresnel_dielectric_transmittance_p(T cos_i, T eta) {
  T cos_t = reference_detail::refracted_cos(cos_i, eta);
  if (cos_t < T(0)) return T(0);
  return T(4) * eta * cos_i * cos_t / reference_detail::sqr(eta * cos_i + cos_t);
}

// Unpolarized dielectric transmittance T = (T_s + T_p) / 2.
template <typename T>
SF_CPU_GPU T fresnel_dielectric_transmittance(T cos_i, T eta) {
  return T(0.5) * (fresnel_dielectric_transmittance_s(cos_i, eta) +
                   fresnel_dielectric_transmittance_p(cos_i, eta));
}

}  // namespace shaderfit::reference

namespace shaderfit::reference_detail {

// The terms of the conductor closed form. With c = cos_i and s2 = sin_i^2, write the complex
// square root sqrt((n + ik)^2 - s2) = a + ib (the refracted "eta cos_t", with a >= 0). Then
//   a^2 + b^2 = sqrt((n^2 - k^2 - s2)^2 + 4 n^2 k^2),   a^2 = ((a^2 + b^2) + (n^2 - k^2 - s2)) / 2.
template <typename T>
struct ConductorTerms {
  T c, s2, a, a2_plus_b2;
};

template <typename T>
SF_CPU_GPU ConductorTerms<T> conductor_terms(T cos_i, T n, T k) {
  using std::sqrt;
  T s2 = T(1) - cos_i * cos_i;
  T a2_minus_b2 = n * n - k * k - s2;
  T a2_plus_b2 = sqrt(a2_minus_b2 * a2_minus_b2 + T(4) * n * n * k * k);
  T a = sqrt0(T(0.5) * (a2_plus_b2 + a2_minus_b2));
  return {cos_i, s2, a, a2_plus_b2};
}

// num / den, or 1 when den is 0 (only reachable at grazing incidence with n + ik = 1).
template <typename T>
SF_CPU_GPU T ratio_or_one(T num, T den) {
  return choose(den > T(0), num / den, T(1));
}

template <typename T>
SF_CPU_GPU T conductor_s(const ConductorTerms<T>& t) {
  T u = t.a2_plus_b2 + t.c * t.c;
  T v = T(2) * t.a * t.c;
  return ratio_or_one(u - v, u + v);
}

template <typename T>
SF_CPU_GPU T conductor_p_over_s(const ConductorTerms<T>& t) {
  T u = t.a2_plus_b2 * t.c * t.c + t.s2 * t.s2;
  T v = T(2) * t.a * t.c * t.s2;
  return ratio_or_one(u - v, u + v);
}

}  // namespace shaderfit::reference_detail

namespace shaderfit::reference {

// Conductor with complex index n + ik (k >= 0), s-polarized, in closed form (see ConductorTerms):
//   R_s = (a^2 + b^2 - 2 a c + c^2) / (a^2 + b^2 + 2 a c + c^2).
// For k = 0 this is the dielectric R_s with eta = n, total internal reflection included.
template <typename T>
SF_CPU_GPU T fresnel_conductor_s(T cos_i, T n, T k) {
  return reference_detail::conductor_s(reference_detail::conductor_terms(cos_i, n, k));
}

// Conductor, p-polarized:
//   R_p = R_s (c^2 (a^2 + b^2) - 2 a c s2 + s2^2) / (c^2 (a^2 + b^2) + 2 a c s2 + s2^2).
template <typename T>
SF_CPU_GPU T fresnel_conductor_p(T cos_i, T n, T k) {
  auto t = reference_detail::conductor_terms(cos_i, n, k);
  return reference_detail::conductor_s(t) * reference_detail::conductor_p_over_s(t);
}

// Conductor, unpolarized: (R_s + R_p) / 2. R(cos_i = 1) = r0_from_complex_ior(n, k).
template <typename T>
SF_CPU_GPU T fresnel_conductor(T cos_i, T n, T k) {
  auto t = reference_detail::conductor_terms(cos_i, n, k);
  T rs = reference_detail::conductor_s(t);
  return T(0.5) * rs * (T(1) + reference_detail::conductor_p_over_s(t));
}

// Normal-incidence reflectance of a dielectric with (relative) index n: ((n - 1) / (n + 1))^2.
template <typename T>
SF_CPU_GPU T r0_from_ior(T n) {
  return reference_detail::sqr((n - T(1)) / (n + T(1)));
}

// Normal-incidence reflectance of a conductor with index n + ik: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
template <typename T>
SF_CPU_GPU T r0_from_complex_ior(T n, T k) {
  return (reference_detail::sqr(n - T(1)) + k * k) / (reference_detail::sqr(n + T(1)) + k * k);
}

// Schlick's approximation: r0 + (1 - r0) (1 - cos)^5.
template <typename T>
SF_CPU_GPU T fresnel_schlick(T r0, T cos_i) {
  T x = T(1) - cos_i;
  T x2 = x * x;
  return r0 + (T(1) - r0) * (x2 * x2 * x);
}

// A symbolic-regression fit to exact Fresnel: r0 + (x - r0) x^4 with x = 1 - cos.
// Same endpoints as Schlick (r0 at cos = 1, 1 at cos = 0), one instruction cheaper.
template <typename T>
SF_CPU_GPU T fresnel_seed(T r0, T cos_i) {
  T x = T(1) - cos_i;
  T x2 = x * x;
  return r0 + (x - r0) * (x2 * x2);
}

// fresnel_seed with a shape parameter s: r0 + (1 - r0 - s cos) x^4 with x = 1 - cos. s = 1 gives
// fresnel_seed; s = 0 gives r0 + (1 - r0) x^4 (Schlick with exponent 4).
template <typename T>
SF_CPU_GPU T fresnel_seed_shape(T r0, T cos_i, T s) {
  T x = T(1) - cos_i;
  T x2 = x * x;
  return r0 + (T(1) - r0 - s * cos_i) * (x2 * x2);
}

}  // namespace shaderfit::reference
