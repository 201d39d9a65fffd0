// SPDX-License-Identifier: MIT
// Edge structure of an indexed triangle mesh and the counts derived from it (shells, boundary and
// non-manifold edges, non-manifold vertices, orientation conflicts). Half-edge h = 3f + k runs
// from triangles[3f+k] to triangles[3f+(k+1)%3].
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace omnislice {

constexpr uint32_t kNoIndex = 0xFFFFFFFFu;

struct MeshEdges {
  std::vector<uint64_t> keys;             // per edge: (min vertex << 32) | max vertex
  std::vector<uint32_t> faceCount;        // per edge: half-edges (faces) using it
  std::vector<uint32_t> firstHalfedge;    // per edge: first half-edge using it
  std::vector<uint32_t> nextHalfedge;     // per half-edge: next half-edge on the same edge, or kNoIndex
  std::vector<uint32_t> edgeOfHalfedge;   // per half-edge: its edge

  size_t edgeCount() const { return keys.size(); }
};

// Build the undirected edges of mesh, sorted by key, in linear time (counting sort of the
// half-edges by their smaller vertex). Half-edges of one edge are listed in increasing order.
// Precondition: every index < vertexCount().
MeshEdges buildEdges(const Mesh& mesh);

struct TopologyCounts {
  size_t shells = 0;               // edge-connected components of faces
  size_t boundaryEdges = 0;        // edges with one face
  size_t nonManifoldEdges = 0;     // edges with more than two faces
  size_t nonManifoldVertices = 0;  // vertices whose incident faces form several fans
  size_t misorientedEdges = 0;     // two-face edges whose faces run the edge the same way
};

// Counts above for mesh and its edges (from buildEdges(mesh)).
TopologyCounts countTopology(const Mesh& mesh, const MeshEdges& edges);

struct FaceComponents {
  std::vector<uint32_t> label;  // per face: component id, 0 .. count-1, numbered by lowest face
  size_t count = 0;
};

// Edge-connected components of faces (faces sharing any edge, manifold or not, are connected).
FaceComponents edgeComponents(const Mesh& mesh, const MeshEdges& edges);

// Each edge-connected component (shell) of mesh as its own mesh, in the order of edgeComponents;
// each keeps only its referenced vertices, in increasing order of their old index (a vertex where
// shells touch is copied into each). With groupCavities, a shell of negative signed volume (an
// inward cavity of a closed solid) stays with the smallest shell of positive volume containing
// it (winding number at one of its face centroids), so each mesh is one solid; a cavity inside no
// such shell stays alone. Cost O(F) plus O(F) per cavity. Precondition: indices < vertexCount().
std::vector<Mesh> splitComponents(const Mesh& mesh, bool groupCavities = false);

}  // namespace omnislice
