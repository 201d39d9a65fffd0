// SPDX-License-Identifier: MIT
// Hand-built machine paths for the writer, reader and verification tests (independent of the
// motion planner): machine values chosen by the test, tips and axes from forwardMap(), and
// part-frame tool-paths mapped through a rotary4 / table5 pose (closed form written here) or a
// robot6 arm (damped Newton on the DH forward kinematics, independent of the analytic IK).
#pragma once
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>

#include "kinematics/kinematics.h"
#include "kinematics/robot_arm.h"
#include "motion/machine_path.h"
#include "program/interpolate_machine_move.h"
#include "toolpath/toolpath.h"

namespace omnislice::test {

inline Eigen::Matrix3d rotDeg(int axis, double deg) {
  return Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
}

class MachinePathBuilder {
 public:
  MachinePathBuilder(const MachineProfile& machine, const MachineValues& start) {
    path.machine = machine;
    path.start = start;
    cur_ = start;
  }
  MachinePath path;
  int part = 0, layer = 0;

  // A move to v; its duration is the part-frame length over `speed` (0.4 s for a pure rotation).
  void go(const MachineValues& v, MoveKind kind, double filament, double speed,
          Feature f = Feature::None) {
    const MoveInterpolation pieces = interpolateMachineMove(path.machine, cur_, v);
    const double len = pieces.length;
    push(v, kind, filament, len > 1e-9 ? len / speed : (v != cur_ ? 0.4 : std::abs(filament) / 35),
         f);
  }
  void retract(double e = 0.8) { push(cur_, MoveKind::Retract, -e, e / 35, Feature::None); }
  void unretract(double e = 0.8) { push(cur_, MoveKind::Unretract, e, e / 35, Feature::None); }
  // Filament for a bead of width 0.45 and height 0.2 along part-frame length len.
  static double bead(double len) { return 0.45 * 0.2 * len / (M_PI * 0.25 * 1.75 * 1.75); }
  const MachineValues& current() const { return cur_; }

  void push(const MachineValues& v, MoveKind kind, double filament, double durationS, Feature f) {
    MachineMove m;
    m.values = v;
    forwardMap(path.machine, v, m.tip, m.axis);
    m.filament = filament;
    m.durationS = durationS;
    m.kind = kind;
    m.feature = f;
    m.part = part;
    m.layer = layer;
    if (kind == MoveKind::Print || kind == MoveKind::Support) {
      m.width = 0.45;
      m.height = 0.2;
    }
    m.source = uint32_t(path.moves.size());
    path.moves.push_back(m);
    path.layerCount = std::max(path.layerCount, layer + 1);
    cur_ = v;
  }

 private:
  MachineValues cur_{};
};

// rotary4 / table5 values that put part-frame point q under the nozzle for rotary angles
// (A) or (B, C): m = P + R (q - P) with R = Rx(A) or Ry(B) Rz(C) (PROGRAM-FORMAT.md).
inline MachineValues gcodeValues(const MachineProfile& machine, const Eigen::Vector3d& q,
                                 double a1 = 0, double a2 = 0) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (machine.kind == MachineKind::Rotary4) r = rotDeg(0, a1);
  if (machine.kind == MachineKind::Table5) r = rotDeg(1, a1) * rotDeg(2, a2);
  const Eigen::Vector3d m = machine.pivot + r * (q - machine.pivot);
  return {m.x(), m.y(), m.z(), a1, a2, 0};
}

// A UR5 robot6 profile holding the platform 50 mm above the flange under a fixed nozzle pointing
// down (axis +Z in the base frame), joint limits +-2 pi.
inline MachineProfile ur5TestMachine() {
  MachineProfile m;
  m.kind = MachineKind::Robot6;
  m.name = "ur5-test";
  m.dh = ur5DhTable();
  for (auto& l : m.jointLimits) l = {-2 * M_PI, 2 * M_PI};
  m.flangeToPlatform = Eigen::Matrix4d::Identity();
  m.flangeToPlatform(2, 3) = 50;
  m.nozzleTip = {-400, -150, 350};
  m.nozzleAxis = {0, 0, 1};
  return m;
}

// Joint values whose platform pose puts part-frame point q at the nozzle with part-frame nozzle
// axis rot(W)^T u = platformRotation^T u: W = [R, N - R q]. Damped Newton from `guess`; returns
// false when it does not converge to 1e-9 mm / rad.
inline bool robotValues(const MachineProfile& machine, const Eigen::Vector3d& q,
                        const Eigen::Matrix3d& platformRotation, MachineValues guess,
                        MachineValues& out) {
  Eigen::Matrix4d w = Eigen::Matrix4d::Identity();
  w.topLeftCorner<3, 3>() = platformRotation;
  w.topRightCorner<3, 1>() = machine.nozzleTip - platformRotation * q;
  const Eigen::Matrix4d target = w * machine.flangeToPlatform.inverse();
  auto error = [&](const MachineValues& v) {
    const Eigen::Matrix4d f = armForward(machine.dh, v);
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = target.topRightCorner<3, 1>() - f.topRightCorner<3, 1>();
    const Eigen::Matrix3d dr = target.topLeftCorner<3, 3>() * f.topLeftCorner<3, 3>().transpose();
    const Eigen::AngleAxisd aa(dr);
    e.tail<3>() = aa.angle() * aa.axis() * 500.0;  // rad scaled to the arm's reach (mm)
    return e;
  };
  MachineValues v = guess;
  for (int it = 0; it < 200; ++it) {
    const Eigen::Matrix<double, 6, 1> e = error(v);
    if (e.norm() < 1e-9) {
      out = v;
      return true;
    }
    Eigen::Matrix<double, 6, 6> j;
    for (int k = 0; k < 6; ++k) {
      MachineValues d = v;
      d[k] += 1e-7;
      j.col(k) = -(error(d) - e) / 1e-7;
    }
    const Eigen::Matrix<double, 6, 6> jjt = j * j.transpose();
    const double lambda = e.norm() > 1 ? 1.0 : 1e-6;
    const Eigen::Matrix<double, 6, 1> step =
        j.transpose() * (jjt + lambda * Eigen::Matrix<double, 6, 6>::Identity()).ldlt().solve(e);
    const double scale = std::min(1.0, 0.3 / std::max(1e-12, step.cwiseAbs().maxCoeff()));
    for (int k = 0; k < 6; ++k) v[k] += scale * step[k];
  }
  return false;
}

// A start guess for robotValues() near the UR5 test machine's working pose (elbow up, wrist so
// the flange faces up); found once by Newton from a few seeds.
inline bool robotStart(const MachineProfile& machine, const Eigen::Vector3d& q,
                       const Eigen::Matrix3d& rot, MachineValues& out) {
  const double seeds[][6] = {{0, -1.2, 1.5, -1.9, -1.57, 0}, {0.5, -1.0, 1.2, -1.7, -1.57, 0.3},
                             {-0.5, -1.5, 1.8, -1.9, -1.57, 0},  {3.0, -1.9, -1.5, -1.2, 1.57, 0},
                             {2.5, -1.2, 1.5, -1.9, -1.57, 0}, {-2.5, -1.2, 1.5, -1.9, -1.57, 0}};
  for (const auto& s : seeds) {
    MachineValues g{s[0], s[1], s[2], s[3], s[4], s[5]};
    if (robotValues(machine, q, rot, g, out)) return true;
  }
  return false;
}

}  // namespace omnislice::test
