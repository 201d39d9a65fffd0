// SPDX-License-Identifier: MIT
// Pose continuity of paper 001 Eq. (4): choose one candidate set of machine values per sample so
// that the summed L1 change of the angular values is minimal, by a shortest path over the layered
// graph of candidates. Layers are produced on demand (the inverse kinematics runs inside the
// forward pass, so memory stays proportional to the kept nodes, not to all candidates).
//
// Exact pruning: the distance is a metric (L1 on the torus for wrapped values), so a node v of a
// layer is dominated when some node u of the same layer has cost(u) + d(u, v) <= cost(v): every
// continuation of v is matched by u. Only the non-dominated nodes are kept and relaxed from.
// Node feasibility (collisions), a penalty (near-singular poses) and a tie-break measure (larger
// is better) are evaluated lazily, only for nodes that survive the cheap dominance test.
// On smooth robot paths the exact rule keeps about half of the 240 candidates of a layer (a
// switch of free-rotation sample straight from the previous best node is cheaper than via any
// other node, so such nodes are never dominated); PoseChoiceOptions::maxKept bounds the work.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/status.h"
#include "machine/machine.h"

namespace omnislice {

struct PoseMetric {
  int begin = 0, end = 6;                 // value indices [begin, end) entering the L1 distance
  std::array<double, 6> period{};         // > 0: the value lives on a circle of this period and
                                          // differences are wrapped to (-period/2, period/2]
};

// |d| of one value difference under a period (> 0: on a circle, the shorter way round). Inline:
// it sits in the inner loops of both pose choosers.
inline double wrappedDistance(double d, double period) {
  d = std::abs(d);
  if (period <= 0) return d;
  if (d > period) {
    // Values stay within a few turns of each other: subtract instead of fmod (much faster).
    d -= period;
    if (d > period) d = std::fmod(d, period);
  }
  return std::min(d, period - d);
}

// L1 distance between two value sets under the metric, stopping early once the sum exceeds
// `bound` (the result is then > bound, not exact).
inline double poseDistanceBounded(const PoseMetric& m, const MachineValues& a,
                                  const MachineValues& b, double bound) {
  double s = 0;
  for (int i = m.begin; i < m.end; ++i) {
    s += wrappedDistance(a[i] - b[i], m.period[i]);
    if (s > bound) return s;
  }
  return s;
}

// L1 distance between two value sets under the metric.
double poseDistance(const PoseMetric& metric, const MachineValues& a, const MachineValues& b);

struct PoseNodeInfo {
  bool feasible = true;   // false: the pose collides (dropped)
  double penalty = 0;     // added to the path cost when the path visits the node (>= 0)
  double measure = std::numeric_limits<double>::quiet_NaN();  // tie-break: larger is preferred
                          // among costs within tieEpsilon; NaN = not computed yet (then the
                          // PoseMeasureFn computes it when a tie needs it)
};

// Candidates of layer `layer` (inverse kinematics); reference = best node of the previous layer
// (nullptr for layer 0). `keys` may be left empty or give each candidate a small non-negative
// track key (robot6: free-rotation sample x 8 + branch): the node of the same key in the previous
// layer seeds the relaxation, which then stops early (speed only, the result is the same).
// Return false to stop (cancellation).
using PoseCandidateFn = std::function<bool(size_t layer, const MachineValues* reference,
                                           std::vector<MachineValues>& out,
                                           std::vector<int32_t>& keys)>;
using PoseInfoFn = std::function<PoseNodeInfo(const MachineValues& values)>;
using PoseMeasureFn = std::function<double(const MachineValues& values)>;

struct PoseChoiceOptions {
  double tieEpsilon = 1e-9;   // costs closer than this are ties (broken by the larger measure)
  size_t maxKept = 0;         // 0 = exact; else at most this many non-dominated nodes are kept
                              // per layer (the cheapest), plus the greedy node, so the result
                              // stays <= greedy but is no longer guaranteed optimal
  double slack = 0;           // with maxKept > 0: v is also dropped when cost(u) + d(u, v) <=
                              // cost(v) + slack (near-duplicates of a kept node make room for
                              // distinct alternatives under the cap)
};

struct PoseChoice : Outcome {
  std::vector<MachineValues> chosen;   // one per layer, as the candidates gave them (wrapped)
  std::vector<MachineValues> greedy;   // greedy choice on the same candidates
  double cost = 0, penalty = 0;             // L1 part and penalty part of the chosen path
  double greedyCost = 0, greedyPenalty = 0;  // same for the greedy path
  size_t failedLayer = 0;             // layer with no feasible candidate (status InvalidOption)
  size_t keptNodes = 0;               // total non-dominated nodes over all layers (for reports)
  size_t candidateNodes = 0;          // total candidates over all layers
  size_t cappedLayers = 0;            // layers where maxKept dropped non-dominated nodes
};

// Shortest path over `layers` layers. Greedy: layer 0 takes the node of least penalty (largest
// measure on ties), then each layer the node minimising d(previous greedy, v) + penalty(v). So
// chosen cost + penalty <= greedy cost + greedy penalty always. Status InvalidOption with
// failedLayer set when a layer has no feasible candidate; Cancelled when candidates() returns false.
PoseChoice choosePoses(size_t layers, const PoseMetric& metric, const PoseCandidateFn& candidates,
                       const PoseInfoFn& info, const PoseMeasureFn& measure = {},
                       const PoseChoiceOptions& options = {});

// Unwrap a chosen sequence: each wrapped value is moved by multiples of its period to be nearest
// the previous one, then, if that leaves [lo, hi], to the alias inside the limits nearest the
// previous value.
void unwrapPoses(std::vector<MachineValues>& values, const PoseMetric& metric,
                 const std::vector<std::pair<double, double>>& limits);

}  // namespace omnislice
