// SPDX-License-Identifier: MIT
#include "slice/plan_layers.h"
#include "toolpath/bead.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <string>

#include "../test_meshes.h"
#include "../test_support.h"
#include "slice/travel_order.h"
#include "slice_test_support.h"

namespace omnislice {
namespace {

using test::makeBox;

// One extruding run: consecutive Print moves, with the point where it starts.
struct PrintRun {
  std::vector<Eigen::Vector3d> points;  // start + every end point
  Feature feature = Feature::None;
  int layer = 0;
  bool closed() const { return points.size() > 2 && (points.front() - points.back()).norm() < 1e-9; }
  double length() const {
    double l = 0;
    for (size_t i = 1; i < points.size(); ++i) l += (points[i] - points[i - 1]).norm();
    return l;
  }
};

std::vector<PrintRun> runsOf(const Toolpath& tp) {
  std::vector<PrintRun> runs;
  Eigen::Vector3d prev = tp.start;
  bool inRun = false;
  for (const Move& m : tp.moves) {
    if (m.kind == MoveKind::Print) {
      if (!inRun || runs.back().feature != m.feature) {
        runs.push_back(PrintRun{{prev}, m.feature, m.layer});
        inRun = true;
      }
      runs.back().points.push_back(m.position);
    } else {
      inRun = false;
    }
    prev = m.position;
  }
  return runs;
}

Eigen::Vector2d toLayer(const SliceFrame& f, const Eigen::Vector3d& p) {
  return {(p - f.origin).dot(f.e1), (p - f.origin).dot(f.e2)};
}

// The layers of these tests' slices (SliceOptions' default layer height), mm.
constexpr double kLayerHeight = 0.2;

PlanarOptions baseSettings() {
  PlanarOptions s;
  s.walls = 2;
  s.topLayers = 4;
  s.bottomLayers = 4;
  s.infillPercent = 20;
  return s;
}

// Independent checks shared by several tests: z only changes in travel, print points inside the
// section with the bead inside (distance to the boundary >= w/2), filament = bead formula, moves
// carry axis / width / height / layer / part.
void checkToolpath(const SliceResult& slices, const PlanarOptions& s, const PlanLayersResult& plan,
                   const std::string& what) {
  ASSERT_TRUE(plan.ok()) << what << ": " << plan.message;
  const Toolpath& tp = plan.toolpath;
  EXPECT_EQ(tp.layerCount, static_cast<int>(slices.layers.size()));
  const double w = s.lineWidth;
  const SliceFrame& f = slices.frame;
  Eigen::Vector3d prev = tp.start;
  size_t outside = 0, tooClose = 0, prints = 0;
  int lastLayer = -1;
  double filament = 0, expectedFilament = 0;
  for (const Move& m : tp.moves) {
    EXPECT_TRUE(m.axis.isApprox(f.d));
    EXPECT_EQ(m.part, 3);
    EXPECT_GE(m.layer, lastLayer);
    lastLayer = m.layer;
    const SliceLayer& layer = slices.layers[m.layer];
    if (m.kind == MoveKind::Print) {
      ++prints;
      const double zTop = slices.minHeight + layer.top;
      EXPECT_NEAR((m.position - f.origin).dot(f.d), zTop, 1e-9) << what;
      EXPECT_NEAR((prev - f.origin).dot(f.d), zTop, 1e-9) << what << ": z changes in a print move";
      EXPECT_DOUBLE_EQ(m.width, w);
      EXPECT_NEAR(m.height, layer.top - layer.bottom, 1e-12);
      const double len = (m.position - prev).norm();
      // Bridges take bridgeFlowPercent of a bead's filament.
      const double flow = m.feature == Feature::Bridge ? s.bridgeFlowPercent / 100 : 1.0;
      EXPECT_NEAR(m.filament, flow * filamentForBead(w, m.height, len, s.filamentDiameter), 1e-12);
      expectedFilament += flow * filamentForBead(w, m.height, len, s.filamentDiameter);
      EXPECT_GT(m.speed, 0);
      EXPECT_NE(m.feature, Feature::None);
      for (const Eigen::Vector3d& p3 : {prev, m.position}) {
        const Eigen::Vector2d p = toLayer(f, p3);
        bool in = false;
        double dist = 0;
        for (const ExPolygon2& island : layer.islands) {
          if (test::insideIsland(island, p)) {
            in = true;
            dist = test::distanceToIslandBoundary(island, p);
          }
        }
        if (!in) ++outside;
        else if (dist < 0.5 * w - 2e-3) ++tooClose;
      }
    }
    if (m.filament > 0) filament += m.filament;
    prev = m.position;
  }
  EXPECT_GT(prints, 0u) << what;
  EXPECT_EQ(outside, 0u) << what << ": print end points outside the section";
  EXPECT_EQ(tooClose, 0u) << what << ": beads reaching outside the section";
  const double retracts = s.retractLength * toolpathStats(tp, 0).retractions;
  EXPECT_NEAR(filament - retracts, expectedFilament, 1e-6 * expectedFilament) << what;
}

TEST(PlanLayers, FilamentForBeadFormula) {
  // w = 0.45, h = 0.2, L = 10: area = 0.25 * 0.2 + pi 0.04 / 4; filament section pi 1.75^2 / 4.
  const double area = 0.25 * 0.2 + M_PI * 0.04 / 4;
  EXPECT_NEAR(filamentForBead(0.45, 0.2, 10, 1.75), area * 10 / (M_PI * 1.75 * 1.75 / 4), 1e-12);
  EXPECT_DOUBLE_EQ(filamentForBead(0.45, 0.2, 0, 1.75), 0);
  // h = w: a round bead of diameter w.
  EXPECT_NEAR(filamentForBead(1, 1, 1, 1), 1, 1e-12);
  // Narrower than tall (w = 0.1, h = 0.8): the upright stadium 0.7 * 0.1 + pi 0.01 / 4, positive
  // and continuous at w = h (the flat formula gave -0.02 mm^2 here).
  EXPECT_NEAR(filamentForBead(0.1, 0.8, 1, 1), (0.7 * 0.1 + M_PI * 0.01 / 4) / (M_PI / 4), 1e-12);
  EXPECT_NEAR(filamentForBead(0.8 - 1e-9, 0.8, 1, 1), filamentForBead(0.8, 0.8, 1, 1), 1e-8);
  for (const double w : {0.01, 0.05, 0.2, 0.5}) EXPECT_GT(filamentForBead(w, 0.8, 1, 1.75), 0) << w;
}

TEST(PlanLayers, BoxWallsSkinsInfillAlongZ) {
  const Mesh box = makeBox(-10, -10, 0, 10, 10, 6);
  SliceOptions o;
  const SliceResult slices = sliceMesh(box, o);
  ASSERT_TRUE(slices.ok());
  ASSERT_EQ(slices.layers.size(), 30u);
  PlanarOptions s = baseSettings();
  s.infillPattern = InfillPattern::Lines;
  const PlanLayersResult plan = planLayers(slices, s, 3);
  checkToolpath(slices, s, plan, "box +Z");
  const std::vector<PrintRun> runs = runsOf(plan.toolpath);
  const double w = s.lineWidth;
  // Solid spacing of the bead model: w - h (1 - pi/4) (Slic3r's flow), the layers all 0.2 mm.
  const double sp = w - kLayerHeight * (1 - 3.14159265358979323846 / 4);
  for (int layer = 0; layer < 30; ++layer) {
    int outer = 0, inner = 0;
    double skin = 0, infill = 0;
    for (const PrintRun& r : runs) {
      if (r.layer != layer) continue;
      if (r.feature == Feature::WallOuter) {
        ++outer;
        EXPECT_TRUE(r.closed());
        // Outer wall of a 20 x 20 square: inset w/2, perimeter 4 (20 - w).
        EXPECT_NEAR(r.length(), 4 * (20 - w), 1e-3);
      }
      if (r.feature == Feature::WallInner) {
        ++inner;
        EXPECT_TRUE(r.closed());
        EXPECT_NEAR(r.length(), 4 * (20 - w - 2 * sp), 1e-3);
      }
      if (r.feature == Feature::Skin) skin += r.length();
      if (r.feature == Feature::Infill) infill += r.length();
    }
    EXPECT_EQ(outer, 1) << "layer " << layer;
    EXPECT_EQ(inner, 1) << "layer " << layer;
    const bool solid = layer < s.bottomLayers || layer >= 30 - s.topLayers;
    if (solid) {
      EXPECT_GT(skin, 0) << "layer " << layer;
      EXPECT_EQ(infill, 0) << "layer " << layer;
      EXPECT_EQ(plan.infillAreaMm2[layer], 0);
      // Solid: skin lines at the solid spacing fill the region: length * spacing ~= area.
      EXPECT_NEAR(skin * sp / plan.skinAreaMm2[layer], 1.0, 0.05) << "layer " << layer;
    } else {
      EXPECT_EQ(skin, 0) << "layer " << layer;
      EXPECT_GT(infill, 0) << "layer " << layer;
      // Share of the sparse region covered by beads ~= infill percent.
      EXPECT_NEAR(infill * w / plan.infillAreaMm2[layer], s.infillPercent / 100, 0.03) << "layer " << layer;
      // Fill region: inset w + (walls - 1) spacing - overlap.
      const double side = 20 - 2 * (w + sp - 0.15 * w);
      EXPECT_NEAR(plan.infillAreaMm2[layer], side * side, 1e-3);
    }
  }
}

// Islands narrower than a line get no path, and the plan says how much: a 10 x 10 x 1 mm base with
// a fin 0.3 mm thick (10 mm long, 4 mm tall) on it; the fin's sections are 3 mm^2 in each of the
// 20 layers above the base, all dropped and warned (thin_sections). A 1 mm fin is printed.
TEST(PlanLayers, SectionsNarrowerThanALineAreCountedAndWarned) {
  for (const double fin : {0.3, 1.0}) {
    const Mesh part = test::makeBoxUnion({{0, 0, 0, 10, 10, 1}, {0, 5, 1, 10, 5 + fin, 5}});
    const SliceResult slices = sliceMesh(part, SliceOptions{});
    ASSERT_TRUE(slices.ok());
    const PlanarOptions s = baseSettings();
    const PlanLayersResult plan = planLayers(slices, s);
    ASSERT_TRUE(plan.ok()) << plan.message;
    const std::optional<Warning> w = thinSectionsWarning(plan.thinAreaMm2, plan.sectionAreaMm2, plan.thinIslands,
                                                         s.lineWidth);
    if (fin < s.lineWidth) {
      EXPECT_EQ(plan.thinIslands, 20u);
      EXPECT_NEAR(plan.thinAreaMm2, 20 * 10 * fin, 1e-6);
      EXPECT_EQ(plan.thinFirstLayer, 5);
      EXPECT_EQ(plan.thinLastLayer, 24);
      ASSERT_TRUE(w.has_value());
      EXPECT_EQ(w->code, "thin_sections");
      EXPECT_NE(w->message.find("20 sections of the part (60.0 mm^2"), std::string::npos) << w->message;
    } else {
      EXPECT_EQ(plan.thinIslands, 0u);
      EXPECT_FALSE(w.has_value());
    }
  }
}

TEST(PlanLayers, GridInfillShareAndFullInfill) {
  const Mesh box = makeBox(0, 0, 0, 30, 25, 4);
  const SliceResult slices = sliceMesh(box, SliceOptions{});
  ASSERT_TRUE(slices.ok());
  for (double pct : {10.0, 20.0, 40.0, 100.0}) {
    PlanarOptions s = baseSettings();
    s.infillPattern = InfillPattern::Grid;
    s.infillPercent = pct;
    const PlanLayersResult plan = planLayers(slices, s, 3);
    checkToolpath(slices, s, plan, "grid " + std::to_string(pct));
    const double w = s.lineWidth;
    double infill = 0, area = 0;
    for (const PrintRun& r : runsOf(plan.toolpath)) {
      if (r.feature == Feature::Infill) infill += r.length();
    }
    for (double a : plan.infillAreaMm2) area += a;
    ASSERT_GT(area, 0);
    // Sparse lines are one bead wide apart per share; 100 % is laid at the solid spacing.
    const double lw = pct >= 100 ? w - kLayerHeight * (1 - 3.14159265358979323846 / 4) : w;
    EXPECT_NEAR(infill * lw / area, pct / 100, 0.04 * pct / 100 + 0.005) << pct << " %";
  }
  // 0 %: no infill moves at all.
  PlanarOptions s = baseSettings();
  s.infillPercent = 0;
  const PlanLayersResult plan = planLayers(slices, s, 3);
  ASSERT_TRUE(plan.ok());
  for (const Move& m : plan.toolpath.moves) EXPECT_NE(m.feature, Feature::Infill);
}

TEST(PlanLayers, TravelRetractionAndLayerStarts) {
  // Four separate columns: islands far apart force long travels.
  Mesh m = makeBox(0, 0, 0, 8, 8, 3);
  m = test::append(m, makeBox(30, 0, 0, 38, 8, 3));
  m = test::append(m, makeBox(0, 30, 0, 8, 38, 3));
  m = test::append(m, makeBox(30, 30, 0, 38, 38, 3));
  const SliceResult slices = sliceMesh(m, SliceOptions{});
  ASSERT_TRUE(slices.ok());
  // Straight travels, retracted over retractMinTravel (the rule of travels between islands; travels
  // inside an island: travel_inside_test.cpp).
  PlanarOptions s = baseSettings();
  s.travelInside = false;
  const PlanLayersResult plan = planLayers(slices, s, 3);
  checkToolpath(slices, s, plan, "four columns");
  const auto& moves = plan.toolpath.moves;
  ASSERT_FALSE(moves.empty());
  EXPECT_EQ(moves.front().kind, MoveKind::Travel);
  // Start: above the first layer's start point along d.
  const Eigen::Vector3d startDelta = plan.toolpath.start - moves.front().position;
  EXPECT_GT(startDelta.dot(slices.frame.d), 0);
  EXPECT_NEAR(startDelta.cross(slices.frame.d).norm(), 0, 1e-9);
  Eigen::Vector3d prev = plan.toolpath.start;
  bool extruded = false;
  int retracts = 0;
  for (size_t i = 0; i < moves.size(); ++i) {
    const Move& mv = moves[i];
    if (mv.kind == MoveKind::Retract) {
      ++retracts;
      EXPECT_EQ(mv.filament, -s.retractLength);
      EXPECT_EQ(mv.speed, s.retractSpeed);
      EXPECT_EQ(mv.position, prev);
      ASSERT_LT(i + 2, moves.size());
      EXPECT_EQ(moves[i + 1].kind, MoveKind::Travel);
      EXPECT_GT((moves[i + 1].position - prev).norm(), s.retractMinTravel);  // only long travels
      EXPECT_EQ(moves[i + 2].kind, MoveKind::Unretract);
      EXPECT_EQ(moves[i + 2].filament, s.retractLength);
      EXPECT_EQ(moves[i + 2].position, moves[i + 1].position);
    }
    if (mv.kind == MoveKind::Travel) {
      EXPECT_EQ(mv.speed, s.travelSpeed);
      EXPECT_EQ(mv.filament, 0);
      const double len = (mv.position - prev).norm();
      // Every long travel after the first extrusion is preceded by a retraction.
      if (extruded && len > s.retractMinTravel) {
        ASSERT_GT(i, 0u);
        EXPECT_EQ(moves[i - 1].kind, MoveKind::Retract);
      }
    }
    // The first move of each layer is a travel (z changes only in travel).
    if (i > 0 && mv.layer != moves[i - 1].layer) {
      EXPECT_TRUE(mv.kind == MoveKind::Travel || mv.kind == MoveKind::Retract) << "move " << i;
    }
    if (mv.kind == MoveKind::Print) extruded = true;
    prev = mv.position;
  }
  // At least one island change per layer is long: 3 per layer plus layer changes.
  EXPECT_GE(retracts, 3 * static_cast<int>(slices.layers.size()));
  // Speeds: first layer all at firstLayerSpeed; later outer walls / infill at their speeds.
  for (const Move& mv : moves) {
    if (mv.kind != MoveKind::Print) continue;
    if (mv.layer == 0) EXPECT_EQ(mv.speed, s.firstLayerSpeed);
    else if (mv.feature == Feature::WallOuter) EXPECT_EQ(mv.speed, s.outerWallSpeed);
    else if (mv.feature == Feature::Infill) EXPECT_EQ(mv.speed, s.infillSpeed);
    else EXPECT_EQ(mv.speed, s.printSpeed);
  }
}

// Travel of the same runs in a shuffled order (each run kept as planned, loops from their planned
// start): the unordered baseline.
double shuffledTravel(std::vector<PrintRun> runs, unsigned seed) {
  std::mt19937 rng(seed);
  double travel = 0;
  size_t i = 0;
  Eigen::Vector3d cur = runs.empty() ? Eigen::Vector3d::Zero() : runs[0].points[0];
  while (i < runs.size()) {
    size_t j = i;
    while (j < runs.size() && runs[j].layer == runs[i].layer) ++j;
    std::shuffle(runs.begin() + i, runs.begin() + j, rng);
    for (size_t k = i; k < j; ++k) {
      if (!runs[k].closed() && (rng() & 1)) std::reverse(runs[k].points.begin(), runs[k].points.end());
      travel += (runs[k].points.front() - cur).norm();
      cur = runs[k].points.back();
    }
    i = j;
  }
  return travel;
}

TEST(PlanLayers, TravelOrderBeatsUnorderedBaseline) {
  Mesh m = test::makeTorus(15, 5, 64, 32, {0, 0, 5});
  m = test::append(m, makeBox(30, -5, 0, 40, 5, 10));
  const SliceResult slices = sliceMesh(m, SliceOptions{});
  ASSERT_TRUE(slices.ok());
  const PlanarOptions s = baseSettings();
  const PlanLayersResult plan = planLayers(slices, s, 3);
  checkToolpath(slices, s, plan, "torus + box");
  const double planned = toolpathStats(plan.toolpath, 0).travelMm;
  const std::vector<PrintRun> runs = runsOf(plan.toolpath);
  // Baseline 1: same runs shuffled within each layer (random direction for lines).
  const double shuffled = shuffledTravel(runs, 7);
  // Baseline 2: same runs in planned order but every line printed in its scan direction (no
  // zig-zag): lines re-oriented so they all point the same way along their own direction.
  double oneWay = 0;
  Eigen::Vector3d cur = plan.toolpath.start;
  for (PrintRun r : runs) {
    if (!r.closed()) {
      const Eigen::Vector3d dir = r.points.back() - r.points.front();
      if (dir.x() + 1e-3 * dir.y() < 0) std::reverse(r.points.begin(), r.points.end());
    }
    oneWay += (r.points.front() - cur).norm();
    cur = r.points.back();
  }
  std::printf("travel: planned %.0f mm, one-way lines %.0f mm, shuffled %.0f mm\n", planned, oneWay,
              shuffled);
  EXPECT_LT(planned, 0.5 * shuffled);
  EXPECT_LT(planned, 0.8 * oneWay);
}

TEST(PlanLayers, NearestIndexMatchesBruteForce) {
  // The grid index behind travel ordering returns exactly the nearest probe of an untaken item.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-50, 50);
  std::vector<std::vector<Eigen::Vector2d>> probes(300);
  for (auto& list : probes) {
    const int n = 1 + static_cast<int>(rng() % 5);
    const Eigen::Vector2d c(u(rng), 0.2 * u(rng));  // an elongated cloud
    for (int i = 0; i < n; ++i) list.push_back(c + Eigen::Vector2d(0.05 * u(rng), 0.05 * u(rng)));
  }
  NearestIndex index(probes);
  std::vector<char> taken(probes.size(), 0);
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector2d from(2 * u(rng), 2 * u(rng));  // also far outside the cloud
    double best = 1e300;
    for (size_t i = 0; i < probes.size(); ++i) {
      if (taken[i]) continue;
      for (const auto& p : probes[i]) best = std::min(best, (p - from).squaredNorm());
    }
    const NearestIndex::Hit hit = index.nearest(from);
    ASSERT_TRUE(hit.found);
    ASSERT_FALSE(taken[hit.item]);
    EXPECT_DOUBLE_EQ((probes[hit.item][hit.probe] - from).squaredNorm(), best) << "query " << q;
    index.take(hit.item);
    taken[hit.item] = 1;
  }
  EXPECT_FALSE(index.nearest({0, 0}).found);
  // Degenerate clouds (the seams of a layer: all on one vertical line, or all at one point), asked
  // from far away: the grid is one cell wide (or one cell), its rings far wider than it.
  for (const bool line : {true, false}) {
    std::vector<std::vector<Eigen::Vector2d>> column(40);
    for (size_t i = 0; i < column.size(); ++i) column[i] = {{3, line ? 0.25 * double(i) : 7.0}};
    NearestIndex degenerate(column);
    for (int q = 0; q < 50; ++q) {
      const Eigen::Vector2d from(2 * u(rng), 2 * u(rng));
      double best = 1e300;
      for (const auto& list : column) best = std::min(best, (list[0] - from).squaredNorm());
      const NearestIndex::Hit hit = degenerate.nearest(from);
      ASSERT_TRUE(hit.found);
      EXPECT_DOUBLE_EQ((column[hit.item][0] - from).squaredNorm(), best) << (line ? "line" : "point") << " query " << q;
    }
  }
}

TEST(PlanLayers, ManyIslandsOrderedQuickly) {
  // 20 x 20 pillars: 400 islands per layer, visited nearest-first (travel close to the minimum
  // tour of about 400 x pitch per layer, far below a shuffled order).
  Mesh m;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) m = test::append(m, makeBox(5 * i, 5 * j, 0, 5 * i + 3, 5 * j + 3, 2));
  }
  const SliceResult slices = sliceMesh(m, SliceOptions{});
  ASSERT_TRUE(slices.ok());
  const PlanarOptions s = baseSettings();
  const auto t0 = std::chrono::steady_clock::now();
  const PlanLayersResult plan = planLayers(slices, s, 3);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  checkToolpath(slices, s, plan, "pillars");
  const std::vector<PrintRun> runs = runsOf(plan.toolpath);
  size_t outer = 0;
  for (const PrintRun& r : runs) outer += r.feature == Feature::WallOuter;
  EXPECT_EQ(outer, 400u * slices.layers.size());
  const double planned = toolpathStats(plan.toolpath, 0).travelMm;
  const double shuffled = shuffledTravel(runs, 11);
  std::printf("pillars: %zu layers, plan %.3f s, travel %.0f mm (shuffled %.0f mm)\n", slices.layers.size(),
              seconds, planned, shuffled);
  EXPECT_LT(planned, 0.2 * shuffled);
  EXPECT_LT(planned / slices.layers.size(), 2.0 * 400 * 5);
}

