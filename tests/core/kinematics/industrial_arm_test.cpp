// SPDX-License-Identifier: MIT
// The ABB IRB 1200 and KUKA KR 6 profiles (machine.cpp) and the spherical-wrist inverse
// (robot_arm.h): the DH tables against each arm's kinematic chain as its makers draw it (joint
// origins and axes from the data sheets' dimension drawings, in orocos-kdl, in the controller's
// angles), the data sheets' flange positions at the controllers' home poses, FK(IK) round trips on
// random poses within the joint ranges, and the placement reaching the build volume.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <random>
#include <string>
#include <vector>

#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "kinematics/robot_arm.h"
#include "machine/machine.h"
#include "machine/machine_json.h"
#include "workspace_reach.h"

namespace omnislice {
namespace {

MachineProfile arm(const std::string& name) {
  const MachineProfileResult r = builtinMachine(name, Eigen::Vector3d(200, 200, 200), 0.4);
  EXPECT_TRUE(r.ok()) << r.message;
  return r.machine;
}

// The arm as a chain of joint origins (offsets from the previous joint at zero, mm) and axes in
// the base frame at the controller's zero, the flange frame turned so its z leaves the flange
// (x pointing down at zero): the makers' drawings, independent of any DH table.
struct DrawnArm {
  std::string name;
  KDL::Vector origins[6];
  KDL::Vector axes[6];
  double flangeOffset;  // mm along the last axis
};

const DrawnArm kDrawn[] = {
    {"robot6-irb1200",
     {{0, 0, 0}, {0, 0, 399.1}, {0, 0, 448}, {0, 0, 42}, {451, 0, 0}, {0, 0, 0}},
     {{0, 0, 1}, {0, 1, 0}, {0, 1, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}},
     82},
    {"robot6-kr6",
     {{0, 0, 400}, {25, 0, 0}, {455, 0, 0}, {0, 0, 35}, {420, 0, 0}, {0, 0, 0}},
     {{0, 0, -1}, {0, 1, 0}, {0, 1, 0}, {-1, 0, 0}, {0, 1, 0}, {-1, 0, 0}},
     80},
};

Eigen::Matrix4d drawnForward(const DrawnArm& d, const double controllerDeg[6]) {
  KDL::Chain chain;
  for (int i = 0; i < 6; ++i) {
    // Segment i: joint i at the origin of its frame, then the offset to joint i + 1.
    const KDL::Vector next = i < 5 ? d.origins[i + 1] : KDL::Vector(d.flangeOffset, 0, 0);
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Vector(0, 0, 0), d.axes[i], KDL::Joint::RotAxis),
                                  KDL::Frame(next)));
  }
  // Flange frame: z along the last axis' outward direction (+x at zero), x down.
  chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(KDL::Rotation::RotY(kPi / 2))));
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::JntArray q(6);
  for (int i = 0; i < 6; ++i) q(i) = controllerDeg[i] * kPi / 180;
  KDL::Frame f;
  EXPECT_GE(fk.JntToCart(q, f), 0);
  // The chain starts at the first joint's origin.
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = f.M(r, c);
    m(r, 3) = f.p(r) + d.origins[0](r);
  }
  return m;
}

JointValues toQ(const MachineProfile& m, const double controllerDeg[6]) {
  JointValues q;
  for (int i = 0; i < 6; ++i) q[i] = m.jointSigns[i] * controllerDeg[i] * kPi / 180;
  return q;
}

double poseDiff(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  return std::max((a.topRightCorner<3, 1>() - b.topRightCorner<3, 1>()).cwiseAbs().maxCoeff(),
                  (a.topLeftCorner<3, 3>() - b.topLeftCorner<3, 3>()).cwiseAbs().maxCoeff());
}

// Random controller angles within the profile's joint ranges (degrees).
void randomAngles(const MachineProfile& m, std::mt19937& rng, double deg[6]) {
  for (int i = 0; i < 6; ++i) {
    double lo = m.jointLimits[i].first, hi = m.jointLimits[i].second;  // of q = sign x angle
    if (m.jointSigns[i] < 0) {
      const double t = lo;
      lo = -hi;
      hi = -t;
    }
    std::uniform_real_distribution<double> u(std::max(lo, -kPi), std::min(hi, kPi));
    deg[i] = u(rng) * 180 / kPi;
  }
}

