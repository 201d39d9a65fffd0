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
};

struct SelfIntersectionResult : Outcome {
  size_t count = 0;     // intersecting face pairs found (<= cap when cap > 0)
  bool capped = false;  // the search stopped at the cap: there may be more
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
