// SPDX-License-Identifier: MIT
#include "kinematics/robot_arm.h"

#include <cmath>

namespace omnislice {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Standard DH link transform: Rz(theta) Tz(d) Tx(a) Rx(alpha).
Eigen::Matrix4d dhLink(const DhRow& row, double q) {
  const double th = q + row.thetaOffset;
  const double ct = std::cos(th), st = std::sin(th);
  const double ca = std::cos(row.alpha), sa = std::sin(row.alpha);
  Eigen::Matrix4d t;
  t << ct, -st * ca, st * sa, row.a * ct,  //
      st, ct * ca, -ct * sa, row.a * st,   //
      0, sa, ca, row.d,                    //
      0, 0, 0, 1;
  return t;
}
}  // namespace

DhTable ur5DhTable() {
  DhTable dh{};
  const double d[6] = {89.159, 0, 0, 109.15, 94.65, 82.3};
  const double a[6] = {0, -425.0, -392.25, 0, 0, 0};
  const double alpha[6] = {kPi / 2, 0, 0, kPi / 2, -kPi / 2, 0};
  for (int i = 0; i < 6; ++i) dh[i] = DhRow{0, d[i], a[i], alpha[i]};
  return dh;
}

Eigen::Matrix4d armForward(const DhTable& dh, const JointValues& q) {
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 6; ++i) t = t * dhLink(dh[i], q[i]);
  return t;
}

std::array<Eigen::Matrix4d, 7> armFrames(const DhTable& dh, const JointValues& q) {
  std::array<Eigen::Matrix4d, 7> frames;
  frames[0] = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 6; ++i) frames[i + 1] = frames[i] * dhLink(dh[i], q[i]);
  return frames;
}

}  // namespace omnislice
