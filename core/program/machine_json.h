// SPDX-License-Identifier: MIT
// Parsing side of the machine JSON of PROGRAM-FORMAT.md, and the axis letters each kind writes.
#pragma once
#include <string>
#include <vector>

#include "common/status.h"
#include "program/machine.h"

namespace omnislice {

struct MachineParseResult : Outcome {
  MachineProfile machine;
};

// Parse the one-line machine JSON (inverse of machineJson()). ParseError for malformed JSON or
// non-numeric / non-finite limits, min > max or a non-positive nozzle size; any kind string is
// accepted here (replaying it is the reader's concern). A missing nozzle cone keeps the defaults
// (40 degrees, 25 mm).
MachineParseResult machineFromJson(const std::string& json);

// Axis letters a kind writes in G-code, in order ("X","Y","Z" for cartesian3; "X","Y","Z","A" for
// rotary4; "X","Y","Z","B","C" for table5); empty for kinds without G-code axes (robot6, unknown).
std::vector<std::string> machineAxisLetters(const std::string& kind);

}  // namespace omnislice
