// SPDX-License-Identifier: MIT
// Planar bridges (PlanarOptions::bridges), measured on the tool path against the slices:
//   - an arch (a deck over a 20 mm gap between two pillars): the first deck layer prints Bridge
//     lines across the gap (along x, perpendicular to its edges), each landing on a pillar's top
//     at both ends, covering the gap, at the bridge speed and flow; no other layer bridges;
//   - a cantilever (a deck hanging from one pillar) has no bridge: its overhang stays skin;
//   - bridges off: the arch's gap is skin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../test_meshes.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"
#include "slice_test_support.h"
#include "toolpath/bead.h"

namespace omnislice {
namespace {

struct Line {
  Eigen::Vector3d a, b;
  int layer;
  double speed, filament;
};

std::vector<Line> printed(const Toolpath& tp, Feature feature) {
  std::vector<Line> out;
  Eigen::Vector3d prev = tp.start;
  for (const Move& m : tp.moves) {
    if (m.kind == MoveKind::Print && m.feature == feature) out.push_back({prev, m.position, m.layer, m.speed, m.filament});
    prev = m.position;
  }
  return out;
}

bool onLayer(const SliceLayer& layer, const Eigen::Vector3d& p) {
  for (const ExPolygon2& island : layer.islands) {
    if (insideIsland(island, p.head<2>())) return true;
  }
  return false;
}

// Pillars x in [0, 10] and [30, 40] (y in [0, 10], z in [0, 10]); a deck x in [0, 40], z in [10, 12].
Mesh arch() { return test::makeBoxUnion({{0, 0, 0, 10, 10, 10}, {30, 0, 0, 40, 10, 10}, {0, 0, 10, 40, 10, 12}}); }

TEST(Bridges, AnArchIsBridgedAcrossItsGapAnchoredOnBothPillars) {
  const SliceResult slices = sliceMesh(arch(), SliceOptions{});
  ASSERT_TRUE(slices.ok()) << slices.message;
  PlanarOptions o;
  const PlanLayersResult r = planLayers(slices, o);
  ASSERT_TRUE(r.ok()) << r.message;
  const std::vector<Line> bridge = printed(r.toolpath, Feature::Bridge);
  ASSERT_FALSE(bridge.empty());
  EXPECT_EQ(r.bridges, 1u);
  const int deck = bridge.front().layer;  // the first layer over the gap
  EXPECT_NEAR(slices.layers[size_t(deck)].bottom, 10, 1e-9);
  const SliceLayer& below = slices.layers[size_t(deck) - 1];
  double across = 0;
  std::vector<double> ys;
  for (const Line& l : bridge) {
    EXPECT_EQ(l.layer, deck);
    EXPECT_EQ(l.speed, o.bridgeSpeed);
    const double len = (l.b - l.a).norm();
    EXPECT_NEAR(l.filament, o.bridgeFlowPercent / 100 * filamentForBead(o.lineWidth, 0.2, len, o.filamentDiameter), 1e-9);
    // Along x, from one pillar to the other.
    EXPECT_LT(std::abs(l.b.y() - l.a.y()), 1e-6);
    EXPECT_TRUE(onLayer(below, l.a) && onLayer(below, l.b)) << l.a.transpose() << " -> " << l.b.transpose();
    EXPECT_LT(std::min(l.a.x(), l.b.x()), 10);
    EXPECT_GT(std::max(l.a.x(), l.b.x()), 30);
    across += len;
    ys.push_back(l.a.y());
  }
  // The lines cover the gap: one per line width across the deck's fill region (10 mm less the
  // walls: inset w + (walls - 1) s - overlap on each side, s the solid spacing).
  std::sort(ys.begin(), ys.end());
  for (size_t k = 1; k < ys.size(); ++k) EXPECT_NEAR(ys[k] - ys[k - 1], o.lineWidth, 1e-3);
  const double w = o.lineWidth, s = w - 0.2 * (1 - M_PI / 4);
  const double inset = w + (o.walls - 1) * s - o.infillOverlapPercent / 100 * w;
  EXPECT_GT(ys.back() - ys.front(), 10 - 2 * inset - 2 * w - 1e-6);
  EXPECT_GT(r.bridgeAreaMm2[size_t(deck)], 20 * 8.0);
  // Bridges off: no bridge lines, the gap is skin.
  o.bridges = false;
  const PlanLayersResult off = planLayers(slices, o);
  EXPECT_TRUE(printed(off.toolpath, Feature::Bridge).empty());
  EXPECT_GT(off.skinAreaMm2[size_t(deck)], r.skinAreaMm2[size_t(deck)] + 20 * 8.0);
}

TEST(Bridges, ACantileverIsNotABridge) {
  // One pillar x in [0, 10]; the deck reaches to x = 30 over air on one side only.
  const SliceResult slices = sliceMesh(test::makeBoxUnion({{0, 0, 0, 10, 10, 10}, {0, 0, 10, 30, 10, 12}}), SliceOptions{});
  ASSERT_TRUE(slices.ok());
  const PlanLayersResult r = planLayers(slices, PlanarOptions{});
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(printed(r.toolpath, Feature::Bridge).empty());
  EXPECT_EQ(r.bridges, 0u);
  PlanarOptions bad;
  bad.bridgeSpeed = 0;
  EXPECT_EQ(planLayers(slices, bad).status, Status::InvalidOption);
  bad = PlanarOptions{};
  bad.bridgeFlowPercent = 0;
  EXPECT_EQ(planLayers(slices, bad).status, Status::InvalidOption);
}

}  // namespace
}  // namespace omnislice
