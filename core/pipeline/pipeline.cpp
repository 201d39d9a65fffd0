// SPDX-License-Identifier: MIT
#include "pipeline/pipeline.h"

#include <algorithm>
#include <atomic>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <exception>
#include <mutex>
#include <new>
#include <thread>

#include "common/math_constants.h"
#include "common/memory_budget.h"
#include "common/parallel.h"
#include "common/stopwatch.h"
#include "machine/machine.h"
#include "machine/machine_json.h"
#include "program/png.h"
#include "program/thumbnail.h"
#include "mesh/place_mesh.h"
#include "mesh/prepare_mesh.h"
#include "mesh/read_mesh.h"
#include "motion/plan_motion.h"
#include "pipeline/auto_choice.h"
#include "pipeline/method.h"
#include "pipeline/curved_supports.h"
#include "pipeline/soundness.h"
#include "program/read_program.h"
#include "program/write_gcode.h"
#include "surface/height_field_solid.h"
#include "toolpath/toolpath.h"
#include "verify/verify_program.h"

namespace omnislice {

namespace {

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
  return Eigen::Quaterniond::FromTwoVectors(d.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// The pipeline's own stages' timings, in the order they ran.
struct StageClock {
  Timings timings;
  Clock::time_point t0 = Clock::now();
  void done(const char* stage) {
    timings.emplace_back(stage, msSince(t0));
    t0 = Clock::now();
  }
};

// Read + validate/repair + place. Shared by slice and info.
struct PreparedInput : Outcome {
  PrepareMeshResult prepared;
  PlaceMeshResult placed;
  std::string format;
  std::vector<std::string> readWarnings;
};

// A warning when the placed part is implausibly small (under 1 mm: modelled in metres?) or large
// (over 2 m: in micrometres?), with the scale that would make it a part of usual size; "" when
// plausible.
std::string implausibleUnits(const BoundingBox& box) {
  const double side = (box.max - box.min).maxCoeff();
  if (!(side > 0) || !std::isfinite(side)) return {};
  double factor = 0;
  const char* unit = "";
  if (side < 1) {
    factor = 1000, unit = "metres";
  } else if (side > 2000) {
    factor = 0.001, unit = "micrometres";
  } else {
    return {};
  }
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "units: the part is %.4g mm across, an unusual size for a print; if the file is in %s, "
                "scale %g makes it %.4g mm (or fit_mm sets its largest side)",
                side, unit, factor, side * factor);
  return buf;
}

PreparedInput prepareInput(const uint8_t* data, size_t size, const std::string& fileName,
                           const PlaceOptions& placement, const Eigen::Matrix3d& extraRotation,
                           bool closeSolid, const ProgressFn& progress, StageClock& clock) {
  PreparedInput in;
  if (!reportProgress(progress, "read", 0)) return failed<PreparedInput>(Status::Cancelled, "cancelled");
  ReadMeshResult read = readMesh(data, size, fileName);
  if (!read.ok()) return failed<PreparedInput>(read);
  in.format = read.format;
  in.readWarnings = read.warnings;
  clock.done("read");
  if (!reportProgress(progress, "read", 1)) return failed<PreparedInput>(Status::Cancelled, "cancelled");

  PrepareOptions prepareOptions;
  prepareOptions.closeSolid = closeSolid;
  prepareOptions.uniteShells = closeSolid;
  in.prepared = prepareMesh(read.mesh, prepareOptions, progress);
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
    PlaceOptions keep;  // no scale, no rotation: only drop to z = 0 and centre
    keep.center = placement.center;
    PlaceMeshResult again = placeMesh(turned, keep);
    if (!again.ok()) return failed<PreparedInput>(again);
    again.transform = again.transform * r * in.placed.transform;
    in.placed = std::move(again);
  }
  if (std::string units = implausibleUnits(boundingBox(in.placed.mesh)); !units.empty()) {
    in.readWarnings.push_back(units);
  }
  clock.done("place");
  if (!reportProgress(progress, "place", 1)) return failed<PreparedInput>(Status::Cancelled, "cancelled");
  return in;
}

// repair = auto and a method that slices a solid: prepareMesh closes what does not bound one.
bool closesSolid(const Settings& settings) {
  return settings.repair == RepairMode::Auto && methodEntry(settings.method).needsSolid;
}

// The input's report: the mesh as read and validated, placed by `placement` as `placed`.
InputReport inputReport(const PreparedInput& in, const Eigen::Matrix4d& placement, const Mesh& placed) {
  InputReport r;
  r.info = in.prepared.info;
  r.format = in.format;
  r.readWarnings = in.readWarnings;
  r.placement = placement;
  r.placedBox = boundingBox(placed);
  return r;
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
  if (!settings.axisLetters.empty()) {
    const Outcome letters = checkAxisLetters(r.machine.kind, settings.axisLetters);
    if (!letters.ok()) return failed<MachineProfileResult>(Status::InvalidOption, "setting 'axis_letters': " + letters.message);
    r.machine.axisLetters = settings.axisLetters;
  }
  return r;
}

// The method prints on this kind of machine.
Outcome methodRunsOn(const MethodEntry& method, const MachineProfile& machine) {
  for (MachineKind k : method.machines) {
    if (k == machine.kind) return {};
  }
  return {Status::InvalidOption, std::string("the ") + methodName(method.method) + " method " + method.machineNeed +
                                     ", not " + machineKindName(machine.kind)};
}

// G-code kinds print the planar layers with every rotary axis at 0, where the machine frame is
// the part frame: the part must fit the linear axes' travel.
Outcome fitsMachine(const Mesh& part, const MachineProfile& machine, const Settings& settings) {
  if (machine.kind == MachineKind::Robot6) return {};
  const BoundingBox box = boundingBox(part);
  const Eigen::Vector3d extent = box.max - box.min;
  for (int a = 0; a < 3; ++a) {
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
      return {Status::InvalidOption, msg};
    }
  }
  return {};
}

