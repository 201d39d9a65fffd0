// SPDX-License-Identifier: MIT
// The report's JSON: the one place where the typed report (report.h) becomes text. Keys and their
// order are those README.md documents; every number passes through num() so a non-finite value
// is written as 0 and reports stay numeric.
#include <cmath>
#include <nlohmann/json.hpp>

#include "machine/machine_json.h"
#include "pipeline/report.h"

namespace omnislice {

namespace {

using Json = nlohmann::ordered_json;

double num(double v) { return std::isfinite(v) ? v : 0.0; }

Json vec(const Eigen::Vector3d& v) { return Json::array({num(v.x()), num(v.y()), num(v.z())}); }

Json numbers(const std::vector<double>& values) {
  Json a = Json::array();
  for (double v : values) a.push_back(num(v));
  return a;
}

Json timings(const Timings& t) {
  Json j = Json::object();
  for (const auto& [stage, ms] : t) j[stage] = num(ms);
  return j;
}

Json matrixJson(const Eigen::Matrix4d& m) {
  Json a = Json::array();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) a.push_back(m(r, c));
  }
  return a;
}

Json bboxJson(const BoundingBox& b) {
  return Json{{"min", {b.min.x(), b.min.y(), b.min.z()}}, {"max", {b.max.x(), b.max.y(), b.max.z()}}};
}

Json supportJson(const SupportReport& r) {
  return {{"generated", true},
          {"sampling_mm", num(r.samplingMm)},
          {"angle_deg", num(r.angleDeg)},
          {"min_diameter_mm", num(r.minDiameterMm)},
          {"roof_mm", num(r.roofMm)},
          {"merge_angle_deg", num(r.mergeAngleDeg)},
          {"samples", r.samples},
          {"point_overhangs", r.pointOverhangs},
          {"patch_samples", r.patchSamples},
          {"landed_on_model", r.landedOnModel},
          {"landed_on_platform", r.landedOnPlatform},
          {"blocked", r.blocked},
          {"merges", r.merges},
          {"struts", r.struts},
          {"roofs", r.roofs},
          {"risky_area_mm2", num(r.riskyAreaMm2)},
          {"strut_volume_mm3", num(r.strutVolumeMm3)},
          {"roof_volume_mm3", num(r.roofVolumeMm3)},
          {"region_volume_mm3", num(r.regionVolumeMm3)},
          {"printed_volume_mm3", num(r.printedVolumeMm3)},
          {"ms", num(r.ms)}};
}

Json sparseFillJson(const CurvedSparseReport& r) {
  return {{"infill_percent", num(r.infillPercent)},
          {"shell_mm", num(r.shellMm)},
          {"interior_spacing_mm", num(r.interiorSpacingMm)},
          {"sparse_regions", r.sparseRegions},
          {"area_mm2", num(r.areaMm2)},
          {"interior_area_mm2", num(r.interiorAreaMm2)}};
}

