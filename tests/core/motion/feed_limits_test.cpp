// SPDX-License-Identifier: MIT
// limitFeeds: after the iteration every velocity, acceleration and jerk finite difference is
// within its limit, durations never fall below length / speed, and unlimited axes change nothing.
#include "motion/feed_limits.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace omnislice {
namespace {

FeedInput randomWalk(unsigned seed, size_t n) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 1);
  FeedInput in;
  in.axes = 6;
  MachineValues v{};
  in.values.push_back(v);
  for (size_t k = 0; k < n; ++k) {
    for (int i = 0; i < 6; ++i) v[i] += 0.01 * g(rng) + (k % 50 == 0 ? 0.2 * g(rng) : 0.0);
    in.values.push_back(v);
    in.length.push_back(0.2 + std::abs(g(rng)));
    in.speed.push_back(k % 7 == 0 ? 0 : 40);
  }
  return in;
}

TEST(FeedLimits, LimitsHoldOnRandomMotion) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    FeedInput in = randomWalk(seed, 3000);
    const double pi = 3.14159265358979323846;
    for (auto& d : in.dynamics) d = {pi / 6, pi / 2, pi};  // paper 003 Table 1
    const FeedResult r = limitFeeds(in);
    ASSERT_EQ(r.duration.size(), in.length.size());
    EXPECT_EQ(r.violations, 0u);
    const auto ratio = feedLimitRatios(in, r.duration);
    EXPECT_LE(ratio[0], 1 + 1e-9);
    EXPECT_LE(ratio[1], 1 + 1e-6);
    EXPECT_LE(ratio[2], 1 + 1e-6);
    for (size_t k = 0; k < in.length.size(); ++k) {
      EXPECT_GT(r.duration[k], 0);
      if (in.speed[k] > 0) {
        EXPECT_GE(r.duration[k], in.length[k] / in.speed[k] * (1 - 1e-12));
      }
    }
    EXPECT_GT(r.limitedMoves, 0u);
  }
}

TEST(FeedLimits, UnlimitedAxesKeepRequestedSpeed) {
  FeedInput in = randomWalk(3, 200);
  for (double& s : in.speed) s = 25;
  const FeedResult r = limitFeeds(in);
  for (size_t k = 0; k < in.length.size(); ++k) {
    EXPECT_NEAR(r.duration[k], in.length[k] / 25, 1e-12);
  }
  EXPECT_EQ(r.limitedMoves, 0u);
}

}  // namespace
}  // namespace omnislice
