// SPDX-License-Identifier: MIT
#include "motion/feed_limits.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace omnislice {

namespace {

constexpr double kStill = 1e-12;  // value change treated as none (mm or the joint unit)

struct Chain {
  const FeedInput& in;
  std::vector<double>& t;

  // Changes at or below kStill are rounding noise (the same threshold gives a move its duration
  // in limitFeeds()): over a near-zero duration they would read as huge velocities.
  double dq(size_t k, int i) const {
    const double d = in.values[k + 1][i] - in.values[k][i];
    return std::abs(d) <= kStill ? 0.0 : d;
  }
  bool motion(size_t k) const { return k < t.size() && t[k] > 0; }

  // Largest |a_i| / amax_i at the junction of moves k, k+1 (both moving), 0 when unlimited.
  double accelRatio(size_t k) const {
    if (!motion(k) || !motion(k + 1)) return 0;
    double r = 0;
    const double tau = 0.5 * (t[k] + t[k + 1]);
    for (int i = 0; i < in.axes; ++i) {
      const double amax = in.dynamics[i].acceleration;
      if (amax <= 0) continue;
      const double a = (dq(k + 1, i) / t[k + 1] - dq(k, i) / t[k]) / tau;
      r = std::max(r, std::abs(a) / amax);
    }
    return r;
  }
  double accel(size_t k, int i) const {
    const double tau = 0.5 * (t[k] + t[k + 1]);
    return (dq(k + 1, i) / t[k + 1] - dq(k, i) / t[k]) / tau;
  }
  // Time between the samples of a_k and a_k+1. a_k is the difference of the velocities at the
  // midpoints of moves k and k+1, so it belongs to the middle of those midpoints; the two samples
  // are (T_k + 2 T_k+1 + T_k+2) / 4 apart (T at equal spacing, as in the paper). Dividing by
  // T_k+1 alone instead made a near-zero move between two long ones (a rounding-noise "move" of
  // 1e-15 mm in a 3+2 safe rotation) read as an almost infinite jerk, and the scaling then
  // stretched its neighbours to days.
  double jerkSpan(size_t k) const { return 0.25 * (t[k] + 2 * t[k + 1] + t[k + 2]); }
  // Largest |j_i| / jmax_i over moves k, k+1, k+2 (all moving).
  double jerkRatio(size_t k) const {
    if (!motion(k) || !motion(k + 1) || !motion(k + 2)) return 0;
    double r = 0;
    const double span = jerkSpan(k);
    for (int i = 0; i < in.axes; ++i) {
      const double jmax = in.dynamics[i].jerk;
      if (jmax <= 0) continue;
      const double j = (accel(k + 1, i) - accel(k, i)) / span;
      r = std::max(r, std::abs(j) / jmax);
    }
    return r;
  }
  double velocityRatio(size_t k) const {
    if (!motion(k)) return 0;
    double r = 0;
    for (int i = 0; i < in.axes; ++i) {
      const double vmax = in.dynamics[i].velocity;
      if (vmax > 0) r = std::max(r, std::abs(dq(k, i)) / t[k] / vmax);
    }
    return r;
  }
};

constexpr double kSlack = 1e-6;  // scale a little beyond the limit so rounding cannot exceed it

// Every acceleration and jerk difference that involves T_k within its limit (accelRatio() of
// junctions k - 1, k and jerkRatio() of windows k - 2 .. k), for trial values of T_k with the other
// durations fixed: what does not depend on T_k (the accelerations at junctions k - 2 and k + 1, the
// velocities of moves k - 1 and k + 1) is computed once. Each value is the same expression as
// Chain's, so within(T) answers as Chain's ratios would with t[k] = T.
class LimitsWindow {
 public:
  LimitsWindow(const Chain& c, size_t k) : c_(c), k_(k), lo_(k >= 2 ? k - 2 : 0) {
    const size_t n = c.t.size();
    for (size_t j = lo_; j <= k + 1 && j + 1 < n; ++j) {
      has_[j - lo_] = moving(j) && moving(j + 1);
      if (!has_[j - lo_] || j + 1 == k || j == k) continue;
      for (int i = 0; i < c.in.axes; ++i) acc_[j - lo_][i] = c.accel(j, i);
    }
    for (int i = 0; i < c.in.axes; ++i) {
      dqK_[i] = c.dq(k, i);
      if (k >= 1 && has_[k - 1 - lo_]) vBefore_[i] = c.dq(k - 1, i) / c.t[k - 1];
      if (has_[k - lo_]) vAfter_[i] = c.dq(k + 1, i) / c.t[k + 1];
    }
  }

