// SPDX-License-Identifier: MIT
#include "toolpath/lookahead_time.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace omnislice {
namespace {

// Time of a move of length L from entry speed vi to exit speed vo, cruising at vc, accelerating
// at a (vi, vo <= vc, and the move long enough to go from vi to vo: the passes ensure it).
double trapezoid(double L, double vi, double vo, double vc, double a) {
  const double up = (vc * vc - vi * vi) / (2 * a), down = (vc * vc - vo * vo) / (2 * a);
  if (up + down <= L) return (vc - vi) / a + (vc - vo) / a + (L - up - down) / vc;
  // No cruise: the peak speed where the ramps meet.
  const double peak = std::sqrt(std::max(0.0, a * L + 0.5 * (vi * vi + vo * vo)));
  return std::max(0.0, (peak - vi) / a) + std::max(0.0, (peak - vo) / a);
}

}  // namespace

double lookaheadTime(const std::vector<PlannedMove>& moves, const LookaheadOptions& options,
                     std::vector<double>* durations) {
  const size_t n = moves.size();
  if (durations) durations->assign(n, 0.0);
  const double a = options.acceleration;
  auto moving = [&](size_t k) { return moves[k].length > 0 && moves[k].speed > 0; };
  if (!(a > 0)) {
    double total = 0;
    for (size_t k = 0; k < n; ++k) {
      if (!moving(k)) continue;
      const double t = moves[k].length / moves[k].speed;
      total += t;
      if (durations) (*durations)[k] = t;
    }
    return total;
  }
  // entry[k]: the speed at the start of move k (the junction with move k - 1); exit = entry of
  // the next moving move, 0 before a stop and at the end.
  std::vector<double> entry(n + 1, 0.0);
  const double jd = std::max(0.0, options.junctionDeviation);
  for (size_t k = 1; k < n; ++k) {
    if (!moving(k) || !moving(k - 1)) continue;
    const double cosTheta = -moves[k - 1].direction.dot(moves[k].direction);
    double limit = std::min(moves[k - 1].speed, moves[k].speed);
    if (cosTheta > 0.999999 || jd <= 0) {
      limit = 0;  // a reversal, or no junction deviation: stop
    } else if (cosTheta > -0.999999) {
      const double sinHalf = std::sqrt(0.5 * (1 - cosTheta));
      limit = std::min(limit, std::sqrt(a * jd * sinHalf / (1 - sinHalf)));
    }
    entry[k] = limit;
  }
  // Backward: brake in time for the next junction; forward: accelerate from the last one.
  for (size_t k = n; k-- > 0;) {
    if (!moving(k)) continue;
    entry[k] = std::min(entry[k], std::sqrt(entry[k + 1] * entry[k + 1] + 2 * a * moves[k].length));
  }
  for (size_t k = 0; k < n; ++k) {
    if (!moving(k)) continue;
    entry[k + 1] = std::min(entry[k + 1], std::sqrt(entry[k] * entry[k] + 2 * a * moves[k].length));
  }
  double total = 0;
  for (size_t k = 0; k < n; ++k) {
    if (!moving(k)) continue;
    const double exit = k + 1 < n && moving(k + 1) ? entry[k + 1] : 0.0;
    const double t = trapezoid(moves[k].length, entry[k], exit, moves[k].speed, a);
    total += t;
    if (durations) (*durations)[k] = t;
  }
  return total;
}

}  // namespace omnislice
