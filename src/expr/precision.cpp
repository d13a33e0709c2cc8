#include "shaderfit/expr/precision.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "shaderfit/core/error.hpp"

namespace shaderfit {

std::optional<Precision> precision_from_name(std::string_view name) {
  if (name == "double" || name == "float64") return Precision::Double;
  if (name == "float" || name == "float32" || name == "single") return Precision::Float;
  if (name == "half" || name == "float16") return Precision::Half;
  return std::nullopt;
}

std::string_view precision_name(Precision p) {
  switch (p) {
    case Precision::Double: return "double";
    case Precision::Float: return "float";
    case Precision::Half: return "half";
  }
  return "double";
}

Precision parse_precision(std::string_view name, const SourceLocation& where) {
  if (const auto p = precision_from_name(name)) return *p;
  throw Error("unknown precision '" + std::string(name) + "' (known: double, float, half)", where);
}

namespace {

// The exponent of the binary16 spacing at a = |v| (finite): 2^(e - 11) for a in [2^(e-1), 2^e),
// never below the subnormal spacing 2^-24.
int half_ulp_exponent(double a) {
  int e = 0;
  (void)std::frexp(a, &e);
  return std::max(e - 11, -24);
}

}  // namespace

double round_to_half(double v) {
  if (!std::isfinite(v)) return v;
  const double a = std::abs(v);
  // 65520 is halfway between 65504 and 2^16, which rounds to even: infinity.
  if (a >= 65520.0) return std::copysign(std::numeric_limits<double>::infinity(), v);
  double r = 0;
  if (a < 0x1p-14) {
    // Subnormal halves are the multiples of 2^-24: adding 1.5 * 2^28 leaves 24 fraction bits
    // below 2^-24 to round away, ties to even, and subtracting it again is exact.
    constexpr double kMagic = 0x1.8p28;
    volatile double t = a + kMagic;  // volatile: the sum must be rounded, not folded away
    r = t - kMagic;
  } else {
    // Normal: keep 10 of the 52 fraction bits, rounding the 42 dropped ones to nearest, ties to
    // even; a carry into the exponent is the right result.
    constexpr int kDrop = 52 - 10;
    auto bits = std::bit_cast<std::uint64_t>(a);
    bits += (std::uint64_t{1} << (kDrop - 1)) - 1 + ((bits >> kDrop) & 1u);
    bits &= ~((std::uint64_t{1} << kDrop) - 1);
    r = std::bit_cast<double>(bits);
  }
  return std::copysign(r, v);
}

double half_ulp(double v) {
  const double a = std::abs(v);
  if (!(a <= kHalfMax)) return std::numeric_limits<double>::infinity();
  return std::ldexp(1.0, half_ulp_exponent(a));
}

}  // namespace shaderfit
