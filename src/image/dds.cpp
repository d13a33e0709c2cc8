#include "shaderfit/image/dds.hpp"

#include <cstring>

#include "shaderfit/core/error.hpp"
#include "shaderfit/image/half.hpp"
#include "write_file.hpp"

namespace shaderfit {

namespace {

// DDS_HEADER and DDS_HEADER_DXT10 constants (Microsoft's "DDS file layout" reference).
// CAPS, HEIGHT, WIDTH, PITCH, PIXELFORMAT, MIPMAPCOUNT.
constexpr std::uint32_t kFlags = 0x1 | 0x2 | 0x4 | 0x8 | 0x1000 | 0x20000;
constexpr std::uint32_t kPixelFormatFourCC = 0x4;
constexpr std::uint32_t kCapsTexture = 0x1000;
constexpr std::uint32_t kDxgiRgba32f = 2, kDxgiRgba16f = 10;
constexpr std::uint32_t kDimensionTexture2D = 3;

}  // namespace

std::vector<std::uint8_t> encode_dds(std::size_t width, std::size_t height,
                                     std::span<const float> rgba, DdsFormat format) {
  if (width == 0 || height == 0) throw Error("a DDS texture needs a size of at least 1 x 1");
  if (rgba.size() != width * height * 4)
    throw Error("encode_dds: " + std::to_string(rgba.size()) + " floats for a " +
                std::to_string(width) + " x " + std::to_string(height) + " RGBA texture");
  const std::size_t texel = format == DdsFormat::rgba32f ? 16 : 8;
  std::vector<std::uint8_t> out(4 + 124 + 20 + width * height * texel, 0);
  using image_detail::put_u32;
  std::memcpy(out.data(), "DDS ", 4);
  std::uint8_t* h = out.data() + 4;
  put_u32(h + 0, 124);                                         // dwSize
  put_u32(h + 4, kFlags);                                      // dwFlags
  put_u32(h + 8, static_cast<std::uint32_t>(height));          // dwHeight
  put_u32(h + 12, static_cast<std::uint32_t>(width));          // dwWidth
  put_u32(h + 16, static_cast<std::uint32_t>(width * texel));  // dwPitchOrLinearSize
  put_u32(h + 24, 1);                                          // dwMipMapCount
  std::uint8_t* pf = h + 72;                                   // DDS_PIXELFORMAT
  put_u32(pf + 0, 32);
  put_u32(pf + 4, kPixelFormatFourCC);
  std::memcpy(pf + 8, "DX10", 4);
  put_u32(h + 104, kCapsTexture);  // dwCaps
  std::uint8_t* dx10 = h + 124;
  put_u32(dx10 + 0, format == DdsFormat::rgba32f ? kDxgiRgba32f : kDxgiRgba16f);
  put_u32(dx10 + 4, kDimensionTexture2D);
  put_u32(dx10 + 8, 0);   // miscFlag
  put_u32(dx10 + 12, 1);  // arraySize
  put_u32(dx10 + 16, 0);  // miscFlags2: alpha mode unknown (the channels are coefficients)
  std::uint8_t* p = dx10 + 20;
  for (float v : rgba) {
    if (format == DdsFormat::rgba32f) {
      std::uint32_t bits;
      std::memcpy(&bits, &v, 4);
      put_u32(p, bits);
      p += 4;
    } else {
      const std::uint16_t bits = float_to_half(v);
      p[0] = static_cast<std::uint8_t>(bits);
      p[1] = static_cast<std::uint8_t>(bits >> 8);
      p += 2;
    }
  }
  return out;
}

void write_dds(const std::string& path, std::size_t width, std::size_t height,
               std::span<const float> rgba, DdsFormat format) {
  image_detail::write_bytes(path, encode_dds(width, height, rgba, format));
}

}  // namespace shaderfit
