// SPDX-License-Identifier: MIT
// Travel inside the part (PlanarOptions::travelInside), checked on the tool path against the
// slice's own sections (an independent point-in-island test), on parts where a straight travel
// leaves the section: a square frame (a hole in the middle) and a C (a notch).
//   - every travel that starts and ends in the same island of a layer stays inside that island;
//     with travelInside off, some do not (so the check measures something);
//   - travels inside the part retract only when longer than retractInsideMaxTravel;
//   - the printed moves are the same either way (only travels change).
#include <gtest/gtest.h>

#include <vector>

#include "../test_meshes.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"
#include "slice_test_support.h"

namespace omnislice {
namespace {

// A travel as planned: consecutive non-extruding moves between two prints, in one layer.
struct TravelRun {
  int layer = 0;
  std::vector<Eigen::Vector3d> points;  // from where the nozzle was to the next print's start
  bool retracted = false;
  double length() const {
    double l = 0;
    for (size_t i = 1; i < points.size(); ++i) l += (points[i] - points[i - 1]).norm();
    return l;
  }
};

std::vector<TravelRun> travels(const Toolpath& tp) {
  std::vector<TravelRun> out;
  Eigen::Vector3d prev = tp.start;
  bool open = false;
  for (const Move& m : tp.moves) {
    if (m.kind == MoveKind::Print) {
      open = false;
    } else {
      if (!open) out.push_back(TravelRun{m.layer, {prev}, false});
      open = true;
      if (m.kind == MoveKind::Retract) out.back().retracted = true;
      if (m.kind == MoveKind::Travel) out.back().points.push_back(m.position);
    }
    prev = m.position;
  }
  return out;
}

const ExPolygon2* islandOf(const SliceLayer& layer, const Eigen::Vector2d& p) {
  for (const ExPolygon2& island : layer.islands) {
    if (insideIsland(island, p)) return &island;
  }
  return nullptr;
}

struct Check {
  size_t inIsland = 0;    // travels from and to the same island, in one layer
  size_t leaving = 0;     // of those, travels with a point outside the island
  size_t retractedShort = 0;  // of those, retracted though no longer than the inside maximum
};

Check check(const SliceResult& slices, const PlanarOptions& o, const Toolpath& tp) {
  Check c;
  for (const TravelRun& t : travels(tp)) {
    if (t.points.size() < 2 || t.layer < 0) continue;
    const Eigen::Vector3d& a = t.points.front();
    const Eigen::Vector3d& b = t.points.back();
    if (std::abs(a.z() - b.z()) > 1e-9) continue;  // between layers
    const SliceLayer& layer = slices.layers[size_t(t.layer)];
    const ExPolygon2* island = islandOf(layer, a.head<2>());
    if (!island || island != islandOf(layer, b.head<2>())) continue;
    ++c.inIsland;
    bool out = false;
    for (size_t i = 1; i < t.points.size() && !out; ++i) {
      const Eigen::Vector3d d = t.points[i] - t.points[i - 1];
      const int steps = std::max(1, static_cast<int>(d.norm() / 0.05));
      for (int k = 0; k <= steps && !out; ++k) {
        const Eigen::Vector2d p = (t.points[i - 1] + d * (double(k) / steps)).head<2>();
        out = !insideIsland(*island, p);
      }
    }
    c.leaving += out;
    c.retractedShort += t.retracted && t.length() <= o.retractInsideMaxTravel;
  }
  return c;
}

std::vector<Eigen::Vector3d> printed(const Toolpath& tp) {
  std::vector<Eigen::Vector3d> out;
  for (const Move& m : tp.moves) {
    if (m.kind == MoveKind::Print) out.push_back(m.position);
  }
  return out;
}

TEST(TravelInside, TravelsKeepToTheSectionRoundHolesAndNotches) {
  const Mesh frame = test::makeBoxUnion({{0, 0, 0, 30, 8, 3}, {0, 22, 0, 30, 30, 3}, {0, 8, 0, 8, 22, 3}, {22, 8, 0, 30, 22, 3}});
  const Mesh c = test::makeBoxUnion({{0, 0, 0, 6, 30, 3}, {6, 0, 0, 30, 6, 3}, {6, 24, 0, 30, 30, 3}});
  for (const auto& [name, mesh] : {std::pair{"frame", frame}, std::pair{"C", c}}) {
    const SliceResult slices = sliceMesh(mesh, SliceOptions{});
    ASSERT_TRUE(slices.ok()) << slices.message;
    PlanarOptions on;
    on.seam = SeamPlacement::Random;  // seams all round the part: travels in every direction
    PlanarOptions off = on;
    off.travelInside = false;
    const PlanLayersResult a = planLayers(slices, on);
    const PlanLayersResult b = planLayers(slices, off);
    ASSERT_TRUE(a.ok() && b.ok()) << a.message << b.message;
    const Check inside = check(slices, on, a.toolpath), straight = check(slices, off, b.toolpath);
    EXPECT_GT(inside.inIsland, 100u) << name;
    EXPECT_EQ(inside.leaving, 0u) << name << ": travels leaving the section";
    EXPECT_GT(straight.leaving, 10u) << name << ": straight travels cross the " << (name[0] == 'f' ? "hole" : "notch");
    EXPECT_EQ(inside.retractedShort, 0u) << name;
    EXPECT_GT(straight.retractedShort, 10u) << name;
    EXPECT_EQ(printed(a.toolpath), printed(b.toolpath)) << name << ": the same prints";
  }
}

TEST(TravelInside, ALongInsideRouteRetractsAndBadOptionsAreRefused) {
  const SliceResult slices = sliceMesh(test::makeBox(0, 0, 0, 40, 40, 1), SliceOptions{});
  PlanarOptions o;
  o.retractInsideMaxTravel = 0.5;
  const PlanLayersResult r = planLayers(slices, o);
  ASSERT_TRUE(r.ok());
  size_t longInside = 0, retracted = 0;
  for (const TravelRun& t : travels(r.toolpath)) {
    if (t.points.size() < 2 || t.layer < 1 || std::abs(t.points.front().z() - t.points.back().z()) > 1e-9) continue;
    if (t.length() > std::max(o.retractMinTravel, o.retractInsideMaxTravel)) {
      ++longInside;
      retracted += t.retracted;
    }
  }
  EXPECT_GT(longInside, 0u);
  EXPECT_EQ(retracted, longInside);
  o.retractInsideMaxTravel = -1;
  EXPECT_EQ(planLayers(slices, o).status, Status::InvalidOption);
}

}  // namespace
}  // namespace omnislice
