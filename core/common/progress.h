// SPDX-License-Identifier: MIT
// Progress and cancellation: long work takes an optional callback, never a global flag.
#pragma once
#include <functional>

namespace omnislice {

// Called with a stage name ("read", "validate", "slice", "toolpath", "gcode", ...) and the fraction
// of that stage done in [0, 1]. Returns false to cancel: the callee then stops soon (within a few
// milliseconds of work) and returns Status::Cancelled. An empty function means "no progress, never
// cancel".
using ProgressFn = std::function<bool(const char* stage, double fraction)>;

// Helper: call fn if set; true means continue.
inline bool reportProgress(const ProgressFn& fn, const char* stage, double fraction) {
  return !fn || fn(stage, fraction);
}

}  // namespace omnislice
