// SPDX-License-Identifier: MIT
// Planar tool-paths from sliced layers: walls, solid top/bottom skins, sparse infill, travel
// ordering and retraction, extrusion from the bead cross-section. For d = +Z a complete 3-axis
// slicer.
#pragma once
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "pipeline/settings.h"
#include "slice/slice_mesh.h"
#include "toolpath/toolpath.h"

namespace omnislice {

// Filament length (mm) that deposits a bead of width w, height h over length L: bead area is a
// rectangle with semicircular ends, (w - h) h + pi h^2 / 4, divided by the filament section; a
// bead narrower than its height (w < h) has its round ends top and bottom: (h - w) w + pi w^2 / 4.
double filamentForBead(double widthMm, double heightMm, double lengthMm, double filamentDiameterMm);

// Paper 003 Eq. 13: the bead an ellipse of width w and height h, (pi / 4) w h L = pi r_m^2 l_m.
double ellipseBeadFilament(double widthMm, double heightMm, double lengthMm, double filamentDiameterMm);

struct PlanLayersResult : Outcome {
  Toolpath toolpath;
  // Per-layer region breakdown (for reports and tests).
  std::vector<double> skinAreaMm2;    // solid-skin area per layer
  std::vector<double> infillAreaMm2;  // sparse-infill area per layer
};

// Plan tool-paths for every layer of `slices` with settings (walls, topLayers, bottomLayers,
// infillPercent, infillPattern, infillAngleDegrees, speeds, retraction, line width, filament).
// Moves are in the part frame; nozzle axis = slices.frame.d; part id = partIndex.
// Per island: walls inner to outer (outer wall last), each loop starting at its vertex nearest the
// nozzle; then skin lines (spacing w, +45/-45 deg by layer), then sparse infill, lines nearest-first
// with either end allowed. Islands nearest-first. The nozzle tip sits at each layer's top; z changes
// only in travel moves; travels longer than retractMinTravel are wrapped in Retract/Unretract
// (none before the first extrusion). toolpath.start is 2 mm above the first point along d.
// Statuses: InvalidOption (settings out of range, slices carrying an error), Cancelled, Internal.
// supportRegions (optional, per layer of slices, in the layer plane's coordinates): support to
// print in that layer before the part's islands, filled solid with lines at the solid spacing
// (0 / 90 deg by layer), MoveKind::Support, Feature::Support.
PlanLayersResult planLayers(const SliceResult& slices, const Settings& settings, int partIndex = 0,
                            const ProgressFn& progress = {},
                            const std::vector<std::vector<ExPolygon2>>* supportRegions = nullptr);

}  // namespace omnislice
