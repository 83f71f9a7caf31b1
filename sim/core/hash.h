// Stable content hashes (FNV-1a 64) for cache keys and sweep-cell ids.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace fovsim {

inline uint64_t fnv1a64(std::string_view s, uint64_t h = 0xcbf29ce484222325ull) {
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}
std::string hex64(uint64_t v);               // 16 lowercase hex digits
std::string short_hash(std::string_view s);  // first 10 hex digits of fnv1a64

}  // namespace fovsim