Outcome layerCountBound(const Mesh& part, const Settings& settings) {
  const BoundingBox box = boundingBox(part);
  if ((box.max.z() - box.min.z()) / settings.layerHeight > 100000) {
    return {Status::InvalidOption, "the model needs more than 100000 layers at this layer height"};
  }
  return {};
}

// A .tet input's own tets, placed as its boundary surface was.
Outcome placedTets(const uint8_t* data, size_t size, const Eigen::Matrix4d& m, std::optional<TetMesh>& out) {
  TetMeshResult tets = readTetMesh(data, size);
  if (!tets.ok()) return tets;
  TetMesh& placed = out.emplace(std::move(tets.mesh));
  for (size_t v = 0; v < placed.vertexCount(); ++v) {
    const Eigen::Vector3d q = m.topLeftCorner<3, 3>() * placed.vertex(v) + m.topRightCorner<3, 1>();
    for (int a = 0; a < 3; ++a) placed.positions[3 * v + a] = q[a];
  }
  return {};
}

MotionOptions motionOptions(const Settings& settings) {
  MotionOptions o;
  o.freeRotationSamples = settings.freeRotationSamples;
  o.smoothOrientations = settings.smoothOrientations;
  o.filterThresholdDegrees = settings.orientationFilterDegrees;
  o.chordTolerance = settings.chordTolerance;
  o.acceleration = settings.acceleration;
  o.junctionDeviation = settings.junctionDeviation;
  o.retractSpeed = settings.retractSpeed;
  return o;
}

ProgramInfo programInfo(const Settings& settings, const MachineProfile& machine, const Eigen::Matrix4d& placement,
                        double layerHeight) {
  ProgramInfo p;
  p.method = methodName(settings.method);
  p.machine = machine;
  p.placement = placement;
  p.filamentDiameter = settings.filamentDiameter;
  p.layerHeight = layerHeight;
  p.lineWidth = settings.effectiveLineWidth();
  p.nozzleTemperature = settings.nozzleTemperature;
  p.bedTemperature = settings.bedTemperature;
  p.fanPercent = settings.fanPercent;
  p.fanOffLayers = settings.fanOffLayers;
  p.bridgeFanPercent = settings.bridgeFanPercent;
  p.acceleration = settings.acceleration;
  p.junctionDeviation = settings.junctionDeviation;
  p.settings = listSettings(settings);
  p.dialect = settings.gcodeFlavor;
  p.robotFormat = settings.robotFormat;
  return p;
}

// Support the program prints: the filament of its support moves as volume (mm^3).
double supportVolume(const MachinePath& motion, double filamentDiameterMm) {
  double filament = 0;
  for (const MachineMove& m : motion.moves) {
    if (m.kind == MoveKind::Support && m.filament > 0) filament += m.filament;
  }
  return filament * kPi / 4 * filamentDiameterMm * filamentDiameterMm;
}

MotionReport motionReport(const MachinePath& motion) {
  const MotionStats& ms = motion.stats;
  MotionReport r;
  r.samples = ms.samples;
  r.machineMoves = motion.moves.size();
  r.subdivisions = ms.subdivisions;
  r.filteredOrientations = ms.filteredOrientations;
  r.feedLimitedMoves = ms.feedLimitedMoves;
  r.safeRotations = ms.safeRotations;
  r.maxJointStep = ms.maxJointStep;
  r.poseCost = ms.poseCost;
  if (ms.greedyPoseCost >= 0) r.greedyPoseCost = ms.greedyPoseCost;
  r.minSingularity = ms.minSingularity;
  r.estimatedTimeS = ms.estimatedTimeS;
  return r;
}

// The report of a slice from the method's result, the motion and the program (the stages'
// timings, the verification and the input's figures are added by runSlice).
SliceReport sliceReport(const Settings& settings, const MachineProfile& machine, MethodResult& result,
                        const MachinePath& motion, const WriteProgramResult& written, const ProgramInfo& pinfo,
                        const Eigen::Vector3d& direction, const Eigen::Matrix4d& placement) {
  SliceReport r;
  const ToolpathStats stats = toolpathStats(result.toolpath, settings.acceleration);
  r.method = methodName(settings.method);
  r.machine = machine.name;
  r.machineKind = machine.kind;
  r.programFormat = machine.kind != MachineKind::Robot6 ? "gcode" : robotFormatName(settings.robotFormat);
  r.programExtension = programExtension(machine.kind, pinfo.robotFormat);
  r.layers = written.layers;
  r.slicedLayers = result.slicedLayers;
  r.layerHeightMm = result.layerHeight;
  r.pathMm = stats.pathMm;
  r.supportVolumeMm3 = supportVolume(motion, settings.filamentDiameter);
  // What the program extrudes (unretracts of the motion planner's safe rotations included), the
  // figure `verify` measures.
  for (const MachineMove& m : motion.moves) r.extrusionMm += std::max(0.0, m.filament);
  r.travelMm = stats.travelMm;
  r.retractions = stats.retractions;
  r.estimatedTimeS = written.estimatedTimeS;
  r.moves = result.toolpath.moves.size();
  r.motion = motionReport(motion);
  r.machineProfile = machine;
  r.direction = direction;
  r.placement = placement;
  r.openChains = result.openChains;
  r.sections = std::move(result.report);
  r.fill = findSetting("fill")->format(settings);
  r.warnings = result.warnings;
  r.settings = pinfo.settings;
  return r;
}

