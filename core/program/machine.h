// SPDX-License-Identifier: MIT
// Machine profiles: the four machine kinds of ../shared/PROGRAM-FORMAT.md (cartesian3, rotary4,
// table5, robot6), their limits, dynamics and nozzle geometry. Plain data; the kinematics live in
// core/kinematics, the JSON schema is documented in docs/MACHINES.md.
#pragma once
#include <Eigen/Core>
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"

namespace omnislice {

// Nozzle geometry used for collision checks. The cone has its apex at the tip and opens along the
// nozzle axis u; the carriage is a box (size x, y along the machine X, Y; z along u) that sits on
// top of the cone, centred on the axis, from coneLength to coneLength + carriageSize.z.
struct NozzleGeometry {
  double diameter = 0.4;                  // mm
  double coneHalfAngleDegrees = 40;       // degrees
  double coneLength = 25;                 // mm
  Eigen::Vector3d carriageSize{60, 60, 40};  // mm
};

// Kinematic limits of one axis or joint; 0 = not limited. Units: mm/s, mm/s^2, mm/s^3 for linear
// axes; deg/s, deg/s^2, deg/s^3 for G-code rotary axes (A, B, C); rad/s, rad/s^2, rad/s^3 for
// robot joints.
struct AxisDynamics {
  double velocity = 0;
  double acceleration = 0;
  double jerk = 0;
};

// One row of a standard (distal) Denavit-Hartenberg table: mm and radians.
struct DhRow {
  double thetaOffset = 0;
  double d = 0;
  double a = 0;
  double alpha = 0;
};

// Values of a machine's axes in the order of machineAxisNames(kind): X Y Z (mm) then A or B C
// (degrees) for G-code kinds; q1..q6 (radians) for robot6. Unused trailing entries are 0.
using MachineValues = std::array<double, 6>;

struct MachineProfile {
  std::string kind = "cartesian3";  // cartesian3 | rotary4 | table5 | robot6
  std::string name = "cartesian3";  // profile name (built-in name or the user's), reports only
  Eigen::Vector3d pivot{0, 0, 0};   // rotary4 / table5: the rotation axes pass through it (machine frame)
  std::map<std::string, std::pair<double, double>> axisLimits;  // axis letter -> [min, max] (mm, deg)
  std::map<std::string, AxisDynamics> axisDynamics;             // axis letter -> limits
  double stepAngleDegrees = 0;  // rotary4: A must be a multiple of it (stepper platform); 0 = any
  double safeZ = 0;             // G-code kinds: machine Z the tip rises to before a 3+2 rotation;
                                // 0 = derived from the part (its highest machine Z + 10 mm)

  // robot6 only (PROGRAM-FORMAT.md): standard DH table, joint limits (rad) and dynamics, the
  // flange-to-platform transform and the fixed nozzle (tip and axis) in the robot base frame.
  std::array<DhRow, 6> dh{};
  std::array<std::pair<double, double>, 6> jointLimits{};
  std::array<AxisDynamics, 6> jointDynamics{};
  Eigen::Matrix4d flangeToPlatform = Eigen::Matrix4d::Identity();
  Eigen::Vector3d nozzleTip{0, 0, 0};   // mm, robot base frame
  Eigen::Vector3d nozzleAxis{0, 0, 1};  // unit, robot base frame, tip -> hot end

  NozzleGeometry nozzle;
};

// Built-in cartesian3 profile whose X/Y limits centre a bed of bedSize on the part origin
// (the part frame is centred on the bed) and Z spans [0, bedSize.z].
MachineProfile cartesian3Profile(const Eigen::Vector3d& bedSize, double nozzleDiameter);

struct MachineProfileResult : Outcome {
  MachineProfile machine;
};

// Built-in profiles by name: "cartesian3", "rotary4", "table5", "robot6-ur5" (alias "robot6").
// bedSize sizes the linear axes of the G-code kinds; nozzleDiameter sets nozzle.diameter.
// InvalidOption for an unknown name (the message lists the names).
MachineProfileResult builtinMachine(const std::string& name, const Eigen::Vector3d& bedSize,
                                    double nozzleDiameter);

// Names accepted by builtinMachine(), in display order.
std::vector<std::string> builtinMachineNames();

// The one-line machine JSON of the program header (PROGRAM-FORMAT.md); for robot6 it includes
// dh, joint_limits, flange_to_platform, nozzle_tip and nozzle_axis. Dynamics, step angle and
// safe Z are written too (extra keys are allowed by the format).
std::string machineJson(const MachineProfile& machine);

}  // namespace omnislice
