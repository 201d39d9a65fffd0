// SPDX-License-Identifier: MIT
// Pose continuity for robot6 by a "track" dynamic programme with lazy inverse kinematics: the
// fast counterpart of choosePoses() (pose_continuity.h) for many samples.
//
// A node of sample (layer) l is (k, b): free-rotation index k in 0..S-1 (circular) and UR branch
// b in 0..7. A track is a fixed (k, b): along a smooth path its joint values change little from
// one sample to the next. Edges join (k, b) to (k', b) with circular |k - k'| <= 1 (stay on the
// track, or turn the platform by one free-rotation step); cost = L1 joint distance (PoseMetric)
// + node penalty. Per sample only the "alive" nodes, whose path cost is within `slack` of the
// sample's best, are kept, and the next sample's inverse kinematics is evaluated only at the
// free-rotation indices within +-1 of an alive node and for the branches alive there (typically
// 3-8 urInverse calls per sample instead of S); maxAlive caps the alive nodes (on a helix, which
// is symmetric about the part's axis, dozens of tracks stay within the slack). Feasibility (collisions) and the penalty are
// evaluated lazily in cost order, only for nodes that can still be alive.
// Restart: at layer 0, when no alive node has a feasible successor (joint limits, collision), or
// when even the best successor needs a joint step above `restartStep` (a branch index that swaps
// at a singularity, a long travel), all S x 8 nodes are evaluated and joined to every alive node
// of the previous sample with full L1 edges (this is where a branch may change).
// It is a heuristic (the exact optimum of the full layered graph is choosePoses()); on the test
// paths its cost is within a few percent of the exact one and below greedy.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "common/status.h"
#include "motion/pose_continuity.h"
#include "machine/machine.h"

namespace omnislice {

// Solutions of layer `layer` at free-rotation index k for the branches set in `branchMask`:
// writes up to 8 value sets (within the joint limits; a wrapped value may be any alias) and
// their branch numbers (0..7), returns how many.
using TrackIkFn = std::function<int(size_t layer, int k, int branchMask, MachineValues values[8],
                                    int branches[8])>;
// Called at the start of every layer (the greedy pass of compareGreedy calls it with
// layers + layer, so the index keeps increasing); return false to cancel.
using TrackLayerFn = std::function<bool(size_t layer)>;

struct TrackOptions {
  int samples = 30;          // S: free-rotation indices (circular neighbours)
  double slack = 0.3;        // rad: nodes whose path cost exceeds the sample's best by more are
                             // dropped (0 = keep only the best node and its ties)
  double restartStep = 0.5;  // rad: a full evaluation when the best successor's L1 step is
                             // above this (0 = only when no alive node has a feasible successor)
  size_t maxAlive = 4;       // > 0: at most this many alive nodes per sample (the cheapest)
  size_t uncappedLayers = 500;  // maxAlive applies from this layer on: at layer 0 every node
                                // costs 0, and which tracks are worth keeping shows only later
  double tieEpsilon = 1e-9;  // costs closer than this are ties (broken by the larger measure)
  bool compareGreedy = false;  // also compute the greedy choice on the full candidate sets
                               // (S x 8 per sample, as slow as the inverse kinematics of
                               // inverseMap()) and return it when it is cheaper
};

struct TrackChoice : Outcome {
  std::vector<MachineValues> chosen;   // one per layer (wrapped values as the IK gave them)
  double cost = 0, penalty = 0;        // L1 part and penalty part of the returned path
  double trackCost = 0, trackPenalty = 0;  // the same for the track path (before the fallback)
  double greedyCost = -1, greedyPenalty = -1;  // greedy path (-1 without compareGreedy)
  bool greedyUsed = false;             // the greedy path was cheaper and is returned
  size_t failedLayer = 0;              // layer with no feasible node (status InvalidOption)
  size_t ikCalls = 0;                  // TrackIkFn calls of the track programme
  size_t aliveNodes = 0;               // total alive nodes over all layers
  size_t evaluatedNodes = 0;           // nodes whose PoseInfoFn was called
  size_t restarts = 0;                 // full evaluations (layer 0 included)
};

// Track DP over `layers` layers (see the file comment). Status InvalidOption with failedLayer
// when a layer has no feasible node even after a full evaluation; Cancelled when layerStart
// returns false. cost + penalty <= greedyCost + greedyPenalty when compareGreedy is set.
TrackChoice chooseTrackPoses(size_t layers, const PoseMetric& metric, const TrackIkFn& ik,
                             const PoseInfoFn& info, const PoseMeasureFn& measure = {},
                             const TrackOptions& options = {},
                             const TrackLayerFn& layerStart = {});

}  // namespace omnislice
