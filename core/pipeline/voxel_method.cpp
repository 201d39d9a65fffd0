// SPDX-License-Identifier: MIT
#include "common/stopwatch.h"
#include "pipeline/voxel_method.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <nlohmann/json.hpp>

#include "pipeline/curved_stage.h"
#include "pipeline/isoplanar_fill.h"
#include "pipeline/stage_support.h"
#include "surface/curved_toolpath.h"
#include "surface/fermat_spiral.h"
#include "voxel/curved_layers.h"
#include "voxel/growth_field.h"
#include "voxel/voxelize.h"

namespace omnislice {

namespace {

using Json = nlohmann::ordered_json;

template <typename... Args>
VoxelMethodOutput failure(Args&&... args) {
  return failed<VoxelMethodOutput>(std::forward<Args>(args)...);
}

void pushPoint(std::vector<float>& out, const Eigen::Vector3d& p) {
  out.push_back(static_cast<float>(p.x()));
  out.push_back(static_cast<float>(p.y()));
  out.push_back(static_cast<float>(p.z()));
}

}  // namespace

namespace {

// How far the machine can lean the nozzle from the part's +Z: a table's B range (tilting beyond it
// is out of reach), 90 degrees for a robot holding the platform (beyond, the arm must hold the
// part upside down, which a UR5 under a fixed nozzle reaches only in part of its workspace).
double machineTiltDegrees(const Settings& settings, const MachineProfile& machine) {
  return settings.voxel.maxTiltDegrees > 0 ? settings.voxel.maxTiltDegrees
                                           : machineTiltLimitDegrees(machine);
}

// Indices of the grown cells (G >= 1) in growth order (counting sort by G).
std::vector<uint32_t> growthOrder(const std::vector<int32_t>& g) {
  int32_t maxG = 0;
  for (int32_t v : g) maxG = std::max(maxG, v);
  std::vector<uint32_t> start(static_cast<size_t>(maxG) + 2, 0);
  for (int32_t v : g) {
    if (v >= 1) ++start[static_cast<size_t>(v) + 1];
  }
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<uint32_t> order(start.back());
  for (size_t i = 0; i < g.size(); ++i) {
    if (g[i] >= 1) order[start[static_cast<size_t>(g[i])]++] = static_cast<uint32_t>(i);
  }
  return order;
}

// The layer field: G counts growth steps (time), and a step of the field-governed growth may add
// only a thin sliver of voxels, so iso-values of G bunch up where the front waited and spread where
// it ran. The generation 1 + max over the voxel's AM-stable neighbours added at earlier steps
// counts fronts instead: one unit per face- or edge-neighbour step (paper 001 Section 6.2.1: "the
// field value is increased by one in both cases", 1.25 w per unit). For neighbouring voxels it
// orders exactly as G does (a voxel added later than its neighbour has a larger generation), so
// the layers keep the growth's order locally; every voxel has a neighbour one generation below.
std::vector<int32_t> generationField(const VoxelGrid& grid, const std::vector<int32_t>& g) {
  const std::vector<uint32_t> order = growthOrder(g);
  std::vector<int32_t> gen(g.size());
  for (size_t i = 0; i < g.size(); ++i) gen[i] = g[i] >= 1 ? 0 : g[i];
  const auto& offsets = amStableOffsets();
  for (uint32_t idx : order) {
    const Eigen::Vector3i c = grid.cell(idx);
    int32_t best = 0;
    for (const Eigen::Vector3i& o : offsets) {
      const Eigen::Vector3i n = c + o;
      if (!grid.inRange(n.x(), n.y(), n.z())) continue;
      const size_t ni = grid.index(n.x(), n.y(), n.z());
      if (g[ni] >= 1 && g[ni] < g[idx]) best = std::max(best, gen[ni]);
    }
    gen[idx] = best + 1;
  }
  return gen;
}

// The growth distance: the length of the shortest path from the platform through AM-stable
// neighbour steps that each go to a voxel added at a later growth step (a shortest path in the
// growth's DAG, in voxel widths x `scale`, rounded), raised where needed to stay above every
// neighbour grown earlier. Where the field-governed growth made a region wait, G jumps between the
// early and the late voxels and its iso-surfaces bunch up there; this distance does not jump, so
// layers keep their thickness (30 mm Bunny, 0.64 mm voxels: thickness std 0.32 mm with G, 0.15 mm
// with this; verify coverage 0.914 -> 0.990, supported 0.797 -> 0.920, collisions 162 -> 344).
std::vector<int32_t> growthDistanceField(const VoxelGrid& grid, const std::vector<int32_t>& g,
                                         double scale, double orderMargin) {
  const std::vector<uint32_t> order = growthOrder(g);
  std::vector<double> d(g.size(), 0.0);
  const auto& offsets = amStableOffsets();
  for (uint32_t idx : order) {
    if (g[idx] == 1) {
      d[idx] = 0.5;  // a first-layer voxel's centre is half a voxel above the platform
      continue;
    }
    const Eigen::Vector3i c = grid.cell(idx);
    double best = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3i& o : offsets) {
      const Eigen::Vector3i n = c + o;
      if (!grid.inRange(n.x(), n.y(), n.z())) continue;
      const size_t ni = grid.index(n.x(), n.y(), n.z());
      if (g[ni] >= 1 && g[ni] < g[idx]) best = std::min(best, d[ni] + o.cast<double>().norm());
    }
    // Keep the growth order with every earlier neighbour: at least orderMargin voxels above each
    // (0.1: on a 30 mm Bunny, 0.1 / 0.25 / 0.5 gave supported 0.92 / 0.90 / 0.88, collisions
    // 344 / 960 / 141, thickness std 0.15 / 0.16 / 0.29 mm).
    double above = 0;
    for (const Eigen::Vector3i& o : offsets) {
      const Eigen::Vector3i n = c + o;
      if (!grid.inRange(n.x(), n.y(), n.z())) continue;
      const size_t ni = grid.index(n.x(), n.y(), n.z());
      if (g[ni] >= 1 && g[ni] < g[idx]) above = std::max(above, d[ni] + orderMargin);
    }
    d[idx] = std::max(std::isfinite(best) ? best : 0.5, above);
  }
  std::vector<int32_t> out(g.size());
  for (size_t i = 0; i < g.size(); ++i) {
    out[i] = g[i] >= 1 ? std::max<int32_t>(1, static_cast<int32_t>(std::lround(d[i] * scale))) : g[i];
  }
  return out;
}

// Jacobi smoothing of a layer field over valued face neighbours (iterations), returned scaled by
// `scale` and rounded (the extractor takes integers): the voxel staircase of G becomes gentler
// iso-surfaces. Values <= 0 (platform, empty, missed) are kept and not averaged in.
std::vector<int32_t> smoothedField(const VoxelGrid& grid, const std::vector<int32_t>& g,
                                   int iterations, int32_t scale) {
  std::vector<double> a(g.size()), b;
  for (size_t i = 0; i < g.size(); ++i) a[i] = g[i];
  const Eigen::Vector3i faces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int it = 0; it < iterations; ++it) {
    b = a;
    for (size_t idx = 0; idx < g.size(); ++idx) {
      if (g[idx] <= 0) continue;
      const Eigen::Vector3i c = grid.cell(idx);
      double sum = a[idx];
      int n = 1;
      for (const Eigen::Vector3i& o : faces) {
        const Eigen::Vector3i q = c + o;
        if (!grid.inRange(q.x(), q.y(), q.z())) continue;
        const size_t qi = grid.index(q.x(), q.y(), q.z());
        if (g[qi] <= 0) continue;
        sum += a[qi];
        ++n;
      }
      b[idx] = sum / n;
    }
    a.swap(b);
  }
  std::vector<int32_t> out(g.size());
  for (size_t i = 0; i < g.size(); ++i) {
    out[i] = g[i] <= 0 ? g[i] : std::max<int32_t>(1, static_cast<int32_t>(std::lround(a[i] * scale)));
  }
  return out;
}

