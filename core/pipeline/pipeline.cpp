// SPDX-License-Identifier: MIT
#include "common/stopwatch.h"
#include "pipeline/pipeline.h"

#include <Eigen/Geometry>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <exception>
#include <new>
#include <optional>
#include <nlohmann/json.hpp>

#include "mesh/prepare_mesh.h"
#include "mesh/read_mesh.h"
#include "motion/plan_motion.h"
#include "machine/machine.h"
#include "machine/machine_json.h"
#include "program/read_program.h"
#include "program/write_gcode.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"
#include "kinematics/kinematics.h"
#include "pipeline/isoplanar_fill.h"
#include "pipeline/stage_support.h"
#include "pipeline/support_stage.h"
#include "multidir/projected_supports.h"
#include "slice/support_regions.h"
#include "pipeline/geodesic_method.h"
#include "pipeline/multidir_method.h"
#include "pipeline/surface_method.h"
#include "pipeline/voxel_method.h"
#include "toolpath/toolpath.h"
#include "verify/verify_program.h"

namespace omnislice {

namespace {

using Json = nlohmann::ordered_json;
using stage::finite;

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

Mesh transformMesh(const Mesh& mesh, const Eigen::Matrix4d& t) {
  Mesh out = mesh;
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    const Eigen::Vector3d p = (t * mesh.vertex(i).homogeneous()).head<3>();
    out.positions[3 * i] = p.x();
    out.positions[3 * i + 1] = p.y();
    out.positions[3 * i + 2] = p.z();
  }
  return out;
}

// Rotation taking unit vector d onto +Z by the shortest arc (identity for d = +Z).
Eigen::Matrix3d rotationToZ(const Eigen::Vector3d& d) {
  return Eigen::Quaterniond::FromTwoVectors(d.normalized(), Eigen::Vector3d::UnitZ())
      .toRotationMatrix();
}

// Wrap a progress callback so every stage reports through one function.
struct StageClock {
  Json timings = Json::object();
  Clock::time_point t0 = Clock::now();
  void done(const char* stage) {
    timings[stage] = msSince(t0);
    t0 = Clock::now();
  }
};

// Preview segments from the planned machine path: the part-frame tip path of every move that
// deposits or travels, with the machine values at each segment's end for the machine animation.
PreviewBuffers makePreview(const MachinePath& path, const Toolpath& toolpath) {
  PreviewBuffers p;
  const size_t n = path.moves.size();
  p.positions.reserve(n * 6);
  p.features.reserve(n);
  p.layers.reserve(n);
  p.machine.reserve(n * 6);
  p.axes.reserve(n * 3);
  Eigen::Vector3d prev, prevAxis;
  if (!forwardMap(path.machine, path.start, prev, prevAxis)) prev = Eigen::Vector3d::Zero();
  for (const MachineMove& m : path.moves) {
    const bool draws = m.kind == MoveKind::Print || m.kind == MoveKind::Support ||
                       m.kind == MoveKind::Travel;
    if (draws && (m.tip - prev).squaredNorm() > 0) {
      for (const Eigen::Vector3d& q : {prev, m.tip}) {
        p.positions.push_back(static_cast<float>(q.x()));
        p.positions.push_back(static_cast<float>(q.y()));
        p.positions.push_back(static_cast<float>(q.z()));
      }
      p.features.push_back(m.kind == MoveKind::Travel ? 0 : static_cast<uint8_t>(m.feature));
      p.layers.push_back(static_cast<uint32_t>(std::max(0, m.layer)));
      for (double v : m.values) p.machine.push_back(static_cast<float>(v));
      for (int k = 0; k < 3; ++k) p.axes.push_back(static_cast<float>(m.axis[k]));
      p.curves.push_back(m.source < toolpath.moves.size() && m.kind != MoveKind::Travel
                             ? toolpath.moves[m.source].curve
                             : 0);
    }
    prev = m.tip;
  }
  return p;
}

// Read + validate/repair + place. Shared by slice and info.
struct PreparedInput : Outcome {
  PrepareMeshResult prepared;
  PlaceMeshResult placed;
  std::string format;
  std::vector<std::string> readWarnings;
};

PreparedInput prepareInput(const uint8_t* data, size_t size, const std::string& fileName,
                           const PlacementSettings& placement, const Eigen::Matrix3d& extraRotation,
                           const ProgressFn& progress, StageClock& clock) {
  PreparedInput in;
  if (!reportProgress(progress, "read", 0)) return failed<PreparedInput>(Status::Cancelled, "cancelled");
  ReadMeshResult read = readMesh(data, size, fileName);
  if (!read.ok()) return failed<PreparedInput>(read);
  in.format = read.format;
  in.readWarnings = read.warnings;
  clock.done("read");
  if (!reportProgress(progress, "read", 1)) return failed<PreparedInput>(Status::Cancelled, "cancelled");

  in.prepared = prepareMesh(read.mesh, PrepareOptions{}, progress);
  if (!in.prepared.ok()) return failed<PreparedInput>(in.prepared);
  clock.done("validate");

  if (!reportProgress(progress, "place", 0)) return failed<PreparedInput>(Status::Cancelled, "cancelled");
  in.placed = placeMesh(in.prepared.mesh, placement);
  if (!in.placed.ok()) return failed<PreparedInput>(in.placed);
  if (!extraRotation.isIdentity(1e-15)) {
    // Re-place after turning the slicing direction up (cartesian3 prints along +Z only).
    Eigen::Matrix4d r = Eigen::Matrix4d::Identity();
    r.topLeftCorner<3, 3>() = extraRotation;
    Mesh turned = transformMesh(in.placed.mesh, r);
    PlacementSettings keep;  // no scale, no rotation: only drop to z = 0 and centre
    keep.center = placement.center;
    PlaceMeshResult again = placeMesh(turned, keep);
    if (!again.ok()) return failed<PreparedInput>(again);
    again.transform = again.transform * r * in.placed.transform;
    in.placed = std::move(again);
  }
  clock.done("place");
  if (!reportProgress(progress, "place", 1)) return failed<PreparedInput>(Status::Cancelled, "cancelled");
  return in;
}

Json infoObject(const PreparedInput& in) {
  Json info = Json::parse(meshInfoJson(in.prepared.info));
  info["format"] = in.format;
  if (!in.readWarnings.empty()) {
    for (const auto& w : in.readWarnings) info["warnings"].push_back(w);
  }
  const BoundingBox placedBox = boundingBox(in.placed.mesh);
  info["placement"] = matrixJson(in.placed.transform);
  info["placed_bbox"] = bboxJson(placedBox);
  return info;
}

// The machine of the settings: the user's profile (machine_json) or a built-in by name. The
// nozzle diameter setting is the one truth for the nozzle size.
MachineProfileResult resolveMachine(const Settings& settings) {
  MachineProfileResult r;
  if (!settings.machineJson.empty()) {
    MachineParseResult parsed = machineFromJson(settings.machineJson);
    if (!parsed.ok()) return failed<MachineProfileResult>(Status::InvalidOption, parsed.message);
    r.machine = parsed.machine;
  } else {
    r = builtinMachine(settings.machine, settings.bedSize, settings.nozzleDiameter);
    if (!r.ok()) return r;
  }
  r.machine.nozzle.diameter = settings.nozzleDiameter;
  return r;
}

}  // namespace

