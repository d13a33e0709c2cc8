// Internals of the FV lookup tables shared by the bake, the error tables and the comparison with
// the exact reference.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "shaderfit/lut/fv_lut.hpp"
#include "shaderfit/reference/fv_reference.hpp"

namespace shaderfit::lut_detail {

using namespace shaderfit::lut;  // the area's public names

// A reference FV dispatched on a tag (no indirect call per sample for the conductor case, and
// no captured state to carry through a function pointer).
struct FvReference {
  enum class Kind { function, conductor };
  Kind kind = Kind::function;
  FvFunction function = nullptr;
  double n = 0, k = 0;  // conductor IOR
  double operator()(double d, double f0, double r) const {
    return kind == Kind::function ? function(d, f0, r) : reference::fv_exact_conductor(d, n, k, r);
  }
};

struct CellSpec {
  std::size_t i = 0, j = 0;  // texel column (roughness) and row (sqrt F0)
  double roughness = 0, f0 = 0;
  [[nodiscard]] std::string label() const;  // "cell (i, j) roughness=r f0=f"
};

// The size x size cells, row-major (row j = sqrt(F0) index).
std::vector<CellSpec> square_grid(std::size_t size);

// The largest angle the variant samples at this roughness, in degrees.
double max_angle_degrees(const FvLutOptions& o, FvVariant v, double roughness);

// Fits (or, for the endpoint variant, computes) the coefficients of every cell. Cells whose
// reference is not finite and positive at a sample, or whose fit fails, come back !ok with the
// reason; the others are fitted together through solve_fixed_form (one block per cell). Each
// cell is counted once in `progress`, when computed, fitted or failed.
std::vector<FvCell> fit_cells(const FvLutOptions& o, FvVariant v, const FvReference& ref,
                              std::span<const CellSpec> cells, const EndpointAdjustment& adjustment,
                              ProgressCounter& progress);

// The texel of a cell: folded and expanded coefficients (P0, P1, P2, 1), or (0, 0, 0, 0) for a
// failed cell. P2 is re-aimed (within the rounding of the others) so that the shader's
// (P0 + P1) + P2 at dot(L,H) = 1, computed in float, lands as close as float allows to
// C + log2(f0); the same for the half texel, whose values are returned widened to float.
void fold_texel(const FvCell& cell, double f0, float* rgba, float* rgba_half);

// |FV(1) / f0 - 1| with FV(1) = exp2f(fmaf(fmaf(P0, 1, P1), 1, P2)) in float, as a shader computes
// it.
double f0_deviation(const float* rgba, double f0);

// cos of eval_samples angles at interval midpoints over [0, eval_max_degrees].
std::vector<double> eval_cosines(const FvLutOptions& o);

// Errors over the given dot(L,H) samples: of the unfolded model, of another reference, and of
// the float32 and float16 texels (sharing the reference's samples).
CellError model_error(const FvReference& ref, std::span<const double> cosines, const CellSpec& c,
                      const FvCell& cell);
CellError reference_error(const FvReference& ref, std::span<const double> cosines,
                          const CellSpec& c, const FvReference& approx);
void texel_errors(const FvReference& ref, std::span<const double> cosines, const CellSpec& c,
                  const float* rgba, const float* rgba_half, CellError* e, CellError* e_half);

// Mean of the per-cell means and max of the per-cell maxima, over the fitted cells.
ErrorSummary summarize(std::span<const CellError> errors, std::span<const FvCell> cells);

}  // namespace shaderfit::lut_detail
