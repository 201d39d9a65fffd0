// SPDX-License-Identifier: MIT
#include "motion/axis_freedom.h"

#include <algorithm>
#include <cmath>

#include "motion/orientation_smoothing.h"

namespace omnislice {

namespace {

using Eigen::Vector3d;

// a turned toward b by at most `degrees` (b when they are closer).
Vector3d turnToward(const Vector3d& a, const Vector3d& b, double degrees) {
  const double angle = axisAngleDegrees(a, b);
  if (angle <= degrees) return b;
  return slerpAxis(a, b, degrees / angle);
}

}  // namespace

Vector3d preferredAxis(const Vector3d& u, double freedomDegrees) {
  return turnToward(u, Vector3d::UnitZ(), freedomDegrees);
}

size_t chooseAxesForMotion(const std::vector<Vector3d>& points, std::vector<Vector3d>& axes,
                           const AxisFreedomOptions& o, const std::vector<double>& limit) {
  const size_t n = axes.size();
  if (n == 0 || points.size() != n || !(o.freedomDegrees > 0) || (!limit.empty() && limit.size() != n)) return 0;
  const double freedom = std::min(o.freedomDegrees, 90.0);
  size_t changed = 0;
  bool havePrev = false;
  Vector3d prev = Vector3d::UnitZ();
  for (size_t i = 0; i < n; ++i) {
    const Vector3d u = axes[i];
    if (!u.allFinite() || std::abs(u.norm() - 1) > 1e-6) {
      havePrev = false;  // left as it is; the next point starts again from its preferred axis
      continue;
    }
    const double free = limit.empty() || !std::isfinite(limit[i]) ? freedom : std::clamp(limit[i], 0.0, freedom);
    Vector3d x = havePrev ? prev : preferredAxis(u, free);
    // Outside the ideal's cone: its nearest axis on the cone.
    if (axisAngleDegrees(x, u) > free) x = turnToward(u, x, free);
    // The tilt range: the chosen axis may not lean further than the range or its ideal does.
    const double tilt = axisAngleDegrees(x, Vector3d::UnitZ());
    const double range = std::max(o.maxTiltDegrees, axisAngleDegrees(u, Vector3d::UnitZ()));
    if (tilt > range) x = turnToward(x, Vector3d::UnitZ(), tilt - range);
    x.normalize();
    if ((x - u).norm() > 1e-9) ++changed;
    axes[i] = x;
    prev = x;
    havePrev = true;
  }
  return changed;
}

}  // namespace omnislice