SliceOutput runSlice(const uint8_t* data, size_t size, const std::string& fileName,
                     const Settings& settings, const ProgressFn& progress) {
  try {
    const Clock::time_point start = Clock::now();
    if (Outcome v = validateSettings(settings); !v.ok()) return failed<SliceOutput>(v);
    const bool voxel = settings.method == "voxel";
    const bool surface = settings.method == "surface";
    const bool geodesic = settings.method == "geodesic";
    const bool multidir = settings.method == "multidir";
    const bool curvedMethod = voxel || surface || geodesic;
    if (settings.method != "planar" && !voxel && !surface && !geodesic && !multidir) {
      return failed<SliceOutput>(Status::InvalidOption, "method '" + settings.method + "' is not available");
    }
    StageClock clock;
    // cartesian3 lays every layer with the nozzle along +Z: a direction d is realised by turning
    // the part so that d points up (recorded in the placement). Curved-layer methods print on the
    // platform as placed.
    const Eigen::Vector3d d =
        curvedMethod || multidir ? Eigen::Vector3d::UnitZ() : settings.direction.normalized();
    const Eigen::Matrix3d turn = rotationToZ(d);
    PreparedInput in =
        prepareInput(data, size, fileName, settings.placement, turn, progress, clock);
    if (!in.ok()) return failed<SliceOutput>(in);
    if (!surface && !in.prepared.solid.ok()) return failed<SliceOutput>(in.prepared.solid);

    BoundingBox box = boundingBox(in.placed.mesh);
    MachineProfileResult resolved = resolveMachine(settings);
    if (!resolved.ok()) return failed<SliceOutput>(resolved);
    const MachineProfile& machine = resolved.machine;
    if (curvedMethod && machine.kind != MachineKind::Table5 && machine.kind != MachineKind::Robot6) {
      return failed<SliceOutput>(
          Status::InvalidOption,
          std::string("the ") + (voxel      ? "voxel method tilts the nozzle along curved layers"
                                 : geodesic ? "geodesic method tilts the nozzle along curved layers"
                                            : "surface method keeps the nozzle along the surface normal") +
              ": choose a machine with two rotary axes or a robot (table5, robot6), not " +
              machineKindName(machine.kind));
    }
    // The surface method lifts the surface onto its support base first.
    SurfaceMethodOutput surfaceOut;
    if (surface) {
      surfaceOut = runSurfaceMethod(in.placed.mesh, settings, machine, progress);
      if (!surfaceOut.ok()) return failed<SliceOutput>(surfaceOut);
      in.placed.transform = surfaceOut.lift * in.placed.transform;
      in.placed.mesh = std::move(surfaceOut.part);
      box = boundingBox(in.placed.mesh);
    }
    // The multidir method decomposes the solid first (a 4dof axis search may turn it about Z).
    MultidirMethodOutput multidirOut;
    if (multidir) {
      multidirOut = runMultidirMethod(in.placed.mesh, settings, machine, progress);
      if (!multidirOut.ok()) return failed<SliceOutput>(multidirOut);
      in.placed.transform = multidirOut.turn * in.placed.transform;
      in.placed.mesh = std::move(multidirOut.part);
      box = boundingBox(in.placed.mesh);
    }
    const Eigen::Vector3d extent = box.max - box.min;
    // G-code kinds print the planar layers with every rotary axis at 0, where the machine frame is
    // the part frame: the part must fit the linear axes' travel.
    for (int a = 0; a < 3 && machine.kind != MachineKind::Robot6; ++a) {
      auto it = machine.axisLimits.find(std::string(1, "XYZ"[a]));
      if (it == machine.axisLimits.end()) continue;
      const auto& lim = it->second;
      if (box.min[a] < lim.first - 1e-9 || box.max[a] > lim.second + 1e-9) {
        char msg[256];
        std::snprintf(msg, sizeof msg,
                      "the placed model (%.1f x %.1f x %.1f mm) does not fit the bed (%.0f x %.0f x "
                      "%.0f mm); scale it (--scale, --fit-mm) or set bed_size",
                      extent.x(), extent.y(), extent.z(), settings.bedSize.x(), settings.bedSize.y(),
                      settings.bedSize.z());
        return failed<SliceOutput>(Status::InvalidOption, msg);
      }
    }
    const double tooManyLayers = 100000;
    if (!voxel && extent.z() / settings.layerHeight > tooManyLayers) {
      return failed<SliceOutput>(Status::InvalidOption,
                                 "the model needs more than 100000 layers at this layer height");
    }

    // The method: part-frame tool-path plus what its report and preview add.
    PlanLayersResult plan;
    size_t slicedLayers = 0, openChains = 0;
    double layerHeight = settings.layerHeight;
    VoxelMethodOutput voxelOut;
    GeodesicMethodOutput geodesicOut;
    std::string planarIsoplanarJson;
    struct PlanarSupport {
      SupportResult result;
      SupportOptions options;
      double regionVolumeMm3 = 0;
      double ms = 0;
    };
    std::optional<PlanarSupport> planarSupport;
    if (geodesic) {
      // A .tet input brings its own tets: the same placement as its boundary surface.
      TetMesh placedTets;
      const bool haveTets = in.format == "tet";
      if (haveTets) {
        TetMeshResult tets = readTetMesh(data, size);
        if (!tets.ok()) return failed<SliceOutput>(tets);
        placedTets = std::move(tets.mesh);
        const Eigen::Matrix4d& m = in.placed.transform;
        for (size_t v = 0; v < placedTets.vertexCount(); ++v) {
          const Eigen::Vector3d q = m.topLeftCorner<3, 3>() * placedTets.vertex(v) + m.topRightCorner<3, 1>();
          for (int a = 0; a < 3; ++a) placedTets.positions[3 * v + a] = q[a];
        }
      }
      geodesicOut = runGeodesicMethod(in.placed.mesh, haveTets ? &placedTets : nullptr, settings, machine, progress);
      if (!geodesicOut.ok()) return failed<SliceOutput>(geodesicOut);
      for (const auto& [stage, ms] : geodesicOut.timingsMs) clock.timings[stage] = ms;
      clock.t0 = Clock::now();
      plan.toolpath = std::move(geodesicOut.toolpath);
      layerHeight = geodesicOut.layerHeight;
      slicedLayers = static_cast<size_t>(geodesicOut.layers);
    } else if (multidir) {
      for (const auto& [stage, ms] : multidirOut.timingsMs) clock.timings[stage] = ms;
      clock.t0 = Clock::now();
      plan.toolpath = std::move(multidirOut.toolpath);
      slicedLayers = static_cast<size_t>(multidirOut.layers);
    } else if (voxel) {
      voxelOut = runVoxelMethod(in.placed.mesh, settings, machine, progress);
      if (!voxelOut.ok()) return failed<SliceOutput>(voxelOut);
      for (const auto& [stage, ms] : voxelOut.timingsMs) clock.timings[stage] = ms;
      clock.t0 = Clock::now();
      plan.toolpath = std::move(voxelOut.toolpath);
      layerHeight = voxelOut.layerHeight;
      slicedLayers = static_cast<size_t>(voxelOut.layers);
    } else if (surface) {
      for (const auto& [stage, ms] : surfaceOut.timingsMs) clock.timings[stage] = ms;
      clock.t0 = Clock::now();
      plan.toolpath = std::move(surfaceOut.toolpath);
      slicedLayers = static_cast<size_t>(surfaceOut.layers);
    } else {
      SliceOptions sliceOptions;
      sliceOptions.direction = Eigen::Vector3d::UnitZ();
      sliceOptions.layerHeight = settings.layerHeight;
      sliceOptions.firstLayerHeight = settings.effectiveFirstLayerHeight();
      SliceResult slices = sliceMesh(in.placed.mesh, sliceOptions, progress);
      if (!slices.ok()) return failed<SliceOutput>(slices);
      clock.done("slice");
      slicedLayers = slices.layers.size();
      openChains = slices.openChains;

      // fill = isoplanar: every layer's lines run along the drive direction theta* of paper 003
      // (the nozzle stays vertical; f* comes from the machine's linear axes).
      Settings planSettings = settings;
      if (settings.fill == "isoplanar") {
        PlanarDirection dir = planarIsoplanarDirection(slices, settings, machine, progress);
        if (!dir.ok()) return failed<SliceOutput>(dir);
        planSettings.infillAngleDegrees = dir.thetaDegrees;
        planarIsoplanarJson = dir.reportJson;
        clock.done("isoplanar");
      }
      // Supports along the one direction (the projected-support generator with no plane).
      SupportRegionsResult regions;
      const bool withSupports = stage::supportsWanted(settings);
      if (withSupports) {
        const SupportOptions so = stage::supportOptionsFor(settings, 45);
        SupportResult sup = projectedSupports(in.placed.mesh, {}, so, progress);
        if (!sup.ok()) return failed<SliceOutput>(sup);
        regions = supportRegions(supportMesh(sup, 0, so), slices, sliceOptions, {}, settings.support.gapMm);
        if (!regions.ok()) return failed<SliceOutput>(regions);
        const double ms = msSince(clock.t0);
        clock.done("supports");
        planarSupport = PlanarSupport{std::move(sup), so, regions.volumeMm3, ms};
      }
      plan = planLayers(slices, planSettings, 0, progress, withSupports ? &regions.layers : nullptr);
      if (!plan.ok()) return failed<SliceOutput>(plan);
      clock.done("toolpath");
    }

    MotionOptions motionOptions;
    motionOptions.freeRotationSamples = settings.freeRotationSamples;
    motionOptions.smoothOrientations = settings.smoothOrientations;
    motionOptions.filterThresholdDegrees = settings.orientationFilterDegrees;
    motionOptions.chordTolerance = settings.chordTolerance;
    motionOptions.acceleration = settings.acceleration;
    motionOptions.retractSpeed = settings.retractSpeed;
    MachinePath motion = planMachineMotion(plan.toolpath, machine, motionOptions, progress);
    if (!motion.ok()) return failed<SliceOutput>(motion);
    clock.done("motion");

    if (!reportProgress(progress, "program", 0)) return failed<SliceOutput>(Status::Cancelled, "cancelled");
    ProgramInfo pinfo;
    pinfo.method = settings.method;
    pinfo.machine = machine;
    pinfo.placement = in.placed.transform;
    pinfo.filamentDiameter = settings.filamentDiameter;
    pinfo.layerHeight = layerHeight;
    pinfo.lineWidth = settings.effectiveLineWidth();
    pinfo.nozzleTemperature = settings.nozzleTemperature;
    pinfo.bedTemperature = settings.bedTemperature;
    pinfo.acceleration = settings.acceleration;
    pinfo.settings = listSettings(settings);
    if (!parseGcodeDialect(settings.gcodeFlavor, pinfo.dialect) ||
        !parseRobotFormat(settings.robotFormat, pinfo.robotFormat)) {
      return failed<SliceOutput>(Status::InvalidOption, "unknown G-code flavour or robot format");
    }
    WriteProgramResult written = writeProgram(motion, pinfo);
    if (!written.ok()) return failed<SliceOutput>(written);
    clock.done("program");
    if (!reportProgress(progress, "program", 1)) return failed<SliceOutput>(Status::Cancelled, "cancelled");

    const ToolpathStats stats = toolpathStats(plan.toolpath, settings.acceleration);
    SliceOutput out;
    Json info = infoObject(in);
    out.infoJson = info.dump();
    // Layers that deposit material (a sliver thinner than a bead at the top prints nothing); the
    // program has one layer marker for each.
    out.layers = written.layers;
    out.preview = makePreview(motion, plan.toolpath);
    if (surface) {
      PreviewBuffers& p = out.preview;
      p.surfacePositions = std::move(surfaceOut.preview.surfacePositions);
      p.surfaceTriangles = std::move(surfaceOut.preview.surfaceTriangles);
      p.surfaceLayers = std::move(surfaceOut.preview.surfaceLayers);
    }
    if (voxel) {
      PreviewBuffers& p = out.preview;
      p.surfacePositions = std::move(voxelOut.preview.surfacePositions);
      p.surfaceTriangles = std::move(voxelOut.preview.surfaceTriangles);
      p.surfaceLayers = std::move(voxelOut.preview.surfaceLayers);
      p.missedVoxels = std::move(voxelOut.preview.missedVoxels);
      p.supportVoxels = std::move(voxelOut.preview.supportVoxels);
      p.voxelWidth = voxelOut.preview.voxelWidth;
    }
    if (geodesic) {
      PreviewBuffers& p = out.preview;
      PreviewBuffers& g = geodesicOut.preview;
      p.surfacePositions = std::move(g.surfacePositions);
      p.surfaceTriangles = std::move(g.surfaceTriangles);
      p.surfaceLayers = std::move(g.surfaceLayers);
      p.fieldPositions = std::move(g.fieldPositions);
      p.fieldTriangles = std::move(g.fieldTriangles);
      p.fieldValues = std::move(g.fieldValues);
      p.nodePositions = std::move(g.nodePositions);
      p.nodeLayers = std::move(g.nodeLayers);
      p.treeEdges = std::move(g.treeEdges);
      p.sequence = std::move(g.sequence);
      p.skippedSegments = std::move(g.skippedSegments);
      p.skippedLayers = std::move(g.skippedLayers);
    }
    if (multidir) {
      PreviewBuffers& p = out.preview;
      PreviewBuffers& m = multidirOut.preview;
      p.partPositions = std::move(m.partPositions);
      p.partTriangles = std::move(m.partTriangles);
      p.partIds = std::move(m.partIds);
      p.riskyBefore = std::move(m.riskyBefore);
      p.riskyAfter = std::move(m.riskyAfter);
    }
    out.partMesh = std::move(in.placed.mesh);
    out.program = std::move(written.text);
    out.programExtension = programExtension(machine.kind, pinfo.robotFormat);

    Json report;
    report["method"] = settings.method;
    report["machine"] = machine.name;
    report["machine_kind"] = machineKindName(machine.kind);
    report["program_format"] = machine.kind != MachineKind::Robot6 ? "gcode" : settings.robotFormat;
    report["program_extension"] = out.programExtension;
    report["layers"] = out.layers;
    report["sliced_layers"] = slicedLayers;
    report["layer_height_mm"] = layerHeight;
    report["path_mm"] = finite(stats.pathMm);
    // What the program extrudes (unretracts of the motion planner's safe rotations included), the
    // figure `verify` measures.
    double programFilament = 0;
    for (const MachineMove& m : motion.moves) programFilament += std::max(0.0, m.filament);
    report["extrusion_mm"] = finite(programFilament);
    report["travel_mm"] = finite(stats.travelMm);
    report["retractions"] = stats.retractions;
    report["estimated_time_s"] = finite(written.estimatedTimeS);
    report["moves"] = plan.toolpath.moves.size();
    const MotionStats& ms = motion.stats;
    report["motion"] = {{"samples", ms.samples},
                        {"machine_moves", motion.moves.size()},
                        {"subdivisions", ms.subdivisions},
                        {"filtered_orientations", ms.filteredOrientations},
                        {"feed_limited_moves", ms.feedLimitedMoves},
                        {"safe_rotations", ms.safeRotations},
                        {"max_joint_step", finite(ms.maxJointStep)},
                        {"pose_cost", finite(ms.poseCost)},
                        {"greedy_pose_cost", ms.greedyPoseCost >= 0 ? Json(finite(ms.greedyPoseCost))
                                                                    : Json(nullptr)},
                        {"min_singularity", finite(ms.minSingularity)},
                        {"estimated_time_s", finite(ms.estimatedTimeS)}};
    report["machine_profile"] = Json::parse(machineJson(machine));
    report["direction"] = {d.x(), d.y(), d.z()};
    report["placement"] = matrixJson(pinfo.placement);
    report["open_chains"] = openChains;
    if (voxel) report["voxel"] = Json::parse(voxelOut.reportJson);
    if (voxel && !voxelOut.isoplanarJson.empty()) report["isoplanar"] = Json::parse(voxelOut.isoplanarJson);
    if (surface) report["isoplanar"] = Json::parse(surfaceOut.reportJson);
    if (geodesic) report["geodesic"] = Json::parse(geodesicOut.reportJson);
    if (multidir) report["multidir"] = Json::parse(multidirOut.reportJson);
    if (geodesic && !geodesicOut.isoplanarJson.empty()) report["isoplanar"] = Json::parse(geodesicOut.isoplanarJson);
    if (!planarIsoplanarJson.empty()) report["isoplanar"] = Json::parse(planarIsoplanarJson);
    if (planarSupport) {
      report["support"] = Json::parse(stage::supportReportJson(
          planarSupport->result, planarSupport->options, planarSupport->regionVolumeMm3,
          stage::printedSupportVolume(plan.toolpath, settings.filamentDiameter), planarSupport->ms));
    }
    report["fill"] = settings.fill;
    // What the user should know about this result, each saying what, how much and where ([] when
    // nothing): the geodesic method's, and collisions the other curved methods print.
    if (geodesic) out.warnings = geodesicOut.warnings;
    // The voxel and surface methods print the points the gouging search could not clear (the
    // geodesic method leaves them out): verify counts them as collisions.
    auto collisionWarning = [&](const Json& methodReport) {
      const Json left = methodReport.value("gouging_uncorrected", Json(0));
      if (!left.is_number() || left.get<size_t>() == 0) return;
      out.warnings.push_back({"nozzle_collision", std::to_string(left.get<size_t>()) +
                              " tool-path points print with the nozzle cone touching printed material: no "
                              "nozzle axis within the correction and tilt limits clears the part there"});
    };
    if (voxel) collisionWarning(report["voxel"]);
    if (surface) collisionWarning(report["isoplanar"]);
    Json warnings = Json::array();
    for (const Warning& w : out.warnings) warnings.push_back({{"code", w.code}, {"message", w.message}});
    report["warnings"] = warnings;
    Json t = clock.timings;
    t["total"] = msSince(start);
    report["timings_ms"] = t;
    report["mesh"] = info;
    Json set = Json::object();
    for (const auto& [k, v] : pinfo.settings) set[k] = v;
    report["settings"] = set;
    out.reportJson = report.dump();
    return out;
  } catch (const std::bad_alloc&) {
    return failed<SliceOutput>(Status::Internal, "out of memory while slicing");
  } catch (const std::exception& e) {
    return failed<SliceOutput>(Status::Internal, std::string("unexpected failure: ") + e.what());
  }
}

