// SPDX-License-Identifier: MIT
// planMachineMotion on the G-code kinds: planar identity for cartesian3, pose continuity on a
// helix and across a crest (table5), orientation smoothing, chord tolerance, feed limits, 3+2
// safe rotations (rotary4), extrusion bookkeeping and the error statuses.
#include "motion/plan_motion.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>

#include "kinematics/kinematics.h"
#include "motion/motion_test_support.h"
#include "program/test_toolpaths.h"

namespace omnislice {
namespace {

using test::angleDeg;
using test::rotary4TestProfile;
using test::table5TestProfile;

TEST(PlanMotion, PlanarCartesianKeepsPositionsAndTime) {
  test::BoxPathOptions bo;
  bo.height = 2;
  const Toolpath tp = test::boxToolpath(bo);
  const MachineProfile m = cartesian3Profile({200, 200, 200}, 0.4);
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  ASSERT_TRUE(mp.ok()) << mp.message;
  // One output move per input move, at the same place (machine = part for cartesian3).
  ASSERT_EQ(mp.moves.size(), tp.moves.size());
  for (size_t i = 0; i < tp.moves.size(); ++i) {
    EXPECT_LT((mp.moves[i].tip - tp.moves[i].position).norm(), 1e-12) << i;
    EXPECT_DOUBLE_EQ(mp.moves[i].values[0], tp.moves[i].position.x());
    EXPECT_DOUBLE_EQ(mp.moves[i].values[2], tp.moves[i].position.z());
    EXPECT_DOUBLE_EQ(mp.moves[i].filament, tp.moves[i].filament);
    EXPECT_EQ(mp.moves[i].kind, tp.moves[i].kind);
  }
  const ToolpathStats ts = toolpathStats(tp, o.acceleration);
  EXPECT_NEAR(mp.stats.estimatedTimeS, ts.estimatedTimeS, 0.01 * ts.estimatedTimeS);
  EXPECT_EQ(mp.stats.subdivisions, 0u);
  EXPECT_EQ(mp.stats.feedLimitedMoves, 0u);
}

TEST(PlanMotion, CartesianFeedLimitedByAxisVelocity) {
  test::BoxPathOptions bo;
  bo.height = 1;
  const Toolpath tp = test::boxToolpath(bo);
  MachineProfile m = cartesian3Profile({200, 200, 200}, 0.4);
  m.axisDynamics["X"] = {20, 0, 0};  // travels at 150 mm/s along X must slow down to 20 mm/s
  const MachinePath mp = planMachineMotion(tp, m);
  ASSERT_TRUE(mp.ok()) << mp.message;
  EXPECT_GT(mp.stats.feedLimitedMoves, 0u);
  MachineValues prev = mp.start;
  for (const MachineMove& mv : mp.moves) {
    if (mv.durationS > 0 && mv.values[0] != prev[0]) {
      EXPECT_LE(std::abs(mv.values[0] - prev[0]) / mv.durationS, 20 * (1 + 1e-9));
    }
    const double len = (mv.values[0] - prev[0]) * (mv.values[0] - prev[0]);
    (void)len;
    prev = mv.values;
  }
}

// Table5 along a 3-turn helix whose axis leans 30 degrees outwards: C follows the helix angle.
TEST(PlanMotion, Table5HelixIsContinuous) {
  const Toolpath tp = test::helixToolpath(20, 5, 2, 3, 1.0, 30);
  const MachineProfile m = table5TestProfile();
  MotionOptions o;
  o.chordTolerance = 0.002;  // the sagitta of a 1 mm move turning C by 2.9 deg on r = 20 is 0.006
  const MachinePath mp = planMachineMotion(tp, m, o);
  ASSERT_TRUE(mp.ok()) << mp.message;
  // Consecutive samples are 1 mm apart on a 20 mm radius: the axis turns by at most
  // 1/20 rad * sin(30 deg) ~ 1.4 deg, C by 1/20 rad = 2.9 deg per sample and B not at all. Any
  // branch switch (B -> -B, C -> C + 180) or C unwinding would be a step of >= 60 degrees.
  const double bound = 1.0 / 20.0 * 180.0 / test::kMotionPi + 1e-6;
  EXPECT_LE(test::maxAngularStep(mp, 3, 5), bound);
  EXPECT_LE(mp.stats.maxJointStep, bound);
  EXPECT_LE(mp.stats.poseCost, mp.stats.greedyPoseCost + 1e-9);
  // C turns through the three turns continuously (unwrapped beyond +-360); the start already
  // has the first sample's axis (one step of 1080/377 degrees along).
  const double steps = std::ceil(3 * 2 * test::kMotionPi * 20 / 1.0);
  EXPECT_NEAR(std::abs(mp.moves.back().values[4] - mp.start[4]), 1080.0 - 1080.0 / steps, 1e-6);
  // Every move ends on its planned point; the interpolated motion stays within the chord.
  EXPECT_LT(test::checkPlannedPoints(mp, tp), 1e-6);
  EXPECT_LE(test::maxChordDeviation(mp, false), o.chordTolerance * (1 + 1e-9));
  EXPECT_GT(mp.stats.subdivisions, 0u);  // a 30-degree tilt about a moving pivot bends the chord
  // The axes are realised (no filtering is needed on a smooth helix).
  EXPECT_EQ(mp.stats.filteredOrientations, 0u);
  for (size_t k = 0; k < mp.moves.size(); ++k) {
    const MachineMove& mv = mp.moves[k];
    if (k + 1 == mp.moves.size() || mp.moves[k + 1].source != mv.source) {
      EXPECT_LT(angleDeg(mv.axis, tp.moves[mv.source].axis), 1e-6);
    }
  }
}

// Table5 across a ridge where the normal flips by 90 degrees: the filter and the slerp
// subdivision turn the axis through +Z, where B passes 0 and the branch (B, C) -> (-B, C + 180)
// lets C stand still.
TEST(PlanMotion, Table5CrestIsSmoothedAndContinuous) {
  const Toolpath tp = test::crestToolpath(20, 30, 1.0, 3.0);
  const MachineProfile m = table5TestProfile();
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  ASSERT_TRUE(mp.ok()) << mp.message;
  EXPECT_GT(mp.stats.filteredOrientations, 0u);
  EXPECT_GT(mp.stats.subdivisions, 0u);
  // No two consecutive nozzle axes differ by more than maxAxisStepDegrees.
  Eigen::Vector3d prevAxis, tip;
  forwardMap(m, mp.start, tip, prevAxis);
  for (const MachineMove& mv : mp.moves) {
    EXPECT_LE(angleDeg(prevAxis, mv.axis), o.maxAxisStepDegrees + 1e-6);
    prevAxis = mv.axis;
  }
  // The axis stays in the XZ plane, so a continuous choice changes B by the axis step and keeps
  // C: bound = maxAxisStepDegrees. Flipping C by 180 at the crest would break it.
  EXPECT_LE(test::maxAngularStep(mp, 3, 5), o.maxAxisStepDegrees + 1e-6);
  EXPECT_LE(mp.stats.poseCost, mp.stats.greedyPoseCost + 1e-9);
  // Greedy must at least go over 90 degrees of B; the optimum is exactly that (B: 45 -> -45).
  EXPECT_NEAR(mp.stats.poseCost, 90.0, 1e-6);
  EXPECT_LT(test::checkPlannedPoints(mp, tp), 1e-6);
  EXPECT_LE(test::maxChordDeviation(mp, false), o.chordTolerance * (1 + 1e-9));
  // Filament: every source move's pieces add up to its filament exactly.
  std::map<uint32_t, double> sum;
  for (const MachineMove& mv : mp.moves) sum[mv.source] += mv.filament;
  ASSERT_EQ(sum.size(), tp.moves.size());
  for (const auto& kv : sum) {
    EXPECT_NEAR(kv.second, tp.moves[kv.first].filament, 1e-12) << kv.first;
  }
}

// Without the filter (motion.smooth_orientations off) turns are still cut into steps of at most
// maxAxisStepDegrees along the great circle the tool path checked; before, the ridge's 90 degree
// flip was one move and the machine interpolated B and C linearly (a 40 mm yoga, voxel: 5,192
// colliding samples, 1,459 with the steps).
TEST(PlanMotion, Table5TurnsAreSubdividedWithoutTheFilter) {
  const Toolpath tp = test::crestToolpath(20, 30, 1.0, 3.0);
  const MachineProfile m = table5TestProfile();
  MotionOptions o;
  o.smoothOrientations = false;
  const MachinePath mp = planMachineMotion(tp, m, o);
  ASSERT_TRUE(mp.ok()) << mp.message;
  EXPECT_EQ(mp.stats.filteredOrientations, 0u);
  EXPECT_GE(mp.stats.subdivisions, 90u / 2 - 1);
  Eigen::Vector3d prevAxis, tip;
  forwardMap(m, mp.start, tip, prevAxis);
  for (const MachineMove& mv : mp.moves) {
    EXPECT_LE(angleDeg(prevAxis, mv.axis), o.maxAxisStepDegrees + 1e-6);
    prevAxis = mv.axis;
  }
  // Every source move's own axis is kept (no filter).
  for (const MachineMove& mv : mp.moves) {
    if (&mv == &mp.moves.back() || mv.source != (&mv + 1)->source) {
      EXPECT_LT(angleDeg(mv.axis, tp.moves[mv.source].axis.normalized()), 1e-6) << mv.source;
    }
  }
}

TEST(PlanMotion, Table5FeedLimitsHold) {
  const Toolpath tp = test::helixToolpath(15, 5, 1, 2, 0.8, 40);
  MachineProfile m = table5TestProfile();
  m.axisDynamics["X"] = {100, 800, 8000};
  m.axisDynamics["Y"] = {100, 800, 8000};
  m.axisDynamics["Z"] = {20, 200, 2000};
  m.axisDynamics["B"] = {30, 200, 2000};
  m.axisDynamics["C"] = {45, 300, 3000};
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  ASSERT_TRUE(mp.ok()) << mp.message;
  std::array<AxisDynamics, 6> dyn{};
  const char* names[5] = {"X", "Y", "Z", "B", "C"};
  for (int i = 0; i < 5; ++i) dyn[i] = m.axisDynamics.at(names[i]);
  // Linear axes: only their velocity is planned here (firmware plans their ramps).
  for (int i = 0; i < 3; ++i) dyn[i].acceleration = dyn[i].jerk = 0;
  const auto r = test::recomputeFeedRatios(mp, 5, dyn);
  EXPECT_LE(r[0], 1 + 1e-6);
  // Rotary axes B and C keep the acceleration and jerk limits of Eq. 7-9.
  EXPECT_LE(r[1], 1 + 1e-4);
  EXPECT_LE(r[2], 1 + 1e-4);
  EXPECT_GT(mp.stats.feedLimitedMoves, 0u);
  // Never faster than requested, and durations add up to the estimate (plus acceleration).
  double sum = 0;
  for (size_t k = 0; k < mp.moves.size(); ++k) {
    const MachineMove& mv = mp.moves[k];
    EXPECT_LE(mv.tipSpeed, tp.moves[mv.source].speed * (1 + 1e-9));
    EXPECT_GT(mv.durationS, 0);
    sum += mv.durationS;
  }
  EXPECT_GE(mp.stats.estimatedTimeS, sum);
  // Slower than the unlimited plan.
  const MachinePath free = planMachineMotion(tp, table5TestProfile(), o);
  ASSERT_TRUE(free.ok());
  EXPECT_GT(mp.stats.estimatedTimeS, free.stats.estimatedTimeS);
}

// Two parts on a rotary4 machine: part 0 printed along +Z, part 1 along (0, sin a, cos a)
// (A = a degrees). The change of A must happen at the safe height with the filament retracted.
Toolpath twoPartRotaryPath(bool retractBeforeSecondPart, double degrees = 30) {
  test::PathBuilder b(0.2, 0.45);
  b.path.start = {0, 0, 5};
  for (int l = 0; l < 3; ++l) {
    b.setLayer(l);
    test::rectLoop(b, -5, -5, 5, 5, 0.2 * (l + 1), Feature::WallOuter);
  }
  Toolpath tp = b.path;
  const double a = degrees * test::kMotionPi / 180;
  const Eigen::Vector3d u(0, std::sin(a), std::cos(a));
  const Eigen::Vector3d e1(1, 0, 0), e2 = u.cross(e1);
  const Eigen::Vector3d c(0, 10, 4);
  auto add = [&](const Eigen::Vector3d& p, MoveKind k, double f, int layer) {
    Move m;
    m.position = p;
    m.axis = u;
    m.kind = k;
    m.filament = f;
    m.speed = k == MoveKind::Travel ? 150 : (k == MoveKind::Print ? 30 : 35);
    m.part = 1;
    m.layer = layer;
    if (k == MoveKind::Print) {
      m.width = 0.45;
      m.height = 0.2;
      m.feature = Feature::WallOuter;
    }
    tp.moves.push_back(m);
  };
  if (retractBeforeSecondPart) {
    Move r = tp.moves.back();
    r.kind = MoveKind::Retract;
    r.filament = -0.8;
    r.speed = 35;
    tp.moves.push_back(r);
  }
  for (int l = 0; l < 2; ++l) {
    const Eigen::Vector3d o = c + 0.2 * (l + 1) * u;
    const Eigen::Vector3d corners[4] = {o - 4 * e1 - 4 * e2, o + 4 * e1 - 4 * e2,
                                        o + 4 * e1 + 4 * e2, o - 4 * e1 + 4 * e2};
    add(corners[0], MoveKind::Travel, 0, 3 + l);
    if (l == 0 && retractBeforeSecondPart) add(corners[0], MoveKind::Unretract, 0.8, 3);
    for (int k = 1; k <= 4; ++k) add(corners[k % 4], MoveKind::Print, 0.3, 3 + l);
  }
  tp.layerCount = 5;
  return tp;
}

void checkSafeRotation(const Toolpath& tp, double degrees = 30) {
  const MachineProfile m = rotary4TestProfile();
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  ASSERT_TRUE(mp.ok()) << mp.message;
  EXPECT_EQ(mp.stats.safeRotations, 1u);
  // Safe height, computed independently: highest machine Z of the extruding moves + safeLift.
  double top = -1e300;
  for (const MachineMove& mv : mp.moves) {
    if (mv.kind == MoveKind::Print) top = std::max(top, mv.values[2]);
  }
  const double safe = top + o.safeLift;
  bool retracted = false;
  int rotations = 0;
  MachineValues prev = mp.start;
  double filamentIn = 0, filamentOut = 0;
  for (const Move& mv : tp.moves) filamentIn += mv.filament;
  for (const MachineMove& mv : mp.moves) {
    filamentOut += mv.filament;
    if (std::abs(mv.values[3] - prev[3]) > 1e-9) {
      ++rotations;
      EXPECT_TRUE(retracted) << "A changes with the filament not retracted";
      EXPECT_GE(prev[2], safe - 1e-9);
      EXPECT_GE(mv.values[2], safe - 1e-9);
      EXPECT_EQ(mv.kind, MoveKind::Travel);
    }
    if (mv.filament < 0) retracted = true;
    if (mv.filament > 0) retracted = false;
    prev = mv.values;
  }
  EXPECT_EQ(rotations, 1);
  EXPECT_NEAR(filamentOut, filamentIn, 1e-12);
  EXPECT_NEAR(mp.moves.back().values[3], degrees, 1e-9);
  EXPECT_LT(test::checkPlannedPoints(mp, tp), 1e-6);
}

TEST(PlanMotion, Rotary4SafeRotationAfterToolpathRetract) { checkSafeRotation(twoPartRotaryPath(true)); }
TEST(PlanMotion, Rotary4SafeRotationAddsItsOwnRetract) { checkSafeRotation(twoPartRotaryPath(false)); }
// Between parts even a turn below the within-part threshold (rotationThresholdDegrees = 5) is a
// safe rotation: two parts of a 3+2 decomposition may differ by a fraction of a degree.
TEST(PlanMotion, Rotary4SmallTurnBetweenPartsIsStillSafe) {
  checkSafeRotation(twoPartRotaryPath(false, 0.3), 0.3);
}

// Rings of a tapering wall (radius 10 mm down to 6 mm over 20 layers) whose nozzle axis leans
// outwards 20 deg on even layers and 32 deg on odd ones, on table5: every ring-to-ring travel
// turns B by 12 deg (and C back by a turn), so it is a safe rotation within the part. Checked
// against every printed bead end, mapped by the platform transform at poses sampled along the
// turn: the nozzle tip stays at least safeClearance above the material while the platform
// turns and while it moves over, and the lifts are lower than those to the part's top + safeLift
// (what a declared machine.safeZ at that height gives).
Toolpath taperingRings() {
  Toolpath tp;
  tp.start = {10, 0, 3};
  for (int l = 0; l < 20; ++l) {
    const double z = 0.5 * (l + 1), r = 10 - 0.2 * l, tilt = (l % 2 ? 32.0 : 20.0) * test::kMotionPi / 180;
    const int n = 64;
    for (int k = 0; k <= n; ++k) {
      const double th = 2 * test::kMotionPi * k / n;
      const Eigen::Vector3d p(r * std::cos(th), r * std::sin(th), z);
      const Eigen::Vector3d u(std::sin(tilt) * std::cos(th), std::sin(tilt) * std::sin(th), std::cos(tilt));
      if (k == 0) {
        Move t = test::printMove(p, u, 0, l);
        t.kind = MoveKind::Travel;
        t.speed = 150;
        t.feature = Feature::None;
        tp.moves.push_back(t);
      } else {
        tp.moves.push_back(test::printMove(p, u, 0.03, l));
      }
    }
  }
  tp.layerCount = 20;
  return tp;
}

TEST(PlanMotion, RotationsWithinAPartLiftOnlyAboveThePrintedMaterial) {
  const Toolpath tp = taperingRings();
  MachineProfile m = table5TestProfile();
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  ASSERT_TRUE(mp.ok()) << mp.message;
  EXPECT_GE(mp.stats.safeRotations, 19u);
  std::vector<Eigen::Vector3d> printed;
  MachineValues prev = mp.start;
  Eigen::Vector3d prevTip;
  Eigen::Vector3d axis;
  forwardMap(m, mp.start, prevTip, axis);
  bool afterTurn = false;  // the move over at the safe height follows the turn
  size_t turns = 0;
  auto materialTop = [&](const MachineValues& v) {
    Eigen::Matrix4d T;
    EXPECT_TRUE(platformTransform(m, v, T));
    double top = -1e300;
    for (const Eigen::Vector3d& q : printed) top = std::max(top, (T.topLeftCorner<3, 3>() * q + T.topRightCorner<3, 1>()).z());
    return top;
  };
  for (const MachineMove& mv : mp.moves) {
    double turn = 0;
    for (int k = 3; k < 5; ++k) turn = std::max(turn, std::abs(mv.values[k] - prev[k]));
    if (mv.kind == MoveKind::Travel && turn > o.rotationThresholdDegrees && !printed.empty()) {
      ++turns;
      const int steps = static_cast<int>(std::ceil(turn / 0.5));
      for (int s = 0; s <= steps; ++s) {
        MachineValues v = prev;
        for (int k = 0; k < 5; ++k) v[k] = prev[k] + (mv.values[k] - prev[k]) * s / steps;
        ASSERT_GE(v[2], materialTop(v) + o.safeClearance - 1e-6) << "turn " << turns << " at " << s << "/" << steps;
      }
      afterTurn = true;
    } else if (afterTurn && mv.kind == MoveKind::Travel) {
      // The move over, at the safe height in the new pose.
      EXPECT_GE(std::min(prev[2], mv.values[2]), materialTop(mv.values) + o.safeClearance - 1e-6);
      afterTurn = false;
    }
    if (mv.kind == MoveKind::Print && mv.filament > 0) {
      printed.push_back(prevTip);
      printed.push_back(mv.tip);
    }
    prev = mv.values;
    prevTip = mv.tip;
  }
  EXPECT_EQ(turns, mp.stats.safeRotations);
  // The same path with the part's top + safeLift declared as the safe height.
  double top = -1e300;
  for (const MachineMove& mv : mp.moves) {
    if (mv.kind == MoveKind::Print) top = std::max(top, mv.values[2]);
  }
  auto zTravel = [](const MachinePath& path) {
    double sum = 0;
    MachineValues p = path.start;
    for (const MachineMove& mv : path.moves) {
      if (mv.kind == MoveKind::Travel) sum += std::abs(mv.values[2] - p[2]);
      p = mv.values;
    }
    return sum;
  };
  m.safeZ = top + o.safeLift;
  const MachinePath global = planMachineMotion(tp, m, o);
  ASSERT_TRUE(global.ok()) << global.message;
  EXPECT_EQ(global.stats.safeRotations, mp.stats.safeRotations);
  EXPECT_LT(zTravel(mp), 0.5 * zTravel(global)) << zTravel(mp) << " vs " << zTravel(global);
}

TEST(PlanMotion, Errors) {
  const Toolpath tp = test::crestToolpath(5, 10, 1.0);
  Toolpath zero = tp;
  zero.moves[3].axis = Eigen::Vector3d::Zero();
  MachinePath r = planMachineMotion(zero, table5TestProfile());
  EXPECT_EQ(r.status, Status::InvalidOption);
  EXPECT_NE(r.message.find("move 3"), std::string::npos) << r.message;

  Toolpath nan = tp;
  nan.moves[2].axis.x() = std::nan("");
  EXPECT_EQ(planMachineMotion(nan, table5TestProfile()).status, Status::InvalidOption);

  // rotary4 cannot tilt about Y: the crest's axes (+-x components) are out of reach.
  r = planMachineMotion(tp, rotary4TestProfile());
  EXPECT_EQ(r.status, Status::InvalidOption);
  EXPECT_NE(r.message.find("out of reach"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("move 0"), std::string::npos) << r.message;

  // cartesian3 cannot realise a tilted axis either.
  r = planMachineMotion(tp, cartesian3Profile({200, 200, 200}, 0.4));
  EXPECT_EQ(r.status, Status::InvalidOption);

  MotionOptions o;
  o.chordTolerance = 0;
  EXPECT_EQ(planMachineMotion(tp, table5TestProfile(), o).status, Status::InvalidOption);

  // An empty tool-path is fine: only the park pose.
  Toolpath empty;
  empty.start = {1, 2, 3};
  const MachinePath e = planMachineMotion(empty, table5TestProfile());
  ASSERT_TRUE(e.ok()) << e.message;
  EXPECT_TRUE(e.moves.empty());
  EXPECT_NEAR(e.start[2], 3, 1e-9);
  EXPECT_EQ(e.stats.estimatedTimeS, 0);
}

TEST(PlanMotion, CancelsQuickly) {
  const Toolpath tp = test::helixToolpath(20, 5, 0.2, 40, 0.5, 30);
  int calls = 0;
  const auto t0 = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point tCancel;
  const MachinePath r = planMachineMotion(tp, table5TestProfile(), {}, [&](const char* stage, double) {
    EXPECT_STREQ(stage, "motion");
    if (++calls == 5) {
      tCancel = std::chrono::steady_clock::now();
      return false;
    }
    return true;
  });
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_EQ(r.status, Status::Cancelled);
  EXPECT_TRUE(r.moves.empty());
  EXPECT_LT(std::chrono::duration<double>(t1 - tCancel).count(), 0.05);
  (void)t0;
}

}  // namespace
}  // namespace omnislice