// One program made and checked: the method with these settings, the motion, the program and,
// unless verify is off, the check (soundness.h).
struct Attempt : Outcome {
  bool dominated = false;  // stopped before the check: a sound candidate with less support, or as
                           // little and less time, was made already (AutoBound)
  Settings settings;
  MethodResult result;
  Mesh printed;                                        // the part as printed (part frame)
  Eigen::Matrix4d placement = Eigen::Matrix4d::Identity();
  MachinePath motion;
  ProgramInfo pinfo;
  WriteProgramResult written;
  std::optional<SoundnessCheck> check;
  Timings timingsMs;  // the method's stages, motion, program, verify
  double ms = 0;
};

Attempt programAndCheck(Attempt a, StageClock& clock, const MachineProfile& machine, VerifyMode mode,
                        const ProgressFn& progress, const AutoBound* bound, Clock::time_point start);

Attempt makeAttempt(const PlacedPart& part, const Settings& settings, const MachineProfile& machine,
                    const MethodEntry& method, VerifyMode mode, const ProgressFn& progress,
                    const AutoBound* bound = nullptr) {
  const Clock::time_point start = Clock::now();
  Attempt a;
  a.settings = settings;
  // The method: a part-frame tool path with its report and preview sections.
  a.result = method.run(part, MethodContext{settings, machine, progress});
  if (!a.result.ok()) return failed<Attempt>(a.result);
  StageClock clock;
  clock.timings = a.result.timingsMs;
  a.placement = part.placement;
  if (a.result.part) {
    a.printed = std::move(*a.result.part);
    a.result.part.reset();
    a.placement = a.result.turn * part.placement;
    if (Outcome o = fitsMachine(a.printed, machine, settings); !o.ok()) return failed<Attempt>(o);
  } else {
    a.printed = part.mesh;
  }
  return programAndCheck(std::move(a), clock, machine, mode, progress, bound, start);
}

// The motion, the program and (unless verify is off) the check of an attempt whose tool path is
// made (a.result, a.printed, a.placement, a.settings).
Attempt programAndCheck(Attempt a, StageClock& clock, const MachineProfile& machine, VerifyMode mode,
                        const ProgressFn& progress, const AutoBound* bound, Clock::time_point start) {
  const Settings& settings = a.settings;
  // Motion and program.
  if (Outcome o = checkMemoryBudget(double(a.result.toolpath.moves.size()) * memory_cost::kMoveBytes,
                                    settings.memoryMb,
                                    "the program (" + std::to_string(a.result.toolpath.moves.size()) +
                                        " moves, with its machine motion)",
                                    "raise layer_height, line_width or memory_mb, or scale the model down");
      !o.ok()) {
    return failed<Attempt>(o);
  }
  a.motion = planMachineMotion(a.result.toolpath, machine, motionOptions(settings), progress);
  if (!a.motion.ok()) return failed<Attempt>(a.motion);
  clock.done("motion");
  if (!reportProgress(progress, "program", 0)) return failed<Attempt>(Status::Cancelled, "cancelled");
  a.pinfo = programInfo(settings, machine, a.placement, a.result.layerHeight);
  if (machine.kind != MachineKind::Robot6) {
    for (const auto& [w, h] : settings.thumbnails) {
      const ThumbnailImage img = renderThumbnail(a.printed, w, h);
      a.pinfo.thumbnails.push_back({img.width, img.height, encodePngRgba(img.rgba, img.width, img.height)});
    }
  }
  a.written = writeProgram(a.motion, a.pinfo);
  if (!a.written.ok()) return failed<Attempt>(a.written);
  clock.done("program");
  if (!reportProgress(progress, "program", 1)) return failed<Attempt>(Status::Cancelled, "cancelled");
  if (bound && bound->sound) {
    // Its check could make it sound at best: it loses on support, or on time at equal support.
    if (dominatedBy(*bound, supportVolume(a.motion, settings.filamentDiameter), a.written.estimatedTimeS)) {
      a.dominated = true;
      a.timingsMs = std::move(clock.timings);
      a.ms = msSince(start);
      return a;
    }
  }

  // Simulate what was made (pipeline/soundness.h) before anything is written.
  if (mode != VerifyMode::Off) {
    a.check = checkProgram(a.written.text, a.printed, settings, machine, a.result, mode, {}, progress);
    if (!a.check->ok()) return failed<Attempt>(*a.check);
    clock.done("verify");
    // The method's own count of points it could not clear (nozzle_collision) is conservative
    // (a wider cone, points as balls); where the simulation finds no collision it is dropped
    // rather than contradict the verdict.
    if (a.check->section.collisions == 0) {
      auto& ws = a.result.warnings;
      ws.erase(std::remove_if(ws.begin(), ws.end(), [](const Warning& w) { return w.code == "nozzle_collision"; }),
               ws.end());
    }
    if (!a.check->section.sound && mode == VerifyMode::Warn) {
      a.result.warnings.push_back({"unsound_program", a.check->section.statement});
    }
  }
  a.timingsMs = std::move(clock.timings);
  a.ms = msSince(start);
  return a;
}

