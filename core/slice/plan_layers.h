// SPDX-License-Identifier: MIT
// Planar tool-paths from sliced layers: walls, solid top/bottom skins, sparse infill, travel
// ordering and retraction, extrusion from the bead cross-section. For d = +Z a complete 3-axis
// slicer.
#pragma once
#include <optional>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "slice/slice_mesh.h"
#include "toolpath/toolpath.h"

namespace omnislice {

enum class InfillPattern { Lines, Grid };

// Where each wall loop starts and ends (the seam, the one mark a closed loop leaves):
//   Aligned: in a corner near the seam of the layer below, so the seams of a part line up in one
//            seam line that follows its edges (the first layer: the sharpest corner, else the
//            rear, +e2 of the layer frame, +Y for d = +Z), as PrusaSlicer's default "aligned";
//   Nearest: the loop's vertex nearest the nozzle (the shortest travel);
//   Sharpest: the loop's sharpest corner, concave (hidden inside the corner) before convex, ties
//            to the one nearest the seam below, as Cura's "sharpest corner";
//   Random: a vertex chosen at random (spreads the seam's bumps), the same on every run.
enum class SeamPlacement { Aligned, Nearest, Sharpest, Random };

// What planLayers lays in each layer and how fast: the planar tool-path's options (every field
// defaulted; the pipeline fills them from the settings).
struct PlanarOptions {
  double lineWidth = 0.45;           // mm, > 0 (the resolved line width)
  double filamentDiameter = 1.75;    // mm, > 0
  int walls = 2;                     // perimeters per island, 0..1000
  int topLayers = 4;                 // solid layers under a top surface, 0..1000
  int bottomLayers = 4;              // solid layers over a bottom surface, 0..1000
  double infillPercent = 20;         // sparse infill density, 0..100 (100 = solid)
  InfillPattern infillPattern = InfillPattern::Grid;
  double infillAngleDegrees = 45;    // angle of infill lines in the layer plane, degrees
  SeamPlacement seam = SeamPlacement::Aligned;  // where wall loops start
  double infillOverlapPercent = 15;  // infill overlap into the innermost wall, % of line width
  bool allLinesAlongInfillAngle = false;  // every skin and infill line along infillAngleDegrees
                                          // (paper 003's iso-planar direction on planar layers)
  double printSpeed = 50;            // mm/s, inner walls, skin
  double outerWallSpeed = 30;        // mm/s
  double infillSpeed = 70;           // mm/s
  double firstLayerSpeed = 20;       // mm/s, every feature of layer 0
  double travelSpeed = 150;          // mm/s
  double retractLength = 0.8;        // mm of filament, 0 = off
  double retractSpeed = 35;          // mm/s of filament
  double retractMinTravel = 1.5;     // mm, shorter travels do not retract
  // Travel inside the part: within an island, travels keep to its section (going round holes and
  // notches along the outline, a quarter line inside it) and retract only when that route is
  // longer than retractInsideMaxTravel; travels between islands go straight and retract over
  // retractMinTravel. false: every travel straight.
  bool travelInside = true;
  double retractInsideMaxTravel = 10;  // mm, >= 0
  // Bridges: skin over air (not on the layer below) whose lines can land on the layer below at
  // both ends is printed as Feature::Bridge lines across the span (the direction that anchors the
  // most line length at both ends, at least half), spaced one line, at bridgeSpeed with
  // bridgeFlowPercent of a bead's filament, extended 2 lines onto the anchors. Skin over air
  // anchored on one side only (a cantilever) stays skin. false: no bridges.
  bool bridges = true;
  double bridgeSpeed = 20;           // mm/s, > 0
  double bridgeFlowPercent = 80;     // % of the bead's filament, (0, 200]
  // Gap fill: where an island narrows so that the next wall level cannot reach the area inside a
  // wall's band (a rib 2.5 lines wide: two walls' beads and a strip between them), that strip,
  // when at least 0.3 lines wide, is filled with lines spaced like skin across its long axis
  // (Feature::Skin, printed after the walls). An inner level narrower than 0.6 bead spacings (its
  // loop would double back on itself) is left out for it. false: no gap fill (the inner levels
  // are left out all the same).
  bool gapFill = true;
};

struct PlanLayersResult : Outcome {
  Toolpath toolpath;
  // Per-layer region breakdown (for reports and tests).
  std::vector<double> skinAreaMm2;    // solid-skin area per layer
  std::vector<double> infillAreaMm2;  // sparse-infill area per layer
  std::vector<double> bridgeAreaMm2;  // bridged area per layer (extended onto the anchors)
  size_t bridges = 0;                 // bridge regions printed
  double gapAreaMm2 = 0;              // area filled by gap fill, over all layers
  // Islands too narrow for any wall or fill (every offset by half a line width or more is empty):
  // they get no path. Their area, the area of every island, and the first and last such layer.
  double thinAreaMm2 = 0, sectionAreaMm2 = 0;
  size_t thinIslands = 0;
  int thinFirstLayer = -1, thinLastLayer = -1;
};

// Plan tool-paths for every layer of `slices` with options (walls, topLayers, bottomLayers,
// infillPercent, infillPattern, infillAngleDegrees, speeds, retraction, line width, filament).
// Moves are in the part frame; nozzle axis = slices.frame.d; part id = partIndex.
// Per island: walls inner to outer (outer wall last), each loop starting at its seam (options.seam);
// then skin lines (spacing w, +45/-45 deg by layer), then sparse infill, lines nearest-first
// with either end allowed. Islands nearest-first. The nozzle tip sits at each layer's top; z changes
// only in travel moves; travels longer than retractMinTravel are wrapped in Retract/Unretract
// (none before the first extrusion). toolpath.start is 2 mm above the first point along d.
// Statuses: InvalidOption (options out of range, slices carrying an error), Cancelled, Internal.
// supportRegions (optional, per layer of slices, in the layer plane's coordinates): support to
// print in that layer before the part's islands, filled solid with lines at the solid spacing
// (0 / 90 deg by layer), MoveKind::Support, Feature::Support.
PlanLayersResult planLayers(const SliceResult& slices, const PlanarOptions& options, int partIndex = 0,
                            const ProgressFn& progress = {},
                            const std::vector<std::vector<ExPolygon2>>* supportRegions = nullptr);

// The warning `thin_sections` when the islands too narrow for any path (PlanLayersResult::
// thinAreaMm2, summed over the parts planned) hold at least 1 mm^2 and 0.5 % of the section area:
// a part of the model thinner than a line is not printed (a dome's last sliver is not worth
// saying). What would: a larger part, a smaller nozzle and line width.
std::optional<Warning> thinSectionsWarning(double thinAreaMm2, double sectionAreaMm2, size_t thinIslands,
                                           double lineWidthMm);

}  // namespace omnislice
