// SPDX-License-Identifier: MIT
// Closest point of a segment and point-segment distances: one definition for the AABB tree, the
// motion planner's chord checks, the program replay and verification.
#pragma once
#include <Eigen/Core>
#include <algorithm>

namespace omnislice {

// Closest point to p on segment [a, b] (a when the segment is degenerate).
inline Eigen::Vector3d closestPointOnSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                             const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0)) return a;
  return a + std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) * ab;
}

// Squared distance from p to segment [a, b].
inline double pointSegmentDistance2(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b) {
  return (closestPointOnSegment(p, a, b) - p).squaredNorm();
}

}  // namespace omnislice
