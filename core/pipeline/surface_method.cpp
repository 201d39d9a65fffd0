// SPDX-License-Identifier: MIT
// `method = surface` (paper 003's experiments): an open surface printed as one layer of iso-planar
// paths on a support base. The surface is lifted so the base under it is at least
// surface.base_mm thick; the base (the solid between z = 0 and the surface moved down by the
// layer height along its normals, core/surface/height_field_solid) is printed with planar layers
// first, then the surface layer with the nozzle along the surface normal. The part `verify`
// checks is the solid between z = 0 and the surface (heightFieldSolid(surface, 0), built again
// from the program's placement).
#include <algorithm>
#include <cmath>

#include "common/stopwatch.h"
#include "pipeline/curved_stage.h"
#include "pipeline/isoplanar_fill.h"
#include "pipeline/method.h"
#include "pipeline/settings.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"
#include "surface/curved_toolpath.h"
#include "surface/height_field_solid.h"
#include "surface/surface_layers.h"

namespace omnislice {

namespace {

template <typename... Args>
MethodResult failure(Args&&... args) {
  return failed<MethodResult>(std::forward<Args>(args)...);
}

Mesh lifted(const Mesh& m, double dz) {
  Mesh out = m;
  for (size_t i = 2; i < out.positions.size(); i += 3) out.positions[i] += dz;
  return out;
}

}  // namespace

MethodResult runSurfaceMethod(const PlacedPart& placed, const MethodContext& context) {
  const Settings& settings = context.settings;
  const MachineProfile& machine = context.machine;
  const ProgressFn& progress = context.progress;
  const Mesh& surface = placed.mesh;
  MethodResult out;
  const double h = settings.layerHeight;
  const double s = settings.nozzleDiameter;

  const BoundingBox box = boundingBox(surface);
  if ((box.max.z() - box.min.z() + settings.surface.baseMm + h) / h > 100000) {
    return failure(Status::InvalidOption, "the surface and its base need more than 100000 layers at this layer height");
  }
  // 1. Lift the surface so the base under it is at least base_mm thick, then build the base and
  //    the part. The offset surface dips by at most h below the surface.
  Clock::time_point t0 = Clock::now();
  double dz = settings.surface.baseMm + h;
  Mesh top = lifted(surface, dz);
  HeightFieldSolid base = heightFieldSolid(top, h);
  if (!base.ok()) return failure(base);
  const double adjust = settings.surface.baseMm - base.minTopZ;
  if (std::abs(adjust) > 1e-9) {
    dz += adjust;
    top = lifted(surface, dz);
    base = heightFieldSolid(top, h);
    if (!base.ok()) return failure(base);
  }
  HeightFieldSolid part = heightFieldSolid(top, 0);
  if (!part.ok()) return failure(part);
  out.turn(2, 3) = dz;

  // 2. The base: planar layers of the layer height (foundation slicer).
  SliceOptions sliceOptions;
  sliceOptions.layerHeight = h;
  sliceOptions.firstLayerHeight = settings.effectiveFirstLayerHeight();
  SliceResult slices = sliceMesh(base.solid, sliceOptions, progress);
  if (!slices.ok()) return failure(slices);
  PlanLayersResult plan = planLayers(slices, planarOptions(settings), 0, progress);
  if (!plan.ok()) return failure(plan);
  out.timingsMs.emplace_back("slice", msSince(t0));

  // 3. The surface layer: theta*, NL curves, nozzle along the normals, Eq. 13 extrusion.
  t0 = Clock::now();
  IsoplanarFillOptions fo;
  fo.beadWidth = s;
  fo.layerHeight = h;
  fo.maxFeed = settings.isoplanar.maxFeedMmS > 0 ? settings.isoplanar.maxFeedMmS : settings.printSpeed;
  fo.travelSpeed = settings.travelSpeed;
  fo.benchmark = settings.isoplanar.benchmark;
  IsoplanarFillResult fill = planIsoplanarFill(part.top, machine, settings.isoplanar, fo, progress);
  if (!fill.ok()) return failure(fill);
  if (fill.paths.empty()) {
    return failure(Status::DegenerateInput, "the surface is too small for one iso-planar path");
  }

  std::vector<CurvedLayer> layers(1);
  LayerRegion region;
  region.mesh = part.top;
  layers[0].regions.push_back(std::move(region));
  std::vector<std::vector<std::vector<SurfacePath>>> paths(1);
  paths[0].push_back(fill.paths);
  CurvedToolpathOptions topt =
      stage::curvedToolpathOptions(settings, machine, h, machineTiltLimitDegrees(machine));
  topt.lineWidth = s;             // the ellipse's major axis (paper 003 Table 1: s = nozzle)
  topt.axisFromNormals = true;
  // Paper 003 aligns the nozzle with the surface normal; the motion term is the curved-layer
  // methods' (its drive direction already chooses the motion).
  topt.axisFreedomDegrees = 0;
  topt.ellipseBeads = true;
  topt.printSpeed = fo.maxFeed;   // requested; the motion planner slows to the joint limits
  topt.firstLayerSpeed = fo.maxFeed;
  CurvedToolpathResult curved = buildCurvedToolpath(layers, paths, topt, progress);
  if (!curved.ok()) return failure(curved);
  out.timingsMs.emplace_back("toolpath", msSince(t0));
  for (const auto& t : fill.timingsMs) out.timingsMs.emplace_back("isoplanar_" + t.first, t.second);

  // 4. One tool-path: the base, then retract, rise above the surface, cross, come down along the
  //    first axis and print the surface layer.
  Toolpath& tp = out.toolpath;
  tp = std::move(plan.toolpath);
  // The surface layer follows the last base layer that prints (a sliver at the base's top can
  // slice into a layer with no moves; layer indices stay consecutive for viewers and the program).
  int32_t surfaceLayer = 0;
  for (const Move& m : tp.moves) surfaceLayer = std::max(surfaceLayer, m.layer + 1);
  Eigen::Vector3d pos = tp.moves.empty() ? tp.start : tp.moves.back().position;
  const double safeZ = boundingBox(part.top).max.z() + topt.travelClearance + 2;
  auto push = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& axis, MoveKind kind) {
    Move m;
    m.position = p;
    m.axis = axis;
    m.kind = kind;
    m.layer = surfaceLayer;
    m.speed = settings.travelSpeed;
    tp.moves.push_back(m);
    return &tp.moves.back();
  };
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const bool retracted = !tp.moves.empty() && tp.moves.back().kind == MoveKind::Retract;
  const bool retract = settings.retractLength > 0 && !tp.moves.empty() && !retracted;
  if (retract) {
    Move* r = push(pos, tp.moves.empty() ? up : tp.moves.back().axis, MoveKind::Retract);
    r->filament = -settings.retractLength;
    r->speed = settings.retractSpeed;
  }
  const Toolpath& c = curved.toolpath;
  const Eigen::Vector3d approach = c.start;
  const Eigen::Vector3d firstAxis = c.moves.empty() ? up : c.moves.front().axis;
  if (!tp.moves.empty()) {
    push({pos.x(), pos.y(), safeZ}, up, MoveKind::Travel);
    push({approach.x(), approach.y(), safeZ}, up, MoveKind::Travel);
  }
  push(approach, firstAxis, MoveKind::Travel);
  bool unretracted = !(retract || retracted);
  for (size_t i = 0; i < c.moves.size(); ++i) {
    Move m = c.moves[i];
    m.layer += surfaceLayer;
    if (!unretracted && m.kind != MoveKind::Travel) {
      Move u;
      u.position = tp.moves.back().position;
      u.axis = tp.moves.back().axis;
      u.kind = MoveKind::Unretract;
      u.filament = settings.retractLength;
      u.speed = settings.retractSpeed;
      u.layer = surfaceLayer;
      tp.moves.push_back(u);
      unretracted = true;
    }
    if (m.kind == MoveKind::Unretract || m.kind == MoveKind::Retract) unretracted = true;
    tp.moves.push_back(m);
  }
  if (tp.moves.empty() || slices.layers.empty()) tp.start = c.start;
  tp.layerCount = surfaceLayer + 1;
  out.slicedLayers = static_cast<size_t>(surfaceLayer + 1);
  out.layerHeight = h;
  out.part = std::move(part.solid);

  // Preview: the surface layer.
  LayerSurfacePreview& p = out.preview.surfaces;
  appendFloats(p.positions, part.top.positions);
  p.triangles.assign(part.top.triangles.begin(), part.top.triangles.end());
  p.layers.assign(part.top.faceCount(), static_cast<uint32_t>(surfaceLayer));

  IsoplanarReport& r = out.report.isoplanar.emplace(std::move(fill.report));
  r.surface = IsoplanarReport::Surface{surfaceLayer,
                                       settings.surface.baseMm,
                                       dz,
                                       part.top.vertexCount(),
                                       part.top.faceCount(),
                                       curved.orientationFallbacks,
                                       curved.tiltClamped,
                                       curved.gougingCorrections,
                                       curved.gougingUncorrected};
  if (auto w = stage::nozzleCollisionWarning(curved.gougingUncorrected)) out.warnings.push_back(*w);
  return out;
}

}  // namespace omnislice
