// SPDX-License-Identifier: MIT
#include "machine/machine.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "common/math_constants.h"

namespace omnislice {

namespace {

// Defaults of the G-code kinds' axes (docs/MACHINES.md): a desktop printer's gantry and a
// geared stepper platform.
void gcodeDynamics(MachineProfile& m) {
  m.axisDynamics["X"] = {200, 3000, 100000};
  m.axisDynamics["Y"] = {200, 3000, 100000};
  m.axisDynamics["Z"] = {20, 500, 10000};
}

// The tilting kinds put part points below the pivot height when they tilt: Z may go down to
// -bedSize.z / 2 (docs/MACHINES.md).
void tiltingLinearLimits(MachineProfile& m, const Eigen::Vector3d& bedSize) {
  m.axisLimits["Z"] = {-0.5 * bedSize.z(), bedSize.z()};
}
}  // namespace

MachineProfile cartesian3Profile(const Eigen::Vector3d& bedSize, double nozzleDiameter) {
  MachineProfile m;
  m.kind = MachineKind::Cartesian3;
  m.axisLimits["X"] = {-0.5 * bedSize.x(), 0.5 * bedSize.x()};
  m.axisLimits["Y"] = {-0.5 * bedSize.y(), 0.5 * bedSize.y()};
  m.axisLimits["Z"] = {0.0, bedSize.z()};
  m.nozzle.diameter = nozzleDiameter;
  return m;
}

DhTable ur5DhTable() {
  DhTable dh{};
  const double d[6] = {89.159, 0, 0, 109.15, 94.65, 82.3};
  const double a[6] = {0, -425.0, -392.25, 0, 0, 0};
  const double alpha[6] = {kPi / 2, 0, 0, kPi / 2, -kPi / 2, 0};
  for (int i = 0; i < 6; ++i) dh[i] = DhRow{0, d[i], a[i], alpha[i]};
  return dh;
}


// UR5 placement (docs/MACHINES.md): the nozzle points straight down (axis +Z: tip -> hot end) at a
// fixed tip 522 mm from the base axis, 300 mm above the base; the platform plate is 50 mm beyond
// the flange along flange z, facing the nozzle when the wrist points up. Chosen by a grid search
// over tip positions for the largest worst-case singularity measure over a 100 mm cube of tips
// tilted up to 60 degrees (flat around 0.09-0.105 between 400 and 700 mm from the base axis); the
// test KinematicsInverse.Robot6Ur5ReachesTheBuildVolume checks it.
namespace {
const double kUr5PlateOffset = 50;  // mm
const double kHead5TipDrop = 60;    // mm, the built-in head5's nozzle tip below its B/C axes
const double kHead4TipDrop = 40;    // mm, the built-in head4's nozzle tip from its C axis
const Eigen::Vector3d kUr5NozzleTip{-500, 150, 300};  // mm, robot base frame

// rated = false: paper 003's Table 1 joint limits (pi/6 rad/s, pi/2 rad/s^2, pi rad/s^3), so time
// figures compare with the paper's. rated = true: the arm's rated joint speed (180 deg/s for every
// UR5 CB3 joint, the datasheet's figure), 5 rad/s^2 (Universal Robots publish torque limits, not
// accelerations; 5 rad/s^2 is the conservative figure their ROS 2 driver gives MoveIt for every
// joint), and no jerk limit (URScript's movej/movel plan trapezoidal speed profiles).
MachineProfile ur5Profile(double nozzleDiameter, bool rated) {
  MachineProfile m;
  m.kind = MachineKind::Robot6;
  m.name = rated ? "robot6-ur5-rated" : "robot6-ur5";
  m.dh = ur5DhTable();
  for (int i = 0; i < 6; ++i) {
    m.jointLimits[i] = {-2 * kPi, 2 * kPi};
    m.jointDynamics[i] = rated ? AxisDynamics{kPi, 5, 0} : AxisDynamics{kPi / 6, kPi / 2, kPi};
  }
  m.flangeToPlatform = Eigen::Matrix4d::Identity();
  m.flangeToPlatform(2, 3) = kUr5PlateOffset;
  m.nozzleTip = kUr5NozzleTip;
  m.nozzleAxis = Eigen::Vector3d::UnitZ();
  m.nozzle.diameter = nozzleDiameter;
  return m;
}

// An industrial arm with a spherical wrist (robot_arm.h) holding the platform under the fixed
// nozzle as the UR5 does: the plate 50 mm beyond the flange along its z, the nozzle pointing down
// at `tip`. The DH table's theta offsets put q = 0 at the controller's zero and `signs` turn q into
// the controller's angles; limits and speeds are the data sheet's, in the controller's degrees.
// The data sheets give no accelerations: each joint reaches its speed in 0.25 s. The tips were
// chosen as the UR5's: a grid search (x 300..900, z 200..1100 mm, y 0 or 150) for the largest
// worst-case singularity measure over a 100 mm cube of tips tilted up to 60 degrees within the
// joint ranges and ik_branches (IRB 1200: 0.119 at (600, 0, 800); KR 6: 0.107 at (700, 0, 800);
// the UR5's about 0.1); the test IndustrialArm.PlacementReachesTheBuildVolume checks it.
struct IndustrialArm {
  const char* name;
  double d[6], a[6], alpha[6], thetaOffset[6];
  int signs[6];
  double minDeg[6], maxDeg[6], speedDegS[6];
  Eigen::Vector3d tip;
};

MachineProfile industrialArmProfile(const IndustrialArm& arm, double nozzleDiameter) {
  MachineProfile m;
  m.kind = MachineKind::Robot6;
  m.name = arm.name;
  for (int i = 0; i < 6; ++i) {
    m.dh[i] = DhRow{arm.thetaOffset[i], arm.d[i], arm.a[i], arm.alpha[i]};
    m.jointSigns[i] = arm.signs[i];
    const double lo = arm.minDeg[i] * kPi / 180, hi = arm.maxDeg[i] * kPi / 180;
    m.jointLimits[i] = arm.signs[i] > 0 ? std::make_pair(lo, hi) : std::make_pair(-hi, -lo);
    const double v = arm.speedDegS[i] * kPi / 180;
    m.jointDynamics[i] = AxisDynamics{v, 4 * v, 0};
  }
  // Shoulder in front of the base axis and elbow up (branches 0 and 2: the zero pose's, either
  // wrist): free, the planner switched to the over-the-back or folded-elbow poses where one joint
  // neared its limit and swung the arm through the print (spot, 40 mm, multidir: 154 print moves
  // of several radians).
  m.ikBranches = 0x05;
  m.flangeToPlatform = Eigen::Matrix4d::Identity();
  m.flangeToPlatform(2, 3) = kUr5PlateOffset;
  m.nozzleTip = arm.tip;
  m.nozzleAxis = Eigen::Vector3d::UnitZ();
  m.nozzle.diameter = nozzleDiameter;
  return m;
}

// ABB IRB 1200-5/0.9 (product specification): 399.1 mm to axis 2, upper arm 448, elbow offset 42,
// forearm 451, wrist to flange 82; zero with the lower arm vertical and the forearm horizontal.
// Every joint turns as ABB counts it about its DH z.
const IndustrialArm kIrb1200{"robot6-irb1200",
                             {399.1, 0, 0, 451, 0, 82},
                             {0, 448, 42, 0, 0, 0},
                             {-kPi / 2, 0, -kPi / 2, kPi / 2, -kPi / 2, 0},
                             {0, -kPi / 2, 0, 0, 0, kPi},
                             {1, 1, 1, 1, 1, 1},
                             {-170, -100, -200, -270, -130, -400},
                             {170, 135, 70, 270, 130, 400},
                             {288, 240, 297, 400, 405, 600},
                             {600, 0, 800}};

// KUKA KR 6 R900 sixx (KR AGILUS, data sheet): 400 mm to axis 2 with a 25 mm shoulder offset,
// lower arm 455, elbow offset 35, forearm 420, wrist to flange 80; zero with the lower arm
// horizontal (A2 = -90 deg raises it). A1, A4 and A6 turn against the DH z axes (KUKA's sense).
const IndustrialArm kKr6{"robot6-kr6",
                         {400, 0, 0, 420, 0, 80},
                         {25, 455, 35, 0, 0, 0},
                         {-kPi / 2, 0, -kPi / 2, kPi / 2, -kPi / 2, 0},
                         {0, 0, -kPi / 2, 0, 0, kPi},
                         {-1, 1, 1, -1, 1, -1},
                         {-170, -190, -120, -185, -120, -350},
                         {170, 45, 156, 185, 120, 350},
                         {360, 300, 360, 381, 388, 615},
                         {700, 0, 800}};
}  // namespace

MachineProfileResult builtinMachine(const std::string& name, const Eigen::Vector3d& bedSize,
                                    double nozzleDiameter) {
  MachineProfileResult r;
  MachineProfile& m = r.machine;
  if (name == "cartesian3") {
    m = cartesian3Profile(bedSize, nozzleDiameter);
    gcodeDynamics(m);
  } else if (name == "rotary4") {
    m = cartesian3Profile(bedSize, nozzleDiameter);
    m.kind = MachineKind::Rotary4;
    m.name = "rotary4";
    tiltingLinearLimits(m, bedSize);
    m.pivot = {0, 0, 0};
    m.axisLimits["A"] = {-60, 60};  // paper 000's stepper platform range
    gcodeDynamics(m);
    m.axisDynamics["A"] = {90, 900, 9000};
  } else if (name == "table5") {
    m = cartesian3Profile(bedSize, nozzleDiameter);
    m.kind = MachineKind::Table5;
    m.name = "table5";
    tiltingLinearLimits(m, bedSize);
    m.pivot = {0, 0, 0};
    m.axisLimits["B"] = {-90, 90};
    m.axisLimits["C"] = {-3600, 3600};
    gcodeDynamics(m);
    m.axisDynamics["B"] = {90, 900, 9000};
    m.axisDynamics["C"] = {90, 900, 9000};
  } else if (name == "head5") {
    // A 5-axis head over a fixed bed (PAX-style): the nozzle tip 60 mm below the point where the
    // B and C axes meet; the carriage reaches 60 mm beyond the bed on every side so the tilted tip
    // covers the whole bed. B and C ranges and speeds as table5's.
    m = cartesian3Profile(bedSize, nozzleDiameter);
    m.kind = MachineKind::Head5;
    m.name = "head5";
    m.tipOffset = {0, 0, -kHead5TipDrop};
    m.axisLimits["X"] = {-0.5 * bedSize.x() - kHead5TipDrop, 0.5 * bedSize.x() + kHead5TipDrop};
    m.axisLimits["Y"] = {-0.5 * bedSize.y() - kHead5TipDrop, 0.5 * bedSize.y() + kHead5TipDrop};
    m.axisLimits["Z"] = {0.0, bedSize.z() + kHead5TipDrop};
    m.axisLimits["B"] = {-90, 90};
    m.axisLimits["C"] = {-3600, 3600};
    gcodeDynamics(m);
    m.axisDynamics["B"] = {90, 900, 9000};
    m.axisDynamics["C"] = {90, 900, 9000};
  } else if (name == "head4") {
    // A rotating tilted nozzle (RotBot / RTN-style): the nozzle leans 45 degrees from vertical and
    // C turns it about the vertical through the carriage point; the tip 40 mm below that point
    // along the nozzle. C continuous (a slip ring), ten turns either way.
    m = cartesian3Profile(bedSize, nozzleDiameter);
    m.kind = MachineKind::Head4;
    m.name = "head4";
    m.tiltDegrees = 45;
    m.tipOffset = {0, 0, -kHead4TipDrop};
    m.axisLimits["X"] = {-0.5 * bedSize.x() - kHead4TipDrop, 0.5 * bedSize.x() + kHead4TipDrop};
    m.axisLimits["Y"] = {-0.5 * bedSize.y() - kHead4TipDrop, 0.5 * bedSize.y() + kHead4TipDrop};
    m.axisLimits["Z"] = {0.0, bedSize.z() + kHead4TipDrop};
    m.axisLimits["C"] = {-3600, 3600};
    gcodeDynamics(m);
    m.axisDynamics["C"] = {90, 900, 9000};
  } else if (name == "robot6-ur5" || name == "robot6" || name == "robot6-ur5-rated") {
    m = ur5Profile(nozzleDiameter, name == "robot6-ur5-rated");
  } else if (name == kIrb1200.name) {
    m = industrialArmProfile(kIrb1200, nozzleDiameter);
  } else if (name == kKr6.name) {
    m = industrialArmProfile(kKr6, nozzleDiameter);
  } else {
    r.status = Status::InvalidOption;
    r.message = "unknown machine \"" + name + "\"; built-in machines:";
    for (const std::string& n : builtinMachineNames()) r.message += " " + n;
    return r;
  }
  if (!(nozzleDiameter > 0) || !std::isfinite(nozzleDiameter) || !bedSize.allFinite() ||
      !(bedSize.minCoeff() > 0)) {
    r.status = Status::InvalidOption;
    r.message = "builtinMachine: bed size and nozzle diameter must be positive";
  }
  return r;
}

std::vector<std::string> builtinMachineNames() {
  return {"cartesian3", "rotary4", "table5", "head4", "head5", "robot6-ur5", "robot6-ur5-rated", "robot6-irb1200", "robot6-kr6"};
}

const char* machineKindName(MachineKind kind) {
  switch (kind) {
    case MachineKind::Cartesian3: return "cartesian3";
    case MachineKind::Rotary4: return "rotary4";
    case MachineKind::Table5: return "table5";
    case MachineKind::Robot6: return "robot6";
    case MachineKind::Head5: return "head5";
    case MachineKind::Head4: return "head4";
  }
  return "cartesian3";
}

bool parseMachineKind(const std::string& name, MachineKind& kind) {
  for (MachineKind k : {MachineKind::Cartesian3, MachineKind::Rotary4, MachineKind::Table5, MachineKind::Robot6,
                        MachineKind::Head5, MachineKind::Head4}) {
    if (name == machineKindName(k)) {
      kind = k;
      return true;
    }
  }
  return false;
}

int machineAxisCount(MachineKind kind) {
  switch (kind) {
    case MachineKind::Cartesian3: return 3;
    case MachineKind::Rotary4: return 4;
    case MachineKind::Table5: return 5;
    case MachineKind::Robot6: return 6;
    case MachineKind::Head5: return 5;
    case MachineKind::Head4: return 4;
  }
  return 0;
}

std::vector<std::string> machineAxisNames(MachineKind kind) {
  if (kind == MachineKind::Robot6) return {"q1", "q2", "q3", "q4", "q5", "q6"};
  return machineAxisLetters(kind);
}

std::vector<std::string> machineAxisLetters(MachineKind kind) {
  switch (kind) {
    case MachineKind::Cartesian3: return {"X", "Y", "Z"};
    case MachineKind::Rotary4: return {"X", "Y", "Z", "A"};
    case MachineKind::Table5:
    case MachineKind::Head5: return {"X", "Y", "Z", "B", "C"};
    case MachineKind::Head4: return {"X", "Y", "Z", "C"};
    case MachineKind::Robot6: return {};
  }
  return {};
}

std::vector<std::string> gcodeAxisLetters(const MachineProfile& machine) {
  std::vector<std::string> letters = machineAxisLetters(machine.kind);
  for (std::string& l : letters) {
    auto it = machine.axisLetters.find(l);
    if (it != machine.axisLetters.end()) l = it->second;
  }
  return letters;
}

Outcome checkAxisLetters(MachineKind kind, const std::map<std::string, std::string>& letters) {
  if (letters.empty()) return {};
  const std::vector<std::string> axes = machineAxisLetters(kind);
  if (axes.empty()) {
    return {Status::InvalidOption, std::string("axis letters: a ") + machineKindName(kind) +
                                       " program has joint values, no G-code axis letters"};
  }
  std::string names;
  for (const std::string& a : axes) names += (names.empty() ? "" : " ") + a;
  static const std::string kFirmwareLetters = "ABCDUVWXYZ";
  for (const auto& [axis, letter] : letters) {
    if (std::find(axes.begin(), axes.end(), axis) == axes.end()) {
      return {Status::InvalidOption, "axis letters: '" + axis.substr(0, 20) + "' is not an axis of " +
                                         machineKindName(kind) + " (" + names + ")"};
    }
    if (letter.size() != 1 || kFirmwareLetters.find(letter[0]) == std::string::npos) {
      return {Status::InvalidOption, "axis letters: axis " + axis + " cannot be written as '" + letter.substr(0, 20) +
                                         "' (one of A B C D U V W X Y Z; E and F are extrusion and feed)"};
    }
  }
  MachineProfile m;
  m.kind = kind;
  m.axisLetters = letters;
  const std::vector<std::string> written = gcodeAxisLetters(m);
  for (size_t i = 0; i < written.size(); ++i) {
    for (size_t j = i + 1; j < written.size(); ++j) {
      if (written[i] == written[j]) {
        return {Status::InvalidOption, "axis letters: axes " + axes[i] + " and " + axes[j] + " would both be written as " +
                                           written[i]};
      }
    }
  }
  return {};
}

bool isAngularAxis(MachineKind kind, int index) {
  const int n = machineAxisCount(kind);
  if (kind == MachineKind::Robot6) return index >= 0 && index < 6;  // every joint
  return index >= 3 && index < n;                                   // A; B, C
}

double machineTiltLimitDegrees(const MachineProfile& machine) {
  if (machine.kind == MachineKind::Table5 || machine.kind == MachineKind::Head5) {
    auto it = machine.axisLimits.find("B");
    if (it != machine.axisLimits.end()) {
      return std::max(1.0, std::min(std::abs(it->second.first), std::abs(it->second.second)) - 0.5);
    }
  }
  if (machine.kind == MachineKind::Head4) return std::clamp(std::abs(machine.tiltDegrees), 1.0, 90.0);
  return 90;
}

}  // namespace omnislice
