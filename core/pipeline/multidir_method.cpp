// SPDX-License-Identifier: MIT
#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "pipeline/multidir_method.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "common/det_math.h"
#include "mesh/clip_mesh.h"
#include "multidir/decomposition.h"
#include "multidir/projected_supports.h"
#include "pipeline/stage_support.h"
#include "pipeline/support_stage.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"
#include "slice/support_regions.h"

namespace omnislice {
namespace {

using Json = nlohmann::ordered_json;
using stage::finite;

template <typename... Args>
MultidirMethodOutput failure(Args&&... args) {
  return failed<MultidirMethodOutput>(std::forward<Args>(args)...);
}

Json vec(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

// Every part's mesh in one soup, the print index per triangle.
void mergeParts(const std::vector<ClipPart>& parts, PreviewBuffers& p) {
  for (size_t i = 0; i < parts.size(); ++i) {
    const Mesh& m = parts[i].mesh;
    const uint32_t base = static_cast<uint32_t>(p.partPositions.size() / 3);
    for (double x : m.positions) p.partPositions.push_back(static_cast<float>(x));
    for (uint32_t v : m.triangles) p.partTriangles.push_back(base + v);
    p.partIds.insert(p.partIds.end(), m.faceCount(), static_cast<uint32_t>(i));
  }
}

// The solid a part is sliced from: its piece of the model (above its own plane, planeIndex; the
// platform part has none) reaching across every plane that bounds it from above (the planes
// clipped before its own: their parts print after it) by delta = halfHeightScale (1 - |n . d|),
// d its direction, n that plane's normal. Where a later part's base plane crosses the earlier
// part's layers steeply (beta near 90 degrees), the earlier part's outer beads end w/2 inside the
// plane and the later part's first tips lie h/2 above it: w/2 + h/2 apart, beyond the 1.5 h that
// holds a bead. Reaching across brings them within it. The bound keeps the later part's nozzle
// clear: the earlier part's layers stand out of their cut by up to (h/2)|cos beta|, so with
// halfHeightScale <= h/2 they stay under the later part's first tip. The pieces overlap by delta
// (report volumes are the exact pieces'). `reaching` stays empty when no plane bounds the part;
// deepest = the largest delta of a plane that crosses the part's reach (0 if none).
Outcome reachAcross(const Mesh& model, const std::vector<Plane>& planes, int planeIndex, const Eigen::Vector3d& d,
                    double halfHeightScale, Mesh& reaching, double& deepest) {
  const size_t bound = planeIndex < 0 ? planes.size() : static_cast<size_t>(planeIndex);
  reaching = Mesh();
  deepest = 0;
  if (bound == 0) return {};
  Mesh s;
  if (planeIndex >= 0) {
    ClipResult c = clipByPlane(model, planes[static_cast<size_t>(planeIndex)]);
    if (!c.ok()) return c;
    s = std::move(c.above);
  } else {
    s = model;
  }
  for (size_t j = 0; j < bound && !s.empty(); ++j) {
    const double len = planes[j].normal.norm();
    const Eigen::Vector3d n = planes[j].normal / len;
    const Plane shifted{n, planes[j].offset / len + halfHeightScale * (1 - std::abs(n.dot(d)))};
    double highest = -std::numeric_limits<double>::infinity();
    for (size_t v = 0; v < s.vertexCount(); ++v) highest = std::max(highest, n.dot(s.vertex(v)));
    if (highest <= shifted.offset) continue;  // wholly below: nothing to cut
    if (highest > planes[j].offset / len) deepest = std::max(deepest, shifted.offset - planes[j].offset / len);
    ClipResult c = clipByPlane(s, shifted);
    if (!c.ok()) return c;
    s = std::move(c.below);
  }
  reaching = std::move(s);
  return {};
}

// Risky flags per triangle of part (Eq. 1): along +Z on the platform (before) and along the
// direction of the part the centroid falls in (after): the first plane in clipping order whose
// above side (n . c >= d) holds it, else the platform part (+Z). Faces whose centroid lies below
// bandMm are on the platform: never risky along +Z.
void riskyFlags(const Mesh& part, const std::vector<Plane>& planes, double alphaMaxDeg, double bandMm,
                PreviewBuffers& p) {
  const double sinAlpha = det::sin(alphaMaxDeg * kPi / 180);
  const size_t nf = part.faceCount();
  p.riskyBefore.assign(nf, 0);
  p.riskyAfter.assign(nf, 0);
  for (size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = part.vertex(part.triangles[3 * f]);
    const Eigen::Vector3d b = part.vertex(part.triangles[3 * f + 1]);
    const Eigen::Vector3d c = part.vertex(part.triangles[3 * f + 2]);
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    if (!(cross.norm() > 0)) continue;  // degenerate: never risky
    const Eigen::Vector3d n = cross.normalized();
    const Eigen::Vector3d centroid = (a + b + c) / 3;
    const bool onPlatform = centroid.z() < bandMm;
    const bool riskyUp = !onPlatform && n.z() + sinAlpha < 0;
    p.riskyBefore[f] = riskyUp ? 1 : 0;
    bool after = riskyUp;
    for (const Plane& q : planes) {
      const double len = q.normal.norm();
      if (!(len > 0)) continue;
      const Eigen::Vector3d d = q.normal / len;
      if (d.dot(centroid) >= q.offset / len) {
        after = n.dot(d) + sinAlpha < 0;
        break;
      }
    }
    p.riskyAfter[f] = after ? 1 : 0;
  }
}

}  // namespace

MultidirMethodOutput runMultidirMethod(const Mesh& input, const Settings& settings,
                                       const MachineProfile& machine, const ProgressFn& progress) {
  MultidirMethodOutput out;
  const MultidirSettings& ms = settings.multidir;
  if (machine.kind == MachineKind::Cartesian3) {
    return failure(Status::InvalidOption,
                   "the multidir method turns the part between parts: choose a machine with a rotary "
                   "axis or a robot (rotary4, table5, robot6), not cartesian3");
  }
  const bool fourDof = ms.dof == "4dof" || (ms.dof == "auto" && machine.kind == MachineKind::Rotary4);
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
    o.dof = "4dof";
    o.rotationAxis = Eigen::Vector3d::UnitX();  // rotary4 turns the part about X (A axis)
    o.axisSearch = ms.axisSearch;
    o.stepAngleDeg = ms.stepAngleDeg > 0 ? ms.stepAngleDeg : machine.stepAngleDegrees;
    auto a = machine.axisLimits.find("A");
    o.rangeDeg = a != machine.axisLimits.end()
                     ? std::max(1.0, std::min(std::abs(a->second.first), std::abs(a->second.second)))
                     : 90.0;
  } else {
    o.dof = "5dof";
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
  out.part = input;
  if (!r.isIdentity(1e-15)) {
    for (size_t v = 0; v < out.part.vertexCount(); ++v) {
      const Eigen::Vector3d q = r * out.part.vertex(v);
      for (int k = 0; k < 3; ++k) out.part.positions[3 * v + size_t(k)] = q[k];
    }
    out.turn.topLeftCorner<3, 3>() = r;
  }

  // 2. Closed parts in print order (Eq. 5-6).
  t0 = Clock::now();
  if (!reportProgress(progress, "clip", 0)) return failure(Status::Cancelled, "cancelled");
  std::vector<Plane> planes;
  for (const MultidirPlane& p : search.planes) planes.push_back({r * p.normal, p.offsetMm});
  PartsResult parts = clipSequence(out.part, planes, 1e-6, progress);
  if (!parts.ok()) return failure(parts);
  out.timingsMs.emplace_back("clip", msSince(t0));
  mergeParts(parts.parts, out.preview);
  riskyFlags(out.part, planes, o.alphaMaxDeg, o.platformBandMm, out.preview);

  // 3. Projected supports (Section V, Algorithm 2) for what stays risky.
  const bool withSupports = stage::supportsWanted(settings);
  const SupportOptions supportOptions = stage::supportOptionsFor(settings, o.alphaMaxDeg);
  SupportResult supports;
  double supportMs = 0, supportRegionVolume = 0;
  if (withSupports) {
    t0 = Clock::now();
    supports = projectedSupports(out.part, planes, supportOptions, progress);
    if (!supports.ok()) return failure(supports);
    supportMs = msSince(t0);
  }

  // 4. Each part sliced along its direction and planned, with its subspace's supports; parts one
  // after the other.
  double sliceMs = 0, planMs = 0;
  int layerOffset = 0;
  Json partsJson = Json::array();
  bool first = true;
  for (size_t i = 0; i < parts.parts.size(); ++i) {
    const ClipPart& cp = parts.parts[i];
    const Eigen::Vector3d d = cp.planeIndex < 0 ? Eigen::Vector3d::UnitZ() : planes[size_t(cp.planeIndex)].normal.normalized();
    // The search's part for this plane (parts[k] is cut off by planes[k]; back() = platform).
    const MultidirPart* sp = nullptr;
    if (cp.planeIndex < 0 && !search.parts.empty()) sp = &search.parts.back();
    if (cp.planeIndex >= 0 && size_t(cp.planeIndex) < search.parts.size()) sp = &search.parts[size_t(cp.planeIndex)];
    Json pj = {{"print_index", i},
               {"direction", vec(d)},
               {"plane", cp.planeIndex < 0 ? Json(nullptr)
                                           : Json({{"normal", vec(d)}, {"offset_mm", planes[size_t(cp.planeIndex)].offset}})},
               {"volume_mm3", finite(cp.volume)},
               {"components", cp.components},
               {"risky_area_mm2", sp ? finite(sp->riskyAreaMm2) : 0.0}};
    if (cp.mesh.empty()) {
      pj["layers"] = 0;
      partsJson.push_back(pj);
      continue;
    }
    auto s0 = Clock::now();
    Mesh reaching;
    double reachMm = 0;
    if (settings.multidir.interfaceOverlap > 0) {
      Outcome o = reachAcross(out.part, planes, cp.planeIndex, d,
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
    Settings ps = settings;
    if (!first) {
      // A part printed on an earlier one: its first layer is an ordinary layer.
      ps.firstLayerHeight = 0;
      ps.firstLayerSpeed = settings.printSpeed;
    }
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
    PlanLayersResult plan = planLayers(slices, ps, static_cast<int>(i), progress, withSupports ? &regions.layers : nullptr);
    if (!plan.ok()) return failure(plan.status, "part " + std::to_string(i) + ": " + plan.message);
    planMs += msSince(s0);
    int maxLayer = -1;
    for (Move m : plan.toolpath.moves) {
      maxLayer = std::max(maxLayer, m.layer);
      m.layer += layerOffset;
      m.part = static_cast<int32_t>(i);
      out.toolpath.moves.push_back(m);
    }
    if (first) out.toolpath.start = plan.toolpath.start;
    layerOffset += maxLayer + 1;
    pj["layers"] = maxLayer + 1;
    pj["support_region_mm3"] = finite(partSupportVolume);
    pj["reach_across_mm"] = finite(reachMm);
    partsJson.push_back(pj);
    first = false;
  }
  if (out.toolpath.moves.empty()) return failure(Status::Internal, "multidir: no part produced a tool-path");
  out.layers = layerOffset;
  out.timingsMs.emplace_back("slice", sliceMs);
  out.timingsMs.emplace_back("toolpath", planMs);
  if (withSupports) out.timingsMs.emplace_back("supports", supportMs);
  const double printedSupport = stage::printedSupportVolume(out.toolpath, settings.filamentDiameter);

  const MultidirStats& st = search.stats;
  Json levels = Json::array();
  for (double j : st.jgPerLevel) levels.push_back(finite(j));
  Json report = {
      {"J_G_before", finite(search.jgBeforeMm2)},
      {"J_G_after", finite(search.jgAfterMm2)},
      {"ratio", search.jgBeforeMm2 > 0 ? finite(search.jgAfterMm2 / search.jgBeforeMm2) : 0.0},
      {"alpha_max_deg", o.alphaMaxDeg},
      {"scheme", o.scheme},
      {"dof", o.dof},
      {"rotation_axis", fourDof ? vec(search.rotationAxis) : Json(nullptr)},
      {"parts", partsJson},
      {"part_count", parts.parts.size()},
      {"volume_mm3", finite(parts.inputVolume)},
      {"cap_area_mm2", finite(parts.totalCapArea)},
      // Projected supports (Section V): the deposited support volume, and the generator's figures.
      {"supports_generated", withSupports},
      {"support_volume_mm3", finite(printedSupport)},
      {"supports", withSupports ? Json::parse(stage::supportReportJson(supports, supportOptions, supportRegionVolume,
                                                                       printedSupport, supportMs))
                                : Json({{"generated", false}})},
      {"search",
       {{"normals", st.normals},
        {"candidates_evaluated", st.candidatesEvaluated},
        {"candidates_checked", st.candidatesChecked},
        {"connectivity_checks", st.connectivityChecks},
        {"refused_floating", st.refusedFloating},
        {"refused_small", st.refusedSmall},
        {"refused_similar", st.refusedSimilar},
        {"beams", st.beams},
        {"levels", st.levels},
        {"axes_tried", st.axesTried},
        {"restarts_run", st.restartsRun},
        {"perturbations", st.perturbations},
        {"perturbations_kept", st.perturbationsKept},
        {"J_G_per_level", levels},
        {"grid_cells", st.gridCells},
        {"cell_mm", finite(st.cellMm)}}},
      {"timings_ms",
       {{"prepare", finite(st.msPrepare)},
        {"normals", finite(st.msNormals)},
        {"sweep", finite(st.msSweep)},
        {"checks", finite(st.msChecks)},
        {"refine", finite(st.msRefine)},
        {"perturb", finite(st.msPerturb)},
        {"exact", finite(st.msExact)},
        {"search", finite(st.msTotal)}}}};
  for (const auto& [k, v] : out.timingsMs) report["timings_ms"][k] = finite(v);
  out.reportJson = report.dump();
  return out;
}

}  // namespace omnislice
