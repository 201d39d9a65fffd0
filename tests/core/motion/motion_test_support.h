// SPDX-License-Identifier: MIT
// Tool-paths, machine profiles and independent checks for the motion-planning tests.
#pragma once
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "kinematics/kinematics.h"
#include "motion/machine_path.h"
#include "machine/machine.h"
#include "toolpath/toolpath.h"

namespace omnislice::test {

constexpr double kMotionPi = 3.14159265358979323846;

inline double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kMotionPi;
}

inline Move printMove(const Eigen::Vector3d& p, const Eigen::Vector3d& u, double filament,
                      int layer = 0, int part = 0, double speed = 30) {
  Move m;
  m.position = p;
  m.axis = u.normalized();
  m.kind = MoveKind::Print;
  m.feature = Feature::WallOuter;
  m.width = 0.45;
  m.height = 0.2;
  m.filament = filament;
  m.speed = speed;
  m.layer = layer;
  m.part = part;
  return m;
}

// Helix of radius r about the part Z axis starting at height z0, rising `pitch` per turn, `turns`
// turns sampled every `step` mm; the nozzle axis leans outwards by tiltDegrees from +Z (the
// normal of a cone wall), so the rotary values turn with the helix.
inline Toolpath helixToolpath(double r, double z0, double pitch, double turns, double step,
                              double tiltDegrees) {
  Toolpath tp;
  const double tilt = tiltDegrees * kMotionPi / 180.0;
  const int n = static_cast<int>(std::ceil(turns * 2 * kMotionPi * r / step));
  auto point = [&](double th) {
    return Eigen::Vector3d(r * std::cos(th), r * std::sin(th), z0 + pitch * th / (2 * kMotionPi));
  };
  auto axis = [&](double th) {
    return Eigen::Vector3d(std::sin(tilt) * std::cos(th), std::sin(tilt) * std::sin(th),
                           std::cos(tilt));
  };
  tp.start = point(0);
  Eigen::Vector3d prev = tp.start;
  for (int i = 1; i <= n; ++i) {
    const double th = turns * 2 * kMotionPi * i / n;
    const Eigen::Vector3d p = point(th);
    tp.moves.push_back(printMove(p, axis(th), 0.033 * (p - prev).norm(), 0));
    prev = p;
  }
  // The first move starts at tp.start with the axis of the first sample.
  tp.layerCount = 1;
  return tp;
}

// A path over a roof-shaped ridge z = top - |x| (slopes of 45 degrees) along X at y = y0,
// sampled every `step` mm, with the surface normal as nozzle axis: the axis flips by 90 degrees
// at the crest (from (-1,0,1)/sqrt2 to (1,0,1)/sqrt2), which the planner must smooth.
inline Toolpath crestToolpath(double halfWidth, double top, double step, double y0 = 0) {
  Toolpath tp;
  const int n = static_cast<int>(std::lround(2 * halfWidth / step));
  auto point = [&](double x) { return Eigen::Vector3d(x, y0, top - std::abs(x)); };
  auto normal = [&](double x) {
    return Eigen::Vector3d(x < 0 ? -1 : 1, 0, 1).normalized();
  };
  tp.start = point(-halfWidth);
  Eigen::Vector3d prev = tp.start;
  for (int i = 1; i <= n; ++i) {
    // Samples avoid x = 0 exactly so the flip happens between two samples.
    const double x = -halfWidth + step * i + (i == n / 2 ? 0.5 * step : 0.0);
    const Eigen::Vector3d p = point(std::min(x, halfWidth));
    tp.moves.push_back(printMove(p, normal(p.x() == 0 ? 1e-9 : p.x()), 0.033 * (p - prev).norm()));
    prev = p;
  }
  tp.layerCount = 1;
  return tp;
}

inline MachineProfile rotary4TestProfile() {
  MachineProfile m;
  m.kind = MachineKind::Rotary4;
  m.name = "rotary4-test";
  m.pivot = {0, 0, 0};
  m.axisLimits["X"] = {-150, 150};
  m.axisLimits["Y"] = {-150, 150};
  m.axisLimits["Z"] = {-100, 250};
  m.axisLimits["A"] = {-60, 60};
  return m;
}

inline MachineProfile table5TestProfile() {
  MachineProfile m;
  m.kind = MachineKind::Table5;
  m.name = "table5-test";
  m.pivot = {0, 0, 0};
  m.axisLimits["X"] = {-150, 150};
  m.axisLimits["Y"] = {-150, 150};
  m.axisLimits["Z"] = {-100, 250};
  m.axisLimits["B"] = {-90, 90};  // C continuous (no limit): a helix turns it many times
  return m;
}

// Largest change of one angular value between consecutive values (start included).
inline double maxAngularStep(const MachinePath& mp, int begin, int end) {
  double s = 0;
  MachineValues prev = mp.start;
  for (const MachineMove& m : mp.moves) {
    for (int i = begin; i < end; ++i) s = std::max(s, std::abs(m.values[i] - prev[i]));
    prev = m.values;
  }
  return s;
}

