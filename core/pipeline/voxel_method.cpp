// SPDX-License-Identifier: MIT
// The voxel method of paper 001: placed solid -> voxel grid (core/voxel/voxelize) -> growing field
// by convex-front advancing (core/voxel/growth_field; supports under missed voxels when asked) ->
// layer field (core/voxel/layer_field) -> curved layers (core/voxel/curved_layers) -> Fermat
// spirals or iso-planar paths on every region (curved_stage) -> part-frame Toolpath with nozzle
// axes (Eq. 3) and local bead heights (core/surface/curved_toolpath).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/memory_budget.h"
#include "common/parallel.h"
#include "common/stopwatch.h"
#include "pipeline/curved_stage.h"
#include "pipeline/method.h"
#include "pipeline/settings.h"
#include "surface/curved_toolpath.h"
#include "voxel/curved_layers.h"
#include "voxel/growth_field.h"
#include "voxel/layer_field.h"
#include "voxel/voxelize.h"

namespace omnislice {

namespace {

// How far the machine can lean the nozzle from the part's +Z: voxel.max_tilt_deg, else the
// machine's (machineTiltLimitDegrees).
double machineTiltDegrees(const Settings& settings, const MachineProfile& machine) {
  return settings.voxel.maxTiltDegrees > 0 ? settings.voxel.maxTiltDegrees : machineTiltLimitDegrees(machine);
}

}  // namespace

MethodResult runVoxelMethod(const PlacedPart& placed, const MethodContext& context) {
  const Settings& settings = context.settings;
  const MachineProfile& machine = context.machine;
  const ProgressFn& progress = context.progress;
  const Mesh& part = placed.mesh;
  auto failure = [](auto&&... args) { return failed<MethodResult>(std::forward<decltype(args)>(args)...); };
  MethodResult out;
  const double nozzle = settings.nozzleDiameter;
  const double w = settings.voxel.widthMm > 0 ? settings.voxel.widthMm : 0.8 * nozzle;
  const BoundingBox box = boundingBox(part);
  const Eigen::Vector3d extent = box.max - box.min;
  // Refuse before allocating: the bounding box holds at least the solid voxels.
  const double boxCells = (extent.x() / w + 5) * (extent.y() / w + 5) * (extent.z() / w + 5);
  if (!(boxCells < 2e9)) {
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "the voxel grid would have %.3g cells at voxel width %.3g mm; raise "
                  "voxel.width_mm or scale the model down",
                  boxCells, w);
    return failure(Status::InvalidOption, msg);
  }
  auto voxelLever = [&] {
    char lever[120];
    std::snprintf(lever, sizeof lever, "raise voxel.width_mm (now %.3g mm) or memory_mb", w);
    return std::string(lever);
  };
  if (Outcome o = checkMemoryBudget(boxCells * memory_cost::kVoxelCellBytes, settings.memoryMb,
                                    "the voxel grid", voxelLever());
      !o.ok()) {
    return failure(o);
  }

  // 1. Voxelisation (Section 4.1).
  Clock::time_point t0 = Clock::now();
  VoxelizeOptions vopt;
  vopt.width = w;
  vopt.platformRadius = settings.voxel.platformRadiusMm;
  vopt.maxCells = static_cast<size_t>(std::min(2e9, std::max(1e6, settings.voxel.maxVoxels * 40)));
  VoxelizeResult vox = voxelizeSolid(part, vopt, progress);
  if (!vox.ok()) return failure(vox);
  if (static_cast<double>(vox.solidCount) > settings.voxel.maxVoxels) {
    char msg[220];
    std::snprintf(msg, sizeof msg,
                  "the model needs %zu voxels at voxel width %.3g mm, more than voxel.max_voxels "
                  "(%.0f); raise voxel.width_mm or voxel.max_voxels",
                  vox.solidCount, w, settings.voxel.maxVoxels);
    return failure(Status::InvalidOption, msg);
  }
  {
    // What the growing field, the layers and the paths will hold (memory_budget.h).
    char what[80];
    std::snprintf(what, sizeof what, "the voxel method (%zu voxels)", vox.solidCount);
    const double bytes = double(vox.grid.cellCount()) * memory_cost::kVoxelCellBytes +
                         double(vox.solidCount) * memory_cost::kSolidVoxelBytes;
    if (Outcome o = checkMemoryBudget(bytes, settings.memoryMb, what, voxelLever()); !o.ok()) return failure(o);
  }
  out.timingsMs.emplace_back("voxelize", msSince(t0));
  VoxelGrid grid = std::move(vox.grid);

