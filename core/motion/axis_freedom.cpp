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
  // Lowered freedoms ramp back up along the path at limitRampDegreesPerMm (both ways), so the
  // axis never has to jump to a point's ideal where the freedom drops.
  std::vector<double> free(n, freedom);
  if (!limit.empty()) {
    for (size_t i = 0; i < n; ++i) free[i] = std::isfinite(limit[i]) ? std::clamp(limit[i], 0.0, freedom) : freedom;
    const double ramp = std::max(0.0, o.limitRampDegreesPerMm);
    for (size_t i = 1; i < n; ++i) {
      const double d = (points[i] - points[i - 1]).norm();
      if (std::isfinite(d)) free[i] = std::min(free[i], free[i - 1] + ramp * d);
    }
    for (size_t i = n - 1; i-- > 0;) {
      const double d = (points[i + 1] - points[i]).norm();
      if (std::isfinite(d)) free[i] = std::min(free[i], free[i + 1] + ramp * d);
    }
  }
  size_t changed = 0;
  bool havePrev = false, relaxing = false;
  const double relax = std::max(0.0, o.relaxDegreesPerMm);
  Vector3d prev = Vector3d::UnitZ();
  for (size_t i = 0; i < n; ++i) {
    const Vector3d u = axes[i];
    if (!u.allFinite() || std::abs(u.norm() - 1) > 1e-6) {
      havePrev = false;  // left as it is; the next point starts again from its preferred axis
      relaxing = false;
      continue;
    }
    Vector3d x = havePrev ? prev : preferredAxis(u, free[i]);
    if (havePrev && relaxing) {
      const double d = (points[i] - points[i - 1]).norm();
      const Vector3d target = preferredAxis(u, free[i]);
      if (std::isfinite(d)) x = turnToward(x, target, relax * d);
      if (axisAngleDegrees(x, target) <= 1e-9) relaxing = false;
    }
    if (relax > 0 && free[i] < freedom - 1e-9) relaxing = true;
    // Outside the ideal's cone: its nearest axis on the cone.
    if (axisAngleDegrees(x, u) > free[i]) x = turnToward(u, x, free[i]);
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
