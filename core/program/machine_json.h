// SPDX-License-Identifier: MIT
// Parsing side of the machine JSON of PROGRAM-FORMAT.md (schema in docs/MACHINES.md), and the axis
// names each kind writes.
#pragma once
#include <string>
#include <vector>

#include "common/status.h"
#include "program/machine.h"

namespace omnislice {

struct MachineParseResult : Outcome {
  MachineProfile machine;
};

// Parse a machine JSON object (inverse of machineJson(); also the user's profile files). ParseError
// for malformed JSON, non-finite numbers, min > max, a non-positive nozzle size, a robot6 profile
// without a 6-row dh table, a non-rigid flange_to_platform or a zero nozzle_axis; any kind string
// is accepted here (replaying it is the reader's concern). Missing nozzle cone keeps the defaults
// (40 degrees, 25 mm).
MachineParseResult machineFromJson(const std::string& json);

// Axis letters a kind writes in G-code, in order ("X","Y","Z" for cartesian3; "X","Y","Z","A" for
// rotary4; "X","Y","Z","B","C" for table5); empty for kinds without G-code axes (robot6, unknown).
std::vector<std::string> machineAxisLetters(const std::string& kind);

}  // namespace omnislice
