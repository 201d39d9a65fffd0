// SPDX-License-Identifier: MIT
// The machine layer: the machine kinds of ../shared/PROGRAM-FORMAT.md (cartesian3, rotary4,
// table5, head4, head5, robot6), their axes, and machine profiles (limits, dynamics, nozzle geometry) with the
// built-in ones. Plain data read from below by kinematics, motion, program and verify; the JSON
// form is machine_json.h (schema in docs/MACHINES.md), the forward and inverse maps are in
// core/kinematics.
#pragma once
#include <Eigen/Core>
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"

namespace omnislice {

// The machine kinds of PROGRAM-FORMAT.md: what the values of a program line mean.
enum class MachineKind {
  Cartesian3,  // X Y Z, nozzle along +Z
  Rotary4,     // X Y Z A, the platform turns about X
  Table5,      // X Y Z B C, a tilting (B) and turning (C) table
  Robot6,      // q1..q6, a six-joint arm holding the platform under a fixed nozzle
  Head5,       // X Y Z B C, bed fixed: the head tilts the nozzle (B about Y, then C about Z)
  Head4,       // X Y Z C, bed fixed: a nozzle tilted by a fixed angle turns about Z (C)
};

// "cartesian3", "rotary4", "table5", "robot6", "head5", "head4".
const char* machineKindName(MachineKind kind);

// The kind of a name as machineKindName() writes it; false for any other text.
bool parseMachineKind(const std::string& name, MachineKind& kind);

// Number of values a kind uses: 3, 4, 5, 6.
int machineAxisCount(MachineKind kind);

// Names of the values in order: "X","Y","Z"[,"A" | ,"B","C"] or "q1".."q6".
std::vector<std::string> machineAxisNames(MachineKind kind);

// Axis letters a kind writes in G-code, in order ("X","Y","Z" for cartesian3; "X","Y","Z","A" for
// rotary4; "X","Y","Z","B","C" for table5); empty for robot6 (no G-code axes).
std::vector<std::string> machineAxisLetters(MachineKind kind);

// True for angular values (A, B, C in degrees; robot joints in radians).
bool isAngularAxis(MachineKind kind, int index);

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

using DhTable = std::array<DhRow, 6>;

// The UR5 (CB series) table of PROGRAM-FORMAT.md.
DhTable ur5DhTable();

// Values of a machine's axes in the order of machineAxisNames(kind): X Y Z (mm) then A or B C
// (degrees) for G-code kinds; q1..q6 (radians) for robot6. Unused trailing entries are 0.
using MachineValues = std::array<double, 6>;

struct MachineProfile {
  MachineKind kind = MachineKind::Cartesian3;
  std::string name = "cartesian3";  // profile name (built-in name or the user's), reports only
  Eigen::Vector3d pivot{0, 0, 0};   // rotary4 / table5: the rotation axes pass through it (machine frame)
  std::map<std::string, std::pair<double, double>> axisLimits;  // axis letter -> [min, max] (mm, deg)
  std::map<std::string, AxisDynamics> axisDynamics;             // axis letter -> limits
  double stepAngleDegrees = 0;  // rotary4: A must be a multiple of it (stepper platform); 0 = any
  // head4, head5: the nozzle tip relative to the carriage point (X Y Z, where the head's axes meet)
  // at B = C = 0, mm; the tip is (X,Y,Z) + Rz(C) Ry(B) tipOffset (PROGRAM-FORMAT.md; head4: B is
  // its fixed tilt).
  Eigen::Vector3d tipOffset{0, 0, 0};
  // head4: the nozzle's fixed tilt tau from +Z, degrees: the tip is (X,Y,Z) + Rz(C) Ry(tau)
  // tipOffset and the axis Rz(C) Ry(tau) +Z, whatever axis a method asks for (only its azimuth
  // is the machine's to choose).
  double tiltDegrees = 0;
  double safeZ = 0;             // G-code kinds: machine Z the tip rises to before a 3+2 rotation;
                                // 0 = derived from the part (its highest machine Z + 10 mm)
  // G-code kinds: the firmware's letter for an axis (axis of the table -> letter written), e.g.
  // {"B":"U","C":"V"}; axes not named keep their own letter. Limits and dynamics stay keyed by
  // the table's axis names (checkAxisLetters).
  std::map<std::string, std::string> axisLetters;