  bool within(double tk) const {
    const std::vector<double>& t = c_.t;
    const size_t n = t.size(), k = k_, lo = lo_;
    const int axes = c_.in.axes;
    // Rows of the accelerations at junctions lo .. lo + 3: the two that depend on T_k computed
    // here, the others read in place.
    double before[6], after[6];
    const double* acc[4] = {acc_[0], acc_[1], acc_[2], acc_[3]};
    if (k >= 1 && has_[k - 1 - lo]) {
      const double tau = 0.5 * (t[k - 1] + tk);
      for (int i = 0; i < axes; ++i) before[i] = (dqK_[i] / tk - vBefore_[i]) / tau;
      acc[k - 1 - lo] = before;
    }
    if (has_[k - lo]) {
      const double tau = 0.5 * (tk + t[k + 1]);
      for (int i = 0; i < axes; ++i) after[i] = (vAfter_[i] - dqK_[i] / tk) / tau;
      acc[k - lo] = after;
    }
    for (size_t j = k >= 1 ? k - 1 : 0; j <= k; ++j) {
      if (!has_[j - lo]) continue;
      for (int i = 0; i < axes; ++i) {
        const double amax = c_.in.dynamics[i].acceleration;
        if (amax > 0 && std::abs(acc[j - lo][i]) / amax > 1 + 1e-9) return false;
      }
    }
    for (size_t w = lo; w <= k && w + 2 < n; ++w) {
      if (!has_[w - lo] || !has_[w + 1 - lo]) continue;
      const double tw = w == k ? tk : t[w], tw1 = w + 1 == k ? tk : t[w + 1], tw2 = w + 2 == k ? tk : t[w + 2];
      const double span = 0.25 * (tw + 2 * tw1 + tw2);  // Chain::jerkSpan
      for (int i = 0; i < axes; ++i) {
        const double jmax = c_.in.dynamics[i].jerk;
        if (jmax <= 0) continue;
        if (std::abs((acc[w + 1 - lo][i] - acc[w - lo][i]) / span) / jmax > 1 + 1e-9) return false;
      }
    }
    return true;
  }

 private:
  bool moving(size_t j) const { return j == k_ || c_.motion(j); }  // trial values of T_k are > 0

  const Chain& c_;
  size_t k_, lo_;
  bool has_[4] = {false, false, false, false};
  double acc_[4][6] = {};
  double dqK_[6] = {}, vBefore_[6] = {}, vAfter_[6] = {};
};

// The raising pass scales windows uniformly: each scale moves the differences next to the window,
// which are then scaled in turn, so whole neighbourhoods end up far slower than any limit needs
// (on a table5 curved-layer print 2/3 of the moves were slowed while every difference they enter
// stayed below 0.9 of its limit). Coordinate descent takes the slack back: each duration is
// lowered towards its floor t0 (velocity limit, requested speed) as far as the differences it
// enters allow, found by bisection between the lower bound and the current (feasible) value to
// 1/4096 of the gap. Only feasible values are ever kept (a value the raising cap left over a
// limit is kept as is), so the limits hold throughout; sweeps alternate direction and stop when a
// sweep saves under 0.1 %.
// A sweep lowers a duration by at most kStep of its value, so that neighbours share the slack:
// lowering each one straight to the floor where it could (the first version) let every other move
// take all of it and left its neighbours slow, feeds alternating 2 and 30 mm/s along a curved
// layer under paper 003's jerk limit (the shared kitten at 40 mm, geodesic, robot6-ur5: 5.46 h
// against 3.00 h with kStep 0.3; a tenth of the step gave the same, motion stage 0.55 -> 0.84 s).
// `order`: the moves to lower, in sweep order (reversed on odd sweeps).
void tighten(Chain& c, const std::vector<double>& t0, const std::vector<size_t>& order) {
  std::vector<double>& t = c.t;
  const size_t n = order.size();
  constexpr int kSweeps = 30, kBisections = 12;
  constexpr double kStep = 0.3;
  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    double total = 0, saved = 0;
    for (size_t idx = 0; idx < n; ++idx) {
      const size_t k = order[sweep % 2 == 0 ? idx : n - 1 - idx];
      const double hi = t[k], lo = std::max(t0[k], (1 - kStep) * hi);
      total += hi;
      if (!(hi > lo * (1 + 1e-9)) || !(lo > 0)) continue;
      const LimitsWindow window(c, k);
      if (window.within(lo)) {
        t[k] = lo;
        saved += hi - lo;
        continue;
      }
      // Already tight within 0.1 % (most moves after the first sweep): one check.
      const double near = hi * (1 - 1e-3);
      if (near <= lo || !window.within(near)) continue;
      double a = lo, b = near;  // a over a limit, b within
      for (int it = 0; it < kBisections; ++it) {
        const double m = 0.5 * (a + b);
        if (window.within(m)) {
          b = m;
        } else {
          a = m;
        }
      }
      t[k] = b;
      saved += hi - b;
    }
    if (saved <= 1e-3 * total) break;
  }
}