Json isoplanarJson(const IsoplanarReport& r) {
  Json j;
  j["theta_deg"] = num(r.thetaDeg);
  j["forced"] = r.forced;
  j["deposition_rate_mm3_s"] = num(r.depositionRateMm3S);
  Json curve = Json::array();
  for (const auto& [theta, rate] : r.curve) curve.push_back({num(theta), num(rate)});
  j["curve"] = curve;
  if (r.paths) {
    const IsoplanarReport::Paths& p = *r.paths;
    j["best_sampled_theta_deg"] = num(p.bestSampledThetaDeg);
    j["path_mm"] = num(p.pathMm);
    j["estimated_time_s"] = num(p.estimatedTimeS);
    j["time_s"] = {{"print", num(p.printS)}, {"joins", num(p.joinsS)}, {"travel", num(p.travelS)}};
    j["mean_feed_mm_s"] = num(p.meanFeedMmS);
    j["benchmark"] = nullptr;
    if (r.benchmark) {
      j["benchmark"] = {{"mean_estimated_time_s", num(r.benchmark->meanEstimatedTimeS)},
                        {"mean_path_mm", num(r.benchmark->meanPathMm)},
                        {"directions", r.benchmark->directions}};
    }
    j["planes"] = p.planes;
    j["curves"] = p.curves;
    j["paths"] = p.paths;
    j["side_step_mm"] = {{"min", num(p.sideStepMinMm)}, {"max", num(p.sideStepMaxMm)}};
    j["mean_width_mm"] = num(p.meanWidthMm);
  }
  j["samples"] = r.samples;
  j["unreachable"] = r.unreachable;
  if (r.paths) {
    j["chord_error_mm"] = num(r.paths->chordErrorMm);
    j["bead_width_mm"] = num(r.paths->beadWidthMm);
    j["layer_height_mm"] = num(r.paths->layerHeightMm);
  }
  if (r.planar) {
    j["sample_spacing_mm"] = num(r.planar->sampleSpacingMm);
    j["sampled_layers"] = r.planar->sampledLayers;
  }
  j["max_feed_mm_s"] = num(r.maxFeedMmS);
  if (!r.paths) j["benchmark"] = nullptr;
  j["timings_ms"] = timings(r.timingsMs);
  if (r.largestRegionThetaDeg) {
    j["largest_region_theta_deg"] = num(*r.largestRegionThetaDeg);
    Json regions = Json::array();
    for (const IsoplanarReport::Region& g : r.regions) {
      regions.push_back({{"layer", g.layer},
                         {"region", g.region},
                         {"theta_deg", num(g.thetaDeg)},
                         {"deposition_rate_mm3_s", num(g.depositionRateMm3S)},
                         {"path_mm", num(g.pathMm)},
                         {"estimated_time_s", num(g.estimatedTimeS)}});
    }
    j["regions"] = regions;
  }
  if (r.surface) {
    const IsoplanarReport::Surface& s = *r.surface;
    j["base_layers"] = s.baseLayers;
    j["base_mm"] = num(s.baseMm);
    j["lift_mm"] = num(s.liftMm);
    j["surface_vertices"] = s.surfaceVertices;
    j["surface_triangles"] = s.surfaceTriangles;
    j["orientation_fallbacks"] = s.orientationFallbacks;
    j["tilt_clamped"] = s.tiltClamped;
    j["gouging_corrections"] = s.gougingCorrections;
    j["gouging_uncorrected"] = s.gougingUncorrected;
  }
  return j;
}

Json voxelJson(const VoxelReport& r) {
  const VoxelReport::Thickness& th = r.thickness;
  return {{"voxels", r.voxels},
          {"solid_voxels", r.solidVoxels},
          {"support_voxels", r.supportVoxels},
          {"missed_voxels", r.missedVoxels},
          {"missed_before_supports", r.missedBeforeSupports},
          {"support_rounds", r.supportRounds},
          {"field_layers", r.fieldLayers},
          {"layer_field", r.layerField},
          {"smooth_iterations", r.smoothIterations},
          {"layer_field_max", r.layerFieldMax},
          {"layers", r.layers},
          {"surface_layers", r.surfaceLayers},
          {"regions", r.regions},
          {"unfilled_regions", r.unfilledRegions},
          {"paths", r.paths},
          {"strategy", r.strategy},
          {"shadow_scheme", r.shadowScheme},
          {"epsilon", num(r.epsilon)},
          {"peel_step", num(r.peelStep)},
          {"voxel_width_mm", num(r.voxelWidthMm)},
          {"iso_step", num(r.isoStep)},
          {"mm_per_field_unit", num(r.mmPerFieldUnit)},
          {"target_layer_mm", num(r.targetLayerMm)},
          {"thickness",
           {{"samples", th.samples},
            {"mean_mm", num(th.meanMm)},
            {"std_mm", num(th.stdMm)},
            {"max_deviation_mm", num(th.maxDeviationMm)},
            {"histogram", {{"min_mm", num(th.histogramMinMm)}, {"bin_mm", num(th.histogramBinMm)}, {"counts", th.histogram}}},
            {"max_ratio", num(th.maxRatio)},
            {"partial_layers", th.partialLayers},
            {"layer_min_mm", numbers(th.layerMinMm)},
            {"layer_max_mm", numbers(th.layerMaxMm)},
            {"layer_partial", th.layerPartial}}},
          {"timings_ms", timings(r.timingsMs)},
          {"shadow_checks", r.shadowChecks},
          {"hull_builds", r.hullBuilds},
          {"orientation_fallbacks", r.orientationFallbacks},
          {"max_tilt_deg", num(r.maxTiltDeg)},
          {"tilt_clamped", r.tiltClamped},
          {"axis_freedom_deg", num(r.axisFreedomDeg)},
          {"axes_freed", r.axesFreed},
          {"gouging_corrections", r.gougingCorrections},
          {"gouging_uncorrected", r.gougingUncorrected},
          {"reordered_paths", r.reorderedPaths},
          {"gouging_ms", num(r.gougingMs)}};
}

