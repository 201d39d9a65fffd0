// SPDX-License-Identifier: MIT
// Growing field on the shared real models (Bunny, Kitten, Fertility): missed voxels and timings
// per strategy (paper 001 Table 1, Figs. 13-14), on grids from voxelizeSolid after placeMesh as the
// pipeline does.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include <sys/resource.h>

#include "../test_support.h"
#include "mesh/place_mesh.h"
#include "pipeline/settings.h"
#include "voxel/growth_field.h"
#include "voxel/lattice_hull.h"
#include "voxel/voxelize.h"

namespace omnislice {
namespace {

using V3 = Eigen::Vector3i;

// The pipeline's conservative voxelisation (voxelizeSolid), platform = footprint.
VoxelGrid voxelGrid(const Mesh& mesh, double w) {
  VoxelizeOptions o;
  o.width = w;
  const VoxelizeResult r = voxelizeSolid(mesh, o);
  EXPECT_TRUE(r.ok()) << r.message;
  return r.grid;
}

size_t countPrintable(const VoxelGrid& g) {
  size_t n = 0;
  for (size_t c = 0; c < g.cellCount(); ++c) n += g.printable(c);
  return n;
}

// Cheap invariants on big grids: first layer on the platform, every later voxel supported by an
// earlier ASN, counts consistent; plus the hull check on a sample of layers (rebuilt from scratch).
void expectFieldInvariants(const VoxelGrid& grid, const GrowthField& f, double eps) {
  ASSERT_TRUE(f.ok()) << f.message;
  std::vector<std::vector<V3>> byLayer(f.layers + 1);
  std::vector<V3> platform;
  for (size_t c = 0; c < grid.cellCount(); ++c) {
    const V3 p = grid.cell(c);
    if (!grid.printable(c)) {
      if (grid.state[c] == uint8_t(VoxelState::Platform)) platform.push_back(p);
      continue;
    }
    const bool onPlatform = p.z() == grid.platformK + 1 &&
                            grid.at(p.x(), p.y(), p.z() - 1) == VoxelState::Platform;
    ASSERT_EQ(f.g[c] == 1, onPlatform);
    if (f.g[c] < 1) continue;
    byLayer[f.g[c]].push_back(p);
    if (f.g[c] == 1) continue;
    bool supported = false;
    for (const V3& o : amStableOffsets()) {
      const int32_t gq = f.g[grid.index(p.x() + o.x(), p.y() + o.y(), p.z() + o.z())];
      supported = supported || (gq >= 1 && gq < f.g[c]);
    }
    ASSERT_TRUE(supported);
  }
  std::vector<V3> earlier = platform;
  const int step = std::max(1, f.layers / 12);
  for (int tau = 1; tau <= f.layers; ++tau) {
    if (tau == 1) {  // the platform contact, by definition
      earlier.insert(earlier.end(), byLayer[1].begin(), byLayer[1].end());
      continue;
    }
    if (tau % step == 0) {
      const LatticeHull hull(earlier);
      for (const V3& p : byLayer[tau]) ASSERT_FALSE(hull.inside(p, eps)) << "layer " << tau;
    }
    earlier.insert(earlier.end(), byLayer[tau].begin(), byLayer[tau].end());
  }
}

struct Case {
  const char* file;
  UpAxis up;
  double fitMm;
  double width;
};

GrowthField runCase(const VoxelGrid& grid, const char* name, GrowthStrategy s,
                    double eps = GrowthOptions().epsilon) {
  GrowthOptions o;
  o.strategy = s;
  o.epsilon = eps;
  const GrowthField f = growField(grid, o);
  std::printf("[ model ] %-10s %-10s eps %.2f: %zu voxels, missed %zu, layers %d, peel %.0f ms, "
              "shadow %.0f ms, total %.0f ms, hull builds %zu, shadow checks %zu\n",
              name, growthStrategyName(s), eps, f.grown + f.missed, f.missed, f.layers,
              f.peelingMs, f.shadowMs, f.totalMs, f.hullBuilds, f.shadowChecks);
  std::fflush(stdout);
  return f;
}

// Strategies to compare: PG-SP-GCFA and GCFA always; SP-GCFA (minutes on these grids, like the
// paper's Fig. 13) only with OMNISLICE_SLOW_TESTS=1.
std::vector<GrowthStrategy> strategiesToRun() {
  std::vector<GrowthStrategy> s = {GrowthStrategy::PgSpGcfa, GrowthStrategy::Gcfa};
  if (std::getenv("OMNISLICE_SLOW_TESTS")) s.push_back(GrowthStrategy::SpGcfa);
  return s;
}

TEST(GrowthFieldModels, BunnyAndKittenHaveNoMissedVoxels) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  // Kitten: pymdp_kitten.off is Y-up (MANIFEST.md).
  const Case cases[] = {{"compas_bunny_closed_low_res.obj", UpAxis::PosZ, 80, 0.8},
                        {"pymdp_kitten.off", UpAxis::PosY, 80, 0.8}};
  for (const Case& c : cases) {
    PlaceOptions pl;
    pl.up = c.up;
    pl.fitMm = c.fitMm;
    const VoxelGrid grid = voxelGrid(test::loadPlaced(c.file, pl), c.width);
    std::printf("[ model ] %s: grid %dx%dx%d, %zu voxels\n", c.file, grid.dims.x(), grid.dims.y(),
                grid.dims.z(), countPrintable(grid));
    {
      // Cancellation reaches into shadow prevention: SP-GCFA (minutes here) stops promptly.
      GrowthOptions o;
      o.strategy = GrowthStrategy::SpGcfa;
      int calls = 0;
      double lastCall = 0;
      const auto t0 = std::chrono::steady_clock::now();
      auto since = [&] {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      };
      const GrowthField f = growField(grid, o, [&](const char*, double) {
        lastCall = since();
        return ++calls < 40;
      });
      const double stopped = since() - lastCall;
      std::printf("[ model ] %s sp-gcfa cancelled at call 40 after %.0f ms, returned %.1f ms later\n",
                  c.file, lastCall, stopped);
      EXPECT_EQ(f.status, Status::Cancelled);
      EXPECT_LT(stopped, 1000.0);
    }
    for (GrowthStrategy s : strategiesToRun()) {
      const GrowthField f = runCase(grid, c.file, s);
      expectFieldInvariants(grid, f, GrowthOptions().epsilon);
      if (s == GrowthStrategy::PgSpGcfa) {
        EXPECT_EQ(f.missed, 0u) << c.file;
      }
      if (s == GrowthStrategy::Gcfa) {
        EXPECT_GT(f.missed, 0u) << "the greedy front shadows overhangs";
      }
    }
  }
}

// A real build plate (a 60 mm disc of Platform cells, as VoxelMultiAxisAM adds its platform
// solid to every hull): the wide base widens every hull, the greedy front misses more, PG-SP-GCFA
// still reaches everything.
TEST(GrowthFieldModels, BunnyOnADiscPlatform) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  PlaceOptions pl;
  pl.fitMm = 80;
  VoxelizeOptions vo;
  vo.width = 0.8;
  vo.platformRadius = 60;
  const VoxelizeResult v = voxelizeSolid(test::loadPlaced("compas_bunny_closed_low_res.obj", pl), vo);
  ASSERT_TRUE(v.ok()) << v.message;
  std::printf("[ model ] bunny on a 60 mm disc: %zu platform cells\n", v.platformCount);
  const GrowthField greedy = runCase(v.grid, "bunny-disc", GrowthStrategy::Gcfa);
  const GrowthField f = runCase(v.grid, "bunny-disc", GrowthStrategy::PgSpGcfa);
  expectFieldInvariants(v.grid, f, GrowthOptions().epsilon);
  EXPECT_EQ(f.missed, 0u);
  EXPECT_GT(greedy.missed, 0u);
}

