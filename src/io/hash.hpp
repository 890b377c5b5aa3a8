#pragma once
// A content hash that is the same on every platform and standard library (std::hash is not):
// 64-bit FNV-1a, printed as 16 hex digits. Keys resume files; not for security.
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace millwear::io {

inline std::uint64_t fnv1a_64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;  // FNV offset basis
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;  // FNV prime
  }
  return h;
}

inline std::string stable_hash_hex(std::string_view bytes) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(fnv1a_64(bytes)));
  return buf;
}

}  // namespace millwear::io