inline double pointSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  double t = ab.squaredNorm() > 0 ? (p - a).dot(ab) / ab.squaredNorm() : 0;
  t = std::clamp(t, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// Every output move's FK lies on the straight part-frame segment of its source move, and the
// last piece of each source move ends exactly on the source point. The intermediate pieces of
// travels (a 3+2 safe rotation: lift, rotate, move over) are exempt. Returns the largest deviation.
inline double checkPlannedPoints(const MachinePath& mp, const Toolpath& tp) {
  double worst = 0;
  for (size_t k = 0; k < mp.moves.size(); ++k) {
    const MachineMove& m = mp.moves[k];
    Eigen::Vector3d tip, axis;
    EXPECT_TRUE(forwardMap(mp.machine, m.values, tip, axis));
    const Eigen::Vector3d end = tp.moves[m.source].position;
    const Eigen::Vector3d begin = m.source == 0 ? tp.start : tp.moves[m.source - 1].position;
    const bool last = k + 1 == mp.moves.size() || mp.moves[k + 1].source != m.source;
    if (!last && tp.moves[m.source].kind == MoveKind::Travel) continue;
    const double d = last ? (tip - end).norm() : pointSegment(tip, begin, end);
    worst = std::max(worst, d);
  }
  return worst;
}

// Largest distance of the tip at the mid-point of the linearly interpolated machine values of a
// move from the straight segment between its end tips (computed with forwardMap only).
inline double maxChordDeviation(const MachinePath& mp, bool skipTravel) {
  double worst = 0;
  MachineValues prev = mp.start;
  for (const MachineMove& m : mp.moves) {
    if (!(skipTravel && m.kind == MoveKind::Travel)) {
      MachineValues mid;
      for (int i = 0; i < 6; ++i) mid[i] = 0.5 * (prev[i] + m.values[i]);
      Eigen::Vector3d a, b, c, u;
      forwardMap(mp.machine, prev, a, u);
      forwardMap(mp.machine, m.values, b, u);
      forwardMap(mp.machine, mid, c, u);
      worst = std::max(worst, pointSegment(c, a, b));
    }
    prev = m.values;
  }
  return worst;
}

// Independent recomputation of the finite differences of paper 003 Eq. 7 in time (see
// feed_limits.h): largest |v| / vmax, |a| / amax, |j| / jmax over consecutive moving moves.
inline std::array<double, 3> recomputeFeedRatios(const MachinePath& mp, int axes,
                                                 const std::array<AxisDynamics, 6>& dyn) {
  std::array<double, 3> worst{0, 0, 0};
  const size_t n = mp.moves.size();
  std::vector<std::array<double, 6>> v(n);
  std::vector<bool> moving(n);
  MachineValues prev = mp.start;
  for (size_t k = 0; k < n; ++k) {
    const MachineMove& m = mp.moves[k];
    bool mv = false;
    for (int i = 0; i < axes; ++i) mv = mv || std::abs(m.values[i] - prev[i]) > 1e-12;
    moving[k] = mv && m.durationS > 0;
    for (int i = 0; i < axes; ++i) {
      v[k][i] = moving[k] ? (m.values[i] - prev[i]) / m.durationS : 0;
      if (dyn[i].velocity > 0) worst[0] = std::max(worst[0], std::abs(v[k][i]) / dyn[i].velocity);
    }
    prev = m.values;
  }
  std::vector<std::array<double, 6>> a(n);
  std::vector<bool> hasA(n, false);
  for (size_t k = 0; k + 1 < n; ++k) {
    if (!moving[k] || !moving[k + 1]) continue;
    hasA[k] = true;
    const double tau = 0.5 * (mp.moves[k].durationS + mp.moves[k + 1].durationS);
    for (int i = 0; i < axes; ++i) {
      a[k][i] = (v[k + 1][i] - v[k][i]) / tau;
      if (dyn[i].acceleration > 0) {
        worst[1] = std::max(worst[1], std::abs(a[k][i]) / dyn[i].acceleration);
      }
    }
  }
  for (size_t k = 0; k + 1 < n; ++k) {
    if (!hasA[k] || !hasA[k + 1]) continue;
    for (int i = 0; i < axes; ++i) {
      // a_k and a_k+1 sit between the midpoints of their moves: (T_k + 2 T_k+1 + T_k+2) / 4 apart.
      const double span = 0.25 * (mp.moves[k].durationS + 2 * mp.moves[k + 1].durationS +
                                   mp.moves[k + 2].durationS);
      const double j = (a[k + 1][i] - a[k][i]) / span;
      if (dyn[i].jerk > 0) worst[2] = std::max(worst[2], std::abs(j) / dyn[i].jerk);
    }
  }
  return worst;
}

}  // namespace omnislice::test
