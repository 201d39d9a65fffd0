// SPDX-License-Identifier: MIT
// Candidate normals of the multidir plane search and refinement (candidate_normals.h). Every
// angle goes through det::sin / det::cos / det::atan2, so native and wasm sample the same normals.
#include "multidir/candidate_normals.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "common/det_math.h"
#include "common/math_constants.h"

namespace omnislice::decomposition_detail {

using Vec3 = Eigen::Vector3d;

// The Fibonacci sphere of o.samples points turned by `phase` (radians) about Z, within the tilt
// range (or o.candidateNormals as given, within it).
std::vector<Vec3> sphereNormals(const MultidirOptions& o, double phase) {
  std::vector<Vec3> out;
  const double minZ = det::cos(o.maxTiltDeg * kPi / 180) - 1e-12;
  if (!o.candidateNormals.empty()) {
    for (const Vec3& n : o.candidateNormals) {
      const Vec3 u = n.normalized();
      if (u.z() >= minZ) out.push_back(u);
    }
    return out;
  }
  const double golden = kPi * (3 - std::sqrt(5.0));
  const int N = o.samples;
  for (int i = 0; i < N; ++i) {
    const double z = 1 - (2.0 * i + 1) / N;
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = golden * i + phase;
    if (z >= minZ) out.emplace_back(r * det::cos(phi), r * det::sin(phi), z);
  }
  return out;
}

// Normals n(theta) = cos(theta) Z + sin(theta) (r x Z) on the great circle n . r = 0, theta a
// multiple of the stepper angle (or of 360/samples), |theta| <= rangeDeg.
std::vector<Vec3> circleNormals(const MultidirOptions& o, const Vec3& r) {
  if (!o.candidateNormals.empty()) {
    std::vector<Vec3> out;
    for (const Vec3& n : o.candidateNormals) out.push_back(n.normalized());
    return out;
  }
  const Vec3 v = r.cross(Vec3(0, 0, 1)).normalized();
  const double stepDeg = o.stepAngleDeg > 0 ? o.stepAngleDeg : 360.0 / o.samples;
  const int kMax = static_cast<int>(std::floor(o.rangeDeg / stepDeg + 1e-9));
  std::vector<Vec3> out;
  for (int k = -kMax; k <= kMax; ++k) {
    const double th = k * stepDeg * kPi / 180;
    if (std::abs(k * stepDeg) > 180 - 1e-9 && k < 0) continue;  // theta = -180 equals +180
    out.push_back(det::cos(th) * Vec3(0, 0, 1) + det::sin(th) * v);
  }
  return out;
}

// Normals near n that the machine can realise: rings up to 12 deg (5dof, within maxTiltDeg), or
// rotations near n's about the axis (4dof: +-0.5..6 deg, or +-1..3 stepper steps, within range).
std::vector<Vec3> nearbyNormals(const MultidirOptions& o, bool fourDof, const Vec3& axis, const Vec3& n) {
  std::vector<Vec3> out;
  if (!o.candidateNormals.empty()) return out;
  if (!fourDof) {
    const double minZ = det::cos(o.maxTiltDeg * kPi / 180) - 1e-12;
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
    for (double deg : {1.5, 3.0, 4.5, 6.0, 8.0, 10.0, 12.0}) {
      const double a = deg * kPi / 180;
      for (int az = 0; az < 8; ++az) {
        const double b = (az + (deg == 3.0 || deg == 6.0 || deg == 10.0 ? 0.5 : 0.0)) * kPi / 4;
        const Vec3 q = (det::cos(a) * n + det::sin(a) * (det::cos(b) * u + det::sin(b) * v)).normalized();
        if (q.z() >= minZ) out.push_back(q);
      }
    }
    return out;
  }
  const Vec3 side = axis.cross(Vec3(0, 0, 1)).normalized();
  const double theta = det::atan2(n.dot(side), n.z()) * 180 / kPi;
  std::vector<double> deltas;
  if (o.stepAngleDeg > 0) {
    for (int k = 1; k <= 3; ++k) deltas.insert(deltas.end(), {k * o.stepAngleDeg, -k * o.stepAngleDeg});
  } else {
    for (int k = 1; k <= 12; ++k) deltas.insert(deltas.end(), {0.5 * k, -0.5 * k});
  }
  for (double dt : deltas) {
    double t = theta + dt;
    if (o.stepAngleDeg > 0) t = std::round(t / o.stepAngleDeg) * o.stepAngleDeg;
    if (std::abs(t) > o.rangeDeg + 1e-9) continue;
    const double r = t * kPi / 180;
    out.push_back(det::cos(r) * Vec3(0, 0, 1) + det::sin(r) * side);
  }
  return out;
}

}  // namespace omnislice::decomposition_detail
