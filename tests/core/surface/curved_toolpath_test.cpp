// SPDX-License-Identifier: MIT
// Curved-layer tool-path assembly: orientation by Eq. 3 (paper 001 Section 5.2) on stacked flat
// discs and concentric spherical caps, local bead heights, the bead-area extrusion formula,
// nearest-neighbour region order, travel/retraction bookkeeping, fallbacks and bad input.
#include "common/math_constants.h"
#include "surface/curved_toolpath.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "geometry/aabb_tree.h"

namespace omnislice {
namespace {

using Eigen::Vector3d;

// Flat disc of the given radius at height z centred at (cx, cy), as a triangle fan (normal +Z).
LayerRegion discRegion(double cx, double cy, double z, double radius, int segments = 64) {
  LayerRegion r;
  r.mesh.positions = {cx, cy, z};
  for (int k = 0; k < segments; ++k) {
    const double a = 2 * kPi * k / segments;
    r.mesh.positions.insert(r.mesh.positions.end(), {cx + radius * std::cos(a), cy + radius * std::sin(a), z});
  }
  for (int k = 0; k < segments; ++k) {
    r.mesh.triangles.insert(r.mesh.triangles.end(),
                            {0u, uint32_t(1 + k), uint32_t(1 + (k + 1) % segments)});
  }
  r.boundaryVertex.assign(r.mesh.vertexCount(), 1);
  r.boundaryVertex[0] = 0;
  r.area = 0.5 * segments * radius * radius * std::sin(2 * kPi / segments);
  return r;
}

// Zigzag path inside a disc: lines of y = const every `spacing`, |x| < half-chord - 1, sampled
// every ~1 mm, alternating direction. normal: the normal given for every point.
SurfacePath zigzag(double cx, double cy, double z, double radius, double spacing, const Vector3d& normal) {
  SurfacePath p;
  bool forward = true;
  for (double y = -radius + spacing; y < radius - spacing; y += spacing) {
    const double half = std::sqrt(radius * radius - y * y) - 1;
    if (half <= 0.5) continue;
    const int n = std::max(2, int(std::ceil(2 * half)));
    for (int i = 0; i <= n; ++i) {
      const double t = forward ? double(i) / n : 1 - double(i) / n;
      p.points.emplace_back(cx - half + 2 * half * t, cy + y, z);
      p.normals.push_back(normal);
    }
    forward = !forward;
  }
  return p;
}

// Spherical cap of radius r around centre c, polar angle up to thetaMax (from +Z).
LayerRegion capRegion(const Vector3d& c, double r, double thetaMax, int rings, int sectors) {
  LayerRegion reg;
  auto add = [&](const Vector3d& p) { reg.mesh.positions.insert(reg.mesh.positions.end(), {p.x(), p.y(), p.z()}); };
  add(c + Vector3d(0, 0, r));
  for (int j = 1; j <= rings; ++j) {
    const double th = thetaMax * j / rings;
    for (int k = 0; k < sectors; ++k) {
      const double ph = 2 * kPi * k / sectors;
      add(c + r * Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  }
  auto ring = [&](int j, int k) { return uint32_t(1 + (j - 1) * sectors + (k % sectors)); };
  for (int k = 0; k < sectors; ++k) reg.mesh.triangles.insert(reg.mesh.triangles.end(), {0u, ring(1, k), ring(1, k + 1)});
  for (int j = 1; j < rings; ++j) {
    for (int k = 0; k < sectors; ++k) {
      reg.mesh.triangles.insert(reg.mesh.triangles.end(), {ring(j, k), ring(j + 1, k), ring(j + 1, k + 1)});
      reg.mesh.triangles.insert(reg.mesh.triangles.end(), {ring(j, k), ring(j + 1, k + 1), ring(j, k + 1)});
    }
  }
  reg.boundaryVertex.assign(reg.mesh.vertexCount(), 0);
  return reg;
}

// A spiral-like path on the sphere of radius r around c: polar angle from 3 to thetaEnd degrees
// while the azimuth turns, points ~1 mm apart, normals radial.
SurfacePath sphericalPath(const Vector3d& c, double r, double thetaEndDeg) {
  SurfacePath p;
  const double thEnd = thetaEndDeg * kPi / 180;
  double th = 3 * kPi / 180, ph = 0;
  while (th < thEnd) {
    const Vector3d u(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    p.points.push_back(c + r * u);
    p.normals.push_back(u);
    ph += 1.0 / (r * std::sin(th));  // ~1 mm along the azimuth
    th += 0.02 / r;
  }
  return p;
}

// A stadium cross-section: a rectangle with round ends on its smaller side.
double bead(double w, double h) {
  const double r = std::min(w, h) / 2;
  return w * h - (4 - kPi) * r * r;
}

// Properties every tool-path must have: unit axes; travel moves never extrude; every Retract is
// answered by an Unretract before the next print move and the filament of the moves between two
// print moves sums to zero; print moves extrude by the bead formula.
void expectWellFormed(const CurvedToolpathResult& r, const CurvedToolpathOptions& o) {
  ASSERT_TRUE(r.ok()) << r.message;
  bool retracted = false;
  double between = 0;
  size_t retracts = 0, unretracts = 0;
  Vector3d pos = r.toolpath.start;
  for (const Move& m : r.toolpath.moves) {
    ASSERT_NEAR(m.axis.norm(), 1, 1e-12);
    switch (m.kind) {
      case MoveKind::Travel:
        ASSERT_EQ(m.filament, 0);
        ASSERT_EQ(m.width, 0);
        break;
      case MoveKind::Retract:
        ASSERT_FALSE(retracted);
        ASSERT_EQ(m.filament, -o.retractLength);
        ASSERT_EQ(m.position, pos) << "retract does not move";
        retracted = true;
        ++retracts;
        between += m.filament;
        break;
      case MoveKind::Unretract:
        ASSERT_TRUE(retracted);
        ASSERT_EQ(m.position, pos) << "unretract does not move";
        retracted = false;
        ++unretracts;
        between += m.filament;
        break;
      case MoveKind::Print:
      case MoveKind::Support: {
        ASSERT_FALSE(retracted) << "printing while retracted";
        ASSERT_NEAR(between, 0, 1e-12) << "unbalanced retraction around a travel";
        between = 0;
        const double len = (m.position - pos).norm();
        ASSERT_GT(len, 0);
        ASSERT_GT(m.width, 0);
        ASSERT_LE(m.width, o.lineWidth);  // narrow regions: their own width
        ASSERT_GE(m.height, o.minHeightFactor * o.nominalHeight - 1e-12);
        ASSERT_LE(m.height, o.maxHeightFactor * o.nominalHeight + 1e-12);
        const double expected = bead(m.width, m.height) * len / (kPi * o.filamentDiameter * o.filamentDiameter / 4);
        ASSERT_NEAR(m.filament, expected, 1e-12 * (1 + expected));
        ASSERT_EQ(m.speed, m.layer == 0 ? o.firstLayerSpeed : o.printSpeed);
        break;
      }
    }
    pos = m.position;
  }
  EXPECT_FALSE(retracted);
  EXPECT_EQ(retracts, unretracts);
}

// Stacked flat discs: per layer three regions (discs at x = 0, 60, 30), spacing 0.4 mm.
struct DiscStack {
  std::vector<CurvedLayer> layers;
  std::vector<std::vector<std::vector<SurfacePath>>> paths;
};
DiscStack discStack(int count, double z0, double spacing) {
  DiscStack s;
  const double xs[3] = {0, 60, 30};
  for (int l = 0; l < count; ++l) {
    const double z = z0 + l * spacing;
    CurvedLayer layer;
    layer.isoValue = l;
    std::vector<std::vector<SurfacePath>> lp;
    for (double x : xs) {
      layer.regions.push_back(discRegion(x, 0, z, 10));
      // Normals alternate in sign by layer: orientation must not depend on them here.
      lp.push_back({zigzag(x, 0, z, 10, 0.45 * 4, Vector3d(0, 0, l % 2 ? -1 : 1))});
    }
    s.layers.push_back(layer);
    s.paths.push_back(lp);
  }
  return s;
}

TEST(CurvedToolpath, StackedFlatDiscsGivePlusZAndTheSpacing) {
  const double spacing = 0.4;
  const DiscStack s = discStack(6, 0.16, spacing);
  CurvedToolpathOptions o;
  const CurvedToolpathResult r = buildCurvedToolpath(s.layers, s.paths, o);
  expectWellFormed(r, o);
  EXPECT_EQ(r.toolpath.layerCount, 6);
  EXPECT_EQ(r.orientationFallbacks, 0u);
  std::vector<double> length(6, 0), filament(6, 0);
  Vector3d pos = r.toolpath.start;
  size_t prints = 0;
  for (const Move& m : r.toolpath.moves) {
    if (m.kind == MoveKind::Print) {
      ++prints;
      EXPECT_NEAR((m.axis - Vector3d::UnitZ()).norm(), 0, 1e-12);
      EXPECT_EQ(m.feature, Feature::Infill);
      EXPECT_NEAR(m.height, m.layer == 0 ? o.nominalHeight : spacing, 1e-12);
      EXPECT_NEAR(m.position.z(), 0.16 + m.layer * spacing, 1e-12);
      length[m.layer] += (m.position - pos).norm();
      filament[m.layer] += m.filament;
    }
    pos = m.position;
  }
  EXPECT_GT(prints, 6u * 3u * 50u);
  // Per layer: filament = bead area x path length / filament section.
  for (int l = 0; l < 6; ++l) {
    const double h = l == 0 ? o.nominalHeight : spacing;
    EXPECT_NEAR(filament[l], bead(o.lineWidth, h) * length[l] / (kPi * 1.75 * 1.75 / 4), 1e-9 * filament[l]);
  }
  // The path lengths equal the input polylines' lengths (nothing dropped, nothing added).
  double input = 0;
  for (const auto& layer : s.paths)
    for (const auto& region : layer)
      for (const SurfacePath& p : region)
        for (size_t i = 1; i < p.points.size(); ++i) input += (p.points[i] - p.points[i - 1]).norm();
  double total = 0;
  for (double L : length) total += L;
  EXPECT_NEAR(total, input, 1e-9 * input);
}

TEST(CurvedToolpath, NarrowPathsPrintWithTheirOwnWidth) {
  // Region 0 of every layer a sliver's centre line (0.12 mm wide), region 1 wider than a bead
  // (capped at the line width), region 2 the tool-path's width: the filament follows each width.
  DiscStack s = discStack(3, 0.16, 0.4);
  const double widths[3] = {0.12, 2.0, 0};
  for (auto& layer : s.paths)
    for (int r = 0; r < 3; ++r) layer[size_t(r)][0].width = widths[r];
  CurvedToolpathOptions o;
  const CurvedToolpathResult r = buildCurvedToolpath(s.layers, s.paths, o);
  expectWellFormed(r, o);
  double filament[3] = {0, 0, 0}, length[3] = {0, 0, 0};
  Vector3d pos = r.toolpath.start;
  for (const Move& m : r.toolpath.moves) {
    if (m.kind == MoveKind::Print && m.layer > 0) {
      const int region = m.position.x() < 15 ? 0 : m.position.x() > 45 ? 1 : 2;
      EXPECT_EQ(m.width, region == 0 ? 0.12 : o.lineWidth) << region;
      filament[region] += m.filament;
      length[region] += (m.position - pos).norm();
    }
    pos = m.position;
  }
  const double section = kPi * 1.75 * 1.75 / 4;
  EXPECT_NEAR(filament[0], bead(0.12, 0.4) * length[0] / section, 1e-9 * filament[0]);
  EXPECT_NEAR(filament[1], bead(o.lineWidth, 0.4) * length[1] / section, 1e-9 * filament[1]);
  EXPECT_NEAR(filament[2], filament[1] * length[2] / length[1], 1e-9 * filament[2]);
  // The sliver's bead is narrower than it is tall: about a third of a full bead's filament
  // (0.045 against 0.146 mm^2), not the full bead.
  EXPECT_LT(filament[0] / length[0], 0.35 * filament[2] / length[2]);
}

TEST(CurvedToolpath, RegionsNearestFirstAndLongTravelsRetractAndLeaveAlongTheAxis) {
  const DiscStack s = discStack(3, 0.16, 0.4);
  CurvedToolpathOptions o;
  const CurvedToolpathResult r = buildCurvedToolpath(s.layers, s.paths, o);
  expectWellFormed(r, o);
  // Region order per layer from the x of the print moves: layer 0 starts at x = 0 (nearest to
  // the park position, which is the first start), then 30, then 60; layer 1 starts where layer 0
  // ended (x = 60) and goes back.
  std::vector<std::vector<int>> order(3);
  for (const Move& m : r.toolpath.moves) {
    if (m.kind != MoveKind::Print) continue;
    const int region = int(std::lround(m.position.x() / 30.0)) * 30;
    if (order[m.layer].empty() || order[m.layer].back() != region) order[m.layer].push_back(region);
  }
  EXPECT_EQ(order[0], (std::vector<int>{0, 30, 60}));
  EXPECT_EQ(order[1], (std::vector<int>{60, 30, 0}));
  EXPECT_EQ(order[2], (std::vector<int>{0, 30, 60}));
  // Every long travel: Retract, leave along the axis by the clearance, cross, approach, Unretract.
  const auto& mv = r.toolpath.moves;
  size_t retracts = 0;
  for (size_t i = 0; i < mv.size(); ++i) {
    if (mv[i].kind != MoveKind::Retract) continue;
    ++retracts;
    ASSERT_LT(i + 4, mv.size());
    EXPECT_EQ(mv[i + 1].kind, MoveKind::Travel);
    EXPECT_NEAR((mv[i + 1].position - (mv[i].position + o.travelClearance * mv[i].axis)).norm(), 0, 1e-12);
    EXPECT_EQ(mv[i + 2].kind, MoveKind::Travel);
    EXPECT_EQ(mv[i + 3].kind, MoveKind::Travel);
    EXPECT_NEAR((mv[i + 2].position - (mv[i + 3].position + o.travelClearance * mv[i + 3].axis)).norm(), 0, 1e-12);
    EXPECT_EQ(mv[i + 4].kind, MoveKind::Unretract);
    EXPECT_GT((mv[i + 3].position - mv[i].position).norm(), o.retractMinTravel);
  }
  // 3 layers x 3 regions = 9 paths: 8 travels between them, all longer than 1.5 mm.
  EXPECT_EQ(retracts, 8u);
  // No retraction before the first extrusion; the park position is above the first point.
  EXPECT_EQ(mv[0].kind, MoveKind::Travel);
  EXPECT_NEAR((r.toolpath.start - (mv[0].position + o.travelClearance * Vector3d::UnitZ())).norm(), 0, 1e-12);
  // Retraction off: no Retract/Unretract at all.
  o.retractLength = 0;
  const CurvedToolpathResult off = buildCurvedToolpath(s.layers, s.paths, o);
  ASSERT_TRUE(off.ok());
  for (const Move& m : off.toolpath.moves) {
    EXPECT_NE(m.kind, MoveKind::Retract);
    EXPECT_NE(m.kind, MoveKind::Unretract);
  }
}

// Concentric spherical caps around a centre below the platform: the axis is the radial direction
// (within 1 degree: the caps are polyhedral) and the height is the radial spacing.
TEST(CurvedToolpath, ConcentricSphericalCapsGiveRadialAxesAndSpacing) {
  const Vector3d c(1.5, -2.0, -10);
  const double r0 = 20, h = 0.3;
  std::vector<CurvedLayer> layers;
  std::vector<std::vector<std::vector<SurfacePath>>> paths;
  for (int l = 0; l < 5; ++l) {
    CurvedLayer layer;
    layer.regions.push_back(capRegion(c, r0 + l * h, 45 * kPi / 180, 60, 360));
    layers.push_back(layer);
    paths.push_back({{sphericalPath(c, r0 + l * h, 32)}});
  }
  CurvedToolpathOptions o;
  o.nominalHeight = 0.32;
  const CurvedToolpathResult r = buildCurvedToolpath(layers, paths, o);
  expectWellFormed(r, o);
  EXPECT_EQ(r.orientationFallbacks, 0u);
  // Independent closest points (brute force over every triangle of the earlier layers).
  std::vector<Mesh> meshes;
  for (const CurvedLayer& L : layers) meshes.push_back(L.regions[0].mesh);
  double worstDeg = 0, worstHeight = 0;
  size_t checked = 0;
  for (size_t i = 0; i < r.toolpath.moves.size(); ++i) {
    const Move& m = r.toolpath.moves[i];
    if (m.kind != MoveKind::Print) continue;
    if (m.layer == 0) {
      EXPECT_NEAR((m.axis - Vector3d::UnitZ()).norm(), 0, 1e-12);
      continue;
    }
    const Vector3d radial = (m.position - c).normalized();
    worstDeg = std::max(worstDeg, std::acos(std::min(1.0, m.axis.dot(radial))) * 180 / kPi);
    worstHeight = std::max(worstHeight, std::abs(m.height - h));
    if (i % 17 == 0) {
      // Eq. 3 by brute force: closest point over all triangles of layers max(0, l - 3) .. l - 1.
      double best = std::numeric_limits<double>::infinity();
      Vector3d cq = Vector3d::Zero();
      for (int k = std::max(0, m.layer - 3); k < m.layer; ++k) {
        const Mesh& mesh = meshes[k];
        for (size_t f = 0; f < mesh.faceCount(); ++f) {
          const Vector3d p = closestPointOnTriangle(m.position, mesh.vertex(mesh.triangles[3 * f]),
                                                    mesh.vertex(mesh.triangles[3 * f + 1]),
                                                    mesh.vertex(mesh.triangles[3 * f + 2]));
          const double d = (p - m.position).norm();
          if (d < best) {
            best = d;
            cq = p;
          }
        }
      }
      EXPECT_NEAR((m.axis - (m.position - cq).normalized()).norm(), 0, 1e-9);
      ++checked;
    }
  }
  EXPECT_GT(checked, 20u);
  EXPECT_LT(worstDeg, 1.0);
  EXPECT_LT(worstHeight, 0.01);
  std::printf("caps: worst axis deviation from radial %.3f deg, worst |height - h| %.5f mm, "
              "orientation %.1f ms\n", worstDeg, worstHeight, r.orientationMs);
}

// Fallbacks: a region beside (not above) the earlier layer sees it at ~89 degrees from its normal;
// a region lying on the earlier layer sees it at distance 0. Both use the normal, flipped to the
// side of the earlier layers / +Z.
TEST(CurvedToolpath, FallsBackToTheFlippedNormal) {
  std::vector<CurvedLayer> layers(3);
  layers[0].regions.push_back(discRegion(0, 0, 5.16, 10));
  layers[1].regions.push_back(discRegion(13, 0, 5.2, 1.5));
  layers[2].regions.push_back(discRegion(13, 0, 5.2, 1.5));
  SurfacePath beside;
  for (int i = 0; i <= 4; ++i) {
    beside.points.emplace_back(12.2 + 0.4 * i, 0, 5.2);
    beside.normals.emplace_back(0, 0, -1);  // pointing down: must be flipped up
  }
  std::vector<std::vector<std::vector<SurfacePath>>> paths = {
      {{zigzag(0, 0, 5.16, 10, 2, Vector3d::UnitZ())}}, {{beside}}, {{beside}}};
  CurvedToolpathOptions o;
  const CurvedToolpathResult r = buildCurvedToolpath(layers, paths, o);
  expectWellFormed(r, o);
  EXPECT_EQ(r.orientationFallbacks, 2u * beside.points.size());
  for (const Move& m : r.toolpath.moves) {
    if (m.kind != MoveKind::Print || m.layer == 0) continue;
    EXPECT_NEAR((m.axis - Vector3d::UnitZ()).norm(), 0, 1e-12);
    // Layer 1: the disc is >= 2.2 mm away, clamped to the maximum; layer 2: distance 0, minimum.
    EXPECT_NEAR(m.height, (m.layer == 1 ? o.maxHeightFactor : o.minHeightFactor) * o.nominalHeight, 1e-12);
  }
}

// Eq. 3 searches the previous earlierLayers layers (and the platform plane): layer 2 sits 0.3 mm
// above layer 0 while layer 1 lies far away. With 3 earlier layers the height is 0.3; with 1 only
// layer 1 and the platform (5.3 mm below) count, so the height is clamped to the maximum.
TEST(CurvedToolpath, SearchesOnlyTheEarlierLayerWindow) {
  std::vector<CurvedLayer> layers(3);
  layers[0].regions.push_back(discRegion(0, 0, 5.0, 10));
  layers[1].regions.push_back(discRegion(100, 0, 5.2, 10));
  layers[2].regions.push_back(discRegion(0, 0, 5.3, 10));
  std::vector<std::vector<std::vector<SurfacePath>>> paths = {
      {{zigzag(0, 0, 5.0, 10, 2, Vector3d::UnitZ())}},
      {{zigzag(100, 0, 5.2, 10, 2, Vector3d::UnitZ())}},
      {{zigzag(0, 0, 5.3, 10, 2, Vector3d::UnitZ())}}};
  for (int window : {3, 2, 1}) {
    SCOPED_TRACE(window);
    CurvedToolpathOptions o;
    o.earlierLayers = window;
    const CurvedToolpathResult r = buildCurvedToolpath(layers, paths, o);
    expectWellFormed(r, o);
    size_t checked = 0;
    for (const Move& m : r.toolpath.moves) {
      if (m.kind != MoveKind::Print || m.layer != 2) continue;
      ++checked;
      EXPECT_NEAR((m.axis - Vector3d::UnitZ()).norm(), 0, 1e-12);
      EXPECT_NEAR(m.height, window >= 2 ? 0.3 : o.maxHeightFactor * o.nominalHeight, 1e-9);
    }
    EXPECT_GT(checked, 50u);
  }
}

TEST(CurvedToolpath, SupportRegionsPrintAsSupport) {
  DiscStack s = discStack(2, 0.16, 0.32);
  s.layers[1].regions[2].support = true;
  CurvedToolpathOptions o;
  const CurvedToolpathResult r = buildCurvedToolpath(s.layers, s.paths, o);
  expectWellFormed(r, o);
  size_t support = 0;
  for (const Move& m : r.toolpath.moves) {
    if (m.kind == MoveKind::Support) {
      ++support;
      EXPECT_EQ(m.feature, Feature::Support);
      EXPECT_EQ(m.layer, 1);
      EXPECT_NEAR(m.position.x(), 30, 10);
    } else if (m.kind == MoveKind::Print) {
      EXPECT_EQ(m.feature, Feature::Infill);
    }
  }
  EXPECT_GT(support, 50u);
}

TEST(CurvedToolpath, BadInputAndCancellation) {
  const DiscStack s = discStack(2, 0.16, 0.32);
  // Empty input: an empty tool-path.
  const CurvedToolpathResult empty = buildCurvedToolpath({}, {}, {});
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty.toolpath.moves.empty());
  EXPECT_EQ(empty.toolpath.layerCount, 0);
  // Shape mismatch.
  auto paths = s.paths;
  paths.pop_back();
  EXPECT_EQ(buildCurvedToolpath(s.layers, paths, {}).status, Status::InvalidOption);
  paths = s.paths;
  paths[1].pop_back();
  EXPECT_EQ(buildCurvedToolpath(s.layers, paths, {}).status, Status::InvalidOption);
  // Non-finite point.
  paths = s.paths;
  paths[1][0][0].points[3].x() = std::nan("");
  EXPECT_EQ(buildCurvedToolpath(s.layers, paths, {}).status, Status::NonFiniteVertex);
  // Options.
  auto bad = [&](auto set) {
    CurvedToolpathOptions o;
    set(o);
    return buildCurvedToolpath(s.layers, s.paths, o).status;
  };
  EXPECT_EQ(bad([](auto& o) { o.lineWidth = 0; }), Status::InvalidOption);
  EXPECT_EQ(bad([](auto& o) { o.nominalHeight = std::nan(""); }), Status::InvalidOption);
  EXPECT_EQ(bad([](auto& o) { o.minHeightFactor = 2; }), Status::InvalidOption);
  EXPECT_EQ(bad([](auto& o) { o.filamentDiameter = -1; }), Status::InvalidOption);
  EXPECT_EQ(bad([](auto& o) { o.printSpeed = 0; }), Status::InvalidOption);
  EXPECT_EQ(bad([](auto& o) { o.retractLength = -1; }), Status::InvalidOption);
  EXPECT_EQ(bad([](auto& o) { o.earlierLayers = 0; }), Status::InvalidOption);
  // Paths with fewer than two points and missing normals do not break anything.
  paths = s.paths;
  paths[0][0][0].points.resize(1);
  paths[1][1][0].normals.clear();
  const CurvedToolpathResult sparse = buildCurvedToolpath(s.layers, paths, {});
  expectWellFormed(sparse, {});
  // Cancellation.
  int calls = 0;
  const CurvedToolpathResult c =
      buildCurvedToolpath(s.layers, s.paths, {}, [&](const char* stage, double) {
        EXPECT_STREQ(stage, "toolpath");
        return ++calls < 2;
      });
  EXPECT_EQ(c.status, Status::Cancelled);
}

}  // namespace
}  // namespace omnislice

namespace omnislice {
namespace {

// Measurement (printed): 60 spherical-cap layers of ~19k triangles each, a dense spiral path
// (turns 0.45 mm apart, points 1 mm apart) per layer. Asserts the radial axes only.
TEST(CurvedToolpath, SixtyDenseLayersMeasurement) {
  const Vector3d c(0, 0, -10);
  const double r0 = 20, h = 0.3;
  std::vector<CurvedLayer> layers;
  std::vector<std::vector<std::vector<SurfacePath>>> paths;
  size_t points = 0;
  for (int l = 0; l < 60; ++l) {
    const double r = r0 + l * h;
    CurvedLayer layer;
    layer.regions.push_back(capRegion(c, r, 45 * kPi / 180, 40, 240));
    SurfacePath p;
    // Archimedean spiral in (theta, phi): theta grows 0.45 mm per turn.
    double th = 0.5 / r, ph = 0;
    while (th < 40 * kPi / 180) {
      const Vector3d u(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      p.points.push_back(c + r * u);
      p.normals.push_back(u);
      const double dph = 1.0 / (r * std::sin(th));
      ph += dph;
      th += 0.45 / r * dph / (2 * kPi);
    }
    points += p.points.size();
    layers.push_back(layer);
    paths.push_back({{p}});
  }
  CurvedToolpathOptions o;
  const auto t0 = std::chrono::steady_clock::now();
  const CurvedToolpathResult r = buildCurvedToolpath(layers, paths, o);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  expectWellFormed(r, o);
  double worst = 0;
  for (const Move& m : r.toolpath.moves) {
    if (m.kind != MoveKind::Print || m.layer == 0) continue;
    worst = std::max(worst, std::acos(std::min(1.0, m.axis.dot((m.position - c).normalized()))) * 180 / kPi);
  }
  EXPECT_LT(worst, 1.5);
  // Progress is reported within long paths too (every 1024 points), monotone, and cancels there.
  int calls = 0;
  double last = -1;
  bool monotone = true;
  const CurvedToolpathResult cut = buildCurvedToolpath(layers, paths, o, [&](const char*, double f) {
    monotone = monotone && f >= last;
    last = f;
    return ++calls < 70;  // past the 60 per-layer reports only if paths report too
  });
  EXPECT_EQ(cut.status, Status::Cancelled);
  EXPECT_TRUE(monotone);
  EXPECT_LT(last, 0.5);
  std::printf("60 layers, %zu path points, %zu moves: %.0f ms (orientation %.0f ms), worst radial "
              "deviation %.2f deg\n", points, r.toolpath.moves.size(), ms, r.orientationMs, worst);
}


// ---- gouging correction (paper 001 Section 6.2.3) ----

// Collision count of a tool-path by the rule of `omnislice verify`, brute force: samples every
// 0.5 mm along each print move (from its start, the move's axis), an earlier sample p inside the
// cone at sample s: (p - s).u > h, angle(p - s, u) < half-angle, |p - s| < length.
size_t bruteForceCollisions(const Toolpath& tp, double h, double halfAngleDeg, double length) {
  struct S {
    Vector3d p, u;
  };
  std::vector<S> samples;
  Vector3d pos = tp.start;
  for (const Move& m : tp.moves) {
    const double len = (m.position - pos).norm();
    if (m.filament > 0 && len > 1e-9) {
      for (double t = 0; t < len || t == 0; t += 0.5) samples.push_back({pos + (t / len) * (m.position - pos), m.axis.normalized()});
    }
    pos = m.position;
  }
  const double cosT = std::cos(halfAngleDeg * kPi / 180);
  size_t collisions = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const Vector3d d = samples[j].p - samples[i].p;
      const double a = d.dot(samples[i].u), n = d.norm();
      if (a > h && n < length && a > cosT * n) {
        ++collisions;
        break;
      }
    }
  }
  return collisions;
}

// Layer 0: a flat disc at z = 0.3. Layer 1: a disc at z = 0.6 whose first path is the top of a
// taller wall printed before, 4 mm above the layer near the disc rim (y = 9.8), then a zigzag
// over the disc: Eq. 3 gives +Z there, and the zigzag points near y = 7, 8 have the wall inside their
// 40 degree cone.
DiscStack wallOverDisc() {
  DiscStack s;
  s.layers.resize(2);
  s.paths.resize(2);
  s.layers[0].regions.push_back(discRegion(0, 0, 0.3, 10));
  s.layers[1].regions.push_back(discRegion(0, 0, 0.6, 10));
  s.paths[0].push_back({zigzag(0, 0, 0.3, 10, 1.0, Vector3d::UnitZ())});
  SurfacePath wall;
  for (int i = 0; i <= 12; ++i) {
    wall.points.emplace_back(-3 + 0.5 * i, 9.8, 4.6);
    wall.normals.push_back(Vector3d::UnitZ());
  }
  s.paths[1].push_back({wall, zigzag(0, 0, 0.6, 10, 1.0, Vector3d::UnitZ())});
  return s;
}

TEST(CurvedToolpath, GougingCorrectionTurnsCollidingAxesToFreeOnes) {
  const DiscStack s = wallOverDisc();
  CurvedToolpathOptions off;
  off.correctGouging = false;
  const CurvedToolpathResult plain = buildCurvedToolpath(s.layers, s.paths, off);
  ASSERT_TRUE(plain.ok()) << plain.message;
  EXPECT_EQ(plain.gougingCorrections, 0u);
  const size_t before = bruteForceCollisions(plain.toolpath, off.nominalHeight, 40, 25);
  EXPECT_GT(before, 10u);  // Eq. 3 axes gouge into the wall
  printf("wall over disc: %zu colliding samples with the Eq. 3 axes\n", before);

  CurvedToolpathOptions o;
  o.collisionClearance = o.nominalHeight;
  const CurvedToolpathResult r = buildCurvedToolpath(s.layers, s.paths, o);
  expectWellFormed(r, o);
  EXPECT_GT(r.gougingCorrections, 0u);
  EXPECT_EQ(r.gougingUncorrected, 0u);
  EXPECT_EQ(bruteForceCollisions(r.toolpath, o.nominalHeight, 40, 25), 0u);

  // Same moves and positions; axes unchanged on layer 0 and far from the wall; neighbouring
  // print axes stay within the planner's 10 degree filter threshold where corrected.
  ASSERT_EQ(r.toolpath.moves.size(), plain.toolpath.moves.size());
  size_t unchangedFar = 0;
  for (size_t i = 0; i < r.toolpath.moves.size(); ++i) {
    const Move& a = r.toolpath.moves[i];
    const Move& b = plain.toolpath.moves[i];
    EXPECT_NEAR((a.position - b.position).norm(), 0, 1e-12);
    if (a.layer == 0 || a.position.y() < -4) {
      EXPECT_NEAR((a.axis - b.axis).norm(), 0, 1e-12) << "move " << i;
      ++unchangedFar;
    }
    if (i > 0 && a.kind == MoveKind::Print && r.toolpath.moves[i - 1].kind == MoveKind::Print) {
      const Vector3d& u0 = r.toolpath.moves[i - 1].axis;
      EXPECT_LT(std::acos(std::clamp(u0.dot(a.axis), -1.0, 1.0)) * 180 / kPi, 10.0) << "move " << i;
    }
  }
  EXPECT_GT(unchangedFar, 100u);

  // Within a tilt range: still collision-free, no axis beyond it.
  o.maxTiltDegrees = 60;
  const CurvedToolpathResult tilted = buildCurvedToolpath(s.layers, s.paths, o);
  ASSERT_TRUE(tilted.ok()) << tilted.message;
  EXPECT_EQ(tilted.gougingUncorrected, 0u);
  EXPECT_EQ(bruteForceCollisions(tilted.toolpath, o.nominalHeight, 40, 25), 0u);
  for (const Move& m : tilted.toolpath.moves) {
    EXPECT_LE(std::acos(std::clamp(m.axis.z(), -1.0, 1.0)) * 180 / kPi, 60 + 1e-9);
  }

  // Nothing to correct on stacked discs: identical to the run without correction.
  const DiscStack stack = discStack(4, 0.16, 0.4);
  const CurvedToolpathResult a = buildCurvedToolpath(stack.layers, stack.paths, o);
  const CurvedToolpathResult b = buildCurvedToolpath(stack.layers, stack.paths, off);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a.gougingCorrections, 0u);
  ASSERT_EQ(a.toolpath.moves.size(), b.toolpath.moves.size());
  for (size_t i = 0; i < a.toolpath.moves.size(); ++i) {
    EXPECT_EQ(a.toolpath.moves[i].axis, b.toolpath.moves[i].axis);
  }

