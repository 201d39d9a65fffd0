// SPDX-License-Identifier: MIT
// Small helpers the pipeline's method steps share (internal to core/pipeline): stage clocks,
// failed results, finite numbers for JSON reports.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/status.h"
#include "machine/machine.h"

namespace omnislice::stage {

// Finite number for JSON (nlohmann writes NaN as null; keep reports numeric).
inline double finite(double v) { return std::isfinite(v) ? v : 0.0; }


}  // namespace omnislice::stage
