// SPDX-License-Identifier: MIT
#include "motion/material_height.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/math_constants.h"

namespace omnislice {

MaterialHeight::MaterialHeight(const Eigen::Vector3d& pivot, double cellMm, int directions)
    : pivot_(pivot), cell_(cellMm > 0 ? cellMm : 1.0) {
  const int n = std::max(directions, 16);
  dirs_.reserve(size_t(n));
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1) / double(n);
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    dirs_.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  maxDot_.assign(size_t(n), -std::numeric_limits<double>::infinity());
}

void MaterialHeight::add(const Eigen::Vector3d& q) {
  // 21 bits per coordinate: +-1 km at 1 mm cells.
  auto key = [&](double v) { return (int64_t(std::floor(v / cell_)) + (int64_t(1) << 20)) & ((int64_t(1) << 21) - 1); };
  const int64_t k = (key(q.x()) << 42) | (key(q.y()) << 21) | key(q.z());
  if (!cells_.insert(k).second) return;
  const Eigen::Vector3d x = q - pivot_;
  radius_ = std::max(radius_, x.norm());
  for (size_t i = 0; i < dirs_.size(); ++i) maxDot_[i] = std::max(maxDot_[i], x.dot(dirs_[i]));
}

double MaterialHeight::bound(const Eigen::Vector3d& u) const {
  if (cells_.empty()) return -std::numeric_limits<double>::infinity();
  double best = radius_;  // |q - P| bounds every projection
  for (size_t i = 0; i < dirs_.size(); ++i) {
    const double c = u.dot(dirs_[i]);
    if (c <= 0) continue;
    const double s = std::sqrt(std::max(0.0, 1 - c * c));
    // cos t max_q (x . d) + sin t R, with max_q (x . d) < 0 allowed (cos t > 0 keeps the sign).
    best = std::min(best, c * maxDot_[i] + s * radius_);
  }
  // A point left out shares its cell with one taken: within the cell's diagonal of it.
  return best + std::sqrt(3.0) * cell_;
}

}  // namespace omnislice
