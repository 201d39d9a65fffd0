// SPDX-License-Identifier: MIT
#include "verify/verify_program.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "../program/test_toolpaths.h"
#include "../test_meshes.h"
#include "../test_support.h"
#include "geometry/aabb_tree.h"
#include "machine/machine_json.h"
#include "mesh/place_mesh.h"
#include "program/write_gcode.h"

namespace omnislice {
namespace {

ParsedProgram throughGcode(const Toolpath& tp, double h = 0.2, double w = 0.45) {
  ProgramInfo info;
  info.isoDate = "2026-11-21T12:00:00Z";
  info.machine = cartesian3Profile({220, 220, 250}, 0.4);
  info.layerHeight = h;
  info.lineWidth = w;
  const WriteProgramResult r = writeGcode(tp, info);
  EXPECT_TRUE(r.ok()) << r.message;
  ParsedProgram p = readProgram(r.text);
  EXPECT_TRUE(p.ok()) << p.message;
  return p;
}

const Mesh& box10() {
  static const Mesh m = test::makeBox(-5, -5, 0, 5, 5, 10);
  return m;
}

VerifyReport verifyBox(const test::BoxPathOptions& o) {
  return verifyProgram(throughGcode(test::boxToolpath(o)), box10());
}

TEST(VerifyProgram, SolidBoxPasses) {
  const Toolpath tp = test::boxToolpath({});
  const VerifyReport r = verifyProgram(throughGcode(tp), box10());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_GE(r.inside, 0.99);
  EXPECT_GE(r.coverage, 0.95);
  EXPECT_GE(r.supported, 0.99);
  EXPECT_GE(r.supportedAll, 0.99);
  EXPECT_EQ(r.collisions, 0u);
  EXPECT_EQ(r.limitViolations, 0u);
  EXPECT_EQ(r.layers, 50);
  const ToolpathStats s = toolpathStats(tp, 0);
  EXPECT_NEAR(r.pathMm, s.pathMm, 1e-3 * s.pathMm);
  // Positive E increments: printing moves plus the unretracts.
  double positive = 0;
  for (const Move& m : tp.moves) positive += std::max(0.0, m.filament);
  EXPECT_NEAR(r.extrusionMm, positive, 1e-3);
  EXPECT_NEAR(double(r.samples), s.pathMm / 0.5, 0.05 * s.pathMm / 0.5);
  // Interior grid: multiples of 0.2 at least w/2 = 0.225 from the faces of [-5,5]^2 x [0,10]:
  // x, y in {-4.6, ..., 4.6} and z in {0.4, ..., 9.6}, 47 values each.
  EXPECT_EQ(r.gridPoints, size_t(47) * 47 * 47);
}

// Support lies outside the part by design: its samples are left out of `inside` and are not
// judged by `supported`, but still hold up what is printed on them. The same moves printed as part
// material count as outside.
TEST(VerifyProgram, SupportSamplesAreOutsideByDesign) {
  const Toolpath box = test::boxToolpath({});
  auto withColumn = [&](MoveKind kind, Feature feature) {
    Toolpath tp = box;
    // A 2 mm line beside the box (x = 7), on the first 5 layers.
    Move t;
    t.kind = MoveKind::Travel;
    t.speed = 100;
    for (int l = 0; l < 5; ++l) {
      const double z = 0.2 * (l + 1);
      t.position = {7, -1, z};
      t.layer = l;
      tp.moves.insert(tp.moves.begin() + 1, t);
    }
    std::vector<Move> column;
    for (int l = 0; l < 5; ++l) {
      const double z = 0.2 * (l + 1);
      Move a = t;
      a.position = {7, -1, z};
      a.layer = l;
      Move b = a;
      b.kind = kind;
      b.feature = feature;
      b.position = {7, 1, z};
      b.width = 0.45;
      b.height = 0.2;
      b.filament = 0.07;
      b.speed = 30;
      column.push_back(a);
      column.push_back(b);
    }
    tp.moves.insert(tp.moves.end(), column.begin(), column.end());
    return verifyProgram(throughGcode(tp), box10());
  };
  const VerifyReport asSupport = withColumn(MoveKind::Support, Feature::Support);
  const VerifyReport asPart = withColumn(MoveKind::Print, Feature::Infill);
  ASSERT_TRUE(asSupport.ok()) << asSupport.message;
  ASSERT_TRUE(asPart.ok()) << asPart.message;
  EXPECT_EQ(asSupport.supportSamples, 4u * 5u);  // 2 mm at 0.5 mm from its start: 4 per layer
  EXPECT_EQ(asPart.supportSamples, 0u);
  EXPECT_GE(asSupport.inside, 0.99);
  EXPECT_DOUBLE_EQ(asSupport.inside, 1.0);
  EXPECT_LT(asPart.inside, 1.0);
  EXPECT_EQ(asSupport.samples, asPart.samples);
}

TEST(VerifyProgram, CoverageAndInsideMatchIndependentBruteForce) {
  // A small box so every grid point can be checked against every segment.
  const Mesh part = test::makeBox(-1.5, -1.5, 0, 1.5, 1.5, 1.2);
  test::BoxPathOptions o;
  o.half = 1.5;
  o.height = 1.2;
  o.keepLayer = [](int l) { return l != 2; };  // a gap, so coverage is well below 1
  const ParsedProgram p = throughGcode(test::boxToolpath(o));
  const VerifyReport r = verifyProgram(p, part);
  ASSERT_TRUE(r.ok()) << r.message;
  const double h = 0.2, w = 0.45, g = 0.2;
  size_t interior = 0, covered = 0;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j)
      for (int k = 0; k <= 10; ++k) {
        const Eigen::Vector3d q(i * g, j * g, k * g);
        const double d = std::min({q.x() + 1.5, 1.5 - q.x(), q.y() + 1.5, 1.5 - q.y(), q.z(), 1.2 - q.z()});
        if (d < 0.5 * w) continue;
        ++interior;
        for (const ProgramMove& m : p.moves) {
          if (m.filament <= 0 || (m.to - m.from).norm() == 0) continue;
          // Closest point by dense sampling along the segment (independent of the verifier).
          bool hit = false;
          for (int t = 0; t <= 2000 && !hit; ++t) {
            const Eigen::Vector3d c = m.from + (m.to - m.from) * (t / 2000.0);
            const Eigen::Vector3d dd = q - c;
            const double ax = dd.z(), lat = std::hypot(dd.x(), dd.y());
            hit = std::pow(ax / (0.75 * h), 2) + std::pow(lat / (0.75 * w), 2) <= 1 + 1e-9;
          }
          if (hit) {
            ++covered;
            break;
          }
        }
      }
  EXPECT_EQ(r.gridPoints, interior);
  EXPECT_NEAR(r.coverage, double(covered) / interior, 2.0 / interior);
  EXPECT_LT(r.coverage, 0.9);

