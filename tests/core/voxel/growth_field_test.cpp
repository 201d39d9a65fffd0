// SPDX-License-Identifier: MIT
// Growing field (paper 001 Sections 4.2-4.4): invariants checked against an independently rebuilt
// hull per layer, the Fig. 4 shadow case, the inverse peeling field, strategies and schemes.
#include "voxel/growth_field.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <functional>

#include "voxel/lattice_hull.h"

namespace omnislice {
namespace {

using V3 = Eigen::Vector3i;

// Grid of sx x sy x sz part cells (k = 3.. above platformK = 2) with 2 empty cells of margin;
// solid(i, j, k) in part coordinates; the platform is the footprint of the lowest part layer.
VoxelGrid makeGrid(int sx, int sy, int sz, const std::function<bool(int, int, int)>& solid) {
  VoxelGrid g;
  g.width = 1;
  g.dims = V3(sx + 4, sy + 4, sz + 5);
  g.platformK = 2;
  g.state.assign(static_cast<size_t>(g.dims.prod()), 0);
  for (int k = 0; k < sz; ++k)
    for (int j = 0; j < sy; ++j)
      for (int i = 0; i < sx; ++i)
        if (solid(i, j, k)) g.state[g.index(i + 2, j + 2, k + 3)] = uint8_t(VoxelState::Solid);
  for (int j = 0; j < sy; ++j)
    for (int i = 0; i < sx; ++i)
      if (g.at(i + 2, j + 2, 3) == VoxelState::Solid)
        g.state[g.index(i + 2, j + 2, 2)] = uint8_t(VoxelState::Platform);
  return g;
}

// Checks the header's invariants with a from-scratch hull per layer (no incremental path, no
// cached planes): first layer = cells on the platform; every voxel of layer tau > 1 has an ASN
// in an earlier layer; no voxel of layer tau is inside (by eps) C(T U layers < tau).
void expectValidField(const VoxelGrid& grid, const GrowthField& f, double eps) {
  ASSERT_TRUE(f.ok()) << f.message;
  ASSERT_EQ(f.g.size(), grid.cellCount());
  std::vector<std::vector<V3>> byLayer(f.layers + 1);
  std::vector<V3> platform;
  size_t grown = 0, missed = 0;
  for (size_t c = 0; c < grid.cellCount(); ++c) {
    const V3 p = grid.cell(c);
    if (!grid.printable(c)) {
      ASSERT_EQ(f.g[c], 0);
      if (grid.state[c] == uint8_t(VoxelState::Platform)) platform.push_back(p);
      continue;
    }
    const bool onPlatform = p.z() == grid.platformK + 1 &&
                            grid.at(p.x(), p.y(), p.z() - 1) == VoxelState::Platform;
    ASSERT_EQ(f.g[c] == 1, onPlatform) << "first layer must be exactly the cells on the platform";
    if (f.g[c] < 0) {
      ++missed;
      continue;
    }
    ASSERT_GE(f.g[c], 1);
    ++grown;
    byLayer[f.g[c]].push_back(p);
    if (f.g[c] > 1) {
      bool supported = false;
      for (const V3& o : amStableOffsets()) {
        const V3 q = p + o;
        const int32_t gq = f.g[grid.index(q.x(), q.y(), q.z())];
        supported = supported || (gq >= 1 && gq < f.g[c]);
      }
      ASSERT_TRUE(supported) << "voxel " << p.transpose() << " of layer " << f.g[c]
                             << " has no AM-stable neighbour in an earlier layer";
    }
  }
  EXPECT_EQ(grown, f.grown);
  EXPECT_EQ(missed, f.missed);
  // Layer 1 is the platform contact by definition; every later layer is checked.
  std::vector<V3> earlier = platform;
  if (f.layers >= 1) earlier.insert(earlier.end(), byLayer[1].begin(), byLayer[1].end());
  for (int tau = 2; tau <= f.layers; ++tau) {
    const LatticeHull hull(earlier);
    for (const V3& p : byLayer[tau])
      ASSERT_FALSE(hull.inside(p, eps)) << "voxel " << p.transpose() << " of layer " << tau
                                        << " is inside the hull of earlier layers";
    earlier.insert(earlier.end(), byLayer[tau].begin(), byLayer[tau].end());
  }
}

// Fig. 4: a post with an arm on top and a hook hanging from the arm; the arm goes on past the
// hook. The flat greedy front runs along the arm and closes the hull under the hook.
VoxelGrid hookGrid() {
  return makeGrid(40, 3, 26, [](int i, int, int k) {
    const bool post = i < 3;
    const bool arm = k >= 22 && k < 25;
    const bool hook = i >= 9 && i < 12 && k >= 6;
    return post || arm || hook;
  });
}

TEST(GrowthField, Fig4ShadowCaseAvoidedWithPreventionNotWithout) {
  const VoxelGrid grid = hookGrid();
  GrowthOptions o;
  for (GrowthStrategy s : {GrowthStrategy::Gcfa, GrowthStrategy::SpGcfa, GrowthStrategy::PgGcfa,
                           GrowthStrategy::PgSpGcfa}) {
    for (ShadowScheme scheme : {ShadowScheme::RecursivePca, ShadowScheme::Incremental}) {
      o.strategy = s;
      o.shadowScheme = scheme;
      const GrowthField f = growField(grid, o);
      std::printf("[ hook ] %-10s %-11s missed %zu of %zu, layers %d, hull builds %zu, %.1f ms\n",
                  growthStrategyName(s), shadowSchemeName(scheme), f.missed, f.grown + f.missed,
                  f.layers, f.hullBuilds, f.totalMs);
      expectValidField(grid, f, o.epsilon);
      if (s == GrowthStrategy::Gcfa) {
        EXPECT_GE(f.missed, 5u) << "greedy front must shadow the hook";
      }
      if (s == GrowthStrategy::SpGcfa) {
        EXPECT_EQ(f.missed, 0u) << "shadow prevention must reach the hook";
      }
    }
  }
}

TEST(GrowthField, BoxGrowsInFlatLayersFromThePlatform) {
  const VoxelGrid grid = makeGrid(10, 8, 6, [](int, int, int) { return true; });
  for (GrowthStrategy s : {GrowthStrategy::Gcfa, GrowthStrategy::SpGcfa, GrowthStrategy::PgGcfa,
                           GrowthStrategy::PgSpGcfa}) {
    GrowthOptions o;
    o.strategy = s;
    const GrowthField f = growField(grid, o);
    expectValidField(grid, f, o.epsilon);
    EXPECT_EQ(f.missed, 0u);
    EXPECT_EQ(f.grown, 480u);
    if (s == GrowthStrategy::Gcfa) {
      // A box on its full footprint grows layer by layer: G = k - platformK.
      for (size_t c = 0; c < grid.cellCount(); ++c)
        if (grid.printable(c)) {
          ASSERT_EQ(f.g[c], grid.cell(c).z() - grid.platformK);
        }
    }
  }
}

TEST(GrowthField, PeelingFieldOfABoxHasConcentricSheets) {
  const int X = 20, Y = 20, Z = 12;
  const VoxelGrid grid = makeGrid(X, Y, Z, [](int, int, int) { return true; });
  const std::vector<int32_t> fb = inversePeelingField(grid, 0.5);
  ASSERT_EQ(fb.size(), grid.cellCount());
  int32_t maxF = 0, minF = 1 << 30, minBottom = 1 << 30;
  for (size_t c = 0; c < grid.cellCount(); ++c) {
    if (!grid.printable(c)) {
      ASSERT_EQ(fb[c], 0);
      continue;
    }
    ASSERT_GE(fb[c], 1);
    maxF = std::max(maxF, fb[c]);
    minF = std::min(minF, fb[c]);
    if (grid.cell(c).z() == grid.platformK + 1) minBottom = std::min(minBottom, fb[c]);
  }
  EXPECT_EQ(minF, 1);
  EXPECT_EQ(minBottom, 1) << "voxels on the platform get the smallest values";
  // Every column: F-bar does not decrease going up (sheets are peeled from the top and sides).
  for (int j = 0; j < Y; ++j)
    for (int i = 0; i < X; ++i)
      for (int k = 1; k < Z; ++k)
        ASSERT_LE(fb[grid.index(i + 2, j + 2, k + 2)], fb[grid.index(i + 2, j + 2, k + 3)]);
  // The whole top face and the upper side walls form the first sheet (F-bar = max).
  for (int j = 0; j < Y; ++j)
    for (int i = 0; i < X; ++i) ASSERT_EQ(fb[grid.index(i + 2, j + 2, Z + 2)], maxF);
  // Concentric: down the centre column one sheet per cell while the top facet stays flat.
  for (int d = 0; d < 5; ++d)
    EXPECT_EQ(fb[grid.index(X / 2 + 2, Y / 2 + 2, Z + 2 - d)], maxF - d) << "depth " << d;
  std::printf("[ peel ] box %dx%dx%d: %d sheets\n", X, Y, Z, maxF);
}

TEST(GrowthField, BothShadowSchemesAndAllStrategiesGiveValidFieldsOnAnOverhang) {
  // A mushroom: stem plus a wide cap with a downward rim (overhangs in every direction).
  const VoxelGrid grid = makeGrid(24, 24, 16, [](int i, int j, int k) {
    const double r = std::hypot(i - 11.5, j - 11.5);
    if (r < 3) return true;
    if (k >= 12 && r < 11.5) return true;
    return k >= 8 && r >= 9 && r < 11.5;
  });
  for (GrowthStrategy s : {GrowthStrategy::Gcfa, GrowthStrategy::SpGcfa, GrowthStrategy::PgGcfa,
                           GrowthStrategy::PgSpGcfa})
    for (ShadowScheme scheme : {ShadowScheme::RecursivePca, ShadowScheme::Incremental}) {
      GrowthOptions o;
      o.strategy = s;
      o.shadowScheme = scheme;
      const GrowthField f = growField(grid, o);
      std::printf("[ mushroom ] %-10s %-11s missed %zu of %zu, layers %d, %.1f ms\n",
                  growthStrategyName(s), shadowSchemeName(scheme), f.missed, f.grown + f.missed,
                  f.layers, f.totalMs);
      expectValidField(grid, f, o.epsilon);
      if (s == GrowthStrategy::PgGcfa || s == GrowthStrategy::PgSpGcfa)
        EXPECT_EQ(f.peel.size(), grid.cellCount());
      else
        EXPECT_TRUE(f.peel.empty());
    }
}

TEST(GrowthField, BadInputAndCancellation) {
  VoxelGrid bad;
  bad.dims = V3(3, 3, 3);
  bad.state.assign(5, 0);
  EXPECT_EQ(growField(bad, {}).status, Status::InvalidOption);
  const VoxelGrid empty = makeGrid(4, 4, 4, [](int, int, int) { return false; });
  EXPECT_EQ(growField(empty, {}).status, Status::EmptyInput);
  const VoxelGrid box = makeGrid(6, 6, 6, [](int, int, int) { return true; });
  GrowthOptions o;
  o.epsilon = -1;
  EXPECT_EQ(growField(box, o).status, Status::InvalidOption);
  o.epsilon = 0.5;
  o.peelStep = 0;
  EXPECT_EQ(growField(box, o).status, Status::InvalidOption);
  o.peelStep = 1;
  std::vector<std::string> stages;
  const GrowthField c = growField(box, o, [&](const char* stage, double) {
    stages.push_back(stage);
    return stages.size() < 2;
  });
  EXPECT_EQ(c.status, Status::Cancelled);
  stages.clear();
  const GrowthField ok = growField(box, o, [&](const char* stage, double) {
    stages.push_back(stage);
    return true;
  });
  ASSERT_TRUE(ok.ok());
  ASSERT_FALSE(stages.empty());
  EXPECT_EQ(stages.front(), "peeling");
  EXPECT_EQ(stages.back(), "growth");
  // Cancelling during growth (SP-GCFA) stops with Cancelled and an empty field.
  {
    GrowthOptions sp;
    sp.strategy = GrowthStrategy::SpGcfa;
    int calls = 0;
    const GrowthField g = growField(hookGrid(), sp, [&](const char*, double) { return ++calls < 1; });
    EXPECT_EQ(g.status, Status::Cancelled);
    EXPECT_TRUE(g.g.empty());
  }
  // A part not touching the platform is entirely missed, not an error.
  VoxelGrid floating = makeGrid(6, 6, 6, [](int, int, int k) { return k >= 3; });
  const GrowthField fl = growField(floating, {});
  ASSERT_TRUE(fl.ok());
  EXPECT_EQ(fl.grown, 0u);
  EXPECT_EQ(fl.missed, 108u);
}

TEST(GrowthField, NamesRoundTrip) {
  for (GrowthStrategy s : {GrowthStrategy::Gcfa, GrowthStrategy::SpGcfa, GrowthStrategy::PgGcfa,
                           GrowthStrategy::PgSpGcfa}) {
    GrowthStrategy back = GrowthStrategy::Gcfa;
    ASSERT_TRUE(parseGrowthStrategy(growthStrategyName(s), back));
    EXPECT_EQ(back, s);
  }
  ShadowScheme sc = ShadowScheme::Incremental;
  ASSERT_TRUE(parseShadowScheme("recursive", sc));
  EXPECT_EQ(sc, ShadowScheme::RecursivePca);
  ASSERT_TRUE(parseShadowScheme(shadowSchemeName(ShadowScheme::Incremental), sc));
  EXPECT_EQ(sc, ShadowScheme::Incremental);
  GrowthStrategy unused = GrowthStrategy::Gcfa;
  EXPECT_FALSE(parseGrowthStrategy("nope", unused));
  EXPECT_FALSE(parseShadowScheme("", sc));
}

}  // namespace
}  // namespace omnislice
