// Truncated Taylor series ("jets") for exact derivatives of any order up to kMaxJetOrder.
//
// A Jet holds the Taylor coefficients c_0..c_{n-1} of a function at a point: c_k = f^(k)(a) / k!.
// Arithmetic and the elementary functions follow the usual power-series recurrences, so evaluating
// a formula (or a reference template such as fresnel_dielectric<Jet>) on the jet of the identity
// at a, Jet::variable(a, n), gives every derivative up to order n - 1 to rounding error: no step
// size, no cancellation, unlike finite differences. Expressions are evaluated on jets by
// expr/forward.hpp, with the operators' meaning from expr/op.hpp, and reference programs by
// reference/program_evaluate.hpp, which also uses the C functions below (tan, asin, erf, atan2,
// hypot, ...); each function's value c_0 is the double function's own. Comparisons look at the
// value c_0 only, so branches (min, max, abs, saturate, sign, copysign, select) follow the branch
// taken at the point itself, and the steps (floor, ceil, trunc, round) have no derivatives.
#pragma once

#include <array>
#include <cmath>

namespace shaderfit {

inline constexpr int kMaxJetOrder = 24;  // highest derivative order a jet carries

struct Jet {
  std::array<double, kMaxJetOrder + 1> c{};
  int n = 1;  // coefficients in use; a constant has n = 1

