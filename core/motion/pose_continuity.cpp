// SPDX-License-Identifier: MIT
#include "motion/pose_continuity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace omnislice {

namespace {

inline double wrapped(double d, double period) {
  d = std::abs(d);
  if (period <= 0) return d;
  if (d > period) d = std::fmod(d, period);
  return std::min(d, period - d);
}

// Distance, stopping early once it exceeds `bound` (the result is then > bound, not exact).
inline double distanceBounded(const PoseMetric& m, const MachineValues& a, const MachineValues& b,
                              double bound) {
  double s = 0;
  for (int i = m.begin; i < m.end; ++i) {
    s += wrapped(a[i] - b[i], m.period[i]);
    if (s > bound) return s;
  }
  return s;
}

struct Kept {
  MachineValues values;
  double cost;     // path cost to here including penalties
  double l1;       // L1 part of that path
  double measure;
  int32_t back;    // index into the previous layer's kept nodes
};

struct Scored {
  double cost, l1;
  int32_t back;
  uint32_t index;
};

}  // namespace

double poseDistance(const PoseMetric& metric, const MachineValues& a, const MachineValues& b) {
  return distanceBounded(metric, a, b, std::numeric_limits<double>::infinity());
}

PoseChoice choosePoses(size_t layers, const PoseMetric& metric, const PoseCandidateFn& candidates,
                       const PoseInfoFn& info, double tieEpsilon) {
  PoseChoice r;
  if (layers == 0) return r;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Kept> kept;              // all layers, flat
  std::vector<size_t> layerBegin{0};   // kept[layerBegin[l] .. layerBegin[l+1])
  std::vector<MachineValues> cand;
  std::vector<Scored> scored;
  std::vector<double> dist;
  std::vector<char> done;
  MachineValues greedyPrev{};
  double greedyL1 = 0, greedyPen = 0;
  r.greedy.reserve(layers);

  for (size_t layer = 0; layer < layers; ++layer) {
    const size_t pb = layer == 0 ? 0 : layerBegin[layer - 1];
    const size_t pe = layerBegin[layer];
    // Reference for the inverse kinematics: the cheapest node of the previous layer (kept nodes
    // are stored in cost order).
    const MachineValues* reference = layer == 0 ? nullptr : &kept[pb].values;
    cand.clear();
    if (!candidates(layer, reference, cand)) {
      r.status = Status::Cancelled;
      r.message = "cancelled";
      return r;
    }
    r.candidateNodes += cand.size();

    // Relax from the kept nodes of the previous layer.
    scored.clear();
    scored.reserve(cand.size());
    for (uint32_t v = 0; v < cand.size(); ++v) {
      if (layer == 0) {
        scored.push_back({0, 0, -1, v});
        continue;
      }
      double best = inf, bestL1 = 0;
      int32_t back = -1;
      for (size_t u = pb; u < pe; ++u) {
        const Kept& ku = kept[u];
        if (ku.cost > best + tieEpsilon) break;  // sorted by cost: nothing cheaper follows
        const double d = distanceBounded(metric, ku.values, cand[v], best + tieEpsilon - ku.cost);
        const double c = ku.cost + d;
        const bool better = c < best - tieEpsilon;
        const bool tieWin =
            !better && c <= best + tieEpsilon && back >= 0 && ku.measure > kept[pb + back].measure;
        if (better || tieWin) {
          best = c;  // the cost stays the one of the path through `back`
          bestL1 = ku.l1 + d;
          back = static_cast<int32_t>(u - pb);
        }
      }
      scored.push_back({best, bestL1, back, v});
    }
    // Exact dominance pruning by repeated selection: take the cheapest remaining node, evaluate
    // it lazily (feasibility, penalty), keep it unless a kept node dominates it, then drop every
    // remaining node it dominates. The test cost(u) + d(u, v) <= cost(v) uses v's cost without
    // its penalty, which is a lower bound, so the drop is exact.
    const size_t kb = kept.size();
    size_t remaining = scored.size();
    while (remaining > 0) {
      size_t mi = 0;
      for (size_t i = 1; i < remaining; ++i) {
        if (scored[i].cost < scored[mi].cost) mi = i;
      }
      const Scored s = scored[mi];
      scored[mi] = scored[--remaining];
      if (!(s.cost < inf)) break;
      const MachineValues& v = cand[s.index];
      const PoseNodeInfo ni = info(v);
      if (!ni.feasible) continue;
      const double cost = s.cost + ni.penalty;
      bool dominated = false;
      for (size_t w = kb; w < kept.size() && !dominated; ++w) {
        if (kept[w].cost > cost) break;
        dominated =
            kept[w].cost + distanceBounded(metric, kept[w].values, v, cost - kept[w].cost) <= cost;
      }
      if (dominated) continue;
      const Kept k{v, cost, s.l1, ni.measure, s.back};
      auto pos = std::upper_bound(kept.begin() + kb, kept.end(), cost,
                                  [](double c, const Kept& e) { return c < e.cost; });
      kept.insert(pos, k);
      for (size_t i = 0; i < remaining;) {
        const double slack = scored[i].cost - cost;
        if (slack >= 0 && distanceBounded(metric, v, cand[scored[i].index], slack) <= slack) {
          scored[i] = scored[--remaining];
        } else {
          ++i;
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

    // Greedy on the same candidates: nearest first, evaluating lazily.
    dist.resize(cand.size());
    done.assign(cand.size(), 0);
    for (uint32_t v = 0; v < cand.size(); ++v) {
      dist[v] = layer == 0 ? 0 : poseDistance(metric, greedyPrev, cand[v]);
    }
    double best = inf, bestMeasure = -inf, bestPen = 0;
    int64_t pick = -1;
    for (;;) {
      int64_t next = -1;
      for (uint32_t v = 0; v < cand.size(); ++v) {
        if (!done[v] && dist[v] <= best + tieEpsilon && (next < 0 || dist[v] < dist[next])) next = v;
      }
      if (next < 0) break;
      done[next] = 1;
      const PoseNodeInfo ni = info(cand[next]);
      if (!ni.feasible) continue;
      const double c = dist[next] + ni.penalty;
      if (c < best - tieEpsilon || (c <= best + tieEpsilon && ni.measure > bestMeasure)) {
        best = c;
        bestMeasure = ni.measure;
        bestPen = ni.penalty;
        pick = next;
      }
    }
    // A feasible node exists (kept is not empty), so pick >= 0.
    greedyL1 += dist[pick];
    greedyPen += bestPen;
    greedyPrev = cand[pick];
    r.greedy.push_back(greedyPrev);
  }

  // Cheapest node of the last layer (ties: larger measure), then backtrack.
  const size_t lb = layerBegin[layers - 1], le = layerBegin[layers];
  size_t end = lb;
  for (size_t i = lb + 1; i < le; ++i) {
    if (kept[i].cost > kept[lb].cost + tieEpsilon) break;
    if (kept[i].measure > kept[end].measure) end = i;
  }
  r.cost = kept[end].l1;
  r.penalty = kept[end].cost - kept[end].l1;
  r.greedyCost = greedyL1;
  r.greedyPenalty = greedyPen;
  r.keptNodes = kept.size();
  r.chosen.resize(layers);
  r.chosenMeasure.resize(layers);
  size_t node = end;
  for (size_t layer = layers; layer-- > 0;) {
    r.chosen[layer] = kept[node].values;
    r.chosenMeasure[layer] = kept[node].measure;
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
        // Nearest alias inside the limits (an unwinding move).
        double bestV = values[k][i], bestD = std::numeric_limits<double>::infinity();
        const double base = values[k][i];
        for (int m = -4; m <= 4; ++m) {
          const double a = base + m * p;
          if (a >= lo - tol && a <= hi + tol && std::abs(a - prev) < bestD) {
            bestD = std::abs(a - prev);
            bestV = a;
          }
        }
        v = bestV;
      }
      values[k][i] = v;
    }
  }
}

}  // namespace omnislice
