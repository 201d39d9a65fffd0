// SPDX-License-Identifier: MIT
// The track DP with unlimited slack equals an independent dynamic programme over the track graph
// (stay or +-1 free-rotation step on the same branch, full edges where no track continues), on
// random grids with wrapped values, missing solutions, infeasible nodes and penalties; with
// compareGreedy the result is never worse than greedy; the reported costs are those of the
// returned sequence.
#include "common/math_constants.h"
#include "motion/track_poses.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace omnislice {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Grid {
  int S = 0;
  size_t layers = 0;
  // present[l][k * 8 + b], values[l][k * 8 + b]
  std::vector<std::vector<char>> present;
  std::vector<std::vector<MachineValues>> values;
};

Grid randomGrid(std::mt19937& rng, int S, size_t layers) {
  std::uniform_real_distribution<double> ang(-kPi, kPi), unit(0, 1);
  Grid g;
  g.S = S;
  g.layers = layers;
  g.present.assign(layers, std::vector<char>(S * 8, 0));
  g.values.assign(layers, std::vector<MachineValues>(S * 8));
  // Smooth tracks (a random walk per node) plus noise, so track edges are usually the cheap ones.
  for (int n = 0; n < S * 8; ++n) {
    MachineValues v;
    for (double& x : v) x = ang(rng);
    for (size_t l = 0; l < layers; ++l) {
      for (double& x : v) x += 0.3 * (unit(rng) - 0.5);
      g.values[l][n] = v;
      g.present[l][n] = unit(rng) > 0.15;
    }
  }
  // Occasionally a layer where only a few nodes exist (forces restarts).
  for (size_t l = 1; l < layers; ++l) {
    if (unit(rng) < 0.15) {
      for (int n = 0; n < S * 8; ++n) g.present[l][n] = unit(rng) < 0.1;
    }
  }
  return g;
}

PoseNodeInfo gridInfo(const MachineValues& v) {
  PoseNodeInfo ni;
  ni.feasible = std::fmod(std::abs(v[0] * 7.3), 1.0) > 0.1;
  ni.penalty = v[1] > 2.0 ? 0.5 * (v[1] - 2.0) : 0.0;
  ni.measure = v[3];
  return ni;
}

// Independent reference: DP over the track graph with every node alive (slack = infinity,
// restartStep = 0): a layer where no node has a feasible track predecessor is joined with full
// edges to every node of the previous layer.
double trackGraphOptimum(const Grid& g, const PoseMetric& metric) {
  const int N = g.S * 8;
  std::vector<double> prev(N, kInf), cur(N);
  for (int n = 0; n < N; ++n) {
    if (g.present[0][n] && gridInfo(g.values[0][n]).feasible) prev[n] = gridInfo(g.values[0][n]).penalty;
  }
  for (size_t l = 1; l < g.layers; ++l) {
    bool any = false;
    for (int n = 0; n < N; ++n) {
      cur[n] = kInf;
      if (!g.present[l][n]) continue;
      const PoseNodeInfo ni = gridInfo(g.values[l][n]);
      if (!ni.feasible) continue;
      const int k = n / 8, b = n % 8;
      for (int dk = -1; dk <= 1; ++dk) {
        const int u = ((k + dk + g.S) % g.S) * 8 + b;
        if (prev[u] < kInf) {
          cur[n] = std::min(cur[n], prev[u] + poseDistance(metric, g.values[l - 1][u], g.values[l][n]) + ni.penalty);
        }
      }
      any = any || cur[n] < kInf;
    }
    if (!any) {
      for (int n = 0; n < N; ++n) {
        if (!g.present[l][n] || !gridInfo(g.values[l][n]).feasible) continue;
        for (int u = 0; u < N; ++u) {
          if (prev[u] < kInf) {
            cur[n] = std::min(cur[n], prev[u] + poseDistance(metric, g.values[l - 1][u], g.values[l][n]) +
                                          gridInfo(g.values[l][n]).penalty);
          }
        }
      }
    }
    std::swap(prev, cur);
  }
  double best = kInf;
  for (double c : prev) best = std::min(best, c);
  return best;
}

TrackIkFn gridIk(const Grid& g, size_t* calls = nullptr) {
  return [&g, calls](size_t l, int k, int mask, MachineValues vals[8], int brs[8]) {
    if (calls) ++*calls;
    int n = 0;
    for (int b = 7; b >= 0; --b) {  // any order: the DP must not depend on it
      if ((mask >> b & 1) && g.present[l][k * 8 + b]) {
        vals[n] = g.values[l][k * 8 + b];
        brs[n++] = b;
      }
    }
    return n;
  };
}

// Costs of a sequence recomputed from scratch.
void sequenceCost(const std::vector<MachineValues>& seq, const PoseMetric& metric, double& l1, double& pen) {
  l1 = pen = 0;
  for (size_t l = 0; l < seq.size(); ++l) {
    const PoseNodeInfo ni = gridInfo(seq[l]);
    EXPECT_TRUE(ni.feasible);
    pen += ni.penalty;
    if (l > 0) l1 += poseDistance(metric, seq[l - 1], seq[l]);
  }
}

PoseMetric wrappedMetric() {
  PoseMetric metric;
  metric.period.fill(2 * kPi);
  metric.period[2] = 0;
  return metric;
}

