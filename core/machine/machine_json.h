// SPDX-License-Identifier: MIT
// The machine JSON of PROGRAM-FORMAT.md (schema in docs/MACHINES.md): the program header's
// `omnislice:machine` line and the user's profile files.
#pragma once
#include <string>

#include "common/status.h"
#include "machine/machine.h"

namespace omnislice {

// The one-line machine JSON of the program header (PROGRAM-FORMAT.md); for robot6 it includes
// dh, joint_limits, flange_to_platform, nozzle_tip and nozzle_axis. Dynamics, step angle and
// safe Z are written too (extra keys are allowed by the format).
std::string machineJson(const MachineProfile& machine);

struct MachineParseResult : Outcome {
  MachineProfile machine;
};

// Parse a machine JSON object (inverse of machineJson(); also the user's profile files). ParseError
// for malformed JSON, non-finite numbers, min > max, a non-positive nozzle size, a robot6 profile
// without a 6-row dh table, a non-rigid flange_to_platform, a zero nozzle_axis or axis_letters
// that checkAxisLetters() refuses;
// UnsupportedFormat for a kind that is not one of the four (a newer build's machine). Missing
// nozzle cone keeps the defaults (40 degrees, 25 mm).
MachineParseResult machineFromJson(const std::string& json);

}  // namespace omnislice
