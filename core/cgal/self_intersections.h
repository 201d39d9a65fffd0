// SPDX-License-Identifier: MIT
// Self-intersection test of an indexed triangle mesh (CGAL behind a plain-data interface).
#pragma once
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct SelfIntersectionOptions {
  size_t cap = 1000;         // stop after this many intersecting pairs (0 = find all)
  bool collectPairs = true;  // fill result.pairs (face indices, first < second)
  // Faces lying exactly in one axis plane (their points share a coordinate bitwise, as the flat
  // faces of CAD parts and tet boundaries do) are decided by exact 2D orientations (a static
  // error bound, else an fma expansion) before CGAL, collinear cases included (rays along one
  // line, a face on another's edge line: exact 1D comparisons): CGAL's filters fail on exact
  // zeros and fall back to exact arithmetic through a thrown exception, which in wasm (no GMP)
  // made the Yoga .tet's check 0.25-0.5 s against 13 ms native, and a 100k-face CAD box 8.6 s.
  // Other pairs go through exact orientations in plain doubles first (a static filter, else an
  // fma expansion): a face strictly on one side of the other's plane (but for shared corners) is
  // apart; faces in one inclined plane (flat regions of CAD parts, the planar quads of a saddle)
  // are decided in 2D in the axis pair onto which they project, as above; a face touching the
  // other's plane, and faces sharing a vertex that cross each other's planes, by orientations
  // too. CGAL decides the rest (faces without a common corner crossing each other's planes).
  // false = CGAL for every pair (the reference in tests).
  bool planarShortcuts = true;
};

struct SelfIntersectionResult : Outcome {
  size_t count = 0;     // intersecting face pairs found (<= cap when cap > 0)
  bool capped = false;  // the search stopped at the cap: there may be more
  size_t candidates = 0;     // face pairs whose boxes overlap (tested)
  size_t planarDecided = 0;  // of those, decided by the axis-plane shortcuts
  size_t orientDecided = 0;  // decided by the exact orientations (after CGAL's box test)
  std::vector<std::pair<uint32_t, uint32_t>> pairs;  // when collectPairs, sorted
};

// Find pairs of faces that intersect, with CGAL's box_intersection_d on the face bounding boxes
// and exact predicates (Exact_predicates_inexact_constructions_kernel) on candidate pairs.
// Faces that share vertex indices are adjacent, not intersecting, unless they overlap beyond what
// they share: two faces on a common edge intersect only when coplanar and folded onto each other;
// two faces on a common vertex intersect when an edge of one meets the other away from it.
// Faces with the same three vertices count as intersecting. Degenerate (collinear) faces are
// ignored. progress gets stage "validate" with fractions in [from, to]; a false return gives
// Cancelled. CGAL exceptions give Internal. Precondition: indices < vertexCount(), finite points.
SelfIntersectionResult findSelfIntersections(const Mesh& mesh, const SelfIntersectionOptions& options = {},
                                             const ProgressFn& progress = {}, double from = 0,
                                             double to = 1);

}  // namespace omnislice
