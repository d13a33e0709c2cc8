// LDR-FLIP (Andersson et al., "FLIP: A Difference Evaluator for Alternating Images", HPG 2020):
// the perceived difference between two sRGB images when a viewer flips between them, per pixel
// in [0, 1], as NVIDIA's flip-evaluator computes it (python/tests/flip_agreement_test.py
// compares the two).
//
//   shaderfit::FlipResult r = shaderfit::ldr_flip(reference, test);
//   double mean = r.mean, bad = r.share_above(0.1);
//   write_png("flip.png", r.width, r.height, shaderfit::flip_colormap(r));
#pragma once

#include <cstdint>
#include <numbers>
#include <vector>

namespace shaderfit {

// An sRGB-encoded image, values in [0, 1], row-major, 3 channels interleaved (RGBRGB...), row 0
// at the top. Values outside [0, 1] are used as they are, as flip-evaluator does.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

struct FlipOptions {
  // The observer's resolution: pixels per degree of visual angle. The default is the paper's and
  // the tool's: a 0.7 m wide monitor of 3840 pixels seen from 0.7 m, about 67.02.
  double pixels_per_degree = 0.7 * (3840.0 / 0.7) * (std::numbers::pi / 180.0);
};

struct FlipResult {
  int width = 0, height = 0;
  std::vector<float> error;  // per pixel, in [0, 1], row-major, row 0 at the top
  double mean = 0;           // of error

  // The share of pixels whose error exceeds threshold, in [0, 1] (0 for an empty result).
  [[nodiscard]] double share_above(double threshold) const;
};

// Throws shaderfit::Error located at "reference" or "test" for images whose sizes differ, are 0,
// or whose rgb.size() is not 3 * width * height, or that hold values that are not finite; and at
// "FlipOptions::pixels_per_degree" when that is not finite and positive.
FlipResult ldr_flip(const RgbImage& reference, const RgbImage& test,
                    const FlipOptions& options = {});

// The error map colour-mapped as the tool shows it (magma, error e at entry round(255 e)), as
// sRGB bytes RGBRGB..., row 0 at the top: for report images (write_png).
std::vector<std::uint8_t> flip_colormap(const FlipResult& r);

}  // namespace shaderfit
