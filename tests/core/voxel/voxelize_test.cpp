// SPDX-License-Identifier: MIT
// Conservative voxelisation (paper 001 Section 4.1): H subset of H~ on generated and real solids,
// tightness, exact cell counts of axis-aligned boxes against an analytic count, a sphere sandwiched
// between analytic balls, the platform footprint/disc, support columns and bad input.
#include "voxel/voxelize.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "../test_meshes.h"
#include "../test_support.h"
#include "geometry/aabb_tree.h"
#include "mesh/place_mesh.h"

namespace omnislice {
namespace {

using Eigen::Vector3d;

const uint8_t kSolid = static_cast<uint8_t>(VoxelState::Solid);
const uint8_t kPlatform = static_cast<uint8_t>(VoxelState::Platform);
const uint8_t kSupport = static_cast<uint8_t>(VoxelState::Support);

size_t countState(const VoxelGrid& g, uint8_t s) {
  return static_cast<size_t>(std::count(g.state.begin(), g.state.end(), s));
}

// True when p lies in the closed cube of some Solid cell (points on a cell boundary may belong to
// either side).
bool inSolidCell(const VoxelGrid& g, const Vector3d& p) {
  const Vector3d u = (p - g.origin) / g.width;
  int lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    const double f = std::floor(u[d]);
    lo[d] = hi[d] = static_cast<int>(f);
    if (u[d] - f < 1e-7) lo[d] -= 1;
    if (f + 1 - u[d] < 1e-7) hi[d] += 1;
  }
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i)
        if (g.inRange(i, j, k) && g.at(i, j, k) == VoxelState::Solid) return true;
  return false;
}

// Grid invariants every result must satisfy: margin of >= 2 empty cells, no Solid below the
// platform plane, platform only in layer platformK, platform layer spans z in [-w, 0].
void expectGridInvariants(const VoxelizeResult& r, int margin) {
  const VoxelGrid& g = r.grid;
  ASSERT_EQ(g.state.size(), size_t(g.dims.x()) * g.dims.y() * g.dims.z());
  EXPECT_NEAR(g.origin.z() + g.width * g.platformK, -g.width, 1e-12 * (1 + std::abs(g.origin.z())));
  EXPECT_EQ(countState(g, kSolid), r.solidCount);
  EXPECT_EQ(countState(g, kPlatform), r.platformCount);
  for (int k = 0; k < g.dims.z(); ++k)
    for (int j = 0; j < g.dims.y(); ++j)
      for (int i = 0; i < g.dims.x(); ++i) {
        const VoxelState s = g.at(i, j, k);
        if (s == VoxelState::Empty) continue;
        ASSERT_TRUE(i >= margin && j >= margin && k >= margin && i < g.dims.x() - margin &&
                    j < g.dims.y() - margin && k < g.dims.z() - margin)
            << "non-empty cell in the margin at " << i << " " << j << " " << k;
        if (s == VoxelState::Platform) {
          ASSERT_EQ(k, g.platformK);
        }
        if (s == VoxelState::Solid) {
          ASSERT_GT(k, g.platformK);
        }
      }
}

// Platform = exactly the cells below the Solid cells of the lowest part layer (no disc).
void expectFootprintPlatform(const VoxelGrid& g) {
  int kFoot = -1;
  for (int k = g.platformK + 1; k < g.dims.z() && kFoot < 0; ++k)
    for (int j = 0; j < g.dims.y() && kFoot < 0; ++j)
      for (int i = 0; i < g.dims.x(); ++i)
        if (g.at(i, j, k) == VoxelState::Solid) {
          kFoot = k;
          break;
        }
  ASSERT_GT(kFoot, g.platformK);
  for (int j = 0; j < g.dims.y(); ++j)
    for (int i = 0; i < g.dims.x(); ++i)
      ASSERT_EQ(g.at(i, j, g.platformK) == VoxelState::Platform, g.at(i, j, kFoot) == VoxelState::Solid)
          << "platform cell " << i << " " << j;
}

