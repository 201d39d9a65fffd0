// SPDX-License-Identifier: MIT
// Feed rates limited by the axis / joint velocity, acceleration and jerk (paper 003 Eq. 7-9).
// The paper differentiates the values over equally spaced samples with the feed f and the chord
// l: V = f dQ / l, A = f^2 (Q0 - 2Q + Q1) / l^2, J = f^3 (...) / l^3. With unequal moves the same
// finite differences are taken in time (they reduce to the paper's at equal spacing):
//   v_k = (Q_k+1 - Q_k) / T_k                            (velocity over move k)
//   a_k = (v_k+1 - v_k) / ((T_k + T_k+1) / 2)             (at the junction of moves k, k+1)
//   j_k = (a_k+1 - a_k) / ((T_k + 2 T_k+1 + T_k+2) / 4)   (time between the two a samples)
// and the durations T are raised until every |v|, |a|, |j| is within its limit: the feed at a
// sample is the smallest of the three limits (Eq. 9).
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "machine/machine.h"

namespace omnislice {

struct FeedInput {
  int axes = 3;                           // number of values used
  std::vector<MachineValues> values;      // values[0] = start, values[k + 1] = end of move k
  std::vector<double> length;             // part-frame tip path length of move k, mm
  std::vector<double> speed;              // requested tip speed of move k, mm/s (0 = none)
  std::array<AxisDynamics, 6> dynamics{}; // per value; 0 = unlimited
  std::array<double, 6> fallbackVelocity{};  // per value: used only when a move changes values
                                             // but neither its length/speed nor a velocity limit
                                             // gives it a duration
};

struct FeedResult {
  std::vector<double> duration;  // s per move (0 when nothing moves)
  size_t limitedMoves = 0;       // moves slower than length / speed
  size_t violations = 0;         // junctions still over a limit after the iteration cap (0 normally)
};

// Durations of the moves under the limits. Consecutive moves with positive durations form a
// chain over which acceleration and jerk are checked; a zero-duration move (retract) breaks it.
FeedResult limitFeeds(const FeedInput& input);

// The finite differences above, for checks: largest ratio |v| / vmax, |a| / amax, |j| / jmax over
// the chain (0 when unlimited). Used by the tests and to count violations.
std::array<double, 3> feedLimitRatios(const FeedInput& input, const std::vector<double>& duration);

}  // namespace omnislice
