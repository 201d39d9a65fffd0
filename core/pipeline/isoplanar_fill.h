// SPDX-License-Identifier: MIT
// Paper 003 as one pipeline step for one layer surface: samples -> kinematic feed field ->
// theta* (Algorithm 1) -> iso-planar NL curves (Algorithm 2) -> surface paths, with the time
// estimate under the kinematic limits and, for the report, the same planning at every other
// sampled direction. Used by `method = surface`, by `fill = isoplanar` on the voxel method's
// curved layers and (direction only) on planar layers. Internal to core/pipeline.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "pipeline/report.h"
#include "pipeline/settings.h"
#include "machine/machine.h"
#include "slice/slice_mesh.h"
#include "surface/fermat_spiral.h"

namespace omnislice {

struct IsoplanarFillOptions {
  double beadWidth = 0.4;     // s = nozzle diameter, mm
  double layerHeight = 0.2;   // h (every sample), mm
  double maxFeed = 50;        // cap on f*, mm/s
  double travelSpeed = 150;   // mm/s, time estimate
  bool benchmark = false;     // plan every other sampled direction too
  uint32_t firstCurve = 1;    // curve tags start here (1-based across a whole print)
};

struct IsoplanarFillResult : Outcome {
  std::vector<SurfacePath> paths;  // zig-zag runs, normals on the surface's triangle side, curve
                                   // tags per point
  uint32_t curves = 0;             // NL curves tagged
  double thetaDegrees = 0;         // theta* (or the forced angle)
  double depositionRate = 0;       // mean v_e at theta*, mm^3/s
  double pathMm = 0;
  double estimatedTimeS = 0;       // estimateIsoplanarTime at theta*
  double benchmarkTimeS = 0;       // mean over the other directions (benchmark only), else 0
  double benchmarkPathMm = 0;
  IsoplanarReport report;          // the report's "isoplanar" section for this surface
  Timings timingsMs;               // samples, feed, direction, paths, benchmark
};

// surface: an oriented triangle surface in the part frame (normals to the nozzle side).
// settings.isoplanar gives theta (forced or searched), directions, chord error, stencil, gamma
// samples. Progress stages "feed", "direction", "paths", "benchmark".
IsoplanarFillResult planIsoplanarFill(const Mesh& surface, const MachineProfile& machine,
                                      const IsoplanarSettings& settings,
                                      const IsoplanarFillOptions& options,
                                      const ProgressFn& progress = {});

// The iso-planar fill of many layer regions summed for the report's "isoplanar" section: the
// largest region's report (its curve and theta*, as largest_region_theta_deg) with path_mm,
// estimated_time_s, the area-weighted deposition_rate_mm3_s and one entry per region.
class IsoplanarTotals {
 public:
  void add(uint32_t layer, uint32_t region, double area, const IsoplanarFillResult& fill);
  std::optional<IsoplanarReport> report() const;  // none when no region was added
 private:
  std::optional<IsoplanarReport> largest_;
  std::vector<IsoplanarReport::Region> regions_;
  double path_ = 0, time_ = 0, rateArea_ = 0, area_ = 0, largestArea_ = -1;
};

struct PlanarDirection : Outcome {
  double thetaDegrees = 0;   // theta* (or the forced angle): the lines' angle on every layer
  IsoplanarReport report;    // the report's "isoplanar" section (no paths: the planar planner
                             // lays the lines)
};

// Paper 003 on planar layers: samples on a grid (about 2 mm, at most ~20k points) inside the
// sections of up to 24 evenly spread layers, nozzle vertical, flat (w_eff = pi s / 4 everywhere),
// f* from the machine's axes; theta* by Eq. 11 (or settings.isoplanar.theta_deg).
PlanarDirection planarIsoplanarDirection(const SliceResult& slices, const Settings& settings,
                                         const MachineProfile& machine,
                                         const ProgressFn& progress = {});

}  // namespace omnislice
