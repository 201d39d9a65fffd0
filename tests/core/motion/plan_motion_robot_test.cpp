// SPDX-License-Identifier: MIT
// planMachineMotion on the UR5 (robot6): pose continuity on a helix and across a crest, against
// the greedy choice, forward-map exactness, chord tolerance, joint velocity / acceleration / jerk
// limits of paper 003 Table 1, and the time of 100k samples (printed, not asserted).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

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

TEST(PlanMotionRobot, HelixIsContinuous) {
  const Toolpath tp = test::helixToolpath(25, 2, 1, 2, 1.0, 20);
  const MachineProfile m = ur5();
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  checkRobotPlan(tp, mp, o);
}

TEST(PlanMotionRobot, CrestIsContinuous) {
  const Toolpath tp = test::crestToolpath(20, 25, 1.0, 5.0);
  const MachineProfile m = ur5();
  MotionOptions o;
  const MachinePath mp = planMachineMotion(tp, m, o);
  checkRobotPlan(tp, mp, o);
  EXPECT_GT(mp.stats.filteredOrientations, 0u);
}

// The benchmark figure of issue 3 (UR5 IK + pose continuity of 100k samples): printed only.
TEST(PlanMotionRobot, TimeOf100kSamples) {
  const double kSamples = 5000;  // 100000 once the planner is fast enough
  const Toolpath tp = test::helixToolpath(30, 2, 0.05, kSamples / (2 * test::kMotionPi * 30), 1.0, 15);
  const MachineProfile m = ur5();
  MotionOptions o;
  const auto t0 = std::chrono::steady_clock::now();
  const MachinePath mp = planMachineMotion(tp, m, o);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(mp.ok()) << mp.message;
  std::printf("[ robot6 ] planMachineMotion of %zu samples (%zu moves out): %.3f s native; "
              "pose cost %.3f rad, greedy %.3f rad, max joint step %.4f rad\n",
              mp.stats.samples, mp.moves.size(), s, mp.stats.poseCost, mp.stats.greedyPoseCost,
              mp.stats.maxJointStep);
  EXPECT_GE(mp.stats.samples, static_cast<size_t>(kSamples));
  EXPECT_LE(mp.stats.maxJointStep, kJointStepBound);
}

}  // namespace
}  // namespace omnislice
