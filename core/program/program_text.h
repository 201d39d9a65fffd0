// SPDX-License-Identifier: MIT
// Internal helpers shared by the program writers (write_gcode.cpp, write_robot.cpp): number
// formatting and the header of PROGRAM-FORMAT.md, identical in every kind but for the comment
// prefix, the extrusion mode and the feed semantics.
#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "motion/machine_path.h"
#include "program/write_gcode.h"

namespace omnislice {

// printf-style formatting of one number.
std::string formatNumber(const char* format, double v);

// v in fixed notation (never an exponent, which firmware and URScript do not read) with about
// `significant` significant digits, at most 12 decimals, trailing zeros removed ("2400", "0.0125").
std::string fixedNumber(double v, int significant);

// Append v with exactly `decimals` decimals (0..9) in fixed notation, "-0.000" written as
// "0.000", and return the value the text denotes (the integer of the text over 10^decimals, as
// strtod would read it back). Formats by integer arithmetic: several times faster than printf,
// which matters for the millions of axis words of a program (and more so in wasm).
double appendFixed(std::string& out, double v, int decimals);

// "1h 2m 3s" with leading zero units left out ("2m 3s", "3s").
std::string durationText(double seconds);

// Header lines of PROGRAM-FORMAT.md, each starting with `prefix` ("; " or "# ") and ending with a
// newline: version line, machine JSON, placement, extrusion, feed, settings, time and filament.
std::string programHeader(const ProgramInfo& info, const MachineProfile& machine,
                          const std::string& prefix, const char* extrusionMode,
                          const char* feedSemantics, double estimatedTimeS, double filamentMm);

// Checks shared by every writer: ok path of a known kind, positive header sizes, finite values,
// durations and filament, and every move's tip / axis equal to the forward map of its values.
// Returns an Outcome with InvalidOption and a message naming the first bad move.
Outcome checkMachinePath(const MachinePath& path, const ProgramInfo& info);

// Time and filament of a path: the planner's estimate when it has one (else the sum of durations)
// and the filament fed by extruding moves.
void pathTotals(const MachinePath& path, double& timeS, double& filamentMm);

// The part / layer / feature markers of PROGRAM-FORMAT.md, in every writer's order: a part's
// marker restates its layer, a layer's restates its first feature. A part's direction is the
// part-frame axis of its first extruding move (of its first move when it has none).
class ProgramMarkers {
 public:
  explicit ProgramMarkers(const MachinePath& path) {
    for (const MachineMove& m : path.moves) {
      if (extruding(m)) partDirection_.emplace(m.part, m.axis.normalized());
    }
    for (const MachineMove& m : path.moves) partDirection_.emplace(m.part, m.axis.normalized());
  }

  // The markers due before move m: line(text) for "omnislice:part ..." and "omnislice:layer ..."
  // (text without the comment prefix), feature(f) when an extruding move starts a feature.
  template <class Line, class NewFeature>
  void before(const MachineMove& m, Line&& line, NewFeature&& feature) {
    if (m.part != part_) {
      part_ = m.part;
      const Eigen::Vector3d d = partDirection_[m.part];
      line("omnislice:part " + std::to_string(m.part) + " direction [" + fixedNumber(d.x(), 10) + "," +
           fixedNumber(d.y(), 10) + "," + fixedNumber(d.z(), 10) + "]");
      layer_ = INT32_MIN;
    }
    if (m.layer != layer_) {
      layer_ = m.layer;
      layers_.insert(m.layer);
      line("omnislice:layer " + std::to_string(m.layer));
      feature_ = Feature::None;
    }
    if (extruding(m) && m.feature != Feature::None && m.feature != feature_) {
      feature_ = m.feature;
      feature(m.feature);
    }
  }

  // Distinct layers marked so far.
  int layerCount() const { return static_cast<int>(layers_.size()); }

  static bool extruding(const MachineMove& m) { return m.kind == MoveKind::Print || m.kind == MoveKind::Support; }

 private:
  std::map<int32_t, Eigen::Vector3d> partDirection_;
  std::set<int> layers_;
  int32_t part_ = INT32_MIN, layer_ = INT32_MIN;
  Feature feature_ = Feature::None;
};

// robot6 writer (CSV or URScript per info.robotFormat; RAPID and KRL through
// writeControllerProgram); checks already done.
WriteProgramResult writeRobotProgram(const MachinePath& path, const ProgramInfo& info);

// robot6 writer for the arm's own controller: ABB RAPID or KUKA KRL per info.robotFormat
// (write_robot_controller.cpp); checks already done.
WriteProgramResult writeControllerProgram(const MachinePath& path, const ProgramInfo& info);

}  // namespace omnislice
