// SPDX-License-Identifier: MIT
// robot_arm.h: UR forward kinematics against Debian's orocos-kdl, the analytic inverse (every
// branch maps forward to the flange pose, the original is among the branches), degenerate poses,
// the Jacobian against finite differences, and paper 003's singularity measure.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <ctime>
#include <cmath>
#include <cstdio>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <random>
#include <vector>

#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "kinematics/robot_arm.h"

namespace omnislice {
namespace {


double wrappedDiff(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }

// Largest difference between two poses: translation (mm) and rotation matrix entries.
double poseDiff(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  return std::max((a.topRightCorner<3, 1>() - b.topRightCorner<3, 1>()).cwiseAbs().maxCoeff(),
                  (a.topLeftCorner<3, 3>() - b.topLeftCorner<3, 3>()).cwiseAbs().maxCoeff());
}

JointValues randomJoints(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-kPi, kPi);
  JointValues q;
  for (double& v : q) v = u(rng);
  return q;
}

// A UR-like table with non-zero theta offsets (exercises the offset handling of urInverse).
DhTable offsetTable() {
  DhTable dh = ur5DhTable();
  const double off[6] = {0.3, -kPi / 2, 0.1, kPi / 2, -0.7, 1.2};
  for (int i = 0; i < 6; ++i) dh[i].thetaOffset = off[i];
  return dh;
}

TEST(RobotArm, ForwardMatchesOrocosKdl) {
  for (const DhTable& dh : {ur5DhTable(), offsetTable()}) {
    KDL::Chain chain;
    for (const DhRow& r : dh) {
      chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ),
                                    KDL::Frame::DH(r.a, r.alpha, r.d, r.thetaOffset)));
    }
    KDL::ChainFkSolverPos_recursive fk(chain);
    std::mt19937 rng(11);
    double worst = 0;
    for (int i = 0; i < 5000; ++i) {
      const JointValues q = randomJoints(rng);
      KDL::JntArray jq(6);
      for (int j = 0; j < 6; ++j) jq(j) = q[j];
      KDL::Frame f;
      ASSERT_GE(fk.JntToCart(jq, f), 0);
      Eigen::Matrix4d k = Eigen::Matrix4d::Identity();
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) k(r, c) = f.M(r, c);
        k(r, 3) = f.p(r);
      }
      const double d = poseDiff(armForward(dh, q), k);
      worst = std::max(worst, d);
      ASSERT_LT(d, 1e-9) << "sample " << i;
      // armFrames ends at the same flange.
      EXPECT_LT(poseDiff(armFrames(dh, q)[6], k), 1e-9);
    }
    std::printf("armForward vs KDL: worst difference %.3g (mm / rotation entries)\n", worst);
  }
}

TEST(RobotArm, UrFamilyStructure) {
  EXPECT_TRUE(isUrFamily(ur5DhTable()));
  EXPECT_TRUE(isUrFamily(offsetTable()));
  DhTable bad = ur5DhTable();
  bad[3].a = 5;
  EXPECT_FALSE(isUrFamily(bad));
  bad = ur5DhTable();
  bad[4].alpha = kPi / 2;
  EXPECT_FALSE(isUrFamily(bad));
  bad = ur5DhTable();
  bad[1].d = std::nan("");
  EXPECT_FALSE(isUrFamily(bad));
}

// Every branch maps forward to the flange pose, the original q is one of them (mod 2 pi), the
// branches are distinct and each joint is in (-pi, pi].
TEST(RobotArm, InverseEveryBranchRoundTrips) {
  for (const DhTable& dh : {ur5DhTable(), offsetTable()}) {
    std::mt19937 rng(12);
    int eight = 0;
    for (int i = 0; i < 5000; ++i) {
      const JointValues q = randomJoints(rng);
      const Eigen::Matrix4d f = armForward(dh, q);
      JointValues sol[8];
      int br[8];
      const int n = urInverse(dh, f, sol, br);
      ASSERT_GE(n, 1);
      eight += n == 8;
      bool found = false;
      int seenBranches = 0;
      for (int s = 0; s < n; ++s) {
        for (double v : sol[s]) {
          EXPECT_TRUE(v > -kPi - 1e-12 && v <= kPi + 1e-12) << v;
        }
        const Eigen::Matrix4d g = armForward(dh, sol[s]);
        EXPECT_LT((g.topRightCorner<3, 1>() - f.topRightCorner<3, 1>()).norm(), 1e-6)
            << "branch " << br[s];
        // Rotation error as an angle (rad).
        const Eigen::Matrix3d dr = g.topLeftCorner<3, 3>().transpose() * f.topLeftCorner<3, 3>();
        EXPECT_LT(std::acos(std::min(1.0, (dr.trace() - 1) / 2)), 1e-6) << "branch " << br[s];
        seenBranches |= 1 << br[s];
        double d = 0;
        for (int j = 0; j < 6; ++j) d = std::max(d, wrappedDiff(sol[s][j], q[j]));
        found = found || d < 1e-6;
      }
      EXPECT_TRUE(found) << "sample " << i;
      if (n == 8) {
        EXPECT_EQ(seenBranches, 255);
      }
    }
    EXPECT_GT(eight, 3500);  // about 78 % of random UR5 poses are reachable by all 8 branches
  }
}