// The chains of moving moves: [first, end) ranges of consecutive moves with t0 > 0 (a move that
// changes nothing has no duration and breaks the differences).
std::vector<std::pair<size_t, size_t>> movingChains(const std::vector<double>& t0) {
  std::vector<std::pair<size_t, size_t>> out;
  for (size_t a = 0; a < t0.size();) {
    if (!(t0[a] > 0)) {
      ++a;
      continue;
    }
    size_t e = a;
    while (e < t0.size() && t0[e] > 0) ++e;
    out.emplace_back(a, e);
    a = e;
  }
  return out;
}

// The second start: on each chain one feed u for every move (T_k = max(t0_k, length_k / u)), the
// largest u under which every difference of the chain is within its limit (bisection on u; at one
// feed a smooth motion has smooth differences, where the raising pass from the floors met the
// floors' kinks and scaled whole neighbourhoods). A chain not feasible even at 0.001 mm/s keeps
// the durations it has.
void uniformFeedStart(Chain& c, const std::vector<double>& t0, const std::vector<std::pair<size_t, size_t>>& chains) {
  std::vector<double>& t = c.t;
  const FeedInput& in = c.in;
  for (const auto& chain : chains) {
    const size_t a = chain.first, e = chain.second;  // captured below (not a structured binding)
    auto durations = [&](double u) {
      for (size_t k = a; k < e; ++k) t[k] = std::max(t0[k], in.length[k] > 0 ? in.length[k] / u : 0.0);
    };
    const std::vector<double> kept(t.begin() + long(a), t.begin() + long(e));
    auto feasible = [&](double u) {
      durations(u);
      for (size_t k = a; k < e; ++k) {
        if (k + 1 < e && c.accelRatio(k) > 1 + 1e-9) return false;
        if (k + 2 < e && c.jerkRatio(k) > 1 + 1e-9) return false;
      }
      return true;
    };
    double lo = 1e-3, hi = 0;
    for (size_t k = a; k < e; ++k) {
      if (in.length[k] > 0) hi = std::max(hi, in.length[k] / t0[k]);
    }
    if (!(hi > lo) || !feasible(lo)) {
      std::copy(kept.begin(), kept.end(), t.begin() + long(a));
      continue;
    }
    if (feasible(hi)) continue;
    while (hi > lo * (1 + 1e-4)) {
      const double m = std::sqrt(lo * hi);
      (feasible(m) ? lo : hi) = m;
    }
    durations(lo);
  }
}

}  // namespace

