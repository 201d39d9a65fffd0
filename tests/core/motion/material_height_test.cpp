// SPDX-License-Identifier: MIT
// MaterialHeight against brute force: for random clouds and axes the bound is never below the
// largest projection (q - pivot) . u and never more than 2 R sin(3.1 deg) (every axis lies within
// 3.05 deg of one of the 2048 directions) + the cell diagonal above it.
#include "motion/material_height.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace omnislice {
namespace {

TEST(MaterialHeight, BoundsTheHighestProjectionTightly) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-20, 20), unit(-1, 1);
  const Eigen::Vector3d pivot(1, -2, 0);
  MaterialHeight h(pivot);
  EXPECT_TRUE(h.empty());
  EXPECT_EQ(h.bound(Eigen::Vector3d::UnitZ()), -std::numeric_limits<double>::infinity());
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 3000; ++i) {
    // A slab and a rod: flat and thin clouds, where a loose bound would show.
    const Eigen::Vector3d q = i % 2 ? Eigen::Vector3d(coord(rng), coord(rng), 0.3 * std::abs(coord(rng)))
                                    : Eigen::Vector3d(0.1 * coord(rng), 0.1 * coord(rng), 20 + coord(rng));
    pts.push_back(q);
    h.add(q);
  }
  double radius = 0;
  for (const Eigen::Vector3d& q : pts) radius = std::max(radius, (q - pivot).norm());
  EXPECT_NEAR(h.radius(), radius, std::sqrt(3.0));
  const double slack = 2 * radius * std::sin(3.1 * M_PI / 180) + std::sqrt(3.0);
  for (int k = 0; k < 500; ++k) {
    Eigen::Vector3d u(unit(rng), unit(rng), unit(rng));
    if (u.norm() < 0.1) continue;
    u.normalize();
    double top = -1e300;
    for (const Eigen::Vector3d& q : pts) top = std::max(top, (q - pivot).dot(u));
    const double b = h.bound(u);
    EXPECT_GE(b, top - 1e-9) << u.transpose();
    EXPECT_LE(b, top + slack) << u.transpose();
  }
}

}  // namespace
}  // namespace omnislice
