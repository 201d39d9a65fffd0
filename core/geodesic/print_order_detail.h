// SPDX-License-Identifier: MIT
// Internal to the print order of the IGDS (skeleton_tree.cpp, collision_surfaces.cpp): the small
// helpers both use on region meshes.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "surface/surface_layers.h"

namespace omnislice::print_order_detail {

// Closest point of p to segment [a, b].
inline Eigen::Vector3d closestOnSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                        const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  if (l2 <= 0) return a;
  const double t = std::clamp((p - a).dot(ab) / l2, 0.0, 1.0);
  return a + t * ab;
}

// An undirected edge (a, b) as one key: the smaller index in the high 32 bits.
inline uint64_t edgeKey(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(a) << 32) | b;
}

// A region mesh whose arrays are triples, indices in range and coordinates finite.
inline bool regionValid(const LayerRegion& r) {
  const size_t n = r.mesh.vertexCount();
  if (r.mesh.positions.size() % 3 || r.mesh.triangles.size() % 3) return false;
  for (uint32_t v : r.mesh.triangles)
    if (v >= n) return false;
  for (double x : r.mesh.positions)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace omnislice::print_order_detail
