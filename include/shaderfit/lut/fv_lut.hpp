// Lookup tables of the Fresnel-visibility term FV(dot(L,H)) = f0 exp2(A x^2 + B x + C),
// x = 1 - dot(L,H), fitted per cell of a grid over roughness and F0, folded and expanded so that
// a shader evaluates
//   FV = exp2((P0 d + P1) d + P2),  d = dot(L,H)
// with one exp2 and two FMAs (P0 = A, P1 = -(2A + B), P2 = A + B + C + log2 f0).
//
//   FvLutOptions options;                   // 128 x 128, fv-schlick-smith-lh
//   FvBake bake = bake_fv_luts(options, kAllFvVariants);
//   const FvTable& t = bake.tables[2];      // the constrained solve
//   float p0 = t.texels[4 * (j * t.size + i)];  // texel (i, j): roughness i, sqrt(F0) j
//
// Texel (i, j) holds the cell whose roughness is (i + 0.5) / size and whose sqrt(F0) is
// (j + 0.5) / size (F0 is indexed by its square root for precision at dielectric values):
// u = roughness and v = sqrt(F0) address the texel centres exactly. RGB = (P0, P1, P2), A = 1
// for a fitted cell and 0 for a failed one (whose RGB are 0).
//
// The four variants:
//   endpoint     A = s(roughness) log2(V90 / f0), B = C = 0, V90 = 4 / alpha^2 (FV(0) of
//                fv-schlick-smith-lh), s a cubic in sqrt(roughness) fitted once per bake (the
//                perceptual adjustment, see docs/lut.md)
//   linear       A, B, C by linear least squares on log2(FV / f0), angles 0..90 degrees
//   constrained  the same with C = 0, so FV(dot(L,H) = 1) = f0 exactly
//   clamped      constrained, angles up to 85 degrees at roughness 0, lerped to 90 by 0.5
// Angles are sampled uniformly at interval midpoints (never exactly 90 degrees).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shaderfit/core/progress.hpp"

namespace shaderfit::lut {

enum class FvVariant { endpoint, linear, constrained, clamped };
inline constexpr std::array<FvVariant, 4> kAllFvVariants = {
    FvVariant::endpoint, FvVariant::linear, FvVariant::constrained, FvVariant::clamped};

std::string_view variant_name(FvVariant v);  // "endpoint", "linear", "constrained", "clamped"
std::optional<FvVariant> parse_variant(std::string_view name);
bool variant_is_constrained(FvVariant v);  // C = 0: endpoint, constrained, clamped

// A reference FV(dot_lh, f0, roughness).
using FvFunction = double (*)(double l_dot_h, double f0, double roughness);

struct FvLutOptions {
  std::size_t size = 128;          // texels per axis
  std::size_t fit_samples = 90;    // angles per cell for the fits
  std::size_t eval_samples = 180;  // angles per cell for the error tables ...
  double eval_max_degrees = 90;    // ... at interval midpoints over [0, this]
  // A built-in reference taking (dot_lh, f0, roughness): fv-schlick-smith-lh (the default),
  // fv-schlick-smith, fv-exact. `function`, when set, replaces it (label: reference_name).
  std::string reference = "fv-schlick-smith-lh";
  FvFunction function = nullptr;
  double clamp_degrees = 85;       // the grazing clamp at roughness 0 ...
  double clamp_roughness = 0.5;    // ... lerped to 90 degrees by this roughness
  std::size_t endpoint_grid = 32;  // cells per axis for deriving the endpoint adjustment
  int threads = 0;                 // 0: all cores
  // Told of the cells fitted so far: by bake_fv_luts over every table, by compare_with_exact
  // over both fits of every cell (core/progress.hpp).
  ProgressCallback on_progress;

  // False, with the reason, for a size, sample count or grid of zero, a clamp outside (0, 90],
  // a non-positive clamp roughness, or an unknown reference.
  bool is_valid(std::string* why) const;
};

// The endpoint variant's adjustment s(r) = c0 + c1 u + c2 u^2 + c3 u^3, u = sqrt(roughness).
struct EndpointAdjustment {
  std::array<double, 4> c{1, 0, 0, 0};
  [[nodiscard]] double operator()(double roughness) const;
};

struct CellError {
  double max_abs = 0, mean_abs = 0;    // |FV - reference|
  double max_log2 = 0, mean_log2 = 0;  // |log2(FV / reference)|
};

struct ErrorSummary {  // over the fitted cells
  double mean_log2 = 0, max_log2 = 0, mean_abs = 0, max_abs = 0;
};

struct FvCell {
  double a = 0, b = 0, c = 0;  // the unfolded coefficients
  bool ok = true;
  std::string failure;
};

struct FvTable {
  FvVariant variant = FvVariant::linear;
  std::size_t size = 0;
  std::vector<FvCell> cells;           // size * size, row j (sqrt F0) major, column i roughness
  std::vector<float> texels;           // size * size * 4: RGBA32F contents
  std::vector<float> texels_half;      // the same rounded as RGBA16F stores them (C' re-aimed)
  std::vector<CellError> errors;       // of the float32 texels against the reference
  std::vector<CellError> errors_half;  // of the float16 texels
  ErrorSummary summary, summary_half;
  std::vector<std::string> failures;  // "cell (i, j) roughness=r f0=f: reason"
  // max over fitted cells of |FV(dot(L,H) = 1) / f0 - 1|, evaluated as the shader does in float
  // (two fmaf and exp2f) from the float32 and from the float16 texels.
  double f0_deviation = 0, f0_deviation_half = 0;
  double seconds = 0;  // this table's share of the bake (fit + texels + errors)
};

struct FvBake {
  std::string reference;
  EndpointAdjustment adjustment;
  std::vector<FvTable> tables;  // in the order asked for
  double seconds = 0;           // wall time of the whole bake (tables in parallel)
};

// Texel centre coordinates.
double cell_roughness(std::size_t i, std::size_t size);
double cell_f0(std::size_t j, std::size_t size);
// The largest sampled angle for the clamped variant at this roughness, in degrees.
double clamp_angle_degrees(const FvLutOptions& o, double roughness);

// Bakes the tables, in parallel. Throws shaderfit::Error for invalid options or when every cell
// of a table fails the same way; cells that fail alone are reported in FvTable::failures.
FvBake bake_fv_luts(const FvLutOptions& options, std::span<const FvVariant> variants);

// Derives the endpoint adjustment: one least-squares fit of log2(FV / f0) ~ s(r) log2(V90 / f0)
// x^2 pooled over an endpoint_grid^2 grid, angles as for the clamped variant.
EndpointAdjustment derive_endpoint_adjustment(const FvLutOptions& options);

// FV rebuilt from a texel: exp2((p0 d + p1) d + p2), in double from the stored floats.
double fv_from_texel(const float* rgba, double l_dot_h);

// One cell's constrained fit in closed form (the default approximation `plot sphere` draws): A, B
// with log2(FV / f0) ~ A x^2 + B x, x = 1 - dot(L,H), FV the default reference
// (fv-schlick-smith-lh), by linear least squares over 256 midpoints of x in [0, 1] (C = 0 keeps
// FV(dot(L,H) = 1) = f0). Throws shaderfit::Error located at "roughness" or "f0" for a roughness
// outside (0, 1] or an F0 outside (0, 1).
std::array<double, 2> fit_fv_constrained(double roughness, double f0);

// The reference a bake fits: options.function, or the built-in named by options.reference.
FvFunction reference_function(const FvLutOptions& options);

}  // namespace shaderfit::lut
