// SPDX-License-Identifier: MIT
// Orientation continuity of paper 001 Section 5.2: a low-pass filter on the nozzle axes of
// printing samples whose neighbours differ by more than a threshold, and the quaternion (slerp)
// interpolation used to subdivide moves across crests.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace omnislice {

// Angle between two unit vectors, degrees (robust near 0 and 180).
double axisAngleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// Spherical linear interpolation of unit vectors a -> b at t in [0, 1] (the rotation of the
// shortest arc, i.e. the slerp of the quaternions taking a to a and a to b). For antiparallel
// inputs the arc turns about an axis perpendicular to a (deterministic choice).
Eigen::Vector3d slerpAxis(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t);

// Low-pass filter of unit axes. `run[i]` is the id of the continuous printing run of sample i
// (-1 = not a printing sample, never filtered nor used as a neighbour). A sample is filtered when
// its axis differs from a neighbour of its run by more than thresholdDegrees; its new axis is
// the normalised binomial average (weights 1 4 6 4 1) of the ORIGINAL axes within +-2 samples
// of the same run. Returns the number of samples whose axis changed.
size_t filterOrientations(std::vector<Eigen::Vector3d>& axes, const std::vector<int>& run,
                          double thresholdDegrees);

}  // namespace omnislice
