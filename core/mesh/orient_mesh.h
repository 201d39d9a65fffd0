// SPDX-License-Identifier: MIT
// Consistent and outward orientation of an indexed triangle mesh.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"
#include "mesh/mesh_topology.h"

namespace omnislice {

struct OrientOptions {
  bool outward = true;     // also flip whole closed components whose volume has the wrong sign
  double nestingBudget = 5e7;  // triangle evaluations allowed for cavity detection (0 = skip)
};

struct OrientResult {
  std::vector<uint8_t> flip;            // per face: 1 = reverse it (apply to get the result)
  size_t components = 0;                // faces linked by two-face edges
  size_t nonOrientableComponents = 0;   // components with no consistent orientation (Moebius-like)
  size_t misorientedEdges = 0;          // two-face edges still running the same way after the
                                        // flips (0 unless a component is non-orientable)
  size_t reorientedFaces = 0;           // faces flipped to agree with their neighbours
  size_t outwardComponents = 0;         // closed components flipped as a whole
  size_t outwardFaces = 0;              // faces in those components
  size_t cavities = 0;                  // closed components nested in one of opposite orientation
  size_t nestedSameOrientation = 0;     // closed components nested in one of the same orientation
                                        // (the non-zero rule fills them: a union)
  size_t nestingUnchecked = 0;          // components whose nesting was not tested (budget)
};

// Orientation repair. Consistency: breadth-first over two-face edges from the lowest face of each
// component, flipping a neighbour whose shared edge runs the same direction; the minority of each
// component is flipped. Outward: closed, orientable components are arranged in nesting trees
// (container = smallest closed component holding a few of its face centroids, by generalised
// winding number, tested only where bounding boxes nest); a tree whose outermost component has a
// negative signed volume is flipped as a whole. Relative orientations are kept, so a correctly
// inward cavity stays a cavity and what the non-zero rule makes of nested shells never changes.
// edges = buildEdges(mesh).
OrientResult orientMesh(const Mesh& mesh, const MeshEdges& edges, const OrientOptions& options = {});

}  // namespace omnislice
