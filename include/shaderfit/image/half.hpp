// IEEE 754 binary16 ("half") conversions, as GPUs store RGBA16F texels.
//
//   std::uint16_t h = float_to_half(0.1f);  // rounded to nearest, ties to even
//   float f = half_to_float(h);             // exact
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace shaderfit {

// Rounds to the nearest half (ties to even), with half subnormals, overflow to infinity (from
// 65520 up), and NaN kept NaN.
inline std::uint16_t float_to_half(float f) {
  const std::uint32_t x = std::bit_cast<std::uint32_t>(f);
  const auto sign = static_cast<std::uint16_t>((x >> 16) & 0x8000u);
  const std::uint32_t mag = x & 0x7fffffffu;
  if (mag >= 0x7f800000u)  // infinity or NaN (a quiet NaN stays a NaN)
    return static_cast<std::uint16_t>(sign | 0x7c00u |
                                      (mag > 0x7f800000u ? 0x200u | ((mag >> 13) & 0x3ffu) : 0u));
  if (mag >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // rounds past 65504
  if (mag < 0x38800000u) {  // below 2^-14: a half subnormal, m * 2^-24 (exact scaling)
    const float scaled = std::bit_cast<float>(mag) * 16777216.0f;
    return static_cast<std::uint16_t>(sign | static_cast<std::uint16_t>(std::nearbyint(scaled)));
  }
  std::uint32_t r = mag - 0x38000000u;  // exponent rebiased from 127 to 15
  r = (r + 0x0fffu + ((r >> 13) & 1u)) >> 13;
  return static_cast<std::uint16_t>(sign | r);
}

inline float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t e = (h >> 10) & 0x1fu, m = h & 0x3ffu;
  if (e == 0) {
    const float v = static_cast<float>(m) * 5.9604644775390625e-8f;  // m * 2^-24
    return sign ? -v : v;
  }
  if (e == 31) return std::bit_cast<float>(sign | 0x7f800000u | (m << 13));
  return std::bit_cast<float>(sign | ((e + 112u) << 23) | (m << 13));
}

}  // namespace shaderfit
