// SPDX-License-Identifier: MIT
// Refinement and fairing of the triangulation that closes a hole (mesh/repair_mesh.h): the patch
// gets interior points at about the spacing of its rim and is bent to continue the surface around
// it (a bi-Laplacian fill, as in Liepa's "Filling holes in meshes", with uniform weights).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace omnislice {

struct HolePatch {
  std::vector<Eigen::Vector3d> points;              // the loop's points first (fixed), then new ones
  std::vector<std::array<uint32_t, 3>> triangles;   // indices into points, running the loop's way
};

// loopSize: the first loopSize points are the hole's rim, in order. outerRing[i]: positions of the
// mesh's neighbours of rim point i outside the patch (the surface the fill continues).
// (1) Interior edges longer than sqrt(2) x the mean rim edge are split at their midpoint (both
// triangles on the edge split in two), longest first, until none is or the patch has 16x its
// triangles. (2) The new points solve L(L(x)) = 0 (uniform umbrella Laplacian L; at rim points L
// also takes the outer ring) with the rim and the ring fixed: a sparse LU solve. The rim is never
// split, so the patch still meets the mesh edge to edge. Returns the patch unchanged when nothing
// is to be refined or the solve fails.
HolePatch refineAndFair(HolePatch patch, size_t loopSize, const std::vector<std::vector<Eigen::Vector3d>>& outerRing);

}  // namespace omnislice