struct Samples {
  std::vector<Vector3d> inside, surface;
};

// Random points inside the solid (rejection sampling in the bbox, tested by winding number) and on
// its surface (random barycentric points of random faces, plus every vertex).
Samples samplePoints(const Mesh& m, size_t insideCount, size_t surfaceCount, uint32_t seed) {
  Samples s;
  const AabbTree tree(m);
  const BoundingBox bb = boundingBox(m);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  for (size_t tries = 0; s.inside.size() < insideCount && tries < 200 * insideCount; ++tries) {
    const Vector3d p = bb.min + (bb.max - bb.min).cwiseProduct(Vector3d(u01(rng), u01(rng), u01(rng)));
    if (tree.inside(p)) s.inside.push_back(p);
  }
  std::uniform_int_distribution<size_t> face(0, m.faceCount() - 1);
  for (size_t n = 0; n < surfaceCount; ++n) {
    const size_t f = face(rng);
    double a = u01(rng), b = u01(rng);
    if (a + b > 1) {
      a = 1 - a;
      b = 1 - b;
    }
    const Vector3d p = m.vertex(m.triangles[3 * f]), q = m.vertex(m.triangles[3 * f + 1]),
                   r = m.vertex(m.triangles[3 * f + 2]);
    s.surface.push_back(p + a * (q - p) + b * (r - p));
  }
  for (size_t v = 0; v < m.vertexCount(); ++v) s.surface.push_back(m.vertex(v));
  return s;
}

// The full property check: H subset of H~ (samples), tightness (each Solid cell has its centre
// inside or the surface within half a cell diagonal), volume band, grid invariants, footprint.
void checkConservative(const Mesh& m, double w, size_t insideSamples, uint32_t seed) {
  VoxelizeOptions o;
  o.width = w;
  const auto t0 = std::chrono::steady_clock::now();
  const VoxelizeResult r = voxelizeSolid(m, o);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.ok()) << r.message;
  const VoxelGrid& g = r.grid;
  expectGridInvariants(r, o.margin);
  expectFootprintPlatform(g);

  const Samples s = samplePoints(m, insideSamples, 4 * insideSamples, seed);
  ASSERT_GT(s.inside.size(), insideSamples / 2);
  size_t missInside = 0, missSurface = 0;
  for (const Vector3d& p : s.inside) missInside += !inSolidCell(g, p);
  for (const Vector3d& p : s.surface) missSurface += !inSolidCell(g, p);
  EXPECT_EQ(missInside, 0u) << "inside samples outside every Solid cell";
  EXPECT_EQ(missSurface, 0u) << "surface samples outside every Solid cell";

  const AabbTree tree(m);
  const double halfDiagonal = 0.5 * std::sqrt(3.0) * w;
  // At most ~150k Solid cells are checked (a fixed stride), so big grids stay quick.
  const size_t stride = std::max<size_t>(1, r.solidCount / 150000);
  size_t loose = 0, seen = 0;
  for (size_t q = 0; q < g.cellCount(); ++q) {
    if (g.state[q] != kSolid || seen++ % stride != 0) continue;
    const Eigen::Vector3i c = g.cell(q);
    const Vector3d centre = g.center(c.x(), c.y(), c.z());
    if (tree.inside(centre)) continue;
    if (!(tree.closest(centre).distance <= halfDiagonal * (1 + 1e-9))) ++loose;
  }
  EXPECT_EQ(loose, 0u) << "Solid cells neither inside nor within half a diagonal of the surface";

  const double volume = test::meshVolume(m), area = test::surfaceArea(m);
  const double voxelVolume = double(r.solidCount) * w * w * w;
  EXPECT_GE(voxelVolume, volume) << "H~ must contain H";
  // The extra volume per unit area over a plane of normal n is about w (|nx| + |ny| + |nz|) / 2
  // (the cells the plane cuts are included whole): w / 2 for an axis-aligned face, at most
  // sqrt(3) w / 2, on average 3/4 w over all directions. Curvature moves it a little (convex up,
  // concave down), so (V~ - V) / (A w) must stay below 0.95.
  EXPECT_LE(voxelVolume, volume + 0.95 * area * w);
  std::printf("  w %.3f: %zu solid cells (grid %d x %d x %d), voxel volume / mesh volume %.4f, "
              "(V~ - V) / (A w) %.3f, %.1f ms\n",
              w, r.solidCount, g.dims.x(), g.dims.y(), g.dims.z(), voxelVolume / volume,
              (voxelVolume - volume) / (area * w), ms);
}

