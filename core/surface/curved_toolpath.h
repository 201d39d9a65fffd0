// SPDX-License-Identifier: MIT
// From curved layers and their surface paths to the part-frame Toolpath every writer consumes:
// printing orientation of paper 001 Section 5.2 (Eq. 3: from the closest point c_q on the layers
// printed before, t_q = q - c_q; the platform normal +Z on the first layer; the region's surface
// normal, flipped to agree, where no earlier layer is near), local bead height from the distance
// to the earlier layers (variable extrusion, paper 002 Eq. 12 / paper 001 Section 6.2.1), and
// travels between regions that retract and leave and approach along the nozzle axis.
// The low-pass filter and crest subdivision of Section 5.2 happen in core/motion (planMachineMotion).
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "surface/fermat_spiral.h"
#include "surface/surface_layers.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct CurvedToolpathOptions {
  double lineWidth = 0.45;          // bead width, mm
  double nominalHeight = 0.32;      // bead height where no earlier layer is measured, mm
  double minHeightFactor = 0.5;     // local height clamped to [min, max] x nominalHeight
  double maxHeightFactor = 1.75;
  double filamentDiameter = 1.75;   // mm
  double printSpeed = 30;           // mm/s
  double firstLayerSpeed = 20;      // mm/s (layer 0)
  double travelSpeed = 100;         // mm/s
  double retractLength = 0.8;       // mm of filament, 0 = off
  double retractSpeed = 35;         // mm/s of filament
  double retractMinTravel = 1.5;    // mm, shorter travels do not retract
  double travelClearance = 2.0;     // mm, leave/approach distance along the nozzle axis
  int earlierLayers = 3;            // layers below searched for c_q (Eq. 3)
  double maxTiltDegrees = 180;      // axes leaning from +Z by more are turned toward +Z onto this
                                    // cone (a table's tilt range); 180 = no limit
  // The axis field's motion term (motion/axis_freedom.h): each path's axes may lean up to this
  // far from their ideal (Eq. 3 or the normal) to keep the machine's rotary axes still; 0 = the
  // ideal axes (paper 001 as written). The gouging correction starts from the chosen axes.
  double axisFreedomDegrees = 0;
  bool axisFromNormals = false;     // true: the nozzle axis is the path's surface normal at every
                                    // point (paper 003: "aligned with the surface normal"; the
                                    // paths' normals must point to the nozzle side), on every
                                    // layer; bead heights are still measured as below
  bool ellipseBeads = false;        // true: filament per segment by paper 003 Eq. 13, the bead an
                                    // ellipse of width lineWidth and height h (area pi w h / 4);
                                    // false: filamentForBead (rectangle with round ends)
  // Gouging correction (paper 001 Section 6.2.3): the nozzle is a cone with its apex at the tip,
  // opening along the axis. A path point collides when a point printed earlier (every <= 0.5 mm
  // of the print moves before it, in print order) lies strictly inside that cone: (p - s).u >
  // collisionClearance, angle(p - s, u) < coneHalfAngleDegrees, |p - s| < coneLength (the rule of
  // `omnislice verify`). Colliding axes are turned to the nearest collision-free axis within the
  // maxTiltDegrees cone and the change is tapered over the path's neighbours. Where the search's
  // wider cone (below) finds no free axis, one free under verify's half-angle is taken. Then the
  // axes are checked as the program moves them (the planner's low-pass filter, the turn of each
  // move on the way, under verify's half-angle with the points as balls of half the sample
  // spacing): a move whose turn sweeps the cone through material gets an end axis, within 30
  // degrees, from and to which both its moves turn freely (the first move's travel arrives with
  // it); turns left colliding count in gougingUncorrected.
  bool correctGouging = true;
  double coneHalfAngleDegrees = 40;  // degrees, in (0, 90)
  double coneLength = 25;            // mm, > 0
  double collisionClearance = 0;     // mm along the axis ignored above the tip; 0 = nominalHeight
  double gougingMarginDegrees = 3;   // the search uses a cone wider by this and points blown up
                                     // to balls of half the sample spacing (safety for the later
                                     // low-pass filter and interpolation), degrees
  double maxCorrectionDegrees = 60;  // largest turn from the Eq. 3 axis searched, degrees
  double correctionTaperDegrees = 4; // neighbours take the correction less this per point, degrees
  // The motion planner's orientation filter as the checks simulate it (motion.filter_deg; 180 =
  // the planner does not filter, motion.smooth_orientations off), degrees.
  double filterThresholdDegrees = 10;
  // true: a segment whose motion (as above: filter, turns, verify's half-angle) is left colliding
  // after the correction is not printed (the nozzle travels over it; the material is missing and
  // counted in skippedPoints / skippedMm), so the program never drives the nozzle into the part. Where two growth fronts meet (a closed
  // loop of the part, the cut locus of a geodesic field) the last gap faces the nozzle from both
  // sides and no axis within the cone and tilt limits is free.
  bool skipUncorrectable = false;
  // true: where points of a path have no free axis only because of the path's own earlier points,
  // the runs of those segments are printed first and the rest after them, when that leaves fewer
  // points colliding (CurvedToolpathResult::reorderedPaths).
  bool reorderSelfBlocked = true;
  // skipUncorrectable with axisFreedomDegrees > 0: a path that leaves segments out is oriented
  // again with no freedom at their ends (their ideal axes there; the freedom ramps back around
  // them and the axis then relaxes to the least tilted one), up to two rounds; the orientation
  // that leaves the least out is printed (CurvedToolpathResult::nearIdealPaths).
  bool retryLeftOutNearIdeal = true;
};