TEST(IndustrialArm, DhTableIsTheDrawnChain) {
  for (const DrawnArm& d : kDrawn) {
    const MachineProfile m = arm(d.name);
    EXPECT_TRUE(isSphericalWrist(m.dh)) << d.name;
    EXPECT_FALSE(isUrFamily(m.dh)) << d.name;
    std::mt19937 rng(3);
    double worst = 0;
    for (int k = 0; k < 2000; ++k) {
      double deg[6];
      randomAngles(m, rng, deg);
      const double diff = poseDiff(armForward(m.dh, toQ(m, deg)), drawnForward(d, deg));
      worst = std::max(worst, diff);
      ASSERT_LT(diff, 1e-9) << d.name << " sample " << k;
    }
    std::printf("%s: DH forward vs the drawn chain, worst %.3g\n", d.name.c_str(), worst);
  }
}

TEST(IndustrialArm, HomeFlangeAtTheDataSheetsPosition) {
  // ABB: every axis 0 (calibration position), flange centre 451 + 82 = 533 mm ahead, 399.1 + 448 +
  // 42 = 889.1 mm up, pointing forward. KUKA: A2 = -90, A3 = +90 (HOME), flange 25 + 420 + 80 =
  // 525 mm ahead, 400 + 455 + 35 = 890 mm up, pointing forward.
  struct Home {
    const char* name;
    double deg[6];
    Eigen::Vector3d flange;
  };
  for (const Home& h : {Home{"robot6-irb1200", {0, 0, 0, 0, 0, 0}, {533, 0, 889.1}},
                        Home{"robot6-kr6", {0, -90, 90, 0, 0, 0}, {525, 0, 890}}}) {
    const MachineProfile m = arm(h.name);
    const Eigen::Matrix4d f = armForward(m.dh, toQ(m, h.deg));
    EXPECT_LT((f.topRightCorner<3, 1>() - h.flange).norm(), 1e-9) << h.name;
    EXPECT_LT((f.block<3, 1>(0, 2) - Eigen::Vector3d::UnitX()).norm(), 1e-12) << h.name;
  }
}

TEST(IndustrialArm, InverseRoundTripsOnRandomPoses) {
  for (const DrawnArm& d : kDrawn) {
    const MachineProfile m = arm(d.name);
    std::mt19937 rng(5);
    int found = 0, total = 0, solutions = 0;
    double worstPose = 0;
    for (int k = 0; k < 5000; ++k) {
      double deg[6];
      randomAngles(m, rng, deg);
      const JointValues q = toQ(m, deg);
      const Eigen::Matrix4d flange = armForward(m.dh, q);
      JointValues sol[8];
      int br[8];
      const int n = armInverseBranches(m.dh, flange, 0xff, sol, br);
      ASSERT_GE(n, 1) << d.name << " sample " << k;
      ASSERT_LE(n, 8);
      ++total;
      solutions += n;
      bool original = false;
      int seen = 0;
      for (int s = 0; s < n; ++s) {
        const double diff = poseDiff(armForward(m.dh, sol[s]), flange);
        worstPose = std::max(worstPose, diff);
        EXPECT_LT(diff, 1e-6) << d.name << " sample " << k << " branch " << br[s];
        EXPECT_FALSE(seen >> br[s] & 1) << "branch twice";
        seen |= 1 << br[s];
        double dq = 0;
        for (int j = 0; j < 6; ++j) dq = std::max(dq, std::abs(std::remainder(sol[s][j] - q[j], 2 * kPi)));
        original = original || dq < 1e-6;
      }
      found += original;
      // A masked call returns exactly the masked branches of the full one.
      const int mask = 1 << br[0];
      JointValues one[8];
      int oneBr[8];
      ASSERT_EQ(armInverseBranches(m.dh, flange, mask, one, oneBr), 1);
      EXPECT_EQ(oneBr[0], br[0]);
      for (int j = 0; j < 6; ++j) EXPECT_EQ(one[0][j], sol[0][j]);
    }
    std::printf("%s: %d poses, %.2f solutions each, original found %d, worst FK(IK) %.3g\n",
                d.name.c_str(), total, double(solutions) / total, found, worstPose);
    EXPECT_EQ(found, total) << d.name;
  }
}

