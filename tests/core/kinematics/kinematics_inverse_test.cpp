// SPDX-License-Identifier: MIT
// inverseMap(): FK(IK(x)) = x for every kind and every branch over thousands of random reachable
// poses, recovery of the original values among the candidates, infeasible orientations, table5
// continuity at B = 0 and across the C wrap, and the robot6 workspace of the built-in UR5.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <random>

#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "kinematics/robot_arm.h"
#include "machine/machine.h"
#include "workspace_reach.h"

namespace omnislice {
namespace {

const Eigen::Vector3d kBed{220, 220, 250};

MachineProfile builtin(const std::string& name) {
  const MachineProfileResult r = builtinMachine(name, kBed, 0.4);
  EXPECT_TRUE(r.ok()) << r.message;
  return r.machine;
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Difference modulo `period`, in [0, period / 2].
double wrappedDiff(double a, double b, double period) {
  return std::abs(std::remainder(a - b, period));
}

// Every candidate maps forward to (tip, axis) and lies within the limits.
void expectCandidatesMapBack(const MachineProfile& m, const IkResult& ik, const Eigen::Vector3d& tip,
                             const Eigen::Vector3d& axis) {
  for (const IkCandidate& c : ik.candidates) {
    Eigen::Vector3d t, u;
    ASSERT_TRUE(forwardMap(m, c.values, t, u));
    EXPECT_LT((t - tip).norm(), 1e-6) << machineKindName(m.kind) << " branch " << c.branch;
    EXPECT_LT(angleBetween(u, axis), 1e-6) << machineKindName(m.kind) << " branch " << c.branch;
    EXPECT_TRUE(withinLimits(m, c.values, 1e-6)) << machineKindName(m.kind);
  }
}

MachineValues randomValues(const MachineProfile& m, std::mt19937& rng) {
  const auto limits = machineLimits(m);
  MachineValues v{};
  for (size_t i = 0; i < limits.size(); ++i) {
    std::uniform_real_distribution<double> d(limits[i].first, limits[i].second);
    v[i] = d(rng);
  }
  return v;
}

TEST(KinematicsInverse, CartesianIsTheIdentityAndNeedsPlusZ) {
  const MachineProfile m = builtin("cartesian3");
  std::mt19937 rng(1);
  for (int i = 0; i < 1000; ++i) {
    const MachineValues v = randomValues(m, rng);
    Eigen::Vector3d tip, axis;
    ASSERT_TRUE(forwardMap(m, v, tip, axis));
    const IkResult ik = inverseMap(m, tip, axis);
    ASSERT_TRUE(ik.ok()) << ik.message;
    ASSERT_EQ(ik.candidates.size(), 1u);
    expectCandidatesMapBack(m, ik, tip, axis);
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(ik.candidates[0].values[j], v[j], 1e-9);
  }
  const IkResult tilted = inverseMap(m, {0, 0, 1}, Eigen::Vector3d(0, 0.1, 1).normalized());
  EXPECT_TRUE(tilted.ok());
  EXPECT_FALSE(tilted.orientationFeasible);
  EXPECT_TRUE(tilted.candidates.empty());
  const IkResult outside = inverseMap(m, {500, 0, 1}, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(outside.candidates.empty());
  EXPECT_EQ(outside.outOfLimits, 1);
}

// platformTransform() is the forward map's platform: for random values of every kind it is rigid
// and takes forwardMap()'s part-frame tip onto the nozzle tip (X Y Z, robot6 the fixed nozzle tip)
// and its axis onto the machine's nozzle axis; non-finite values and unknown kinds give false.
TEST(KinematicsInverse, PlatformTransformIsTheForwardMapsPlatform) {
  std::mt19937 rng(7);
  for (const char* name : {"cartesian3", "rotary4", "table5", "head4", "head5", "robot6"}) {
    const MachineProfile m = builtin(name);
    const bool robot = m.kind == MachineKind::Robot6;
    const bool head = m.kind == MachineKind::Head5 || m.kind == MachineKind::Head4;  // the bed stays
    double worstTip = 0, worstAxis = 0, worstRigid = 0;
    for (int i = 0; i < 1000; ++i) {
      const MachineValues v = randomValues(m, rng);
      Eigen::Vector3d tip, axis;
      Eigen::Matrix4d t;
      ASSERT_TRUE(forwardMap(m, v, tip, axis));
      ASSERT_TRUE(platformTransform(m, v, t));
      const Eigen::Matrix3d r = t.topLeftCorner<3, 3>();
      worstRigid = std::max(worstRigid, (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() +
                                            std::abs(r.determinant() - 1) + t.row(3).cwiseAbs().sum() - 1);
      // head5: the nozzle tip is the carriage point plus the turned tip offset, the axis the head's.
      // head5 turns by Rz(C = v[4]) Ry(B = v[3]); head4 by Rz(C = v[3]) Ry(its fixed tilt).
      const bool fixedTilt = m.kind == MachineKind::Head4;
      const Eigen::Matrix3d headTurn =
          Eigen::AngleAxisd((fixedTilt ? v[3] : v[4]) * kPi / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
          Eigen::AngleAxisd((fixedTilt ? m.tiltDegrees : v[3]) * kPi / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
      const Eigen::Vector3d nozzle = robot  ? m.nozzleTip
                                     : head ? Eigen::Vector3d(Eigen::Vector3d(v[0], v[1], v[2]) + headTurn * m.tipOffset)
                                            : Eigen::Vector3d(v[0], v[1], v[2]);
      const Eigen::Vector3d nozzleAxis = robot ? m.nozzleAxis : head ? Eigen::Vector3d(headTurn.col(2)) : Eigen::Vector3d::UnitZ();
      worstTip = std::max(worstTip, (r * tip + t.topRightCorner<3, 1>() - nozzle).norm());
      worstAxis = std::max(worstAxis, (r * axis - nozzleAxis).norm());
    }
    EXPECT_LT(worstRigid, 1e-9) << name;
    EXPECT_LT(worstTip, 1e-9) << name;
    EXPECT_LT(worstAxis, 1e-12) << name;
    MachineValues bad{};
    bad[m.kind == MachineKind::Cartesian3 ? 2 : 3] = std::nan("");
    Eigen::Matrix4d t;
    EXPECT_FALSE(platformTransform(m, bad, t)) << name;
  }
  MachineProfile unknown = builtin("table5");
  unknown.kind = static_cast<MachineKind>(99);
  Eigen::Matrix4d t;
  EXPECT_FALSE(platformTransform(unknown, MachineValues{}, t));
}

TEST(KinematicsInverse, BadInputsGiveInvalidOption) {
  const MachineProfile m = builtin("table5");
  const double nan = std::nan("");
  EXPECT_EQ(inverseMap(m, {nan, 0, 0}, Eigen::Vector3d::UnitZ()).status, Status::InvalidOption);
  EXPECT_EQ(inverseMap(m, {0, 0, 0}, {0, 0, 2}).status, Status::InvalidOption);
  EXPECT_EQ(inverseMap(m, {0, 0, 0}, {0, 0, 0}).status, Status::InvalidOption);
  EXPECT_EQ(inverseMap(m, {0, 0, 0}, {0, nan, 1}).status, Status::InvalidOption);
  // A robot6 profile whose DH table is not of the UR family has no analytic inverse here.
  MachineProfile arm = builtin("robot6");
  arm.dh[3].a = 10;
  EXPECT_EQ(inverseMap(arm, {0, 0, 0}, Eigen::Vector3d::UnitZ()).status, Status::InvalidOption);
}

TEST(KinematicsInverse, Rotary4RoundTripsAndRecoversTheOriginal) {
  MachineProfile m = builtin("rotary4");
  std::mt19937 rng(2);
  for (int pass = 0; pass < 2; ++pass) {
    // Pass 1: wide limits so that several 360-degree aliases are candidates.
    if (pass == 1) m.axisLimits["A"] = {-400, 400};
    for (int i = 0; i < 3000; ++i) {
      const MachineValues v = randomValues(m, rng);
      Eigen::Vector3d tip, axis;
      ASSERT_TRUE(forwardMap(m, v, tip, axis));
      const IkResult ik = inverseMap(m, tip, axis);
      ASSERT_TRUE(ik.ok()) << ik.message;
      ASSERT_TRUE(ik.orientationFeasible);
      ASSERT_FALSE(ik.candidates.empty());
      expectCandidatesMapBack(m, ik, tip, axis);
      bool found = false;
      for (const IkCandidate& c : ik.candidates) {
        bool same = std::abs(c.values[3] - v[3]) < 1e-7;
        for (int j = 0; j < 3; ++j) same = same && std::abs(c.values[j] - v[j]) < 1e-7;
        found = found || same;
      }
      EXPECT_TRUE(found) << "A " << v[3];
      if (pass == 1) {
        // Every alias inside [-400, 400]: 2 or 3 of them.
        int expected = 0;
        for (int k = -2; k <= 2; ++k) expected += std::abs(v[3] + 360 * k) <= 400;
        EXPECT_EQ(static_cast<int>(ik.candidates.size()), expected);
      }
    }
  }
}

TEST(KinematicsInverse, Rotary4ReportsInfeasibleOrientations) {
  MachineProfile m = builtin("rotary4");
  // Any x component cannot be realised by a rotation about X.
  const IkResult side = inverseMap(m, {1, 2, 3}, Eigen::Vector3d(0.2, 0, 1).normalized());
  ASSERT_TRUE(side.ok());
  EXPECT_FALSE(side.orientationFeasible);
  EXPECT_TRUE(side.candidates.empty());
  // A tilt of 70 degrees is beyond the +-60 degree platform.
  const double t = 70 * kPi / 180;
  const IkResult steep = inverseMap(m, {1, 2, 3}, {0, std::sin(t), std::cos(t)});
  ASSERT_TRUE(steep.ok());
  EXPECT_FALSE(steep.orientationFeasible);
  EXPECT_TRUE(steep.candidates.empty());
  EXPECT_EQ(steep.outOfLimits, 1);
  // Step angle 7.5 degrees: 30 degrees is on a step, 31 is not.
  m.stepAngleDegrees = 7.5;
  const double on = 30 * kPi / 180, off = 31 * kPi / 180;
  const IkResult onStep = inverseMap(m, {1, 2, 3}, {0, std::sin(on), std::cos(on)});
  ASSERT_EQ(onStep.candidates.size(), 1u);
  EXPECT_DOUBLE_EQ(onStep.candidates[0].values[3], 30.0);
  const IkResult offStep = inverseMap(m, {1, 2, 3}, {0, std::sin(off), std::cos(off)});
  EXPECT_FALSE(offStep.orientationFeasible);
  EXPECT_TRUE(offStep.candidates.empty());
  // Step 7 degrees with wide limits: 28 degrees is on a step, its alias 388 is not (360 is not a
  // multiple of 7), -332 neither; a 1.8 degree step keeps every alias.
  m.axisLimits["A"] = {-400, 400};
  m.stepAngleDegrees = 7;
  const double a28 = 28 * kPi / 180;
  const IkResult seven = inverseMap(m, {1, 2, 3}, {0, std::sin(a28), std::cos(a28)});
  ASSERT_EQ(seven.candidates.size(), 1u);
  EXPECT_NEAR(seven.candidates[0].values[3], 28, 1e-12);
  m.stepAngleDegrees = 1.8;
  const double a36 = 36 * kPi / 180;
  const IkResult fine = inverseMap(m, {1, 2, 3}, {0, std::sin(a36), std::cos(a36)});
  EXPECT_EQ(fine.candidates.size(), 3u);  // 36, 396, -324
}

TEST(KinematicsInverse, Table5EveryBranchRoundTripsAndRecoversTheOriginal) {
  MachineProfile m = builtin("table5");
  std::mt19937 rng(3);
  int twoBranches = 0;
  for (int i = 0; i < 5000; ++i) {
    const MachineValues v = randomValues(m, rng);
    Eigen::Vector3d tip, axis;
    ASSERT_TRUE(forwardMap(m, v, tip, axis));
    const bool withReference = i % 2 == 0;
    IkOptions o;
    o.reference = withReference ? &v : nullptr;
    const IkResult ik = inverseMap(m, tip, axis, o);
    ASSERT_TRUE(ik.ok()) << ik.message;
    ASSERT_TRUE(ik.orientationFeasible);
    ASSERT_FALSE(ik.candidates.empty());
    EXPECT_LE(ik.candidates.size(), 2u);
    expectCandidatesMapBack(m, ik, tip, axis);
    twoBranches += ik.candidates.size() == 2;
    bool found = false;
    for (const IkCandidate& c : ik.candidates) {
      EXPECT_EQ(c.branch, c.values[3] >= 0 ? 0 : 1);
      const bool sameB = std::abs(c.values[3] - v[3]) < 1e-7;
      // With the original as reference its C comes back exactly, else modulo 360.
      const bool sameC = withReference ? std::abs(c.values[4] - v[4]) < 1e-7
                                       : wrappedDiff(c.values[4], v[4], 360) < 1e-7;
      found = found || (sameB && sameC);
    }
    EXPECT_TRUE(found) << "B " << v[3] << " C " << v[4];
  }
  EXPECT_GT(twoBranches, 1000);
}

// head5 (PROGRAM-FORMAT.md): both branches map back, the original values are among them, and the
// carriage point sits the tip offset (60 mm, turned with the head) from the tip.
TEST(KinematicsInverse, Head5EveryBranchRoundTripsAndRecoversTheOriginal) {
  const MachineProfile m = builtin("head5");
  ASSERT_NEAR(m.tipOffset.norm(), 60, 1e-12);
  std::mt19937 rng(5);
  int twoBranches = 0;
  for (int i = 0; i < 5000; ++i) {
    const MachineValues v = randomValues(m, rng);
    Eigen::Vector3d tip, axis;
    ASSERT_TRUE(forwardMap(m, v, tip, axis));
    EXPECT_NEAR((tip - Eigen::Vector3d(v[0], v[1], v[2])).norm(), 60, 1e-9);
    EXPECT_NEAR(std::acos(std::clamp(axis.z(), -1.0, 1.0)) * 180 / kPi, std::abs(v[3]), 1e-7) << "the tilt is |B|";
    const bool withReference = i % 2 == 0;
    IkOptions o;
    o.reference = withReference ? &v : nullptr;
    const IkResult ik = inverseMap(m, tip, axis, o);
    ASSERT_TRUE(ik.ok()) << ik.message;
    ASSERT_TRUE(ik.orientationFeasible);
    ASSERT_FALSE(ik.candidates.empty());
    EXPECT_LE(ik.candidates.size(), 2u);
    expectCandidatesMapBack(m, ik, tip, axis);
    twoBranches += ik.candidates.size() == 2;
    bool found = false;
    for (const IkCandidate& c : ik.candidates) {
      const bool sameB = std::abs(c.values[3] - v[3]) < 1e-7;
      const bool sameC = withReference ? std::abs(c.values[4] - v[4]) < 1e-7 : wrappedDiff(c.values[4], v[4], 360) < 1e-7;
      found = found || (sameB && sameC);
    }
    EXPECT_TRUE(found) << "B " << v[3] << " C " << v[4];
  }
  EXPECT_GT(twoBranches, 1000);
  // Beyond the B range: no orientation.
  MachineProfile narrow = m;
  narrow.axisLimits["B"] = {-30, 30};
  const Eigen::Vector3d lean = Eigen::Vector3d(std::sin(0.7), 0, std::cos(0.7));  // 40 degrees
  const IkResult far = inverseMap(narrow, {0, 0, 10}, lean);
  EXPECT_FALSE(far.orientationFeasible);
  EXPECT_TRUE(far.candidates.empty());
  // Vertical: C stays at the reference (no spin through the singularity).
  MachineValues ref{0, 0, 0, 10, 123, 0};
  IkOptions o;
  o.reference = &ref;
  const IkResult up = inverseMap(m, {5, 5, 5}, Eigen::Vector3d::UnitZ(), o);
  ASSERT_FALSE(up.candidates.empty());
  EXPECT_EQ(up.candidates[0].values[4], 123);
  EXPECT_NEAR(up.candidates[0].values[2], 65, 1e-9) << "the carriage 60 mm above the tip";
}

// head4 (a nozzle leaning a fixed 45 degrees, turned by C): axes on its cone round-trip exactly;
// for any other axis only the azimuth is the machine's: the candidate keeps the tip, turns the
// nozzle to that azimuth, and a vertical axis keeps the reference's C.
TEST(KinematicsInverse, Head4RoundTripsOnItsConeAndTakesTheAzimuthOfAnyOtherAxis) {
  const MachineProfile m = builtin("head4");
  ASSERT_EQ(m.tiltDegrees, 45);
  std::mt19937 rng(9);
  for (int i = 0; i < 5000; ++i) {
    const MachineValues v = randomValues(m, rng);
    Eigen::Vector3d tip, axis;
    ASSERT_TRUE(forwardMap(m, v, tip, axis));
    EXPECT_NEAR(std::acos(axis.z()) * 180 / kPi, 45, 1e-9);
    EXPECT_NEAR((tip - Eigen::Vector3d(v[0], v[1], v[2])).norm(), 40, 1e-9);
    const bool withReference = i % 2 == 0;
    IkOptions o;
    o.reference = withReference ? &v : nullptr;
    const IkResult ik = inverseMap(m, tip, axis, o);
    ASSERT_TRUE(ik.ok() && ik.orientationFeasible) << ik.message;
    ASSERT_EQ(ik.candidates.size(), 1u);
    expectCandidatesMapBack(m, ik, tip, axis);
    const MachineValues& c = ik.candidates[0].values;
    EXPECT_TRUE(withReference ? std::abs(c[3] - v[3]) < 1e-7 : wrappedDiff(c[3], v[3], 360) < 1e-7) << v[3] << " " << c[3];
    // An axis off the cone: the same azimuth, the head's tilt, the tip exact.
    const double lean = std::uniform_real_distribution<double>(0.05, 1.4)(rng);
    const double az = std::atan2(axis.y(), axis.x());
    const Eigen::Vector3d off(std::sin(lean) * std::cos(az), std::sin(lean) * std::sin(az), std::cos(lean));
    const IkResult k2 = inverseMap(m, tip, off, o);
    ASSERT_EQ(k2.candidates.size(), 1u);
    Eigen::Vector3d t2, u2;
    ASSERT_TRUE(forwardMap(m, k2.candidates[0].values, t2, u2));
    EXPECT_LT((t2 - tip).norm(), 1e-9);
    EXPECT_LT((u2 - axis).norm(), 1e-9) << "the head's axis at the asked azimuth";
  }
  MachineValues ref{0, 0, 0, 77, 0, 0};
  IkOptions o;
  o.reference = &ref;
  const IkResult up = inverseMap(m, {5, 5, 5}, Eigen::Vector3d::UnitZ(), o);
  ASSERT_EQ(up.candidates.size(), 1u);
  EXPECT_EQ(up.candidates[0].values[3], 77) << "vertical: C stays";
}

TEST(KinematicsInverse, Table5KeepsTheReferenceCAtBZeroAndAcrossTheWrap) {
  const MachineProfile m = builtin("table5");
  // At B = 0 the C axis is free: the reference C is kept (no spin of the table).
  MachineValues ref{0, 0, 0, 10, 123.4, 0};
  IkOptions o;
  o.reference = &ref;
  const Eigen::Vector3d tip{5, -3, 2};
  const IkResult flat = inverseMap(m, tip, Eigen::Vector3d::UnitZ(), o);
  ASSERT_EQ(flat.candidates.size(), 1u);
  EXPECT_EQ(flat.candidates[0].values[3], 0.0);
  EXPECT_EQ(flat.candidates[0].values[4], 123.4);
  expectCandidatesMapBack(m, flat, tip, Eigen::Vector3d::UnitZ());
  // Without a reference C = 0.
  const IkResult flat0 = inverseMap(m, tip, Eigen::Vector3d::UnitZ());
  ASSERT_EQ(flat0.candidates.size(), 1u);
  EXPECT_EQ(flat0.candidates[0].values[4], 0.0);

  // Sweep the axis through B = 0 and around the C wrap; following the candidate nearest the
  // previous values gives a continuous motion (no C jump across B = 0, C crossing +-180 keeps
  // going past 180 while within [-360, 360]).
  auto axisOf = [](double bDeg, double cDeg) {
    const double b = bDeg * kPi / 180, c = cDeg * kPi / 180;
    return Eigen::Vector3d(-std::sin(b) * std::cos(c), std::sin(b) * std::sin(c), std::cos(b));
  };
  MachineValues prev{0, 0, 0, 20, 170, 0};
  // Tilt passes B = 0 in a straight line (C jumps by 180 in branch 0 only).
  for (int k = 0; k <= 80; ++k) {
    const double b = 20 - 0.5 * k;  // 20 .. -20
    const Eigen::Vector3d u = axisOf(b, 170);
    IkOptions oo;
    oo.reference = &prev;
    const IkResult ik = inverseMap(m, tip, u, oo);
    ASSERT_FALSE(ik.candidates.empty());
    expectCandidatesMapBack(m, ik, tip, u);
    const IkCandidate* best = nullptr;
    double bestCost = 1e300;
    for (const IkCandidate& c : ik.candidates) {
      const double cost = std::abs(c.values[3] - prev[3]) + std::abs(c.values[4] - prev[4]);
      if (cost < bestCost) bestCost = cost, best = &c;
    }
    EXPECT_LT(bestCost, 0.5 + 1e-6) << "at B " << b;
    prev = best->values;
  }
  EXPECT_NEAR(prev[3], -20, 1e-9);
  EXPECT_NEAR(prev[4], 170, 1e-9);
  // C turns from 170 past 180 up to 350: the chosen C keeps increasing beyond 180.
  for (int k = 0; k <= 180; ++k) {
    const double c = 170 + k;
    const Eigen::Vector3d u = axisOf(30, c);
    IkOptions oo;
    oo.reference = &prev;
    const IkResult ik = inverseMap(m, tip, u, oo);
    ASSERT_FALSE(ik.candidates.empty());
    bool continuous = false;
    for (const IkCandidate& cand : ik.candidates) {
      if (std::abs(cand.values[4] - prev[4]) <= 1 + 1e-6 && cand.branch == 0) {
        continuous = true;
        prev = cand.values;
      }
    }
    EXPECT_TRUE(continuous) << "at C " << c;
  }
  EXPECT_NEAR(prev[4], 350, 1e-9);
}

// Reference implementation of the platform pose the spec describes, written in the test from the
// contract: W t = N and R u = n, rotated about the nozzle axis.
TEST(KinematicsInverse, Robot6EveryCandidateRoundTrips) {
  const MachineProfile m = builtin("robot6");
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> uq(-kPi, kPi);
  int checked = 0, candidates = 0;
  for (int i = 0; i < 2000; ++i) {
    MachineValues q;
    for (double& v : q) v = uq(rng);
    Eigen::Vector3d tip, axis;
    ASSERT_TRUE(forwardMap(m, q, tip, axis));
    IkOptions o;
    o.freeRotationSamples = 7;
    o.reference = i % 2 ? &q : nullptr;
    const IkResult ik = inverseMap(m, tip, axis, o);
    ASSERT_TRUE(ik.ok()) << ik.message;
    ASSERT_LE(ik.candidates.size(), 8u * 7u);
    expectCandidatesMapBack(m, ik, tip, axis);
    for (const IkCandidate& c : ik.candidates) {
      // freeAngle is on the sample grid and the branch bits are within 0..7.
      const double k = (c.freeAngle + kPi) / (2 * kPi / 7);
      EXPECT_NEAR(k, std::round(k), 1e-9);
      EXPECT_GE(c.branch, 0);
      EXPECT_LT(c.branch, 8);
      if (o.reference) {
        for (int j = 0; j < 6; ++j) EXPECT_LE(std::abs(c.values[j] - q[j]), kPi + 1e-9);
      }
    }
    candidates += static_cast<int>(ik.candidates.size());
    ++checked;
  }
  EXPECT_GT(candidates, checked * 8);  // most random poses have many reachable samples
}

// Candidates of one free-angle sample share one flange pose and are all of its urInverse()
// branches; with a fine free-angle sampling the original joint values are among the candidates
// up to the sampling step (every branch of every random pose is recovered).
TEST(KinematicsInverse, Robot6RecoversTheOriginalUpToTheSamplingStep) {
  const MachineProfile m = builtin("robot6");
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uq(-kPi, kPi);
  const int samples = 720;  // 0.5 degree steps
  double worst = 0;
  for (int i = 0; i < 200; ++i) {
    MachineValues q0;
    for (double& v : q0) v = uq(rng);
    if (singularityMeasure(armJacobian(m.dh, q0)) < 0.02) continue;  // near-singular: skip
    Eigen::Vector3d tip, axis;
    ASSERT_TRUE(forwardMap(m, q0, tip, axis));
    IkOptions o;
    o.freeRotationSamples = samples;
    const IkResult ik = inverseMap(m, tip, axis, o);
    ASSERT_TRUE(ik.ok());
    double nearest = 1e300;
    for (const IkCandidate& c : ik.candidates) {
      double d = 0;
      for (int j = 0; j < 6; ++j) d = std::max(d, wrappedDiff(c.values[j], q0[j], 2 * kPi));
      nearest = std::min(nearest, d);
    }
    worst = std::max(worst, nearest);
    EXPECT_LT(nearest, 0.05) << "pose " << i;
    if (i % 20 == 0) {
      // The candidates of one sample are exactly the urInverse() branches of their flange pose.
      const IkCandidate& c = ik.candidates.front();
      JointValues sol[8];
      int br[8];
      const int ns = urInverse(m.dh, armForward(m.dh, c.values), sol, br);
      int same = 0;
      for (const IkCandidate& d : ik.candidates) same += d.freeAngle == c.freeAngle;
      EXPECT_EQ(same, ns);
    }
  }
  std::printf("robot6: worst distance of the original to its nearest candidate %.4f rad\n", worst);
}

// The built-in UR5 reaches a 100 x 100 x 100 mm part on its platform (x, y in [-50, 50],
// z in [0, 100]) at every grid point with the nozzle axis +Z and tilted up to 60 degrees in 8
// directions, with a candidate away from singularities.
TEST(KinematicsInverse, Robot6Ur5ReachesTheBuildVolume) {
  const WorkspaceReach r = workspaceReach(builtin("robot6-ur5"));
  std::printf("UR5 workspace: %d poses, %d unreachable, min over poses of the best w_PS %.4f "
              "(at tip %.0f %.0f %.0f axis %.2f %.2f %.2f)\n",
              r.points, r.unreachable, r.minBest, r.worstTip.x(), r.worstTip.y(), r.worstTip.z(),
              r.worstAxis.x(), r.worstAxis.y(), r.worstAxis.z());
  EXPECT_EQ(r.unreachable, 0);
  EXPECT_EQ(r.outsideLimits, 0);
  EXPECT_GT(r.minBest, 0.05);
}

// Speed is benchmarked, not tested: print the cost of one robot6 inverseMap() with 30 free-rotation
// samples (the unit of the lead's 100k-sample benchmark).
TEST(KinematicsInverse, Robot6Timing) {
  const MachineProfile m = builtin("robot6-ur5");
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> ux(-50, 50), uz(0, 100), ut(-0.8, 0.8);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> poses;
  for (int i = 0; i < 2000; ++i) {
    poses.emplace_back(Eigen::Vector3d(ux(rng), ux(rng), uz(rng)),
                       Eigen::Vector3d(ut(rng), ut(rng), 1).normalized());
  }
  size_t total = 0;
  MachineValues ref{0.5, -1.5, 1.5, -1.5, -1.5, 0};
  IkOptions o;
  o.reference = &ref;
  const std::clock_t t0 = std::clock();  // CPU time: the machine is shared
  for (const auto& p : poses) total += inverseMap(m, p.first, p.second, o).candidates.size();
  const std::clock_t t1 = std::clock();
  const double us = (double(t1 - t0) / CLOCKS_PER_SEC * 1e6) / poses.size();
  std::printf("robot6 inverseMap (30 samples): %.1f us per call, %.1f candidates per call\n", us,
              double(total) / poses.size());
  // One branch only (the reference's configuration): the cost the motion planner pays when it
  // tracks a configuration.
  o.branchMask = 1 << 4;  // branch 4: shoulder 0, wrist 0, elbow 1
  size_t one = 0;
  const std::clock_t t2 = std::clock();
  for (const auto& p : poses) {
    const IkResult ik = inverseMap(m, p.first, p.second, o);
    for (const IkCandidate& c : ik.candidates) EXPECT_EQ(c.branch, 4);
    one += ik.candidates.size();
  }
  const std::clock_t t3 = std::clock();
  std::printf("robot6 inverseMap (30 samples, 1 branch): %.1f us per call, %.1f candidates\n",
              double(t3 - t2) / CLOCKS_PER_SEC * 1e6 / poses.size(), double(one) / poses.size());
  EXPECT_GT(one, 0u);
  EXPECT_GT(total, poses.size());
}

}  // namespace
}  // namespace omnislice
