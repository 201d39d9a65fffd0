// SPDX-License-Identifier: MIT
// det::sin, cos, atan2, acos against the C library (within 2e-15) over many arguments, quadrant
// and sign cases, and exact values the search relies on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "common/det_math.h"

namespace omnislice {
namespace {

TEST(DetMath, MatchesTheCLibraryClosely) {
  uint64_t state = 12345;
  auto next = [&]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 53);
  };
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const double x = (next() - 0.5) * (i % 4 == 0 ? 2e4 : 20);
    worst = std::max({worst, std::abs(det::sin(x) - std::sin(x)), std::abs(det::cos(x) - std::cos(x))});
    const double y = next() - 0.5, z = next() - 0.5;
    worst = std::max(worst, std::abs(det::atan2(y, z) - std::atan2(y, z)));
    const double c = 2 * next() - 1;
    worst = std::max(worst, std::abs(det::acos(c) - std::acos(c)));
  }
  EXPECT_LT(worst, 2e-15);
}

TEST(DetMath, SpecialValues) {
  EXPECT_EQ(det::sin(0.0), 0.0);
  EXPECT_EQ(det::cos(0.0), 1.0);
  EXPECT_NEAR(det::sin(kPi / 2), 1.0, 1e-16);
  EXPECT_NEAR(det::cos(kPi), -1.0, 1e-16);
  EXPECT_NEAR(det::sin(45 * kPi / 180), std::sqrt(0.5), 2e-16);
  EXPECT_EQ(det::atan2(0.0, 1.0), 0.0);
  EXPECT_NEAR(det::atan2(1.0, 0.0), kPi / 2, 1e-16);
  EXPECT_NEAR(det::atan2(0.0, -1.0), kPi, 1e-16);
  EXPECT_NEAR(det::atan2(-1.0, -1.0), -3 * kPi / 4, 1e-15);
  EXPECT_NEAR(det::acos(1.5), 0.0, 0);
  EXPECT_NEAR(det::acos(-1.0), kPi, 1e-16);
  EXPECT_TRUE(std::isnan(det::atan2(std::nan(""), 1.0)));
}

}  // namespace
}  // namespace omnislice
