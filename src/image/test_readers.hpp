// Minimal, independent readers for the files shaderfit writes (tests only): DDS (DX10 header,
// RGBA32F / RGBA16F), uncompressed scanline OpenEXR with FLOAT or HALF channels, and PNG with
// stored deflate blocks. Written from the format specifications, sharing no code with the writers
// (their own half decoding and CRC), so that a read-back checks the files, not the writer against
// itself. Each returns false with a reason on anything unexpected.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

namespace shaderfit::test_readers {

inline std::vector<std::uint8_t> slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

inline std::uint32_t le32(const std::uint8_t* p) {
  return p[0] | (p[1] << 8) | (p[2] << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
inline std::uint32_t be32(const std::uint8_t* p) {
  return (static_cast<std::uint32_t>(p[0]) << 24) | (p[1] << 16) | (p[2] << 8) | p[3];
}
inline float le_float(const std::uint8_t* p) {
  const std::uint32_t u = le32(p);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}
// binary16 by its definition: (-1)^s 2^(e-15) (1 + m/1024), subnormals 2^-14 m/1024.
inline float decode_half(std::uint16_t h) {
  const int s = h >> 15, e = (h >> 10) & 31, m = h & 1023;
  double v = e == 0    ? std::ldexp(m / 1024.0, -14)
             : e == 31 ? (m ? NAN : INFINITY)
                       : std::ldexp(1 + m / 1024.0, e - 15);
  return static_cast<float>(s ? -v : v);
}

struct Image {
  std::size_t width = 0, height = 0;
  std::vector<float> rgba;  // row 0 first
};

inline bool read_dds(const std::string& path, Image* img, std::uint32_t* dxgi, std::string* why) {
  const std::vector<std::uint8_t> b = slurp(path);
  if (b.size() < 148 || std::memcmp(b.data(), "DDS ", 4) != 0) return *why = "no DDS magic", false;
  const std::uint8_t* h = b.data() + 4;
  if (le32(h) != 124) return *why = "header size is not 124", false;
  img->height = le32(h + 8);
  img->width = le32(h + 12);
  if (le32(h + 72) != 32 || !(le32(h + 76) & 4) || std::memcmp(h + 80, "DX10", 4) != 0)
    return *why = "pixel format is not FourCC DX10", false;
  const std::uint8_t* x = h + 124;
  *dxgi = le32(x);
  if (le32(x + 4) != 3 || le32(x + 12) != 1) return *why = "not a single 2D texture", false;
  const std::size_t texel = *dxgi == 2 ? 16 : *dxgi == 10 ? 8 : 0;
  if (texel == 0) return *why = "unexpected DXGI format " + std::to_string(*dxgi), false;
  if (le32(h + 16) != img->width * texel) return *why = "pitch mismatch", false;
  const std::size_t n = img->width * img->height * 4;
  if (b.size() != 148 + n * texel / 4) return *why = "file size mismatch", false;
  const std::uint8_t* p = x + 20;
  img->rgba.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    img->rgba[i] = texel == 16
                       ? le_float(p + 4 * i)
                       : decode_half(static_cast<std::uint16_t>(p[2 * i] | (p[2 * i + 1] << 8)));
  return true;
}

// Single-part scanline EXR, NO_COMPRESSION, channels of pixel type HALF (1) or FLOAT (2).
inline bool read_exr(const std::string& path, Image* img,
                     std::map<std::string, std::string>* strings, std::string* why) {
  const std::vector<std::uint8_t> b = slurp(path);
  if (b.size() < 8 || le32(b.data()) != 20000630u) return *why = "no EXR magic", false;
  if ((le32(b.data() + 4) & 0xff) != 2 || (le32(b.data() + 4) & 0x1e00) != 0)
    return *why = "not a version-2 single-part scanline file", false;
  std::size_t pos = 8;
  auto cstr = [&](std::string* s) {
    s->clear();
    while (pos < b.size() && b[pos] != 0) s->push_back(static_cast<char>(b[pos++]));
    return pos++ < b.size();
  };
  std::vector<std::pair<std::string, int>> channels;
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1, compression = -1;
  while (true) {
    std::string name, type;
    if (!cstr(&name)) return *why = "truncated header", false;
    if (name.empty()) break;
    if (!cstr(&type) || pos + 4 > b.size()) return *why = "truncated attribute", false;
    const std::uint32_t size = le32(&b[pos]);
    pos += 4;
    const std::uint8_t* v = &b[pos];
    if (name == "channels") {
      std::size_t q = pos;
      while (b[q] != 0) {
        std::string ch;
        while (b[q] != 0) ch.push_back(static_cast<char>(b[q++]));
        ++q;
        channels.emplace_back(ch, static_cast<int>(le32(&b[q])));
        q += 16;
      }
    } else if (name == "compression") {
      compression = v[0];
    } else if (name == "dataWindow") {
      x0 = static_cast<int>(le32(v)), y0 = static_cast<int>(le32(v + 4));
      x1 = static_cast<int>(le32(v + 8)), y1 = static_cast<int>(le32(v + 12));
    } else if (type == "string") {
      (*strings)[name] = std::string(reinterpret_cast<const char*>(v), size);
    }
    pos += size;
  }
  if (compression != 0) return *why = "compressed (" + std::to_string(compression) + ")", false;
  img->width = static_cast<std::size_t>(x1 - x0 + 1);
  img->height = static_cast<std::size_t>(y1 - y0 + 1);
  img->rgba.assign(img->width * img->height * 4, NAN);
  pos += 8 * img->height;  // the offset table: one block per scanline without compression
  for (std::size_t line = 0; line < img->height; ++line) {
    const int y = static_cast<int>(le32(&b[pos])) - y0;
    pos += 8;                                    // y, byte count
    for (const auto& [name, type] : channels) {  // stored in the header's (alphabetical) order
      const int c = name == "R" ? 0 : name == "G" ? 1 : name == "B" ? 2 : name == "A" ? 3 : -1;
      for (std::size_t x = 0; x < img->width; ++x) {
        const float v = type == 2
                            ? le_float(&b[pos])
                            : decode_half(static_cast<std::uint16_t>(b[pos] | (b[pos + 1] << 8)));
        pos += type == 2 ? 4 : 2;
        if (c >= 0)
          img->rgba[4 * (static_cast<std::size_t>(y) * img->width + x) +
                    static_cast<std::size_t>(c)] = v;
      }
    }
  }
  return pos == b.size() || (*why = "trailing bytes", false);
}

// PNG, 8-bit RGB, zlib stream of stored deflate blocks, every scanline with filter 0.
inline bool read_png(const std::string& path, std::size_t* w, std::size_t* h,
                     std::vector<std::uint8_t>* rgb, std::string* why) {
  const std::vector<std::uint8_t> b = slurp(path);
  const std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() < 8 || std::memcmp(b.data(), sig, 8) != 0) return *why = "no PNG signature", false;
  auto crc = [](const std::uint8_t* p, std::size_t n) {  // bit by bit, polynomial 0xEDB88320
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = 0; i < n; ++i) {
      c ^= p[i];
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
  };
  std::vector<std::uint8_t> z;
  for (std::size_t pos = 8; pos + 12 <= b.size();) {
    const std::uint32_t len = be32(&b[pos]);
    const std::string type(reinterpret_cast<const char*>(&b[pos + 4]), 4);
    if (crc(&b[pos + 4], len + 4) != be32(&b[pos + 8 + len]))
      return *why = "bad CRC in " + type, false;
    if (type == "IHDR") {
      *w = be32(&b[pos + 8]);
      *h = be32(&b[pos + 12]);
      if (b[pos + 16] != 8 || b[pos + 17] != 2) return *why = "not 8-bit RGB", false;
    }
    if (type == "IDAT") z.insert(z.end(), b.data() + pos + 8, b.data() + pos + 8 + len);
    pos += 12 + len;
  }
  if (z.size() < 6 || (z[0] & 0x0f) != 8 || ((z[0] << 8) | z[1]) % 31 != 0)
    return *why = "bad zlib header", false;
  std::vector<std::uint8_t> raw;
  std::size_t pos = 2;
  for (bool last = false; !last;) {
    last = z[pos] & 1;
    if ((z[pos] >> 1) != 0) return *why = "not a stored block", false;
    const std::size_t len = z[pos + 1] | (z[pos + 2] << 8);
    raw.insert(raw.end(), z.data() + pos + 5, z.data() + pos + 5 + len);
    pos += 5 + len;
  }
  std::uint32_t a = 1, s = 0;
  for (std::uint8_t v : raw) a = (a + v) % 65521, s = (s + a) % 65521;
  if (be32(&z[pos]) != ((s << 16) | a)) return *why = "bad Adler-32", false;
  if (raw.size() != *h * (1 + 3 * *w)) return *why = "wrong amount of pixel data", false;
  rgb->clear();
  for (std::size_t y = 0; y < *h; ++y) {
    if (raw[y * (1 + 3 * *w)] != 0) return *why = "unexpected filter", false;
    // Pointers, not &raw[i]: the last row ends at raw.size(), which operator[] may not index.
    rgb->insert(rgb->end(), raw.data() + y * (1 + 3 * *w) + 1, raw.data() + (y + 1) * (1 + 3 * *w));
  }
  return true;
}

}  // namespace shaderfit::test_readers
