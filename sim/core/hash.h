// Stable content hashes (FNV-1a 64) for cache keys and sweep-cell ids.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

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

// XXH64 (OpenImageIO's implementation) of a byte range, chained through `seed`: fast enough for
// the content of whole scenes and cached images (sim/core/disk_cache.h).
uint64_t content_hash(const void* data, size_t bytes, uint64_t seed = 0);

// Incremental content hash: every added value (with the length of strings and arrays) goes
// through content_hash in turn. pod() and vec() take types without padding bytes only.
class ContentHasher {
 public:
  ContentHasher& bytes(const void* p, size_t n) {
    h_ = content_hash(p, n, h_);
    return *this;
  }
  template <class T>
  ContentHasher& pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    return bytes(&v, sizeof v);
  }
  ContentHasher& str(std::string_view s) {
    pod(uint64_t(s.size()));
    return bytes(s.data(), s.size());
  }
  template <class T>
  ContentHasher& vec(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod(uint64_t(v.size()));
    return bytes(v.data(), v.size() * sizeof(T));
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 0x9e3779b97f4a7c15ull;
};

}  // namespace fovsim