// The report's entry for a program made again with `settings` ("key=value") for `why`.
AttemptSection attemptSection(const std::string& settings, const std::string& why, const Attempt& again) {
  AttemptSection t;
  t.settings = settings;
  t.why = why;
  t.ms = again.ms;
  if (again.ok() && again.check) {
    t.sound = again.check->section.sound;
    t.failures = again.check->section.failures;
  } else {
    t.failures = {again.message};
  }
  return t;
}

// Supports as the last resort of the curved methods (curved_supports.h): support = projected adds
// fins under whatever the check finds printed over air; auto only when beads over air are the one
// failure left, and the finned program is delivered only when its check finds it sound.
bool curvedSupportsWanted(const Settings& settings, const SoundnessCheck& check) {
  if (settings.method != Method::Voxel && settings.method != Method::Geodesic) return false;
  if (check.unsupportedTips.empty() || settings.support.mode == SupportMode::None) return false;
  if (settings.support.mode == SupportMode::Projected) return true;
  const VerifySection& v = check.section;
  return !v.sound && v.inside >= v.minInside && (!v.coverageJudged || v.coverage >= v.minCoverage) &&
         v.surfaceReached >= v.minReached && v.limits == 0 && v.collisions == 0 && v.leftOutMm <= 0 &&
         v.supported < v.minSupported;
}

// The attempt `made` again with fins under its unsupported samples: motion, program and check of
// the finned tool path (the method does not run again).
Attempt withCurvedSupports(const Attempt& made, const MachineProfile& machine, VerifyMode mode,
                           const ProgressFn& progress, CurvedSupportResult& fins) {
  const Clock::time_point start = Clock::now();
  StageClock clock;  // its first stage: the fins
  const Settings& settings = made.settings;
  CurvedSupportOptions o;
  o.layerHeightMm = made.result.layerHeight > 0 ? made.result.layerHeight : settings.layerHeight;
  o.lineWidthMm = settings.effectiveLineWidth();
  o.filamentDiameterMm = settings.filamentDiameter;
  o.speedMmS = settings.outerWallSpeed;
  o.travelSpeedMmS = settings.travelSpeed;
  o.retractMm = settings.retractLength;
  o.retractSpeedMmS = settings.retractSpeed;
  o.coneHalfAngleDeg = machine.nozzle.coneHalfAngleDegrees;
  o.coneLengthMm = machine.nozzle.coneLength;
  fins = addCurvedSupports(made.result.toolpath, made.printed, made.check->unsupportedTips, o, progress);
  if (fins.cancelled) return failed<Attempt>(Status::Cancelled, "cancelled");
  if (fins.columns == 0) return failed<Attempt>(Status::InvalidOption, "no fin: no sample over air has room under it");
  Attempt a;
  a.settings = settings;
  a.result = made.result;
  a.result.toolpath = std::move(fins.toolpath);
  auto& ws = a.result.warnings;  // the check of the finned program says again what it must
  ws.erase(std::remove_if(ws.begin(), ws.end(), [](const Warning& w) { return w.code == "unsound_program"; }),
           ws.end());
  fins.toolpath = {};
  a.printed = made.printed;
  a.placement = made.placement;
  clock.timings = made.timingsMs;
  // The method's stages stay (it did not run again); motion, program and check follow the fins.
  clock.timings.erase(std::remove_if(clock.timings.begin(), clock.timings.end(),
                                     [](const auto& t) { return t.first == "motion" || t.first == "program" ||
                                                                t.first == "verify"; }),
                      clock.timings.end());
  clock.done("supports");
  return programAndCheck(std::move(a), clock, machine, mode, progress, nullptr, start);
}

