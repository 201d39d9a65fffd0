// SPDX-License-Identifier: MIT
// The layered-graph shortest path with dominance pruning equals brute force over every path, on
// random graphs with wrapped angles, penalties and infeasible nodes; greedy is never better.
#include "common/math_constants.h"
#include "motion/pose_continuity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

namespace omnislice {
namespace {


// Brute force: every path through the layers (feasible nodes only).
double bruteForce(const std::vector<std::vector<MachineValues>>& layers, const PoseMetric& metric,
                  const PoseInfoFn& info) {
  double best = std::numeric_limits<double>::infinity();
  std::function<void(size_t, const MachineValues*, double)> go = [&](size_t l, const MachineValues* prev,
                                                                    double cost) {
    if (l == layers.size()) {
      best = std::min(best, cost);
      return;
    }
    for (const MachineValues& v : layers[l]) {
      const PoseNodeInfo ni = info(v);
      if (!ni.feasible) continue;
      go(l + 1, &v, cost + ni.penalty + (prev ? poseDistance(metric, *prev, v) : 0.0));
    }
  };
  go(0, nullptr, 0);
  return best;
}

TEST(PoseContinuity, EqualsBruteForceOnRandomGraphs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ang(-kPi, kPi), unit(0, 1);
  PoseMetric metric;
  metric.period.fill(2 * kPi);
  metric.period[2] = 0;  // one value without wrapping
  for (int trial = 0; trial < 300; ++trial) {
    const size_t nl = 2 + rng() % 5;
    std::vector<std::vector<MachineValues>> layers(nl);
    for (auto& layer : layers) {
      const size_t nc = 1 + rng() % 7;
      for (size_t c = 0; c < nc; ++c) {
        MachineValues v;
        for (double& x : v) x = trial % 3 == 0 ? std::round(ang(rng)) : ang(rng);  // ties too
        layer.push_back(v);
      }
    }
    // Penalty and feasibility as functions of the values (deterministic), measure for ties.
    auto info = [&](const MachineValues& v) {
      PoseNodeInfo ni;
      ni.feasible = std::fmod(std::abs(v[0] * 7.3), 1.0) > 0.15;
      ni.penalty = v[1] > 2.0 ? 0.5 * (v[1] - 2.0) : 0.0;
      ni.measure = v[3];
      return ni;
    };
    // Keys (tracks) on every other trial: the result must not depend on them.
    auto cands = [&](size_t l, const MachineValues*, std::vector<MachineValues>& out,
                     std::vector<int32_t>& keys) {
      out = layers[l];
      if (trial % 2 == 0) {
        for (size_t i = 0; i < out.size(); ++i) keys.push_back(static_cast<int32_t>((i * 7 + l) % 5));
      }
      return true;
    };
    const PoseChoice r = choosePoses(nl, metric, cands, info, [](const MachineValues& v) { return v[3]; });
    const double brute = bruteForce(layers, metric, info);
    if (!std::isfinite(brute)) {
      EXPECT_EQ(r.status, Status::InvalidOption);
      continue;
    }
    ASSERT_TRUE(r.ok()) << trial;
    EXPECT_NEAR(r.cost + r.penalty, brute, 1e-9) << trial;
    EXPECT_LE(r.cost + r.penalty, r.greedyCost + r.greedyPenalty + 1e-9) << trial;
    // The reported costs are those of the returned sequence.
    double l1 = 0, pen = 0;
    for (size_t l = 0; l < nl; ++l) {
      pen += info(r.chosen[l]).penalty;
      EXPECT_TRUE(info(r.chosen[l]).feasible);
      if (l > 0) l1 += poseDistance(metric, r.chosen[l - 1], r.chosen[l]);
    }
    EXPECT_NEAR(l1, r.cost, 1e-9);
    EXPECT_NEAR(pen, r.penalty, 1e-9);
    double gl1 = 0;
    for (size_t l = 1; l < nl; ++l) gl1 += poseDistance(metric, r.greedy[l - 1], r.greedy[l]);
    EXPECT_NEAR(gl1, r.greedyCost, 1e-9);
  }
}

TEST(PoseContinuity, WrappedDistanceAndUnwrap) {
  PoseMetric m;
  m.begin = 3;
  m.end = 5;
  m.period[3] = 0;
  m.period[4] = 360;
  const MachineValues a{0, 0, 0, 10, 170, 0}, b{5, 5, 5, 20, -170, 0};
  EXPECT_NEAR(poseDistance(m, a, b), 10 + 20, 1e-12);  // X Y Z do not count; C wraps
  std::vector<MachineValues> seq{a, b, {0, 0, 0, 20, -100, 0}};
  unwrapPoses(seq, m, {{-1e9, 1e9}, {-1e9, 1e9}, {-1e9, 1e9}, {-90, 90}, {-400, 400}});
  EXPECT_NEAR(seq[1][4], 190, 1e-9);
  EXPECT_NEAR(seq[2][4], 260, 1e-9);
  // Limits force the alias back inside (an unwinding move).
  std::vector<MachineValues> lim{{0, 0, 0, 0, 350, 0}, {0, 0, 0, 0, 20, 0}};
  unwrapPoses(lim, m, {{-1e9, 1e9}, {-1e9, 1e9}, {-1e9, 1e9}, {-90, 90}, {-360, 360}});
  EXPECT_NEAR(lim[1][4], 20, 1e-9);  // 380 is outside [-360, 360]: the alias 20 is nearest
  // Winding down 11 turns (a spiral's loops) against limits of +-10 turns: one-turn unwinding
  // steps, never a jump of several turns, every value inside and an alias of the raw one.
  std::vector<MachineValues> wind;
  for (int k = 0; k <= 11 * 36; ++k) {
    const double c = -10.0 * k;  // degrees, continuous
    wind.push_back({0, 0, 0, 0, std::remainder(c, 360.0), 0});
  }
  std::vector<MachineValues> raw = wind;
  unwrapPoses(wind, m, {{-1e9, 1e9}, {-1e9, 1e9}, {-1e9, 1e9}, {-90, 90}, {-3600, 3600}});
  int unwinds = 0;
  for (size_t k = 0; k < wind.size(); ++k) {
    EXPECT_GE(wind[k][4], -3600 - 1e-9);
    EXPECT_LE(wind[k][4], 3600 + 1e-9);
    EXPECT_NEAR(std::remainder(wind[k][4] - raw[k][4], 360.0), 0, 1e-9) << k;
    if (k == 0) continue;
    const double step = wind[k][4] - wind[k - 1][4];
    if (std::abs(step) > 180) {
      ++unwinds;
      EXPECT_NEAR(step, 350, 1e-9) << k;  // -10 deg and one turn back
    } else {
      EXPECT_NEAR(step, -10, 1e-9) << k;
    }
  }
  EXPECT_EQ(unwinds, 1);
}

}  // namespace
}  // namespace omnislice
