// Texels from fitted cells (fold F0 into C, expand the polynomial in dot(L,H)), FV rebuilt from
// texels, and the per-cell errors against the reference.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "fv_internal.hpp"
#include "shaderfit/image/half.hpp"

namespace shaderfit::lut {

double fv_from_texel(const float* rgba, double l_dot_h) {
  const double p0 = rgba[0], p1 = rgba[1], p2 = rgba[2];
  return std::exp2((p0 * l_dot_h + p1) * l_dot_h + p2);
}

}  // namespace shaderfit::lut

namespace shaderfit::lut_detail {

using namespace shaderfit::lut;  // the area's public names

void fold_texel(const FvCell& cell, double f0, float* rgba, float* rgba_half) {
  if (!cell.ok) {
    std::fill(rgba, rgba + 4, 0.0f);
    std::fill(rgba_half, rgba_half + 4, 0.0f);
    return;
  }
  // F(1 - d) = A (1 - d)^2 + B (1 - d) + C + log2 f0 = A d^2 - (2A + B) d + (A + B + C + log2 f0).
  const double p0 = cell.a, p1 = -(2 * cell.a + cell.b);
  const double at_one = cell.c + std::log2(f0);  // the exponent at d = 1
  // The shader computes fma(fma(P0, d, P1), d, P2); at d = 1 that is (P0 + P1) + P2, each sum
  // rounded to float. Aim P2 at at_one from the float sum of the stored P0 and P1.
  const auto f_p0 = static_cast<float>(p0), f_p1 = static_cast<float>(p1);
  const float f_sum = f_p0 + f_p1;  // -ffp-contract=off: one float rounding, as the shader's fma
  rgba[0] = f_p0;
  rgba[1] = f_p1;
  rgba[2] = static_cast<float>(at_one - static_cast<double>(f_sum));
  rgba[3] = 1.0f;
  const float h_p0 = half_to_float(float_to_half(f_p0)), h_p1 = half_to_float(float_to_half(f_p1));
  const float h_sum = h_p0 + h_p1;
  rgba_half[0] = h_p0;
  rgba_half[1] = h_p1;
  rgba_half[2] =
      half_to_float(float_to_half(static_cast<float>(at_one - static_cast<double>(h_sum))));
  rgba_half[3] = 1.0f;
}

double f0_deviation(const float* rgba, double f0) {
  const float e = std::fma(std::fma(rgba[0], 1.0f, rgba[1]), 1.0f, rgba[2]);
  return std::abs(static_cast<double>(std::exp2(e)) / f0 - 1);
}

std::vector<double> eval_cosines(const FvLutOptions& o) {
  std::vector<double> d(o.eval_samples);
  const double top = o.eval_max_degrees * std::numbers::pi / 180;
  for (std::size_t k = 0; k < d.size(); ++k)
    d[k] = std::cos(top * (static_cast<double>(k) + 0.5) / static_cast<double>(d.size()));
  return d;
}

namespace {

// Accumulates one sample: the approximation as its exponent (FV = exp2(e)) against log2 of the
// reference, so the log error needs no division.
struct Accumulator {
  CellError e;
  std::size_t n = 0;
  void add(double exponent, double want, double log2_want) {
    double abs_err = std::abs(std::exp2(exponent) - want), log_err = std::abs(exponent - log2_want);
    if (!std::isfinite(abs_err)) abs_err = std::numeric_limits<double>::infinity();
    if (!std::isfinite(log_err)) log_err = std::numeric_limits<double>::infinity();
    e.max_abs = std::max(e.max_abs, abs_err);
    e.max_log2 = std::max(e.max_log2, log_err);
    e.mean_abs += abs_err;
    e.mean_log2 += log_err;
    ++n;
  }
  CellError result() const {
    CellError r = e;
    if (n > 0) {
      r.mean_abs /= static_cast<double>(n);
      r.mean_log2 /= static_cast<double>(n);
    }
    return r;
  }
};

double texel_exponent(const float* t, double d) {
  return (static_cast<double>(t[0]) * d + static_cast<double>(t[1])) * d +
         static_cast<double>(t[2]);
}

}  // namespace

CellError model_error(const FvReference& ref, std::span<const double> cosines, const CellSpec& c,
                      const FvCell& cell) {
  Accumulator acc;
  const double l0 = std::log2(c.f0);
  for (double d : cosines) {
    const double want = ref(d, c.f0, c.roughness), x = 1 - d;
    acc.add((cell.a * x + cell.b) * x + cell.c + l0, want, std::log2(want));
  }
  return acc.result();
}

CellError reference_error(const FvReference& ref, std::span<const double> cosines,
                          const CellSpec& c, const FvReference& approx) {
  Accumulator acc;
  for (double d : cosines) {
    const double want = ref(d, c.f0, c.roughness);
    acc.add(std::log2(approx(d, c.f0, c.roughness)), want, std::log2(want));
  }
  return acc.result();
}

void texel_errors(const FvReference& ref, std::span<const double> cosines, const CellSpec& c,
                  const float* rgba, const float* rgba_half, CellError* e, CellError* e_half) {
  Accumulator a, h;
  for (double d : cosines) {
    const double want = ref(d, c.f0, c.roughness), log2_want = std::log2(want);
    a.add(texel_exponent(rgba, d), want, log2_want);
    h.add(texel_exponent(rgba_half, d), want, log2_want);
  }
  *e = a.result();
  *e_half = h.result();
}

ErrorSummary summarize(std::span<const CellError> errors, std::span<const FvCell> cells) {
  ErrorSummary s;
  std::size_t n = 0;
  for (std::size_t k = 0; k < errors.size(); ++k) {
    if (!cells[k].ok) continue;
    ++n;
    s.mean_log2 += errors[k].mean_log2;
    s.mean_abs += errors[k].mean_abs;
    s.max_log2 = std::max(s.max_log2, errors[k].max_log2);
    s.max_abs = std::max(s.max_abs, errors[k].max_abs);
  }
  if (n > 0) {
    s.mean_log2 /= static_cast<double>(n);
    s.mean_abs /= static_cast<double>(n);
  }
  return s;
}

}  // namespace shaderfit::lut_detail

namespace shaderfit::lut {}  // namespace shaderfit::lut
