// SPDX-License-Identifier: MIT
// The nozzle axes of a curved-layer path chosen for the machine's motion within a cone around the
// ideal axes. The axis field has three terms: the surface (the ideal axis, paper 001 Eq. 3 or the
// layer normal, which the chosen axis stays within `freedomDegrees` of), motion (the axis keeps
// still wherever that cone lets it and otherwise moves only as far as the cone forces it: the
// shortest motion of the axis inside the moving cone, a taut string; each path starts from the
// least tilted axis of its first cone, +Z where the ideal leans less than the freedom, so near
// +Z, where a table's C axis and a robot's wrist follow every small change of azimuth, nothing
// turns) and collisions (the gouging correction of surface/curved_toolpath then turns what
// would touch printed material, trying the ideal axis first).
//
// Measured on the shared kitten at 40 mm on table5 (issue 33): relaxing the axis back toward +Z
// along the path (1 and 5 degrees per mm) moved the rotary axes more than this taut string
// (geodesic: 568k and 785k degrees against 477k), so the axis never returns on its own.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace omnislice {

struct AxisFreedomOptions {
  double freedomDegrees = 15;   // largest angle between an axis and its ideal; 0 = the ideal
  double maxTiltDegrees = 180;  // the machine's tilt range from +Z (axes stay within it)
  double limitRampDegreesPerMm = 2;  // a lowered freedom (limit) rises back at most this fast
  // After a point whose freedom a limit lowered, the axis turns back toward each next point's
  // preferred axis at most this fast (degrees per mm of path) until it reaches it; 0 = it stays
  // where the taut string leaves it. Without it an axis pulled to a tilted ideal at one point
  // stays tilted along the rest of the path (it is inside every later cone) instead of +Z, and
  // near +Z a small tilt whose azimuth the cones drag along is what turns a table's C axis.
  double relaxDegreesPerMm = 0;
};

// The least tilted axis within freedomDegrees of u: +Z when u leans from +Z by at most
// freedomDegrees, otherwise u turned toward +Z by freedomDegrees.
Eigen::Vector3d preferredAxis(const Eigen::Vector3d& u, double freedomDegrees);

// One path: points[i] and ideal unit axes[i] in, axes[i] out. The first axis is its preferred
// one; each next one is the previous one while that stays within the freedom of its own ideal,
// otherwise the nearest axis of that cone (the ideal turned toward the previous by the
// freedom). Every output axis is within the freedom of its ideal (and within the tilt range
// when the ideal is). `limit`, when not empty (one per point), lowers the freedom of single
// points: point i leans at most min(freedomDegrees, limit[j] + limitRampDegreesPerMm x the path
// length between i and j) over every j (0 at j: its ideal axis exactly there, and the freedom
// ramps up around it, so the axis comes to the ideal gradually instead of jumping to it; after
// it the axis relaxes back to the preferred axes at relaxDegreesPerMm).
// Non-finite or non-unit axes are left as they are. Returns the number of axes changed by more
// than 1e-9. Sizes must match (otherwise nothing changes).
size_t chooseAxesForMotion(const std::vector<Eigen::Vector3d>& points, std::vector<Eigen::Vector3d>& axes,
                           const AxisFreedomOptions& options, const std::vector<double>& limit = {});

}  // namespace omnislice
