// SPDX-License-Identifier: MIT
// Placement of a mesh on the platform: scale (or fit), up axis, rotations, the drop to z = 0 and
// the centring, as one transform from the input file's coordinates to the part frame.
#pragma once
#include <Eigen/Core>

#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

enum class UpAxis { PosZ, NegZ, PosY, NegY, PosX, NegX };

struct PlaceOptions {
  double scale = 1.0;          // uniform factor applied first; must be > 0
  double fitMm = 0;            // > 0: scale so the largest bbox side equals this (overrides scale)
  UpAxis up = UpAxis::PosZ;    // which input axis points up on the platform
  double rotateXDegrees = 0;   // extra rotation after the up-axis change, about part X, then Y, then Z
  double rotateYDegrees = 0;
  double rotateZDegrees = 0;
  bool center = true;          // centre the bbox on (0,0) in XY (else keep XY as read)
};

struct PlaceMeshResult : Outcome {
  Mesh mesh;                  // in the part frame: lowest point at z = 0, centred in XY if asked
  Eigen::Matrix4d transform;  // input-file coordinates -> part frame (homogeneous, row-major use)
};

// Apply PlaceOptions: scale (or fit largest side to fitMm), up-axis change, rotations X,Y,Z,
// then translate so min z = 0 and (if center) bbox centre at x = y = 0. InvalidOption for
// scale <= 0, fitMm < 0, non-finite values or a result that overflows; EmptyInput without
// vertices; NonFiniteVertex; DegenerateInput when fitting a zero-size mesh. Orientation
// (outwardness) is preserved (a mirror never happens). Up axis: PosY turns input +Y into +Z by
// +90 degrees about X, NegY by -90 about X, PosX by -90 about Y, NegX by +90 about Y, NegZ by 180
// about X. Rotations are about the fixed part axes, X first. The output vertices equal
// transform * (input, 1) up to rounding (~1e-16 relative); min z is exactly 0.
PlaceMeshResult placeMesh(const Mesh& mesh, const PlaceOptions& placement);

}  // namespace omnislice