  Jet() = default;
  explicit Jet(double v) { c[0] = v; }
  // The identity x at x = a, carrying derivatives up to `order`.
  static Jet variable(double a, int order) {
    Jet j(a);
    j.n = order + 1;
    if (order >= 1) j.c[1] = 1.0;
    return j;
  }
  [[nodiscard]] double value() const { return c[0]; }
  // The k-th derivative, k! c_k (0 beyond the carried order).
  [[nodiscard]] double derivative(int k) const {
    if (k >= n) return 0.0;
    double f = 1.0;
    for (int i = 2; i <= k; ++i) f *= i;
    return c[k] * f;
  }
};

inline int jet_size(const Jet& a, const Jet& b) { return a.n > b.n ? a.n : b.n; }

inline Jet operator+(const Jet& a, const Jet& b) {
  Jet r;
  r.n = jet_size(a, b);
  for (int k = 0; k < r.n; ++k) r.c[k] = a.c[k] + b.c[k];
  return r;
}
inline Jet operator-(const Jet& a, const Jet& b) {
  Jet r;
  r.n = jet_size(a, b);
  for (int k = 0; k < r.n; ++k) r.c[k] = a.c[k] - b.c[k];
  return r;
}
inline Jet operator-(const Jet& a) {
  Jet r = a;
  for (int k = 0; k < r.n; ++k) r.c[k] = -r.c[k];
  return r;
}
inline Jet operator*(const Jet& a, const Jet& b) {
  Jet r;
  r.n = jet_size(a, b);
  for (int k = 0; k < r.n; ++k) {
    double s = a.c[0] * b.c[k];  // not 0 + ...: the value keeps the sign of a zero product
    for (int i = 1; i <= k; ++i) s += a.c[i] * b.c[k - i];
    r.c[k] = s;
  }
  return r;
}
inline Jet operator/(const Jet& a, const Jet& b) {
  Jet r;
  r.n = jet_size(a, b);
  for (int k = 0; k < r.n; ++k) {
    double s = a.c[k];
    for (int i = 1; i <= k; ++i) s -= b.c[i] * r.c[k - i];
    r.c[k] = s / b.c[0];
  }
  return r;
}
inline Jet& operator+=(Jet& a, const Jet& b) { return a = a + b; }
inline Jet& operator-=(Jet& a, const Jet& b) { return a = a - b; }
inline Jet& operator*=(Jet& a, const Jet& b) { return a = a * b; }
inline Jet& operator/=(Jet& a, const Jet& b) { return a = a / b; }

inline bool operator<(const Jet& a, const Jet& b) { return a.c[0] < b.c[0]; }
inline bool operator>(const Jet& a, const Jet& b) { return a.c[0] > b.c[0]; }
inline bool operator<=(const Jet& a, const Jet& b) { return a.c[0] <= b.c[0]; }
inline bool operator>=(const Jet& a, const Jet& b) { return a.c[0] >= b.c[0]; }

// Elementary functions, found by argument-dependent lookup from the reference templates.
inline Jet sqrt(const Jet& a) {
  Jet r;
  r.n = a.n;
  r.c[0] = std::sqrt(a.c[0]);
  for (int k = 1; k < r.n; ++k) {
    double s = a.c[k];
    for (int i = 1; i < k; ++i) s -= r.c[i] * r.c[k - i];
    r.c[k] = s / (2.0 * r.c[0]);
  }
  return r;
}
inline Jet exp(const Jet& a) {
  Jet r;
  r.n = a.n;
  r.c[0] = std::exp(a.c[0]);
  for (int k = 1; k < r.n; ++k) {
    double s = 0;
    for (int i = 1; i <= k; ++i) s += i * a.c[i] * r.c[k - i];
    r.c[k] = s / k;
  }
  return r;
}
inline Jet log(const Jet& a) {
  Jet r;
  r.n = a.n;
  r.c[0] = std::log(a.c[0]);
  for (int k = 1; k < r.n; ++k) {
    double s = 0;
    for (int i = 1; i < k; ++i) s += i * r.c[i] * a.c[k - i];
    r.c[k] = (a.c[k] - s / k) / a.c[0];
  }
  return r;
}
// exp2 and log2 through exp and log, their values std::exp2's and std::log2's.
inline Jet exp2(const Jet& a) {
  Jet r = exp(a * Jet(0.69314718055994530942));
  r.c[0] = std::exp2(a.c[0]);
  return r;
}
inline Jet log2(const Jet& a) {
  Jet r = log(a) * Jet(1.44269504088896340736);
  r.c[0] = std::log2(a.c[0]);
  return r;
}

// A pair s, c with s' = c a' and c' = sign s a', from their values at a's value: sin and cos
// (sign -1), sinh and cosh (sign +1).
inline void jet_pair_series(const Jet& a, double s0, double c0, double sign, Jet& s, Jet& co) {
  s = Jet();
  co = Jet();
  s.n = co.n = a.n;
  s.c[0] = s0;
  co.c[0] = c0;
  for (int k = 1; k < a.n; ++k) {
    double ss = 0, cc = 0;
    for (int i = 1; i <= k; ++i) {
      ss += i * a.c[i] * co.c[k - i];
      cc += i * a.c[i] * s.c[k - i];
    }
    s.c[k] = ss / k;
    co.c[k] = sign * cc / k;
  }
}

// sin and cos together: s' = c a', c' = -s a'.
inline void sincos(const Jet& a, Jet& s, Jet& co) {
  jet_pair_series(a, std::sin(a.c[0]), std::cos(a.c[0]), -1.0, s, co);
}
inline Jet sin(const Jet& a) {
  Jet s, c;
  sincos(a, s, c);
  return s;
}
inline Jet cos(const Jet& a) {
  Jet s, c;
  sincos(a, s, c);
  return c;
}

// The series whose derivative is d (d's coefficients shifted up), with constant term v0.
inline Jet integrate_series(const Jet& d, double v0, int n) {
  Jet r;
  r.n = n;
  r.c[0] = v0;
  for (int k = 1; k < n; ++k) r.c[k] = d.c[k - 1] / k;
  return r;
}
// The series of a' (coefficients shifted down).
inline Jet derivative_series(const Jet& a) {
  Jet r;
  r.n = a.n > 1 ? a.n - 1 : 1;
  for (int k = 0; k + 1 < a.n; ++k) r.c[k] = (k + 1) * a.c[k + 1];
  return r;
}
// atan' = a' / (1 + a^2).
inline Jet atan(const Jet& a) {
  if (a.n == 1) return Jet(std::atan(a.c[0]));
  Jet d = derivative_series(a) / (Jet(1.0) + a * a);
  return integrate_series(d, std::atan(a.c[0]), a.n);
}
// a^p for a constant p and a != 0, given its value: the series of r = a^p from a r' = p r a'
// (so a < 0 works where the value exists: an integer p, or the real cube root).
inline Jet jet_constant_power(const Jet& a, double p, double value) {
  Jet r;
  r.n = a.n;
  r.c[0] = value;
  for (int k = 1; k < r.n; ++k) {
    double s = 0;
    for (int i = 1; i <= k; ++i) s += ((p + 1.0) * i - k) * a.c[i] * r.c[k - i];
    r.c[k] = s / (k * a.c[0]);
  }
  return r;
}
// pow(a, b) as std::pow: a constant exponent takes the power series (defined for a < 0 and
// integer b), any other exp(b log a).
inline Jet pow(const Jet& a, const Jet& b) {
  bool constant = true;
  for (int k = 1; k < b.n; ++k) constant = constant && b.c[k] == 0.0;
  if (constant && a.c[0] != 0.0) return jet_constant_power(a, b.c[0], std::pow(a.c[0], b.c[0]));
  Jet r = exp(b * log(a));
  r.c[0] = std::pow(a.c[0], b.c[0]);
  return r;
}
// At a = 0 the derivatives are infinite: the coefficients come out NaN.
inline Jet cbrt(const Jet& a) { return jet_constant_power(a, 1.0 / 3.0, std::cbrt(a.c[0])); }
inline Jet expm1(const Jet& a) {
  Jet r = exp(a);
  r.c[0] = std::expm1(a.c[0]);
  return r;
}
// log1p' = a' / (1 + a).
inline Jet log1p(const Jet& a) {
  if (a.n == 1) return Jet(std::log1p(a.c[0]));
  return integrate_series(derivative_series(a) / (Jet(1.0) + a), std::log1p(a.c[0]), a.n);
}
inline Jet log10(const Jet& a) {
  Jet r = log(a) * Jet(0.43429448190325182765);
  r.c[0] = std::log10(a.c[0]);
  return r;
}

// tan' = a' (1 + tan^2) and tanh' = a' (1 - tanh^2): coefficient k of r from those below it.
inline Jet jet_tan_series(const Jet& a, double value, double sign) {
  Jet r;
  r.n = a.n;
  r.c[0] = value;
  Jet u;  // 1 + sign r^2, filled as r is
  for (int k = 1; k < r.n; ++k) {
    double sq = 0;
    for (int i = 0; i <= k - 1; ++i) sq += r.c[i] * r.c[k - 1 - i];
    u.c[k - 1] = (k == 1 ? 1.0 : 0.0) + sign * sq;
    double s = 0;
    for (int i = 1; i <= k; ++i) s += i * a.c[i] * u.c[k - i];
    r.c[k] = s / k;
  }
  return r;
}
inline Jet tan(const Jet& a) { return jet_tan_series(a, std::tan(a.c[0]), 1.0); }
inline Jet tanh(const Jet& a) { return jet_tan_series(a, std::tanh(a.c[0]), -1.0); }

// sinh and cosh together: s' = c a', c' = s a'.
inline void sinhcosh(const Jet& a, Jet& s, Jet& co) {
  jet_pair_series(a, std::sinh(a.c[0]), std::cosh(a.c[0]), 1.0, s, co);
}
inline Jet sinh(const Jet& a) {
  Jet s, c;
  sinhcosh(a, s, c);
  return s;
}
inline Jet cosh(const Jet& a) {
  Jet s, c;
  sinhcosh(a, s, c);
  return c;
}

// The inverse functions by integrating their derivatives: asin' = a' / sqrt(1 - a^2),
// acos' = -asin', asinh' = a' / sqrt(a^2 + 1), acosh' = a' / sqrt(a^2 - 1), atanh' = a' / (1 -
// a^2).
inline Jet asin(const Jet& a) {
  if (a.n == 1) return Jet(std::asin(a.c[0]));
  return integrate_series(derivative_series(a) / sqrt(Jet(1.0) - a * a), std::asin(a.c[0]), a.n);
}
inline Jet acos(const Jet& a) {
  if (a.n == 1) return Jet(std::acos(a.c[0]));
  return integrate_series(-(derivative_series(a) / sqrt(Jet(1.0) - a * a)), std::acos(a.c[0]), a.n);
}
inline Jet asinh(const Jet& a) {
  if (a.n == 1) return Jet(std::asinh(a.c[0]));
  return integrate_series(derivative_series(a) / sqrt(a * a + Jet(1.0)), std::asinh(a.c[0]), a.n);
}
inline Jet acosh(const Jet& a) {
  if (a.n == 1) return Jet(std::acosh(a.c[0]));
  return integrate_series(derivative_series(a) / sqrt(a * a - Jet(1.0)), std::acosh(a.c[0]), a.n);
}
inline Jet atanh(const Jet& a) {
  if (a.n == 1) return Jet(std::atanh(a.c[0]));
  return integrate_series(derivative_series(a) / (Jet(1.0) - a * a), std::atanh(a.c[0]), a.n);
}
// atan2(y, x)' = (x y' - y x') / (x^2 + y^2), the value std::atan2's (its quadrant).
inline Jet atan2(const Jet& y, const Jet& x) {
  const int n = jet_size(y, x);
  if (n == 1) return Jet(std::atan2(y.c[0], x.c[0]));
  const Jet d = (x * derivative_series(y) - y * derivative_series(x)) / (x * x + y * y);
  return integrate_series(d, std::atan2(y.c[0], x.c[0]), n);
}
// erf' = 2 / sqrt(pi) exp(-a^2) a'; erfc = 1 - erf, its value std::erfc's.
inline Jet erf(const Jet& a) {
  if (a.n == 1) return Jet(std::erf(a.c[0]));
  const Jet d = derivative_series(a) * exp(-(a * a)) * Jet(1.12837916709551257390);
  return integrate_series(d, std::erf(a.c[0]), a.n);
}
inline Jet erfc(const Jet& a) {
  if (a.n == 1) return Jet(std::erfc(a.c[0]));
  const Jet d = derivative_series(a) * exp(-(a * a)) * Jet(-1.12837916709551257390);
  return integrate_series(d, std::erfc(a.c[0]), a.n);
}
// sqrt(a^2 + b^2), scaled by the larger magnitude so that squares cannot overflow; the value is
// std::hypot's.
inline Jet hypot(const Jet& a, const Jet& b) {
  const double m = std::fmax(std::fabs(a.c[0]), std::fabs(b.c[0]));
  Jet r;
  if (m > 0 && std::isfinite(m)) {
    const Jet as = a / Jet(m), bs = b / Jet(m);
    r = sqrt(as * as + bs * bs) * Jet(m);
  } else {
    r = sqrt(a * a + b * b);
  }
  r.c[0] = std::hypot(a.c[0], b.c[0]);
  return r;
}

// Piecewise constant functions: the value, no derivatives (the steps themselves have none
// either side of them).
inline Jet jet_step(const Jet& a, double v) {
  Jet r(v);
  r.n = a.n;
  return r;
}
inline Jet floor(const Jet& a) { return jet_step(a, std::floor(a.c[0])); }
inline Jet ceil(const Jet& a) { return jet_step(a, std::ceil(a.c[0])); }
inline Jet trunc(const Jet& a) { return jet_step(a, std::trunc(a.c[0])); }
inline Jet round(const Jet& a) { return jet_step(a, std::round(a.c[0])); }
// fmod(a, b) = a - b q with q = trunc(a / b) constant between its steps; the value std::fmod's.
inline Jet fmod(const Jet& a, const Jet& b) {
  const double v = std::fmod(a.c[0], b.c[0]);
  Jet r = a - b * Jet(std::round((a.c[0] - v) / b.c[0]));
  r.c[0] = v;
  return r;
}

// |a| by the sign bit, as std::abs: -0 gives +0.
inline Jet abs(const Jet& a) { return std::signbit(a.c[0]) ? -a : a; }
// |a| with b's sign bit, as std::copysign: a or -a by the sign bits of the two values.
inline Jet copysign(const Jet& a, const Jet& b) {
  return std::signbit(a.c[0]) != std::signbit(b.c[0]) ? -a : a;
}
// min and max by the value; a tie takes the first argument, and a NaN the other one (as
// std::fmin and std::fmax).
inline Jet fmin(const Jet& a, const Jet& b) {
  return b.c[0] < a.c[0] || std::isnan(a.c[0]) ? b : a;
}
inline Jet fmax(const Jet& a, const Jet& b) {
  return b.c[0] > a.c[0] || std::isnan(a.c[0]) ? b : a;
}

}  // namespace shaderfit
