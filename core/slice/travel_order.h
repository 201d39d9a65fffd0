// SPDX-License-Identifier: MIT
// Internal to core/slice: nearest-item queries for travel ordering. Each item (a wall loop, a fill
// line, an island) is represented by a few probe points; a uniform grid over the probes answers
// "nearest probe of an item not yet taken" in about constant time, so greedy nearest-neighbour
// ordering of n items costs O(n) queries instead of O(n^2) distance scans.
#pragma once
#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace omnislice {

class NearestIndex {
 public:
  // probes[i]: probe points of item i (an item without probes is never returned).
  explicit NearestIndex(const std::vector<std::vector<Eigen::Vector2d>>& probes);

  struct Hit {
    size_t item = 0;   // item index
    size_t probe = 0;  // index of the probe within the item's list
    bool found = false;
  };
  // Nearest probe to `from` among items not yet taken (exact over the probes).
  Hit nearest(const Eigen::Vector2d& from) const;
  // Marks an item as taken: its probes are skipped from now on.
  void take(size_t item);

 private:
  struct Probe {
    Eigen::Vector2d p;
    size_t item;
    size_t index;
  };
  std::vector<Probe> probes_;       // sorted by cell
  std::vector<size_t> cellStart_;   // CSR offsets into probes_, nx_ * ny_ + 1 entries
  std::vector<char> taken_;
  Eigen::Vector2d origin_{0, 0};
  double cell_ = 1;
  long nx_ = 0, ny_ = 0;
};

}  // namespace omnislice
