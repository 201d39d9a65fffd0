// SPDX-License-Identifier: MIT
// Internal to the multidir decomposition: the candidate normals of the plane search (paper 000
// Section IV samples the printing directions): the Fibonacci sphere within the tilt range (5dof),
// the great circle about the rotary axis (4dof), and the nearby normals the refinement tries.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "multidir/decomposition.h"

namespace omnislice::decomposition_detail {

// The Fibonacci sphere of o.samples points turned by `phase` (radians) about Z, within the tilt
// range (or o.candidateNormals as given, within it).
std::vector<Eigen::Vector3d> sphereNormals(const MultidirOptions& o, double phase);

// Normals n(theta) = cos(theta) Z + sin(theta) (r x Z) on the great circle n . r = 0, theta a
// multiple of the stepper angle (or of 360/samples), |theta| <= rangeDeg.
std::vector<Eigen::Vector3d> circleNormals(const MultidirOptions& o, const Eigen::Vector3d& r);

// Normals near n that the machine can realise: rings up to 12 deg (5dof, within maxTiltDeg), or
// rotations near n's about the axis (4dof: +-0.5..6 deg, or +-1..3 stepper steps, within range).
// None when o.candidateNormals is given.
std::vector<Eigen::Vector3d> nearbyNormals(const MultidirOptions& o, bool fourDof, const Eigen::Vector3d& axis,
                                           const Eigen::Vector3d& n);

}  // namespace omnislice::decomposition_detail
