// SPDX-License-Identifier: MIT
#include "motion/pose_continuity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace omnislice {

namespace {

struct Kept {
  MachineValues values;
  double cost;     // path cost to here including penalties
  double l1;       // L1 part of that path
  double measure;
  int32_t back;    // index into the previous layer's kept nodes
  int32_t key;     // track key (-1 = none)
};

struct Scored {
  double cost, l1;
  int32_t back;
  uint32_t index;
};

}  // namespace

double poseDistance(const PoseMetric& metric, const MachineValues& a, const MachineValues& b) {
  return poseDistanceBounded(metric, a, b, std::numeric_limits<double>::infinity());
}

PoseChoice choosePoses(size_t layers, const PoseMetric& metric, const PoseCandidateFn& candidates,
                       const PoseInfoFn& info, const PoseMeasureFn& measureFn,
                       const PoseChoiceOptions& options) {
  PoseChoice r;
  if (layers == 0) return r;
  const double inf = std::numeric_limits<double>::infinity();
  const double eps = options.tieEpsilon;
  std::vector<Kept> kept;              // all layers, flat
  std::vector<size_t> layerBegin{0};   // kept[layerBegin[l] .. layerBegin[l+1])
  std::vector<MachineValues> cand;
  std::vector<int32_t> keys, prevOfKey;
  std::vector<Scored> scored;
  std::vector<double> dist;
  std::vector<PoseNodeInfo> infos;
  std::vector<char> evaluated, done;
  MachineValues greedyPrev{};
  double greedyL1 = 0, greedyPen = 0;
  r.greedy.reserve(layers);

  auto measureOf = [&](double& m, const MachineValues& v) {
    if (std::isnan(m)) m = measureFn ? measureFn(v) : 0.0;
    return m;
  };

  for (size_t layer = 0; layer < layers; ++layer) {
    const size_t pb = layer == 0 ? 0 : layerBegin[layer - 1];
    const size_t pe = layerBegin[layer];
    // Reference for the inverse kinematics: the cheapest node of the previous layer (kept nodes
    // are stored in cost order).
    const MachineValues* reference = layer == 0 ? nullptr : &kept[pb].values;
    cand.clear();
    keys.clear();
    if (!candidates(layer, reference, cand, keys)) {
      r.status = Status::Cancelled;
      r.message = "cancelled";
      return r;
    }
    r.candidateNodes += cand.size();
    const size_t nc = cand.size();
    infos.assign(nc, PoseNodeInfo{});
    evaluated.assign(nc, 0);
    auto infoOf = [&](uint32_t v) -> PoseNodeInfo& {
      if (!evaluated[v]) {
        infos[v] = info(cand[v]);
        evaluated[v] = 1;
      }
      return infos[v];
    };

    // Greedy on the same candidates: nearest first, evaluating lazily.
    dist.resize(nc);
    done.assign(nc, 0);
    for (uint32_t v = 0; v < nc; ++v) {
      dist[v] = layer == 0 ? 0 : poseDistance(metric, greedyPrev, cand[v]);
    }
    double gBest = inf, gPen = 0;
    int64_t pick = -1;
    for (;;) {
      int64_t next = -1;
      for (uint32_t v = 0; v < nc; ++v) {
        if (!done[v] && dist[v] <= gBest + eps && (next < 0 || dist[v] < dist[next])) next = v;
      }
      if (next < 0) break;
      done[next] = 1;
      PoseNodeInfo& ni = infoOf(static_cast<uint32_t>(next));
      if (!ni.feasible) continue;
      const double c = dist[next] + ni.penalty;
      bool take = pick < 0 || c < gBest - eps;
      if (!take && c <= gBest + eps) {
        take = measureOf(ni.measure, cand[next]) > measureOf(infos[pick].measure, cand[pick]);
      }
      if (take) {
        gBest = c;
        gPen = ni.penalty;
        pick = next;
      }
    }
    if (pick < 0) {
      r.status = Status::InvalidOption;
      r.failedLayer = layer;
      r.message = "no feasible candidate";
      return r;
    }

    // Relax from the kept nodes of the previous layer, seeded by the node of the same track.
    const bool keyed = keys.size() == nc;
    if (keyed) {
      prevOfKey.assign(prevOfKey.size(), -1);
      for (size_t u = pb; u < pe; ++u) {
        const int32_t k = kept[u].key;
        if (k < 0) continue;
        if (static_cast<size_t>(k) >= prevOfKey.size()) prevOfKey.resize(k + 1, -1);
        if (prevOfKey[k] < 0) prevOfKey[k] = static_cast<int32_t>(u - pb);
      }
    }
    scored.clear();
    scored.reserve(nc);
    for (uint32_t v = 0; v < nc; ++v) {
      if (layer == 0) {
        scored.push_back({0, 0, -1, v});
        continue;
      }
      double best = inf, bestL1 = 0;
      int32_t back = -1;
      if (keyed && keys[v] >= 0 && static_cast<size_t>(keys[v]) < prevOfKey.size() &&
          prevOfKey[keys[v]] >= 0) {
        const Kept& ks = kept[pb + prevOfKey[keys[v]]];
        const double d = poseDistance(metric, ks.values, cand[v]);
        best = ks.cost + d;
        bestL1 = ks.l1 + d;
        back = prevOfKey[keys[v]];
      }
      for (size_t u = pb; u < pe; ++u) {
        Kept& ku = kept[u];
        if (ku.cost > best + eps) break;  // sorted by cost: nothing cheaper follows
        const double d = poseDistanceBounded(metric, ku.values, cand[v], best + eps - ku.cost);
        const double c = ku.cost + d;
        const bool better = c < best - eps;
        const bool tieWin = !better && c <= best + eps && back >= 0 &&
                            measureOf(ku.measure, ku.values) >
                                measureOf(kept[pb + back].measure, kept[pb + back].values);
        if (better || tieWin) {
          best = c;  // the cost stays the one of the path through `back`
          bestL1 = ku.l1 + d;
          back = static_cast<int32_t>(u - pb);
        }
      }
      scored.push_back({best, bestL1, back, v});
    }

    // Dominance pruning in cost order: evaluate each node lazily (feasibility, penalty) and keep
    // it unless a kept node u has cost(u) + d(u, v) <= cost(v). Kept nodes are never dominated
    // by later ones (their cost is not lower), so one pass is exact. The greedy node is always
    // kept.
    const size_t kb = kept.size();
    auto keep = [&](const Scored& s, const MachineValues& v, const PoseNodeInfo& ni) {
      const double cost = s.cost + ni.penalty;
      const Kept k{v, cost, s.l1, ni.measure, s.back, keyed ? keys[s.index] : -1};
      auto pos = std::upper_bound(kept.begin() + kb, kept.end(), cost,
                                  [](double c, const Kept& e) { return c < e.cost; });
      kept.insert(pos, k);
    };
    std::sort(scored.begin(), scored.end(),
              [](const Scored& a, const Scored& b) { return a.cost < b.cost; });
    bool greedyKept = false;
    const double slack = options.maxKept > 0 ? options.slack : 0.0;
    for (const Scored& s : scored) {
      if (options.maxKept > 0 && kept.size() - kb >= options.maxKept) {
        ++r.cappedLayers;
        break;
      }
      if (!(s.cost < inf)) break;
      const MachineValues& v = cand[s.index];
      // Cheap test first, with v's cost before its penalty (a lower bound): exact drop.
      bool dominated = false;
      const double reach = s.cost + slack;
      for (size_t w = kb; w < kept.size() && !dominated; ++w) {
        if (kept[w].cost > reach) break;
        dominated = kept[w].cost +
                        poseDistanceBounded(metric, kept[w].values, v, reach - kept[w].cost) <=
                    reach;
      }
      if (dominated) continue;
      const PoseNodeInfo& ni = infoOf(s.index);
      if (!ni.feasible) continue;
      const double cost = s.cost + ni.penalty;
      if (ni.penalty > 0) {
        for (size_t w = kb; w < kept.size() && !dominated; ++w) {
          if (kept[w].cost > cost) break;
          dominated =
              kept[w].cost + poseDistanceBounded(metric, kept[w].values, v, cost - kept[w].cost) <=
              cost;
        }
        if (dominated) continue;
      }
      keep(s, v, ni);
      greedyKept = greedyKept || s.index == pick;
    }
    if (!greedyKept && options.maxKept > 0) {
      // The greedy node with its shortest-path cost (from the kept nodes, which include the
      // previous greedy node): so the final cost never exceeds the greedy one.
      for (size_t i = 0; i < scored.size(); ++i) {
        if (scored[i].index == pick) {
          keep(scored[i], cand[pick], infoOf(static_cast<uint32_t>(pick)));
          break;
        }
      }
    }
    if (kept.size() == kb) {
      r.status = Status::InvalidOption;
      r.failedLayer = layer;
      r.message = "no feasible candidate";
      return r;
    }
    layerBegin.push_back(kept.size());
    greedyL1 += dist[pick];
    greedyPen += gPen;
    greedyPrev = cand[pick];
    r.greedy.push_back(greedyPrev);
  }

  // Cheapest node of the last layer (ties: larger measure), then backtrack.
  const size_t lb = layerBegin[layers - 1], le = layerBegin[layers];
  size_t end = lb;
  for (size_t i = lb + 1; i < le; ++i) {
    if (kept[i].cost > kept[lb].cost + eps) break;
    if (measureOf(kept[i].measure, kept[i].values) > measureOf(kept[end].measure, kept[end].values)) {
      end = i;
    }
  }
  r.cost = kept[end].l1;
  r.penalty = kept[end].cost - kept[end].l1;
  r.greedyCost = greedyL1;
  r.greedyPenalty = greedyPen;
  r.keptNodes = kept.size();
  r.chosen.resize(layers);
  size_t node = end;
  for (size_t layer = layers; layer-- > 0;) {
    r.chosen[layer] = kept[node].values;
    if (layer > 0) node = layerBegin[layer - 1] + static_cast<size_t>(kept[node].back);
  }
  return r;
}

