// The library's one hash of bytes (internal): FNV-1a, 64 bits. Stable across builds and
// machines, so files may record it: checkpoints (the data and the body's checksum) and the batch
// manifest's entries (which results a resumed batch may keep).
#pragma once

#include <cstdint>
#include <string_view>

namespace shaderfit::core_detail {

inline std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ULL) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

}  // namespace shaderfit::core_detail