TEST(PlanLayers, TiltedDirectionsStayInsideSections) {
  const Mesh sphere = test::makeUvSphere(10, 64, 32, {0, 0, 10});
  for (const Eigen::Vector3d& dir :
       {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0, -1, 0.3)}) {
    SliceOptions o;
    o.direction = dir;
    const SliceResult slices = sliceMesh(sphere, o);
    ASSERT_TRUE(slices.ok());
    const PlanarOptions s = baseSettings();
    const PlanLayersResult plan = planLayers(slices, s, 3);
    checkToolpath(slices, s, plan, "sphere");
    // Skin on the first bottomLayers and last topLayers layers; their regions hold no sparse infill.
    const size_t n = slices.layers.size();
    for (size_t i = 0; i < n; ++i) {
      if (i < static_cast<size_t>(s.bottomLayers) || i + s.topLayers >= n) {
        EXPECT_EQ(plan.infillAreaMm2[i], 0) << "layer " << i;
        if (!slices.layers[i].islands.empty() && i > 0 && i + 1 < n) {
          EXPECT_GT(plan.skinAreaMm2[i], 0) << i;
        }
      }
    }
    // Middle layers of a sphere carry both: sparse core and skin ring where the surface slopes.
    EXPECT_GT(plan.infillAreaMm2[n / 2], 0);
  }
}

