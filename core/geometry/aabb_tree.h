// SPDX-License-Identifier: MIT
// Bounding-volume hierarchy over the triangles of a mesh (double precision) for the queries
// verification needs: closest point / unsigned distance, "any triangle within r", inside test and
// the signed crossings of a vertical line (column) with the surface.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "mesh/mesh.h"

namespace omnislice {

struct ClosestPoint {
  double distance = std::numeric_limits<double>::infinity();  // mm; infinity when none found
  Eigen::Vector3d point{0, 0, 0};
  int64_t triangle = -1;  // face index, -1 when none
};

// One crossing of a vertical line with the surface: height z and sign +1 where the line enters
// the solid going up (the face looks down), -1 where it leaves (the face looks up).
struct ColumnCrossing {
  double z = 0;
  int sign = 0;
};

class AabbTree {
 public:
  // Builds the tree over mesh's triangles (index-out-of-range faces are skipped). O(F log F).
  explicit AabbTree(const Mesh& mesh);

  size_t triangleCount() const { return a_.size(); }

  // Closest point on the surface to p among points closer than maxDistance (mm). Returns
  // distance = infinity when no triangle is that close.
  ClosestPoint closest(const Eigen::Vector3d& p,
                       double maxDistance = std::numeric_limits<double>::infinity()) const;

  // True when some triangle lies within distance r of p (early exit; cheap far from the surface).
  bool anyWithin(const Eigen::Vector3d& p, double r) const;

  // Signed crossings of the vertical line through (x, y) with the surface, unsorted. Points on a
  // shared edge or vertex are assigned to exactly one side by a fixed half-open rule (as if the
  // line were shifted by an infinitesimal (e, e^2)), so a closed mesh gives consistent parity even
  // when the line hits edges exactly (grid points on axis-aligned models do).
  void columnCrossings(double x, double y, std::vector<ColumnCrossing>& out) const;

  // Winding number of the surface around p along the +Z ray: non-zero inside a closed oriented
  // solid (either orientation), 0 outside. Points exactly on the surface are undefined.
  int winding(const Eigen::Vector3d& p) const;
  bool inside(const Eigen::Vector3d& p) const { return winding(p) != 0; }

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int32_t left = -1, right = -1;  // children, -1 for a leaf
    int32_t first = 0, count = 0;   // leaf range in a_, b_, c_
  };
  struct BuildItem {
    Eigen::Vector3d centroid;
    int64_t face;
  };
  int32_t build(int32_t first, int32_t count, std::vector<BuildItem>& items, const Mesh& mesh);
  // Crossing of the vertical line through (x, y) with triangle t: z and sign, false if none.
  bool crossing(int32_t t, double x, double y, ColumnCrossing& out) const;
  // Visits the triangles of every leaf whose box holds (x, y) and reaches above zAbove.
  template <class Visit>
  void visitColumn(double x, double y, double zAbove, Visit&& visit) const;

  std::vector<Eigen::Vector3d> a_, b_, c_;  // triangle corners, grouped by leaf
  std::vector<int64_t> faceIndex_;          // original face index per triangle
  std::vector<Node> nodes_;
};

// Closest point to p on triangle (a, b, c) (handles degenerate triangles).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace omnislice