  // inside: a program shifted 1 mm in x against the analytic box distance.
  Toolpath shifted = test::boxToolpath(o);
  for (Move& m : shifted.moves) m.position.x() += 1.0;
  shifted.start.x() += 1.0;
  const ParsedProgram ps = throughGcode(shifted);
  const VerifyReport rs = verifyProgram(ps, part);
  size_t in = 0, n = 0;
  for (const ProgramMove& m : ps.moves) {
    const double len = (m.to - m.from).norm();
    if (m.filament <= 0 || len == 0) continue;
    for (int k = 0; k == 0 || k * 0.5 < len; ++k) {
      const Eigen::Vector3d s = m.from + (m.to - m.from) * (k * 0.5 / len);
      const double dx = std::max({-1.5 - s.x(), s.x() - 1.5, 0.0});
      const double dy = std::max({-1.5 - s.y(), s.y() - 1.5, 0.0});
      const double dz = std::max({-s.z(), s.z() - 1.2, 0.0});
      ++n;
      if (std::sqrt(dx * dx + dy * dy + dz * dz) <= 0.5 * w) ++in;
    }
  }
  EXPECT_EQ(rs.samples, n);
  EXPECT_NEAR(rs.inside, double(in) / n, 1e-12);
  EXPECT_LT(rs.inside, 0.95);
}

TEST(VerifyProgram, MissingEveryOtherLayerFailsCoverage) {
  test::BoxPathOptions o;
  o.keepLayer = [](int l) { return l % 2 == 0; };
  const VerifyReport r = verifyBox(o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(r.coverage, 0.7);
  EXPECT_GE(r.inside, 0.99);
}

// The share of the surface with a bead within reach, against the area computed by hand: the box's
// lower half printed (layers 0-24, tips up to z = 5) reaches its bottom face and its sides up to
// 5 + sqrt(reach^2 - (w/2)^2) (the outer wall's tips stand w/2 inside), reach = w + h + 0.25.
TEST(VerifyProgram, SurfaceReachedIsTheAreaNearSomeBead) {
  const VerifyReport full = verifyBox({});
  ASSERT_TRUE(full.ok()) << full.message;
  EXPECT_NEAR(full.surfaceReach, 0.45 + 0.2 + 0.25, 1e-12);
  EXPECT_GE(full.surfaceReached, 0.999);
  test::BoxPathOptions o;
  o.keepLayer = [](int l) { return l < 25; };
  const VerifyReport half = verifyBox(o);
  ASSERT_TRUE(half.ok()) << half.message;
  const double reach = half.surfaceReach;
  const double expected = (100 + 40 * (5 + std::sqrt(reach * reach - 0.225 * 0.225))) / 600;
  EXPECT_NEAR(half.surfaceReached, expected, 0.01);
  EXPECT_GE(half.coverage, 0.45);  // the interior of the lower half is filled
}

TEST(VerifyProgram, ShiftedProgramFailsInside) {
  Toolpath tp = test::boxToolpath({});
  for (Move& m : tp.moves) m.position.x() += 5.0;
  const VerifyReport r = verifyProgram(throughGcode(tp), box10());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(r.inside, 0.7);
  EXPECT_LT(r.coverage, 0.7);
}

TEST(VerifyProgram, FloatingLayerIsUnsupported) {
  test::BoxPathOptions good, floating;
  good.keepLayer = [](int l) { return l < 5; };
  floating.keepLayer = [](int l) { return l >= 25 && l < 30; };  // starts 5 mm above the bed
  const VerifyReport rg = verifyBox(good);
  const VerifyReport rf = verifyBox(floating);
  ASSERT_TRUE(rg.ok() && rf.ok());
  EXPECT_GE(rg.supported, 0.99);
  EXPECT_GE(rg.supportedAll, 0.99);
  EXPECT_LT(rf.supported, 0.85);
  EXPECT_LT(rf.supportedAll, 0.85);
  EXPECT_GT(rf.supportedAll, 0.7);  // the 4 layers over the floating one are supported
}

TEST(VerifyProgram, TallWallFirstThenLowerInfillCollides) {
  test::BoxPathOptions walls, infill;
  walls.wallsOnly = true;
  walls.keepLayer = [](int l) { return l < 20; };
  infill.infillOnly = true;
  infill.keepLayer = [](int l) { return l == 0; };
  Toolpath tp = test::boxToolpath(walls);
  const Toolpath late = test::boxToolpath(infill);
  tp.moves.insert(tp.moves.end(), late.moves.begin(), late.moves.end());
  const VerifyReport r = verifyProgram(throughGcode(tp), box10());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_GT(r.collisions, 0u);
  // The first collisions are located: each example is an infill sample of layer 0 with the
  // earlier wall point inside its cone by the rule, on a program line.
  ASSERT_EQ(r.collisionExamples.size(), std::min<size_t>(10, r.collisions));
  for (const CollisionExample& e : r.collisionExamples) {
    const Eigen::Vector3d tip(e.tip[0], e.tip[1], e.tip[2]), u(e.axis[0], e.axis[1], e.axis[2]),
        p(e.earlier[0], e.earlier[1], e.earlier[2]);
    const Eigen::Vector3d d = p - tip;
    EXPECT_GT(d.dot(u), 0.2);
    EXPECT_LT(std::sqrt(std::max(0.0, d.squaredNorm() - d.dot(u) * d.dot(u))), d.dot(u) * std::tan(40 * M_PI / 180));
    EXPECT_LT(d.norm(), 25);
    EXPECT_EQ(e.layer, 0);
    EXPECT_GT(e.line, 0);
  }
  // The same moves in a layer-by-layer order do not collide.
  test::BoxPathOptions both;
  both.keepLayer = [](int l) { return l < 20; };
  EXPECT_EQ(verifyBox(both).collisions, 0u);
}

TEST(VerifyProgram, TopDownOrderCollidesEverywhereAndStaysFast) {
  // Layers printed from the top down: every sample below the first layers has earlier material
  // above it inside the cone, so the slow path of the collision search runs for nearly all samples.
  const Toolpath tp = test::boxToolpath({});
  std::vector<std::vector<Move>> byLayer(50);
  for (const Move& m : tp.moves) byLayer[m.layer].push_back(m);
  Toolpath reversed = tp;
  reversed.moves.clear();
  for (int l = 49; l >= 0; --l) {
    reversed.moves.insert(reversed.moves.end(), byLayer[l].begin(), byLayer[l].end());
  }
  const VerifyReport r = verifyProgram(throughGcode(reversed), box10());
  ASSERT_TRUE(r.ok()) << r.message;
  // Every sample of layers 0..46 has layer 49 (>= 3 h higher) inside its cone; layers 47 and 48
  // are too close below it (a sample only collides with material more than h above).
  size_t lastLayerSamples = 0;
  {
    test::BoxPathOptions top;
    top.keepLayer = [](int l) { return l == 49; };
    lastLayerSamples = verifyBox(top).samples;
  }
  EXPECT_GE(r.collisions, r.samples - 3 * lastLayerSamples - 100);
  EXPECT_LE(r.collisions, r.samples - 2 * lastLayerSamples + 100);
}

TEST(VerifyProgram, BeyondTheBedViolatesLimits) {
  // The planner refuses points beyond the bed, so the program is written for a wider bed and its
  // header then declares the real one (X in [-110, 110]): the verifier counts the moves beyond it.
  Toolpath tp = test::boxToolpath({});
  size_t beyond = 0;
  for (Move& m : tp.moves) {
    if (m.layer == 3 && m.kind == MoveKind::Print) {
      m.position.x() = 120;
      ++beyond;
    }
  }
  ProgramInfo info;
  info.isoDate = "2026-11-21T12:00:00Z";
  info.machine = cartesian3Profile({300, 220, 250}, 0.4);
  const WriteProgramResult w = writeGcode(tp, info);
  ASSERT_TRUE(w.ok()) << w.message;
  std::string text = w.text;
  const std::string wide = machineJson(info.machine);
  const std::string real = machineJson(cartesian3Profile({220, 220, 250}, 0.4));
  ASSERT_NE(text.find(wide), std::string::npos);
  text.replace(text.find(wide), wide.size(), real);
  const VerifyReport r = verifyProgram(readProgram(text), box10());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.limitViolations, beyond);
  EXPECT_EQ(verifyBox({}).limitViolations, 0u);
}

TEST(VerifyProgram, SphereOf30mmPasses) {
  const double R = 15;
  const Mesh sphere = test::makeUvSphere(R, 256, 128, {0, 0, R});
  const ParsedProgram p = throughGcode(test::sphereToolpath(R, 0.2, 0.45));
  const auto t0 = std::chrono::steady_clock::now();
  const VerifyReport r = verifyProgram(p, sphere);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.ok()) << r.message;
  std::printf("verify 30 mm sphere: %.2f s, %zu samples, %zu grid points, %.0f mm path, %s\n",
              seconds, r.samples, r.gridPoints, r.pathMm, verifyReportJson(r).c_str());
  EXPECT_GE(r.inside, 0.99);
  EXPECT_GE(r.coverage, 0.95);
  EXPECT_EQ(r.collisions, 0u);
}