// Curved supports after the remedies (curvedSupportsWanted): the fins' program is tried, listed in
// `tried` and delivered into `made` when sound (or with support = projected); `retryMs` then counts
// what was not delivered. False when cancelled.
bool supportsLastResort(Attempt& made, std::vector<AttemptSection>& tried, double& retryMs, bool& delivered,
                        const MachineProfile& machine, VerifyMode mode, const ProgressFn& progress) {
  if (!reportProgress(progress, "retry", 1)) return false;
  const Settings& settings = made.settings;
  CurvedSupportResult fins;
  Attempt finned;
  try {
    finned = withCurvedSupports(made, machine, mode, progress, fins);
  } catch (const std::bad_alloc&) {
    finned = failed<Attempt>(allocationFailed("adding supports"));
  }
  if (finned.status == Status::Cancelled) return false;
  if (fins.columns == 0) {  // nothing to print: nothing made again
    if (fins.copies > CurvedSupportOptions().maxCopies) {
      made.result.warnings.push_back(
          {"curved_supports", "no support fins: the samples printed over air would need " + std::to_string(fins.copies) +
                                  " support beads, more than " + std::to_string(CurvedSupportOptions().maxCopies)});
    }
    return true;
  }
  const AttemptSection t = attemptSection(
      "support=projected", "beads over air: support fins under them, printed before the paths they carry", finned);
  tried.push_back(t);
  if (!t.sound && !(finned.ok() && settings.support.mode == SupportMode::Projected)) return true;
  char text[600];
  std::snprintf(text, sizeof text,
                "support fins under %zu of the %zu surface samples printed over air (%zu fins, %.0f mm of support "
                "path, %zu standing on the platform); none under %zu with part below them (not an underside), "
                "%zu whose column a path printed later would strike, %zu landing on part printed after them, %zu "
                "with no room",
                fins.columns, fins.samples, fins.fins, fins.pathMm, fins.onPlatform, fins.notUnderside,
                fins.inLaterCones, fins.landsLater, fins.blocked - fins.inLaterCones - fins.landsLater);
  finned.result.warnings.push_back({"curved_supports", text});
  // The first program's motion, program and check, and the remedies before, were not delivered
  // (its method's stages are the delivered program's).
  retryMs = 0;
  for (const auto& [stage, ms] : made.timingsMs) {
    if (stage == "motion" || stage == "program" || stage == "verify") retryMs += ms;
  }
  for (size_t j = 0; j + 1 < tried.size(); ++j) retryMs += tried[j].ms;
  if (t.sound && !made.check->section.sound) {
    finned.result.warnings.push_back({"remedied", remediedMessage(made.check->section, tried)});
  }
  made = std::move(finned);
  delivered = true;
  return true;
}

}  // namespace

