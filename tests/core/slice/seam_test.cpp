// SPDX-License-Identifier: MIT
// Seams of planar wall loops (PlanarOptions::seam), measured on the tool path per layer: where each
// wall loop starts (the point its first extruding move leaves from, which is also where it ends).
//   aligned:  on an L-shaped prism every layer's outer seam is in the concave corner; on a box in
//             one corner, the same one in every layer; on a cylinder (no corner) on one vertical
//             line at the rear (+Y);
//   sharpest: the L's concave corner, and a corner of a box;
//   nearest:  each loop starts at its vertex nearest the nozzle before the travel to it;
//   random:   spread around a cylinder, and the same on every run.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "../test_meshes.h"
#include "common/math_constants.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"

namespace omnislice {
namespace {

// A vertical prism over a convex polygon (counter-clockwise in XY), from z0 to z1.
Mesh makePrismZ(const std::vector<Eigen::Vector2d>& poly, double z0, double z1) {
  Mesh m;
  const uint32_t n = static_cast<uint32_t>(poly.size());
  for (double z : {z0, z1}) {
    for (const Eigen::Vector2d& p : poly) m.positions.insert(m.positions.end(), {p.x(), p.y(), z});
  }
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    m.triangles.insert(m.triangles.end(), {i, j, n + j, i, n + j, n + i});
  }
  for (uint32_t i = 1; i + 1 < n; ++i) {
    m.triangles.insert(m.triangles.end(), {0, i + 1, i});          // bottom, facing down
    m.triangles.insert(m.triangles.end(), {n, n + i, n + i + 1});  // top, facing up
  }
  return m;
}

Mesh makeCylinder(double r, double h, int sides) {
  std::vector<Eigen::Vector2d> poly;
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * kPi * (i + 0.37) / sides;  // no vertex exactly at the rear
    poly.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return makePrismZ(poly, 0, h);
}

// A wall loop as printed: its layer, feature, the nozzle before the travel to it, its points.
struct Loop {
  int layer = 0;
  Feature feature = Feature::None;
  Eigen::Vector2d before{0, 0};
  std::vector<Eigen::Vector2d> points;  // start ... end (= start)
  Eigen::Vector2d seam() const { return points.front(); }
};

std::vector<Loop> wallLoops(const Toolpath& tp) {
  std::vector<Loop> loops;
  Eigen::Vector3d prev = tp.start, beforeTravel = tp.start;
  bool inRun = false;
  for (const Move& m : tp.moves) {
    const bool wall = m.kind == MoveKind::Print &&
                      (m.feature == Feature::WallOuter || m.feature == Feature::WallInner);
    if (wall && (!inRun || loops.back().feature != m.feature)) {
      Loop l;
      l.layer = m.layer;
      l.feature = m.feature;
      l.before = beforeTravel.head<2>();
      l.points.push_back(prev.head<2>());
      loops.push_back(l);
    }
    if (wall) loops.back().points.push_back(m.position.head<2>());
    inRun = wall;
    if (m.kind != MoveKind::Travel && m.kind != MoveKind::Retract && m.kind != MoveKind::Unretract) {
      beforeTravel = m.position;
    }
    prev = m.position;
  }
  return loops;
}

Toolpath plan(const Mesh& mesh, SeamPlacement seam) {
  const SliceResult slices = sliceMesh(mesh, SliceOptions{});
  EXPECT_TRUE(slices.ok()) << slices.message;
  PlanarOptions o;
  o.seam = seam;
  const PlanLayersResult r = planLayers(slices, o);
  EXPECT_TRUE(r.ok()) << r.message;
  return r.toolpath;
}

std::vector<Loop> outerLoops(const Toolpath& tp) {
  std::vector<Loop> out;
  for (const Loop& l : wallLoops(tp)) {
    if (l.feature == Feature::WallOuter) out.push_back(l);
  }
  return out;
}

// An L-shaped prism: a 20 x 20 mm square with its 12 x 12 mm corner at (+x, +y) taken away, so
// its only concave corner is at (8, 8); 4 mm tall (20 layers).
Mesh makeL() {
  return test::makeBoxUnion({{0, 0, 0, 20, 8, 4}, {0, 8, 0, 8, 20, 4}});
}

TEST(Seams, AlignedAndSharpestHideTheSeamInTheConcaveCorner) {
  const double w = PlanarOptions{}.lineWidth;
  // The outer wall runs w/2 inside the outline: its concave corner is at (8 - w/2, 8 - w/2).
  const Eigen::Vector2d corner(8 - 0.5 * w, 8 - 0.5 * w);
  for (SeamPlacement mode : {SeamPlacement::Aligned, SeamPlacement::Sharpest}) {
    const std::vector<Loop> loops = outerLoops(plan(makeL(), mode));
    ASSERT_EQ(loops.size(), 20u);
    for (const Loop& l : loops) {
      EXPECT_LT((l.seam() - corner).norm(), 0.5 * w) << "layer " << l.layer << " seam " << l.seam().transpose();
    }
  }
  // Nearest (the travel's shortest) does not look for corners: on the L it starts elsewhere in
  // most layers (so the test above measures a choice).
  int inCorner = 0;
  for (const Loop& l : outerLoops(plan(makeL(), SeamPlacement::Nearest))) inCorner += (l.seam() - corner).norm() < 0.5 * w;
  EXPECT_LT(inCorner, 10);
}

TEST(Seams, AlignedKeepsOneCornerOfABoxAndOneLineOnACylinder) {
  const double w = PlanarOptions{}.lineWidth;
  // Box: all four corners convex and alike; every layer's seam at the same corner.
  const std::vector<Loop> box = outerLoops(plan(test::makeBox(-10, -7, 0, 10, 7, 5), SeamPlacement::Aligned));
  ASSERT_EQ(box.size(), 25u);
  const Eigen::Vector2d first = box.front().seam();
  EXPECT_NEAR(std::abs(first.x()), 10 - 0.5 * w, 0.5 * w) << first.transpose();
  EXPECT_NEAR(std::abs(first.y()), 7 - 0.5 * w, 0.5 * w) << first.transpose();
  for (const Loop& l : box) EXPECT_LT((l.seam() - first).norm(), 0.25 * w) << "layer " << l.layer;

  // Cylinder of 64 sides (5.6 deg turns, below the corner floor): the rear, one line. The inner
  // wall's seam lines up with the outer's too.
  const double r = 10;
  const std::vector<Loop> all = wallLoops(plan(makeCylinder(r, 6, 64), SeamPlacement::Aligned));
  size_t outer = 0;
  for (const Loop& l : all) {
    EXPECT_GT(l.seam().y(), 0.97 * (r - 2 * w)) << "layer " << l.layer << ": at the rear";
    EXPECT_LT(std::abs(l.seam().x()), 1.5) << "layer " << l.layer << ": on one line";
    outer += l.feature == Feature::WallOuter;
  }
  EXPECT_EQ(outer, 30u);
}

TEST(Seams, NearestStartsAtTheLoopsVertexNearestTheNozzle) {
  const std::vector<Loop> loops = wallLoops(plan(makeL(), SeamPlacement::Nearest));
  ASSERT_GE(loops.size(), 40u);
  for (const Loop& l : loops) {
    double nearest = INFINITY;
    for (const Eigen::Vector2d& p : l.points) nearest = std::min(nearest, (p - l.before).norm());
    EXPECT_LE((l.seam() - l.before).norm(), nearest + 1e-9) << "layer " << l.layer;
  }
}

TEST(Seams, RandomSpreadsAroundACylinderTheSameOnEveryRun) {
  const Toolpath a = plan(makeCylinder(10, 6, 64), SeamPlacement::Random);
  const Toolpath b = plan(makeCylinder(10, 6, 64), SeamPlacement::Random);
  const std::vector<Loop> la = outerLoops(a), lb = outerLoops(b);
  ASSERT_EQ(la.size(), 30u);
  ASSERT_EQ(lb.size(), la.size());
  Eigen::Vector2d resultant(0, 0);
  std::map<int, int> octants;
  for (size_t i = 0; i < la.size(); ++i) {
    EXPECT_EQ(la[i].seam(), lb[i].seam()) << "layer " << la[i].layer << ": the same on every run";
    const Eigen::Vector2d u = la[i].seam().normalized();
    resultant += u;
    ++octants[static_cast<int>(std::floor((std::atan2(u.y(), u.x()) + kPi) / (kPi / 4))) % 8];
  }
  // Aligned seams would give a resultant of length 1 and one octant.
  EXPECT_LT(resultant.norm() / la.size(), 0.5);
  EXPECT_GE(octants.size(), 5u);
}

}  // namespace
}  // namespace omnislice