// Speed at the large size (~540k voxels, Armadillo-sized): Bunny at w = 0.6 mm.
// Time and peak memory printed, not asserted.
TEST(GrowthFieldModels, LargeGridTiming) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  PlaceOptions pl;
  pl.fitMm = 80;
  const VoxelGrid grid = voxelGrid(test::loadPlaced("compas_bunny_closed_high_res.stl", pl), 0.6);
  std::printf("[ model ] bunny high-res at 0.6 mm: grid %dx%dx%d (%zu cells), %zu voxels\n",
              grid.dims.x(), grid.dims.y(), grid.dims.z(), grid.cellCount(), countPrintable(grid));
  const GrowthField f = runCase(grid, "bunny-0.6", GrowthStrategy::PgSpGcfa);
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  std::printf("[ model ] peak RSS of the test process so far: %.0f MB\n", ru.ru_maxrss / 1024.0);
  expectFieldInvariants(grid, f, GrowthOptions().epsilon);
  EXPECT_EQ(f.missed, 0u);
}

// eps sweep (printed, not asserted; OMNISLICE_EPS_SWEEP=1): missed voxels and time of
// PG-SP-GCFA per eps on the three models, the measurement behind GrowthOptions::epsilon.
TEST(GrowthFieldModels, EpsilonSweep) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  if (!std::getenv("OMNISLICE_EPS_SWEEP")) GTEST_SKIP() << "set OMNISLICE_EPS_SWEEP=1";
  const Case cases[] = {{"nestedcages_fertility.off", UpAxis::PosX, 80, 0.8},
                        {"pymdp_kitten.off", UpAxis::PosY, 80, 0.8},
                        {"compas_bunny_closed_low_res.obj", UpAxis::PosZ, 80, 0.8}};
  for (const Case& c : cases) {
    PlaceOptions pl;
    pl.up = c.up;
    pl.fitMm = c.fitMm;
    const VoxelGrid grid = voxelGrid(test::loadPlaced(c.file, pl), c.width);
    for (double eps : {1.0, 0.75, 0.5, 0.3, 0.1}) {
      const GrowthField f = runCase(grid, c.file, GrowthStrategy::PgSpGcfa, eps);
      expectFieldInvariants(grid, f, eps);
    }
  }
}