Json sequenceJson(const GeodesicReport::Sequence& s) {
  return {{"retractions", s.retractions},
          {"air_move_mm", num(s.airMoveMm)},
          {"collision_free", s.collisionFree},
          {"colliding_nodes", s.collidingNodes},
          {"colliding_lower_bound", s.collidingLowerBound},
          {"criterion2_relaxed", s.criterion2Relaxed},
          {"unavoidable_nodes", s.unavoidableNodes},
          {"ms", num(s.ms)}};
}

Json geodesicJson(const GeodesicReport& r) {
  Json mesher = nullptr;
  if (r.mesher) {
    const GeodesicReport::Mesher& m = *r.mesher;
    mesher = {{"cell_size_mm", num(m.cellSizeMm)},
              {"boundary_vertices", m.boundaryVertices},
              {"max_boundary_distance_mm", num(m.maxBoundaryDistanceMm)},
              {"unsnapped", m.unsnapped},
              {"volume_ratio", num(m.volumeRatio)},
              {"classify_ms", num(m.classifyMs)},
              {"stuff_ms", num(m.stuffMs)},
              {"snap_ms", num(m.snapMs)}};
  }
  const GeodesicReport::Sequence* chosen = nullptr;
  Json traversals = Json::object();
  for (const GeodesicReport::Sequence& s : r.traversals) {
    traversals[s.name] = sequenceJson(s);
    if (s.name == r.sequence) chosen = &s;
  }
  const GeodesicReport::Sequence none;
  if (chosen == nullptr) chosen = &none;
  const GeodesicReport::TetQualityReport& q = r.tetQuality;
  const GeodesicReport::Tree& t = r.tree;
  return {{"tets", r.tets},
          {"vertices", r.vertices},
          {"tet_source", r.tetSource},
          {"mesher", mesher},
          {"tet_quality",
           {{"volume_mm3", num(q.volumeMm3)},
            {"mean_edge_mm", num(q.meanEdgeMm)},
            {"min_dihedral_deg", num(q.minDihedralDeg)},
            {"max_dihedral_deg", num(q.maxDihedralDeg)},
            {"min_radius_ratio", num(q.minRadiusRatio)}}},
          {"sources", r.sources},
          {"base_band_mm", num(r.baseBandMm)},
          {"max_thickness_ratio", num(r.maxThicknessRatio)},
          {"heat_time", num(r.heatTime)},
          {"align_passes", num(r.alignPasses)},
          {"align_retry", {{"retried", r.alignRetried},
                           {"first_left_out_mm", num(r.alignFirstLeftOutMm)},
                           {"ms", num(r.alignRetryMs)}}},
          {"max_geodesic_mm", num(r.maxGeodesicMm)},
          {"interval_mm", num(r.intervalMm)},
          {"step_min_mm", num(r.stepMinMm)},
          {"layers", r.layers},
          {"printed_layers", r.printedLayers},
          {"igds", r.igds},
          {"iso_values_mm", numbers(r.isoValuesMm)},
          {"triangles", r.triangles},
          {"interpolated_triangles", r.interpolatedTriangles},
          {"overhang_avg_deg", numbers(r.overhangAvgDeg)},
          {"overhang_ratio", numbers(r.overhangRatio)},
          {"overhang_max_deg", numbers(r.overhangMaxDeg)},
          {"overhang_avg_all_deg", num(r.overhangAvgAllDeg)},
          {"overhang_max_layer_deg", num(r.overhangMaxLayerDeg)},
          {"thickness",
           {{"mean_mm", numbers(r.thickness.meanMm)},
            {"max_deviation_percent", numbers(r.thickness.maxDeviationPercent)},
            {"mean_deviation_percent", numbers(r.thickness.meanDeviationPercent)},
            {"max_deviation_all_percent", num(r.thickness.maxDeviationAllPercent)}}},
          {"tree",
           {{"nodes", t.nodes},
            {"edges", t.edges},
            {"is_tree", t.isTree},
            {"branch_points", t.branchPoints},
            {"merges", t.merges},
            {"fallback_links", t.fallbackLinks},
            {"max_nodes_per_layer", t.maxNodesPerLayer}}},
          {"nozzle_angle_deg", num(r.nozzleAngleDeg)},
          {"pcs_pairs_tested", r.pcsPairsTested},
          {"sequence", r.sequence},
          {"retractions", chosen->retractions},
          {"air_move_mm", num(chosen->airMoveMm)},
          {"collision_free", chosen->collisionFree},
          {"traversals", traversals},
          {"paths", r.paths},
          {"unfilled_regions", r.unfilledRegions},
          {"orientation_fallbacks", r.orientationFallbacks},
          {"tilt_clamped", r.tiltClamped},
          {"max_tilt_deg", num(r.maxTiltDeg)},
          {"axis_freedom_deg", num(r.axisFreedomDeg)},
          {"axes_freed", r.axesFreed},
          {"gouging_corrections", r.gougingCorrections},
          {"gouging_uncorrected", r.gougingUncorrected},
          {"reordered_paths", r.reorderedPaths},
          {"near_ideal_paths", r.nearIdealPaths},
          {"skipped_segments", r.skippedSegments},
          {"skipped_mm", num(r.skippedMm)},
          {"skipped_layers", r.skippedLayers ? Json::array({r.skippedLayers->first, r.skippedLayers->second})
                                             : Json(nullptr)},
          {"timings_ms", timings(r.timingsMs)}};
}

