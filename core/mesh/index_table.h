// SPDX-License-Identifier: MIT
// Open-addressing hash set of uint32 ids whose keys live outside the table (vertex positions,
// sorted face triples, packed edge keys). Used by welding and topology so that every step stays
// linear: one probe sequence per element, no node allocation, no std::map per edge.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace omnislice {

// 64-bit mixer (splitmix64 finaliser): spreads nearby keys over the whole table.
inline uint64_t mixHash64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

class IndexTable {
 public:
  static constexpr uint32_t kEmpty = 0xFFFFFFFFu;

  // Room for at most maxEntries ids (load factor stays <= 1/2).
  explicit IndexTable(size_t maxEntries) {
    size_t capacity = 16;
    while (capacity < 2 * maxEntries) capacity <<= 1;
    slots_.assign(capacity, kEmpty);
    mask_ = capacity - 1;
  }

  // Returns the id already stored whose key equals id's key (same(existing) is true), or stores
  // id and returns it. hash must be the same for equal keys.
  template <class Same>
  uint32_t findOrInsert(uint64_t hash, uint32_t id, Same same) {
    size_t slot = static_cast<size_t>(hash) & mask_;
    while (true) {
      const uint32_t existing = slots_[slot];
      if (existing == kEmpty) {
        slots_[slot] = id;
        return id;
      }
      if (same(existing)) return existing;
      slot = (slot + 1) & mask_;
    }
  }

  // Returns the stored id whose key matches (same(existing) true), or kEmpty.
  template <class Same>
  uint32_t find(uint64_t hash, Same same) const {
    size_t slot = static_cast<size_t>(hash) & mask_;
    while (true) {
      const uint32_t existing = slots_[slot];
      if (existing == kEmpty || same(existing)) return existing;
      slot = (slot + 1) & mask_;
    }
  }

 private:
  std::vector<uint32_t> slots_;
  size_t mask_ = 0;
};

}  // namespace omnislice
