// SPDX-License-Identifier: MIT
// The tool-path model every method produces and every writer consumes: ordered moves in the part
// frame (platform z = 0, part in z >= 0).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace omnislice {

enum class MoveKind : uint8_t { Travel, Print, Support, Retract, Unretract };

// Feature of a printing move; names follow PROGRAM-FORMAT.md (featureName()).
enum class Feature : uint8_t { None, WallOuter, WallInner, Skin, Infill, Support, Bridge };

const char* featureName(Feature f);  // "wall-outer", ... ; "" for None
const char* moveKindName(MoveKind k);  // "travel", "print", ...

// One straight move from the previous move's end to `position`.
struct Move {
  Eigen::Vector3d position{0, 0, 0};  // end point, part frame, mm
  Eigen::Vector3d axis{0, 0, 1};      // nozzle axis u at the end point (unit, tip -> hot end)
  double width = 0;                   // bead width, mm (0 for travel)
  double height = 0;                  // bead height (layer thickness), mm (0 for travel)
  double filament = 0;                // filament length fed during this move, mm (>0 print, <0 retract)
  double speed = 0;                   // tip speed along the part, mm/s
  MoveKind kind = MoveKind::Travel;
  Feature feature = Feature::None;
  int32_t part = 0;                   // part index (multi-directional), 0 otherwise
  int32_t layer = 0;                  // layer index within the print, 0-based
  uint32_t curve = 0;                 // iso-planar fill: NL curve index, 1-based (0 = none)
};

struct Toolpath {
  Eigen::Vector3d start{0, 0, 0};  // position before the first move (park position)
  std::vector<Move> moves;
  int32_t layerCount = 0;
};

// Summary figures over a tool-path: extruding path length, filament, estimated time as a
// firmware look-ahead runs the moves (lookahead_time.h: acceleration in mm/s^2, 0 = constant
// speed; junction deviation in mm, 0 = every move from and to rest) and retraction time.
struct ToolpathStats {
  double pathMm = 0;        // length of Print/Support moves
  double travelMm = 0;      // length of Travel moves
  double filamentMm = 0;    // sum of positive filament
  double estimatedTimeS = 0;
  int32_t retractions = 0;
};
ToolpathStats toolpathStats(const Toolpath& path, double accelerationMmS2, double junctionDeviationMm = 0.013);

}  // namespace omnislice