Json multidirJson(const MultidirReport& r) {
  Json parts = Json::array();
  for (const MultidirReport::Part& p : r.parts) {
    Json pj = {{"print_index", p.printIndex},
               {"direction", vec(p.direction)},
               {"plane", p.planeOffsetMm ? Json({{"normal", vec(p.direction)}, {"offset_mm", num(*p.planeOffsetMm)}})
                                         : Json(nullptr)},
               {"volume_mm3", num(p.volumeMm3)},
               {"components", p.components},
               {"risky_area_mm2", num(p.riskyAreaMm2)},
               {"layers", p.layers}};
    if (p.sliced) {
      pj["support_region_mm3"] = num(p.supportRegionMm3);
      pj["reach_across_mm"] = num(p.reachAcrossMm);
    }
    parts.push_back(pj);
  }
  const MultidirReport::Search& s = r.search;
  return {{"J_G_before", num(r.jgBeforeMm2)},
          {"J_G_after", num(r.jgAfterMm2)},
          {"ratio", r.jgBeforeMm2 > 0 ? num(r.jgAfterMm2 / r.jgBeforeMm2) : 0.0},
          {"alpha_max_deg", num(r.alphaMaxDeg)},
          {"scheme", r.scheme},
          {"dof", r.dof},
          {"rotation_axis", r.rotationAxis ? vec(*r.rotationAxis) : Json(nullptr)},
          {"parts", parts},
          {"part_count", r.parts.size()},
          {"volume_mm3", num(r.volumeMm3)},
          {"cap_area_mm2", num(r.capAreaMm2)},
          {"supports_generated", r.supportsGenerated},
          {"support_volume_mm3", num(r.supportVolumeMm3)},
          {"supports", r.supports ? supportJson(*r.supports) : Json({{"generated", false}})},
          {"search",
           {{"normals", s.normals},
            {"candidates_evaluated", s.candidatesEvaluated},
            {"candidates_checked", s.candidatesChecked},
            {"connectivity_checks", s.connectivityChecks},
            {"refused_floating", s.refusedFloating},
            {"refused_small", s.refusedSmall},
            {"refused_similar", s.refusedSimilar},
            {"beams", s.beams},
            {"levels", s.levels},
            {"axes_tried", s.axesTried},
            {"restarts_run", s.restartsRun},
            {"perturbations", s.perturbations},
            {"perturbations_kept", s.perturbationsKept},
            {"J_G_per_level", numbers(s.jgPerLevel)},
            {"grid_cells", s.gridCells},
            {"cell_mm", num(s.cellMm)}}},
          {"timings_ms", timings(r.timingsMs)}};
}