TEST(TrackPoses, UnlimitedSlackEqualsTrackGraphOptimum) {
  std::mt19937 rng(3);
  const PoseMetric metric = wrappedMetric();
  int solved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int S = 1 + static_cast<int>(rng() % 6);
    const size_t layers = 1 + rng() % 12;
    const Grid g = randomGrid(rng, S, layers);
    TrackOptions o;
    o.samples = S;
    o.slack = 1e9;
    o.maxAlive = 0;
    o.restartStep = 0;
    const TrackChoice r = chooseTrackPoses(layers, metric, gridIk(g), gridInfo,
                                           [](const MachineValues& v) { return v[3]; }, o);
    const double ref = trackGraphOptimum(g, metric);
    if (!std::isfinite(ref)) {
      EXPECT_EQ(r.status, Status::InvalidOption) << trial;
      continue;
    }
    ASSERT_TRUE(r.ok()) << trial << " " << r.message;
    ++solved;
    EXPECT_NEAR(r.cost + r.penalty, ref, 1e-9) << trial;
    double l1, pen;
    sequenceCost(r.chosen, metric, l1, pen);
    EXPECT_NEAR(l1, r.cost, 1e-9) << trial;
    EXPECT_NEAR(pen, r.penalty, 1e-9) << trial;
    EXPECT_EQ(r.greedyCost, -1);
  }
  EXPECT_GT(solved, 100);
}

TEST(TrackPoses, SlackAndGreedyFallback) {
  std::mt19937 rng(5);
  const PoseMetric metric = wrappedMetric();
  int greedyUsed = 0, solved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int S = 3 + static_cast<int>(rng() % 8);
    const size_t layers = 2 + rng() % 30;
    const Grid g = randomGrid(rng, S, layers);
    TrackOptions o;
    o.samples = S;
    o.slack = trial % 2 ? 0.0 : 0.3;
    o.restartStep = trial % 3 ? 0.5 : 0.0;
    o.maxAlive = trial % 4 ? 8 : 2;
    o.uncappedLayers = trial % 5 ? 0 : 500;  // the cap from the first layer on, mostly
    o.compareGreedy = true;
    size_t calls = 0;
    const TrackChoice r = chooseTrackPoses(layers, metric, gridIk(g, &calls), gridInfo, {}, o);
    if (!r.ok()) {
      EXPECT_EQ(r.status, Status::InvalidOption);
      continue;
    }
    ++solved;
    EXPECT_LE(r.cost + r.penalty, r.greedyCost + r.greedyPenalty + 1e-9) << trial;
    EXPECT_LE(r.cost + r.penalty, r.trackCost + r.trackPenalty + 1e-9) << trial;
    EXPECT_GE(r.greedyCost, 0);
    greedyUsed += r.greedyUsed;
    double l1, pen;
    sequenceCost(r.chosen, metric, l1, pen);
    EXPECT_NEAR(l1, r.cost, 1e-9) << trial;
    EXPECT_NEAR(pen, r.penalty, 1e-9) << trial;
    EXPECT_LE(r.ikCalls, calls);
  }
  EXPECT_GT(solved, 100);
  std::printf("[ track ] greedy fallback used in %d of %d random grids\n", greedyUsed, solved);
}

// Two branches whose labels swap at layer 6 (as UR branches do through a wrist singularity):
// following the label costs a jump of ~pi in two values; restartStep sees the large step, does
// a full evaluation and continues on the other label.
TEST(TrackPoses, RestartStepFollowsSwappedBranches) {
  Grid g;
  g.S = 1;
  g.layers = 12;
  g.present.assign(g.layers, std::vector<char>(8, 0));
  g.values.assign(g.layers, std::vector<MachineValues>(8));
  for (size_t l = 0; l < g.layers; ++l) {
    MachineValues a{0.5 + 0.01 * l, 0.2, 0.1, 0.3, 0.4 + 0.01 * l, 0.3};
    MachineValues b = a;
    b[3] += 3.0;
    b[5] -= 3.0;
    g.values[l][0] = l < 6 ? a : b;
    g.values[l][1] = l < 6 ? b : a;
    g.present[l][0] = g.present[l][1] = 1;
  }
  const PoseMetric metric = wrappedMetric();
  auto info = [](const MachineValues&) { return PoseNodeInfo{}; };
  TrackOptions o;
  o.samples = 1;
  o.slack = 0;  // only the best node stays alive: no other track to switch to
  o.restartStep = 0;
  const TrackChoice follow = chooseTrackPoses(g.layers, metric, gridIk(g), info, {}, o);
  o.restartStep = 0.5;
  const TrackChoice restart = chooseTrackPoses(g.layers, metric, gridIk(g), info, {}, o);
  ASSERT_TRUE(follow.ok() && restart.ok());
  std::printf("[ track ] swapped branches: cost %.4f following the label, %.4f with restarts "
              "(%zu)\n", follow.cost, restart.cost, restart.restarts);
  EXPECT_GT(follow.cost, 5.9);
  EXPECT_NEAR(restart.cost, 11 * 0.02, 1e-9);
  EXPECT_EQ(restart.restarts, 2u);
}

TEST(TrackPoses, CancelsAndEmpty) {
  std::mt19937 rng(9);
  const Grid g = randomGrid(rng, 4, 20);
  const PoseMetric metric = wrappedMetric();
  TrackOptions o;
  o.samples = 4;
  const TrackChoice c = chooseTrackPoses(20, metric, gridIk(g), gridInfo, {}, o,
                                         [](size_t layer) { return layer < 5; });
  EXPECT_EQ(c.status, Status::Cancelled);
  const TrackChoice e = chooseTrackPoses(0, metric, gridIk(g), gridInfo, {}, o);
  EXPECT_TRUE(e.ok());
  EXPECT_TRUE(e.chosen.empty());
}

}  // namespace
}  // namespace omnislice
