// SPDX-License-Identifier: MIT
// Print time as a firmware's look-ahead planner runs a sequence of straight moves (Grbl, Marlin
// and Klipper plan this way): each move cruises at its feed and accelerates and decelerates at
// `acceleration` along its path; consecutive moves join without stopping at the junction speed
// the junction deviation allows for the angle between them, v^2 = a jd sin(t/2) / (1 - sin(t/2))
// with t the angle between the reversed incoming and the outgoing direction (a straight
// continuation has no limit, a reversal stops); each junction speed is also at most either
// move's cruise. A backward pass then keeps every speed reachable by braking before the next
// stop, a forward pass by accelerating from the last one, and each move takes the trapezoid (or
// triangle) between its entry and exit speeds. A move without length (retract, unretract, dwell)
// is a stop: the planner arrives at rest before it and leaves from rest after it.
#pragma once
#include <Eigen/Core>

#include <vector>

namespace omnislice {

struct PlannedMove {
  Eigen::Vector3d direction{0, 0, 0};  // unit direction of the path, mm (ignored without length)
  double length = 0;                   // mm; 0 = a stop
  double speed = 0;                    // cruise, mm/s (> 0 for a move with length)
};

struct LookaheadOptions {
  double acceleration = 1500;       // mm/s^2; 0 = no ramps (every move at its cruise)
  double junctionDeviation = 0.013; // mm; 0 = a full stop at every junction
};

// Total time (s) of the moves; with `durations`, each move's time too (0 for a stop).
double lookaheadTime(const std::vector<PlannedMove>& moves, const LookaheadOptions& options,
                     std::vector<double>* durations = nullptr);

}  // namespace omnislice
