// SPDX-License-Identifier: MIT
// Union of the closed shells of a mesh that overlap (CGAL's corefinement behind a plain-data
// interface).
#pragma once
#include <cstddef>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct ShellUnionOptions {
  // Shells in groups to unite larger than this many faces in all are left as they are (CGAL's
  // corefinement costs about 1 s per 100k faces natively, several times that in wasm).
  size_t maxFaces = 300000;
};

struct ShellUnionResult : Outcome {
  Mesh mesh;                 // the shells of the input, overlapping ones replaced by their union
  size_t shellsIn = 0;       // closed outward shells examined
  size_t shellsUnited = 0;   // shells that went into a union (groups x their members)
  size_t groups = 0;         // unions made (each replaces >= 2 shells by the surface of their union)
  size_t shellsLeft = 0;     // overlapping shells left as they were (their group too large, or
                             // CGAL could not unite them with the rest of it)
  double removedAreaMm2 = 0; // surface of the united shells that lay inside another (no longer there)
};

// Shells = edge-connected components (the mesh is expected closed, manifold and outward, as
// prepareMesh leaves a solid). Shells of positive volume whose surfaces intersect, or one of which
// lies inside another, are grouped (union-find over pairs with overlapping boxes, tested by
// Polygon_mesh_processing::do_intersect with the bounded-side test), and each group is replaced by
// the surface of the union of its volumes (corefine_and_compute_union, folded over the group).
// The output holds the united groups' faces first, then the faces of every other shell in their
// input order (so faces that trailed the input still trail it when their shell was not united).
// Inward shells (cavities) are never united. A member CGAL cannot unite with the rest of its
// group (it throws, e.g. on a shell that intersects itself, or the result is not closed, or its
// volume is not between the larger part's and the sum) is kept as it was, counted in shellsLeft. progress: stage "validate",
// fractions in [from, to]; false gives Cancelled. mesh is the input when nothing was united.
ShellUnionResult uniteOverlappingShells(const Mesh& mesh, const ShellUnionOptions& options = {},
                                        const ProgressFn& progress = {}, double from = 0, double to = 1);

}  // namespace omnislice
