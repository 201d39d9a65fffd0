// SPDX-License-Identifier: MIT
// Union-find over 0..n-1 with path halving; the smaller index becomes the root, so roots are
// deterministic. Used for shells, layer regions, boundary loops and contour cells.
#pragma once
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace omnislice {

struct DisjointSets {
  std::vector<uint32_t> parent;
  explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) parent[b] = a;
    else parent[a] = b;
  }
};

}  // namespace omnislice
