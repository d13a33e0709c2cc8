// Adaptive Gauss-Legendre quadrature (internal to src/rational).
//
// A 10-point Gauss-Legendre rule on an interval is compared with the same rule on its two halves;
// where they differ by more than the tolerance the halves are refined recursively. Smooth
// integrands converge in one or two levels; the depth limit keeps a singular integrand finite
// (the result is then only as good as the deepest level).
#pragma once

#include <cmath>

namespace shaderfit::rational_detail {

using namespace shaderfit::rational;  // the area's public names

inline constexpr double kGaussNodes[5] = {0.1488743389816312, 0.4333953941292472,
                                          0.6794095682990244, 0.8650633666889845,
                                          0.9739065285171717};
inline constexpr double kGaussWeights[5] = {0.2955242247147529, 0.2692667193099963,
                                            0.2190863625159820, 0.1494513491505806,
                                            0.0666713443086881};

template <typename F>
double gauss_legendre_10(const F& f, double a, double b) {
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double s = 0;
  for (int i = 0; i < 5; ++i) {
    const double d = half * kGaussNodes[i];
    s += kGaussWeights[i] * (f(mid - d) + f(mid + d));
  }
  return s * half;
}

template <typename F>
double adaptive_gauss(const F& f, double a, double b, double whole, double tol, int depth) {
  const double mid = 0.5 * (a + b);
  const double left = gauss_legendre_10(f, a, mid), right = gauss_legendre_10(f, mid, b);
  const double both = left + right;
  if (depth <= 0 || std::abs(both - whole) <= tol || !std::isfinite(both)) return both;
  return adaptive_gauss(f, a, mid, left, 0.5 * tol, depth - 1) +
         adaptive_gauss(f, mid, b, right, 0.5 * tol, depth - 1);
}

// The integral of f over [a, b] (b < a gives the negative), to about `rel_tol` of the integral
// of |f| estimated from the first rule.
template <typename F>
double integrate(const F& f, double a, double b, double rel_tol = 1e-13) {
  if (a == b) return 0.0;
  const double whole = gauss_legendre_10(f, a, b);
  const double scale = std::abs(gauss_legendre_10([&](double x) { return std::abs(f(x)); }, a, b));
  const double tol = rel_tol * (scale > 0 ? scale : 1.0);
  return adaptive_gauss(f, a, b, whole, tol, 24);
}

// Composite 10-point Gauss-Legendre on `panels` equal panels: a fixed rule for integrands known
// to be smooth (a rational function with no pole near the interval), cheap enough for Jacobians.
template <typename F>
double integrate_fixed(const F& f, double a, double b, int panels = 8) {
  double s = 0;
  const double h = (b - a) / panels;
  for (int i = 0; i < panels; ++i)
    s += gauss_legendre_10(f, a + i * h, i + 1 == panels ? b : a + (i + 1) * h);
  return s;
}

}  // namespace shaderfit::rational_detail
