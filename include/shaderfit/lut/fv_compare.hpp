// How close the fitted FV gets to the ground truth, exact Fresnel x exact Smith GGX visibility
// (reference/fv_reference.hpp), compared with Schlick x Schlick-Smith.
//
//   ExactComparison c = compare_with_exact(options, FvVariant::clamped);
//   for (const auto& row : c.rows) row.exact_fit.mean_log2 ...
//
// Rows: the dielectrics of the size x size (roughness, sqrt F0) grid, each F0 read as the IOR
// (1 + sqrt F0) / (1 - sqrt F0); then each metal of the fresnel-seed data set (complex IOR n + ik)
// over `size` roughness cells at its own F0. Every column is an error against the ground truth,
// on the error tables' angles (midpoints over 0..90 degrees):
//   schlick_lh    fv-schlick-smith-lh, Schlick x Hable's dot(L,H) visibility
//   schlick_peak  Schlick x Schlick-Smith at n = h (the same slice as the ground truth)
//   seed_fit      the variant fitted to fv-schlick-smith-lh (bake_fv_luts's default table)
//   exact_fit     the same variant fitted to the ground truth
#pragma once

#include <string>
#include <vector>

#include "shaderfit/lut/fv_lut.hpp"

namespace shaderfit::lut {

struct ExactComparisonRow {
  std::string material;  // "dielectrics (grid)" or "metal 0.3+3i"
  double f0 = 0;         // the metal's normal-incidence reflectance (0 for the grid row)
  ErrorSummary schlick_lh, schlick_peak, seed_fit, exact_fit;
  std::size_t failed = 0;  // cells where a fit failed (left out of the summaries)
};

struct ExactComparison {
  FvVariant variant = FvVariant::clamped;
  std::vector<ExactComparisonRow> rows;
  double seconds = 0;
};

// Throws shaderfit::Error for invalid options or the endpoint variant (not a fit).
ExactComparison compare_with_exact(const FvLutOptions& options, FvVariant variant);

// A table for people, one row per material.
std::string format_exact_comparison(const ExactComparison& c);

}  // namespace shaderfit::lut
