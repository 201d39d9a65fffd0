// SPDX-License-Identifier: MIT
// What the curved-layer methods (voxel, geodesic, surface) share (internal to core/pipeline): the
// fill of every layer region, the tool-path options taken from the settings and the machine, the
// printed layer count and the preview's layer surfaces.
#pragma once
#include <optional>
#include <vector>

#include "common/progress.h"
#include "machine/machine.h"
#include "pipeline/preview.h"
#include "pipeline/report.h"
#include "pipeline/settings.h"
#include "surface/curved_toolpath.h"
#include "surface/fermat_spiral.h"

namespace omnislice::stage {

// Every region of every layer filled (paths[l][r] in the layers' shape): Fermat spirals at the
// line width (paper 001 Section 5.1, paper 002 Section 3.2; a region too narrow for one gets no
// path and counts as unfilled), or with fill = isoplanar the iso-planar paths of paper 003 (one
// theta* per region, beads of the nozzle width and isoLayerHeight). Progress: `stage` at
// progressScale (l + 1) / layers after each layer.
//
// Sparse fill (issue 33; spiral fill, `infill` < 100, `solid` given): a part region's shell,
// the points within curvedShellMm (walls x line width, top/bottom layers x isoLayerHeight, at
// least one line) of the solid's surface, is filled solid as above, and the rest, its interior,
// with Fermat spirals spaced line width x 100 / infill (none at 0 %): walls along the part's
// sides and skins under and over its top and bottom surfaces stay solid, since curved layers
// meet those surfaces at whatever angle. Triangles every point of which lies deeper than the
// shell are interior (each corner deeper by 0.6 x the longest edge at it). Supports and partial layers' cut edges are judged the same way (supports: solid).
struct CurvedFill : Outcome {
  std::vector<std::vector<std::vector<SurfacePath>>> paths;
  size_t regions = 0, pathCount = 0, unfilled = 0;
  std::optional<IsoplanarReport> isoplanar;  // fill = isoplanar: the regions' totals
  std::optional<CurvedSparseReport> sparse;  // sparse fill: its figures
};
CurvedFill fillCurvedLayers(const std::vector<CurvedLayer>& layers, const Settings& settings,
                            const MachineProfile& machine, double isoLayerHeight, const char* stage,
                            double progressScale, const ProgressFn& progress, const Mesh* solid = nullptr);

// Whether curved layers are filled sparsely: spiral fill below 100 % infill (fillCurvedLayers;
// verify judges coverage only where this is false).
bool sparseCurvedFill(const Settings& settings);

// The solid shell of curved layers under sparse fill, mm (see fillCurvedLayers).
double curvedShellMm(const Settings& settings, double isoLayerHeight);

// Speeds, retraction and filament from the settings; the nozzle cone from the machine; the tilt
// limit maxTiltDegrees; bead height nominalHeight, also the gouging check's clearance (the
// program header's layer_height, verify's h); with fill = isoplanar, elliptic beads of the nozzle
// width, else the line width.
CurvedToolpathOptions curvedToolpathOptions(const Settings& settings, const MachineProfile& machine,
                                            double nominalHeight, double maxTiltDegrees);

// The voxel and surface methods print the points the gouging search could not clear (the
// geodesic method leaves them out): the warning a user sees ("nozzle_collision", how many), or
// none when every point was cleared. verify counts them as collisions.
std::optional<Warning> nozzleCollisionWarning(size_t uncorrectedPoints);

// Beads laid closer to the platform than half their planned height (a curved first layer that
// touches the bed: the nozzle would press into it, or the filament back up): the warning
// ("bead_on_platform", the length and share of the extruding path), or none below 1 mm. verify's measures do not see it (its beads are ellipsoids around the tip path).
std::optional<Warning> beadOnPlatformWarning(const Toolpath& toolpath);

// Layers with at least one path.
int printedLayerCount(const std::vector<std::vector<std::vector<SurfacePath>>>& paths);

// Every region's surface into the preview's layer surfaces.
void appendLayerSurfaces(const std::vector<CurvedLayer>& layers, LayerSurfacePreview& preview);

}  // namespace omnislice::stage