// Number of lattice cells (pitch w) whose open interval meets [a, b], a < b.
int cellsTouched(double a, double b, double w) {
  return static_cast<int>(std::ceil(b / w) - std::floor(a / w));
}

// ---- axis-aligned boxes: exact counts -----------------------------------------------------------

// Decision: a cell is Solid when its open cube meets the open solid, so a box whose faces lie on
// cell boundaries gives exactly the cells it covers (neighbours sharing only a face, edge or
// corner hold no material and are not Solid).
TEST(Voxelize, AlignedBoxGivesExactlyItsCells) {
  const double w = 0.5;  // power of two: box faces at multiples of w are exact cell boundaries
  const VoxelizeResult r = voxelizeSolid(test::makeBox(0, 0, 0, 2.0, 1.5, 1.0), {w});
  ASSERT_TRUE(r.ok()) << r.message;
  expectGridInvariants(r, 2);
  EXPECT_EQ(r.solidCount, 4u * 3u * 2u);
  EXPECT_EQ(r.platformCount, 4u * 3u);
  expectFootprintPlatform(r.grid);
  // The Solid cells are exactly those with centres inside the box.
  const VoxelGrid& g = r.grid;
  for (size_t q = 0; q < g.cellCount(); ++q) {
    const Eigen::Vector3i c = g.cell(q);
    const Vector3d p = g.center(c.x(), c.y(), c.z());
    const bool inBox = p.x() > 0 && p.x() < 2 && p.y() > 0 && p.y() < 1.5 && p.z() > 0 && p.z() < 1;
    ASSERT_EQ(g.state[q] == kSolid, inBox) << c.transpose();
  }
  // Margin: exactly two empty cells around, one platform layer, so the grid is 8 x 7 x 7.
  EXPECT_EQ(g.dims, Eigen::Vector3i(4 + 4, 3 + 4, 2 + 1 + 4));
}

// The same box moved by half a cell in x and y, and its top in the middle of a cell layer: every
// partially covered cell counts, (4 + 1) x (3 + 1) x 3.
TEST(Voxelize, HalfCellOffsetBoxGivesEveryTouchedCell) {
  const double w = 0.5;
  const VoxelizeResult r = voxelizeSolid(test::makeBox(0.25, 0.25, 0, 2.25, 1.75, 1.25), {w});
  ASSERT_TRUE(r.ok()) << r.message;
  expectGridInvariants(r, 2);
  EXPECT_EQ(r.solidCount, 5u * 4u * 3u);
  EXPECT_EQ(r.platformCount, 5u * 4u);
  expectFootprintPlatform(r.grid);
}

// Random boxes (faces at random positions, w not a power of two): the count equals the analytic
// number of lattice cells whose open interval meets each side.
TEST(Voxelize, RandomBoxesMatchAnalyticCount) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-20, 20), size(0.05, 9), width(0.13, 1.7);
  for (int n = 0; n < 200; ++n) {
    const double w = width(rng);
    const double x0 = pos(rng), y0 = pos(rng), sx = size(rng), sy = size(rng), sz = size(rng);
    const VoxelizeResult r = voxelizeSolid(test::makeBox(x0, y0, 0, x0 + sx, y0 + sy, sz), {w});
    ASSERT_TRUE(r.ok()) << r.message;
    const int nx = cellsTouched(x0, x0 + sx, w), ny = cellsTouched(y0, y0 + sy, w),
              nz = cellsTouched(0, sz, w);
    ASSERT_EQ(r.solidCount, size_t(nx) * ny * nz) << "box " << n << " w " << w;
    ASSERT_EQ(r.platformCount, size_t(nx) * ny);
  }
}

