// Writing an FV bake: the textures (DDS RGBA32F and RGBA16F, OpenEXR), the per-cell error tables
// (CSV) and images (PNG), the HLSL and GLSL that sample the textures, and a JSON summary.
//
//   FvBake bake = bake_fv_luts(options, kAllFvVariants);
//   std::vector<std::string> files = write_fv_bake(bake, options, "out/");
//
// Files, per variant V: fv_V_rgba32f.dds, fv_V_rgba16f.dds, fv_V.exr, fv_V_errors.csv,
// fv_V_errors.png (fv_error_maps, or without gnuplot fv_error_image); once: fv_lut.hlsl,
// fv_lut.glsl, fv_summary.json.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "shaderfit/lut/fv_lut.hpp"
#include "shaderfit/plot/chart.hpp"

namespace shaderfit::lut {

// Writes every file into `directory` (created if missing) and returns their paths. Throws
// shaderfit::Error when a file cannot be written.
std::vector<std::string> write_fv_bake(const FvBake& bake, const FvLutOptions& options,
                                       const std::string& directory);

// One CSV line per cell: i, j, roughness, f0, status, the unfolded A, B, C, the texel P0, P1, P2,
// and the errors (max and mean, linear and log2; float32 and float16 texels).
std::string fv_error_csv(const FvTable& table);

// The error maps that fv_V_errors.png shows (drawn by gnuplot): four heat maps, 2 x 2, of the
// mean and max |log2(FV / reference)| and |FV - reference| per cell, each titled, over
// roughness (x) and sqrt(F0) (y) with a colour bar on a log scale; failed cells blank.
HeatmapGrid fv_error_maps(const FvTable& table);

// The bare error image, written as fv_V_errors.png where gnuplot is not installed: four panels side
// by side (mean log2, max log2, mean abs, max abs error), each one pixel per cell scaled up to at
// least 128 pixels, rows as in the texture (sqrt(F0) grows downward, roughness to the right),
// colours on a log10 scale from the smallest to the largest value of the panel (see
// fv_summary.json), failed cells magenta. RGB bytes, row 0 on top.
std::vector<std::uint8_t> fv_error_image(const FvTable& table, std::size_t* width,
                                         std::size_t* height);

// Shader code that samples the tables (same for every variant), and the endpoint variant
// computed without a texture from the bake's adjustment.
std::string fv_hlsl(const FvBake& bake, const FvLutOptions& options);
std::string fv_glsl(const FvBake& bake, const FvLutOptions& options);

// The JSON summary: options, the endpoint adjustment, the bake time, and per variant the error
// summaries, F0 deviations, failed cells and the panel scales of the error image.
std::string fv_summary_json(const FvBake& bake, const FvLutOptions& options);

}  // namespace shaderfit::lut
