// SPDX-License-Identifier: MIT
// The geodesic method of paper 002: placed solid (or a given tet mesh) -> tet mesh
// (core/tet/tet_mesher) -> heat-method geodesic distance from the platform
// (core/geodesic/heat_geodesic) -> iso-geodesic distance surfaces with metrics
// (core/geodesic/igds) -> skeleton tree, potential collision surfaces and the LPT / DPT / A3
// sequences (core/geodesic/print_order) -> filling paths on every IGDS (Section 3.2: Fermat
// spirals of iso-contours of the boundary distance; or iso-planar paths with fill = isoplanar,
// curved_stage) -> part-frame Toolpath in the chosen sequence, nozzle axis along the IGDS normal,
// extrusion from the local layer thickness (Eq. 12).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <thread>

#include "common/memory_budget.h"
#include "common/parallel.h"
#include "common/stopwatch.h"
#include "geodesic/heat_geodesic.h"
#include "geodesic/igds.h"
#include "geodesic/print_order.h"
#include "mesh/mesh_measures.h"
#include "pipeline/curved_stage.h"
#include "pipeline/method.h"
#include "pipeline/settings.h"
#include "surface/curved_toolpath.h"
#include "tet/tet_mesher.h"

namespace omnislice {

namespace {

template <typename... Args>
MethodResult failure(Args&&... args) {
  return failed<MethodResult>(std::forward<Args>(args)...);
}

GeodesicReport::Sequence sequenceReport(const PrintSequence& s) {
  GeodesicReport::Sequence r;
  r.name = traversalName(s.kind);
  r.retractions = s.retractions;
  r.airMoveMm = s.airMoveMm;
  r.collisionFree = s.collisionFree;
  r.collidingNodes = s.collidingNodes;
  r.collidingLowerBound = s.collidingLowerBound;
  r.criterion2Relaxed = s.criterion2Relaxed;
  r.unavoidableNodes = s.unavoidableNodes;
  r.ms = s.ms;
  return r;
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

// The preview's geodesic section: the tool path left out, the boundary with the distance per
// vertex, the skeleton tree and the print sequence.
GeodesicPreview geodesicPreview(const CurvedToolpathResult& tp, const Mesh& boundary,
                                const std::vector<double>& distance, const SkeletonTree& tree,
                                const std::vector<uint32_t>& sequence) {
  GeodesicPreview p;
  for (const Eigen::Vector3d& e : tp.skippedEnds) appendPoint(p.skippedSegments, e);
  p.skippedLayers.assign(tp.skippedLayers.begin(), tp.skippedLayers.end());
  std::vector<uint32_t> remap(boundary.vertexCount(), UINT32_MAX);
  for (uint32_t v : boundary.triangles) {
    if (remap[v] == UINT32_MAX) {
      remap[v] = static_cast<uint32_t>(p.fieldValues.size());
      appendPoint(p.fieldPositions, boundary.vertex(v));
      p.fieldValues.push_back(static_cast<float>(distance[v]));
    }
    p.fieldTriangles.push_back(remap[v]);
  }
  for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
    const SkeletonNode& n = tree.nodes[i];
    appendPoint(p.nodePositions, n.centroid);
    p.nodeLayers.push_back(n.layer);
    for (uint32_t u : n.upper) {
      p.treeEdges.push_back(i);
      p.treeEdges.push_back(u);
    }
  }
  p.sequence = sequence;
  return p;
}

// The report's tree figures: nodes, edges, branch points (nodes with several upper nodes), merges
// (several lower nodes), the most IGDS in one layer.
GeodesicReport::Tree treeReport(const SkeletonTree& tree, size_t layers) {
  size_t branchPoints = 0, merges = 0;
  std::vector<uint32_t> nodesPerLayer(layers, 0);
  for (const SkeletonNode& n : tree.nodes) {
    branchPoints += n.upper.size() > 1;
    merges += n.lower.size() > 1;
    if (n.layer < nodesPerLayer.size()) ++nodesPerLayer[n.layer];
  }
  return {tree.nodes.size(), tree.edges, tree.isTree, branchPoints, merges, tree.fallbackLinks,
          nodesPerLayer.empty() ? 0u : *std::max_element(nodesPerLayer.begin(), nodesPerLayer.end())};
}

// The report's per-layer figures (Eq. 11 overhang, thickness) and the shortest iso-value step.
void addLayerMetrics(GeodesicReport& report, const IgdsMetrics& metrics) {
  double stepMin = 0, previousIso = 0;
  GeodesicReport::Thickness& thickness = report.thickness;
  for (const IgdsLayerMetrics& m : metrics.layers) {
    const double step = m.isoValue - previousIso;
    stepMin = previousIso == 0 ? step : std::min(stepMin, step);
    previousIso = m.isoValue;
    report.isoValuesMm.push_back(m.isoValue);
    report.overhangAvgDeg.push_back(m.overhangAverageDegrees);
    report.overhangRatio.push_back(m.overhangRatio);
    report.overhangMaxDeg.push_back(m.overhangMaxDegrees);
    thickness.meanMm.push_back(m.thicknessMeanMm);
    thickness.maxDeviationPercent.push_back(m.thicknessMaxDeviationPercent);
    thickness.meanDeviationPercent.push_back(m.thicknessMeanDeviationPercent);
  }
  thickness.maxDeviationAllPercent = metrics.thicknessMaxDeviationPercent;
  report.stepMinMm = stepMin;
  report.overhangAvgAllDeg = metrics.overhangAverageDegrees;
  report.overhangMaxLayerDeg = metrics.overhangMaxLayerDegrees;
}

// Steps 2-6 of the method with `alignPasses` (HeatGeodesicOptions::alignPasses): what the rest
// of the method reads, with its timings.
struct GeodesicAttempt : Outcome {
  int alignPasses = 0;
  GeodesicField field;
  IgdsResult igds;
  SkeletonTree tree;
  CollisionModel collisions;
  PrintSequence sequences[3];
  int chosenIndex = 0;
  std::vector<GeodesicReport::Sequence> traversals;
  stage::CurvedFill filled;
  CurvedToolpathOptions topt;
  CurvedToolpathResult tp;
  Timings stageMs, reportMs;  // MethodResult::timingsMs and GeodesicReport::timingsMs entries
  const PrintSequence& chosen() const { return sequences[chosenIndex]; }
};

// The tets, the heat method's matrices and the layers of `tets` tets within the memory budget.
Outcome checkTetBudget(double tets, double budgetMb) {
  char what[80];
  std::snprintf(what, sizeof what, "the geodesic method (%.0f tets)", tets);
  return checkMemoryBudget(tets * memory_cost::kTetBytes, budgetMb, what,
                           "lower geodesic.target_tets, raise geodesic.tet_size_mm or raise memory_mb");
}

GeodesicAttempt geodesicAttempt(const TetMesh& tets, const Mesh& boundary, const std::vector<uint32_t>& sources,
                                int alignPasses, double interval, const MethodContext& context) {
  const Settings& settings = context.settings;
  const MachineProfile& machine = context.machine;
  const ProgressFn& progress = context.progress;
  const GeodesicSettings& gs = settings.geodesic;
  GeodesicAttempt a;
  a.alignPasses = alignPasses;
  auto fail = [](const auto& r) { return failed<GeodesicAttempt>(r); };

  // 2. Geodesic distance from the platform (Section 2.1).
  Clock::time_point t0 = Clock::now();
  if (!reportProgress(progress, "field", 0)) return failed<GeodesicAttempt>(Status::Cancelled, "cancelled");
  HeatGeodesicOptions hopt;
  hopt.timeFactor = gs.heatTime;
  hopt.alignPasses = alignPasses;
  hopt.renormalizations = 1;  // a broad source: even layer spacing (heat_geodesic.h)
  HeatGeodesic heat(tets, hopt);
  if (!heat.status().ok()) return fail(heat.status());
  // The heat source: the boundary vertices within geodesic.base_band_mm of the platform (0 = a
  // quarter interval: they print in the first layer anyway), held at their height above it. A
  // wider band helps a base that is not exactly flat and grows domes from a few contact points
  // (the shared Kitten's bottom rises 0.5 mm over its width): full size at 0.6 mm, 2,721 tool-path
  // segments (2.1 m) could not be printed without gouging with the quarter interval, 107 (84 mm)
  // with one interval. It harms a base with a pocket (the compas bunny's bowl, fit 60: 0 -> 361
  // segments, the sources then climb its inner slope), so it is not the default.
  a.field = heat.distanceFrom(sources, heightsAboveLowest(tets, sources), progress);
  if (!a.field.ok()) return fail(a.field);
  a.stageMs.emplace_back("field", msSince(t0));
  a.reportMs.emplace_back("field", a.stageMs.back().second);
  a.reportMs.emplace_back("field_setup", a.field.setupMs);
  a.reportMs.emplace_back("field_solve", a.field.heatMs + a.field.gradientMs + a.field.poissonMs);

  // 3. IGDS (Section 2.2) and their metrics (Eq. 11, Fig. 10).
  t0 = Clock::now();
  IgdsOptions iopt;
  iopt.interval = interval;
  // Steps shortened where the field is slow at the surface (geodesic.max_thickness_ratio; 0 =
  // the paper's i d): the interval is then the thickest layer at the part's surface.
  if (gs.maxThicknessRatio > 0) {
    iopt.isoValues = surfaceLimitedIsoValues(tets, a.field.distance, interval, gs.maxThicknessRatio);
  }
  iopt.remesh = gs.remesh;
  a.igds = extractIgds(tets, a.field.distance, iopt, progress);
  if (!a.igds.ok()) return fail(a.igds);
  a.stageMs.emplace_back("igds", msSince(t0));
  a.reportMs.emplace_back("igds", a.stageMs.back().second);
  a.reportMs.emplace_back("interpolation", a.igds.interpolationMs);
  a.reportMs.emplace_back("remesh", a.igds.remeshMs);
  a.reportMs.emplace_back("smooth", a.igds.smoothMs);

  // 4. Skeleton tree, potential collision surfaces, the three traversals (Section 3.1).
  t0 = Clock::now();
  if (!reportProgress(progress, "order", 0)) return failed<GeodesicAttempt>(Status::Cancelled, "cancelled");
  a.tree = buildSkeletonTree(a.igds.layers, boundary, a.field.distance);
  if (!a.tree.ok()) return fail(a.tree);
  CollisionConeOptions copt;
  copt.angleDegrees = gs.nozzleAngleDeg > 0 ? gs.nozzleAngleDeg : machine.nozzle.coneHalfAngleDegrees;
  copt.length = machine.nozzle.coneLength;
  copt.clearance = interval;
  copt.threads = threadCount(settings.threads);
  a.collisions = potentialCollisionSurfaces(a.igds.layers, a.tree, copt, progress);
  if (!a.collisions.ok()) return fail(a.collisions);
  const TraversalKind kinds[3] = {TraversalKind::LPT, TraversalKind::DPT, TraversalKind::A3};
  for (int k = 0; k < 3; ++k) {
    a.sequences[k] = printSequence(a.tree, a.collisions, kinds[k]);
    if (!a.sequences[k].ok()) return fail(a.sequences[k]);
    a.traversals.push_back(sequenceReport(a.sequences[k]));
    if (kinds[k] == gs.sequence) a.chosenIndex = k;
  }
  a.stageMs.emplace_back("order", msSince(t0));
  a.reportMs.emplace_back("tree", a.tree.ms);
  a.reportMs.emplace_back("collision", a.collisions.ms);
  a.reportMs.emplace_back("order", a.stageMs.back().second);

  // 5. Filling paths on every IGDS (Section 3.2).
  t0 = Clock::now();
  a.filled = stage::fillCurvedLayers(a.igds.layers, settings, machine, interval, "paths", 1, progress, &boundary);
  if (!a.filled.ok()) return fail(a.filled);
  a.stageMs.emplace_back("paths", msSince(t0));
  a.reportMs.emplace_back("paths", a.stageMs.back().second);

  // 6. The tool-path in the chosen sequence: nozzle along the IGDS normal, bead height from the
  // local distance to the layer below (Eq. 12's variable extrusion).
  t0 = Clock::now();
  std::vector<std::pair<uint32_t, uint32_t>> order;
  order.reserve(a.chosen().order.size());
  for (uint32_t node : a.chosen().order) order.emplace_back(a.tree.nodes[node].layer, a.tree.nodes[node].region);
  a.topt = stage::curvedToolpathOptions(settings, machine, interval, machineTiltLimitDegrees(machine));
  a.topt.axisFromNormals = true;
  a.topt.skipUncorrectable = true;
  a.tp = buildCurvedToolpath(a.igds.layers, a.filled.paths, order, a.topt, progress);
  if (!a.tp.ok()) return fail(a.tp);
  a.stageMs.emplace_back("toolpath", msSince(t0));
  a.reportMs.emplace_back("toolpath", a.stageMs.back().second);
  a.reportMs.emplace_back("toolpath_orientation", a.tp.orientationMs);
  a.reportMs.emplace_back("toolpath_gouging", a.tp.gougingMs);
  return a;
}

}  // namespace

MethodResult runGeodesicMethod(const PlacedPart& placed, const MethodContext& context) {
  const Settings& settings = context.settings;
  const MachineProfile& machine = context.machine;
  const ProgressFn& progress = context.progress;
  MethodResult out;
  GeodesicReport report;
  const GeodesicSettings& gs = settings.geodesic;
  const double interval = gs.intervalMm > 0 ? gs.intervalMm : settings.layerHeight;
  Timings& timings = report.timingsMs;

  // 1. The tet mesh: the input's own (.tet) or generated from the solid.
  Clock::time_point t0 = Clock::now();
  TetMesh tets;
  if (placed.tets) {
    TetMeshResult checked = validateTetMesh(*placed.tets);
    if (!checked.ok()) return failure(checked);
    tets = std::move(checked.mesh);
  } else {
    TetMesherOptions mopt;
    mopt.cellSize = gs.tetSizeMm;
    mopt.targetTets = static_cast<size_t>(gs.targetTets);
    // The tets the mesher will make: its target, or at cell size h about 6 per h^3 of the solid
    // (a body-centred cubic lattice).
    const double expected = mopt.cellSize > 0 ? 6.0 * std::abs(signedVolume(placed.mesh)) / std::pow(mopt.cellSize, 3)
                                              : double(mopt.targetTets);
    if (Outcome o = checkTetBudget(expected, settings.memoryMb); !o.ok()) return failure(o);
    TetMesherResult meshed = tetrahedralize(placed.mesh, mopt, progress);
    if (!meshed.ok()) return failure(meshed);
    report.mesher = GeodesicReport::Mesher{meshed.cellSize,          meshed.boundaryVertices,
                                           meshed.maxBoundaryDistance, meshed.unsnapped,
                                           meshed.volumeRatio,       meshed.classifyMs,
                                           meshed.stuffMs,           meshed.snapMs};
    tets = std::move(meshed.mesh);
  }
  if (Outcome o = checkTetBudget(double(tets.tetCount()), settings.memoryMb); !o.ok()) return failure(o);
  const TetQuality quality = tetQuality(tets);
  out.timingsMs.emplace_back("tetmesh", msSince(t0));
  timings.emplace_back("tetmesh", out.timingsMs.back().second);

  // 2-6. The field, layers, order, paths and tool path: one attempt with geodesic.align_passes,
  // and where it leaves tool path out, a second with geodesic.align_retry_passes (stronger
  // alignment rounds the creases more, yet on some models leaves a little path out where the
  // first left none, so it is the retry, not the default); the one leaving less out is kept.
  const double baseBand = std::max(1e-4, gs.baseBandMm > 0 ? gs.baseBandMm : 0.25 * interval);
  const std::vector<uint32_t> sources = platformVertices(tets, baseBand);
  if (sources.empty()) {
    return failure(Status::DegenerateInput, "no vertex of the tet mesh lies on the platform");
  }
  const Clock::time_point firstStart = Clock::now();
  const Mesh boundary = tetBoundary(tets);
  const int firstPasses = static_cast<int>(gs.alignPasses), retryPasses = static_cast<int>(gs.alignRetryPasses);
  const bool mayRetry = retryPasses > firstPasses;
  GeodesicAttempt attempt, retry;
  bool retried = false;
  double firstMs = 0, retryMs = 0;
  if (mayRetry && threadCount(settings.threads) > 1) {
    // On two threads or more (natively): the retry starts beside the first attempt, silent, each
    // attempt's own loops on one thread, and is stopped as soon as the first leaves nothing out.
    // The same choice as one after another; sooner where the retry is needed.
    Settings single = settings;
    single.threads = 1;
    std::atomic<bool> stop{false}, retryDone{false};
    const ProgressFn quiet = [&](const ProgressEvent&) { return !stop.load(); };
    const MethodContext firstContext{single, context.machine, context.progress};
    const MethodContext retryContext{single, context.machine, quiet};
    std::exception_ptr retryError;
    std::thread beside([&] {
      const Clock::time_point t = Clock::now();
      try {
        retry = geodesicAttempt(tets, boundary, sources, retryPasses, interval, retryContext);
      } catch (...) {
        retryError = std::current_exception();
      }
      retryMs = msSince(t);
      retryDone = true;
    });
    try {
      attempt = geodesicAttempt(tets, boundary, sources, firstPasses, interval, firstContext);
    } catch (...) {
      stop = true;
      beside.join();
      throw;
    }
    firstMs = msSince(firstStart);
    retried = attempt.ok() && attempt.tp.skippedMm > 0;
    if (!retried) stop = true;
    // While the retry runs on, the caller may still cancel (asked at the first's last stage).
    while (!retryDone) {
      if (!stop && !reportProgress(context.progress, "toolpath", 1.0)) stop = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    beside.join();
    if (retryError) std::rethrow_exception(retryError);
    if (retried && stop) return failure(Status::Cancelled, "cancelled");
  } else {
    attempt = geodesicAttempt(tets, boundary, sources, firstPasses, interval, context);
    firstMs = msSince(firstStart);
    retried = mayRetry && attempt.ok() && attempt.tp.skippedMm > 0;
    if (retried) {
      const Clock::time_point t = Clock::now();
      retry = geodesicAttempt(tets, boundary, sources, retryPasses, interval, context);
      retryMs = msSince(t);
    }
  }
  if (!attempt.ok()) return failure(attempt);
  report.alignFirstLeftOutMm = attempt.tp.skippedMm;
  if (retried) {
    if (!retry.ok()) return failure(retry);
    report.alignRetried = true;
    // The time of the attempt not kept.
    report.alignRetryMs = retryMs;
    if (retry.tp.skippedMm < attempt.tp.skippedMm) {
      report.alignRetryMs = firstMs;
      attempt = std::move(retry);
    }
  }
  const GeodesicField& field = attempt.field;
  const IgdsResult& igds = attempt.igds;
  const SkeletonTree& tree = attempt.tree;
  const CollisionModel& collisions = attempt.collisions;
  const stage::CurvedFill& filled = attempt.filled;
  CurvedToolpathResult& tp = attempt.tp;
  const CurvedToolpathOptions& topt = attempt.topt;
  for (const auto& [name, ms] : attempt.stageMs) out.timingsMs.emplace_back(name, ms);
  for (const auto& [name, ms] : attempt.reportMs) timings.emplace_back(name, ms);
  if (report.alignRetried) timings.emplace_back("align_retry", report.alignRetryMs);
  t0 = Clock::now();
  const IgdsMetrics metrics = igdsMetrics(igds.layers, interval);
  timings.emplace_back("metrics", msSince(t0));
  report.traversals = attempt.traversals;
  out.report.isoplanar = std::move(attempt.filled.isoplanar);
  out.report.sparseFill = attempt.filled.sparse;
  out.toolpath = std::move(tp.toolpath);
  if (tp.skippedPoints > 0) out.warnings.push_back(skippedPathWarning(tp, out.toolpath, igds.layers.size()));
  if (auto w = stage::beadOnPlatformWarning(out.toolpath)) out.warnings.push_back(*w);
  out.leftOutMm = tp.skippedMm;
  for (const Eigen::Vector3d& e : tp.skippedEnds) out.leftOutLowestMm = std::min(out.leftOutLowestMm, e.z());
  out.layerHeight = interval;
  const int printedLayers = stage::printedLayerCount(filled.paths);
  out.slicedLayers = static_cast<size_t>(printedLayers);

  // Preview: IGDS, the boundary with the field, the skeleton tree and the sequence.
  stage::appendLayerSurfaces(igds.layers, out.preview.surfaces);
  out.preview.geodesic = geodesicPreview(tp, boundary, field.distance, tree, attempt.chosen().order);

  // The report.
  if (!tp.skippedLayers.empty()) {
    const auto [lo, hi] = std::minmax_element(tp.skippedLayers.begin(), tp.skippedLayers.end());
    report.skippedLayers = std::make_pair(*lo, *hi);
  }
  addLayerMetrics(report, metrics);
  report.tets = tets.tetCount();
  report.vertices = tets.vertexCount();
  report.tetSource = placed.tets ? "input" : "mesher";
  report.tetQuality = {quality.volume, quality.meanEdge, quality.minDihedralDegrees, quality.maxDihedralDegrees,
                       quality.minRadiusRatio};
  report.sources = sources.size();
  report.baseBandMm = baseBand;
  report.maxThicknessRatio = gs.maxThicknessRatio;
  report.heatTime = gs.heatTime;
  report.alignPasses = attempt.alignPasses;
  report.maxGeodesicMm = field.maxDistance;
  report.intervalMm = interval;
  report.layers = igds.layers.size();
  report.printedLayers = printedLayers;
  report.igds = tree.nodes.size();
  report.triangles = igds.triangleCount;
  report.interpolatedTriangles = igds.interpolatedTriangles;
  report.tree = treeReport(tree, igds.layers.size());
  report.nozzleAngleDeg = gs.nozzleAngleDeg > 0 ? gs.nozzleAngleDeg : machine.nozzle.coneHalfAngleDegrees;
  report.pcsPairsTested = collisions.pairsTested;
  report.sequence = traversalName(gs.sequence);
  report.paths = filled.pathCount;
  report.unfilledRegions = filled.unfilled;
  report.orientationFallbacks = tp.orientationFallbacks;
  report.tiltClamped = tp.tiltClamped;
  report.axesFreed = tp.axesFreed;
  report.axisFreedomDeg = topt.axisFreedomDegrees;
  report.maxTiltDeg = topt.maxTiltDegrees;
  report.gougingCorrections = tp.gougingCorrections;
  report.gougingUncorrected = tp.gougingUncorrected;
  report.reorderedPaths = tp.reorderedPaths;
  report.nearIdealPaths = tp.nearIdealPaths;
  report.skippedSegments = tp.skippedPoints;
  report.skippedMm = tp.skippedMm;
  out.report.geodesic = std::move(report);
  return out;
}

}  // namespace omnislice