// urInverseBranches() returns exactly urInverse()'s solutions of the masked branches.
TEST(RobotArm, MaskedInverseIsASubset) {
  const DhTable dh = offsetTable();
  std::mt19937 rng(16);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Matrix4d f = armForward(dh, randomJoints(rng));
    JointValues all[8], some[8];
    int brAll[8], brSome[8];
    const int n = urInverse(dh, f, all, brAll);
    const int mask = static_cast<int>(rng() % 256);
    const int m = urInverseBranches(dh, f, mask, some, brSome);
    int expected = 0;
    for (int s = 0; s < n; ++s) expected += mask >> brAll[s] & 1;
    ASSERT_EQ(m, expected) << "mask " << mask;
    for (int s = 0; s < m; ++s) {
      EXPECT_TRUE(mask >> brSome[s] & 1);
      int match = -1;
      for (int t = 0; t < n; ++t) {
        if (brAll[t] == brSome[s]) match = t;
      }
      ASSERT_GE(match, 0);
      for (int j = 0; j < 6; ++j) EXPECT_NEAR(some[s][j], all[match][j], 1e-12);
    }
  }
}

// A branch keeps its index along a continuous motion away from singularities.
TEST(RobotArm, BranchIndexIsStableAlongAMotion) {
  const DhTable dh = ur5DhTable();
  JointValues q{0.3, -1.2, 1.4, -1.7, 1.1, 0.4};
  JointValues sol[8];
  int br[8];
  const int n0 = urInverse(dh, armForward(dh, q), sol, br);
  ASSERT_EQ(n0, 8);
  int branch = -1;
  for (int s = 0; s < 8; ++s) {
    double d = 0;
    for (int j = 0; j < 6; ++j) d += wrappedDiff(sol[s][j], q[j]);
    if (d < 1e-9) branch = br[s];
  }
  ASSERT_GE(branch, 0);
  for (int k = 0; k < 200; ++k) {
    for (int j = 0; j < 6; ++j) q[j] += 0.002 * (j + 1);
    const int n = urInverse(dh, armForward(dh, q), sol, br);
    ASSERT_EQ(n, 8);
    for (int s = 0; s < 8; ++s) {
      if (br[s] != branch) continue;
      double d = 0;
      for (int j = 0; j < 6; ++j) d += wrappedDiff(sol[s][j], q[j]);
      EXPECT_LT(d, 1e-6) << "step " << k;
    }
  }
}

// Degenerate poses give finite solutions that map forward to the pose.
TEST(RobotArm, InverseAtSingularPosesIsFinite) {
  const DhTable dh = ur5DhTable();
  const std::vector<JointValues> poses{
      {0.4, -1.0, 1.2, 0.3, 0.0, 0.7},     // wrist singularity q5 = 0
      {0.4, -1.0, 1.2, 0.3, kPi, 0.7},     // q5 = pi
      {0.2, -0.8, 0.0, 0.5, 1.0, -0.3},    // elbow stretched q3 = 0
      {0.0, 0.0, 0.0, 0.0, 0.0, 0.0},      // zero pose: stretched and wrist-singular
      {1.0, -kPi / 2, 0, -kPi / 2, 0, 0},  // arm straight up
  };
  for (const JointValues& q : poses) {
    const Eigen::Matrix4d f = armForward(dh, q);
    JointValues sol[8];
    int br[8];
    const int n = urInverse(dh, f, sol, br);
    ASSERT_GE(n, 1);
    bool found = false;
    for (int s = 0; s < n; ++s) {
      for (double v : sol[s]) ASSERT_TRUE(std::isfinite(v));
      EXPECT_LT(poseDiff(armForward(dh, sol[s]), f), 1e-6) << "branch " << br[s];
      double d = 0;
      for (int j = 0; j < 6; ++j) d = std::max(d, wrappedDiff(sol[s][j], q[j]));
      found = found || d < 1e-6;
    }
    // Away from the wrist singularity (where q4 and q6 trade off) the original is recovered.
    if (std::abs(std::sin(q[4])) > 0.1) {
      EXPECT_TRUE(found);
    }
  }
  // Out of reach: nothing, and a non-finite pose: nothing.
  Eigen::Matrix4d far = Eigen::Matrix4d::Identity();
  far(0, 3) = 2000;
  JointValues sol[8];
  int br[8];
  EXPECT_EQ(urInverse(dh, far, sol, br), 0);
  far(0, 3) = std::nan("");
  EXPECT_EQ(urInverse(dh, far, sol, br), 0);
}

