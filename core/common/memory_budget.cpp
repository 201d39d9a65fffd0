// SPDX-License-Identifier: MIT
#include "common/memory_budget.h"

#include <cmath>
#include <cstdio>

namespace omnislice {

Outcome checkMemoryBudget(double bytes, double budgetMb, const std::string& what, const std::string& lever) {
  if (!(budgetMb > 0)) return {};
  const double mb = bytes / (1024.0 * 1024.0);
  if (mb <= budgetMb) return {};
  char figures[160];
  std::snprintf(figures, sizeof figures, " needs about %.0f MB, more than the memory budget (memory_mb = %.0f MB); ",
                std::isfinite(mb) ? std::ceil(mb) : 1e18, budgetMb);
  return {Status::OutOfMemory, what + figures + lever};
}

Outcome checkProgramReadBudget(double textBytes, double budgetMb) {
  char what[80];
  std::snprintf(what, sizeof what, "reading the program (%.0f MB of text)", std::ceil(textBytes / (1024.0 * 1024.0)));
  return checkMemoryBudget(textBytes * memory_cost::kProgramTextBytes, budgetMb, what,
                           "raise memory_mb, or verify a smaller program");
}

Outcome allocationFailed(const std::string& doing) {
  return {Status::OutOfMemory,
          "ran out of memory while " + doing +
              " (an allocation failed): make the model smaller or coarser (a larger layer height, "
              "voxel.width_mm or geodesic.tet_size_mm), or close other tabs and programs"};
}

}  // namespace omnislice
