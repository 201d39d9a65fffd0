// SPDX-License-Identifier: MIT
// Internal: the right-handed rotations about the machine X, Y, Z axes by an axis value in degrees
// (PROGRAM-FORMAT.md's Rx, Ry, Rz), shared by the forward and inverse maps.
#pragma once
#include <Eigen/Core>
#include <cmath>

#include "common/math_constants.h"

namespace omnislice::detail {

inline Eigen::Matrix3d rotX(double deg) {
  const double a = deg * (kPi / 180.0);
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}

inline Eigen::Matrix3d rotY(double deg) {
  const double a = deg * (kPi / 180.0);
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, 0, s, 0, 1, 0, -s, 0, c;
  return r;
}

inline Eigen::Matrix3d rotZ(double deg) {
  const double a = deg * (kPi / 180.0);
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

}  // namespace omnislice::detail