TEST(PlanLayers, TorusWallsAroundHole) {
  const Mesh torus = test::makeTorus(10, 3, 96, 48, {0, 0, 5});
  const SliceResult slices = sliceMesh(torus, SliceOptions{});
  ASSERT_TRUE(slices.ok());
  PlanarOptions s = baseSettings();
  s.walls = 3;
  const PlanLayersResult plan = planLayers(slices, s, 3);
  checkToolpath(slices, s, plan, "torus walls");
  const std::vector<PrintRun> runs = runsOf(plan.toolpath);
  const int mid = static_cast<int>(slices.layers.size() / 2);
  int outer = 0, inner = 0;
  for (const PrintRun& r : runs) {
    if (r.layer != mid) continue;
    outer += r.feature == Feature::WallOuter;
    inner += r.feature == Feature::WallInner;
  }
  // One ring: an outer wall around the contour and one along the hole, each with 2 inner walls.
  EXPECT_EQ(outer, 2);
  EXPECT_EQ(inner, 4);
}

TEST(PlanLayers, EmptyLayersAndNoWalls) {
  const Mesh two = test::append(makeBox(0, 0, 0, 4, 4, 1), makeBox(0, 0, 2, 4, 4, 3));
  SliceOptions o;
  o.layerHeight = 0.25;
  const SliceResult slices = sliceMesh(two, o);
  ASSERT_TRUE(slices.ok());
  PlanarOptions s = baseSettings();
  s.walls = 0;
  s.topLayers = 1;
  s.bottomLayers = 1;
  const PlanLayersResult plan = planLayers(slices, s, 3);
  checkToolpath(slices, s, plan, "gap, no walls");
  for (const Move& m : plan.toolpath.moves) {
    EXPECT_TRUE(m.layer < 4 || m.layer >= 8 || m.kind != MoveKind::Print);
    EXPECT_NE(m.feature, Feature::WallOuter);
  }
  // Layers 3 and 8 border the gap: solid skin (the layers beside them are empty).
  for (int i : {0, 3, 8, 11}) EXPECT_GT(plan.skinAreaMm2[i], 0) << i;
  for (int i : {1, 2, 9, 10}) EXPECT_EQ(plan.skinAreaMm2[i], 0) << i;
}