// runSlice for one method (not auto). With a bound (auto), a program that cannot beat it is not
// checked: *dominated is set and the output is a failure naming the candidate it lost to.
static SliceOutput runOneMethod(const uint8_t* data, size_t size, const std::string& fileName, const Settings& settings,
                         const ProgressFn& progress, const AutoBound* bound, bool* dominated) {
  try {
    const Clock::time_point start = Clock::now();
    if (Outcome v = validateSettings(settings); !v.ok()) return failed<SliceOutput>(v);
    const MethodEntry& method = methodEntry(settings.method);
    StageClock clock;

    // Read, validate, place. A method that slices along a direction d gets the part turned so
    // that d points up (recorded in the placement); the others print on the platform as placed.
    const Eigen::Vector3d d =
        method.slicesAlongDirection ? Eigen::Vector3d(settings.direction.normalized()) : Eigen::Vector3d::UnitZ();
    PreparedInput in = prepareInput(data, size, fileName, settings.placement, rotationToZ(d),
                                    closesSolid(settings), progress, clock);
    if (!in.ok()) return failed<SliceOutput>(in);
    if (method.needsSolid && !in.prepared.solid.ok()) {
      Outcome refused = in.prepared.solid;
      if (settings.repair == RepairMode::None) {
        refused.message += " (repair = none; repair = auto closes holes and splits non-manifold edges and vertices)";
      }
      return failed<SliceOutput>(refused);
    }
    MachineProfileResult resolved = resolveMachine(settings);
    if (!resolved.ok()) return failed<SliceOutput>(resolved);
    const MachineProfile& machine = resolved.machine;
    if (Outcome o = methodRunsOn(method, machine); !o.ok()) return failed<SliceOutput>(o);
    if (Outcome o = fitsMachine(in.placed.mesh, machine, settings); !o.ok()) return failed<SliceOutput>(o);
    if (method.boundsLayerCount) {
      if (Outcome o = layerCountBound(in.placed.mesh, settings); !o.ok()) return failed<SliceOutput>(o);
    }
    PlacedPart part;
    part.mesh = std::move(in.placed.mesh);
    part.placement = in.placed.transform;
    if (method.usesInputTets && in.format == "tet") {
      if (Outcome o = placedTets(data, size, part.placement, part.tets); !o.ok()) return failed<SliceOutput>(o);
    }

    // The method, the motion, the program and the check: one attempt. When the check finds the
    // program unsound, the remedies the slicer can apply itself (soundness.h automaticRemedies)
    // are tried, up to verify_attempts programs in all, and the first sound one is delivered;
    // when none is, the one made with the user's settings, its statement naming what was tried.
    const VerifyMode mode = effectiveVerifyMode(settings);
    Attempt made = makeAttempt(part, settings, machine, method, mode, progress, bound);
    if (!made.ok()) return failed<SliceOutput>(made);
    if (made.dominated) {
      if (dominated) *dominated = true;
      char text[300];
      const double support = supportVolume(made.motion, settings.filamentDiameter);
      std::snprintf(text, sizeof text,
                    "stopped before its check: %.0f mm^3 of support and %.2f h, against %s's sound program with "
                    "%.0f mm^3 and %.2f h",
                    support, made.written.estimatedTimeS / 3600, bound->method.c_str(), bound->supportVolumeMm3,
                    bound->timeS / 3600);
      SliceOutput out = failed<SliceOutput>(Status::Cancelled, text);
      out.report.supportVolumeMm3 = support;
      out.report.estimatedTimeS = made.written.estimatedTimeS;
      return out;
    }
    std::vector<AttemptSection> tried;
    double retryMs = 0;  // attempts not delivered
    bool finnedDelivered = false;  // the delivered program is the one with curved supports
    if (made.check && (!made.check->section.sound || curvedSupportsWanted(settings, *made.check))) {
      const std::vector<SettingRemedy> remedies =
          automaticRemedies(made.check->section, settings, made.result.leftOutLowestMm);
      for (size_t k = 0; k < remedies.size() && k + 1 < size_t(settings.verifyAttempts); ++k) {
        Settings changed = settings;
        if (Outcome o = setSetting(changed, remedies[k].key, remedies[k].value); !o.ok()) continue;
        // Viewers see the stages again after this one (the method's, motion, program, verify).
        if (!reportProgress(progress, "retry", double(k) / double(remedies.size()))) {
          return failed<SliceOutput>(Status::Cancelled, "cancelled");
        }
        // A second program that does not fit in memory leaves the first one delivered.
        Attempt again;
        try {
          again = makeAttempt(part, changed, machine, method, mode, progress);
        } catch (const std::bad_alloc&) {
          again = failed<Attempt>(allocationFailed("making the program again"));
        }
        if (again.status == Status::Cancelled) return failed<SliceOutput>(again);
        const AttemptSection t = attemptSection(remedies[k].key + "=" + remedies[k].value, remedies[k].why, again);
        tried.push_back(t);
        if (t.sound) {
          retryMs = made.ms;
          for (size_t j = 0; j + 1 < tried.size(); ++j) retryMs += tried[j].ms;
          again.result.warnings.push_back({"remedied", remediedMessage(made.check->section, tried)});
          made = std::move(again);
          break;
        }
      }
      // Asked for (projected), or a remedy within verify_attempts (auto).
      const bool finsAllowed = settings.support.mode == SupportMode::Projected ||
                               tried.size() + 1 < size_t(settings.verifyAttempts);
      if (finsAllowed && curvedSupportsWanted(settings, *made.check) &&
          !supportsLastResort(made, tried, retryMs, finnedDelivered, machine, mode, progress)) {
        return failed<SliceOutput>(Status::Cancelled, "cancelled");
      }
      noteAttempts(made.check->section, tried);
      if (!made.check->section.sound && !finnedDelivered) {
        for (const AttemptSection& t : tried) retryMs += t.ms;
        for (Warning& w : made.result.warnings) {
          if (w.code == "unsound_program") w.message = made.check->section.statement;
        }
      }
    }
    if (!made.check && settings.support.mode == SupportMode::Projected &&
        (settings.method == Method::Voxel || settings.method == Method::Geodesic)) {
      made.result.warnings.push_back(
          {"curved_supports", "no support fins: they go under what the check finds printed over air, and verify = off "
                              "skips the check"});
    }
    MethodResult& result = made.result;
    std::optional<SoundnessCheck>& check = made.check;
    const MachinePath& motion = made.motion;
    const ProgramInfo& pinfo = made.pinfo;
    WriteProgramResult& written = made.written;
    part.mesh = std::move(made.printed);
    part.placement = made.placement;
    clock.timings.insert(clock.timings.end(), made.timingsMs.begin(), made.timingsMs.end());
    if (!tried.empty()) clock.timings.emplace_back("retries", retryMs);
    clock.t0 = Clock::now();

    // The result and its report.
    SliceOutput out;
    out.layers = written.layers;  // layers that deposit material: one program marker each
    out.programExtension = programExtension(machine.kind, pinfo.robotFormat);
    out.warnings = result.warnings;
    out.report = sliceReport(made.settings, machine, result, motion, written, pinfo, d, part.placement);
    SliceReport& r = out.report;
    if (check) r.verify = check->section;
    r.timingsMs = std::move(clock.timings);
    r.timingsMs.emplace_back("total", msSince(start));
    r.mesh = inputReport(in, part.placement, part.mesh);
    out.reportJson = sliceReportJson(r);
    out.infoJson = inputReportJson(r.mesh);
    out.preview.toolpath = toolpathPreview(motion, result.toolpath);
    out.preview.method = std::move(result.preview);
    if (check) out.preview.verify = std::move(check->preview);
    out.partMesh = std::move(part.mesh);
    if (check && !check->section.sound && mode == VerifyMode::Refuse) {
      // Refused: no program, but the report and the preview say why and where.
      out.status = Status::UnsoundProgram;
      out.message = check->section.statement;
      return out;
    }
    out.program = std::move(written.text);
    return out;
  } catch (const std::bad_alloc&) {
    return failed<SliceOutput>(allocationFailed("slicing"));
  } catch (const std::exception& e) {
    return failed<SliceOutput>(Status::Internal, std::string("unexpected failure: ") + e.what());
  }
}

// Threads for method = auto's candidates: the `threads` setting (common/parallel.h threadCount).
static size_t autoThreads(const Settings& settings) { return threadCount(settings.threads); }

// method = auto's candidates for this input and machine: every method the machine takes, cheapest
// first (surface only for an input that is not a closed solid).
static Outcome autoCandidates(const uint8_t* data, size_t size, const std::string& fileName,
                              const Settings& settings, std::vector<Method>& order) {
  MachineProfileResult resolved = resolveMachine(settings);
  if (!resolved.ok()) return resolved;
  const MachineKind kind = resolved.machine.kind;
  bool closed = true;
  {
    StageClock clock;
    const PreparedInput in = prepareInput(data, size, fileName, settings.placement, Eigen::Matrix3d::Identity(),
                                          false, {}, clock);
    if (!in.ok()) return in;
    closed = in.prepared.solid.ok();
  }
  order.clear();
  for (Method m : {Method::Planar, Method::Multidir, Method::Surface, Method::Geodesic, Method::Voxel}) {
    const MethodEntry& e = methodEntry(m);
    if (std::find(e.machines.begin(), e.machines.end(), kind) == e.machines.end()) continue;
    if (m == Method::Surface && closed) continue;
    order.push_back(m);
  }
  return {};
}

