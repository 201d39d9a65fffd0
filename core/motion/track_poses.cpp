// SPDX-License-Identifier: MIT
#include "motion/track_poses.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace omnislice {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Node {
  MachineValues q{};
  double cost = kInf;  // path cost to here, penalties included
  double l1 = 0;       // L1 part of that path
  double edge = 0;     // L1 of the incoming edge
  double measure = std::numeric_limits<double>::quiet_NaN();
  int32_t parent = -1;  // index into the previous layer's alive nodes
  int16_t k = 0;
  int8_t b = 0;
};

// Compact back-pointer of an alive node (8 bytes: 100k samples x a few alive nodes stay small).
struct Back {
  int32_t parent;
  uint16_t k;
  uint8_t b;
};

}  // namespace

TrackChoice chooseTrackPoses(size_t layers, const PoseMetric& metric, const TrackIkFn& ik,
                             const PoseInfoFn& info, const PoseMeasureFn& measureFn,
                             const TrackOptions& options, const TrackLayerFn& layerStart) {
  TrackChoice r;
  if (layers == 0) return r;
  const int S = std::max(1, options.samples);
  const double eps = options.tieEpsilon;
  const double slack = std::max(0.0, options.slack);
  std::vector<Node> prev, cand, alive;
  std::vector<Back> backs;
  backs.reserve(layers * 4);
  std::vector<size_t> begin;
  begin.reserve(layers + 1);
  begin.push_back(0);
  std::vector<int32_t> slot(static_cast<size_t>(S) * 8, -1);
  std::vector<int> mask(static_cast<size_t>(S), 0);
  std::vector<int> touched;
  std::vector<uint32_t> order, kept;
  std::vector<double> heap;
  size_t maxAlive = 0;  // no cap during the first options.uncappedLayers layers
  MachineValues vals[8];
  int brs[8];

  auto measureOf = [&](Node& n) {
    if (std::isnan(n.measure)) n.measure = measureFn ? measureFn(n.q) : 0.0;
    return n.measure;
  };
  auto addSolutions = [&](size_t layer, int k, int m) {
    const int n = ik(layer, k, m, vals, brs);
    ++r.ikCalls;
    for (int i = 0; i < n; ++i) {
      const int b = brs[i] & 7;
      if (!(m >> b & 1) || slot[static_cast<size_t>(k) * 8 + b] >= 0) continue;
      Node c;
      c.q = vals[i];
      c.k = static_cast<int16_t>(k);
      c.b = static_cast<int8_t>(b);
      slot[static_cast<size_t>(k) * 8 + b] = static_cast<int32_t>(cand.size());
      cand.push_back(c);
    }
  };
  auto clearCandidates = [&]() {
    for (const Node& c : cand) slot[static_cast<size_t>(c.k) * 8 + c.b] = -1;
    cand.clear();
  };
  auto relax = [&](Node& c, const Node& u, int32_t ui) {
    const double d = poseDistanceBounded(metric, u.q, c.q, c.cost - u.cost);
    const double cost = u.cost + d;
    if (cost < c.cost) {
      c.cost = cost;
      c.l1 = u.l1 + d;
      c.edge = d;
      c.parent = ui;
    }
  };
  // Lazy evaluation in cost order: feasibility and penalty only for nodes that may be alive.
  auto evaluate = [&]() {
    order.clear();
    for (uint32_t i = 0; i < cand.size(); ++i) {
      if (cand[i].cost < kInf) order.push_back(i);
    }
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return cand[a].cost < cand[b].cost; });
    double best = kInf;
    kept.clear();
    heap.clear();  // max-heap of the maxAlive smallest final costs
    for (uint32_t i : order) {
      Node& c = cand[i];
      // Penalties are >= 0: nothing later can be alive (within the slack, among the cheapest).
      double cutoff = best + slack;
      if (maxAlive > 0 && heap.size() >= maxAlive) cutoff = std::min(cutoff, heap.front());
      if (c.cost > cutoff + eps) break;
      const PoseNodeInfo ni = info(c.q);
      ++r.evaluatedNodes;
      if (!ni.feasible) continue;
      c.cost += ni.penalty;
      c.measure = ni.measure;
      best = std::min(best, c.cost);
      kept.push_back(i);
      if (maxAlive > 0) {
        if (heap.size() < maxAlive) {
          heap.push_back(c.cost);
          std::push_heap(heap.begin(), heap.end());
        } else if (c.cost < heap.front()) {
          std::pop_heap(heap.begin(), heap.end());
          heap.back() = c.cost;
          std::push_heap(heap.begin(), heap.end());
        }
      }
    }
    alive.clear();
    for (uint32_t i : kept) {
      if (cand[i].cost <= best + slack + eps) alive.push_back(cand[i]);
    }
    std::sort(alive.begin(), alive.end(),
              [](const Node& a, const Node& b) { return a.cost < b.cost; });
    if (maxAlive > 0 && alive.size() > maxAlive) alive.resize(maxAlive);
  };
  // Full evaluation: every free-rotation index and branch, joined to every node of `prev`.
  auto restart = [&](size_t layer) {
    ++r.restarts;
    clearCandidates();
    for (int k = 0; k < S; ++k) addSolutions(layer, k, 0xff);
    for (Node& c : cand) {
      if (prev.empty()) {
        c.cost = 0;
        continue;
      }
      for (size_t u = 0; u < prev.size(); ++u) {
        if (prev[u].cost >= c.cost) break;  // sorted by cost
        relax(c, prev[u], static_cast<int32_t>(u));
      }
    }
    evaluate();
  };

  for (size_t layer = 0; layer < layers; ++layer) {
    if (layerStart && !layerStart(layer)) {
      r.status = Status::Cancelled;
      r.message = "cancelled";
      return r;
    }
    maxAlive = layer < options.uncappedLayers ? 0 : options.maxAlive;
    if (layer == 0) {
      restart(layer);
    } else {
      // Free-rotation indices (and their branches) within +-1 of an alive node.
      clearCandidates();
      touched.clear();
      for (const Node& u : prev) {
        for (int dk = -1; dk <= 1; ++dk) {
          const int k = ((u.k + dk) % S + S) % S;
          if (mask[k] == 0) touched.push_back(k);
          mask[k] |= 1 << u.b;
        }
      }
      for (int k : touched) {
        addSolutions(layer, k, mask[k]);
        mask[k] = 0;
      }
      for (size_t ui = 0; ui < prev.size(); ++ui) {
        const Node& u = prev[ui];
        for (int dk = -1; dk <= 1; ++dk) {
          if (S < 3 && dk != 0 && (S == 1 || dk > 0)) continue;  // the same neighbour twice
          const int k = ((u.k + dk) % S + S) % S;
          const int32_t s = slot[static_cast<size_t>(k) * 8 + u.b];
          if (s >= 0) relax(cand[s], u, static_cast<int32_t>(ui));
        }
      }
      evaluate();
      if (alive.empty() || (options.restartStep > 0 && alive[0].edge > options.restartStep)) {
        restart(layer);
      }
    }
    if (alive.empty()) {
      r.status = Status::InvalidOption;
      r.failedLayer = layer;
      r.message = "no feasible candidate";
      return r;
    }
    for (const Node& a : alive) {
      backs.push_back({a.parent, static_cast<uint16_t>(a.k), static_cast<uint8_t>(a.b)});
    }
    begin.push_back(backs.size());
    r.aliveNodes += alive.size();
    std::swap(prev, alive);
  }
  clearCandidates();

  // Cheapest node of the last layer (ties: larger measure), then backtrack.
  size_t end = 0;
  for (size_t i = 1; i < prev.size(); ++i) {
    if (prev[i].cost > prev[0].cost + eps) break;
    if (measureOf(prev[i]) > measureOf(prev[end])) end = i;
  }
  r.trackCost = prev[end].l1;
  r.trackPenalty = prev[end].cost - prev[end].l1;
  r.chosen.resize(layers);
  size_t node = begin[layers - 1] + end;
  for (size_t layer = layers; layer-- > 0;) {
    const Back& bk = backs[node];
    const int n = ik(layer, bk.k, 1 << bk.b, vals, brs);
    ++r.ikCalls;
    bool found = false;
    for (int i = 0; i < n && !found; ++i) {
      if ((brs[i] & 7) == bk.b) {
        r.chosen[layer] = vals[i];
        found = true;
      }
    }
    if (!found) {  // the IK is deterministic: it gave this node before
      r.status = Status::Internal;
      r.message = "track pose choice: a chosen node vanished on recomputation";
      return r;
    }
    if (layer > 0) node = begin[layer - 1] + static_cast<size_t>(bk.parent);
  }
  r.cost = r.trackCost;
  r.penalty = r.trackPenalty;
  if (!options.compareGreedy) return r;

  // Greedy on the full candidate sets: layer 0 takes the node of least penalty (larger measure
  // on ties), then each layer the node minimising d(previous greedy, v) + penalty(v).
  std::vector<MachineValues> greedy(layers);
  std::vector<double> dist;
  std::vector<Node> all;
  double gl1 = 0, gpen = 0;
  for (size_t layer = 0; layer < layers; ++layer) {
    if (layerStart && !layerStart(layers + layer)) {
      r.status = Status::Cancelled;
      r.message = "cancelled";
      return r;
    }
    all.clear();
    for (int k = 0; k < S; ++k) {
      const int n = ik(layer, k, 0xff, vals, brs);
      for (int i = 0; i < n; ++i) {
        Node c;
        c.q = vals[i];
        c.cost = layer == 0 ? 0.0 : poseDistance(metric, greedy[layer - 1], c.q);
        all.push_back(c);
      }
    }
    std::sort(all.begin(), all.end(), [](const Node& a, const Node& b) { return a.cost < b.cost; });
    double gBest = kInf, gPen = 0, gDist = 0;
    int64_t pick = -1;
    for (size_t i = 0; i < all.size(); ++i) {
      Node& c = all[i];
      if (c.cost > gBest + eps) break;
      const PoseNodeInfo ni = info(c.q);
      if (!ni.feasible) continue;
      c.measure = ni.measure;
      const double total = c.cost + ni.penalty;
      bool take = pick < 0 || total < gBest - eps;
      if (!take && total <= gBest + eps) take = measureOf(c) > measureOf(all[pick]);
      if (take) {
        gBest = total;
        gPen = ni.penalty;
        gDist = c.cost;
        pick = static_cast<int64_t>(i);
      }
    }
    if (pick < 0) return r;  // cannot happen when the track found a feasible node here
    greedy[layer] = all[pick].q;
    gl1 += gDist;
    gpen += gPen;
  }
  r.greedyCost = gl1;
  r.greedyPenalty = gpen;
  if (gl1 + gpen < r.trackCost + r.trackPenalty - eps) {
    r.chosen = std::move(greedy);
    r.cost = gl1;
    r.penalty = gpen;
    r.greedyUsed = true;
  }
  return r;
}

}  // namespace omnislice
