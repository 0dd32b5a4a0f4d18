#pragma once
// A 64-bit content hash of a scene's input (topology and every frame's positions), stored
// in results files so `cdbench compare` can tell two runs of "the same" scene name apart
// when the frames differ (another descriptor version, another generator build). Not
// cryptographic: it only has to make accidental equality unlikely.
//
// FNV-1a over 64-bit words instead of bytes: one multiply per 8 bytes keeps a frame of a
// million-triangle sequence (~12 MB of doubles) at a few milliseconds, and the splitmix64
// finalizer mixes the high bits that word-wise FNV leaves weak.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace cdb {

class ContentHash {
 public:
  void add(uint64_t word) { h_ = (h_ ^ word) * kPrime; }
  // The bytes as whole 64-bit words, the tail zero-padded; the length goes in too, so
  // "ab" and "ab\0" differ.
  void add_bytes(const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
      uint64_t w;
      std::memcpy(&w, p + i, 8);
      add(w);
    }
    if (i < bytes) {
      uint64_t w = 0;
      std::memcpy(&w, p + i, bytes - i);
      add(w);
    }
    add(uint64_t(bytes));
  }
  uint64_t value() const {
    uint64_t z = h_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }

 private:
  static constexpr uint64_t kOffset = 0xcbf29ce484222325ull, kPrime = 0x100000001b3ull;
  uint64_t h_ = kOffset;
};

// 16 lower-case hex digits: how results files store a hash (HDF5 and JSON readers differ
// on unsigned 64-bit integers; text compares the same everywhere).
inline std::string hash_hex(uint64_t h) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

}  // namespace cdb
