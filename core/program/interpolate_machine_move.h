// SPDX-License-Identifier: MIT
// The part-frame tip path of one machine move (PROGRAM-FORMAT.md: between two consecutive targets
// every axis or joint value changes linearly), cut into pieces whose chords stay within a
// tolerance of that path. Shared by the writers (path length for the robot feed f) and the reader
// (replayed pieces), so both see the same path.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "common/status.h"
#include "machine/machine.h"

namespace omnislice {

struct InterpolateOptions {
  double chordTolerance = 0.01;   // mm: largest distance of the tip path from a piece's chord
  double maxAxisStepDegrees = 2;  // largest change of the part-frame nozzle axis within a piece
  size_t maxPieces = 1 << 16;     // safety cap per move (absurd rotations of broken input); when
                                  // reached, pieces may exceed the tolerances
};

struct MoveInterpolation : Outcome {
  std::vector<double> t;                 // parameters 0 = t[0] < ... < t.back() = 1
  std::vector<Eigen::Vector3d> tips;     // part-frame tip at each parameter
  std::vector<Eigen::Vector3d> axes;     // part-frame nozzle axis at each parameter
  double length = 0;                     // sum of the chords (part-frame path length), mm
};

// Machine values at parameter s of the move from a to b (linear in every value).
MachineValues lerpValues(const MachineValues& a, const MachineValues& b, double s);

// Pieces of the move a -> b on `machine`: two points when no angular value changes (the tip path is
// then straight), more otherwise (bisection until the tip path at the quarter, middle and three
// quarter points of every piece is within chordTolerance of its chord and the nozzle axis turns by
// at most maxAxisStepDegrees). InvalidOption for an unknown kind or values the forward map
// cannot take (non-finite results).
MoveInterpolation interpolateMachineMove(const MachineProfile& machine, const MachineValues& a,
                                         const MachineValues& b,
                                         const InterpolateOptions& options = {});

// interpolateMachineMove(machine, a, b, options).length (the same pieces, summed in the same
// order) without storing the pieces, from the end points' forward maps already known (tipA, axisA
// = forwardMap of a; tipB, axisB of b). -1 where interpolateMachineMove fails. For writers: no
// allocation, two forward maps fewer per move.
double interpolatedTipLength(const MachineProfile& machine, const MachineValues& a,
                             const MachineValues& b, const Eigen::Vector3d& tipA,
                             const Eigen::Vector3d& axisA, const Eigen::Vector3d& tipB,
                             const Eigen::Vector3d& axisB, const InterpolateOptions& options = {});

}  // namespace omnislice
