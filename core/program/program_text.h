// SPDX-License-Identifier: MIT
// Internal helpers shared by the program writers (write_gcode.cpp, write_robot.cpp): number
// formatting and the header of PROGRAM-FORMAT.md, identical in every kind but for the comment
// prefix, the extrusion mode and the feed semantics.
#pragma once
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

// robot6 writer (CSV or URScript per info.robotFormat; RAPID and KRL through
// writeControllerProgram); checks already done.
WriteProgramResult writeRobotProgram(const MachinePath& path, const ProgramInfo& info);

// robot6 writer for the arm's own controller: ABB RAPID or KUKA KRL per info.robotFormat
// (write_robot_controller.cpp); checks already done.
WriteProgramResult writeControllerProgram(const MachinePath& path, const ProgramInfo& info);

}  // namespace omnislice