Json attemptsJson(const std::vector<AttemptSection>& attempts) {
  Json a = Json::array();
  for (const AttemptSection& t : attempts) {
    a.push_back({{"settings", t.settings}, {"why", t.why}, {"sound", t.sound}, {"failures", t.failures}, {"ms", num(t.ms)}});
  }
  return a;
}

Json verifyJson(const VerifySection& v) {
  return {{"mode", v.mode},
          {"sound", v.sound},
          {"inside", num(v.inside)},
          {"coverage", num(v.coverage)},
          {"coverage_judged", v.coverageJudged},
          {"surface_reached", num(v.surfaceReached)},
          {"surface_reach_mm", num(v.surfaceReachMm)},
          {"supported", num(v.supported)},
          {"supported_all", num(v.supportedAll)},
          {"collisions", v.collisions},
          {"limits", v.limits},
          {"left_out_mm", num(v.leftOutMm)},
          {"samples", v.samples},
          {"surface_samples", v.surfaceSamples},
          {"unsupported_samples", v.unsupportedSamples},
          {"criteria", {{"inside", num(v.minInside)}, {"coverage", num(v.minCoverage)}, {"supported", num(v.minSupported)},
                        {"surface_reached", num(v.minReached)}}},
          {"failures", v.failures},
          {"statement", v.statement},
          {"attempts", attemptsJson(v.attempts)},
          {"ms", num(v.ms)}};
}

Json autoJson(const AutoSection& section) {
  Json candidates = Json::array();
  for (const AutoCandidate& c : section.candidates) {
    Json cj = {{"method", c.method},
               {"status", c.status},
               {"message", c.message},
               {"stopped_early", c.stoppedEarly},
               {"support_volume_mm3", num(c.supportVolumeMm3)},
               {"estimated_time_s", num(c.estimatedTimeS)},
               {"timings_ms", {{"total", num(c.totalMs)}}}};
    if (c.verify) {
      const VerifySection& v = *c.verify;
      cj["verify"] = {{"sound", v.sound},         {"inside", num(v.inside)},
                      {"coverage", num(v.coverage)}, {"supported", num(v.supported)},
                      {"collisions", v.collisions}, {"limits", v.limits},
                      {"left_out_mm", num(v.leftOutMm)}, {"failures", v.failures}};
    } else {
      cj["verify"] = nullptr;
    }
    candidates.push_back(cj);
  }
  return {{"candidates", candidates}, {"chosen", section.chosen}, {"reason", section.reason}};
}