TEST(GrowthFieldModels, FertilityMissesAtMostThePapersCount) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  // Up axis: the one whose lowest voxel layer (the footprint on the platform) is largest, i.e.
  // the flat stable base; printed below (+X: the statue's base). Longest side 84 mm gives the
  // paper's ~77k voxels at 0.8 mm with the conservative voxelisation.
  PlaceOptions pl;
  pl.fitMm = 84;
  UpAxis best = UpAxis::PosZ;
  size_t bestFoot = 0;
  const char* names[] = {"+z", "-z", "+y", "-y", "+x", "-x"};
  for (UpAxis up : {UpAxis::PosZ, UpAxis::NegZ, UpAxis::PosY, UpAxis::NegY, UpAxis::PosX, UpAxis::NegX}) {
    pl.up = up;
    const VoxelGrid g = voxelGrid(test::loadPlaced("nestedcages_fertility.off", pl), 0.8);
    size_t foot = 0;
    for (size_t c = 0; c < g.cellCount(); ++c) foot += g.state[c] == uint8_t(VoxelState::Platform);
    std::printf("[ model ] fertility up %s: footprint %zu cells\n", names[int(up)], foot);
    if (foot > bestFoot) {
      bestFoot = foot;
      best = up;
    }
  }
  pl.up = best;
  const VoxelGrid grid = voxelGrid(test::loadPlaced("nestedcages_fertility.off", pl), 0.8);
  std::printf("[ model ] fertility: up %s, grid %dx%dx%d, %zu voxels\n", names[int(best)],
              grid.dims.x(), grid.dims.y(), grid.dims.z(), countPrintable(grid));
  for (GrowthStrategy s : strategiesToRun()) {
    const GrowthField f = runCase(grid, "fertility", s);
    expectFieldInvariants(grid, f, GrowthOptions().epsilon);
    if (s == GrowthStrategy::PgSpGcfa) {
      EXPECT_LE(f.missed, 511u) << "paper: 511 of 77,064";
    }
  }
  {
    // The incremental (Dijkstra-ordered) scheme on the same grid.
    GrowthOptions o;
    o.shadowScheme = ShadowScheme::Incremental;
    const GrowthField f = growField(grid, o);
    std::printf("[ model ] fertility  pg-sp-gcfa incremental: missed %zu, layers %d, shadow %.0f ms, "
                "total %.0f ms, hull builds %zu\n", f.missed, f.layers, f.shadowMs, f.totalMs,
                f.hullBuilds);
    expectFieldInvariants(grid, f, o.epsilon);
    EXPECT_LE(f.missed, 511u);
  }
  // Fig. 14c loop for the greedy scheme: support columns under missed voxels, grow again.
  VoxelGrid g = grid;
  GrowthField f = runCase(g, "fertility", GrowthStrategy::Gcfa);
  for (int round = 1; round <= 3 && f.missed > 0; ++round) {
    std::vector<uint8_t> missed(g.cellCount(), 0);
    for (size_t c = 0; c < g.cellCount(); ++c) missed[c] = f.g[c] < 0;
    const size_t added = addSupportColumns(g, missed);
    f = runCase(g, "fertility+supports", GrowthStrategy::Gcfa);
    std::printf("[ model ] support round %d: %zu support cells, gcfa missed %zu\n", round, added,
                f.missed);
    expectFieldInvariants(g, f, GrowthOptions().epsilon);
  }
}

}  // namespace
}  // namespace omnislice