// The interior grid points (inside, at least w/2 from the surface) equal the point-by-point
// count with the AABB tree: winding number and "any triangle within w/2".
TEST(VerifyProgram, InteriorGridPointsMatchPointByPointDistance) {
  const double R = 4;
  const Mesh sphere = test::makeUvSphere(R, 48, 24, {0.07, -0.03, R});
  const ParsedProgram p = throughGcode(test::sphereToolpath(R, 0.2, 0.45));
  const VerifyReport r = verifyProgram(p, sphere);
  ASSERT_TRUE(r.ok()) << r.message;
  const AabbTree tree(sphere);
  const double g = 0.2, half = 0.5 * 0.45;
  size_t interior = 0;
  for (int i = -25; i <= 25; ++i)
    for (int j = -25; j <= 25; ++j)
      for (int k = 0; k <= 45; ++k) {
        const Eigen::Vector3d q(i * g, j * g, k * g);
        if (tree.inside(q) && !tree.anyWithin(q, half * (1 - 1e-9))) ++interior;
      }
  EXPECT_GT(interior, 10000u);
  EXPECT_EQ(r.gridPoints, interior);
}

// `inside` equals the sample-by-sample count with the AABB tree (closest point within w/2, else
// the winding number) on a curved part, for a program shifted so that part of it lies outside.
TEST(VerifyProgram, InsideMatchesSampleBySampleDistance) {
  const double R = 4;
  const Mesh sphere = test::makeUvSphere(R, 40, 20, {0, 0, R});
  Toolpath tp = test::sphereToolpath(R, 0.2, 0.45);
  for (Move& m : tp.moves) m.position += Eigen::Vector3d(0.61, -0.37, 0.05);
  tp.start += Eigen::Vector3d(0.61, -0.37, 0.05);
  const ParsedProgram p = throughGcode(tp);
  const VerifyReport r = verifyProgram(p, sphere);
  ASSERT_TRUE(r.ok()) << r.message;
  const AabbTree tree(sphere);
  size_t in = 0, n = 0;
  for (const ProgramMove& m : p.moves) {
    const double len = (m.to - m.from).norm();
    if (!(m.filament > 0) || !(len > 1e-9)) continue;
    for (int k = 0; k == 0 || k * 0.5 < len; ++k) {
      const Eigen::Vector3d q = m.from + (k * 0.5 / len) * (m.to - m.from);
      ++n;
      if (tree.closest(q).distance <= 0.5 * 0.45 || tree.inside(q)) ++in;
    }
  }
  EXPECT_EQ(r.samples, n);
  EXPECT_EQ(r.inside, double(in) / double(n));
  EXPECT_LT(r.inside, 0.99);
  EXPECT_GT(r.inside, 0.5);
}

