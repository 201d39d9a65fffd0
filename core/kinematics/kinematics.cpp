// SPDX-License-Identifier: MIT
// Names, limits and the forward maps of PROGRAM-FORMAT.md. The inverse maps are in
// kinematics_inverse.cpp.
#include "kinematics/kinematics.h"

#include <cmath>
#include <limits>

#include "kinematics/axis_rotations.h"
#include "kinematics/robot_arm.h"

namespace omnislice {

namespace {
using detail::rotX;
using detail::rotY;
using detail::rotZ;

}  // namespace

std::vector<std::pair<double, double>> machineLimits(const MachineProfile& machine) {
  const double inf = std::numeric_limits<double>::infinity();
  const int n = machineAxisCount(machine.kind);
  std::vector<std::pair<double, double>> out(n, {-inf, inf});
  if (machine.kind == MachineKind::Robot6) {
    for (int i = 0; i < 6; ++i) {
      const auto& l = machine.jointLimits[i];
      if (l.first < l.second) out[i] = l;
    }
    return out;
  }
  const std::vector<std::string> names = machineAxisNames(machine.kind);
  for (int i = 0; i < n; ++i) {
    auto it = machine.axisLimits.find(names[i]);
    if (it != machine.axisLimits.end()) out[i] = it->second;
  }
  return out;
}

bool withinLimits(const MachineProfile& machine, const MachineValues& values, double tolerance) {
  const auto limits = machineLimits(machine);
  for (size_t i = 0; i < limits.size(); ++i) {
    if (!(values[i] >= limits[i].first - tolerance && values[i] <= limits[i].second + tolerance)) {
      return false;
    }
  }
  return true;
}

Eigen::Matrix4d robotPlatformPose(const MachineProfile& machine, const MachineValues& q) {
  return armForward(machine.dh, q) * machine.flangeToPlatform;
}

bool platformTransform(const MachineProfile& machine, const MachineValues& v,
                       Eigen::Matrix4d& transform) {
  const int n = machineAxisCount(machine.kind);
  if (n == 0) return false;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  if (n == 6) {
    transform = robotPlatformPose(machine, v);
    return true;
  }
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (machine.kind == MachineKind::Head5 || machine.kind == MachineKind::Head4) {  // the bed is fixed
    transform.setIdentity();
    return true;
  }
  if (machine.kind == MachineKind::Rotary4) r = rotX(v[3]);
  if (machine.kind == MachineKind::Table5) r = rotY(v[3]) * rotZ(v[4]);
  transform.setIdentity();
  transform.topLeftCorner<3, 3>() = r;
  transform.topRightCorner<3, 1>() = machine.pivot - r * machine.pivot;
  return true;
}

bool forwardMap(const MachineProfile& machine, const MachineValues& v, Eigen::Vector3d& tip,
                Eigen::Vector3d& axis) {
  const int n = machineAxisCount(machine.kind);
  if (n == 0) return false;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  const Eigen::Vector3d m(v[0], v[1], v[2]);
  const Eigen::Vector3d& p = machine.pivot;
  if (machine.kind == MachineKind::Cartesian3) {
    tip = m;
    axis = Eigen::Vector3d::UnitZ();
  } else if (machine.kind == MachineKind::Rotary4) {
    // m = P + Rx(A)(q - P)  =>  q = P + Rx(A)^T (m - P); u = Rx(A)^T z.
    const Eigen::Matrix3d r = rotX(v[3]);
    tip = p + r.transpose() * (m - p);
    axis = r.transpose() * Eigen::Vector3d::UnitZ();
  } else if (machine.kind == MachineKind::Head4) {
    // As head5 with B fixed at the nozzle's tilt: q = (X,Y,Z) + Rz(C) Ry(tau) o.
    const Eigen::Matrix3d r = rotZ(v[3]) * rotY(machine.tiltDegrees);
    tip = m + r * machine.tipOffset;
    axis = r * Eigen::Vector3d::UnitZ();
  } else if (machine.kind == MachineKind::Head5) {
    // The part frame is the machine frame: q = (X,Y,Z) + Rz(C) Ry(B) o, u = Rz(C) Ry(B) z.
    const Eigen::Matrix3d r = rotZ(v[4]) * rotY(v[3]);
    tip = m + r * machine.tipOffset;
    axis = r * Eigen::Vector3d::UnitZ();
  } else if (machine.kind == MachineKind::Table5) {
    // m = P + Ry(B) Rz(C)(q - P).
    const Eigen::Matrix3d r = rotY(v[3]) * rotZ(v[4]);
    tip = p + r.transpose() * (m - p);
    axis = r.transpose() * Eigen::Vector3d::UnitZ();
  } else {  // robot6: q = W^-1 N, u = rot(W)^T u_base
    const Eigen::Matrix4d w = robotPlatformPose(machine, v);
    const Eigen::Matrix3d r = w.topLeftCorner<3, 3>();
    tip = r.transpose() * (machine.nozzleTip - w.topRightCorner<3, 1>());
    axis = (r.transpose() * machine.nozzleAxis).normalized();
  }
  return tip.allFinite() && axis.allFinite();
}

}  // namespace omnislice
