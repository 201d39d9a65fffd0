// SPDX-License-Identifier: MIT
// The firmware look-ahead time model (toolpath/lookahead_time.h) against closed forms: a straight
// line cut into many collinear moves takes the time of one trapezoid; without junction deviation
// every move starts and ends at rest; a square's corners slow the tip to the junction speed of a
// right angle; a long move reaches its cruise; stops split the chain; the time falls as the
// junction deviation grows and never beats cruising everywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "toolpath/lookahead_time.h"

namespace omnislice {
namespace {

// From rest to rest over L at cruise v, acceleration a.
double restToRest(double L, double v, double a) {
  return L >= v * v / a ? L / v + v / a : 2 * std::sqrt(L / a);
}

std::vector<PlannedMove> line(int pieces, double length, double speed, const Eigen::Vector3d& dir) {
  return std::vector<PlannedMove>(size_t(pieces), PlannedMove{dir.normalized(), length / pieces, speed});
}

TEST(LookaheadTime, CollinearPiecesTakeOneTrapezoid) {
  const double a = 1500, v = 60;
  for (double L : {1.0, 2.4, 10.0, 100.0}) {
    const std::vector<PlannedMove> moves = line(50, L, v, {1, 2, 0});
    std::vector<double> each;
    const double t = lookaheadTime(moves, {a, 0.013}, &each);
    EXPECT_NEAR(t, restToRest(L, v, a), 1e-9 * (1 + t)) << L;
    double sum = 0;
    for (double d : each) sum += d;
    EXPECT_NEAR(sum, t, 1e-12 * (1 + t));
  }
}

TEST(LookaheadTime, NoJunctionDeviationStopsAtEveryJunction) {
  const double a = 1500, v = 60;
  std::vector<PlannedMove> moves = line(7, 7, v, {0, 1, 0});
  EXPECT_NEAR(lookaheadTime(moves, {a, 0}), 7 * restToRest(1, v, a), 1e-12);
  // No acceleration: every move at its cruise.
  EXPECT_NEAR(lookaheadTime(moves, {0, 0.013}), 7 / v, 1e-12);
}

TEST(LookaheadTime, RightAnglesSlowToTheirJunctionSpeed) {
  const double a = 1500, jd = 0.013, v = 100, side = 40;
  std::vector<PlannedMove> square;
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(-1, 0, 0),
                                  Eigen::Vector3d(0, -1, 0)}) {
    square.push_back({d, side, v});
  }
  // A right angle: sin(t/2) = sqrt(1/2).
  const double s = std::sqrt(0.5);
  const double vj = std::sqrt(a * jd * s / (1 - s));
  ASSERT_LT(vj, v);
  // First side: rest -> vj; middle sides vj -> vj; last vj -> rest; each long enough to cruise.
  auto ramp = [&](double vi, double vo) {
    const double up = (v * v - vi * vi) / (2 * a), down = (v * v - vo * vo) / (2 * a);
    return (v - vi) / a + (v - vo) / a + (side - up - down) / v;
  };
  const double expected = ramp(0, vj) + 2 * ramp(vj, vj) + ramp(vj, 0);
  EXPECT_NEAR(lookaheadTime(square, {a, jd}), expected, 1e-9);
  // A reversal stops; a stop (no length) splits the chain.
  std::vector<PlannedMove> back{{Eigen::Vector3d(1, 0, 0), side, v}, {Eigen::Vector3d(-1, 0, 0), side, v}};
  EXPECT_NEAR(lookaheadTime(back, {a, jd}), 2 * restToRest(side, v, a), 1e-9);
  std::vector<PlannedMove> split{{Eigen::Vector3d(1, 0, 0), side, v}, {}, {Eigen::Vector3d(1, 0, 0), side, v}};
  std::vector<double> each;
  EXPECT_NEAR(lookaheadTime(split, {a, jd}, &each), 2 * restToRest(side, v, a), 1e-9);
  EXPECT_EQ(each[1], 0);
}

TEST(LookaheadTime, MoreDeviationIsFasterButNeverFasterThanCruising) {
  // A polygonal circle of 200 sides, radius 20 mm, at 80 mm/s.
  std::vector<PlannedMove> circle;
  const int n = 200;
  double length = 0;
  for (int i = 0; i < n; ++i) {
    const double t0 = 2 * M_PI * i / n, t1 = 2 * M_PI * (i + 1) / n;
    const Eigen::Vector3d p0(20 * std::cos(t0), 20 * std::sin(t0), 0), p1(20 * std::cos(t1), 20 * std::sin(t1), 0);
    circle.push_back({(p1 - p0).normalized(), (p1 - p0).norm(), 80});
    length += (p1 - p0).norm();
  }
  double previous = INFINITY;
  for (double jd : {0.0, 0.001, 0.005, 0.013, 0.05, 1.0}) {
    const double t = lookaheadTime(circle, {1500, jd});
    EXPECT_LE(t, previous + 1e-12) << jd;
    EXPECT_GE(t, length / 80 - 1e-12) << jd;
    previous = t;
  }
  // With a large deviation only the start and the end ramp: one trapezoid over the whole length.
  EXPECT_NEAR(lookaheadTime(circle, {1500, 1.0}), restToRest(length, 80, 1500), 1e-9);
}

}  // namespace
}  // namespace omnislice