// ---- sphere: sandwiched between analytic balls ----------------------------------------------

// For an inscribed polyhedral sphere (icosphere), every cell whose cube comes closer than the
// inradius to the centre must be Solid, and no Solid cell's cube may be farther than the radius.
TEST(Voxelize, IcosphereBetweenInscribedAndCircumscribedBalls) {
  const double radius = 6;
  const Mesh raw = test::makeIcosphere(radius, 3, Vector3d(0.37, -0.21, 0));
  const Mesh m = test::onPlatform(raw);
  const Vector3d c0(0.37, -0.21, -boundingBox(raw).min.z());  // the centre after placing
  double inradius = radius;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Vector3d p = m.vertex(m.triangles[3 * f]), q = m.vertex(m.triangles[3 * f + 1]),
                   r = m.vertex(m.triangles[3 * f + 2]);
    const Vector3d n = (q - p).cross(r - p).normalized();
    inradius = std::min(inradius, std::abs(n.dot(p - c0)));
  }
  for (double w : {0.7, 0.31}) {
    SCOPED_TRACE(w);
    const VoxelizeResult r = voxelizeSolid(m, {w});
    ASSERT_TRUE(r.ok()) << r.message;
    const VoxelGrid& g = r.grid;
    size_t mustBeSolid = 0, tooFar = 0, missing = 0;
    for (size_t q = 0; q < g.cellCount(); ++q) {
      const Eigen::Vector3i c = g.cell(q);
      if (c.z() <= g.platformK) continue;
      const Vector3d lo = g.origin + w * c.cast<double>(), hi = lo + Vector3d::Constant(w);
      const double d = (c0.cwiseMax(lo).cwiseMin(hi) - c0).norm();  // centre to closed cube
      if (d < inradius - 1e-9) {
        ++mustBeSolid;
        missing += g.state[q] != kSolid;
      }
      if (g.state[q] == kSolid && !(d < radius + 1e-9)) ++tooFar;
    }
    EXPECT_GT(mustBeSolid, 100u);
    EXPECT_EQ(missing, 0u);
    EXPECT_EQ(tooFar, 0u);
  }
  checkConservative(m, 0.45, 3000, 11);
}

TEST(Voxelize, TorusAndRotatedBoxAreConservativeAndTight) {
  {
    SCOPED_TRACE("torus");
    checkConservative(test::onPlatform(test::makeTorus(10, 3.3, 48, 24)), 0.6, 3000, 3);
  }
  {
    SCOPED_TRACE("rotated box");
    Mesh box = test::makeBox(-4, -3, -2, 4, 3, 2);
    const Eigen::Matrix3d rot = (Eigen::AngleAxisd(0.4, Vector3d(1, 2, 3).normalized())).toRotationMatrix();
    for (size_t v = 0; v < box.vertexCount(); ++v) {
      const Vector3d p = rot * box.vertex(v);
      for (int d = 0; d < 3; ++d) box.positions[3 * v + d] = p[d];
    }
    checkConservative(test::onPlatform(box), 0.37, 3000, 5);
  }
}

// Large slanted triangles (a CAD-like rotated cube: 12 faces, each spanning ~100 cells per side):
// conservative voxels (the time is printed: a triangle/box test per cell of their bounding boxes
// would show in `npm run bench`'s voxelize stage, where speed is measured).
TEST(Voxelize, LargeSlantedTriangles) {
  Mesh box = test::makeBox(-15, -15, -15, 15, 15, 15);
  const Eigen::Matrix3d rot = (Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized())).toRotationMatrix();
  for (size_t v = 0; v < box.vertexCount(); ++v) {
    const Vector3d p = rot * box.vertex(v);
    for (int d = 0; d < 3; ++d) box.positions[3 * v + d] = p[d];
  }
  const Mesh m = test::onPlatform(box);
  const auto t0 = std::chrono::steady_clock::now();
  const VoxelizeResult r = voxelizeSolid(m, {0.25});
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.ok()) << r.message;
  std::printf("rotated 30 mm cube at w 0.25: %zu solid cells of %zu, %.0f ms\n", r.solidCount, r.grid.cellCount(), ms);
  checkConservative(m, 0.25, 2000, 23);
}

