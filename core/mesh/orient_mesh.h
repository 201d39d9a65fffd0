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
  size_t cavities = 0;                  // closed components kept inward: nested inside another
  size_t nestingUnchecked = 0;          // components whose nesting was not tested (budget)
};

// Orientation repair. Consistency: breadth-first over two-face edges from the lowest face of each
// component, flipping a neighbour whose shared edge runs the same direction; the minority of each
// component is flipped. Outward: each closed, orientable component gets a positive signed volume
// unless it lies inside an odd number of other closed components (then it is a cavity and gets a
// negative one), so hollow parts keep their voids. Nesting is tested with the generalised winding
// number of a few face centroids, only where bounding boxes nest. edges = buildEdges(mesh).
OrientResult orientMesh(const Mesh& mesh, const MeshEdges& edges, const OrientOptions& options = {});

}  // namespace omnislice
