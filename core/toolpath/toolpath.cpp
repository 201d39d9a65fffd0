// SPDX-License-Identifier: MIT
#include "toolpath/toolpath.h"

#include <algorithm>
#include <cmath>

namespace omnislice {

const char* featureName(Feature f) {
  switch (f) {
    case Feature::None: return "";
    case Feature::WallOuter: return "wall-outer";
    case Feature::WallInner: return "wall-inner";
    case Feature::Skin: return "skin";
    case Feature::Infill: return "infill";
    case Feature::Support: return "support";
    case Feature::Bridge: return "bridge";
  }
  return "";
}

const char* moveKindName(MoveKind k) {
  switch (k) {
    case MoveKind::Travel: return "travel";
    case MoveKind::Print: return "print";
    case MoveKind::Support: return "support";
    case MoveKind::Retract: return "retract";
    case MoveKind::Unretract: return "unretract";
  }
  return "travel";
}

namespace {
// Time for a move of length L at cruise speed v starting and ending at rest with acceleration a
// (trapezoid, or triangle when L is too short to reach v). Conservative: each move stops.
double moveTime(double length, double speed, double accel) {
  if (length <= 0 || speed <= 0) return 0;
  if (accel <= 0) return length / speed;
  const double accelDist = speed * speed / accel;  // accelerate + decelerate
  if (length >= accelDist) return length / speed + speed / accel;
  return 2.0 * std::sqrt(length / accel);
}
}  // namespace

ToolpathStats toolpathStats(const Toolpath& path, double accelerationMmS2) {
  ToolpathStats s;
  Eigen::Vector3d prev = path.start;
  for (const Move& m : path.moves) {
    const double len = (m.position - prev).norm();
    switch (m.kind) {
      case MoveKind::Print:
      case MoveKind::Support:
        s.pathMm += len;
        break;
      case MoveKind::Travel:
        s.travelMm += len;
        break;
      case MoveKind::Retract:
        ++s.retractions;
        break;
      case MoveKind::Unretract:
        break;
    }
    if (m.filament > 0) s.filamentMm += m.filament;
    if (len > 0) {
      s.estimatedTimeS += moveTime(len, m.speed, accelerationMmS2);
    } else if (m.filament != 0 && m.speed > 0) {
      s.estimatedTimeS += std::abs(m.filament) / m.speed;  // retract/unretract at filament speed
    }
    prev = m.position;
  }
  return s;
}

}  // namespace omnislice
