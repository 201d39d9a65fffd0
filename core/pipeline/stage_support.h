// SPDX-License-Identifier: MIT
// Small helpers the pipeline's method steps share (internal to core/pipeline): stage clocks,
// failed results, finite numbers for JSON reports.
#pragma once
#include <chrono>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/status.h"
#include "program/machine.h"

namespace omnislice::stage {

using Clock = std::chrono::steady_clock;

// Milliseconds since t0.
inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// A result of type Result carrying only a status and a message.
template <typename Result>
Result failed(Status status, std::string message) {
  Result r;
  r.status = status;
  r.message = std::move(message);
  return r;
}

template <typename Result>
Result failed(const Outcome& o) {
  return failed<Result>(o.status, o.message);
}

// Finite number for JSON (nlohmann writes NaN as null; keep reports numeric).
inline double finite(double v) { return std::isfinite(v) ? v : 0.0; }

// How far the machine can lean the nozzle axis from +Z, degrees: table5 its B range (less half a
// degree of margin, at least 1), a robot 90.
inline double machineTiltLimitDegrees(const MachineProfile& machine) {
  if (machine.kind == "table5") {
    auto it = machine.axisLimits.find("B");
    if (it != machine.axisLimits.end()) {
      return std::max(1.0, std::min(std::abs(it->second.first), std::abs(it->second.second)) - 0.5);
    }
  }
  return 90;
}

}  // namespace omnislice::stage
