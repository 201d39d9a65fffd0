// SPDX-License-Identifier: MIT
#include "pipeline/curved_stage.h"

#include <algorithm>
#include <cstdio>
#include <memory>

#include <Eigen/Geometry>

#include "common/parallel.h"
#include "geometry/aabb_tree.h"
#include "pipeline/isoplanar_fill.h"

namespace omnislice::stage {

namespace {

// The triangles of m with keep[t] set, as a mesh of their own (vertices renumbered).
Mesh trianglesOf(const Mesh& m, const std::vector<uint8_t>& keep) {
  Mesh out;
  std::vector<uint32_t> remap(m.vertexCount(), UINT32_MAX);
  for (size_t t = 0; t < m.faceCount(); ++t) {
    if (!keep[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.triangles[3 * t + size_t(k)];
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<uint32_t>(out.vertexCount());
        for (int a = 0; a < 3; ++a) out.positions.push_back(m.positions[3 * size_t(v) + size_t(a)]);
      }
      out.triangles.push_back(remap[v]);
    }
  }
  return out;
}

double triangleArea(const Mesh& m, size_t t) {
  const Eigen::Vector3d a = m.vertex(m.triangles[3 * t]), b = m.vertex(m.triangles[3 * t + 1]),
                        c = m.vertex(m.triangles[3 * t + 2]);
  return 0.5 * (b - a).cross(c - a).norm();
}

}  // namespace

bool sparseCurvedFill(const Settings& settings) {
  return settings.fill != FillMode::Isoplanar && settings.infillPercent < 100;
}

double curvedShellMm(const Settings& settings, double isoLayerHeight) {
  const double w = settings.effectiveLineWidth();
  const double walls = std::max(0, settings.walls) * w;
  const double skins = std::max(0, std::max(settings.topLayers, settings.bottomLayers)) * isoLayerHeight;
  return std::max({walls, skins, w});
}

CurvedFill fillCurvedLayers(const std::vector<CurvedLayer>& layers, const Settings& settings,
                            const MachineProfile& machine, double isoLayerHeight, const char* stage,
                            double progressScale, const ProgressFn& progress, const Mesh* solid) {
  CurvedFill out;
  out.paths.resize(layers.size());
  const bool isoplanar = settings.fill == FillMode::Isoplanar;
  SpiralOptions sopt;
  sopt.spacing = settings.effectiveLineWidth();
  // Sparse fill: the solid's surface, the shell's thickness and the interior's spacing.
  std::unique_ptr<AabbTree> surface;
  CurvedSparseReport sparse;
  SpiralOptions interior = sopt;
  if (sparseCurvedFill(settings) && solid != nullptr && !solid->empty()) {
    surface = std::make_unique<AabbTree>(*solid);
    sparse.infillPercent = std::max(0.0, settings.infillPercent);
    sparse.shellMm = curvedShellMm(settings, isoLayerHeight);
    sparse.interiorSpacingMm = sparse.infillPercent > 0 ? sopt.spacing * 100 / sparse.infillPercent : 0;
    interior.spacing = sparse.interiorSpacingMm;
  }
  IsoplanarFillOptions iso;
  iso.beadWidth = settings.nozzleDiameter;
  iso.layerHeight = isoLayerHeight;
  iso.maxFeed = settings.isoplanar.maxFeedMmS > 0 ? settings.isoplanar.maxFeedMmS : settings.printSpeed;
  iso.travelSpeed = settings.travelSpeed;
  IsoplanarTotals totals;
  if (isoplanar) {
    // One after another: each region's NL curves are numbered after the previous ones'.
    for (size_t l = 0; l < layers.size(); ++l) {
      const CurvedLayer& layer = layers[l];
      out.paths[l].resize(layer.regions.size());
      for (size_t r = 0; r < layer.regions.size(); ++r) {
        ++out.regions;
        IsoplanarFillResult fill = planIsoplanarFill(layer.regions[r].mesh, machine, settings.isoplanar, iso);
        if (fill.status == Status::Cancelled) return failed<CurvedFill>(fill);
        if (!fill.ok() || fill.paths.empty()) {
          ++out.unfilled;
          continue;
        }
        iso.firstCurve += fill.curves;
        totals.add(uint32_t(l), uint32_t(r), layer.regions[r].area, fill);
        out.pathCount += fill.paths.size();
        out.paths[l][r] = std::move(fill.paths);
      }
      if (!reportProgress(progress, stage, progressScale * double(l + 1) / double(layers.size()))) {
        return failed<CurvedFill>(Status::Cancelled, "cancelled");
      }
    }
    out.isoplanar = totals.report();
    return out;
  }

  // Fermat spirals: every region on its own, on the `threads` threads; the figures are summed
  // afterwards in layer and region order (the same on any number of threads).
  struct RegionFill {
    size_t layer = 0, region = 0;
    bool filled = false, sparseMade = false, surfaceChecked = false;
    double area = 0, interiorArea = 0;
  };
  std::vector<RegionFill> regions;
  for (size_t l = 0; l < layers.size(); ++l) {
    out.paths[l].resize(layers[l].regions.size());
    for (size_t r = 0; r < layers[l].regions.size(); ++r) regions.push_back({l, r});
  }
  auto fillRegion = [&](size_t k, size_t) {
    RegionFill& f = regions[k];
    const LayerRegion& region = layers[f.layer].regions[f.region];
    std::vector<SurfacePath>& filled = out.paths[f.layer][f.region];
    if (surface && !region.support) {
      // Interior triangles: every corner deeper than the shell (no surface within it) by the
      // longest edge at the corner x 0.6 more: depth changes at most as fast as position, so
      // then every point of the triangle is (its farthest point from the corners is within 0.6
      // x its longest edge of one of them). Measured on the shared kitten, geodesic table5,
      // supported: corners alone 0.934 at 40 mm (the layer meshes' edges are ~1.5 mm: shell
      // bands came out narrower than the shell, and the layer below a surface bead sparse);
      // with the margin 0.994 at 40 mm and 0.995 at 50 mm, as the solid fill's 0.994 and 0.996.
      const Mesh& m = region.mesh;
      std::vector<double> reach(m.vertexCount(), 0.0);
      for (size_t t = 0; t < m.faceCount(); ++t) {
        const uint32_t* tri = &m.triangles[3 * t];
        const Eigen::Vector3d a = m.vertex(tri[0]), b = m.vertex(tri[1]), c = m.vertex(tri[2]);
        const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
        for (int j = 0; j < 3; ++j) reach[tri[j]] = std::max(reach[tri[j]], 0.6 * longest);
      }
      std::vector<uint8_t> shallow(m.vertexCount(), 0);
      for (size_t v = 0; v < m.vertexCount(); ++v) {
        shallow[v] = surface->anyWithin(m.vertex(v), sparse.shellMm + reach[v]);
      }
      std::vector<uint8_t> deep(m.faceCount(), 0);
      size_t deepCount = 0;
      f.surfaceChecked = true;
      for (size_t t = 0; t < m.faceCount(); ++t) {
        const double a = triangleArea(m, t);
        f.area += a;
        if (shallow[m.triangles[3 * t]] || shallow[m.triangles[3 * t + 1]] || shallow[m.triangles[3 * t + 2]]) continue;
        deep[t] = 1;
        ++deepCount;
        f.interiorArea += a;
      }
      if (deepCount > 0) {
        SpiralResult inner;
        if (interior.spacing > 0) inner = fermatSpiralPaths(trianglesOf(m, deep), interior);
        for (uint8_t& d : deep) d = !d;
        SpiralResult outer;
        if (deepCount < m.faceCount()) outer = fermatSpiralPaths(trianglesOf(m, deep), sopt);
        // The shell first (walls and skins), then the interior; where either spiral fails, the
        // whole region solid below (nothing of the shell may go missing).
        if (outer.ok() && inner.ok()) {
          f.sparseMade = true;
          filled = std::move(outer.paths);
          filled.insert(filled.end(), inner.paths.begin(), inner.paths.end());
          f.filled = !filled.empty();
          return;
        }
      }
    }
    SpiralResult spiral = fermatSpiralPaths(region.mesh, sopt);
    if (!spiral.ok() || spiral.paths.empty()) return;
    f.filled = true;
    filled = std::move(spiral.paths);
  };
  const bool finished = parallelFor(regions.size(), threadCount(settings.threads), fillRegion, [&](size_t done) {
    return reportProgress(progress, stage, progressScale * double(done) / double(regions.size()));
  });
  if (!finished) return failed<CurvedFill>(Status::Cancelled, "cancelled");
  for (const RegionFill& f : regions) {
    ++out.regions;
    if (!f.filled) ++out.unfilled;
    out.pathCount += out.paths[f.layer][f.region].size();
    if (f.surfaceChecked) sparse.areaMm2 += f.area;
    if (f.sparseMade) {
      ++sparse.sparseRegions;
      sparse.interiorAreaMm2 += f.interiorArea;
    }
  }
  if (surface) out.sparse = sparse;
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
  o.axisFreedomDegrees = settings.effectiveAxisFreedom();
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
      appendFloats(p.positions, region.mesh.positions);
      for (uint32_t i : region.mesh.triangles) p.triangles.push_back(base + i);
      p.layers.insert(p.layers.end(), region.mesh.faceCount(), static_cast<uint32_t>(l));
    }
  }
}

}  // namespace omnislice::stage