  // Bad cone options.
  CurvedToolpathOptions bad = o;
  bad.coneHalfAngleDegrees = 90;
  EXPECT_EQ(buildCurvedToolpath(s.layers, s.paths, bad).status, Status::InvalidOption);
  bad = o;
  bad.coneLength = 0;
  EXPECT_EQ(buildCurvedToolpath(s.layers, s.paths, bad).status, Status::InvalidOption);
}

// Where no axis within the tilt range is free (the wall over the disc with the axis held within 5
// degrees of +Z), the colliding segments are left out with skipUncorrectable: the program then has
// no collision, the rest prints as before and what is missing is counted.
TEST(CurvedToolpath, UncorrectableSegmentsAreLeftOutAndCounted) {
  const DiscStack s = wallOverDisc();
  CurvedToolpathOptions o;
  o.collisionClearance = o.nominalHeight;
  o.maxTiltDegrees = 5;
  const CurvedToolpathResult kept = buildCurvedToolpath(s.layers, s.paths, o);
  ASSERT_TRUE(kept.ok()) << kept.message;
  EXPECT_GT(kept.gougingUncorrected, 0u);
  EXPECT_EQ(kept.skippedPoints, 0u);
  EXPECT_GT(bruteForceCollisions(kept.toolpath, o.nominalHeight, 40, 25), 0u);

  o.skipUncorrectable = true;
  const CurvedToolpathResult r = buildCurvedToolpath(s.layers, s.paths, o);
  expectWellFormed(r, o);
  EXPECT_GT(r.skippedPoints, 0u);
  EXPECT_EQ(bruteForceCollisions(r.toolpath, o.nominalHeight, 40, 25), 0u);
  // Printed length = the full program's less the skipped segments; every skipped segment lies
  // under the wall (y > 4), and the wall itself and layer 0 print in full.
  auto printedMm = [](const Toolpath& tp, double minY) {
    double mm = 0;
    Vector3d pos = tp.start;
    for (const Move& m : tp.moves) {
      if (m.kind == MoveKind::Print && m.position.y() >= minY) mm += (m.position - pos).norm();
      pos = m.position;
    }
    return mm;
  };
  const double all = printedMm(kept.toolpath, -1e9), left = printedMm(r.toolpath, -1e9);
  EXPECT_NEAR(all - left, r.skippedMm, 1e-9);
  EXPECT_GT(r.skippedMm, 1.0);
  EXPECT_NEAR(printedMm(kept.toolpath, -1e9) - printedMm(kept.toolpath, 4.0),
              printedMm(r.toolpath, -1e9) - printedMm(r.toolpath, 4.0), 1.0);
  size_t layer0 = 0, layer0Kept = 0;
  for (const Move& m : r.toolpath.moves) layer0 += m.layer == 0 && m.kind == MoveKind::Print;
  for (const Move& m : kept.toolpath.moves) layer0Kept += m.layer == 0 && m.kind == MoveKind::Print;
  EXPECT_EQ(layer0, layer0Kept);
}

// The print segments of a tool path as unordered end-point pairs (rounded to 1e-9 mm), sorted.
std::vector<std::array<double, 6>> printSegments(const Toolpath& tp) {
  std::vector<std::array<double, 6>> out;
  Vector3d pos = tp.start;
  auto r = [](double x) { return std::round(x * 1e9) / 1e9; };
  for (const Move& m : tp.moves) {
    if (m.kind == MoveKind::Print && (m.position - pos).norm() > 1e-12) {
      std::array<double, 6> a{r(pos.x()), r(pos.y()), r(pos.z()), r(m.position.x()), r(m.position.y()), r(m.position.z())};
      const std::array<double, 6> b{a[3], a[4], a[5], a[0], a[1], a[2]};
      out.push_back(std::min(a, b));
    }
    pos = m.position;
  }
  std::sort(out.begin(), out.end());
  return out;
}

// A path that runs under what it printed itself: the wall over the disc and the disc's zigzag
// joined into one path, the axes held within 5 degrees of +Z (no free axis under the wall). In
// its own order the zigzag under the wall collides with the wall printed just before; printed in
// another order (the blocked runs first, or reversed) fewer points collide, and every segment is
// still printed, once.
TEST(CurvedToolpath, SelfBlockedPathPrintsInAnotherOrder) {
  DiscStack s = wallOverDisc();
  ASSERT_EQ(s.paths[1][0].size(), 2u);
  SurfacePath joined = s.paths[1][0][0];
  const SurfacePath& disc = s.paths[1][0][1];
  // From the wall's end down to the zigzag's start: a segment of its own, as a spiral's joins are.
  joined.points.insert(joined.points.end(), disc.points.begin(), disc.points.end());
  joined.normals.insert(joined.normals.end(), disc.normals.begin(), disc.normals.end());
  s.paths[1][0] = {joined};

  CurvedToolpathOptions o;
  o.collisionClearance = o.nominalHeight;
  o.maxTiltDegrees = 5;
  o.reorderSelfBlocked = false;
  const CurvedToolpathResult inOrder = buildCurvedToolpath(s.layers, s.paths, o);
  ASSERT_TRUE(inOrder.ok()) << inOrder.message;
  EXPECT_GT(inOrder.gougingUncorrected, 0u);
  EXPECT_EQ(inOrder.reorderedPaths, 0u);
  const size_t collidingInOrder = bruteForceCollisions(inOrder.toolpath, o.nominalHeight, 40, 25);
  EXPECT_GT(collidingInOrder, 0u);

  o.reorderSelfBlocked = true;
  const CurvedToolpathResult r = buildCurvedToolpath(s.layers, s.paths, o);
  expectWellFormed(r, o);
  EXPECT_EQ(r.reorderedPaths, 1u);
  EXPECT_LT(r.gougingUncorrected, inOrder.gougingUncorrected);
  const size_t colliding = bruteForceCollisions(r.toolpath, o.nominalHeight, 40, 25);
  printf("self-blocked path: %zu -> %zu points left colliding, %zu -> %zu colliding samples\n",
         inOrder.gougingUncorrected, r.gougingUncorrected, collidingInOrder, colliding);
  EXPECT_LT(colliding, collidingInOrder);
  EXPECT_EQ(printSegments(r.toolpath), printSegments(inOrder.toolpath)) << "the same segments, each once";

  // Blocked by another path (the wall and the zigzag as two paths): no order of the zigzag helps,
  // none is tried; the program is the one without the option.
  const DiscStack apart = wallOverDisc();
  CurvedToolpathOptions plain = o;
  plain.reorderSelfBlocked = false;
  const CurvedToolpathResult a = buildCurvedToolpath(apart.layers, apart.paths, o);
  const CurvedToolpathResult b = buildCurvedToolpath(apart.layers, apart.paths, plain);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_GT(a.gougingUncorrected, 0u);
  EXPECT_EQ(a.reorderedPaths, 0u);
  ASSERT_EQ(a.toolpath.moves.size(), b.toolpath.moves.size());
  for (size_t i = 0; i < a.toolpath.moves.size(); ++i) {
    EXPECT_EQ(a.toolpath.moves[i].position, b.toolpath.moves[i].position);
    EXPECT_EQ(a.toolpath.moves[i].axis, b.toolpath.moves[i].axis);
  }
}

}  // namespace
}  // namespace omnislice

