// SPDX-License-Identifier: MIT
// Map a part-frame tool-path through a machine: orientation continuity (paper 001 Section 5.2),
// inverse kinematics, pose continuity (paper 001 Eq. 4, ties broken by paper 003's singularity
// measure), 3+2 safe rotations, subdivision so the interpolated machine motion stays on the
// part-frame path, and feed rates limited by axis / joint velocity, acceleration and jerk
// (paper 003 Eq. 7-9), with the time estimate that follows.
#pragma once
#include <Eigen/Core>

#include "common/progress.h"
#include "motion/machine_path.h"
#include "machine/machine.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct MotionOptions {
  int freeRotationSamples = 30;     // robot6: samples of the rotation about the nozzle axis
  bool smoothOrientations = true;   // paper 001 Section 5.2 low-pass filter (turns are subdivided either way)
  double filterThresholdDegrees = 10;  // filter where neighbouring axes differ by more than this
  double maxAxisStepDegrees = 2;    // subdivide (quaternion interpolation) so consecutive nozzle
                                    // axes differ by at most this
  double chordTolerance = 0.01;     // mm: the part-frame tip path of an interpolated move may leave
                                    // the straight move by at most this; longer moves are split
  double acceleration = 1500;       // mm/s^2 tip acceleration for the time estimate (0 = none)
  double junctionDeviation = 0.013; // mm, the look-ahead's junction speeds in the time estimate
                                    // (lookahead_time.h; 0 = every move from and to rest)
  double retractSpeed = 35;         // mm/s of filament, for the time of retract moves
  double safeLift = 10;             // mm above the part's highest machine Z for 3+2 rotations
  double rotationThresholdDegrees = 5;  // a travel whose rotary values change more than this is
                                        // done as a safe rotation (retract, lift, rotate, lower)
  double safeClearance = 2;         // mm: a safe rotation within a part (curved layers) lifts the
                                    // nozzle only this far above the highest point the material
                                    // printed so far reaches while the platform turns
                                    // (MaterialHeight), not to the part's top + safeLift
  double safeRetract = 1.0;         // mm of filament retracted for a safe rotation when the
                                    // tool-path has not just retracted (unretracted after lowering)
  double singularityThreshold = 0.02;  // robot6: poses with singularityMeasure() below this pay
                                       // a penalty in the pose choice
  double singularityPenalty = 0.1;  // robot6: penalty (rad of L1 joint change) at measure 0,
                                    // falling linearly to 0 at singularityThreshold
  bool trackPoses = true;           // robot6: pose choice by the track DP with lazy inverse
                                    // kinematics (track_poses.h, ~3 us per sample natively);
                                    // false = choosePoses() on all candidates (pose_continuity.h)
  double trackSlack = 0.3;          // rad, track DP: nodes costlier than the sample's best by
                                    // more than this are dropped
  int trackMaxAlive = 4;            // track DP: at most this many alive nodes per sample (the
                                    // cheapest; 0 = no cap)
  double trackRestartStep = 0.5;    // rad, track DP: evaluate every candidate (branch changes
                                    // allowed) when the best successor's L1 joint step exceeds
                                    // this (0 = only when no successor is feasible)
  bool compareGreedy = false;       // track DP: also compute the greedy choice on all candidates
                                    // (as slow as choosePoses' inverse kinematics) and return it
                                    // when cheaper; false: stats.greedyPoseCost / Penalty = -1
  int maxKeptPoses = 0;             // choosePoses() (table5, rotary4, robot6 without
                                    // trackPoses): 0 = exact shortest path (robot6: ~0.8 ms per
                                    // sample natively); else at most this many non-dominated
                                    // candidates per sample are kept (plus the greedy one, so the
                                    // result is never worse than greedy; 16: ~0.1 ms per sample)
  double poseSlack = 0.05;          // rad, robot6 choosePoses() with maxKeptPoses > 0: a
                                    // candidate within this of being dominated is dropped to make
                                    // room for distinct ones
  double armClearance = 10;         // mm, robot6: arm frame origins must stay this far above the
                                    // base plane (z = 0) and outside the extruder cylinder
};

// Plan the machine motion of a tool-path. Steps: (1) low-pass filter of the axes of printing
// samples that differ from a neighbour by more than filterThresholdDegrees, then subdivision
// (slerp of the axis, linear positions, filament split in equal shares) so consecutive axes
// differ by at most maxAxisStepDegrees (printing moves; every move for robot6); rotary4 with a
// step angle keeps its axes. (2) inverse kinematics of every sample, (3) pose choice by shortest
// path (pose_continuity.h; robot6: the track DP of track_poses.h, which runs the inverse
// kinematics lazily itself), unwrapped within the limits; robot6 candidates whose arm frame
// origins enter the extruder cylinder or go below the base plane are excluded. (4) G-code
// kinds: travels whose rotary values change by more than rotationThresholdDegrees become
// retract, lift to safe Z, rotate, move over, lower, unretract. Between parts (3+2) safe Z is
// machine.safeZ, else the part's highest machine Z + safeLift; within a part, without a declared
// machine.safeZ, it is the highest machine Z the material printed so far reaches during the turn
// (bead included) + safeClearance, as long as the nozzle axis stays within 90 deg - the cone's
// half-angle of the platform's normal (a platform tilted less than that cannot rise into a nozzle
// above it); beyond, the part's top + safeLift again. (5) moves split at part-frame
// midpoints until the tip of the interpolated machine motion stays within chordTolerance.
// (6) durations under the velocity / acceleration / jerk limits (feed_limits.h; robot6 joints
// and rotary axes take all three, the linear axes X Y Z only their velocity because firmware
// plans their junctions and ramps itself); the time
// estimate of the G-code kinds ramps the tip as firmware plans it (lookahead_time.h: trapezoids
// at `acceleration`, junction speeds from `junctionDeviation`, a stop at every move without tip
// motion), and adds retract time |filament| / speed (the move's speed, else retractSpeed).
// Errors (Status, message naming the first bad move):
// InvalidOption for an unknown kind, a non-finite or zero-length axis, or a point no candidate of
// the inverse kinematics reaches within the limits ("move 123 at (x, y, z) axis (...) is out of
// reach of machine 'robot6-ur5'"); Cancelled when progress returns false.
MachinePath planMachineMotion(const Toolpath& toolpath, const MachineProfile& machine,
                              const MotionOptions& options = {}, const ProgressFn& progress = {});

// Paper 003 Eq. (5) (singularityMeasure() in robot_arm.h) from the eigenvalues of J^T J instead
// of an SVD: the same value up to rounding, several times faster (used inside the pose choice).
double fastSingularityMeasure(const Eigen::Matrix<double, 6, 6>& jacobian);

}  // namespace omnislice