struct CurvedToolpathResult : Outcome {
  Toolpath toolpath;                // Move.layer = layer index, Feature::Infill for part regions
                                    // (Feature::Support for support regions), axis per move
  size_t orientationFallbacks = 0;  // samples that used the surface normal instead of Eq. 3
  size_t tiltClamped = 0;           // samples whose axis was turned onto the maxTiltDegrees cone
  size_t axesFreed = 0;             // samples whose axis leans from its ideal for motion
  size_t gougingCorrections = 0;    // path points whose axis was turned to avoid earlier material
  size_t gougingUncorrected = 0;    // path points left colliding (no free axis within the limits)
  size_t reorderedPaths = 0;        // paths printed with their self-blocked runs first
  size_t nearIdealPaths = 0;        // paths printed with their ideal axes where others left path out
  size_t skippedPoints = 0;         // skipUncorrectable: segments left out
  double skippedMm = 0;             // their length, mm
  std::vector<Eigen::Vector3d> skippedEnds;  // start and end of each segment left out (2 per segment)
  std::vector<int32_t> skippedLayers;        // the layer of each segment left out
  double orientationMs = 0;
  double gougingMs = 0;
};

// paths[l][r]: the paths of region r of layer l (same shape as layers). Progress stage "toolpath".
// Per layer in order, regions nearest-first from the previous end point (distance to the start of
// the region's first path), paths in the given order; each path: a travel to its start, then one
// Print move per segment (MoveKind::Support with Feature::Support for support regions; the
// move's curve = the path's curves[i] for the segment ending at point i, when given).
// Orientation per point (Eq. 3): axis = normalize(q - c_q), c_q the closest point on the regions
// of the previous earlierLayers layers or on the platform plane z = 0 (T is printed before every
// layer); +Z on layer 0. Partial layers (CurvedLayer::partial) count for the bead height but
// not for the axis, which then comes from the closest point on the full layers (or the
// platform). Where |q - c_q| < 0.1 nominalHeight or q - c_q is more than 80 degrees from
// the path normal (flipped to the side of q - c_q, or of the previous point's axis, +Z for the
// first, when q - c_q is that short), the normal is used and counted in
// orientationFallbacks. Bead height per point = |q - c_q| clamped to [min, max] x nominalHeight
// (nominalHeight on layer 0); a segment takes the mean of its end heights, and its filament is
// filamentForBead (toolpath/bead.h: rectangle with semicircular ends, as the planar planner).
// Travels longer than retractMinTravel after the first extrusion: Retract at the current point,
// leave by travelClearance along the current axis, cross to start + clearance x axis, approach,
// Unretract; shorter travels are one Travel move. toolpath.start = first start + clearance x axis.
// Statuses: InvalidOption (options out of range, paths not shaped like layers), NonFiniteVertex,
// Cancelled.
CurvedToolpathResult buildCurvedToolpath(const std::vector<CurvedLayer>& layers,
                                         const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                                         const CurvedToolpathOptions& options,
                                         const ProgressFn& progress = {});

// The same in a given print order: order[k] = (layer, region), visited in sequence (a region
// may be left out; a region listed twice is printed twice). Used by the geodesic method, whose
// print sequence (paper 002 Section 3.1) interleaves layers across branches. Earlier layers for
// Eq. 3 and the bead heights are still the layer indices below (geometry, not print order).
// InvalidOption also when an order entry names a region that does not exist.
CurvedToolpathResult buildCurvedToolpath(const std::vector<CurvedLayer>& layers,
                                         const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                                         const std::vector<std::pair<uint32_t, uint32_t>>& order,
                                         const CurvedToolpathOptions& options,
                                         const ProgressFn& progress = {});

}  // namespace omnislice
