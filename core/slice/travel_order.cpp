// SPDX-License-Identifier: MIT
#include "slice/travel_order.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace omnislice {

NearestIndex::NearestIndex(const std::vector<std::vector<Eigen::Vector2d>>& probes)
    : taken_(probes.size(), 0) {
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  size_t count = 0;
  for (const auto& list : probes) {
    for (const Eigen::Vector2d& p : list) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      ++count;
    }
  }
  if (count == 0) return;
  // About two probes per cell, at most 1024 cells per side.
  const Eigen::Vector2d size = (hi - lo).cwiseMax(1e-6);
  cell_ = std::max(std::sqrt(size.x() * size.y() / (0.5 * count)), 1e-6);
  cell_ = std::max({cell_, size.x() / 1024, size.y() / 1024});
  origin_ = lo;
  nx_ = std::max(1L, static_cast<long>(std::ceil(size.x() / cell_)) + 1);
  ny_ = std::max(1L, static_cast<long>(std::ceil(size.y() / cell_)) + 1);
  std::vector<size_t> cellOf;
  cellOf.reserve(count);
  std::vector<Probe> unsorted;
  unsorted.reserve(count);
  cellStart_.assign(static_cast<size_t>(nx_ * ny_) + 1, 0);
  for (size_t i = 0; i < probes.size(); ++i) {
    for (size_t j = 0; j < probes[i].size(); ++j) {
      const Eigen::Vector2d& p = probes[i][j];
      const long cx = std::min(nx_ - 1, static_cast<long>((p.x() - lo.x()) / cell_));
      const long cy = std::min(ny_ - 1, static_cast<long>((p.y() - lo.y()) / cell_));
      const size_t c = static_cast<size_t>(cy * nx_ + cx);
      cellOf.push_back(c);
      unsorted.push_back(Probe{p, i, j});
      ++cellStart_[c + 1];
    }
  }
  for (size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
  probes_.resize(count);
  std::vector<size_t> fill(cellStart_.begin(), cellStart_.end() - 1);
  for (size_t k = 0; k < count; ++k) probes_[fill[cellOf[k]]++] = unsorted[k];
}

void NearestIndex::take(size_t item) {
  if (item < taken_.size()) taken_[item] = 1;
}

NearestIndex::Hit NearestIndex::nearest(const Eigen::Vector2d& from) const {
  Hit hit;
  if (probes_.empty()) return hit;
  // Start at the cell of `from` projected onto the grid; a probe in ring r + 1 or beyond is at
  // least r cells away (projection onto the grid box does not increase distances), so the search
  // stops once the best distance found is within r cells.
  const long cx = std::clamp(static_cast<long>(std::floor((from.x() - origin_.x()) / cell_)), 0L, nx_ - 1);
  const long cy = std::clamp(static_cast<long>(std::floor((from.y() - origin_.y()) / cell_)), 0L, ny_ - 1);
  double best = std::numeric_limits<double>::infinity();
  // Rings beyond this lie wholly outside the grid.
  const long maxRing = std::max({cx, nx_ - 1 - cx, cy, ny_ - 1 - cy});
  auto scanCell = [&](long x, long y) {
    if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return;
    const size_t c = static_cast<size_t>(y * nx_ + x);
    for (size_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k) {
      const Probe& pr = probes_[k];
      if (taken_[pr.item]) continue;
      const double d = (pr.p - from).squaredNorm();
      if (d < best) {
        best = d;
        hit.item = pr.item;
        hit.probe = pr.index;
        hit.found = true;
      }
    }
  };
  for (long r = 0; r <= maxRing; ++r) {
    if (r == 0) {
      scanCell(cx, cy);
    } else {
      // Only the ring's cells inside the grid (a long thin grid has rings far wider than it).
      const long x0 = std::max(cx - r, 0L), x1 = std::min(cx + r, nx_ - 1);
      const long y0 = std::max(cy - r + 1, 0L), y1 = std::min(cy + r - 1, ny_ - 1);
      for (long x = x0; x <= x1; ++x) {
        scanCell(x, cy - r);
        scanCell(x, cy + r);
      }
      for (long y = y0; y <= y1; ++y) {
        scanCell(cx - r, y);
        scanCell(cx + r, y);
      }
    }
    const double reach = static_cast<double>(r) * cell_;
    if (hit.found && best <= reach * reach) break;
  }
  return hit;
}

}  // namespace omnislice
