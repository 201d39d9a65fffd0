// SPDX-License-Identifier: MIT
// Map a part-frame tool-path through a machine: orientation continuity (paper 001 Section 5.2),
// inverse kinematics, pose continuity (paper 001 Eq. 4, ties broken by paper 003's singularity
// measure), 3+2 safe rotations, subdivision so the interpolated machine motion stays on the
// part-frame path, and feed rates limited by axis / joint velocity, acceleration and jerk
// (paper 003 Eq. 7-9), with the time estimate that follows.
#pragma once
#include "common/progress.h"
#include "motion/machine_path.h"
#include "program/machine.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct MotionOptions {
  int freeRotationSamples = 30;     // robot6: samples of the rotation about the nozzle axis
  bool smoothOrientations = true;   // paper 001 Section 5.2 low-pass filter and crest subdivision
  double filterThresholdDegrees = 10;  // filter where neighbouring axes differ by more than this
  double maxAxisStepDegrees = 2;    // subdivide (quaternion interpolation) so consecutive nozzle
                                    // axes differ by at most this
  double chordTolerance = 0.01;     // mm: the part-frame tip path of an interpolated move may leave
                                    // the straight move by at most this; longer moves are split
  double acceleration = 1500;       // mm/s^2 tip acceleration for the time estimate (0 = none)
  double retractSpeed = 35;         // mm/s of filament, for the time of retract moves
  double safeLift = 10;             // mm above the part's highest machine Z for 3+2 rotations
  double rotationThresholdDegrees = 5;  // a travel whose rotary values change more than this is
                                        // done as a safe rotation (retract, lift, rotate, lower)
};

// Plan the machine motion of a tool-path. Errors (Status, message naming the first bad move):
// InvalidOption for an unknown kind, a non-finite or zero-length axis, or a point no candidate of
// the inverse kinematics reaches within the limits ("move 123 at (x, y, z) axis (...) is out of
// reach of machine 'robot6-ur5'"); Cancelled when progress returns false.
MachinePath planMachineMotion(const Toolpath& toolpath, const MachineProfile& machine,
                              const MotionOptions& options = {}, const ProgressFn& progress = {});

}  // namespace omnislice
