// SPDX-License-Identifier: MIT
// A tool-path mapped through a machine: every move carries the machine values at its end, the
// part-frame tip and axis they realise (forward map), the extrusion and the planned duration after
// the kinematic limits. Writers turn it into text; nothing in it is dialect-specific.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/status.h"
#include "machine/machine.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct MachineMove {
  MachineValues values{};                // machine values at the end (mm, deg; robot: rad)
  Eigen::Vector3d tip{0, 0, 0};          // part-frame tip at the end = forwardMap(values)
  Eigen::Vector3d axis{0, 0, 1};         // part-frame nozzle axis at the end
  double filament = 0;                   // mm of filament fed during the move (<0 retract)
  double durationS = 0;                  // planned duration after all limits, s (> 0 for motion)
  double tipSpeed = 0;                   // planned part-frame tip speed, mm/s (<= requested)
  double width = 0, height = 0;          // bead width and height (layer thickness), mm
  MoveKind kind = MoveKind::Travel;
  Feature feature = Feature::None;
  int32_t part = 0;
  int32_t layer = 0;
  uint32_t source = 0;                   // index of the Toolpath move this piece comes from
};

// Figures of the motion planning, for reports and tests.
struct MotionStats {
  size_t samples = 0;              // tool-path points mapped through the inverse kinematics
  size_t subdivisions = 0;         // extra points added (orientation crests, chord tolerance)
  size_t filteredOrientations = 0; // samples whose nozzle axis the low-pass filter changed
  size_t feedLimitedMoves = 0;     // moves slowed below the requested speed by a kinematic limit
  size_t safeRotations = 0;        // 3+2 rotations done after retract and lift
  double maxJointStep = 0;         // largest change of one angular value between moves (deg or rad)
  double poseCost = 0;             // robot6 / table5: summed L1 change of the angular values
  double greedyPoseCost = 0;       // same for the greedy choice (nearest candidate each step);
                                   // -1 when not computed (robot6 track DP without
                                   // MotionOptions::compareGreedy)
  double posePenalty = 0;          // robot6: singularity penalties on the chosen path (same unit)
  double greedyPosePenalty = 0;    // the same on the greedy path (-1 when not computed); when
                                   // computed, poseCost + posePenalty <= greedyPoseCost +
                                   // greedyPosePenalty
  bool greedyPoseUsed = false;     // robot6 track DP with compareGreedy: greedy was cheaper and
                                   // is the returned choice
  size_t poseIkCalls = 0;          // robot6 track DP: urInverse calls of the pose choice
  size_t poseRestarts = 0;         // robot6 track DP: full evaluations (first sample included)
  size_t poseAliveNodes = 0;       // robot6 track DP: alive nodes summed over the samples
  double minSingularity = 0;       // robot6: smallest singularityMeasure() on the chosen poses
  double estimatedTimeS = 0;       // sum of durations (retractions included) plus the
                                   // acceleration term of G-code kinds
};

struct MachinePath : Outcome {
  MachineProfile machine;
  MachineValues start{};           // values before the first move (park pose)
  std::vector<MachineMove> moves;
  int32_t layerCount = 0;
  MotionStats stats;
};

}  // namespace omnislice