// Millimetres per field unit as the layers will measure it: the thickness of iso-surfaces spaced
// one unit apart, averaged over their area, is 1 / |grad G| weighted by area, and by the coarea
// formula that average over all level sets is V / integral |grad G| dV, i.e. w over the mean
// gradient (in units per cell) over the valued voxels (central differences over valued face
// neighbours, one-sided at the border). The growth advances G by one per front step, but how far a
// step reaches depends on the strategy (the field-governed growth takes thinner steps), so curved
// layers of a given thickness need the iso step measured, not assumed (Eq. 2 assumes the paper's
// 1.25 w per unit, Section 6.2.1).
double millimetresPerFieldUnit(const VoxelGrid& grid, const std::vector<int32_t>& g) {
  auto valued = [&](int i, int j, int k, double& v) {
    if (!grid.inRange(i, j, k)) return false;
    const int32_t x = g[grid.index(i, j, k)];
    if (x <= 0) return false;
    v = x;
    return true;
  };
  double sum = 0;
  size_t count = 0;
  for (size_t idx = 0; idx < grid.cellCount(); ++idx) {
    if (g[idx] <= 0) continue;
    const Eigen::Vector3i c = grid.cell(idx);
    double grad2 = 0;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3i lo = c, hi = c;
      lo[a] -= 1;
      hi[a] += 1;
      double vl = 0, vh = 0;
      const bool hasL = valued(lo.x(), lo.y(), lo.z(), vl), hasH = valued(hi.x(), hi.y(), hi.z(), vh);
      double d = 0;
      if (hasL && hasH) d = 0.5 * (vh - vl);
      else if (hasL) d = g[idx] - vl;
      else if (hasH) d = vh - g[idx];
      grad2 += d * d;
    }
    sum += std::sqrt(grad2);
    ++count;
  }
  // A field without any gradient (one voxel layer, e.g. a plate thinner than a voxel): 0, and the
  // caller extracts a single layer.
  if (count == 0 || sum <= 0) return 0;
  return grid.width * static_cast<double>(count) / sum;
}

}  // namespace

