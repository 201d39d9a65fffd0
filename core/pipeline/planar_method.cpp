// SPDX-License-Identifier: MIT
// The planar method: the placed part (turned by the pipeline so the slicing direction points up)
// sliced into layers of the layer height along +Z (core/slice/slice_mesh), with supports under
// its overhangs when asked (the projected-support generator with no plane, core/multidir/
// projected_supports + core/slice/support_regions), and planned with walls, skins and infill
// (core/slice/plan_layers). fill = isoplanar lays every line along paper 003's drive direction
// theta* (the nozzle stays vertical; f* comes from the machine's linear axes).
#include <cstdio>

#include "common/stopwatch.h"
#include "pipeline/isoplanar_fill.h"
#include "pipeline/method.h"
#include "pipeline/settings.h"
#include "pipeline/support_stage.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"
#include "slice/support_regions.h"

namespace omnislice {

MethodResult runPlanarMethod(const PlacedPart& part, const MethodContext& context) {
  const Settings& settings = context.settings;
  const ProgressFn& progress = context.progress;
  MethodResult out;
  Clock::time_point t0 = Clock::now();
  SliceOptions sliceOptions;
  sliceOptions.direction = Eigen::Vector3d::UnitZ();
  sliceOptions.layerHeight = settings.layerHeight;
  sliceOptions.firstLayerHeight = settings.effectiveFirstLayerHeight();
  SliceResult slices = sliceMesh(part.mesh, sliceOptions, progress);
  if (!slices.ok()) return failed<MethodResult>(slices);
  out.timingsMs.emplace_back("slice", msSince(t0));
  t0 = Clock::now();
  out.slicedLayers = slices.layers.size();
  out.openChains = slices.openChains;
  out.layerHeight = settings.layerHeight;

  PlanarOptions planar = planarOptions(settings);
  if (settings.fill == FillMode::Isoplanar) {
    PlanarDirection dir = planarIsoplanarDirection(slices, settings, context.machine, progress);
    if (!dir.ok()) return failed<MethodResult>(dir);
    planar.infillAngleDegrees = dir.thetaDegrees;
    out.report.isoplanar = std::move(dir.report);
    out.timingsMs.emplace_back("isoplanar", msSince(t0));
    t0 = Clock::now();
  }
  // Supports along the one direction (the projected-support generator with no plane); with
  // support = auto, when the overhanging share of the surface is above support.auto_share_pct.
  SupportRegionsResult regions;
  bool withSupports = stage::supportsWanted(settings);
  if (settings.support.mode == SupportMode::Auto) {
    const stage::OverhangShare share =
        stage::overhangShare(part.mesh, settings.support.angleDeg > 0 ? settings.support.angleDeg : 45,
                             0.5 * settings.effectiveFirstLayerHeight());
    MethodReport::SupportAuto a;
    a.overhangPercent = share.percent;
    a.overhangMm2 = share.overhangMm2;
    a.thresholdPercent = settings.support.autoSharePercent;
    a.supports = withSupports = share.percent > settings.support.autoSharePercent;
    out.report.supportAuto = a;
    if (a.supports) {
      char text[300];
      std::snprintf(text, sizeof text,
                    "%.1f %% of the part's surface (%.0f mm^2) overhangs more than %.0f deg: support = auto prints "
                    "projected supports under it (above %.1f %%, support.auto_share_pct); support = none prints "
                    "without",
                    share.percent, share.overhangMm2, settings.support.angleDeg > 0 ? settings.support.angleDeg : 45.0,
                    settings.support.autoSharePercent);
      out.warnings.push_back({"supports_added", text});
    }
  }
  std::optional<SupportResult> supports;
  SupportOptions supportOptions;
  double supportMs = 0;
  if (withSupports) {
    supportOptions = stage::supportOptionsFor(settings, 45);
    supports = projectedSupports(part.mesh, {}, supportOptions, progress);
    if (!supports->ok()) return failed<MethodResult>(*supports);
    regions = supportRegions(supportMesh(*supports, 0, supportOptions), slices, sliceOptions, {},
                             settings.support.gapMm);
    if (!regions.ok()) return failed<MethodResult>(regions);
    supportMs = msSince(t0);
    out.timingsMs.emplace_back("supports", supportMs);
    t0 = Clock::now();
  }
  PlanLayersResult plan = planLayers(slices, planar, 0, progress, withSupports ? &regions.layers : nullptr);
  if (!plan.ok()) return failed<MethodResult>(plan);
  out.timingsMs.emplace_back("toolpath", msSince(t0));
  out.toolpath = std::move(plan.toolpath);
  if (auto w = thinSectionsWarning(plan.thinAreaMm2, plan.sectionAreaMm2, plan.thinIslands, planar.lineWidth)) {
    out.warnings.push_back(*w);
  }
  if (supports) {
    out.report.support =
        stage::supportReport(*supports, supportOptions, regions.volumeMm3,
                             stage::printedSupportVolume(out.toolpath, settings.filamentDiameter), supportMs);
  }
  return out;
}

}  // namespace omnislice