TEST(RobotArm, JacobianMatchesFiniteDifferences) {
  const DhTable dh = offsetTable();
  std::mt19937 rng(13);
  for (int i = 0; i < 200; ++i) {
    const JointValues q = randomJoints(rng);
    const Eigen::Matrix<double, 6, 6> j = armJacobian(dh, q);
    const Eigen::Matrix4d f0 = armForward(dh, q);
    const double h = 1e-6;
    for (int c = 0; c < 6; ++c) {
      JointValues qp = q, qm = q;
      qp[c] += h;
      qm[c] -= h;
      const Eigen::Matrix4d fp = armForward(dh, qp), fm = armForward(dh, qm);
      const Eigen::Vector3d v = (fp.topRightCorner<3, 1>() - fm.topRightCorner<3, 1>()) / (2 * h);
      // Angular velocity from dR/dq R^T (skew-symmetric).
      const Eigen::Matrix3d dr = (fp.topLeftCorner<3, 3>() - fm.topLeftCorner<3, 3>()) / (2 * h);
      const Eigen::Matrix3d w = dr * f0.topLeftCorner<3, 3>().transpose();
      const Eigen::Vector3d omega(w(2, 1), w(0, 2), w(1, 0));
      EXPECT_LT((j.block<3, 1>(0, c) - v * 1e-3).norm(), 1e-6) << "column " << c;
      EXPECT_LT((j.block<3, 1>(3, c) - omega).norm(), 1e-6) << "column " << c;
    }
  }
}

TEST(RobotArm, SingularityMeasureVanishesAtSingularPoses) {
  const DhTable dh = ur5DhTable();
  const JointValues wrist{0.4, -1.0, 1.2, 0.3, 0.0, 0.7};
  const JointValues elbow{0.2, -0.8, 0.0, 0.5, 1.0, -0.3};
  EXPECT_LT(singularityMeasure(armJacobian(dh, wrist)), 1e-6);
  EXPECT_LT(singularityMeasure(armJacobian(dh, elbow)), 1e-6);
  const JointValues good{0.3, -1.2, 1.4, -1.7, 1.1, 0.4};
  const double w = singularityMeasure(armJacobian(dh, good));
  EXPECT_GT(w, 0.01);
  // Approaching the wrist singularity the measure decreases monotonically.
  double prev = 1e300;
  for (double q5 = 1.0; q5 >= 0; q5 -= 0.1) {
    JointValues q = good;
    q[4] = q5;
    const double m = singularityMeasure(armJacobian(dh, q));
    EXPECT_LE(m, prev + 1e-12);
    prev = m;
  }
  // Random poses are almost never singular.
  std::mt19937 rng(14);
  int positive = 0;
  for (int i = 0; i < 1000; ++i) positive += singularityMeasure(armJacobian(dh, randomJoints(rng))) > 1e-9;
  EXPECT_GT(positive, 990);
  // The definition: sqrt(prod s) * sqrt(s6 / s1) on a diagonal matrix.
  Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Zero();
  const double s[6] = {4, 3, 2, 1, 0.5, 0.25};
  double prod = 1;
  for (int i = 0; i < 6; ++i) d(i, i) = s[i], prod *= s[i];
  EXPECT_NEAR(singularityMeasure(d), std::sqrt(prod) * std::sqrt(0.25 / 4), 1e-12);
  d(0, 0) = std::nan("");
  EXPECT_EQ(singularityMeasure(d), 0.0);
}

// Speed is benchmarked, not tested: print ns per urInverse() and per robot6 inverseMap() sample.
TEST(RobotArm, InverseTiming) {
  const DhTable dh = ur5DhTable();
  std::mt19937 rng(15);
  std::vector<Eigen::Matrix4d> poses;
  for (int i = 0; i < 1000; ++i) poses.push_back(armForward(dh, randomJoints(rng)));
  JointValues sol[8];
  int br[8];
  long total = 0;
  const int reps = 500;
  const std::clock_t t0 = std::clock();  // CPU time: the machine is shared
  for (int r = 0; r < reps; ++r) {
    for (const Eigen::Matrix4d& f : poses) total += urInverse(dh, f, sol, br);
  }
  const std::clock_t t1 = std::clock();
  const double ns =
      (double(t1 - t0) / CLOCKS_PER_SEC * 1e9) / (reps * poses.size());
  std::printf("urInverse: %.1f ns per call (%.2f solutions per call)\n", ns,
              double(total) / (reps * poses.size()));
  EXPECT_GT(total, 0);
}

}  // namespace
}  // namespace omnislice
