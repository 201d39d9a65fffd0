// SPDX-License-Identifier: MIT
// What printing needs of a multi-directional decomposition's parts (paper 000): the solid each
// part is sliced from, reaching across the planes of the parts printed after it, and the Eq. 1
// risky flags of the model's faces before (along +Z) and after the decomposition.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/status.h"
#include "mesh/clip_mesh.h"
#include "mesh/mesh.h"

namespace omnislice {

// The solid a part is sliced from: its piece of the model (above its own plane, planeIndex; the
// platform part, planeIndex < 0, has none) reaching across every plane that bounds it from above
// (the planes clipped before its own: their parts print after it) by delta = halfHeightScale
// (1 - |n . d|), d its direction, n that plane's normal (multidir_parts.cpp says why). The pieces
// overlap by delta. `reaching` stays empty when no plane bounds the part; deepest = the largest
// delta of a plane that crosses the part's reach (0 if none).
Outcome reachAcross(const Mesh& model, const std::vector<Plane>& planes, int planeIndex, const Eigen::Vector3d& d,
                    double halfHeightScale, Mesh& reaching, double& deepest);

// Risky flags per triangle of part (Eq. 1, 1 = risky): along +Z on the platform (before) and
// along the direction of the part the centroid falls in (after): the first plane in clipping order
// whose above side (n . c >= d) holds it, else the platform part (+Z). Faces whose centroid lies
// below bandMm are on the platform: never risky along +Z. Degenerate faces are never risky.
void riskyFlags(const Mesh& part, const std::vector<Plane>& planes, double alphaMaxDeg, double bandMm,
                std::vector<uint8_t>& riskyBefore, std::vector<uint8_t>& riskyAfter);

}  // namespace omnislice