// 100 % raster tool-path of any closed mesh, independent of the slicer: per layer, lines along X
// spaced w in Y (along Y on odd layers), split into runs where the column through each 0.1 mm
// step is inside the solid at mid-layer.
Toolpath rasterToolpath(const Mesh& mesh, double h, double w) {
  const AabbTree tree(mesh);
  const BoundingBox box = boundingBox(mesh);
  test::PathBuilder b(h, w);
  std::vector<ColumnCrossing> xs;
  auto insideAt = [&](double x, double y, double z) {
    tree.columnCrossings(x, y, xs);
    int wind = 0;
    for (const ColumnCrossing& c : xs) {
      if (c.z > z) wind -= c.sign;
    }
    return wind != 0;
  };
  const int layers = int(std::floor((box.max.z() - box.min.z()) / h));
  const double step = 0.1;
  for (int l = 0; l < layers; ++l) {
    b.setLayer(l);
    const double z = box.min.z() + (l + 1) * h, zm = z - 0.5 * h;
    const bool alongX = l % 2 == 0;
    const int a0 = alongX ? 1 : 0;  // scan axis
    const int c0 = 1 - a0;          // line axis
    for (double t = box.min[a0] + 0.5 * w; t < box.max[a0]; t += w) {
      double runStart = 0;
      bool inRun = false;
      for (double s = box.min[c0]; s <= box.max[c0] + step; s += step) {
        Eigen::Vector2d q;
        q[a0] = t;
        q[c0] = s;
        const bool in = s <= box.max[c0] && insideAt(q.x(), q.y(), zm);
        if (in && !inRun) {
          runStart = s;
          inRun = true;
        } else if (!in && inRun) {
          inRun = false;
          Eigen::Vector3d p0(0, 0, z), p1(0, 0, z);
          p0[a0] = t;
          p1[a0] = t;
          p0[c0] = runStart;
          p1[c0] = s - step;
          b.travel(p0);
          if ((p1 - p0).norm() == 0) p1[c0] += 0.05;
          b.print(p1, Feature::Infill);
        }
      }
    }
  }
  return b.path;
}