InfoOutput runInfo(const uint8_t* data, size_t size, const std::string& fileName,
                   const PlacementSettings& placement, const ProgressFn& progress) {
  try {
    StageClock clock;
    PreparedInput in = prepareInput(data, size, fileName, placement, Eigen::Matrix3d::Identity(),
                                    progress, clock);
    if (!in.ok()) return failed<InfoOutput>(in);
    Json info = infoObject(in);
    info["timings_ms"] = clock.timings;
    InfoOutput out;
    out.infoJson = info.dump();
    out.partMesh = std::move(in.placed.mesh);
    return out;
  } catch (const std::bad_alloc&) {
    return failed<InfoOutput>(Status::Internal, "out of memory while reading the mesh");
  } catch (const std::exception& e) {
    return failed<InfoOutput>(Status::Internal, std::string("unexpected failure: ") + e.what());
  }
}

VerifyOutput runVerify(const std::string& programText, const uint8_t* meshData, size_t meshSize,
                       const std::string& meshName, const ProgressFn& progress) {
  try {
    ParsedProgram program = readProgram(programText);
    if (!program.ok()) return failed<VerifyOutput>(program);
    ReadMeshResult read = readMesh(meshData, meshSize, meshName);
    if (!read.ok()) return failed<VerifyOutput>(read);
    PrepareMeshResult prepared = prepareMesh(read.mesh, PrepareOptions{}, progress);
    if (!prepared.ok()) return failed<VerifyOutput>(prepared);
    Mesh part;
    if (program.method == "surface") {
      // A surface program prints the solid between the platform and the surface (its base and
      // its surface layer): the same construction as the slice, from the placed surface.
      SurfacePartResult built = surfacePart(transformMesh(prepared.mesh, program.placement));
      if (!built.ok()) return failed<VerifyOutput>(built);
      part = std::move(built.part);
    } else {
      if (!prepared.solid.ok()) return failed<VerifyOutput>(prepared.solid);
      part = transformMesh(prepared.mesh, program.placement);
    }
    VerifyReport report = verifyProgram(program, part, VerifyOptions{}, progress);
    if (!report.ok()) return failed<VerifyOutput>(report);
    VerifyOutput out;
    out.verifyJson = verifyReportJson(report);
    return out;
  } catch (const std::bad_alloc&) {
    return failed<VerifyOutput>(Status::Internal, "out of memory while verifying");
  } catch (const std::exception& e) {
    return failed<VerifyOutput>(Status::Internal, std::string("unexpected failure: ") + e.what());
  }
}

}  // namespace omnislice
