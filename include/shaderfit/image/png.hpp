// PNG files for report images, written without a library: 8-bit RGB, one IDAT holding a zlib
// stream of stored (uncompressed) deflate blocks, with CRC-32 and Adler-32 computed here.
//
//   write_png("errors.png", w, h, rgb);  // rgb: w * h * 3 bytes, row 0 at the top
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace shaderfit {

std::vector<std::uint8_t> encode_png(std::size_t width, std::size_t height,
                                     std::span<const std::uint8_t> rgb);
void write_png(const std::string& path, std::size_t width, std::size_t height,
               std::span<const std::uint8_t> rgb);

// CRC-32 (ISO 3309, as PNG chunks use) of bytes.
std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace shaderfit
