// SPDX-License-Identifier: MIT
// Open-addressing hash set of uint32 ids whose keys live outside the table (vertex positions,
// sorted face triples). Each slot keeps 32 bits of the key's hash next to the id, so a probe
// rarely touches the key itself, and the table grows with the number of distinct keys (not with
// the number of lookups): welding 3M STL corners into 0.5M vertices keeps the table in cache.
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

  // expectedEntries only sizes the first allocation; the table doubles when half full.
  explicit IndexTable(size_t expectedEntries = 0) { allocate(capacityFor(expectedEntries)); }

  // Returns the id already stored whose key equals id's key (same(existing) is true), or stores
  // id and returns it. hash must be the same for equal keys.
  template <class Same>
  uint32_t findOrInsert(uint64_t hash, uint32_t id, Same same) {
    const uint32_t tag = static_cast<uint32_t>(hash);
    size_t slot = tag & mask_;
    while (true) {
      Slot& s = slots_[slot];
      if (s.id == kEmpty) {
        s.id = id;
        s.tag = tag;
        if (++size_ * 2 > slots_.size()) grow();
        return id;
      }
      if (s.tag == tag && same(s.id)) return s.id;
      slot = (slot + 1) & mask_;
    }
  }

  // Returns the stored id whose key matches (same(existing) true), or kEmpty.
  template <class Same>
  uint32_t find(uint64_t hash, Same same) const {
    const uint32_t tag = static_cast<uint32_t>(hash);
    size_t slot = tag & mask_;
    while (true) {
      const Slot& s = slots_[slot];
      if (s.id == kEmpty || (s.tag == tag && same(s.id))) return s.id;
      slot = (slot + 1) & mask_;
    }
  }

 private:
  struct Slot {
    uint32_t id;
    uint32_t tag;  // low 32 bits of the hash; also the home slot after growth
  };

  static size_t capacityFor(size_t entries) {
    size_t capacity = 16;
    while (capacity < 2 * entries) capacity <<= 1;
    return capacity;
  }

  void allocate(size_t capacity) {
    slots_.assign(capacity, Slot{kEmpty, 0});
    mask_ = capacity - 1;
  }

  void grow() {
    std::vector<Slot> old;
    old.swap(slots_);
    allocate(old.size() * 2);
    for (const Slot& s : old) {
      if (s.id == kEmpty) continue;
      size_t slot = s.tag & mask_;
      while (slots_[slot].id != kEmpty) slot = (slot + 1) & mask_;
      slots_[slot] = s;
    }
  }

  std::vector<Slot> slots_;
  size_t mask_ = 0;
  size_t size_ = 0;
};

}  // namespace omnislice