void unwrapPoses(std::vector<MachineValues>& values, const PoseMetric& metric,
                 const std::vector<std::pair<double, double>>& limits) {
  for (size_t k = 1; k < values.size(); ++k) {
    for (int i = metric.begin; i < metric.end; ++i) {
      const double p = metric.period[i];
      if (p <= 0) continue;
      const double prev = values[k - 1][i];
      double d = std::fmod(values[k][i] - prev, p);
      if (d > 0.5 * p) d -= p;
      if (d <= -0.5 * p) d += p;
      double v = prev + d;
      const double lo = i < static_cast<int>(limits.size()) ? limits[i].first : -1e300;
      const double hi = i < static_cast<int>(limits.size()) ? limits[i].second : 1e300;
      const double tol = 1e-9 * p;
      if (v < lo - tol || v > hi + tol) {
        // The alias inside the limits nearest the previous value: whole turns back from the
        // continuous value (an unwinding move, one turn when the limits span more than one).
        // Aliases of the raw value within 4 turns of it were tried before: from a value wound up
        // near a limit (the table's C at -3587 deg after a Fermat spiral's many loops) the nearest
        // of those was 14 turns away, and verify refused the program.
        const double turns = v < lo - tol ? std::ceil((lo - tol - v) / p) : -std::ceil((v - hi - tol) / p);
        const double a = v + turns * p;
        if (a >= lo - tol && a <= hi + tol) v = a;
        else v = values[k][i];  // limits narrower than a turn: no alias may fit; the raw value
      }
      values[k][i] = v;
    }
  }
}

}  // namespace omnislice
