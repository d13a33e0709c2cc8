// Writing a byte buffer to a file, with shaderfit's error on failure.
#pragma once

#include <cstdint>
#include <fstream>
#include <span>
#include <string>

#include "shaderfit/core/error.hpp"

namespace shaderfit::image_detail {

inline void write_bytes(const std::string& path, std::span<const std::uint8_t> bytes) {
  std::ofstream f(path, std::ios::binary);
  if (f)
    f.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!f) throw Error("cannot write '" + path + "'", SourceLocation{path});
}

inline void put_u32(std::uint8_t* p, std::uint32_t v) {  // little-endian
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

}  // namespace shaderfit::image_detail
