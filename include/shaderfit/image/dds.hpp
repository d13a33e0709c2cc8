// DirectDraw Surface files for float textures, in the DX10 extended layout that D3D10+ loaders
// (DirectXTex, DDSTextureLoader) read.
//
//   write_dds("fv.dds", 128, 128, rgba, DdsFormat::rgba16f);  // rgba: 128*128*4 floats
//
// Layout: the magic "DDS ", DDS_HEADER (124 bytes; flags CAPS|HEIGHT|WIDTH|PIXELFORMAT|PITCH, the
// pixel format a FourCC "DX10", caps TEXTURE), DDS_HEADER_DXT10 (20 bytes: DXGI format 2 =
// R32G32B32A32_FLOAT or 10 = R16G16B16A16_FLOAT, dimension 3 = TEXTURE2D, array size 1), then
// one mip level, rows top to bottom (row 0 first, which D3D and GL address as v = 0), all
// little-endian.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace shaderfit {

enum class DdsFormat { rgba32f, rgba16f };

// The file's bytes. rgba holds width * height * 4 floats, row by row. Throws Error for a size of
// zero or a span of the wrong length.
std::vector<std::uint8_t> encode_dds(std::size_t width, std::size_t height,
                                     std::span<const float> rgba, DdsFormat format);

// Writes encode_dds(...) to path; throws Error "cannot write 'path'" on failure.
void write_dds(const std::string& path, std::size_t width, std::size_t height,
               std::span<const float> rgba, DdsFormat format);

}  // namespace shaderfit
