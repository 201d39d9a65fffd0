// SPDX-License-Identifier: MIT
// The voxel grid of paper 001 (Dai et al. 2018) Section 4.1: a regular grid of width w holding the
// solid H~ (H subset of H~), the printing platform T as a solid layer of cells below the part, and
// support cells added for missed regions. Plain data; every voxel-method stage reads it.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace omnislice {

// What one cell holds.
enum class VoxelState : uint8_t {
  Empty = 0,
  Solid = 1,     // the part: the cell's closed cube meets the input solid (conservative)
  Support = 2,   // support added below missed voxels (paper 001 Fig. 14c)
  Platform = 3,  // the printing platform T, one cell layer directly below the part
};

// Cell (i, j, k) spans origin + w * [i, i+1] x [j, j+1] x [k, k+1]. The platform plane z = 0 is a
// cell boundary: platform cells lie at k = platformK (z in [-w, 0]), part cells at k > platformK.
// The grid keeps at least two empty cells of margin around solid, support and platform cells, so
// every neighbour query of a non-empty cell stays in range.
struct VoxelGrid {
  Eigen::Vector3d origin{0, 0, 0};  // part frame, mm, corner of cell (0, 0, 0)
  double width = 0;                 // w, mm
  Eigen::Vector3i dims{0, 0, 0};    // cells along x, y, z
  int platformK = 0;                // k of the platform layer
  std::vector<uint8_t> state;       // VoxelState per cell, index() order

  size_t cellCount() const { return state.size(); }
  size_t index(int i, int j, int k) const {
    return static_cast<size_t>(i) + static_cast<size_t>(dims.x()) *
                                        (static_cast<size_t>(j) + static_cast<size_t>(dims.y()) *
                                                                      static_cast<size_t>(k));
  }
  Eigen::Vector3i cell(size_t index) const {
    const size_t nx = static_cast<size_t>(dims.x()), ny = static_cast<size_t>(dims.y());
    return {static_cast<int>(index % nx), static_cast<int>((index / nx) % ny),
            static_cast<int>(index / (nx * ny))};
  }
  bool inRange(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < dims.x() && j < dims.y() && k < dims.z();
  }
  Eigen::Vector3d center(int i, int j, int k) const {
    return origin + width * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
  }
  VoxelState at(int i, int j, int k) const { return static_cast<VoxelState>(state[index(i, j, k)]); }
  // Solid or Support: the cells the growing field must cover.
  bool printable(size_t index) const {
    return state[index] == static_cast<uint8_t>(VoxelState::Solid) ||
           state[index] == static_cast<uint8_t>(VoxelState::Support);
  }
};

// The 18 AM-stable-neighbour offsets of Definition 1 (L1 distance 1 or 2: 6 face + 12 edge
// neighbours), face neighbours first.
inline const std::vector<Eigen::Vector3i>& amStableOffsets() {
  static const std::vector<Eigen::Vector3i> offsets = [] {
    std::vector<Eigen::Vector3i> o;
    for (int l1 = 1; l1 <= 2; ++l1)
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (std::abs(dx) + std::abs(dy) + std::abs(dz) == l1) o.emplace_back(dx, dy, dz);
    return o;
  }();
  return offsets;
}

}  // namespace omnislice
