// SPDX-License-Identifier: MIT
// Triangulation of planar regions bounded by closed loops (outer contours with holes, islands in
// holes) using only the loops' own points: ear clipping after bridging each hole into its
// contour, with a uniform grid for the ear tests. Used for the caps of a clipped solid.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/status.h"

namespace omnislice {

struct TriangulateOptions {
  double minArea = 0;  // mm^2; ears of this area or less are cut only when no larger ear is
                       // left (keeps slivers out of a mesh checked for degenerate faces); 0 =
                       // only nearly straight corners (sine of the turn < 1e-12) wait
  // Point-index pairs (either order) that should not become triangle edges, e.g. edges a mesh
  // closed by the triangles already has: used only where no other ear is left. Empty = none.
  std::vector<std::array<uint32_t, 2>> avoidEdges;
};

struct PolygonTriangulation : Outcome {
  std::vector<uint32_t>
      triangles;               // #T*3 point indices, counter-clockwise (orphan holes: clockwise)
  size_t outerLoops = 0;       // loops with signed area >= 0
  size_t holeLoops = 0;        // loops with signed area < 0, each placed in an outer loop
  size_t orphanHoles = 0;      // clockwise loops inside no outer loop: triangulated on their
                               // own with clockwise triangles (0 for consistent input)
  size_t skippedLoops = 0;     // loops of fewer than 3 points (left out)
  size_t forcedTriangles = 0;  // triangles cut where no valid ear was left (numerically
                               // degenerate input: zero-length edges, crossing loops); 0
                               // for a valid region
  double area = 0;             // mm^2, sum of the signed areas of the triangles
};

// Triangulate the region bounded by loops. points: #P 2D points (mm); loops: closed point-index
// cycles (the last point connects back to the first), counter-clockwise for outer contours and
// clockwise for holes, the region on the left of every edge. Loops may share points (touching at
// a vertex) and contain straight (collinear) vertices, but must not cross. Each hole goes to the
// smallest outer loop containing it. Only the given points are used (no Steiner points), and every
// directed loop edge a->b appears in exactly one output triangle running a->b (unless b->a is a
// loop edge too: then the two may pair with each other), while every other triangle edge appears
// twice in opposite directions, whatever the geometry: a mesh closed by these triangles stays
// closed. An outer loop of k points with h holes of k_1..k_h points gives k + sum k_i + 2h - 2
// triangles (2 fewer per hole touching the contour). Cost: O(n log n) typical, O(n^2) worst case
// for n points (natively ~10 ms for 13k points with 129 holes). Statuses: InvalidOption (index
// out of range, non-finite point, negative or non-finite options.minArea).
PolygonTriangulation triangulatePolygons(const std::vector<Eigen::Vector2d>& points,
                                         const std::vector<std::vector<uint32_t>>& loops,
                                         const TriangulateOptions& options = {});

}  // namespace omnislice
