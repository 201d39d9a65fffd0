// SPDX-License-Identifier: MIT
// Planar gap fill and inner wall levels (PlanarOptions::gapFill), measured against the model:
//   - ribs 0.8 to 2.2 mm wide (1.8 to 4.9 lines of 0.45 mm), 20 mm long: on a middle layer the
//     filament laid on each rib, as bead volume, is the rib's section times the layer height to
//     within a few per cent. Without gap fill the ribs whose middle strip is narrower than another
//     wall level get 57-82 % of it (and before inner levels were opened, a level's loop doubling
//     back on itself gave 110-125 %);
//   - the gap lines cross each rib (along x, across its long axis y) and stay inside it;
//   - a plain box and the same box turned by 30 degrees have no gap at all (the wall levels meet
//     exactly), so gap fill does not spread over every wall.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../test_meshes.h"
#include "common/math_constants.h"
#include "slice/plan_layers.h"
#include "slice/slice_mesh.h"

namespace omnislice {
namespace {

const std::vector<double> kRibWidths = {0.8, 1.0, 1.15, 1.3, 1.45, 1.6, 1.9, 2.2};
constexpr double kRibLength = 20, kRibHeight = 8, kRibPitch = 3;

std::vector<double> ribStarts() {
  std::vector<double> x0;
  double x = 0;
  for (double t : kRibWidths) {
    x0.push_back(x);
    x += t + kRibPitch;
  }
  return x0;
}

Mesh ribs() {
  std::vector<test::Box> boxes;
  const std::vector<double> x0 = ribStarts();
  for (size_t k = 0; k < kRibWidths.size(); ++k) {
    boxes.push_back({x0[k], 0, 0, x0[k] + kRibWidths[k], kRibLength, kRibHeight});
  }
  return test::makeBoxUnion(boxes);
}

struct RibLayer {
  std::vector<double> volumeRatio;  // bead volume laid on each rib / its section x layer height
  std::vector<std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>> skin;  // skin lines per rib
};

RibLayer measure(const PlanLayersResult& r, const SliceResult& slices, int layer, const PlanarOptions& o) {
  RibLayer out;
  out.volumeRatio.assign(kRibWidths.size(), 0);
  out.skin.resize(kRibWidths.size());
  const std::vector<double> x0 = ribStarts();
  const double h = slices.layers[size_t(layer)].top - slices.layers[size_t(layer)].bottom;
  const double filamentArea = kPi / 4 * o.filamentDiameter * o.filamentDiameter;
  Eigen::Vector3d prev = r.toolpath.start;
  for (const Move& m : r.toolpath.moves) {
    if (m.kind == MoveKind::Print && m.layer == layer) {
      const double x = 0.5 * (prev.x() + m.position.x());
      for (size_t k = 0; k < kRibWidths.size(); ++k) {
        if (x < x0[k] - 0.5 || x > x0[k] + kRibWidths[k] + 0.5) continue;
        out.volumeRatio[k] += m.filament * filamentArea;
        if (m.feature == Feature::Skin) out.skin[k].push_back({prev, m.position});
      }
    }
    prev = m.position;
  }
  for (size_t k = 0; k < kRibWidths.size(); ++k) out.volumeRatio[k] /= kRibWidths[k] * kRibLength * h;
  return out;
}

TEST(GapFill, EveryRibGetsItsVolumeAndGapLinesCrossIt) {
  const SliceResult slices = sliceMesh(ribs(), SliceOptions{});
  ASSERT_TRUE(slices.ok()) << slices.message;
  PlanarOptions o;
  o.infillPercent = 100;
  const int mid = static_cast<int>(slices.layers.size() / 2);
  const PlanLayersResult r = planLayers(slices, o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_GT(r.gapAreaMm2, 0);
  const RibLayer with = measure(r, slices, mid, o);
  const double w = o.lineWidth;
  const std::vector<double> x0 = ribStarts();
  for (size_t k = 0; k < kRibWidths.size(); ++k) {
    SCOPED_TRACE("rib " + std::to_string(kRibWidths[k]) + " mm");
    EXPECT_GT(with.volumeRatio[k], 0.93);
    EXPECT_LT(with.volumeRatio[k], 1.05);
    // On a middle layer at 100 % infill every skin line is a gap line: across the rib, inside it.
    for (const auto& [a, b] : with.skin[k]) {
      const Eigen::Vector3d d = (b - a).normalized();
      EXPECT_LT(std::abs(d.y()), std::sin(1.0 * kPi / 180)) << a.transpose() << " -> " << b.transpose();
      for (const Eigen::Vector3d& p : {a, b}) {
        EXPECT_GT(p.x(), x0[k] + 0.5 * w - 1e-6);
        EXPECT_LT(p.x(), x0[k] + kRibWidths[k] - 0.5 * w + 1e-6);
      }
    }
  }
  // The ribs whose middle strip is narrower than a wall level (1.0-1.45 mm at two walls) get gap
  // lines; without gap fill they lack a fifth of their material or more, and get no skin there.
  for (size_t k = 1; k <= 4; ++k) EXPECT_GE(with.skin[k].size(), 30u) << kRibWidths[k];
  PlanarOptions off = o;
  off.gapFill = false;
  const PlanLayersResult r0 = planLayers(slices, off);
  ASSERT_TRUE(r0.ok());
  EXPECT_EQ(r0.gapAreaMm2, 0);
  const RibLayer without = measure(r0, slices, mid, off);
  for (size_t k = 1; k <= 4; ++k) {
    EXPECT_LT(without.volumeRatio[k], 0.85) << kRibWidths[k];
    EXPECT_TRUE(without.skin[k].empty());
  }
}

TEST(GapFill, WallLevelsOfABoxMeetWithoutGaps) {
  PlanarOptions o;
  for (double turn : {0.0, 30.0}) {
    SCOPED_TRACE("box turned " + std::to_string(turn) + " deg");
    const Eigen::Matrix3d R = Eigen::AngleAxisd(turn * kPi / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const SliceResult slices = sliceMesh(test::transformed(test::makeBox(0, 0, 0, 20, 12, 4), R, {0, 0, 0}),
                                         SliceOptions{});
    ASSERT_TRUE(slices.ok()) << slices.message;
    for (int walls : {1, 2, 3, 5}) {
      o.walls = walls;
      const PlanLayersResult r = planLayers(slices, o);
      ASSERT_TRUE(r.ok()) << r.message;
      EXPECT_EQ(r.gapAreaMm2, 0) << walls << " walls";
      // Every wall level is a full loop on every layer.
      std::vector<int> loops(slices.layers.size(), 0);
      for (const Move& m : r.toolpath.moves) {
        if (m.kind == MoveKind::Print && (m.feature == Feature::WallOuter || m.feature == Feature::WallInner)) {
          loops[size_t(m.layer)] += 1;
        }
      }
      for (int n : loops) EXPECT_GE(n, 4 * walls);
    }
  }
}

}  // namespace
}  // namespace omnislice