TEST(IndustrialArm, SingularWristIsFinite) {
  // q5 = 0: joints 4 and 6 in line; the inverse still returns finite poses that map forward.
  for (const DrawnArm& d : kDrawn) {
    const MachineProfile m = arm(d.name);
    const JointValues q{0.3, -0.2, 0.4, 0.7, 0.0, -0.5};
    const Eigen::Matrix4d flange = armForward(m.dh, q);
    JointValues sol[8];
    int br[8];
    const int n = armInverseBranches(m.dh, flange, 0xff, sol, br);
    ASSERT_GE(n, 1);
    for (int s = 0; s < n; ++s) {
      for (double v : sol[s]) EXPECT_TRUE(std::isfinite(v));
      EXPECT_LT(poseDiff(armForward(m.dh, sol[s]), flange), 1e-6) << d.name;
    }
  }
  // Out of reach: no solution.
  const MachineProfile m = arm("robot6-kr6");
  Eigen::Matrix4d far = Eigen::Matrix4d::Identity();
  far(0, 3) = 2000;
  JointValues sol[8];
  int br[8];
  EXPECT_EQ(armInverseBranches(m.dh, far, 0xff, sol, br), 0);
}

TEST(IndustrialArm, JsonRoundTripKeepsTheJointSigns) {
  const MachineProfile m = arm("robot6-kr6");
  const std::string json = machineJson(m);
  EXPECT_NE(json.find("\"joint_signs\":[-1,1,1,-1,1,-1]"), std::string::npos) << json;
  EXPECT_NE(json.find("\"ik_branches\":5"), std::string::npos) << json;
  const MachineParseResult back = machineFromJson(json);
  ASSERT_TRUE(back.ok()) << back.message;
  EXPECT_EQ(back.machine.jointSigns, m.jointSigns);
  EXPECT_EQ(back.machine.ikBranches, 5);
  EXPECT_EQ(machineJson(back.machine), json);
  // The UR5 keeps its JSON without the key.
  EXPECT_EQ(machineJson(arm("robot6-ur5")).find("joint_signs"), std::string::npos);
  std::string bad = json;
  bad.replace(bad.find("[-1,1,1,-1,1,-1]"), 16, "[-1,1,1,-1,1,2]");
  const MachineParseResult refused = machineFromJson(bad);
  EXPECT_EQ(refused.status, Status::ParseError);
  EXPECT_NE(refused.message.find("joint_signs"), std::string::npos);
  std::string noBranch = json;
  noBranch.replace(noBranch.find("\"ik_branches\":5"), 15, "\"ik_branches\":0");
  EXPECT_EQ(machineFromJson(noBranch).status, Status::ParseError);
}

TEST(IndustrialArm, ZeroPoseIsOnTheAllowedBranches) {
  // The controllers' zero and home poses (either wrist) are branches 0 and 2, the profiles'
  // ik_branches; the inverse restricted to them still round-trips such poses.
  struct Pose {
    const char* name;
    double deg[6];
  };
  for (const Pose& p : {Pose{"robot6-irb1200", {0, 0, 0, 0, 30, 0}}, Pose{"robot6-irb1200", {10, 30, -20, 40, -60, 5}},
                        Pose{"robot6-kr6", {0, -90, 90, 0, 30, 0}}, Pose{"robot6-kr6", {-10, -60, 70, 20, -60, 5}}}) {
    const MachineProfile m = arm(p.name);
    const JointValues q = toQ(m, p.deg);
    JointValues sol[8];
    int br[8];
    const int n = armInverseBranches(m.dh, armForward(m.dh, q), m.ikBranches, sol, br);
    bool found = false;
    for (int s = 0; s < n; ++s) {
      EXPECT_TRUE(m.ikBranches >> br[s] & 1);
      double dq = 0;
      for (int j = 0; j < 6; ++j) dq = std::max(dq, std::abs(std::remainder(sol[s][j] - q[j], 2 * kPi)));
      found = found || dq < 1e-9;
    }
    EXPECT_TRUE(found) << p.name << " " << p.deg[4];
  }
}

TEST(IndustrialArm, PlacementReachesTheBuildVolume) {
  // Every tip of a 100 mm cube on the platform, the nozzle axis vertical or tilted 30 and 60
  // degrees in 8 directions, has an inverse within the joint ranges, away from singularities.
  for (const DrawnArm& d : kDrawn) {
    const WorkspaceReach r = workspaceReach(arm(d.name));
    std::printf("%s workspace: %d poses, %d unreachable, min over poses of the best w_PS %.4f\n",
                d.name.c_str(), r.points, r.unreachable, r.minBest);
    EXPECT_EQ(r.unreachable, 0) << d.name;
    EXPECT_EQ(r.outsideLimits, 0) << d.name;
    EXPECT_GT(r.minBest, 0.05) << d.name;
  }
}

}  // namespace
}  // namespace omnislice