// A candidate's settings: the method, checked with verify = warn, with `attempts` programs at most.
static Settings candidateSettings(const Settings& settings, Method m, int attempts) {
  Settings s = settings;
  s.method = m;
  s.verify = VerifyMode::Warn;
  s.verifyAttempts = attempts;
  return s;
}

static AutoFigures figuresOf(Method m, const SliceOutput& out, bool dominated, bool full, double ms) {
  AutoFigures f;
  f.method = methodName(m);
  f.ms = ms;
  f.full = full;
  f.supportVolumeMm3 = out.report.supportVolumeMm3;
  f.estimatedTimeS = out.report.estimatedTimeS;
  if (out.ok()) {
    f.verify = out.report.verify;
    f.extrusionMm = out.report.extrusionMm;
  } else {
    f.status = dominated ? "dominated" : statusCode(out.status);
    f.message = out.message;
  }
  return f;
}

// The delivered output of method = auto: the chosen candidate's, with the `auto` section.
static SliceOutput autoOutput(SliceOutput best, const AutoDecision& d, double ms) {
  if (d.chosen < 0 || d.status == Status::Cancelled) return failed<SliceOutput>(d.status, d.message);
  SliceReport& r = best.report;
  r.autoChoice = d.section;
  r.timingsMs.emplace_back("auto", ms);
  best.reportJson = sliceReportJson(r);
  if (d.status == Status::UnsoundProgram) {
    best.status = d.status;
    best.message = d.message;
    best.program.clear();
  }
  return best;
}

