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

TEST(PlanMotionRobot, HelixIsContinuous) {
  const Toolpath tp = test::helixToolpath(25, 2, 1, 2, 1.0, 20);
  const MachineProfile m = ur5();
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  checkRobotPlan(tp, mp, o);
  MotionOptions exact = o;
  exact.maxKeptPoses = 0;
  const MachinePath me = planMachineMotion(tp, m, exact);
  checkRobotPlan(tp, me, exact);
  EXPECT_LE(me.stats.poseCost + me.stats.posePenalty,
            mp.stats.poseCost + mp.stats.posePenalty + 1e-9);
}

TEST(PlanMotionRobot, CrestIsContinuous) {
  const Toolpath tp = test::crestToolpath(20, 25, 1.0, 5.0);
  const MachineProfile m = ur5();
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  checkRobotPlan(tp, mp, o);
  EXPECT_GT(mp.stats.filteredOrientations, 0u);
  // The exact shortest path (no cap on the kept nodes) is never worse than the capped one.
  MotionOptions exact = o;
  exact.maxKeptPoses = 0;
  const MachinePath me = planMachineMotion(tp, m, exact);
  checkRobotPlan(tp, me, exact);
  EXPECT_LE(me.stats.poseCost + me.stats.posePenalty,
            mp.stats.poseCost + mp.stats.posePenalty + 1e-9);
}

// The benchmark figure of issue 3 (UR5 IK + pose continuity of 100k samples): printed only.
// 100k samples with the capped pose choice (maxKeptPoses = 16), and 10k with the exact default.
double timePlan(double samples, int maxKept, MachinePath& mp) {
  const Toolpath tp =
      test::helixToolpath(30, 2, 0.05, samples / (2 * test::kMotionPi * 30), 1.0, 15);
  MotionOptions o;
  o.maxKeptPoses = maxKept;
  const auto t0 = std::chrono::steady_clock::now();
  mp = planMachineMotion(tp, ur5(), o);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ robot6 ] planMachineMotion of %zu samples (maxKeptPoses %d, %zu moves out): "
              "%.3f s native; pose cost %.3f rad, greedy %.3f rad, max joint step %.4f rad\n",
              mp.stats.samples, maxKept, mp.moves.size(), s, mp.stats.poseCost,
              mp.stats.greedyPoseCost, mp.stats.maxJointStep);
  return s;
}

TEST(PlanMotionRobot, TimeOf100kSamples) {
  {
    // The inverse kinematics alone (30 free-rotation samples x 8 branches per point).
    const Toolpath tp = test::helixToolpath(30, 2, 0.05, 100000 / (2 * test::kMotionPi * 30), 1.0, 15);
    const MachineProfile m = ur5();
    size_t candidates = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const Move& mv : tp.moves) candidates += inverseMap(m, mv.position, mv.axis).candidates.size();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("[ robot6 ] inverseMap alone for %zu samples: %.3f s native (%zu candidates)\n",
                tp.moves.size(), s, candidates);
  }
  MachinePath capped, exact;
  timePlan(100000, 16, capped);
  ASSERT_TRUE(capped.ok()) << capped.message;
  EXPECT_GE(capped.stats.samples, 100000u);
  EXPECT_LE(capped.stats.maxJointStep, kJointStepBound);
  EXPECT_LE(capped.stats.poseCost + capped.stats.posePenalty,
            capped.stats.greedyPoseCost + capped.stats.greedyPosePenalty + 1e-6);
  timePlan(10000, 0, exact);
  ASSERT_TRUE(exact.ok()) << exact.message;
  EXPECT_LE(exact.stats.maxJointStep, kJointStepBound);
}

}  // namespace
}  // namespace omnislice