VoxelMethodOutput runVoxelMethod(const Mesh& part, const Settings& settings,
                                 const MachineProfile& machine, const ProgressFn& progress) {
  VoxelMethodOutput out;
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
  out.timingsMs.emplace_back("voxelize", msSince(t0));
  VoxelGrid grid = std::move(vox.grid);

  // 2. Growing field (Section 4.2-4.4, Algorithm 1), supports under missed voxels (Fig. 14c).
  t0 = Clock::now();
  GrowthOptions gopt;
  if (!parseGrowthStrategy(settings.voxel.strategy, gopt.strategy) ||
      !parseShadowScheme(settings.voxel.shadow, gopt.shadowScheme)) {
    return failure(Status::InvalidOption, "unknown voxel.strategy or voxel.shadow");
  }
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
  std::vector<int32_t> layerField =
      settings.voxel.layerField == "generations" ? generationField(grid, field.g)
      : settings.voxel.layerField == "distance"  ? growthDistanceField(grid, field.g, 16, 0.1)
                                                 : field.g;
  const int smoothIterations = static_cast<int>(settings.voxel.smoothIterations);
  if (smoothIterations > 0) layerField = smoothedField(grid, layerField, smoothIterations, 16);
  const double mmPerUnit = millimetresPerFieldUnit(grid, layerField);
  const double targetLayer = settings.voxel.layerMm > 0 ? settings.voxel.layerMm : w;
  const int32_t fieldMax = *std::max_element(layerField.begin(), layerField.end());
  lopt.isoStep = settings.voxel.isoStep > 0 ? settings.voxel.isoStep
                 : mmPerUnit > 0            ? targetLayer / mmPerUnit
                                            : 2.0 * std::max(1, fieldMax);  // one layer
  lopt.nozzleDiameter = nozzle;
  CurvedLayersResult layers = extractCurvedLayers(grid, layerField, part, lopt, progress);
  if (!layers.ok()) return failure(layers);
  // The gradient estimate can miss on fields of a few voxels: when the measured mean thickness is
  // off the target by more than half, extract once more with the step scaled by their ratio.
  const double measured = layers.thickness.samples > 0 ? layers.thickness.mean : 0;
  if (settings.voxel.isoStep <= 0 && measured > 0 &&
      (measured < 0.5 * targetLayer || measured > 1.5 * targetLayer)) {
    lopt.isoStep *= targetLayer / measured;
    layers = extractCurvedLayers(grid, layerField, part, lopt, progress);
    if (!layers.ok()) return failure(layers);
  }
  out.timingsMs.emplace_back("layers", msSince(t0));

  // 4. Fermat spirals on every region (Section 5.1) and the tool-path (Section 5.2).
  t0 = Clock::now();
  const double lineWidth = settings.effectiveLineWidth();
  SpiralOptions sopt;
  sopt.spacing = lineWidth;
  std::vector<std::vector<std::vector<SurfacePath>>> paths(layers.layers.size());
  size_t regionCount = 0, pathCount = 0, unfilledRegions = 0;
  // fill = isoplanar (paper 003): every region gets its own theta* and iso-planar NL curves.
  const bool isoplanar = settings.fill == "isoplanar";
  IsoplanarFillOptions iso;
  iso.beadWidth = nozzle;
  iso.layerHeight = layers.thickness.samples > 0 ? layers.thickness.mean : w;
  iso.maxFeed = settings.isoplanar.maxFeedMmS > 0 ? settings.isoplanar.maxFeedMmS : settings.printSpeed;
  iso.travelSpeed = settings.travelSpeed;
  IsoplanarTotals isoTotals;
  for (size_t l = 0; l < layers.layers.size(); ++l) {
    const CurvedLayer& layer = layers.layers[l];
    paths[l].resize(layer.regions.size());
    for (size_t r = 0; r < layer.regions.size(); ++r) {
      ++regionCount;
      if (isoplanar) {
        IsoplanarFillResult fill = planIsoplanarFill(layer.regions[r].mesh, machine, settings.isoplanar, iso);
        if (fill.status == Status::Cancelled) return failure(fill);
        if (!fill.ok() || fill.paths.empty()) {
          ++unfilledRegions;
          continue;
        }
        iso.firstCurve += fill.curves;
        isoTotals.add(uint32_t(l), uint32_t(r), layer.regions[r].area, fill);
        pathCount += fill.paths.size();
        paths[l][r] = std::move(fill.paths);
        continue;
      }
      SpiralResult spiral = fermatSpiralPaths(layer.regions[r].mesh, sopt);
      if (!spiral.ok() || spiral.paths.empty()) {
        ++unfilledRegions;
        continue;
      }
      pathCount += spiral.paths.size();
      paths[l][r] = std::move(spiral.paths);
    }
    if (!reportProgress(progress, "toolpath", 0.8 * (l + 1) / layers.layers.size())) {
      return failure(Status::Cancelled, "cancelled");
    }
  }
  const double spiralMs = msSince(t0);
  // The largest region's curve and theta*; totals over every region.
  if (isoplanar) out.isoplanarJson = isoTotals.json();
  CurvedToolpathOptions topt =
      stage::curvedToolpathOptions(settings, machine, layers.thickness.samples > 0 ? layers.thickness.mean : w,
                            machineTiltDegrees(settings, machine));
  topt.lineWidth = isoplanar ? nozzle : lineWidth;
  topt.ellipseBeads = isoplanar;
  CurvedToolpathResult tp = buildCurvedToolpath(layers.layers, paths, topt, progress);
  if (!tp.ok()) return failure(tp);
  out.timingsMs.emplace_back("toolpath", msSince(t0));
  out.toolpath = std::move(tp.toolpath);
  out.layerHeight = topt.nominalHeight;
  out.layers = stage::printedLayerCount(paths);

  // Preview: layer surfaces, missed and support voxels.
  PreviewBuffers& p = out.preview;
  stage::appendLayerSurfaces(layers.layers, p);
  size_t solid = 0, support = 0;
  auto centre = [&](size_t i) {
    const Eigen::Vector3i c = grid.cell(i);
    return grid.center(c.x(), c.y(), c.z());
  };
  for (size_t i = 0; i < grid.cellCount(); ++i) {
    if (grid.state[i] == static_cast<uint8_t>(VoxelState::Solid)) ++solid;
    if (grid.state[i] == static_cast<uint8_t>(VoxelState::Support)) {
      ++support;
      pushPoint(p.supportVoxels, centre(i));
    }
    if (field.g[i] < 0) pushPoint(p.missedVoxels, centre(i));
  }
  p.voxelWidth = static_cast<float>(w);

  const ThicknessStats& th = layers.thickness;
  Json hist = {{"min_mm", th.histogramMin}, {"bin_mm", th.histogramBin}, {"counts", th.histogram}};
  Json timings = {{"voxelize", out.timingsMs[0].second},
                  {"peeling", peelingMs},
                  {"shadow", shadowMs},
                  {"growth", std::max(0.0, fieldMs - peelingMs)},
                  {"extraction", out.timingsMs[3].second},
                  {"spirals", spiralMs},
                  {"toolpaths", out.timingsMs[4].second}};
  Json report = {{"voxels", solid + support},
                 {"solid_voxels", solid},
                 {"support_voxels", support},
                 {"missed_voxels", field.missed},
                 {"missed_before_supports", missedBeforeSupports},
                 {"support_rounds", supportRounds},
                 {"field_layers", field.layers},
                 {"layer_field", settings.voxel.layerField},
                 {"smooth_iterations", smoothIterations},
                 {"layer_field_max", *std::max_element(layerField.begin(), layerField.end())},
                 {"layers", out.layers},
                 {"surface_layers", layers.layers.size()},
                 {"regions", regionCount},
                 {"unfilled_regions", unfilledRegions},
                 {"paths", pathCount},
                 {"strategy", growthStrategyName(gopt.strategy)},
                 {"shadow_scheme", shadowSchemeName(gopt.shadowScheme)},
                 {"epsilon", gopt.epsilon},
                 {"peel_step", gopt.peelStep},
                 {"voxel_width_mm", w},
                 {"iso_step", lopt.isoStep},
                 {"mm_per_field_unit", mmPerUnit},
                 {"target_layer_mm", targetLayer},
                 {"thickness",
                  {{"samples", th.samples},
                   {"mean_mm", th.mean},
                   {"std_mm", th.stddev},
                   {"max_deviation_mm", th.maxDeviation},
                   {"histogram", hist}}},
                 {"timings_ms", timings},
                 {"shadow_checks", field.shadowChecks},
                 {"hull_builds", field.hullBuilds},
                 {"orientation_fallbacks", tp.orientationFallbacks},
                 {"max_tilt_deg", topt.maxTiltDegrees},
                 {"tilt_clamped", tp.tiltClamped},
                 {"gouging_corrections", tp.gougingCorrections},
                 {"gouging_uncorrected", tp.gougingUncorrected},
                 {"gouging_ms", tp.gougingMs}};
  out.reportJson = report.dump();
  return out;
}

}  // namespace omnislice
