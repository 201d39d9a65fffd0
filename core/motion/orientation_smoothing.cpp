// SPDX-License-Identifier: MIT
#include "common/math_constants.h"
#include "motion/orientation_smoothing.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace omnislice {

namespace {
}

double axisAngleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kPi;
}

Eigen::Vector3d slerpAxis(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
  if (t <= 0) return a;
  if (t >= 1) return b;
  Eigen::Vector3d k = a.cross(b);
  const double s = k.norm();
  const double angle = std::atan2(s, a.dot(b));
  if (angle < 1e-12) return a;
  if (s < 1e-12) {
    // Antiparallel: any axis perpendicular to a gives a shortest arc; take the most stable one.
    Eigen::Vector3d e = Eigen::Vector3d::UnitX();
    if (std::abs(a.x()) > 0.6) e = Eigen::Vector3d::UnitY();
    k = a.cross(e).normalized();
  } else {
    k /= s;
  }
  // Quaternion slerp of identity -> rotation(angle, k) is the rotation(t * angle, k).
  return (Eigen::AngleAxisd(t * angle, k) * a).normalized();
}

size_t filterOrientations(std::vector<Eigen::Vector3d>& axes, const std::vector<int>& run,
                          double thresholdDegrees) {
  const size_t n = axes.size();
  const std::vector<Eigen::Vector3d> original = axes;
  auto sameRun = [&](size_t i, long j) {
    return j >= 0 && static_cast<size_t>(j) < n && run[i] >= 0 && run[j] == run[i];
  };
  static const double kWeights[5] = {1, 4, 6, 4, 1};
  size_t changed = 0;
  for (size_t i = 0; i < n; ++i) {
    if (run[i] < 0) continue;
    const long li = static_cast<long>(i);
    const bool jump =
        (sameRun(i, li - 1) && axisAngleDegrees(original[i - 1], original[i]) > thresholdDegrees) ||
        (sameRun(i, li + 1) && axisAngleDegrees(original[i], original[i + 1]) > thresholdDegrees);
    if (!jump) continue;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = -2; k <= 2; ++k) {
      if (sameRun(i, li + k)) sum += kWeights[k + 2] * original[i + k];
    }
    // Opposite axes can cancel: keep the original then (the subdivision handles the turn).
    if (sum.norm() < 1e-6) continue;
    const Eigen::Vector3d u = sum.normalized();
    if ((u - original[i]).norm() > 1e-12) {
      axes[i] = u;
      ++changed;
    }
  }
  return changed;
}

}  // namespace omnislice