  // robot6 only (PROGRAM-FORMAT.md): standard DH table, joint limits (rad) and dynamics, the
  // flange-to-platform transform and the fixed nozzle (tip and axis) in the robot base frame.
  DhTable dh{};
  std::array<std::pair<double, double>, 6> jointLimits{};
  std::array<AxisDynamics, 6> jointDynamics{};
  Eigen::Matrix4d flangeToPlatform = Eigen::Matrix4d::Identity();
  Eigen::Vector3d nozzleTip{0, 0, 0};   // mm, robot base frame
  Eigen::Vector3d nozzleAxis{0, 0, 1};  // unit, robot base frame, tip -> hot end
  // The controller's joint angles (RAPID, KRL: degrees) = jointSigns[i] x q_i: -1 where the
  // controller turns a joint against its DH z axis (KUKA's A1, A4, A6). The theta offsets put
  // q = 0 at the controller's zero. URScript and the CSV write q itself.
  std::array<int, 6> jointSigns{1, 1, 1, 1, 1, 1};
  // The inverse-kinematics branches the planner may use (bit b = branch b of urInverse /
  // sphericalWristInverseBranches: 1 shoulder, 2 wrist, 4 elbow); 0xff = all. An industrial arm
  // is usually run in one shoulder and elbow configuration (as a robot programmer fixes ABB's
  // confdata or KUKA's Status): switching between them mid-print is a joint swing no bead
  // survives.
  int ikBranches = 0xff;

  NozzleGeometry nozzle;
};

// Built-in cartesian3 profile whose X/Y limits centre a bed of bedSize on the part origin
// (the part frame is centred on the bed) and Z spans [0, bedSize.z].
MachineProfile cartesian3Profile(const Eigen::Vector3d& bedSize, double nozzleDiameter);

struct MachineProfileResult : Outcome {
  MachineProfile machine;
};

// Built-in profiles by name: "cartesian3", "rotary4", "table5", "head4", "head5", "robot6-ur5"
// (alias "robot6"; paper 003's joint limits), "robot6-ur5-rated" (the same arm at its rated joint
// speed), "robot6-irb1200" (ABB IRB 1200-5/0.9) and "robot6-kr6" (KUKA KR 6 R900 sixx), the
// industrial arms at their data sheets' axis ranges and speeds.
// bedSize sizes the linear axes of the G-code kinds; nozzleDiameter sets nozzle.diameter.
// InvalidOption for an unknown name (the message lists the names).
MachineProfileResult builtinMachine(const std::string& name, const Eigen::Vector3d& bedSize,
                                    double nozzleDiameter);

// Names accepted by builtinMachine(), in display order.
std::vector<std::string> builtinMachineNames();

// The letters a profile's G-code writes and reads, in the order of machineAxisLetters(kind): each
// axis's letter, or the firmware's letter for it from profile.axisLetters (e.g. B and C written as
// U and V on a RepRapFirmware machine whose rotary axes have those letters). Empty for robot6.
std::vector<std::string> gcodeAxisLetters(const MachineProfile& machine);

// Checks an axis-letter map for a kind: keys are axes of the kind's G-code letters, values one of
// the firmware axis letters A B C D U V W X Y Z, and the letters written (mapped or not) all
// differ. InvalidOption naming the problem; robot6 takes no letters.
Outcome checkAxisLetters(MachineKind kind, const std::map<std::string, std::string>& letters);

// How far the machine can lean the nozzle axis from the part's +Z, degrees: a table5 its B range
// (less half a degree of margin, at least 1; beyond it is out of reach), a robot 90 (beyond, the
// arm must hold the part upside down), the others 90 (their methods do not tilt by this bound).
double machineTiltLimitDegrees(const MachineProfile& machine);

}  // namespace omnislice
