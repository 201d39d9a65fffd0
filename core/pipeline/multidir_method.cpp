// SPDX-License-Identifier: MIT
// The multi-directional (3+2-axis) method of paper 000: placed solid -> clipping planes by the
// search of Section IV (core/multidir/decomposition) -> closed parts in print order (Eq. 5-6,
// core/mesh/clip_mesh) -> each part sliced with planar layers along its own direction, reaching
// across later parts' planes (core/multidir/multidir_parts), with its subspace's projected
// supports (Section V) -> one part-frame Toolpath, Move.part = the part's print index; the motion
// planner turns the machine between parts only after a retract and a safe move.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "common/stopwatch.h"
#include "mesh/clip_mesh.h"
#include "multidir/decomposition.h"
#include "multidir/multidir_parts.h"
#include "multidir/projected_supports.h"
#include "pipeline/method.h"
#include "pipeline/settings.h"
#include "pipeline/support_stage.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"
#include "slice/support_regions.h"

namespace omnislice {
namespace {

// Every part's mesh in one soup, the print index per triangle.
void mergeParts(const std::vector<ClipPart>& parts, MultidirPreview& p) {
  for (size_t i = 0; i < parts.size(); ++i) {
    const Mesh& m = parts[i].mesh;
    const uint32_t base = static_cast<uint32_t>(p.partPositions.size() / 3);
    appendFloats(p.partPositions, m.positions);
    for (uint32_t v : m.triangles) p.partTriangles.push_back(base + v);
    p.partIds.insert(p.partIds.end(), m.faceCount(), static_cast<uint32_t>(i));
  }
}

MultidirReport::Search searchReport(const MultidirStats& st) {
  MultidirReport::Search s;
  s.normals = st.normals;
  s.candidatesEvaluated = st.candidatesEvaluated;
  s.candidatesChecked = st.candidatesChecked;
  s.connectivityChecks = st.connectivityChecks;
  s.refusedFloating = st.refusedFloating;
  s.refusedSmall = st.refusedSmall;
  s.refusedSimilar = st.refusedSimilar;
  s.beams = st.beams;
  s.levels = st.levels;
  s.axesTried = st.axesTried;
  s.restartsRun = st.restartsRun;
  s.perturbations = st.perturbations;
  s.perturbationsKept = st.perturbationsKept;
  s.jgPerLevel = st.jgPerLevel;
  s.gridCells = st.gridCells;
  s.cellMm = st.cellMm;
  return s;
}

}  // namespace

MethodResult runMultidirMethod(const PlacedPart& placed, const MethodContext& context) {
  const Settings& settings = context.settings;
  const MachineProfile& machine = context.machine;
  const ProgressFn& progress = context.progress;
  const Mesh& input = placed.mesh;
  auto failure = [](auto&&... args) { return failed<MethodResult>(std::forward<decltype(args)>(args)...); };
  MethodResult out;
  const MultidirSettings& ms = settings.multidir;
  const bool fourDof = ms.dof == MultidirDof::FourDof || (ms.dof == MultidirDof::Auto && machine.kind == MachineKind::Rotary4);
  if (fourDof && machine.kind != MachineKind::Rotary4) {
    return failure(Status::InvalidOption, "multidir.dof = 4dof needs a rotary4 machine (one rotary axis)");
  }
  if (!fourDof && machine.kind == MachineKind::Rotary4) {
    return failure(Status::InvalidOption, "a rotary4 machine turns the part about one axis: multidir.dof = 4dof");
  }

  // 1. The search (Section IV).
  MultidirOptions o;
  o.alphaMaxDeg = ms.alphaMaxDeg;
  o.samples = ms.samples;
  o.offsetStepMm = ms.offsetStepMm;
  o.w = ms.w;
  o.beamWidth = ms.beamWidth;
  o.restarts = ms.restarts;
  o.perturbations = ms.perturbations;
  o.scheme = ms.scheme;
  o.platformMarginMm = ms.platformMarginMm;
  if (fourDof) {
    o.dof = DofMode::FourDof;
    o.rotationAxis = Eigen::Vector3d::UnitX();  // rotary4 turns the part about X (A axis)
    o.axisSearch = ms.axisSearch;
    o.stepAngleDeg = ms.stepAngleDeg > 0 ? ms.stepAngleDeg : machine.stepAngleDegrees;
    auto a = machine.axisLimits.find("A");
    o.rangeDeg = a != machine.axisLimits.end()
                     ? std::max(1.0, std::min(std::abs(a->second.first), std::abs(a->second.second)))
                     : 90.0;
  } else {
    o.dof = DofMode::FiveDof;
    o.maxTiltDeg = ms.maxTiltDeg > 0 ? ms.maxTiltDeg : machineTiltLimitDegrees(machine);
  }
  auto t0 = Clock::now();
  MultidirResult search = searchDecomposition(input, o, progress);
  if (!search.ok()) return failure(search);
  out.timingsMs.emplace_back("decompose", msSince(t0));

  // 4dof with an axis search: turn the part about Z so the chosen axis lies on the machine's X.
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (fourDof && search.rotationAxis.squaredNorm() > 0.5) {
    const Eigen::Vector3d a = search.rotationAxis.normalized();
    // About Z by -atan2(a.y, a.x), from the axis itself (no libm: the same bits in wasm).
    const double len = std::sqrt(a.x() * a.x() + a.y() * a.y());
    const double c = a.x() / len, s = -a.y() / len;
    r << c, -s, 0, s, c, 0, 0, 0, 1;
  }
  Mesh& part = out.part.emplace(input);
  if (!r.isIdentity(1e-15)) {
    for (size_t v = 0; v < part.vertexCount(); ++v) {
      const Eigen::Vector3d q = r * part.vertex(v);
      for (int k = 0; k < 3; ++k) part.positions[3 * v + size_t(k)] = q[k];
    }
    out.turn.topLeftCorner<3, 3>() = r;
  }

  // 2. Closed parts in print order (Eq. 5-6).
  t0 = Clock::now();
  if (!reportProgress(progress, "clip", 0)) return failure(Status::Cancelled, "cancelled");
  std::vector<Plane> planes;
  for (const MultidirPlane& p : search.planes) planes.push_back({r * p.normal, p.offsetMm});
  PartsResult parts = clipSequence(part, planes, 1e-6, progress);
  if (!parts.ok()) return failure(parts);
  out.timingsMs.emplace_back("clip", msSince(t0));
  mergeParts(parts.parts, out.preview.multidir);
  riskyFlags(part, planes, o.alphaMaxDeg, o.platformBandMm, out.preview.multidir.riskyBefore,
             out.preview.multidir.riskyAfter);

  // 3. Projected supports (Section V, Algorithm 2) for what stays risky.
  const bool withSupports = stage::supportsWanted(settings);
  const SupportOptions supportOptions = stage::supportOptionsFor(settings, o.alphaMaxDeg);
  SupportResult supports;
  double supportMs = 0, supportRegionVolume = 0;
  if (withSupports) {
    t0 = Clock::now();
    supports = projectedSupports(part, planes, supportOptions, progress);
    if (!supports.ok()) return failure(supports);
    supportMs = msSince(t0);
  }

  // 4. Each part sliced along its direction and planned, with its subspace's supports; parts one
  // after the other.
  double sliceMs = 0, planMs = 0;
  double thinArea = 0, sectionArea = 0;  // islands too narrow for a path, and all islands (mm^2)
  size_t thinIslands = 0;
  int layerOffset = 0;
  MultidirReport report;
  bool first = true;
  for (size_t i = 0; i < parts.parts.size(); ++i) {
    const ClipPart& cp = parts.parts[i];
    const Eigen::Vector3d d = cp.planeIndex < 0 ? Eigen::Vector3d::UnitZ() : planes[size_t(cp.planeIndex)].normal.normalized();
    // The search's part for this plane (parts[k] is cut off by planes[k]; back() = platform).
    const MultidirPart* sp = nullptr;
    if (cp.planeIndex < 0 && !search.parts.empty()) sp = &search.parts.back();
    if (cp.planeIndex >= 0 && size_t(cp.planeIndex) < search.parts.size()) sp = &search.parts[size_t(cp.planeIndex)];
    MultidirReport::Part& pr = report.parts.emplace_back();
    pr.printIndex = i;
    pr.direction = d;
    if (cp.planeIndex >= 0) pr.planeOffsetMm = planes[size_t(cp.planeIndex)].offset;
    pr.volumeMm3 = cp.volume;
    pr.components = cp.components;
    pr.riskyAreaMm2 = sp ? sp->riskyAreaMm2 : 0.0;
    if (cp.mesh.empty()) continue;
    auto s0 = Clock::now();
    Mesh reaching;
    double reachMm = 0;
    if (settings.multidir.interfaceOverlap > 0) {
      Outcome o = reachAcross(part, planes, cp.planeIndex, d,
                              settings.multidir.interfaceOverlap * 0.5 * settings.layerHeight, reaching, reachMm);
      if (!o.ok()) return failure(o.status, "part " + std::to_string(i) + ": " + o.message);
    }
    SliceOptions so;
    so.direction = d;
    so.layerHeight = settings.layerHeight;
    so.firstLayerHeight = first ? settings.effectiveFirstLayerHeight() : 0.5 * settings.layerHeight;
    SliceResult slices = sliceMesh(reaching.empty() ? cp.mesh : reaching, so, progress);
    if (!slices.ok()) return failure(slices.status, "part " + std::to_string(i) + ": " + slices.message);
    sliceMs += msSince(s0);
    s0 = Clock::now();
    PlanarOptions planar = planarOptions(settings);
    // A part printed on an earlier one: its first layer is an ordinary layer.
    if (!first) planar.firstLayerSpeed = settings.printSpeed;
    SupportRegionsResult regions;
    double partSupportVolume = 0;
    if (withSupports) {
      const int subspace = cp.planeIndex < 0 ? static_cast<int>(planes.size()) : cp.planeIndex;
      const std::vector<Plane> earlier(planes.begin(), planes.begin() + subspace);
      auto r0 = Clock::now();
      regions = supportRegions(supportMesh(supports, subspace, supportOptions), slices, so, earlier, settings.support.gapMm);
      if (!regions.ok()) return failure(regions.status, "part " + std::to_string(i) + ": " + regions.message);
      supportMs += msSince(r0);
      supportRegionVolume += regions.volumeMm3;
      partSupportVolume = regions.volumeMm3;
      s0 = Clock::now();  // the tool-path time leaves the support regions out
    }
    PlanLayersResult plan = planLayers(slices, planar, static_cast<int>(i), progress, withSupports ? &regions.layers : nullptr);
    if (!plan.ok()) return failure(plan.status, "part " + std::to_string(i) + ": " + plan.message);
    planMs += msSince(s0);
    thinArea += plan.thinAreaMm2;
    sectionArea += plan.sectionAreaMm2;
    thinIslands += plan.thinIslands;
    int maxLayer = -1;
    for (Move m : plan.toolpath.moves) {
      maxLayer = std::max(maxLayer, m.layer);
      m.layer += layerOffset;
      m.part = static_cast<int32_t>(i);
      out.toolpath.moves.push_back(m);
    }
    if (first) out.toolpath.start = plan.toolpath.start;
    layerOffset += maxLayer + 1;
    pr.layers = maxLayer + 1;
    pr.sliced = true;
    pr.supportRegionMm3 = partSupportVolume;
    pr.reachAcrossMm = reachMm;
    first = false;
  }
  if (out.toolpath.moves.empty()) return failure(Status::Internal, "multidir: no part produced a tool-path");
  if (auto w = thinSectionsWarning(thinArea, sectionArea, thinIslands, settings.effectiveLineWidth())) {
    out.warnings.push_back(*w);
  }
  out.slicedLayers = static_cast<size_t>(layerOffset);
  out.layerHeight = settings.layerHeight;
  out.timingsMs.emplace_back("slice", sliceMs);
  out.timingsMs.emplace_back("toolpath", planMs);
  if (withSupports) out.timingsMs.emplace_back("supports", supportMs);
  const double printedSupport = stage::printedSupportVolume(out.toolpath, settings.filamentDiameter);

  const MultidirStats& st = search.stats;
  report.jgBeforeMm2 = search.jgBeforeMm2;
  report.jgAfterMm2 = search.jgAfterMm2;
  report.alphaMaxDeg = o.alphaMaxDeg;
  report.scheme = searchSchemeName(o.scheme);
  report.dof = dofModeName(o.dof);
  if (fourDof) report.rotationAxis = search.rotationAxis;
  report.volumeMm3 = parts.inputVolume;
  report.capAreaMm2 = parts.totalCapArea;
  // Projected supports (Section V): the deposited support volume, and the generator's figures.
  report.supportsGenerated = withSupports;
  report.supportVolumeMm3 = printedSupport;
  if (withSupports) {
    report.supports = stage::supportReport(supports, supportOptions, supportRegionVolume, printedSupport, supportMs);
  }
  report.search = searchReport(st);
  report.timingsMs = {{"prepare", st.msPrepare}, {"normals", st.msNormals}, {"sweep", st.msSweep},
                      {"checks", st.msChecks},   {"refine", st.msRefine},   {"perturb", st.msPerturb},
                      {"exact", st.msExact},     {"search", st.msTotal}};
  report.timingsMs.insert(report.timingsMs.end(), out.timingsMs.begin(), out.timingsMs.end());
  out.report.multidir = std::move(report);
  return out;
}

}  // namespace omnislice
