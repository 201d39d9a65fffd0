// SPDX-License-Identifier: MIT
// Machine kinematics for every kind of ../shared/PROGRAM-FORMAT.md: the forward map (machine
// values -> part-frame tip and nozzle axis) and the inverse (tip and axis -> every candidate set of
// machine values), limits, and the units of each axis.
#pragma once
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "machine/machine.h"

namespace omnislice {

// [min, max] per value index from the profile (axisLimits by letter, jointLimits for robot6);
// (-inf, inf) where the profile declares none.
std::vector<std::pair<double, double>> machineLimits(const MachineProfile& machine);

// True when every value is inside machineLimits() (with tolerance, in the value's unit).
bool withinLimits(const MachineProfile& machine, const MachineValues& values,
                  double tolerance = 1e-9);

// Forward map of PROGRAM-FORMAT.md: part-frame tip position and nozzle axis (unit) for machine
// values. False for an unknown kind or non-finite values.
bool forwardMap(const MachineProfile& machine, const MachineValues& values, Eigen::Vector3d& tip,
                Eigen::Vector3d& axis);

struct IkOptions {
  int freeRotationSamples = 30;          // robot6: samples of the free rotation about the nozzle
                                         // axis over [-pi, pi) (paper 001 Section 5.3 uses 30)
  const MachineValues* reference = nullptr;  // resolves free axes (table5 C at B = 0) and angle
                                             // wraps (C +- 360, A +- 360) to the nearest values
  double axisTolerance = 1e-9;           // rotary4: |u.x| above this is infeasible;
                                         // cartesian3: |(u.x, u.y)| above this is infeasible
  int branchMask = 0xff;                 // robot6: urInverse() branches to keep (bit b = branch
                                         // b, see robot_arm.h); 0xff = all 8
};

struct IkCandidate {
  MachineValues values{};
  int branch = 0;           // table5: 0 (B >= 0) or 1 (B < 0); robot6: urInverse() branch bits
  double freeAngle = 0;     // robot6: rotation about the nozzle axis (rad); 0 otherwise
};

struct IkResult : Outcome {
  std::vector<IkCandidate> candidates;  // only candidates within the limits
  bool orientationFeasible = true;      // false when no value set can realise the nozzle axis
                                        // (rotary4 with u.x != 0, table5 tilt beyond B limits...)
  int outOfLimits = 0;                  // solutions dropped by the limits
};

// Every candidate set of machine values that puts the tip at `tip` with nozzle axis `axis` (part
// frame). rotary4: A = atan2(u.y, u.z) (and its 360-degree aliases inside the limits), snapped to
// the step angle when one is declared (then orientationFeasible is false if u is not on a step);
// table5 and head5: both branches (B, C) and (-B, C + 180), C chosen among its 360-degree aliases
// nearest the reference; head4: C from the axis's azimuth alone (its nozzle always leans its fixed
// tilt, so the candidate's axis is the head's at that azimuth, the tip exact); robot6: urInverse()
// on the freeRotationSamples platform poses. Status InvalidOption for a non-unit or non-finite
// input or an unknown kind.
IkResult inverseMap(const MachineProfile& machine, const Eigen::Vector3d& tip,
                    const Eigen::Vector3d& axis, const IkOptions& options = {});

// robot6: the parts of the flange pose for (tip, axis) that do not depend on the free rotation
// about the nozzle axis (precomputed once per sample, then robotFlangeForFreeAngle() per angle).
struct RobotFreeRotation {
  Eigen::Matrix3d rH = Eigen::Matrix3d::Identity();    // platform +Z onto the nozzle axis
  Eigen::Matrix3d rMin = Eigen::Matrix3d::Identity();  // part-frame axis onto platform +Z
  Eigen::Matrix3d tRt = Eigen::Matrix3d::Identity();   // rotation of flangeToPlatform^-1
  Eigen::Vector3d tInvP{0, 0, 0};                      // translation of flangeToPlatform^-1, mm
  Eigen::Vector3d tip{0, 0, 0};                        // part-frame tip, mm
  Eigen::Vector3d nozzleTip{0, 0, 0};                  // machine.nozzleTip, mm
};

// Precomputation of robotFlangeForFreeAngle() for a part-frame tip and unit axis (robot6).
RobotFreeRotation robotFreeRotation(const MachineProfile& machine, const Eigen::Vector3d& tip,
                                    const Eigen::Vector3d& axis);

// Flange pose (robot base frame, mm) that puts the tip at the nozzle with the axis along the
// nozzle axis, turned by `angle` (rad) about the nozzle axis: exactly the pose inverseMap() gives
// urInverse() for free-rotation sample k at angle robotFreeAngle(k, samples).
Eigen::Matrix4d robotFlangeForFreeAngle(const RobotFreeRotation& frame, double angle);

// Angle of free-rotation sample k of `samples` over [-pi, pi): -pi + 2 pi k / samples.
double robotFreeAngle(int k, int samples);

// robot6: platform pose W in the robot base frame for joint values q (W = FK(q) T).
Eigen::Matrix4d robotPlatformPose(const MachineProfile& machine, const MachineValues& q);

// The platform transform of PROGRAM-FORMAT.md: the rigid map of part-frame points into the machine
// frame (robot6: the robot base frame) for machine values, so that it maps forwardMap()'s tip onto
// the nozzle tip (X Y Z for the G-code kinds whose bed moves, nozzleTip for robot6). cartesian3:
// identity; rotary4: T(P) Rx(A) T(-P); table5: T(P) Ry(B) Rz(C) T(-P); head4, head5: identity (the
// bed is fixed; the tip is X Y Z + the head's turn of tip_offset); robot6: robotPlatformPose(). False for an
// unknown kind or non-finite values.
bool platformTransform(const MachineProfile& machine, const MachineValues& values,
                       Eigen::Matrix4d& transform);

}  // namespace omnislice