// method = auto: every candidate (autoCandidates) verified (verify = warn for the candidates), the
// best delivered (auto_choice.h decideAuto) with the report's `auto` section. One after another
// (threads = 1, or wasm), a candidate that a sound one already beats on support and time stops
// before its check; in threads every candidate is checked. With verify = refuse an unsound best
// is refused.
static SliceOutput runAuto(const uint8_t* data, size_t size, const std::string& fileName, const Settings& settings,
                           const ProgressFn& progress) {
  std::vector<Method> order;
  if (Outcome o = autoCandidates(data, size, fileName, settings, order); !o.ok()) return failed<SliceOutput>(o);
  const Clock::time_point start = Clock::now();
  std::vector<SliceOutput> outs(order.size());
  std::vector<AutoFigures> figures(order.size());
  const size_t threads = std::min(order.size(), autoThreads(settings));
  auto runCandidate = [&](size_t k, const ProgressFn& fn, const AutoBound* bound, int attempts) {
    bool dominated = false;
    const Clock::time_point t0 = Clock::now();
    Settings s = candidateSettings(settings, order[k], attempts);
    if (threads > 1) s.threads = 1;  // the candidates side by side already use the cores
    outs[k] = runOneMethod(data, size, fileName, s, fn, bound, &dominated);
    figures[k] = figuresOf(order[k], outs[k], dominated, attempts == settings.verifyAttempts, msSince(t0));
  };
  AutoDecision d;
  if (threads > 1) {
    // In threads: no candidate stops early (which would depend on which finished first), so the
    // report is the same on every run; each makes one program (no remedies yet: decideAuto asks,
    // in order, for those that could still win); the progress is serialised and a cancel stops
    // them all.
    std::mutex progressLock;
    std::atomic<bool> cancelled{false};
    std::atomic<size_t> next{0}, done{0};
    const ProgressFn shared = [&](const ProgressEvent& e) {
      if (cancelled) return false;
      std::lock_guard<std::mutex> lock(progressLock);
      if (progress && !progress(e)) cancelled = true;
      return !cancelled;
    };
    if (!reportProgress(shared, "auto", 0)) return failed<SliceOutput>(Status::Cancelled, "cancelled");
    auto worker = [&] {
      for (size_t k; (k = next++) < order.size() && !cancelled;) {
        runCandidate(k, shared, nullptr, 1);
        reportProgress(shared, "auto", double(++done) / double(order.size()));
      }
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (cancelled) return failed<SliceOutput>(Status::Cancelled, "cancelled");
    for (d = decideAuto(figures, settings); d.rerun >= 0; d = decideAuto(figures, settings)) {
      const size_t k = size_t(d.rerun);
      if (!reportProgress(progress, "auto", double(k) / double(order.size()))) {
        return failed<SliceOutput>(Status::Cancelled, "cancelled");
      }
      runCandidate(k, progress, nullptr, settings.verifyAttempts);
      figures[k].full = true;
    }
  } else {
    for (size_t k = 0; k < order.size(); ++k) {
      if (!reportProgress(progress, "auto", double(k) / double(order.size()))) {
        return failed<SliceOutput>(Status::Cancelled, "cancelled");
      }
      const AutoDecision sofar = decideAuto({figures.begin(), figures.begin() + k}, settings);
      runCandidate(k, progress, sofar.bound ? &*sofar.bound : nullptr, settings.verifyAttempts);
      figures[k].full = true;
      if (figures[k].status == "cancelled") return std::move(outs[k]);
    }
    if (!reportProgress(progress, "auto", 1)) return failed<SliceOutput>(Status::Cancelled, "cancelled");
    d = decideAuto(figures, settings);
  }
  if (d.chosen < 0) return failed<SliceOutput>(d.status, d.message);
  return autoOutput(std::move(outs[size_t(d.chosen)]), d, msSince(start));
}

std::string planAuto(const uint8_t* data, size_t size, const std::string& fileName, const Settings& settings,
                     Outcome* outcome) {
  std::vector<Method> order;
  *outcome = autoCandidates(data, size, fileName, settings, order);
  if (!outcome->ok()) return {};
  std::vector<std::pair<std::string, Settings>> candidates;
  for (Method m : order) candidates.emplace_back(methodName(m), candidateSettings(settings, m, 1));
  return autoPlanJson(candidates, settings);
}

std::string chooseAuto(const Settings& settings, const std::vector<std::string>& candidatesJson, Outcome* outcome) {
  std::vector<AutoFigures> figures;
  for (const std::string& c : candidatesJson) {
    std::string error;
    figures.push_back(autoFiguresFromJson(c, &error));
    if (!error.empty()) {
      *outcome = failed<Outcome>(Status::InvalidOption, error);
      return {};
    }
  }
  *outcome = {};
  return autoDecisionJson(decideAuto(figures, settings));
}

SliceOutput runSlice(const uint8_t* data, size_t size, const std::string& fileName, const Settings& settings,
                     const ProgressFn& progress) {
  if (settings.method == Method::Auto) {
    try {
      return runAuto(data, size, fileName, settings, progress);
    } catch (const std::bad_alloc&) {
      return failed<SliceOutput>(allocationFailed("slicing"));
    } catch (const std::exception& e) {
      return failed<SliceOutput>(Status::Internal, std::string("unexpected failure: ") + e.what());
    }
  }
  return runOneMethod(data, size, fileName, settings, progress, nullptr, nullptr);
}

InfoOutput runInfo(const uint8_t* data, size_t size, const std::string& fileName, const Settings& settings,
                   const ProgressFn& progress) {
  try {
    StageClock clock;
    PreparedInput in = prepareInput(data, size, fileName, settings.placement, Eigen::Matrix3d::Identity(),
                                    closesSolid(settings), progress, clock);
    if (!in.ok()) return failed<InfoOutput>(in);
    InfoOutput out;
    out.infoJson = inputReportJson(inputReport(in, in.placed.transform, in.placed.mesh), clock.timings);
    out.partMesh = std::move(in.placed.mesh);
    return out;
  } catch (const std::bad_alloc&) {
    return failed<InfoOutput>(allocationFailed("reading the mesh"));
  } catch (const std::exception& e) {
    return failed<InfoOutput>(Status::Internal, std::string("unexpected failure: ") + e.what());
  }
}

VerifyOutput runVerify(const std::string& programText, const uint8_t* meshData, size_t meshSize,
                       const std::string& meshName, const ProgressFn& progress, double memoryMb) {
  try {
    if (Outcome o = checkProgramReadBudget(double(programText.size()), memoryMb); !o.ok()) {
      return failed<VerifyOutput>(o);
    }
    ParsedProgram program = readProgram(programText);
    if (!program.ok()) return failed<VerifyOutput>(program);
    ReadMeshResult read = readMesh(meshData, meshSize, meshName);
    if (!read.ok()) return failed<VerifyOutput>(read);
    // The solid a program prints is the mesh as repair = auto closes it (repair = none refuses
    // what auto would repair, so no program was made from such a mesh that way).
    PrepareOptions prepareOptions;
    prepareOptions.closeSolid = program.method != methodName(Method::Surface);
    prepareOptions.uniteShells = prepareOptions.closeSolid;
    PrepareMeshResult prepared = prepareMesh(read.mesh, prepareOptions, progress);
    if (!prepared.ok()) return failed<VerifyOutput>(prepared);
    Mesh part;
    if (program.method == methodName(Method::Surface)) {
      // A surface program prints the solid between the platform and the surface (its base and
      // its surface layer): the same construction as the slice, from the placed surface.
      HeightFieldSolid built = heightFieldSolid(transformMesh(prepared.mesh, program.placement), 0);
      if (!built.ok()) return failed<VerifyOutput>(built);
      part = std::move(built.solid);
    } else {
      if (!prepared.solid.ok()) return failed<VerifyOutput>(prepared.solid);
      part = transformMesh(prepared.mesh, program.placement);
    }
    VerifyOptions options;
    options.memoryBudgetMb = memoryMb;
    VerifyReport report = verifyProgram(program, part, options, progress);
    if (!report.ok()) return failed<VerifyOutput>(report);
    VerifyOutput out;
    out.verifyJson = verifyReportJson(report);
    return out;
  } catch (const std::bad_alloc&) {
    return failed<VerifyOutput>(allocationFailed("verifying"));
  } catch (const std::exception& e) {
    return failed<VerifyOutput>(Status::Internal, std::string("unexpected failure: ") + e.what());
  }
}

}  // namespace omnislice
