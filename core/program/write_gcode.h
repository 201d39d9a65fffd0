// SPDX-License-Identifier: MIT
// Program writers following ../shared/PROGRAM-FORMAT.md: G-code for cartesian3, rotary4 (A) and
// table5 (B C) in the Marlin, RepRapFirmware and Klipper dialects; robot joint CSV, URScript, ABB RAPID and KUKA KRL
// for robot6. Header (version, method, date, machine JSON, placement, extrusion, feed semantics,
// settings, time and filament estimate), part / layer / feature markers, moves.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"
#include "motion/machine_path.h"
#include "machine/machine.h"
#include "toolpath/toolpath.h"

namespace omnislice {

enum class GcodeDialect { Marlin, RepRap, Klipper };
enum class RobotFormat { Csv, UrScript, Rapid, Krl };

// "marlin" | "reprap" | "klipper"; parse returns false for other text.
const char* gcodeDialectName(GcodeDialect d);
bool parseGcodeDialect(const std::string& text, GcodeDialect& out);
// "csv" | "urscript" | "rapid" | "krl"
const char* robotFormatName(RobotFormat f);
bool parseRobotFormat(const std::string& text, RobotFormat& out);

// A PNG thumbnail of the part for printer hosts (program/thumbnail.h).
struct ProgramThumbnail {
  int width = 0, height = 0;
  std::vector<uint8_t> png;
};

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
  // Part cooling fan (G-code kinds; robot programs have no standard fan output): off (M107) for
  // the first fanOffLayers layers printed, counted as (part, layer) pairs in print order, then
  // M106 S<0-255> at fanPercent, and at bridgeFanPercent while printing Feature::Bridge.
  double fanPercent = 100;                           // %, 0 = off
  int fanOffLayers = 1;
  double bridgeFanPercent = 100;                     // %
  double acceleration = 1500;                        // mm/s^2 for the cartesian3 time estimate
  double junctionDeviation = 0.013;                  // mm, the estimate's look-ahead junctions
  GcodeDialect dialect = GcodeDialect::Marlin;       // G-code kinds
  RobotFormat robotFormat = RobotFormat::Csv;        // robot6
  double extruderAnalogPerMmS = 0.1;                 // URScript: analog output (V) per mm/s of
                                                     // filament feed (set_analog_out, documented
                                                     // in the program header)
  std::vector<std::pair<std::string, std::string>> settings;  // every setting, as header lines
  // G-code kinds: PrusaSlicer-style thumbnail blocks after the header (robot programs: none).
  std::vector<ProgramThumbnail> thumbnails;
};

struct WriteProgramResult : Outcome {
  std::string text;
  double estimatedTimeS = 0;
  double filamentMm = 0;
  int layers = 0;
};

// Write the program of a planned machine path (planMachineMotion()) for path.machine.kind:
// G-code for cartesian3 / rotary4 / table5 (dialect from info), CSV, URScript, RAPID or KRL for robot6.
// The feed semantics declared in the header: "xyz" (Marlin, Klipper: F is the machine XYZ speed;
// pure rotations use the rotary distance in degrees), "combined" (RepRapFirmware: F over all axes,
// degrees counted as mm), "part_tip" (robot CSV: f is the tip speed along the part). F / f are
// computed from each move's planned duration, so every dialect reproduces the planned time.
// InvalidOption for non-finite values or a kind / format mismatch.
WriteProgramResult writeProgram(const MachinePath& path, const ProgramInfo& info);

// cartesian3 convenience: plan the tool-path on info.machine (which must be cartesian3, every
// printing axis +Z) and write it.
WriteProgramResult writeGcode(const Toolpath& toolpath, const ProgramInfo& info);

// File extension for a machine kind and robot format: "gcode", "csv", "script" (URScript), "mod" (RAPID) or "src" (KRL).
const char* programExtension(MachineKind kind, RobotFormat robotFormat);

}  // namespace omnislice
