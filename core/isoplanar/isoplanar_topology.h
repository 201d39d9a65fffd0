// SPDX-License-Identifier: MIT
// Internal to the iso-planar NL curves (isoplanar_paths.cpp): the surface's edges, triangle-edge
// incidence and ordered boundary loops, which the plane sweep cuts and the joins walk along.
#pragma once
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace omnislice::isoplanar_detail {

constexpr uint32_t kNone = 0xffffffffu;

// Edges, triangle-edge incidence and ordered boundary loops of the surface.
struct Topology {
  std::vector<uint32_t> tris;       // kept (non-degenerate) triangles, 3 vertices each
  std::vector<uint32_t> triEdge;    // per kept triangle: edges v0v1, v1v2, v2v0
  std::vector<uint32_t> ea, eb;     // edge endpoints, ea < eb
  std::vector<uint8_t> faces;       // triangles per edge (saturating)
  std::vector<std::vector<uint32_t>> loops;  // boundary loops: vertices in order
  std::vector<std::vector<double>> loopCum;  // arc length at loop vertex i (closed: size m + 1)
  std::vector<uint8_t> loopClosed;
  std::vector<uint32_t> edgeLoop, edgeLoopIndex;  // boundary edge -> loop, index of its segment
  std::vector<uint8_t> edgeForward;                // loop walks the edge from ea to eb
};

// Edges and boundary loops. Bit-identical positions are welded first (an unwelded layer mesh
// cuts like the welded one; indices stay those of the mesh, the first of equal vertices).
// Edges of more than two triangles are kept (the cut pairs their triangles in order).
void buildTopology(const Mesh& mesh, Topology& topo);

}  // namespace omnislice::isoplanar_detail
