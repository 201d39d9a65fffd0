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
#pragma once
#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "common/status.h"
#include "program/machine.h"

namespace omnislice {

struct PoseMetric {
  int begin = 0, end = 6;                 // value indices [begin, end) entering the L1 distance
  std::array<double, 6> period{};         // > 0: the value lives on a circle of this period and
                                          // differences are wrapped to (-period/2, period/2]
};

// L1 distance between two value sets under the metric.
double poseDistance(const PoseMetric& metric, const MachineValues& a, const MachineValues& b);

struct PoseNodeInfo {
  bool feasible = true;   // false: the pose collides (dropped)
  double penalty = 0;     // added to the path cost when the path visits the node (>= 0)
  double measure = 0;     // tie-break: larger is preferred among costs within tieEpsilon
};

// Candidates of layer `layer` (inverse kinematics); reference = best node of the previous layer
// (nullptr for layer 0). Return false to stop (cancellation).
using PoseCandidateFn =
    std::function<bool(size_t layer, const MachineValues* reference, std::vector<MachineValues>& out)>;
using PoseInfoFn = std::function<PoseNodeInfo(const MachineValues& values)>;

struct PoseChoice : Outcome {
  std::vector<MachineValues> chosen;   // one per layer, as the candidates gave them (wrapped)
  std::vector<double> chosenMeasure;   // info().measure of each chosen node
  std::vector<MachineValues> greedy;   // greedy choice on the same candidates
  double cost = 0, penalty = 0;             // L1 part and penalty part of the chosen path
  double greedyCost = 0, greedyPenalty = 0;  // same for the greedy path
  size_t failedLayer = 0;             // layer with no feasible candidate (status InvalidOption)
  size_t keptNodes = 0;               // total non-dominated nodes over all layers (for reports)
  size_t candidateNodes = 0;          // total candidates over all layers
};

// Shortest path over `layers` layers. Greedy: layer 0 takes the node of least penalty (largest
// measure on ties), then each layer the node minimising d(previous greedy, v) + penalty(v). So
// chosen cost + penalty <= greedy cost + greedy penalty always. Status InvalidOption with
// failedLayer set when a layer has no feasible candidate; Cancelled when candidates() returns false.
PoseChoice choosePoses(size_t layers, const PoseMetric& metric, const PoseCandidateFn& candidates,
                       const PoseInfoFn& info, double tieEpsilon = 1e-9);

// Unwrap a chosen sequence: each wrapped value is moved by multiples of its period to be nearest
// the previous one, then, if that leaves [lo, hi], to the alias inside the limits nearest the
// previous value.
void unwrapPoses(std::vector<MachineValues>& values, const PoseMetric& metric,
                 const std::vector<std::pair<double, double>>& limits);

}  // namespace omnislice
