// SPDX-License-Identifier: MIT
// The one clock for stage timings (reports' timings_ms): wall time, monotonic, in milliseconds.
#pragma once
#include <chrono>

namespace omnislice {

using Clock = std::chrono::steady_clock;

// Milliseconds since t0.
inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Milliseconds since the clock's epoch (for differences only).
inline double nowMs() { return std::chrono::duration<double, std::milli>(Clock::now().time_since_epoch()).count(); }

}  // namespace omnislice
