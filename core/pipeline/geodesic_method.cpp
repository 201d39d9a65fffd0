// SPDX-License-Identifier: MIT
#include "common/stopwatch.h"
#include "pipeline/geodesic_method.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "geodesic/heat_geodesic.h"
#include "geodesic/igds.h"
#include "geodesic/print_order.h"
#include "pipeline/curved_stage.h"
#include "pipeline/isoplanar_fill.h"
#include "pipeline/stage_support.h"
#include "surface/curved_toolpath.h"
#include "surface/fermat_spiral.h"
#include "tet/tet_mesher.h"

namespace omnislice {

namespace {

using Json = nlohmann::ordered_json;
using stage::finite;

template <typename... Args>
GeodesicMethodOutput failure(Args&&... args) {
  return failed<GeodesicMethodOutput>(std::forward<Args>(args)...);
}

Json sequenceJson(const PrintSequence& s) {
  return {{"retractions", s.retractions},
          {"air_move_mm", finite(s.airMoveMm)},
          {"collision_free", s.collisionFree},
          {"colliding_nodes", s.collidingNodes},
          {"colliding_lower_bound", s.collidingLowerBound},
          {"criterion2_relaxed", s.criterion2Relaxed},
          {"unavoidable_nodes", s.unavoidableNodes},
          {"ms", s.ms}};
}

// The warning for tool path left out where no nozzle axis clears the part (skipUncorrectable):
// how much, its share of the tool path and where (layers 1-based, as the page counts them, and
// the box around it), so a user can see the gaps before printing.
Warning skippedPathWarning(const CurvedToolpathResult& tp, const Toolpath& printed, size_t layerCount) {
  double printedMm = 0;
  for (size_t i = 1; i < printed.moves.size(); ++i) {
    const MoveKind k = printed.moves[i].kind;
    if (k == MoveKind::Print || k == MoveKind::Support) {
      printedMm += (printed.moves[i].position - printed.moves[i - 1].position).norm();
    }
  }
  const auto [lo, hi] = std::minmax_element(tp.skippedLayers.begin(), tp.skippedLayers.end());
  Eigen::Vector3d bmin = tp.skippedEnds.front(), bmax = bmin;
  for (const Eigen::Vector3d& p : tp.skippedEnds) {
    bmin = bmin.cwiseMin(p);
    bmax = bmax.cwiseMax(p);
  }
  const double share = 100 * tp.skippedMm / std::max(printedMm + tp.skippedMm, 1e-9);
  char text[640];
  std::snprintf(text, sizeof text,
                "%.0f mm of tool path (%.2g %% of it, %zu segments) left out on layers %d-%d of %zu, within "
                "x %.0f..%.0f, y %.0f..%.0f, z %.0f..%.0f mm: no nozzle axis within the tilt range clears the "
                "material printed before (growth fronts meeting where a loop of the part closes, layers "
                "facing down past the tilt range); the print has gaps there. Another placement of the part "
                "(up axis, rotation) or a slimmer nozzle cone in the machine profile may avoid them",
                tp.skippedMm, share, tp.skippedPoints, *lo + 1, *hi + 1, layerCount, bmin.x(), bmax.x(), bmin.y(),
                bmax.y(), bmin.z(), bmax.z());
  return {"skipped_tool_path", text};
}

}  // namespace

GeodesicMethodOutput runGeodesicMethod(const Mesh& part, const TetMesh* given, const Settings& settings,
                                       const MachineProfile& machine, const ProgressFn& progress) {
  GeodesicMethodOutput out;
  const GeodesicSettings& gs = settings.geodesic;
  const double interval = gs.intervalMm > 0 ? gs.intervalMm : settings.layerHeight;
  Json timings = Json::object();

  // 1. The tet mesh: the input's own (.tet) or generated from the solid.
  Clock::time_point t0 = Clock::now();
  TetMesh tets;
  Json mesher = nullptr;
  if (given != nullptr) {
    TetMeshResult checked = validateTetMesh(*given);
    if (!checked.ok()) return failure(checked);
    tets = std::move(checked.mesh);
  } else {
    TetMesherOptions mopt;
    mopt.cellSize = gs.tetSizeMm;
    mopt.targetTets = static_cast<size_t>(gs.targetTets);
    TetMesherResult meshed = tetrahedralize(part, mopt, progress);
    if (!meshed.ok()) return failure(meshed);
    mesher = {{"cell_size_mm", meshed.cellSize},
              {"boundary_vertices", meshed.boundaryVertices},
              {"max_boundary_distance_mm", finite(meshed.maxBoundaryDistance)},
              {"unsnapped", meshed.unsnapped},
              {"volume_ratio", finite(meshed.volumeRatio)},
              {"classify_ms", meshed.classifyMs},
              {"stuff_ms", meshed.stuffMs},
              {"snap_ms", meshed.snapMs}};
    tets = std::move(meshed.mesh);
  }
  const TetQuality quality = tetQuality(tets);
  out.timingsMs.emplace_back("tetmesh", msSince(t0));
  timings["tetmesh"] = out.timingsMs.back().second;

  // 2. Geodesic distance from the platform (Section 2.1).
  t0 = Clock::now();
  if (!reportProgress(progress, "field", 0)) return failure(Status::Cancelled, "cancelled");
  HeatGeodesicOptions hopt;
  hopt.renormalizations = 1;  // a broad source: even layer spacing (heat_geodesic.h)
  HeatGeodesic heat(tets, hopt);
  if (!heat.status().ok()) return failure(heat.status());
  // The heat source: the boundary vertices within geodesic.base_band_mm of the platform (0 = a
  // quarter interval: they print in the first layer anyway), held at their height above it. A
  // wider band helps a base that is not exactly flat and grows domes from a few contact points
  // (the shared Kitten's bottom rises 0.5 mm over its width): full size at 0.6 mm, 2,721 tool-path
  // segments (2.1 m) could not be printed without gouging with the quarter interval, 107 (84 mm)
  // with one interval. It harms a base with a pocket (the compas bunny's bowl, fit 60: 0 -> 361
  // segments, the sources then climb its inner slope), so it is not the default.
  const double baseBand = std::max(1e-4, gs.baseBandMm > 0 ? gs.baseBandMm : 0.25 * interval);
  const std::vector<uint32_t> sources = platformVertices(tets, baseBand);
  if (sources.empty()) {
    return failure(Status::DegenerateInput, "no vertex of the tet mesh lies on the platform");
  }
  GeodesicField field = heat.distanceFrom(sources, heightsAboveLowest(tets, sources), progress);
  if (!field.ok()) return failure(field);
  out.timingsMs.emplace_back("field", msSince(t0));
  timings["field"] = out.timingsMs.back().second;

  // 3. IGDS (Section 2.2) and their metrics (Eq. 11, Fig. 10).
  t0 = Clock::now();
  IgdsOptions iopt;
  iopt.interval = interval;
  // Steps shortened where the field is slow at the surface (geodesic.max_thickness_ratio; 0 =
  // the paper's i d): the interval is then the thickest layer at the part's surface.
  if (gs.maxThicknessRatio > 0) {
    iopt.isoValues = surfaceLimitedIsoValues(tets, field.distance, interval, gs.maxThicknessRatio);
  }
  iopt.remesh = gs.remesh;
  IgdsResult igds = extractIgds(tets, field.distance, iopt, progress);
  if (!igds.ok()) return failure(igds);
  out.timingsMs.emplace_back("igds", msSince(t0));
  timings["igds"] = out.timingsMs.back().second;
  t0 = Clock::now();
  const IgdsMetrics metrics = igdsMetrics(igds.layers, interval);
  timings["metrics"] = msSince(t0);

  // 4. Skeleton tree, potential collision surfaces, the three traversals (Section 3.1).
  t0 = Clock::now();
  if (!reportProgress(progress, "order", 0)) return failure(Status::Cancelled, "cancelled");
  const Mesh boundary = tetBoundary(tets);
  SkeletonTree tree = buildSkeletonTree(igds.layers, boundary, field.distance);
  if (!tree.ok()) return failure(tree);
  CollisionConeOptions copt;
  copt.angleDegrees = gs.nozzleAngleDeg > 0 ? gs.nozzleAngleDeg : machine.nozzle.coneHalfAngleDegrees;
  copt.length = machine.nozzle.coneLength;
  copt.clearance = interval;
  CollisionModel collisions = potentialCollisionSurfaces(igds.layers, tree, copt, progress);
  if (!collisions.ok()) return failure(collisions);
  TraversalKind chosenKind = TraversalKind::A3;
  if (!parseTraversal(gs.sequence, chosenKind)) {
    return failure(Status::InvalidOption, "unknown geodesic.sequence '" + gs.sequence + "'");
  }
  PrintSequence sequences[3];
  const TraversalKind kinds[3] = {TraversalKind::LPT, TraversalKind::DPT, TraversalKind::A3};
  Json traversals = Json::object();
  const PrintSequence* chosen = nullptr;
  for (int k = 0; k < 3; ++k) {
    sequences[k] = printSequence(tree, collisions, kinds[k]);
    if (!sequences[k].ok()) return failure(sequences[k]);
    traversals[traversalName(kinds[k])] = sequenceJson(sequences[k]);
    if (kinds[k] == chosenKind) chosen = &sequences[k];
  }
  out.timingsMs.emplace_back("order", msSince(t0));
  timings["tree"] = tree.ms;
  timings["collision"] = collisions.ms;
  timings["order"] = out.timingsMs.back().second;

  // 5. Filling paths on every IGDS (Section 3.2).
  t0 = Clock::now();
  const double lineWidth = settings.effectiveLineWidth();
  const bool isoplanar = settings.fill == "isoplanar";
  SpiralOptions sopt;
  sopt.spacing = lineWidth;
  IsoplanarFillOptions iso;
  iso.beadWidth = settings.nozzleDiameter;
  iso.layerHeight = interval;
  iso.maxFeed = settings.isoplanar.maxFeedMmS > 0 ? settings.isoplanar.maxFeedMmS : settings.printSpeed;
  iso.travelSpeed = settings.travelSpeed;
  std::vector<std::vector<std::vector<SurfacePath>>> paths(igds.layers.size());
  size_t pathCount = 0, unfilled = 0;
  IsoplanarTotals isoTotals;
  for (size_t l = 0; l < igds.layers.size(); ++l) {
    const CurvedLayer& layer = igds.layers[l];
    paths[l].resize(layer.regions.size());
    for (size_t r = 0; r < layer.regions.size(); ++r) {
      const LayerRegion& region = layer.regions[r];
      if (isoplanar) {
        IsoplanarFillResult fill = planIsoplanarFill(region.mesh, machine, settings.isoplanar, iso);
        if (fill.status == Status::Cancelled) return failure(fill);
        if (!fill.ok() || fill.paths.empty()) {
          ++unfilled;
          continue;
        }
        iso.firstCurve += fill.curves;
        isoTotals.add(uint32_t(l), uint32_t(r), region.area, fill);
        pathCount += fill.paths.size();
        paths[l][r] = std::move(fill.paths);
        continue;
      }
      SpiralResult spiral = fermatSpiralPaths(region.mesh, sopt);
      if (!spiral.ok() || spiral.paths.empty()) {
        ++unfilled;
        continue;
      }
      pathCount += spiral.paths.size();
      paths[l][r] = std::move(spiral.paths);
    }
    if (!reportProgress(progress, "paths", double(l + 1) / double(igds.layers.size()))) {
      return failure(Status::Cancelled, "cancelled");
    }
  }
  if (isoplanar) out.isoplanarJson = isoTotals.json();
  out.timingsMs.emplace_back("paths", msSince(t0));
  timings["paths"] = out.timingsMs.back().second;

  // 6. The tool-path in the chosen sequence: nozzle along the IGDS normal, bead height from the
  // local distance to the layer below (Eq. 12's variable extrusion).
  t0 = Clock::now();
  std::vector<std::pair<uint32_t, uint32_t>> order;
  order.reserve(chosen->order.size());
  for (uint32_t node : chosen->order) order.emplace_back(tree.nodes[node].layer, tree.nodes[node].region);
  CurvedToolpathOptions topt =
      stage::curvedToolpathOptions(settings, machine, interval, machineTiltLimitDegrees(machine));
  topt.lineWidth = isoplanar ? settings.nozzleDiameter : lineWidth;
  topt.ellipseBeads = isoplanar;
  topt.axisFromNormals = true;
  topt.skipUncorrectable = true;
  CurvedToolpathResult tp = buildCurvedToolpath(igds.layers, paths, order, topt, progress);
  if (!tp.ok()) return failure(tp);
  out.timingsMs.emplace_back("toolpath", msSince(t0));
  timings["toolpath"] = out.timingsMs.back().second;
  out.toolpath = std::move(tp.toolpath);
  if (tp.skippedPoints > 0) out.warnings.push_back(skippedPathWarning(tp, out.toolpath, igds.layers.size()));
  out.layerHeight = interval;
  out.layers = stage::printedLayerCount(paths);

  // Preview: IGDS, the boundary with the field, the skeleton tree and the sequence.
  PreviewBuffers& p = out.preview;
  stage::appendLayerSurfaces(igds.layers, p);
  for (const Eigen::Vector3d& e : tp.skippedEnds) {
    for (int a = 0; a < 3; ++a) p.skippedSegments.push_back(static_cast<float>(e[a]));
  }
  p.skippedLayers.assign(tp.skippedLayers.begin(), tp.skippedLayers.end());
  {
    std::vector<uint32_t> remap(boundary.vertexCount(), UINT32_MAX);
    for (uint32_t v : boundary.triangles) {
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<uint32_t>(p.fieldValues.size());
        for (int a = 0; a < 3; ++a) p.fieldPositions.push_back(static_cast<float>(boundary.positions[3 * size_t(v) + a]));
        p.fieldValues.push_back(static_cast<float>(field.distance[v]));
      }
      p.fieldTriangles.push_back(remap[v]);
    }
  }
  size_t branchPoints = 0, merges = 0;
  std::vector<uint32_t> nodesPerLayer(igds.layers.size(), 0);
  for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
    const SkeletonNode& n = tree.nodes[i];
    for (int a = 0; a < 3; ++a) p.nodePositions.push_back(static_cast<float>(n.centroid[a]));
    p.nodeLayers.push_back(n.layer);
    for (uint32_t u : n.upper) {
      p.treeEdges.push_back(i);
      p.treeEdges.push_back(u);
    }
    branchPoints += n.upper.size() > 1;
    merges += n.lower.size() > 1;
    if (n.layer < nodesPerLayer.size()) ++nodesPerLayer[n.layer];
  }
  p.sequence = chosen->order;

  Json skippedLayers = nullptr;  // [first, last]
  if (!tp.skippedLayers.empty()) {
    const auto [lo, hi] = std::minmax_element(tp.skippedLayers.begin(), tp.skippedLayers.end());
    skippedLayers = Json::array({*lo, *hi});
  }
  Json overhangAvg = Json::array(), overhangRatio = Json::array(), overhangMax = Json::array(),
       thicknessMean = Json::array(), thicknessMaxDev = Json::array(), thicknessMeanDev = Json::array(),
       isoValues = Json::array();
  double stepMin = 0, previousIso = 0;
  for (const IgdsLayerMetrics& m : metrics.layers) {
    const double step = m.isoValue - previousIso;
    stepMin = previousIso == 0 ? step : std::min(stepMin, step);
    previousIso = m.isoValue;
    isoValues.push_back(m.isoValue);
    overhangAvg.push_back(finite(m.overhangAverageDegrees));
    overhangRatio.push_back(finite(m.overhangRatio));
    overhangMax.push_back(finite(m.overhangMaxDegrees));
    thicknessMean.push_back(finite(m.thicknessMeanMm));
    thicknessMaxDev.push_back(finite(m.thicknessMaxDeviationPercent));
    thicknessMeanDev.push_back(finite(m.thicknessMeanDeviationPercent));
  }
  Json report = {
      {"tets", tets.tetCount()},
      {"vertices", tets.vertexCount()},
      {"tet_source", given != nullptr ? "input" : "mesher"},
      {"mesher", mesher},
      {"tet_quality",
       {{"volume_mm3", finite(quality.volume)},
        {"mean_edge_mm", finite(quality.meanEdge)},
        {"min_dihedral_deg", finite(quality.minDihedralDegrees)},
        {"max_dihedral_deg", finite(quality.maxDihedralDegrees)},
        {"min_radius_ratio", finite(quality.minRadiusRatio)}}},
      {"sources", sources.size()},
      {"base_band_mm", baseBand},
      {"max_thickness_ratio", gs.maxThicknessRatio},
      {"max_geodesic_mm", finite(field.maxDistance)},
      {"interval_mm", interval},
      {"step_min_mm", finite(stepMin)},  // the shortest step between iso-values
      {"layers", igds.layers.size()},
      {"printed_layers", out.layers},
      {"igds", tree.nodes.size()},
      {"iso_values_mm", isoValues},
      {"triangles", igds.triangleCount},
      {"interpolated_triangles", igds.interpolatedTriangles},
      {"overhang_avg_deg", overhangAvg},
      {"overhang_ratio", overhangRatio},
      {"overhang_max_deg", overhangMax},
      {"overhang_avg_all_deg", finite(metrics.overhangAverageDegrees)},
      {"overhang_max_layer_deg", finite(metrics.overhangMaxLayerDegrees)},
      {"thickness",
       {{"mean_mm", thicknessMean},
        {"max_deviation_percent", thicknessMaxDev},
        {"mean_deviation_percent", thicknessMeanDev},
        {"max_deviation_all_percent", finite(metrics.thicknessMaxDeviationPercent)}}},
      {"tree",
       {{"nodes", tree.nodes.size()},
        {"edges", tree.edges},
        {"is_tree", tree.isTree},
        {"branch_points", branchPoints},
        {"merges", merges},
        {"fallback_links", tree.fallbackLinks},
        {"max_nodes_per_layer", nodesPerLayer.empty() ? 0u : *std::max_element(nodesPerLayer.begin(), nodesPerLayer.end())}}},
      {"nozzle_angle_deg", copt.angleDegrees},
      {"pcs_pairs_tested", collisions.pairsTested},
      {"sequence", traversalName(chosenKind)},
      {"retractions", chosen->retractions},
      {"air_move_mm", finite(chosen->airMoveMm)},
      {"collision_free", chosen->collisionFree},
      {"traversals", traversals},
      {"paths", pathCount},
      {"unfilled_regions", unfilled},
      {"orientation_fallbacks", tp.orientationFallbacks},
      {"tilt_clamped", tp.tiltClamped},
      {"max_tilt_deg", topt.maxTiltDegrees},
      {"gouging_corrections", tp.gougingCorrections},
      {"gouging_uncorrected", tp.gougingUncorrected},
      {"skipped_segments", tp.skippedPoints},
      {"skipped_mm", finite(tp.skippedMm)},
      {"skipped_layers", skippedLayers},
      {"timings_ms",
       {{"tetmesh", timings["tetmesh"]},
        {"field", timings["field"]},
        {"field_setup", field.setupMs},
        {"field_solve", field.heatMs + field.gradientMs + field.poissonMs},
        {"igds", timings["igds"]},
        {"interpolation", igds.interpolationMs},
        {"remesh", igds.remeshMs},
        {"smooth", igds.smoothMs},
        {"metrics", timings["metrics"]},
        {"tree", timings["tree"]},
        {"collision", timings["collision"]},
        {"order", timings["order"]},
        {"paths", timings["paths"]},
        {"toolpath", timings["toolpath"]},
        {"toolpath_orientation", tp.orientationMs},
        {"toolpath_gouging", tp.gougingMs}}}};
  out.reportJson = report.dump();
  return out;
}

}  // namespace omnislice