  // 2. Growing field (Section 4.2-4.4, Algorithm 1), supports under missed voxels (Fig. 14c).
  t0 = Clock::now();
  GrowthOptions gopt;
  gopt.strategy = settings.voxel.strategy;
  gopt.shadowScheme = settings.voxel.shadow;
  gopt.peelStep = settings.voxel.peelStep;
  if (settings.voxel.epsilon >= 0) gopt.epsilon = settings.voxel.epsilon;
  GrowthField field = growField(grid, gopt, progress);
  if (!field.ok()) return failure(field);
  const size_t missedBeforeSupports = field.missed;
  int supportRounds = 0;
  double peelingMs = field.peelingMs, shadowMs = field.shadowMs;
  while (settings.voxel.supports && field.missed > 0 && supportRounds < 3) {
    std::vector<uint8_t> missed(grid.cellCount(), 0);
    for (size_t i = 0; i < grid.cellCount(); ++i) missed[i] = field.g[i] < 0 ? 1 : 0;
    const size_t added = addSupportColumns(grid, missed);
    ++supportRounds;
    if (added == 0) break;
    field = growField(grid, gopt, progress);
    if (!field.ok()) return failure(field);
    peelingMs += field.peelingMs;
    shadowMs += field.shadowMs;
  }
  const double fieldMs = msSince(t0);
  out.timingsMs.emplace_back("peeling", peelingMs);
  out.timingsMs.emplace_back("growth", std::max(0.0, fieldMs - peelingMs));

  // 3. Curved layers (Section 4.5, Eq. 2).
  t0 = Clock::now();
  CurvedLayersOptions lopt;
  const int smoothIterations = static_cast<int>(settings.voxel.smoothIterations);
  const std::vector<int32_t> layerField = layerFieldOf(grid, field.g, settings.voxel.layerField, smoothIterations);
  const double mmPerUnit = millimetresPerFieldUnit(grid, layerField);
  const double targetLayer = settings.voxel.layerMm > 0 ? settings.voxel.layerMm : w;
  const int32_t fieldMax = *std::max_element(layerField.begin(), layerField.end());
  lopt.isoStep = settings.voxel.isoStep > 0 ? settings.voxel.isoStep
                 : mmPerUnit > 0            ? targetLayer / mmPerUnit
                                            : std::max(1, fieldMax);  // one layer, at the cells' centres
  lopt.nozzleDiameter = nozzle;
  lopt.maxThickness = settings.voxel.maxThicknessRatio * targetLayer;
  lopt.threads = threadCount(settings.threads);
  const Clock::time_point tx = Clock::now();
  CurvedLayersResult layers = extractCurvedLayers(grid, layerField, part, lopt, progress);
  if (!layers.ok()) return failure(layers);
  // The layers' surfaces, full and partial: the loops that run on the threads (their thickness
  // statistics, one after another, left out).
  double surfacesMs = msSince(tx) - layers.thicknessMs;
  // The gradient estimate can miss on fields of a few voxels: when the measured mean thickness is
  // off the target by more than half, extract once more with the step scaled by their ratio.
  const double measured = layers.thickness.samples > 0 ? layers.thickness.fullMean() : 0;
  if (settings.voxel.isoStep <= 0 && measured > 0 &&
      (measured < 0.5 * targetLayer || measured > 1.5 * targetLayer)) {
    lopt.isoStep *= targetLayer / measured;
    const Clock::time_point ty = Clock::now();
    layers = extractCurvedLayers(grid, layerField, part, lopt, progress);
    if (!layers.ok()) return failure(layers);
    surfacesMs += msSince(ty) - layers.thicknessMs;
  }
  out.timingsMs.emplace_back("layers", msSince(t0));

  // 4. Fermat spirals on every region (Section 5.1) and the tool-path (Section 5.2); with fill =
  // isoplanar (paper 003) every region gets its own theta* and iso-planar NL curves.
  t0 = Clock::now();
  // The nominal layer: the measured mean thickness, or the target the partial layers bound the
  // thickness by when there are any.
  const double measuredHeight = layers.partialLayers > 0        ? targetLayer
                                : layers.thickness.samples > 0 ? layers.thickness.mean
                                                               : w;
  stage::CurvedFill filled =
      stage::fillCurvedLayers(layers.layers, settings, machine, measuredHeight, "toolpath", 0.8, progress, &part);
  if (!filled.ok()) return failure(filled);
  std::vector<std::vector<std::vector<SurfacePath>>>& paths = filled.paths;
  const double spiralMs = msSince(t0);
  // The largest region's curve and theta*; totals over every region.
  out.report.isoplanar = std::move(filled.isoplanar);
  out.report.sparseFill = filled.sparse;
  CurvedToolpathOptions topt =
      stage::curvedToolpathOptions(settings, machine, measuredHeight, machineTiltDegrees(settings, machine));
  // Eq. 3 and the bead heights look back past every partial layer to the full one below.
  int partialRun = 0;
  for (const CurvedLayer& layer : layers.layers) {
    partialRun = layer.partial ? partialRun + 1 : 0;
    topt.earlierLayers = std::max(topt.earlierLayers, partialRun + 1);
  }
  CurvedToolpathResult tp = buildCurvedToolpath(layers.layers, paths, topt, progress);
  if (!tp.ok()) return failure(tp);
  out.timingsMs.emplace_back("toolpath", msSince(t0));
  out.toolpath = std::move(tp.toolpath);
  out.layerHeight = topt.nominalHeight;
  const int printedLayers = stage::printedLayerCount(paths);
  out.slicedLayers = static_cast<size_t>(printedLayers);

