// OpenEXR files for float textures, written with the OpenEXR library (Debian libopenexr-dev).
//
//   write_exr("fv.exr", 128, 128, rgba, {{"shaderfit.variant", "constrained"}});
//
// Channels R, G, B, A as 32-bit FLOAT (the file lists them alphabetically: A, B, G, R), a single
// part, scanlines top to bottom (row 0 first), no compression (so that a reader needs no codec),
// and the given string attributes in the header.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace shaderfit {

// rgba holds width * height * 4 floats, row by row. Throws Error for a bad size or when the file
// cannot be written.
void write_exr(const std::string& path, std::size_t width, std::size_t height,
               std::span<const float> rgba,
               const std::vector<std::pair<std::string, std::string>>& attributes = {});

}  // namespace shaderfit
