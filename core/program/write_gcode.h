// SPDX-License-Identifier: MIT
// G-code writer for cartesian3 following ../shared/PROGRAM-FORMAT.md: header (version, method, date,
// machine JSON, placement, extrusion, feed semantics, settings, time and filament estimate),
// per-layer markers, per-feature markers, G0/G1 moves with absolute E, retraction.
#pragma once
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"
#include "program/machine.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct ProgramInfo {
  std::string version = OMNISLICE_VERSION;
  std::string method = "planar";
  std::string isoDate;                               // "2026-11-21T12:00:00Z"; empty = now (UTC)
  MachineProfile machine;
  Eigen::Matrix4d placement = Eigen::Matrix4d::Identity();  // input file -> part frame
  double filamentDiameter = 1.75;                    // mm
  double layerHeight = 0.2;                          // mm (header setting)
  double lineWidth = 0.45;                           // mm (header setting)
  double nozzleTemperature = 210;                    // deg C, 0 = no heating commands
  double bedTemperature = 60;                        // deg C, 0 = none
  double acceleration = 1500;                        // mm/s^2 for the time estimate
  std::vector<std::pair<std::string, std::string>> settings;  // every setting, printed as header lines
};

struct WriteProgramResult : Outcome {
  std::string text;
  double estimatedTimeS = 0;
  double filamentMm = 0;
  int layers = 0;
};

// Write a cartesian3 G-code program. InvalidOption when the machine kind is not cartesian3 or a
// move's nozzle axis is not +Z.
WriteProgramResult writeGcode(const Toolpath& toolpath, const ProgramInfo& info);

}  // namespace omnislice
