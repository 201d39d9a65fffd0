// SPDX-License-Identifier: MIT
#include "pipeline/curved_stage.h"

#include <cstdio>

#include "pipeline/isoplanar_fill.h"

namespace omnislice::stage {

CurvedFill fillCurvedLayers(const std::vector<CurvedLayer>& layers, const Settings& settings,
                            const MachineProfile& machine, double isoLayerHeight, const char* stage,
                            double progressScale, const ProgressFn& progress) {
  CurvedFill out;
  out.paths.resize(layers.size());
  const bool isoplanar = settings.fill == FillMode::Isoplanar;
  SpiralOptions sopt;
  sopt.spacing = settings.effectiveLineWidth();
  IsoplanarFillOptions iso;
  iso.beadWidth = settings.nozzleDiameter;
  iso.layerHeight = isoLayerHeight;
  iso.maxFeed = settings.isoplanar.maxFeedMmS > 0 ? settings.isoplanar.maxFeedMmS : settings.printSpeed;
  iso.travelSpeed = settings.travelSpeed;
  IsoplanarTotals totals;
  for (size_t l = 0; l < layers.size(); ++l) {
    const CurvedLayer& layer = layers[l];
    out.paths[l].resize(layer.regions.size());
    for (size_t r = 0; r < layer.regions.size(); ++r) {
      ++out.regions;
      const LayerRegion& region = layer.regions[r];
      if (isoplanar) {
        IsoplanarFillResult fill = planIsoplanarFill(region.mesh, machine, settings.isoplanar, iso);
        if (fill.status == Status::Cancelled) return failed<CurvedFill>(fill);
        if (!fill.ok() || fill.paths.empty()) {
          ++out.unfilled;
          continue;
        }
        iso.firstCurve += fill.curves;
        totals.add(uint32_t(l), uint32_t(r), region.area, fill);
        out.pathCount += fill.paths.size();
        out.paths[l][r] = std::move(fill.paths);
        continue;
      }
      SpiralResult spiral = fermatSpiralPaths(region.mesh, sopt);
      if (!spiral.ok() || spiral.paths.empty()) {
        ++out.unfilled;
        continue;
      }
      out.pathCount += spiral.paths.size();
      out.paths[l][r] = std::move(spiral.paths);
    }
    if (!reportProgress(progress, stage, progressScale * double(l + 1) / double(layers.size()))) {
      return failed<CurvedFill>(Status::Cancelled, "cancelled");
    }
  }
  if (isoplanar) out.isoplanar = totals.report();
  return out;
}

CurvedToolpathOptions curvedToolpathOptions(const Settings& settings, const MachineProfile& machine,
                                            double nominalHeight, double maxTiltDegrees) {
  CurvedToolpathOptions o;
  o.nominalHeight = nominalHeight;
  o.filamentDiameter = settings.filamentDiameter;
  o.printSpeed = settings.printSpeed;
  o.firstLayerSpeed = settings.firstLayerSpeed;
  o.travelSpeed = settings.travelSpeed;
  o.retractLength = settings.retractLength;
  o.retractMinTravel = settings.retractMinTravel;
  o.retractSpeed = settings.retractSpeed;
  o.maxTiltDegrees = maxTiltDegrees;
  o.coneHalfAngleDegrees = machine.nozzle.coneHalfAngleDegrees;
  o.coneLength = machine.nozzle.coneLength;
  o.collisionClearance = nominalHeight;
  o.filterThresholdDegrees = settings.smoothOrientations ? settings.orientationFilterDegrees : 180;
  o.axisFreedomDegrees = settings.axisFreedomDegrees;
  const bool isoplanar = settings.fill == FillMode::Isoplanar;
  o.lineWidth = isoplanar ? settings.nozzleDiameter : settings.effectiveLineWidth();
  o.ellipseBeads = isoplanar;
  return o;
}

std::optional<Warning> nozzleCollisionWarning(size_t uncorrectedPoints) {
  if (uncorrectedPoints == 0) return std::nullopt;
  return Warning{"nozzle_collision", std::to_string(uncorrectedPoints) +
                                         " tool-path points print with the nozzle cone touching printed material: no "
                                         "nozzle axis within the correction and tilt limits clears the part there"};
}

std::optional<Warning> beadOnPlatformWarning(const Toolpath& toolpath) {
  double total = 0, low = 0;
  Eigen::Vector3d from = toolpath.start;
  for (const Move& m : toolpath.moves) {
    const double len = (m.position - from).norm();
    from = m.position;
    if (m.kind != MoveKind::Print && m.kind != MoveKind::Support) continue;
    total += len;
    if (m.position.z() < 0.5 * m.height) low += len;
  }
  if (!(total > 0) || low < 1.0) return std::nullopt;
  char text[320];
  std::snprintf(text, sizeof text,
                "%.1f mm of the extruding path (%.2f %%) runs closer to the platform than half its bead "
                "height: the curved layers reach down to the bed there, so the nozzle would press into it "
                "(planar and multidir print a flat first layer)",
                low, 100 * low / total);
  return Warning{"bead_on_platform", text};
}

int printedLayerCount(const std::vector<std::vector<std::vector<SurfacePath>>>& paths) {
  int printed = 0;
  for (const auto& layer : paths) {
    bool any = false;
    for (const auto& region : layer) any = any || !region.empty();
    printed += any ? 1 : 0;
  }
  return printed;
}

void appendLayerSurfaces(const std::vector<CurvedLayer>& layers, LayerSurfacePreview& p) {
  for (size_t l = 0; l < layers.size(); ++l) {
    for (const LayerRegion& region : layers[l].regions) {
      const uint32_t base = static_cast<uint32_t>(p.positions.size() / 3);
      for (double v : region.mesh.positions) p.positions.push_back(static_cast<float>(v));
      for (uint32_t i : region.mesh.triangles) p.triangles.push_back(base + i);
      p.layers.insert(p.layers.end(), region.mesh.faceCount(), static_cast<uint32_t>(l));
    }
  }
}

}  // namespace omnislice::stage