// Inside-ness uses the non-zero winding rule, and the triangle test does not care about order:
// an inward-oriented copy with shuffled faces gives the same grid.
TEST(Voxelize, IndependentOfOrientationAndFaceOrder) {
  const Mesh m = test::onPlatform(test::makeTorus(10, 3.3, 48, 24));
  Mesh flipped = m;
  const size_t nf = m.faceCount();
  std::vector<size_t> order(nf);
  for (size_t f = 0; f < nf; ++f) order[f] = f;
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  for (size_t f = 0; f < nf; ++f) {
    const size_t g = order[f];
    flipped.triangles[3 * f] = m.triangles[3 * g];
    flipped.triangles[3 * f + 1] = m.triangles[3 * g + 2];
    flipped.triangles[3 * f + 2] = m.triangles[3 * g + 1];
  }
  ASSERT_LT(test::meshVolume(flipped), 0);
  const VoxelizeResult a = voxelizeSolid(m, {0.41}), b = voxelizeSolid(flipped, {0.41});
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_GT(a.solidCount, 1000u);
  EXPECT_EQ(a.grid.dims, b.grid.dims);
  EXPECT_EQ(a.grid.origin, b.grid.origin);
  EXPECT_TRUE(a.grid.state == b.grid.state);
}

// ---- platform --------------------------------------------------------------------------------

TEST(Voxelize, PlatformDiscAroundFootprintCentre) {
  const double w = 0.5;
  VoxelizeOptions o;
  o.width = w;
  o.platformRadius = 10;
  const VoxelizeResult r = voxelizeSolid(test::makeBox(0.25, 0.25, 0, 2.25, 1.75, 1.25), o);
  ASSERT_TRUE(r.ok()) << r.message;
  expectGridInvariants(r, 2);
  const VoxelGrid& g = r.grid;
  // Footprint cells x in [0, 2.5], y in [0, 2]: centre (1.25, 1.0).
  const Vector3d c(1.25, 1.0, 0);
  size_t expected = 0;
  for (int j = 0; j < g.dims.y(); ++j)
    for (int i = 0; i < g.dims.x(); ++i) {
      const Vector3d p = g.center(i, j, g.platformK);
      const bool inDisc = std::hypot(p.x() - c.x(), p.y() - c.y()) <= 10;
      const bool underFoot = g.at(i, j, g.platformK + 1) == VoxelState::Solid;
      expected += inDisc || underFoot;
      ASSERT_EQ(g.at(i, j, g.platformK) == VoxelState::Platform, inDisc || underFoot);
    }
  EXPECT_EQ(r.platformCount, expected);
  EXPECT_NEAR(double(r.platformCount) * w * w, 3.14159265 * 100, 0.05 * 314);
}

// ---- support columns -------------------------------------------------------------------------