Json inputJson(const InputReport& in) {
  Json info = Json::parse(meshInfoJson(in.info));
  info["format"] = in.format;
  for (const std::string& w : in.readWarnings) info["warnings"].push_back(w);
  info["placement"] = matrixJson(in.placement);
  info["placed_bbox"] = bboxJson(in.placedBox);
  return info;
}

}  // namespace

std::string autoSectionJson(const AutoSection& section) { return autoJson(section).dump(); }

std::string inputReportJson(const InputReport& input, const Timings& timingsMs) {
  Json info = inputJson(input);
  if (!timingsMs.empty()) info["timings_ms"] = timings(timingsMs);
  return info.dump();
}

std::string sliceReportJson(const SliceReport& r) {
  Json j;
  j["method"] = r.method;
  j["machine"] = r.machine;
  j["machine_kind"] = machineKindName(r.machineKind);
  j["program_format"] = r.programFormat;
  j["program_extension"] = r.programExtension;
  j["layers"] = r.layers;
  j["sliced_layers"] = r.slicedLayers;
  j["layer_height_mm"] = num(r.layerHeightMm);
  j["path_mm"] = num(r.pathMm);
  j["extrusion_mm"] = num(r.extrusionMm);
  j["travel_mm"] = num(r.travelMm);
  j["retractions"] = r.retractions;
  j["estimated_time_s"] = num(r.estimatedTimeS);
  j["moves"] = r.moves;
  const MotionReport& m = r.motion;
  j["motion"] = {{"samples", m.samples},
                 {"machine_moves", m.machineMoves},
                 {"subdivisions", m.subdivisions},
                 {"filtered_orientations", m.filteredOrientations},
                 {"feed_limited_moves", m.feedLimitedMoves},
                 {"safe_rotations", m.safeRotations},
                 {"max_joint_step", num(m.maxJointStep)},
                 {"pose_cost", num(m.poseCost)},
                 {"greedy_pose_cost", m.greedyPoseCost ? Json(num(*m.greedyPoseCost)) : Json(nullptr)},
                 {"min_singularity", num(m.minSingularity)},
                 {"estimated_time_s", num(m.estimatedTimeS)}};
  j["machine_profile"] = Json::parse(machineJson(r.machineProfile));
  j["direction"] = vec(r.direction);
  j["placement"] = matrixJson(r.placement);
  j["open_chains"] = r.openChains;
  const MethodReport& s = r.sections;
  if (s.voxel) j["voxel"] = voxelJson(*s.voxel);
  if (s.geodesic) j["geodesic"] = geodesicJson(*s.geodesic);
  if (s.multidir) j["multidir"] = multidirJson(*s.multidir);
  if (s.isoplanar) j["isoplanar"] = isoplanarJson(*s.isoplanar);
  if (s.sparseFill) j["sparse_fill"] = sparseFillJson(*s.sparseFill);
  if (s.support) j["support"] = supportJson(*s.support);
  if (s.supportAuto) {
    j["support_auto"] = {{"overhang_percent", num(s.supportAuto->overhangPercent)},
                         {"threshold_percent", num(s.supportAuto->thresholdPercent)},
                         {"overhang_mm2", num(s.supportAuto->overhangMm2)},
                         {"chosen", s.supportAuto->supports ? "projected" : "none"}};
  }
  if (r.verify) j["verify"] = verifyJson(*r.verify);
  j["support_volume_mm3"] = num(r.supportVolumeMm3);
  if (r.autoChoice) j["auto"] = autoJson(*r.autoChoice);
  j["fill"] = r.fill;
  Json warnings = Json::array();
  for (const Warning& w : r.warnings) warnings.push_back({{"code", w.code}, {"message", w.message}});
  j["warnings"] = warnings;
  j["timings_ms"] = timings(r.timingsMs);
  j["mesh"] = inputJson(r.mesh);
  Json settings = Json::object();
  for (const auto& [k, v] : r.settings) settings[k] = v;
  j["settings"] = settings;
  return j.dump();
}

}  // namespace omnislice
