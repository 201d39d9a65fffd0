// SPDX-License-Identifier: MIT
// The axis field's motion term: every axis within the freedom of its ideal and the tilt range;
// near-vertical ideals give +Z exactly; in a plane the total turn equals the least any axes
// within the cones can turn from the same start (dynamic programming over a fine grid); on a
// ring whose ideals lean further than the freedom the axis winds once, as it must, and on
// ideals that wobble within the freedom it settles and stays still; where the freedom drops, it
// ramps instead of jumping, and after it the axis relaxes back to +Z when asked to.
#include "common/math_constants.h"
#include "motion/axis_freedom.h"
#include "motion/orientation_smoothing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

namespace omnislice {
namespace {

using Eigen::Vector3d;

constexpr double kDeg = kPi / 180;

Vector3d fromTiltAzimuth(double tiltDeg, double azimuthDeg) {
  return {std::sin(tiltDeg * kDeg) * std::cos(azimuthDeg * kDeg), std::sin(tiltDeg * kDeg) * std::sin(azimuthDeg * kDeg),
          std::cos(tiltDeg * kDeg)};
}

std::vector<Vector3d> linePoints(size_t n) {
  std::vector<Vector3d> p(n);
  for (size_t i = 0; i < n; ++i) p[i] = Vector3d(0.5 * double(i), 0, 0);
  return p;
}

double totalTurn(const std::vector<Vector3d>& a) {
  double t = 0;
  for (size_t i = 1; i < a.size(); ++i) t += axisAngleDegrees(a[i - 1], a[i]);
  return t;
}

TEST(AxisFreedom, WithinTheConeAndTheTiltRangeOnRandomPaths) {
  std::mt19937 rng(11);
  std::normal_distribution<double> step(0, 0.08);
  for (int trial = 0; trial < 40; ++trial) {
    const size_t n = 400;
    std::vector<Vector3d> ideal(n);
    Vector3d u = fromTiltAzimuth(60 * (trial % 3), 37.0 * trial);
    for (size_t i = 0; i < n; ++i) {
      u = (u + Vector3d(step(rng), step(rng), step(rng))).normalized();
      // Within a tilt range of 90 degrees, as table5's ideals are after the tilt clamp.
      if (u.z() < 0) u.z() = -u.z();
      ideal[i] = u;
    }
    AxisFreedomOptions o;
    o.freedomDegrees = 5 + trial % 4 * 5;
    o.maxTiltDegrees = 90;
    std::vector<Vector3d> axes = ideal;
    chooseAxesForMotion(linePoints(n), axes, o);
    for (size_t i = 0; i < n; ++i) {
      EXPECT_NEAR(axes[i].norm(), 1, 1e-12);
      EXPECT_LE(axisAngleDegrees(axes[i], ideal[i]), o.freedomDegrees + 1e-6) << trial << " " << i;
      EXPECT_LE(axisAngleDegrees(axes[i], Vector3d::UnitZ()), 90 + 1e-6);
    }
    // Never more turning than the ideals'.
    EXPECT_LE(totalTurn(axes), totalTurn(ideal) + 1e-6);
  }
}

TEST(AxisFreedom, NearVerticalIdealsGiveVerticalAxes) {
  // A ring of ideals leaning 12 degrees with a full turn of azimuth: a table's C axis would turn
  // once; within a freedom of 15 degrees the axis stays +Z and nothing turns.
  const size_t n = 360;
  std::vector<Vector3d> ideal(n);
  for (size_t i = 0; i < n; ++i) ideal[i] = fromTiltAzimuth(12, double(i));
  std::vector<Vector3d> axes = ideal;
  AxisFreedomOptions o;
  o.freedomDegrees = 15;
  EXPECT_EQ(chooseAxesForMotion(linePoints(n), axes, o), n);
  for (const Vector3d& a : axes) EXPECT_LT((a - Vector3d::UnitZ()).norm(), 1e-12);
}

TEST(AxisFreedom, RingLeaningFurtherWindsOnceAtLessTilt) {
  // Ideals leaning 40 degrees around a full turn: no axis within 15 degrees of all of them, so
  // the axis must wind once about +Z (the bound), at a tilt between 25 and 40 degrees.
  const size_t n = 720;
  std::vector<Vector3d> ideal(n);
  for (size_t i = 0; i < n; ++i) ideal[i] = fromTiltAzimuth(40, 0.5 * double(i));
  std::vector<Vector3d> axes = ideal;
  AxisFreedomOptions o;
  o.freedomDegrees = 15;
  chooseAxesForMotion(linePoints(n), axes, o);
  double wound = 0;
  for (size_t i = 1; i < n; ++i) {
    const double a0 = std::atan2(axes[i - 1].y(), axes[i - 1].x()), a1 = std::atan2(axes[i].y(), axes[i].x());
    wound += std::remainder(a1 - a0, 2 * kPi);
    const double tilt = axisAngleDegrees(axes[i], Vector3d::UnitZ());
    EXPECT_GE(tilt, 25 - 1e-6);
    EXPECT_LE(tilt, 40 + 1e-6);
  }
  // 359.5 degrees of ideal azimuth; the axis trails it by less than the freedom allows.
  EXPECT_GT(wound / kDeg, 300);
  EXPECT_LE(wound / kDeg, 359.5 + 1e-6);
}

TEST(AxisFreedom, WobbleWithinTheFreedomKeepsTheAxisStill) {
  const size_t n = 500;
  std::vector<Vector3d> ideal(n);
  for (size_t i = 0; i < n; ++i) {
    ideal[i] = fromTiltAzimuth(50 + 6 * std::sin(0.3 * double(i)), 120 + 8 * std::cos(0.17 * double(i)));
  }
  std::vector<Vector3d> axes = ideal;
  AxisFreedomOptions o;
  o.freedomDegrees = 15;
  chooseAxesForMotion(linePoints(n), axes, o);
  EXPECT_GT(totalTurn(ideal), 500);
  // It starts from the least tilted axis of the first cone, settles near where every later
  // ideal keeps it (new extremes of the wobble still nudge it), and then hardly turns.
  EXPECT_LT(totalTurn(axes), 15);
  EXPECT_LT(totalTurn(std::vector<Vector3d>(axes.begin() + 100, axes.end())), 1);
}

// In the xz-plane the axis is one angle a (signed tilt); the least total turn sum |a_i - a_i-1|
// from the same first axis with |a_i - b_i| <= freedom, by dynamic programming over a 0.05
// degree grid.
double leastTurnInPlane(const std::vector<double>& b, double start, double freedom) {
  const double h = 0.05;
  const int lo = int(std::floor(-95 / h)), hi = int(std::ceil(95 / h));
  const size_t m = size_t(hi - lo + 1);
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> cost(m, inf), next(m);
  for (size_t k = 0; k < m; ++k) {
    const double a = (lo + int(k)) * h;
    if (std::abs(a - b[0]) <= freedom + 1e-9) cost[k] = std::abs(a - start);
  }
  for (size_t i = 1; i < b.size(); ++i) {
    // min over j of cost[j] + |a_k - a_j|: two sweeps (distance transform of an L1 cost).
    std::vector<double> best = cost;
    for (size_t k = 1; k < m; ++k) best[k] = std::min(best[k], best[k - 1] + h);
    for (size_t k = m - 1; k-- > 0;) best[k] = std::min(best[k], best[k + 1] + h);
    for (size_t k = 0; k < m; ++k) {
      const double a = (lo + int(k)) * h;
      next[k] = std::abs(a - b[i]) <= freedom + 1e-9 ? best[k] : inf;
    }
    cost.swap(next);
  }
  return *std::min_element(cost.begin(), cost.end());
}

TEST(AxisFreedom, PlanarPathTurnsTheLeastAnyAxesCan) {
  std::mt19937 rng(5);
  std::normal_distribution<double> step(0, 2.5);
  for (int trial = 0; trial < 12; ++trial) {
    const size_t n = 300;
    std::vector<double> b(n);
    double t = -40 + 7.0 * trial;
    for (size_t i = 0; i < n; ++i) {
      t = std::clamp(t + step(rng), -85.0, 85.0);
      b[i] = t;
    }
    std::vector<Vector3d> ideal(n);
    for (size_t i = 0; i < n; ++i) ideal[i] = fromTiltAzimuth(std::abs(b[i]), b[i] < 0 ? 180 : 0);
    std::vector<Vector3d> axes = ideal;
    AxisFreedomOptions o;
    o.freedomDegrees = 10;
    chooseAxesForMotion(linePoints(n), axes, o);
    // Stays in the plane; its first axis is the least tilted of the first cone.
    for (const Vector3d& a : axes) EXPECT_NEAR(a.y(), 0, 1e-9);
    const double start = std::abs(b[0]) <= 10 ? 0 : b[0] - std::copysign(10.0, b[0]);
    const double a0 = std::atan2(axes[0].x(), axes[0].z()) / kDeg;
    EXPECT_NEAR(a0, start, 1e-9);
    const double least = leastTurnInPlane(b, start, o.freedomDegrees);
    EXPECT_NEAR(totalTurn(axes), least, 0.05 * double(n) * 0.05 + 1e-6) << trial;
  }
}

TEST(AxisFreedom, ZeroLimitKeepsTheIdealAndBadInputIsLeftAlone) {
  const size_t n = 50;
  std::vector<Vector3d> ideal(n);
  for (size_t i = 0; i < n; ++i) ideal[i] = fromTiltAzimuth(30 + 0.2 * double(i), 3.0 * double(i));
  ideal[20] = Vector3d(std::nan(""), 0, 1);
  std::vector<double> limit(n, 15);
  for (size_t i = 30; i < 40; ++i) limit[i] = 0;
  std::vector<Vector3d> axes = ideal;
  AxisFreedomOptions o;
  chooseAxesForMotion(linePoints(n), axes, o, limit);
  EXPECT_TRUE(std::isnan(axes[20].x()));
  for (size_t i = 30; i < 40; ++i) EXPECT_LT((axes[i] - ideal[i]).norm(), 1e-12) << i;
  // Sizes that do not match, or no freedom: nothing changes.
  std::vector<Vector3d> same = ideal;
  EXPECT_EQ(chooseAxesForMotion(linePoints(n - 1), same, o), 0u);
  o.freedomDegrees = 0;
  EXPECT_EQ(chooseAxesForMotion(linePoints(n), same, o), 0u);
  for (size_t i = 0; i < n; ++i) {
    if (i != 20) {
      EXPECT_EQ(same[i], ideal[i]);
    }
  }
}

TEST(AxisFreedom, LoweredFreedomRampsInsteadOfJumping) {
  // Ideals leaning 60 degrees with a slowly turning azimuth; in the middle the freedom drops to 0
  // (axes clamped onto the tilt range keep their axis). The chosen axes come to the ideal there
  // and leave it again no faster than the ramp allows: between neighbours (0.5 mm apart) at most
  // the ideals' own turn plus 2 deg/mm x 0.5 mm, never a jump to the ideal.
  const size_t n = 200;
  std::vector<Vector3d> ideal(n);
  for (size_t i = 0; i < n; ++i) ideal[i] = fromTiltAzimuth(60, 0.2 * double(i));
  std::vector<double> limit(n, 15);
  for (size_t i = 90; i < 110; ++i) limit[i] = 0;
  std::vector<Vector3d> axes = ideal;
  AxisFreedomOptions o;
  o.limitRampDegreesPerMm = 2;
  chooseAxesForMotion(linePoints(n), axes, o, limit);
  for (size_t i = 90; i < 110; ++i) EXPECT_LT(axisAngleDegrees(axes[i], ideal[i]), 1e-9) << i;
  for (size_t i = 1; i < n; ++i) {
    EXPECT_LE(axisAngleDegrees(axes[i], axes[i - 1]), axisAngleDegrees(ideal[i], ideal[i - 1]) + 2 * 0.5 + 1e-6) << i;
    // Within the ramped freedom: 15 far from the drop, less near it.
    const double d = std::min(std::abs(double(i) - 89.5), std::abs(double(i) - 109.5)) * 0.5;
    const double bound = i >= 90 && i < 110 ? 0.0 : std::min(15.0, 2 * (d + 0.25));
    EXPECT_LE(axisAngleDegrees(axes[i], ideal[i]), bound + 1e-6) << i;
  }
  // Far from the drop the axis leans the full freedom toward +Z (the path starts there).
  EXPECT_NEAR(axisAngleDegrees(axes[0], Vector3d::UnitZ()), 45, 1e-6);
}

TEST(AxisFreedom, AfterALoweredPointTheAxisRelaxesBackToVertical) {
  // A ring whose ideals lean 10 degrees (within the freedom 15: +Z everywhere, nothing turns),
  // the freedom lowered to 0 at one point (a segment left out with the motion term's axes). The
  // axis comes to that point's ideal. Without relaxing it then stays tilted inside the later
  // cones, dragged along until it settles where they all meet (5 degrees from +Z); relaxing at
  // 5 deg/mm it is back on +Z within a few mm and the whole path turns little more than there
  // and back.
  const size_t n = 720, at = 100;
  std::vector<Vector3d> ideal(n);
  for (size_t i = 0; i < n; ++i) ideal[i] = fromTiltAzimuth(10, 0.5 * double(i));
  std::vector<double> limit(n, std::numeric_limits<double>::infinity());
  limit[at] = 0;
  AxisFreedomOptions o;
  o.freedomDegrees = 15;
  std::vector<Vector3d> stays = ideal, relaxes = ideal;
  chooseAxesForMotion(linePoints(n), stays, o, limit);
  o.relaxDegreesPerMm = 5;
  chooseAxesForMotion(linePoints(n), relaxes, o, limit);
  for (const auto* axes : {&stays, &relaxes}) {
    EXPECT_LT(axisAngleDegrees((*axes)[at], ideal[at]), 1e-9);
    for (size_t i = 0; i < n; ++i) EXPECT_LE(axisAngleDegrees((*axes)[i], ideal[i]), 15 + 1e-6) << i;
    for (size_t i = 0; i + 20 < at; ++i) EXPECT_LT(axisAngleDegrees((*axes)[i], Vector3d::UnitZ()), 1e-9) << i;
  }
  // Staying: still tilted half a ring later.
  EXPECT_GT(axisAngleDegrees(stays[at + 360], Vector3d::UnitZ()), 4);
  // Relaxing: +Z again within 10 mm (20 points), turning about 2 x 10 degrees in all.
  for (size_t i = at + 20; i < n; ++i) EXPECT_LT(axisAngleDegrees(relaxes[i], Vector3d::UnitZ()), 1e-9) << i;
  EXPECT_LT(totalTurn(relaxes), 2 * 10 + 3);
  // What a table's C axis turns (the azimuth of tilted axes): the staying axis is dragged along
  // by the cones until it settles where all of them meet (5 degrees from +Z), the relaxing one
  // turns only around the point.
  auto azimuthMotion = [](const std::vector<Vector3d>& a) {
    double sum = 0;
    for (size_t i = 1; i < a.size(); ++i) {
      if (std::hypot(a[i - 1].x(), a[i - 1].y()) < 1e-9 || std::hypot(a[i].x(), a[i].y()) < 1e-9) continue;
      sum += std::abs(std::remainder(std::atan2(a[i].y(), a[i].x()) - std::atan2(a[i - 1].y(), a[i - 1].x()), 2 * kPi));
    }
    return sum / kDeg;
  };
  std::printf("azimuth motion: %.1f staying, %.1f relaxing (degrees)\n", azimuthMotion(stays), azimuthMotion(relaxes));
  EXPECT_LT(azimuthMotion(relaxes), 0.5 * azimuthMotion(stays));
}

}  // namespace
}  // namespace omnislice