TEST(Voxelize, SupportColumnsEndOnSolidOrPlatform) {
  // An overhanging T: a pillar [0,1]^2 x [0,4] and a slab [-3,4] x [-3,4] x [4,5].
  Mesh m = test::append(test::makeBox(0, 0, 0, 1, 1, 4.0), test::makeBox(-3, -3, 4.0, 4, 4, 5));
  const double w = 0.5;
  VoxelizeResult r = voxelizeSolid(m, {w});
  ASSERT_TRUE(r.ok()) << r.message;
  VoxelGrid g = r.grid;
  const VoxelGrid before = g;
  // Mark the slab's lowest layer as missed, plus one pillar cell (already supported by cells below).
  std::vector<uint8_t> missed(g.cellCount(), 0);
  const int kSlab = g.platformK + 1 + 8;  // z in [4, 4.5]
  size_t slabCells = 0, pillarColumns = 0;
  for (int j = 0; j < g.dims.y(); ++j)
    for (int i = 0; i < g.dims.x(); ++i)
      if (g.at(i, j, kSlab) == VoxelState::Solid) {
        missed[g.index(i, j, kSlab)] = 1;
        ++slabCells;
        pillarColumns += g.at(i, j, kSlab - 1) == VoxelState::Solid;
      }
  ASSERT_EQ(slabCells, 14u * 14u);
  ASSERT_EQ(pillarColumns, 4u);
  const size_t added = addSupportColumns(g, missed);
  // Every column outside the pillar: 8 support cells (z 0..4) plus one new platform cell.
  EXPECT_EQ(added, (slabCells - pillarColumns) * 8);
  EXPECT_EQ(countState(g, kSupport), added);
  EXPECT_EQ(countState(g, kPlatform), countState(before, kPlatform) + slabCells - pillarColumns);
  for (size_t q = 0; q < g.cellCount(); ++q) {
    if (g.state[q] != kSupport) continue;
    ASSERT_EQ(before.state[q], 0) << "support replaced a non-empty cell";
    // Walking down from a support cell stays in support until Solid or Platform.
    const Eigen::Vector3i c = g.cell(q);
    int k = c.z();
    while (g.at(c.x(), c.y(), k) == VoxelState::Support) --k;
    const VoxelState end = g.at(c.x(), c.y(), k);
    ASSERT_TRUE(end == VoxelState::Solid || end == VoxelState::Platform);
    // ... and up from it to a missed cell.
    k = c.z();
    while (g.at(c.x(), c.y(), k) == VoxelState::Support) ++k;
    ASSERT_TRUE(missed[g.index(c.x(), c.y(), k)]);
  }
  // Idempotent: a second call adds nothing.
  EXPECT_EQ(addSupportColumns(g, missed), 0u);
  // Wrong-sized mask: nothing happens.
  EXPECT_EQ(addSupportColumns(g, std::vector<uint8_t>(3, 1)), 0u);
}

// ---- bad input ------------------------------------------------------------------------------

TEST(Voxelize, BadInputReturnsStatus) {
  const Mesh box = test::makeBox(0, 0, 0, 10, 10, 10);
  EXPECT_EQ(voxelizeSolid(Mesh{}, {}).status, Status::EmptyInput);
  VoxelizeOptions o;
  o.width = std::nan("");
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  o.width = std::numeric_limits<double>::infinity();
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  o.width = -1;
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  o.width = 0;
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  // Absurdly small width: refused before allocating, the message names the cell count.
  o.width = 1e-5;
  const VoxelizeResult tiny = voxelizeSolid(box, o);
  EXPECT_EQ(tiny.status, Status::InvalidOption);
  EXPECT_NE(tiny.message.find("cells"), std::string::npos) << tiny.message;
  EXPECT_NE(tiny.message.find("1000"), std::string::npos) << tiny.message;
  o.width = 1e-300;
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  // A small maxCells refuses a normal grid.
  o = {};
  o.width = 1;
  o.maxCells = 100;
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  // Absurdly large width: one cell holds the whole box (still conservative).
  o = {};
  o.width = 1e6;
  const VoxelizeResult huge = voxelizeSolid(box, o);
  ASSERT_TRUE(huge.ok()) << huge.message;
  EXPECT_EQ(huge.solidCount, 1u);
  o = {};
  o.margin = 1;
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  o = {};
  o.platformRadius = -2;
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  o.platformRadius = std::nan("");
  EXPECT_EQ(voxelizeSolid(box, o).status, Status::InvalidOption);
  // A platform disc far larger than the part: refused by the cell count of the final grid.
  o.platformRadius = 1e5;
  const VoxelizeResult disc = voxelizeSolid(box, o);
  EXPECT_EQ(disc.status, Status::InvalidOption);
  EXPECT_NE(disc.message.find("maxCells"), std::string::npos) << disc.message;
  Mesh bad = box;
  bad.positions[4] = std::nan("");
  EXPECT_EQ(voxelizeSolid(bad, {}).status, Status::NonFiniteVertex);
  bad = box;
  bad.triangles[5] = 99;
  EXPECT_EQ(voxelizeSolid(bad, {}).status, Status::ParseError);
  // Not placed: below the platform.
  EXPECT_EQ(voxelizeSolid(test::makeBox(0, 0, -1, 1, 1, 1), {}).status, Status::InvalidOption);
  // Far from the origin relative to the width.
  EXPECT_EQ(voxelizeSolid(test::makeBox(1e12, 0, 0, 1e12 + 1, 1, 1), {}).status, Status::InvalidOption);
  // A flat (zero-volume) mesh lying on the platform.
  Mesh flat;
  flat.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  flat.triangles = {0, 1, 2, 0, 2, 1};
  EXPECT_EQ(voxelizeSolid(flat, {}).status, Status::DegenerateInput);
}

