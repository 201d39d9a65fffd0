// SPDX-License-Identifier: MIT
// The last resort of repair = auto: a closed surface rebuilt from inside/outside samples of a
// triangle soup that the face-by-face repair (mesh/repair_mesh.h) could not close.
#pragma once
#include <cstddef>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct RebuildOptions {
  int cells = 160;               // grid cells along the longest side of the box (>= 8)
  // The soup bounds a solid only when the three ray directions agree on most samples: samples
  // where they disagree (rays through holes or along sheets), over the samples judged inside, at
  // most this (measured: a sphere with five holes 1 mm across 0.04, a bowl 0.14) ...
  double maxDisagreement = 0.25;
  // ... and when little of the rebuilt surface is invented: net vertices none of whose edges has
  // a crossing of the soup on its line (they close openings: a hole's patch, a bowl's lid), over
  // all net vertices, at most this.
  double maxInventedShare = 0.1;
};

struct RebuildResult : Outcome {
  Mesh mesh;                  // the rebuilt surface (quads split in two), empty when not accepted
  bool accepted = false;      // the samples bound a solid (see RebuildOptions), mesh is set
  double pitchMm = 0;         // grid pitch
  size_t insideSamples = 0;
  size_t disagreeing = 0;     // samples where the three directions' parities disagree
  size_t touchedSamples = 0;  // samples inside by at least one direction
  size_t netVertices = 0;
  size_t inventedVertices = 0;  // net vertices placed where no face of the soup crosses its edges
  bool touchesBorder = false; // a sample judged inside lies on the grid's outer layer (unbounded)
  bool winding = false;       // the winding rule decided (else parity), see rebuildSolid
};

// Inside/outside by rays, as Nooruddin and Turk's volumetric repair (2003) does: along lines
// parallel to x, y and z through the points of a regular grid (pitch = longest side / cells,
// offset off round coordinates), a point is inside for a direction when an odd number of the
// soup's triangles cross the line before it (parity), or when the entries minus the exits before
// it are not zero (winding); inside overall when at least two directions say so. Parity needs no
// orientation, and faces present twice (inner walls of a cell-by-cell export, in any
// triangulation) cancel; winding also fills where bodies overlap (parity would empty them) but
// needs consistent orientation. The rule whose directions disagree on fewer points is used
// (winding on a tie). The surface between inside and outside samples is a naive
// surface net: one vertex per grid cell that changes sign, at the mean of the exact crossings on
// its sign-changing edges (the crossing of the edge's own line nearest the edge's middle, or the
// middle when that line has none), one quad per sign-changing edge, oriented outward. Sharp edges
// are rounded within a cell; where two inside samples meet only diagonally the net can be
// non-manifold, which repairSolid splits. Not accepted (accepted = false, Ok, mesh empty) when the
// samples disagree too much, too much of the net is invented, or an inside sample lies on the
// grid border. Progress stage "repair" over
// [from, to]; false gives Cancelled. Errors: EmptyInput, Cancelled.
RebuildResult rebuildSolid(const Mesh& soup, const RebuildOptions& options = {},
                           const ProgressFn& progress = {}, double from = 0, double to = 1);

}  // namespace omnislice