TEST(VerifyProgram, KittenOf30mmRasterPasses) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  // Y-up to Z-up (rotation about X by +90 degrees), scaled to 30 mm tall, resting on z = 0.
  PlaceOptions place;
  place.up = UpAxis::PosY;
  place.scale = 30.0 / 116.3;
  const Mesh kitten = test::loadPlaced("pymdp_kitten.off", place);
  ASSERT_EQ(kitten.faceCount(), 10000u);
  const Toolpath tp = rasterToolpath(kitten, 0.2, 0.45);
  const ParsedProgram p = throughGcode(tp);
  const auto t0 = std::chrono::steady_clock::now();
  const VerifyReport r = verifyProgram(p, kitten);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.ok()) << r.message;
  std::printf("verify 30 mm kitten (raster): %.2f s, %s\n", seconds, verifyReportJson(r).c_str());
  EXPECT_GE(r.inside, 0.99);
  EXPECT_GE(r.coverage, 0.95);
  EXPECT_EQ(r.collisions, 0u);
}

TEST(VerifyProgram, ReportJsonAndStatuses) {
  test::BoxPathOptions o;
  o.half = 2;
  o.height = 1;
  const ParsedProgram p = throughGcode(test::boxToolpath(o));
  const Mesh part = test::makeBox(-2, -2, 0, 2, 2, 1);
  const VerifyReport r = verifyProgram(p, part);
  ASSERT_TRUE(r.ok());
  const nlohmann::json j = nlohmann::json::parse(verifyReportJson(r));
  for (const char* key : {"inside", "coverage", "surface_reached", "surface_reach_mm", "supported", "supported_all",
                          "collisions", "limits", "extrusion_mm", "path_mm", "samples", "grid_points", "layers"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["samples"].get<size_t>(), r.samples);
  EXPECT_EQ(j.size(), 16u);
  EXPECT_EQ(j["support_samples"].get<size_t>(), 0u);
  EXPECT_TRUE(j["unsupported_examples"].is_array());
  EXPECT_TRUE(j["collision_examples"].is_array() && j["collision_examples"].empty());

  VerifyOptions small;
  small.maxGridPoints = 1000;
  EXPECT_EQ(verifyProgram(p, part, small).status, Status::InvalidOption);
  EXPECT_EQ(verifyProgram(p, Mesh{}).status, Status::EmptyInput);
  int calls = 0;
  const VerifyReport c = verifyProgram(p, part, {}, [&](const char* stage, double) {
    EXPECT_STREQ(stage, "verify");
    return ++calls < 2;
  });
  EXPECT_EQ(c.status, Status::Cancelled);
  // Absurd coordinates or sample counts are refused, not looped over.
  ParsedProgram far = p;
  far.moves[5].to.x() = 1e300;
  EXPECT_EQ(verifyProgram(far, part).status, Status::InvalidOption);
  VerifyOptions fine;
  fine.sampleSpacing = 1e-9;
  EXPECT_EQ(verifyProgram(p, part, fine).status, Status::InvalidOption);
  fine = {};
  fine.gridSpacing = 1e-300;
  EXPECT_EQ(verifyProgram(p, part, fine).status, Status::InvalidOption);
  ParsedProgram noHeight = p;
  noHeight.layerHeight = 0;
  EXPECT_EQ(verifyProgram(noHeight, part).status, Status::InvalidOption);
}

}  // namespace
}  // namespace omnislice
