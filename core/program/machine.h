// SPDX-License-Identifier: MIT
// Machine profile as far as the foundation needs it (cartesian3). The machines issue extends this
// with rotary4, table5 and robot6 kinematics.
#pragma once
#include <Eigen/Core>
#include <map>
#include <string>
#include <utility>

namespace omnislice {

struct NozzleGeometry {
  double diameter = 0.4;          // mm
  double coneHalfAngleDegrees = 40;
  double coneLength = 25;         // mm
};

struct MachineProfile {
  std::string kind = "cartesian3";                         // PROGRAM-FORMAT.md machine kind
  Eigen::Vector3d pivot{0, 0, 0};                          // rotary kinds only
  std::map<std::string, std::pair<double, double>> axisLimits;  // axis letter -> [min, max]
  NozzleGeometry nozzle;
};

// Built-in cartesian3 profile whose X/Y limits centre a bed of bedSize on the part origin
// (the part frame is centred on the bed) and Z spans [0, bedSize.z].
MachineProfile cartesian3Profile(const Eigen::Vector3d& bedSize, double nozzleDiameter);

// The one-line machine JSON of the program header (PROGRAM-FORMAT.md).
std::string machineJson(const MachineProfile& machine);

}  // namespace omnislice
