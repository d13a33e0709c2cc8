// Truncated Taylor series ("jets") for exact derivatives of any order up to kMaxJetOrder.
//
// A Jet holds the Taylor coefficients c_0..c_{n-1} of a function at a point: c_k = f^(k)(a) / k!.
// Arithmetic and the elementary functions follow the usual power-series recurrences, so evaluating
// a formula (or a reference template such as fresnel_dielectric<Jet>) on the jet of the identity
// at a, Jet::variable(a, n), gives every derivative up to order n - 1 to rounding error: no step
// size, no cancellation, unlike finite differences. Expressions are evaluated on jets by
// expr/forward.hpp, with the operators' meaning from expr/op.hpp. Comparisons look at the value
// c_0 only, so branches (min, max, abs, saturate, sign, copysign, select) follow the branch
// taken at the point itself.
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
    double s = 0;
    for (int i = 0; i <= k; ++i) s += a.c[i] * b.c[k - i];
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
inline Jet exp2(const Jet& a) { return exp(a * Jet(0.69314718055994530942)); }
inline Jet log2(const Jet& a) { return log(a) * Jet(1.44269504088896340736); }
inline Jet pow(const Jet& a, const Jet& b) { return exp(b * log(a)); }

// sin and cos together: s' = c a', c' = -s a'.
inline void sincos(const Jet& a, Jet& s, Jet& co) {
  s = Jet();
  co = Jet();
  s.n = co.n = a.n;
  s.c[0] = std::sin(a.c[0]);
  co.c[0] = std::cos(a.c[0]);
  for (int k = 1; k < a.n; ++k) {
    double ss = 0, cc = 0;
    for (int i = 1; i <= k; ++i) {
      ss += i * a.c[i] * co.c[k - i];
      cc -= i * a.c[i] * s.c[k - i];
    }
    s.c[k] = ss / k;
    co.c[k] = cc / k;
  }
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
inline Jet abs(const Jet& a) { return a.c[0] < 0 ? -a : a; }
// |a| with b's sign bit, as std::copysign: a or -a by the sign bits of the two values.
inline Jet copysign(const Jet& a, const Jet& b) {
  return std::signbit(a.c[0]) != std::signbit(b.c[0]) ? -a : a;
}
// min and max by the value; a tie takes the first argument.
inline Jet fmin(const Jet& a, const Jet& b) { return b.c[0] < a.c[0] ? b : a; }
inline Jet fmax(const Jet& a, const Jet& b) { return b.c[0] > a.c[0] ? b : a; }

}  // namespace shaderfit