  // Preview: layer surfaces, missed and support voxels.
  stage::appendLayerSurfaces(layers.layers, out.preview.surfaces);
  VoxelPreview& p = out.preview.voxel;
  size_t solid = 0, support = 0;
  auto centre = [&](size_t i) {
    const Eigen::Vector3i c = grid.cell(i);
    return grid.center(c.x(), c.y(), c.z());
  };
  for (size_t i = 0; i < grid.cellCount(); ++i) {
    if (grid.state[i] == static_cast<uint8_t>(VoxelState::Solid)) ++solid;
    if (grid.state[i] == static_cast<uint8_t>(VoxelState::Support)) {
      ++support;
      appendPoint(p.support, centre(i));
    }
    if (field.g[i] < 0) appendPoint(p.missed, centre(i));
  }
  p.width = static_cast<float>(w);

  const ThicknessStats& th = layers.thickness;
  VoxelReport& r = out.report.voxel.emplace();
  r.voxels = solid + support;
  r.solidVoxels = solid;
  r.supportVoxels = support;
  r.missedVoxels = field.missed;
  r.missedBeforeSupports = missedBeforeSupports;
  r.supportRounds = supportRounds;
  r.fieldLayers = field.layers;
  r.layerField = layerFieldName(settings.voxel.layerField);
  r.smoothIterations = smoothIterations;
  r.layerFieldMax = *std::max_element(layerField.begin(), layerField.end());
  r.layers = printedLayers;
  r.surfaceLayers = layers.layers.size();
  r.regions = filled.regions;
  r.unfilledRegions = filled.unfilled;
  r.paths = filled.pathCount;
  r.strategy = growthStrategyName(gopt.strategy);
  r.shadowScheme = shadowSchemeName(gopt.shadowScheme);
  r.epsilon = gopt.epsilon;
  r.peelStep = gopt.peelStep;
  r.voxelWidthMm = w;
  r.isoStep = lopt.isoStep;
  r.mmPerFieldUnit = mmPerUnit;
  r.targetLayerMm = targetLayer;
  r.thickness = {th.samples, th.mean, th.stddev, th.maxDeviation, th.histogramMin, th.histogramBin, th.histogram,
                 {}, {}, {}, settings.voxel.maxThicknessRatio, layers.partialLayers};
  for (size_t l = 0; l < th.layers.size() && l < paths.size(); ++l) {
    bool printed = false;
    for (const auto& region : paths[l]) printed = printed || !region.empty();
    if (!printed) continue;
    r.thickness.layerMinMm.push_back(th.layers[l].min);
    r.thickness.layerMaxMm.push_back(th.layers[l].max);
    r.thickness.layerPartial.push_back(th.layers[l].full ? 0 : 1);
  }
  r.timingsMs = {{"voxelize", out.timingsMs[0].second},
                 {"peeling", peelingMs},
                 {"shadow", shadowMs},
                 {"growth", std::max(0.0, fieldMs - peelingMs)},
                 {"extraction", out.timingsMs[3].second},
                 {"surfaces", surfacesMs},
                 {"spirals", spiralMs},
                 {"toolpaths", out.timingsMs[4].second}};
  r.shadowChecks = field.shadowChecks;
  r.hullBuilds = field.hullBuilds;
  r.orientationFallbacks = tp.orientationFallbacks;
  r.maxTiltDeg = topt.maxTiltDegrees;
  r.tiltClamped = tp.tiltClamped;
  r.axesFreed = tp.axesFreed;
  r.axisFreedomDeg = topt.axisFreedomDegrees;
  r.gougingCorrections = tp.gougingCorrections;
  r.gougingUncorrected = tp.gougingUncorrected;
  r.reorderedPaths = tp.reorderedPaths;
  r.gougingMs = tp.gougingMs;
  if (auto w = stage::nozzleCollisionWarning(tp.gougingUncorrected)) out.warnings.push_back(*w);
  if (auto w = stage::beadOnPlatformWarning(out.toolpath)) out.warnings.push_back(*w);
  return out;
}

}  // namespace omnislice
