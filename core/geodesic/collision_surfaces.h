// SPDX-License-Identifier: MIT
// The nozzle's collision model over the IGDS (paper 002 Section 3.1): its bounding cone swept over
// each IGDS (Fig. 15) and the potential collision surfaces of every node (Algorithm 2).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "geodesic/skeleton_tree.h"
#include "surface/surface_layers.h"

namespace omnislice {

// The nozzle as its bounding cone (Fig. 15a): apex at the tip, axis along the IGDS normal,
// half-angle angleDegrees (the paper's nozzle angle), length length; points within clearance
// along the axis above the tip are ignored (the bead being laid).
struct CollisionConeOptions {
  double angleDegrees = 45;   // (0, 90)
  double length = 25;         // mm, > 0
  double clearance = 0.3;     // mm, >= 0
  double sampleSpacing = 1.0; // mm, > 0: points tested on each IGDS (vertices, open-boundary
                              // samples, and a grid on triangles longer than 2 sampleSpacing;
                              // at most 64 samples per edge, 16 per triangle side)
  size_t threads = 1;         // nodes tested side by side (common/parallel.h; the same model on any)
};

struct CollisionModel : Outcome {
  // pcs[i]: the potential collision surfaces of node i (Algorithm 2): the other nodes with a test
  // point inside the envelope volume of the cone swept over node i, closed as in Fig. 15: the
  // ring-like ruled surface of the cones along the IGDS's boundary on the sides, the IGDS itself
  // below, the cone length on top. Tested as the union of the IGDS's normal offset up to the cone
  // length (faces, creases, vertex fans) and the cones along its open boundary (axis: the
  // boundary vertices' normals); on a flat IGDS this is exactly the union of the cones placed at
  // all its points. Sorted ascending.
  std::vector<std::vector<uint32_t>> pcs;
  size_t pairsTested = 0;   // node pairs whose bounding volumes met (others skipped)
  size_t foldedFaces = 0;   // IGDS faces whose normal opposes the sum of their corners' vertex
                            // normals (flipped by remeshing): no nozzle direction, left out
  double ms = 0;
};

// The exact inside rule and the culling (hierarchies with spheres, normal cones and slabs, dual
// traversal, early exit) are stated in collision_surfaces.cpp; tests compare it with a brute force.
// Options: angle in (0, 90), length > 0, clearance in [0, length), sampleSpacing > 0.
// Measured native (CPU time; cone length 25 mm): 300 curved IGDS of 1,024 vertices on three
// leaning branches 0.6 s at 15 deg, 1.0 s at 45 deg, 1.8-2.0 s at 75 deg (about half of all pairs
// collide there); 136 marching-tets IGDS of the test tree 60-180 ms; 1,896 IGDS of
// compas_branches_16 (56k tets) 0.4 s at 15 deg, 0.65 s at 45 deg.
// Statuses: InvalidOption (options out of range, tree not built from these layers, malformed
// region mesh), Cancelled (progress stage "collision").
CollisionModel potentialCollisionSurfaces(const std::vector<CurvedLayer>& layers,
                                          const SkeletonTree& tree,
                                          const CollisionConeOptions& options = {},
                                          const ProgressFn& progress = {});

}  // namespace omnislice
