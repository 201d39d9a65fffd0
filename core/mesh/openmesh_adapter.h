// SPDX-License-Identifier: MIT
// The one place that knows OpenMesh: the core's Mesh is converted to an OpenMesh TriMesh (a
// half-edge structure) to walk boundary loops. No OpenMesh type appears in this header.
#pragma once
#include <cstddef>

#include "mesh/mesh.h"

namespace omnislice {

struct HalfedgeBoundary {
  size_t boundaryLoops = 0;      // closed chains of boundary half-edges (holes)
  size_t boundaryHalfedges = 0;  // half-edges with no face on their side
  size_t rejectedFaces = 0;      // faces OpenMesh refused (non-manifold edge or vertex, degenerate)
};

// Build an OpenMesh TriMesh from mesh (all vertices, faces in order) and count its boundary loops
// by following next-half-edge links around each hole. Faces OpenMesh cannot insert without breaking
// its half-edge invariants are skipped and counted: evidence of non-manifoldness, and the loops are
// then those of the accepted faces. Faces with a repeated vertex index are rejected without being
// offered to OpenMesh. OpenMesh's own error log is muted while building.
// Precondition: every index < mesh.vertexCount().
HalfedgeBoundary countBoundaryLoops(const Mesh& mesh);

}  // namespace omnislice
