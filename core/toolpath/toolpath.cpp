// SPDX-License-Identifier: MIT
#include "toolpath/toolpath.h"

#include "toolpath/lookahead_time.h"

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

ToolpathStats toolpathStats(const Toolpath& path, double accelerationMmS2, double junctionDeviationMm) {
  ToolpathStats s;
  Eigen::Vector3d prev = path.start;
  std::vector<PlannedMove> planned;
  planned.reserve(path.moves.size());
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
    if (len > 0 && m.speed > 0) {
      planned.push_back({(m.position - prev) / len, len, m.speed});
    } else {
      planned.push_back({});  // a stop
      if (m.filament != 0 && m.speed > 0) s.estimatedTimeS += std::abs(m.filament) / m.speed;  // retract/unretract
    }
    prev = m.position;
  }
  s.estimatedTimeS += lookaheadTime(planned, {accelerationMmS2, junctionDeviationMm});
  return s;
}

}  // namespace omnislice
