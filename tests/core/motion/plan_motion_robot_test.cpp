// SPDX-License-Identifier: MIT
// planMachineMotion on the UR5 (robot6): pose continuity on a helix and across a crest, against
// the greedy choice, forward-map exactness, chord tolerance, joint velocity / acceleration / jerk
// limits of paper 003 Table 1, and the time of 100k samples (printed, not asserted).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "kinematics/kinematics.h"
#include "kinematics/robot_arm.h"
#include "motion/motion_test_support.h"
#include "motion/plan_motion.h"

namespace omnislice {
namespace {

MachineProfile ur5() {
  const MachineProfileResult r = builtinMachine("robot6-ur5", {200, 200, 200}, 0.4);
  EXPECT_TRUE(r.ok()) << r.message;
  return r.machine;
}

// A switch to the neighbouring free-rotation sample turns the platform by 2 pi / 30 = 0.21 rad
// about the nozzle axis, which moves the wrist joints by about that much; a change of IK branch
// (shoulder, elbow or wrist flip) or an unwinding by 2 pi moves some joint by more than 1 rad.
// 0.35 rad per move admits the first and excludes the others.
constexpr double kJointStepBound = 0.35;

void checkRobotPlan(const Toolpath& tp, const MachinePath& mp, const MotionOptions& o) {
  ASSERT_TRUE(mp.ok()) << mp.message;
  const double step = test::maxAngularStep(mp, 0, 6);
  std::printf("[ robot6 ] moves %zu samples %zu max joint step %.4f rad cost %.4f greedy %.4f "
              "penalty %.4f/%.4f min w %.4g subdivisions %zu filtered %zu\n",
              mp.moves.size(), mp.stats.samples, step, mp.stats.poseCost,
              mp.stats.greedyPoseCost, mp.stats.posePenalty, mp.stats.greedyPosePenalty,
              mp.stats.minSingularity, mp.stats.subdivisions, mp.stats.filteredOrientations);
  EXPECT_LE(step, kJointStepBound);
  EXPECT_NEAR(mp.stats.maxJointStep, step, 1e-12);
  // Exact optimum of the penalised objective vs greedy on the same candidates, and in practice
  // the L1 part alone.
  EXPECT_LE(mp.stats.poseCost + mp.stats.posePenalty,
            mp.stats.greedyPoseCost + mp.stats.greedyPosePenalty + 1e-6);
  EXPECT_LE(mp.stats.poseCost, mp.stats.greedyPoseCost + 1e-6);
  EXPECT_GT(mp.stats.minSingularity, 0);
  if (mp.stats.subdivisions == 0) {
    // Every move ends on a chosen pose: the smallest measure over them, by brute force.
    double mn = singularityMeasure(armJacobian(mp.machine.dh, mp.start));
    for (const MachineMove& mv : mp.moves) {
      mn = std::min(mn, singularityMeasure(armJacobian(mp.machine.dh, mv.values)));
    }
    EXPECT_NEAR(mp.stats.minSingularity, mn, 1e-9);
  }
  EXPECT_LT(test::checkPlannedPoints(mp, tp), 1e-6);
  EXPECT_LE(test::maxChordDeviation(mp, false), o.chordTolerance * (1 + 1e-6));
  for (const MachineMove& mv : mp.moves) {
    EXPECT_TRUE(withinLimits(mp.machine, mv.values, 1e-9));
  }
  // No two consecutive nozzle axes differ by more than the axis step.
  Eigen::Vector3d prevAxis, tip;
  forwardMap(mp.machine, mp.start, tip, prevAxis);
  double worstAxis = 0;
  for (const MachineMove& mv : mp.moves) {
    worstAxis = std::max(worstAxis, test::angleDeg(prevAxis, mv.axis));
    prevAxis = mv.axis;
  }
  EXPECT_LE(worstAxis, o.maxAxisStepDegrees + 1e-6);
  // Joint dynamics of paper 003 Table 1.
  const auto r = test::recomputeFeedRatios(mp, 6, mp.machine.jointDynamics);
  EXPECT_LE(r[0], 1 + 1e-6);
  EXPECT_LE(r[1], 1 + 1e-4);
  EXPECT_LE(r[2], 1 + 1e-4);
}

TEST(PlanMotionRobot, FastSingularityMeasureMatchesSvd) {
  const MachineProfile m = ur5();
  std::srand(11);
  for (int i = 0; i < 2000; ++i) {
    JointValues q;
    for (double& v : q) v = (std::rand() / double(RAND_MAX) * 2 - 1) * 3.14159;
    if (i % 10 == 0) q[4] = 1e-4 * i;  // near the wrist singularity too
    const auto j = armJacobian(m.dh, q);
    EXPECT_NEAR(fastSingularityMeasure(j), singularityMeasure(j), 1e-7) << i;
  }
}

// Default options (track DP) with compareGreedy: never worse than greedy by construction; the
// track DP's own result (no fallback taken) is already below greedy; the exact choosePoses() on
// the same path is at most a few percent cheaper.
void compareWithGreedyAndExact(const Toolpath& tp, const char* name, double& ratio,
                               const MotionOptions& base = {}) {
  const MachineProfile m = ur5();
  MotionOptions o = base;
  o.compareGreedy = true;
  const MachinePath mp = planMachineMotion(tp, m, o);
  checkRobotPlan(tp, mp, o);
  ASSERT_TRUE(mp.ok());
  ASSERT_GE(mp.stats.greedyPoseCost, 0);
  // The fallback was not needed: the returned path is the track DP's.
  EXPECT_FALSE(mp.stats.greedyPoseUsed);
  MotionOptions plain = base;  // no greedy pass: same track path, greedy not reported
  const MachinePath mt = planMachineMotion(tp, m, plain);
  ASSERT_TRUE(mt.ok()) << mt.message;
  EXPECT_EQ(mt.stats.greedyPoseCost, -1);
  EXPECT_NEAR(mt.stats.poseCost, mp.stats.poseCost, 1e-9);
  EXPECT_NEAR(mt.stats.posePenalty, mp.stats.posePenalty, 1e-9);
  EXPECT_LE(mt.stats.poseCost + mt.stats.posePenalty,
            mp.stats.greedyPoseCost + mp.stats.greedyPosePenalty + 1e-6);
  EXPECT_LE(mt.stats.maxJointStep, kJointStepBound);
  MotionOptions exact = o;
  exact.trackPoses = false;
  exact.maxKeptPoses = 0;
  const MachinePath me = planMachineMotion(tp, m, exact);
  checkRobotPlan(tp, me, exact);
  const double track = mt.stats.poseCost + mt.stats.posePenalty;
  const double ex = me.stats.poseCost + me.stats.posePenalty;
  ratio = track / ex;
  std::printf("[ robot6 ] %s: %zu samples; track %.4f (+%.4f penalty), exact %.4f (+%.4f), "
              "greedy %.4f (+%.4f); track / exact %.4f; IK calls %zu (%.2f per sample), "
              "alive %.2f per sample, restarts %zu\n",
              name, mt.stats.samples, mt.stats.poseCost, mt.stats.posePenalty, me.stats.poseCost,
              me.stats.posePenalty, mp.stats.greedyPoseCost, mp.stats.greedyPosePenalty, ratio,
              mt.stats.poseIkCalls, double(mt.stats.poseIkCalls) / (mt.stats.samples + 1),
              double(mt.stats.poseAliveNodes) / (mt.stats.samples + 1), mt.stats.poseRestarts);
  // The exact optimum is a lower bound; the track DP stays within 5 % (+ 0.05 rad).
  EXPECT_LE(ex, track + 1e-9);
  EXPECT_LE(track, 1.05 * ex + 0.05);
}

TEST(PlanMotionRobot, HelixIsContinuous) {
  double ratio = 0;
  compareWithGreedyAndExact(test::helixToolpath(25, 2, 1, 2, 1.0, 20), "helix", ratio);
}

TEST(PlanMotionRobot, CrestIsContinuous) {
  const Toolpath tp = test::crestToolpath(20, 25, 1.0, 5.0);
  double ratio = 0;
  compareWithGreedyAndExact(tp, "crest", ratio);
  MotionOptions o;
  EXPECT_GT(planMachineMotion(tp, ur5(), o).stats.filteredOrientations, 0u);
}

// A steeper, longer helix (the nozzle axis turns 360 degrees per turn at 35 degrees of tilt).
TEST(PlanMotionRobot, TiltedHelixNearExact) {
  double ratio = 0;
  compareWithGreedyAndExact(test::helixToolpath(35, 5, 0.5, 3, 1.0, 35), "tilted helix", ratio);
}

// The rated arm (robot6-ur5-rated) follows the same poses as paper 003's limits (dynamics do not
// enter the pose choice) and keeps its own, faster, joint limits: velocity pi rad/s and 5 rad/s^2
// (no jerk limit), so the same path takes less time.
TEST(PlanMotionRobot, RatedArmSamePosesLessTime) {
  const Toolpath tp = test::helixToolpath(35, 5, 0.5, 3, 1.0, 35);
  const MachinePath paper = planMachineMotion(tp, ur5(), {});
  const MachineProfileResult rr = builtinMachine("robot6-ur5-rated", {200, 200, 200}, 0.4);
  ASSERT_TRUE(rr.ok()) << rr.message;
  const MachinePath rated = planMachineMotion(tp, rr.machine, {});
  ASSERT_TRUE(paper.ok() && rated.ok()) << paper.message << rated.message;
  ASSERT_EQ(paper.moves.size(), rated.moves.size());
  for (size_t k = 0; k < paper.moves.size(); ++k) {
    for (int i = 0; i < 6; ++i) ASSERT_EQ(paper.moves[k].values[i], rated.moves[k].values[i]) << k;
  }
  const auto r = test::recomputeFeedRatios(rated, 6, rated.machine.jointDynamics);
  EXPECT_LE(r[0], 1 + 1e-6);
  EXPECT_LE(r[1], 1 + 1e-4);
  std::printf("[ robot6 ] helix: %.1f s at paper 003's joint limits, %.1f s rated\n",
              paper.stats.estimatedTimeS, rated.stats.estimatedTimeS);
  EXPECT_LT(rated.stats.estimatedTimeS, paper.stats.estimatedTimeS);
  // On this smooth helix paper 003's jerk limit costs little once the durations share their slack
  // (feed_limits.cpp tighten(): 26.0 s; lowering each move to its floor where it could left
  // 155.8 s, feeds alternating fast and slow).
  EXPECT_LT(paper.stats.estimatedTimeS, 1.5 * rated.stats.estimatedTimeS);
}

// Penalties in play: a singularity threshold above the measure of most poses of the path (w is
// about 0.085-0.1 there) makes every pose pay a penalty that varies along the tracks.
TEST(PlanMotionRobot, PenaltiesNearExact) {
  MotionOptions o;
  o.singularityThreshold = 0.11;
  o.singularityPenalty = 0.05;
  double ratio = 0;
  const Toolpath tp = test::helixToolpath(35, 5, 0.5, 3, 1.0, 35);
  compareWithGreedyAndExact(tp, "tilted helix with penalties", ratio, o);
  const MachinePath mp = planMachineMotion(tp, ur5(), o);
  EXPECT_GT(mp.stats.posePenalty, 0);
}

// An empty tool-path: only the park pose, the one of largest measure among the candidates at
// the start (all cost 0); progress stays monotonic with the greedy pass and cancels.
TEST(PlanMotionRobot, EmptyPathAndProgress) {
  Toolpath empty;
  empty.start = {10, 20, 5};
  const MachinePath e = planMachineMotion(empty, ur5());
  ASSERT_TRUE(e.ok()) << e.message;
  EXPECT_TRUE(e.moves.empty());
  Eigen::Vector3d tip, axis;
  ASSERT_TRUE(forwardMap(e.machine, e.start, tip, axis));
  EXPECT_LT((tip - empty.start).norm(), 1e-6);
  const IkResult all = inverseMap(e.machine, empty.start, Eigen::Vector3d::UnitZ());
  double best = 0;
  for (const IkCandidate& c : all.candidates) {
    best = std::max(best, fastSingularityMeasure(armJacobian(e.machine.dh, c.values)));
  }
  EXPECT_NEAR(fastSingularityMeasure(armJacobian(e.machine.dh, e.start)), best, 1e-12);

  const Toolpath tp = test::helixToolpath(25, 2, 1, 1, 0.5, 20);
  MotionOptions o;
  o.compareGreedy = true;
  double last = -1;
  bool monotonic = true;
  const MachinePath mp = planMachineMotion(tp, ur5(), o, [&](const char*, double f) {
    monotonic = monotonic && f >= last;
    last = f;
    return true;
  });
  ASSERT_TRUE(mp.ok()) << mp.message;
  EXPECT_TRUE(monotonic);
  EXPECT_EQ(last, 1.0);
  int calls = 0;
  const MachinePath c = planMachineMotion(tp, ur5(), o, [&](const char*, double) { return ++calls < 3; });
  EXPECT_EQ(c.status, Status::Cancelled);
  EXPECT_TRUE(c.moves.empty());
}

// A sample beyond the arm's reach: InvalidOption naming the move, from the track DP's full
// evaluation (the same message as choosePoses()).
TEST(PlanMotionRobot, OutOfReachNamesTheMove) {
  Toolpath tp = test::helixToolpath(25, 2, 1, 0.5, 1.0, 20);
  const size_t bad = tp.moves.size() / 2;
  tp.moves[bad].position = {3000, 0, 5};
  for (const bool track : {true, false}) {
    MotionOptions o;
    o.trackPoses = track;
    const MachinePath mp = planMachineMotion(tp, ur5(), o);
    EXPECT_EQ(mp.status, Status::InvalidOption);
    EXPECT_NE(mp.message.find("move " + std::to_string(bad) + " "), std::string::npos) << mp.message;
    EXPECT_NE(mp.message.find("out of reach"), std::string::npos) << mp.message;
    EXPECT_TRUE(mp.moves.empty());
  }
  MotionOptions o;
  o.trackSlack = -1;
  EXPECT_EQ(planMachineMotion(tp, ur5(), o).status, Status::InvalidOption);
}

// The capped choosePoses() still works for robot6 (trackPoses = false).
TEST(PlanMotionRobot, CappedChoosePosesStillWorks) {
  const Toolpath tp = test::helixToolpath(25, 2, 1, 1, 1.0, 20);
  MotionOptions o;
  o.trackPoses = false;
  o.maxKeptPoses = 16;
  const MachinePath mp = planMachineMotion(tp, ur5(), o);
  checkRobotPlan(tp, mp, o);
}

// Planar-like layers: points 1 mm apart, zig-zag rows 1 mm apart over 80 x 80 mm, axis +Z,
// layers 0.2 mm apart until `samples` points.
Toolpath zigzagToolpath(size_t samples) {
  Toolpath tp;
  tp.start = {-40, -40, 0.2};
  Eigen::Vector3d prev = tp.start;
  int layer = 0;
  while (tp.moves.size() < samples) {
    const double z = 0.2 * (layer + 1);
    for (int row = 0; row <= 80 && tp.moves.size() < samples; ++row) {
      const double y = -40 + row;
      for (int i = 0; i <= 80 && tp.moves.size() < samples; ++i) {
        const double x = row % 2 == 0 ? -40 + i : 40 - i;
        const Eigen::Vector3d p(x, y, z);
        if ((p - prev).norm() < 1e-9) continue;
        tp.moves.push_back(test::printMove(p, {0, 0, 1}, 0.033 * (p - prev).norm(), layer));
        if (row == 0 && i == 0) {  // to the start of a layer: a travel
          tp.moves.back().kind = MoveKind::Travel;
          tp.moves.back().filament = 0;
        }
        prev = p;
      }
    }
    ++layer;
  }
  tp.layerCount = layer;
  return tp;
}

double timePlan(const Toolpath& tp, const MotionOptions& o, const char* name, MachinePath& mp) {
  const MachineProfile m = ur5();
  const auto t0 = std::chrono::steady_clock::now();
  mp = planMachineMotion(tp, m, o);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ robot6 ] planMachineMotion %s of %zu samples (%s, %zu moves out): %.3f s "
              "native; pose cost %.3f rad + %.3f penalty, greedy %.3f, max joint step %.4f rad, "
              "IK calls %.2f per sample, alive %.2f per sample, restarts %zu\n",
              name, mp.stats.samples, o.trackPoses ? "track DP" : "choosePoses", mp.moves.size(),
              s, mp.stats.poseCost, mp.stats.posePenalty, mp.stats.greedyPoseCost,
              mp.stats.maxJointStep, double(mp.stats.poseIkCalls) / (mp.stats.samples + 1),
              double(mp.stats.poseAliveNodes) / (mp.stats.samples + 1), mp.stats.poseRestarts);
  return s;
}