TEST(Voxelize, ProgressAndCancellation) {
  const Mesh m = test::onPlatform(test::makeTorus(10, 3, 64, 32));
  double last = -1;
  bool monotone = true;
  const VoxelizeResult ok = voxelizeSolid(m, {0.2}, [&](const char* stage, double f) {
    if (std::string(stage) != "voxelize") monotone = false;
    if (f < last) monotone = false;
    last = f;
    return true;
  });
  ASSERT_TRUE(ok.ok());
  EXPECT_TRUE(monotone);
  EXPECT_EQ(last, 1.0);
  int calls = 0;
  const VoxelizeResult cancelled = voxelizeSolid(m, {0.2}, [&](const char*, double) { return ++calls < 3; });
  EXPECT_EQ(cancelled.status, Status::Cancelled);
  EXPECT_TRUE(cancelled.grid.state.empty());
}

// ---- real models -----------------------------------------------------------------------------

TEST(VoxelizeModels, BunnyKittenFertilityAreConservative) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  struct Case {
    const char* file;
    UpAxis up;
    double fitMm;
    double width;
  };
  const Case cases[] = {
      {"compas_bunny_closed_low_res.obj", UpAxis::PosZ, 0, 0.8},
      {"compas_bunny_closed_high_res.stl", UpAxis::PosZ, 0, 0.8},
      {"pymdp_kitten.off", UpAxis::PosY, 0, 0.8},
      {"nestedcages_fertility.off", UpAxis::PosZ, 120, 0.8},
      {"nestedcages_fertility.off", UpAxis::PosZ, 86, 0.8},  // ~ the paper's 77k voxels (Fig. 14)
      {"compas_bunny_closed_low_res.obj", UpAxis::PosZ, 60, 0.32},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    std::printf("%s (fit %g):\n", c.file, c.fitMm);
    const Mesh m = test::loadPlaced(c.file, c.up, c.fitMm);
    checkConservative(m, c.width, 4000, 17);
  }
}

// A ~540k-Solid-voxel grid of the full-resolution Bunny (the paper's Fig. 3 size); the time is
// printed (speed: `npm run bench`, the 540k-voxel Bunny).
TEST(VoxelizeModels, FiveHundredFortyThousandVoxels) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh m = test::loadPlaced("compas_bunny_closed_high_res.stl", UpAxis::PosZ, 0);
  const double w = std::cbrt(test::meshVolume(m) / 540000.0);
  VoxelizeOptions o;
  o.width = w;
  const auto t0 = std::chrono::steady_clock::now();
  const VoxelizeResult r = voxelizeSolid(m, o);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.ok()) << r.message;
  std::printf("bunny high-res (69,598 faces), w %.3f mm: %zu solid cells, %zu grid cells, %.0f ms\n", w,
              r.solidCount, r.grid.cellCount(), ms);
  EXPECT_GT(r.solidCount, 500000u);
  EXPECT_LT(r.solidCount, 700000u);
}

}  // namespace
}  // namespace omnislice