FeedResult limitFeeds(const FeedInput& in) {
  FeedResult r;
  const size_t n = in.length.size();
  r.duration.assign(n, 0.0);
  std::vector<double>& t = r.duration;
  for (size_t k = 0; k < n; ++k) {
    double tk = 0;
    if (in.length[k] > 0 && in.speed[k] > 0) tk = in.length[k] / in.speed[k];
    bool moves = in.length[k] > 0;
    double fallback = 0;
    for (int i = 0; i < in.axes; ++i) {
      const double d = std::abs(in.values[k + 1][i] - in.values[k][i]);
      if (d <= kStill) continue;
      moves = true;
      if (in.dynamics[i].velocity > 0) tk = std::max(tk, d / in.dynamics[i].velocity);
      if (in.fallbackVelocity[i] > 0) fallback = std::max(fallback, d / in.fallbackVelocity[i]);
    }
    if (moves && tk <= 0) tk = fallback > 0 ? fallback : 1e-3;
    t[k] = tk;
  }
  const std::vector<double> t0 = t;  // the velocity and requested-speed floor of every move
  Chain c{in, t};
  // Raise durations until acceleration and jerk are within the limits: scaling the durations of
  // the moves a difference spans by s divides a by s^2 and j by s^3. A work list re-checks the
  // neighbours of every scaled window; every scale only slows down, so it converges (to rest in
  // the limit). The cap on the work only guards against pathological inputs.
  bool any = false;
  for (int i = 0; i < in.axes; ++i) {
    any = any || in.dynamics[i].acceleration > 0 || in.dynamics[i].jerk > 0;
  }
  if (any && n >= 2) {
    std::vector<size_t> queue;
    std::vector<char> queued(n, 1);
    queue.reserve(n);
    for (size_t k = n; k-- > 0;) queue.push_back(k);  // popped from the back: k = 0 first
    size_t work = 0;
    const size_t cap = 200 * n + 1000;
    while (!queue.empty() && work++ < cap) {
      const size_t k = queue.back();
      queue.pop_back();
      queued[k] = 0;
      bool scaled = false;
      if (k + 1 < n) {
        const double ra = c.accelRatio(k);
        if (ra > 1 + 1e-9) {
          const double f = std::sqrt(ra) * (1 + kSlack);
          t[k] *= f;
          t[k + 1] *= f;
          scaled = true;
        }
      }
      if (k + 2 < n) {
        const double rj = c.jerkRatio(k);
        if (rj > 1 + 1e-9) {
          const double f = std::cbrt(rj) * (1 + kSlack);
          t[k] *= f;
          t[k + 1] *= f;
          t[k + 2] *= f;
          scaled = true;
        }
      }
      if (scaled) {
        const size_t lo = k >= 3 ? k - 3 : 0, hi = std::min(n - 1, k + 3);
        for (size_t j = hi + 1; j-- > lo;) {
          if (!queued[j]) {
            queued[j] = 1;
            queue.push_back(j);
          }
        }
      }
    }
  }
  if (any && n >= 2) {
    const std::vector<std::pair<size_t, size_t>> chains = movingChains(t0);
    std::vector<size_t> order;
    for (const auto& [a, e] : chains) {
      for (size_t k = a; k < e; ++k) order.push_back(k);
    }
    tighten(c, t0, order);
    // The one-feed start, and the same descent from it on the chains where it starts shorter than
    // the first ended (elsewhere the first already beats every single feed); each chain keeps the
    // shorter of the two (their differences are independent). Measured: tests' smooth motion over
    // uneven moves 184 -> 51 s; the shared kitten (40 mm, geodesic, robot6-ur5) 3.00 -> 2.95 h;
    // descending from it on every chain gained 2 % more there for 40 % more time in this stage.
    std::vector<double> other = t;
    Chain alt{in, other};
    uniformFeedStart(alt, t0, chains);
    auto sum = [](const std::vector<double>& v, size_t a, size_t e) {
      double s = 0;
      for (size_t k = a; k < e; ++k) s += v[k];
      return s;
    };
    std::vector<std::pair<size_t, size_t>> tried;
    order.clear();
    for (const auto& [a, e] : chains) {
      if (!(sum(other, a, e) < sum(t, a, e))) continue;
      tried.emplace_back(a, e);
      for (size_t k = a; k < e; ++k) order.push_back(k);
    }
    tighten(alt, t0, order);
    for (const auto& [a, e] : tried) {
      if (sum(other, a, e) < sum(t, a, e)) std::copy(other.begin() + long(a), other.begin() + long(e), t.begin() + long(a));
    }
  }
  for (size_t k = 0; k + 1 < n; ++k) {
    if (c.accelRatio(k) > 1 + 1e-6 || (k + 2 < n && c.jerkRatio(k) > 1 + 1e-6)) ++r.violations;
  }
  for (size_t k = 0; k < n; ++k) {
    if (in.length[k] > 0 && in.speed[k] > 0 && t[k] > in.length[k] / in.speed[k] * (1 + 1e-9)) {
      ++r.limitedMoves;
    }
  }
  return r;
}

std::array<double, 3> feedLimitRatios(const FeedInput& in, const std::vector<double>& duration) {
  std::vector<double> t = duration;
  Chain c{in, t};
  std::array<double, 3> r{0, 0, 0};
  const size_t n = t.size();
  for (size_t k = 0; k < n; ++k) {
    r[0] = std::max(r[0], c.velocityRatio(k));
    if (k + 1 < n) r[1] = std::max(r[1], c.accelRatio(k));
    if (k + 2 < n) r[2] = std::max(r[2], c.jerkRatio(k));
  }
  return r;
}

}  // namespace omnislice
