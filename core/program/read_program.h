// SPDX-License-Identifier: MIT
// Reader of Omnislice programs of every machine kind (G-code for cartesian3 / rotary4 / table5,
// robot joint CSV and URScript for robot6) and of plain 3-axis G-code from other slicers where
// possible: header facts and the moves replayed into the part frame, as verification needs them.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <deque>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/status.h"
#include "machine/machine.h"

namespace omnislice {

// A move's machine values at its end (X Y Z [A|B C] or q1..q6): the machine kind's count of
// them, held in the move itself (a program of millions of moves allocates nothing per move).
struct MoveAxes {
  MachineValues values{};
  uint8_t count = 0;

  size_t size() const { return count; }
  double operator[](size_t i) const { return values[i]; }
  double at(size_t i) const {
    if (i >= count) throw std::out_of_range("MoveAxes::at");
    return values[i];
  }
  const double* begin() const { return values.data(); }
  const double* end() const { return values.data() + count; }
  bool operator==(const MoveAxes& o) const { return std::equal(begin(), end(), o.begin(), o.end()); }
  bool operator!=(const MoveAxes& o) const { return !(*this == o); }
};

struct ProgramMove {
  Eigen::Vector3d from{0, 0, 0};   // part-frame tip position at the start
  Eigen::Vector3d to{0, 0, 0};     // part-frame tip position at the end
  Eigen::Vector3d axis{0, 0, 1};   // part-frame nozzle axis
  double filament = 0;             // E increment (mm filament), > 0 extruding
  double feedMmPerMin = 0;
  int layer = -1;                  // last `; omnislice:layer` (or ;LAYER:) marker, -1 before any
  int part = 0;
  int line = 0;                    // 1-based source line
  uint16_t feature = 0;            // last feature marker: ParsedProgram::features[feature]
  MoveAxes axes;                   // machine values at the end, for the limits
};

struct ParsedProgram : Outcome {
  std::string method;
  std::string format = "gcode";    // "gcode" | "csv" | "urscript"
  std::string feedSemantics;       // header feed semantics ("xyz", "combined", "part_tip"), "" if none
  MachineProfile machine;
  Eigen::Matrix4d placement = Eigen::Matrix4d::Identity();
  bool absoluteExtrusion = true;
  double filamentDiameter = 1.75;
  double layerHeight = 0;          // from `; omnislice:setting layer_height = ...`
  double lineWidth = 0;
  double nozzleDiameter = 0;
  // Every G0/G1 with motion or extrusion. A deque: millions of moves grow in blocks, without a
  // vector's doubling (its peak of three times the moves while it moves them), so the memory
  // held is proportional to the program (memory_budget.h's kProgramTextBytes).
  std::deque<ProgramMove> moves;
  int layerCount = 0;              // number of distinct layer markers
  // The feature markers' names in order of first use ("wall-outer", ...); features[0] is "",
  // the moves before any marker.
  std::vector<std::string> features{""};

  const std::string& featureOf(const ProgramMove& m) const { return features[m.feature]; }
};

// Parse program text (format detected from the header: `;` G-code, `#` CSV or URScript). Every
// axis / joint changes linearly between consecutive targets (PROGRAM-FORMAT.md), so a move whose
// angular values change is split into pieces whose part-frame chords stay within 0.01 mm of the
// replayed tip path; pieces keep the source line. ParseError with the line number for malformed
// header JSON, words or CSV rows; UnsupportedFormat for machine kinds this build cannot replay.
ParsedProgram readProgram(const std::string& text);

}  // namespace omnislice