TEST(PlanLayers, StatusForBadInput) {
  const SliceResult slices = sliceMesh(makeBox(0, 0, 0, 5, 5, 2), SliceOptions{});
  PlanarOptions s = baseSettings();
  s.infillPercent = 120;
  EXPECT_EQ(planLayers(slices, s).status, Status::InvalidOption);
  s = baseSettings();
  s.walls = -1;
  EXPECT_EQ(planLayers(slices, s).status, Status::InvalidOption);
  s = baseSettings();
  s.filamentDiameter = 0;
  EXPECT_EQ(planLayers(slices, s).status, Status::InvalidOption);
  s = baseSettings();
  s.travelSpeed = 0;
  EXPECT_EQ(planLayers(slices, s).status, Status::InvalidOption);
  SliceResult broken;
  broken.status = Status::EmptyInput;
  EXPECT_EQ(planLayers(broken, baseSettings()).status, Status::InvalidOption);
  int calls = 0;
  const PlanLayersResult c = planLayers(slices, baseSettings(), 0, [&](const char* stage, double) {
    EXPECT_STREQ(stage, "toolpath");
    return ++calls < 3;
  });
  EXPECT_EQ(c.status, Status::Cancelled);
}

TEST(PlanLayers, TimingHundredThousandTriangles) {
  // ~100k triangles, 100 mm tall: a sphere of radius 50 mm (nLat 224 x nLon 448 = 100,352 faces).
  const Mesh sphere = test::makeUvSphere(50, 224, 224, {0, 0, 50});
  ASSERT_GE(sphere.faceCount(), 99000u);
  const auto t0 = std::chrono::steady_clock::now();
  const SliceResult slices = sliceMesh(sphere, SliceOptions{});
  const auto t1 = std::chrono::steady_clock::now();
  ASSERT_TRUE(slices.ok());
  EXPECT_EQ(slices.openChains, 0u);
  const PlanLayersResult plan = planLayers(slices, baseSettings());
  const auto t2 = std::chrono::steady_clock::now();
  ASSERT_TRUE(plan.ok());
  const double sliceS = std::chrono::duration<double>(t1 - t0).count();
  const double planS = std::chrono::duration<double>(t2 - t1).count();
  std::printf("%zu triangles, %zu layers: slice %.3f s, plan %.3f s, %zu moves\n", sphere.faceCount(),
              slices.layers.size(), sliceS, planS, plan.toolpath.moves.size());
  // The times are printed; speed is measured by `npm run bench` (torus-100k), never asserted here.
}


TEST(PlanLayers, RealModelKittenTilted) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh kitten = test::loadModel("pymdp_kitten.off");
  ASSERT_EQ(kitten.faceCount(), 10000u);
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 1, 0.2)}) {
    SliceOptions o;
    o.direction = dir;
    o.layerHeight = 0.3;
    const SliceResult slices = sliceMesh(kitten, o);
    ASSERT_TRUE(slices.ok());
    EXPECT_EQ(slices.openChains, 0u);
    const PlanarOptions s = baseSettings();
    const PlanLayersResult plan = planLayers(slices, s, 3);
    checkToolpath(slices, s, plan, "kitten");
    // The kitten has a handle (genus 1): some layers hold two islands or a hole.
    size_t multi = 0;
    for (const SliceLayer& layer : slices.layers) {
      multi += layer.islands.size() > 1 || (layer.islands.size() == 1 && !layer.islands[0].holes.empty());
    }
    EXPECT_GT(multi, 0u);
  }
}

}  // namespace
}  // namespace omnislice
