// SPDX-License-Identifier: MIT
// Volume and area of a triangle mesh.
#pragma once
#include "mesh/mesh.h"

namespace omnislice {

// Signed volume (mm^3) enclosed by the triangles, by the divergence theorem: positive for a closed
// solid oriented outward, independent of the origin for closed meshes (summed about the bounding
// box centre to limit rounding); 0 for a mesh without triangles. Precondition: every index <
// vertexCount().
double signedVolume(const Mesh& mesh);

// Total triangle area (mm^2). Precondition: every index < vertexCount().
double surfaceArea(const Mesh& mesh);

}  // namespace omnislice