// The benchmark figure of issue 3 (UR5 IK + pose continuity of 100k samples): printed only.
TEST(PlanMotionRobot, TimeOf100kSamples) {
  const Toolpath zigzag = zigzagToolpath(100000);
  {
    // The inverse kinematics alone (30 free-rotation samples x 8 branches per point).
    const MachineProfile m = ur5();
    size_t candidates = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const Move& mv : zigzag.moves) candidates += inverseMap(m, mv.position, mv.axis).candidates.size();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("[ robot6 ] inverseMap alone for %zu samples: %.3f s native (%zu candidates)\n",
                zigzag.moves.size(), s, candidates);
  }
  MotionOptions o;
  MachinePath mp;
  timePlan(zigzag, o, "zig-zag", mp);
  ASSERT_TRUE(mp.ok()) << mp.message;
  EXPECT_GE(mp.stats.samples, 100000u);
  EXPECT_LE(mp.stats.maxJointStep, kJointStepBound);
  EXPECT_LT(test::checkPlannedPoints(mp, zigzag), 1e-6);
  const Toolpath helix = test::helixToolpath(30, 2, 0.05, 100000 / (2 * test::kMotionPi * 30), 1.0, 15);
  timePlan(helix, o, "helix", mp);
  ASSERT_TRUE(mp.ok()) << mp.message;
  EXPECT_LE(mp.stats.maxJointStep, kJointStepBound);
  // The same zig-zag's first 3000 samples against the exact choosePoses (slow: 0.8 ms/sample).
  const Toolpath small = zigzagToolpath(3000);
  MachinePath track, exact;
  timePlan(small, o, "zig-zag", track);
  MotionOptions ex = o;
  ex.trackPoses = false;
  timePlan(small, ex, "zig-zag", exact);
  ASSERT_TRUE(track.ok() && exact.ok());
  const double t = track.stats.poseCost + track.stats.posePenalty;
  const double e = exact.stats.poseCost + exact.stats.posePenalty;
  std::printf("[ robot6 ] zig-zag 3000: track / exact %.4f, exact greedy %.3f\n", t / e,
              exact.stats.greedyPoseCost + exact.stats.greedyPosePenalty);
  EXPECT_LE(e, t + 1e-9);
  EXPECT_LE(t, 1.05 * e + 0.05);
}

}  // namespace
}  // namespace omnislice
