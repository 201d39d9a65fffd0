// SPDX-License-Identifier: MIT
#include "slice/slice_mesh.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "../test_meshes.h"
#include "../test_support.h"
#include "slice_test_support.h"

namespace omnislice {
namespace {

using test::layerArea;
using test::makeBox;
using test::makeBipyramid;
using test::makeUvSphere;
using test::makeTorus;
using test::meshVolume;
using test::slicedVolume;

// Every contour closed (>= 3 points, first != last), outer contours CCW, holes CW, no open chain,
// and the printed height within h/2 of the part's extent.
void expectWellFormed(const SliceResult& r, const Mesh& mesh, double h, const std::string& what) {
  ASSERT_TRUE(r.ok()) << what << ": " << r.message;
  EXPECT_EQ(r.openChains, 0u) << what;
  double lo = 1e300, hi = -1e300;
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    const double t = mesh.vertex(v).dot(r.frame.d);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  EXPECT_NEAR(r.minHeight, lo, 1e-9) << what;
  ASSERT_FALSE(r.layers.empty());
  EXPECT_LE(std::abs(r.layers.back().top - (hi - lo)), 0.5 * h + 1e-9) << what;
  for (size_t i = 0; i < r.layers.size(); ++i) {
    const SliceLayer& layer = r.layers[i];
    EXPECT_NEAR(layer.sliceHeight, 0.5 * (layer.bottom + layer.top), 1e-12);
    if (i > 0) {
      EXPECT_NEAR(layer.bottom, r.layers[i - 1].top, 1e-12);
    }
    for (const ExPolygon2& island : layer.islands) {
      ASSERT_GE(island.contour.size(), 3u) << what << " layer " << i;
      EXPECT_NE(island.contour.front(), island.contour.back()) << what << " layer " << i;
      EXPECT_GT(polygonArea(island.contour), 0) << what << " layer " << i;
      for (const Polygon2& hole : island.holes) {
        ASSERT_GE(hole.size(), 3u);
        EXPECT_NE(hole.front(), hole.back());
        EXPECT_LT(polygonArea(hole), 0) << what << " layer " << i;
      }
    }
  }
}

TEST(SliceMesh, FrameIsRightHandedOrthonormal) {
  const SliceFrame z = makeSliceFrame({0, 0, 5});
  EXPECT_TRUE(z.e1.isApprox(Eigen::Vector3d::UnitX()));
  EXPECT_TRUE(z.e2.isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(z.d.isApprox(Eigen::Vector3d::UnitZ()));
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 1),
                                     Eigen::Vector3d(0, -1, 0.3), Eigen::Vector3d(0, 0, -1),
                                     Eigen::Vector3d(0.2, 3, -0.5)}) {
    const SliceFrame f = makeSliceFrame(dir);
    EXPECT_NEAR(f.d.norm(), 1, 1e-12);
    EXPECT_TRUE(f.d.isApprox(dir.normalized()));
    EXPECT_NEAR(f.e1.norm(), 1, 1e-12);
    EXPECT_NEAR(f.e2.norm(), 1, 1e-12);
    EXPECT_NEAR(f.e1.dot(f.d), 0, 1e-12);
    EXPECT_NEAR(f.e2.dot(f.d), 0, 1e-12);
    EXPECT_TRUE(f.e1.cross(f.e2).isApprox(f.d)) << dir.transpose();
    // toPart inverts the projection used for layer coordinates.
    const Eigen::Vector3d p(3, -2, 7);
    const Eigen::Vector2d q((p - f.origin).dot(f.e1), (p - f.origin).dot(f.e2));
    EXPECT_TRUE(f.toPart(q, (p - f.origin).dot(f.d)).isApprox(p));
  }
}

TEST(SliceMesh, PolygonAndIslandArea) {
  const Polygon2 square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  EXPECT_DOUBLE_EQ(polygonArea(square), 4);
  Polygon2 hole = {{0.5, 0.5}, {0.5, 1.5}, {1.5, 1.5}, {1.5, 0.5}};
  EXPECT_DOUBLE_EQ(polygonArea(hole), -1);
  EXPECT_DOUBLE_EQ(islandArea(ExPolygon2{square, {hole}}), 3);
}

// baseHeight lines a mesh's layers up with another's (supports with their part): layer i keeps
// its heights from the given base, what lies below the base is not sliced, a mesh wholly below
// gives no layers; maxLayers caps the count.
TEST(SliceMesh, BaseHeightAndMaxLayers) {
  const Mesh box = makeBox(0, 0, 2, 4, 4, 3);  // z in [2, 3]
  SliceOptions o;
  o.layerHeight = 0.2;
  o.baseHeight = 1.0;
  const SliceResult r = sliceMesh(box, o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_DOUBLE_EQ(r.minHeight, 1.0);
  ASSERT_EQ(r.layers.size(), 10u);  // planes at 1.1 ... 2.9
  for (size_t i = 0; i < r.layers.size(); ++i) {
    EXPECT_NEAR(r.layers[i].sliceHeight, 0.1 + 0.2 * double(i), 1e-12);
    const double plane = 1.0 + r.layers[i].sliceHeight;
    EXPECT_EQ(r.layers[i].islands.size(), plane > 2 && plane < 3 ? 1u : 0u) << i;
  }
  o.baseHeight = 2.5;  // the lower half is not sliced
  const SliceResult half = sliceMesh(box, o);
  ASSERT_TRUE(half.ok());
  ASSERT_EQ(half.layers.size(), 2u);
  EXPECT_NEAR(islandArea(half.layers[0].islands[0]), 16, 1e-9);
  o.baseHeight = 3.5;
  const SliceResult none = sliceMesh(box, o);
  ASSERT_TRUE(none.ok());
  EXPECT_TRUE(none.layers.empty());
  o.baseHeight = 1.0;
  o.maxLayers = 3;
  EXPECT_EQ(sliceMesh(box, o).layers.size(), 3u);
  o.baseHeight = std::numeric_limits<double>::infinity();
  EXPECT_EQ(sliceMesh(box, o).status, Status::InvalidOption);
}

TEST(SliceMesh, BoxAlongZLayerCountAndSections) {
  const Mesh box = makeBox(-10, -5, 0, 10, 5, 10);
  SliceOptions o;
  o.layerHeight = 0.2;
  const SliceResult r = sliceMesh(box, o);
  expectWellFormed(r, box, 0.2, "box +Z");
  ASSERT_EQ(r.layers.size(), 50u);
  for (const SliceLayer& layer : r.layers) {
    ASSERT_EQ(layer.islands.size(), 1u);
    EXPECT_EQ(layer.islands[0].holes.size(), 0u);
    EXPECT_EQ(layer.islands[0].contour.size(), 4u);  // collinear points removed
    EXPECT_NEAR(layerArea(layer), 200, 1e-6);
  }
  EXPECT_NEAR(slicedVolume(r), 2000, 1e-4);
}

TEST(SliceMesh, LayerCountRuleKeepsHeightWithinHalfLayer) {
  // Brief formula: ceil((H - first)/h) + 1 layers, dropping a last layer the part fills less than
  // half of (its cutting plane would be above the part).
  struct Case { double height, first, h; size_t layers; };
  for (const Case c : {Case{10.05, 0, 0.2, 50}, Case{10.15, 0, 0.2, 51}, Case{10.02, 0.3, 0.2, 50},
                       Case{1.0, 0.35, 0.25, 4}, Case{0.15, 0.2, 0.2, 1}}) {
    const Mesh box = makeBox(0, 0, 3, 5, 5, 3 + c.height);
    SliceOptions o;
    o.layerHeight = c.h;
    o.firstLayerHeight = c.first;
    const SliceResult r = sliceMesh(box, o);
    expectWellFormed(r, box, c.h, "height " + std::to_string(c.height));
    EXPECT_EQ(r.layers.size(), c.layers) << "height " << c.height;
    const double first = c.first > 0 ? c.first : c.h;
    EXPECT_DOUBLE_EQ(r.layers[0].top, first);
    for (const SliceLayer& layer : r.layers) EXPECT_NEAR(layerArea(layer), 25, 1e-6);
  }
}

TEST(SliceMesh, SphereVolumeAlongSeveralDirections) {
  const Mesh sphere = makeUvSphere(10, 96, 48, {3, -2, 12});
  const double volume = meshVolume(sphere);
  ASSERT_GT(volume, 0);
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0),
                                     Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0, -1, 0.3)}) {
    SliceOptions o;
    o.direction = dir;
    o.layerHeight = 0.2;
    const SliceResult r = sliceMesh(sphere, o);
    expectWellFormed(r, sphere, 0.2, "sphere");
    EXPECT_NEAR(r.layers.size(), 100, 1) << dir.transpose();
    // Mid-point rule over the layers: error O(h^2) plus the caps within h/2.
    EXPECT_NEAR(slicedVolume(r), volume, 0.005 * volume) << dir.transpose();
    for (const SliceLayer& layer : r.layers) {
      EXPECT_EQ(layer.islands.size(), 1u);
      for (const ExPolygon2& island : layer.islands) EXPECT_TRUE(island.holes.empty());
    }
  }
}

TEST(SliceMesh, TorusIslandsAndHoles) {
  // Torus around Z: R = 10, r = 3, centre z = 5.
  const Mesh torus = makeTorus(10, 3, 96, 48, {0, 0, 5});
  const double volume = meshVolume(torus);
  SliceOptions o;
  o.layerHeight = 0.2;
  // Along +Z (across the hole): middle layers are one ring = one island with one hole.
  const SliceResult rz = sliceMesh(torus, o);
  expectWellFormed(rz, torus, 0.2, "torus +Z");
  EXPECT_EQ(rz.layers.size(), 30u);
  for (size_t i = 3; i + 3 < rz.layers.size(); ++i) {
    ASSERT_EQ(rz.layers[i].islands.size(), 1u) << "layer " << i;
    EXPECT_EQ(rz.layers[i].islands[0].holes.size(), 1u) << "layer " << i;
  }
  EXPECT_NEAR(slicedVolume(rz), volume, 0.01 * volume);
  // Along +X: the planes near x = 0 cut the tube twice (two discs), the planes at |x| > 7 once.
  o.direction = {1, 0, 0};
  const SliceResult rx = sliceMesh(torus, o);
  expectWellFormed(rx, torus, 0.2, "torus +X");
  EXPECT_NEAR(slicedVolume(rx), volume, 0.01 * volume);
  for (const SliceLayer& layer : rx.layers) {
    const double x = rx.minHeight + layer.sliceHeight;
    for (const ExPolygon2& island : layer.islands) EXPECT_TRUE(island.holes.empty());
    if (std::abs(x) < 6.5) {
      EXPECT_EQ(layer.islands.size(), 2u) << "x = " << x;
    }
    if (std::abs(x) > 7.5) {
      EXPECT_EQ(layer.islands.size(), 1u) << "x = " << x;
    }
  }
  // Along a tilted direction the volume still matches.
  o.direction = {0, -1, 0.3};
  const SliceResult rt = sliceMesh(torus, o);
  expectWellFormed(rt, torus, 0.2, "torus tilted");
  EXPECT_NEAR(slicedVolume(rt), volume, 0.01 * volume);
}

TEST(SliceMesh, TiltedCubeSectionsMatchAnalyticArea) {
  // Cube [0,a]^3 cut by planes x + y + z = s: area = sqrt(3)/2 (s^2 - 3 (s-a)+^2 + 3 (s-2a)+^2).
  const double a = 10;
  const Mesh cube = makeBox(0, 0, 0, a, a, a);
  SliceOptions o;
  o.direction = {1, 1, 1};
  o.layerHeight = 0.2;
  const SliceResult r = sliceMesh(cube, o);
  expectWellFormed(r, cube, 0.2, "cube (1,1,1)");
  EXPECT_NEAR(r.minHeight, 0, 1e-12);
  auto pos2 = [](double v) { return v > 0 ? v * v : 0.0; };
  for (const SliceLayer& layer : r.layers) {
    const double s = std::sqrt(3.0) * (r.minHeight + layer.sliceHeight);
    const double expected = std::sqrt(3.0) / 2 * (s * s - 3 * pos2(s - a) + 3 * pos2(s - 2 * a));
    EXPECT_NEAR(layerArea(layer), expected, 2e-4) << "s = " << s;  // 10 nm integer grid
  }
  // A long box tilted by theta about X: planes crossing only the side faces cut area A / cos(theta).
  const Mesh column = makeBox(-5, -5, 0, 5, 5, 100);
  const Eigen::Vector3d d = Eigen::Vector3d(0, 0.3, 1).normalized();
  o.direction = d;
  const SliceResult rc = sliceMesh(column, o);
  expectWellFormed(rc, column, 0.2, "column tilted");
  size_t checked = 0;
  for (const SliceLayer& layer : rc.layers) {
    const double t = rc.minHeight + layer.sliceHeight;
    // Side-only cuts: the plane's z range over the square |y| <= 5 stays inside [0, 100].
    const double zLo = (t - 5 * std::abs(d.y())) / d.z(), zHi = (t + 5 * std::abs(d.y())) / d.z();
    if (zLo < 0 || zHi > 100) continue;
    EXPECT_NEAR(layerArea(layer), 100 / d.z(), 2e-4);  // 10 nm integer grid
    ++checked;
  }
  EXPECT_GT(checked, 400u);
}

TEST(SliceMesh, DegenerateVerticesOnCuttingPlane) {
  // Bipyramid whose equator vertices lie exactly on layer 4's plane (h = 0.25: planes at
  // 0.125 + 0.25 k, all exact binary fractions). A vertex on the plane counts as above, so the
  // lower faces' edges end exactly at the equator: the section is the equator square itself.
  const Mesh bip = makeBipyramid(2, 0, 1.125, 2);
  SliceOptions o;
  o.layerHeight = 0.25;
  const SliceResult r = sliceMesh(bip, o);
  expectWellFormed(r, bip, 0.25, "bipyramid");
  ASSERT_EQ(r.layers.size(), 8u);
  ASSERT_DOUBLE_EQ(r.layers[4].sliceHeight, 1.125);
  ASSERT_EQ(r.layers[4].islands.size(), 1u);
  EXPECT_NEAR(layerArea(r.layers[4]), 16, 1e-9);
  EXPECT_EQ(r.layers[4].islands[0].contour.size(), 4u);
  // Apex vertices (heights 0 and 2) are never on a plane here; neighbours shrink linearly.
  EXPECT_NEAR(layerArea(r.layers[3]), 16 * std::pow(0.875 / 1.125, 2), 2e-4);  // 10 nm grid
  EXPECT_NEAR(layerArea(r.layers[5]), 16 * std::pow(0.625 / 0.875, 2), 2e-4);
}

TEST(SliceMesh, DegenerateFaceLyingInCuttingPlane) {
  // L-shaped prism (profile in XZ, extruded 0..1 along Y): a 2-wide foot up to z = 1.125, a 1-wide
  // column above. The step face lies exactly in layer 4's plane (z = 1.125): its vertices count as
  // above, so the face itself produces no segment and the plane acts as if lowered by an
  // infinitesimal: the section is the foot's (area 2), one clean rectangle, no sliver, no overlap.
  const Mesh l = test::makePrismXZ({{1, 1.125}, {1, 2}, {0, 2}, {0, 0}, {2, 0}, {2, 1.125}}, 0, 1);
  ASSERT_NEAR(meshVolume(l), 2 * 1.125 + 0.875, 1e-12);
  SliceOptions o;
  o.layerHeight = 0.25;
  const SliceResult r = sliceMesh(l, o);
  expectWellFormed(r, l, 0.25, "L prism");
  ASSERT_EQ(r.layers.size(), 8u);
  for (size_t i = 0; i < r.layers.size(); ++i) {
    ASSERT_EQ(r.layers[i].islands.size(), 1u) << "layer " << i;
    EXPECT_NEAR(layerArea(r.layers[i]), i <= 4 ? 2.0 : 1.0, 1e-9) << "layer " << i;
  }
  // A box whose top face lies in a would-be layer plane (2.125): the part fills only half of that
  // layer, so the layer is dropped (layer-count rule) and no layer is empty.
  const Mesh box = makeBox(0, 0, 0, 1, 1, 2.125);
  const SliceResult rb = sliceMesh(box, o);
  expectWellFormed(rb, box, 0.25, "box top on plane");
  EXPECT_EQ(rb.layers.size(), 8u);
  for (const SliceLayer& layer : rb.layers) EXPECT_NEAR(layerArea(layer), 1, 1e-9);
}

TEST(SliceMesh, DegenerateEmptySlices) {
  // Empty slice above the part: a would-be last layer whose plane is at or above the top (so it
  // would cut nothing or only the top face's limit) is not emitted: no empty layer above the part.
  const Mesh box = makeBox(0, 0, 0, 4, 4, 2.125);
  SliceOptions o;
  o.layerHeight = 0.25;
  const SliceResult r = sliceMesh(box, o);
  ASSERT_TRUE(r.ok());
  for (const SliceLayer& layer : r.layers) EXPECT_FALSE(layer.islands.empty());
  // Two shells with a gap: the layers in the gap are empty, the others hold one island.
  const Mesh two = test::append(makeBox(0, 0, 0, 4, 4, 1), makeBox(0, 0, 2, 4, 4, 3));
  const SliceResult r2 = sliceMesh(two, o);
  expectWellFormed(r2, two, 0.25, "two boxes");
  ASSERT_EQ(r2.layers.size(), 12u);
  for (size_t i = 0; i < r2.layers.size(); ++i) {
    EXPECT_EQ(r2.layers[i].islands.size(), (i >= 4 && i < 8) ? 0u : 1u) << "layer " << i;
  }
}

TEST(SliceMesh, PartThinnerThanHalfFirstLayer) {
  // A 0.08 mm plate with a 0.2 mm first layer: the mid-layer plane (0.1) is above the part, so the
  // only layer is cut at half the part's height instead of being dropped or left empty.
  const Mesh plate = makeBox(0, 0, 0, 5, 4, 0.08);
  const SliceResult r = sliceMesh(plate, SliceOptions{});
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.layers.size(), 1u);
  EXPECT_NEAR(r.layers[0].sliceHeight, 0.04, 1e-12);
  EXPECT_NEAR(layerArea(r.layers[0]), 20, 1e-6);
}

TEST(SliceMesh, OverlappingShellsAreUnited) {
  // Two overlapping boxes (non-zero union): one island of the union's area.
  const Mesh two = test::append(makeBox(0, 0, 0, 4, 4, 2), makeBox(2, 2, 0, 6, 6, 2));
  const SliceResult r = sliceMesh(two, SliceOptions{});
  expectWellFormed(r, two, 0.2, "overlap");
  for (const SliceLayer& layer : r.layers) {
    ASSERT_EQ(layer.islands.size(), 1u);
    EXPECT_NEAR(layerArea(layer), 28, 1e-6);
  }
}

TEST(SliceMesh, ManyOverlappingShellsFormIslandsWithHoles) {
  // A support-like soup past the direct island-tree union (over 64 loops a layer): 164 unit
  // boxes overlapping by half along the four sides of a 21 x 21 square frame. One island, the
  // frame minus its 19 x 19 hole (area 80), and a second island of 30 overlapping boxes inside
  // the hole, a 15.5 x 1 strip: areas from the union, not from the loop count.
  Mesh soup;
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.5 * k;
    soup = test::append(soup, makeBox(t, 0, 0, t + 1, 1, 1));
    soup = test::append(soup, makeBox(t, 20, 0, t + 1, 21, 1));
    soup = test::append(soup, makeBox(0, t, 0, 1, t + 1, 1));
    soup = test::append(soup, makeBox(20, t, 0, 21, t + 1, 1));
  }
  for (int k = 0; k < 30; ++k) soup = test::append(soup, makeBox(3 + 0.5 * k, 10, 0, 4 + 0.5 * k, 11, 1));
  SliceOptions o;
  o.layerHeight = 0.25;
  const SliceResult r = sliceMesh(soup, o);
  expectWellFormed(r, soup, 0.25, "frame soup");
  for (const SliceLayer& layer : r.layers) {
    ASSERT_EQ(layer.islands.size(), 2u);
    size_t holes = 0;
    for (const ExPolygon2& ex : layer.islands) holes += ex.holes.size();
    EXPECT_EQ(holes, 1u);
    EXPECT_NEAR(layerArea(layer), 21.0 * 21.0 - 19.0 * 19.0 + 15.5, 1e-6);
  }
}

TEST(SliceMesh, InsideOutMeshGivesTheSameRegions) {
  // Non-zero union: with every face flipped, loops reverse (outer CW, holes CCW) yet the winding
  // is still non-zero exactly inside the solid, so islands and holes are unchanged.
  Mesh torus = makeTorus(10, 3, 48, 24, {0, 0, 5});
  const SliceResult a = sliceMesh(torus, SliceOptions{});
  torus = test::flipped(torus);
  const SliceResult b = sliceMesh(torus, SliceOptions{});
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a.layers.size(), b.layers.size());
  for (size_t i = 0; i < a.layers.size(); ++i) {
    ASSERT_EQ(a.layers[i].islands.size(), b.layers[i].islands.size());
    EXPECT_NEAR(layerArea(a.layers[i]), layerArea(b.layers[i]), 1e-9);
    for (const ExPolygon2& island : b.layers[i].islands) EXPECT_GT(polygonArea(island.contour), 0);
  }
}

TEST(SliceMesh, ClosingRadiusBridgesTinyGaps) {
  // Two boxes 0.02 mm apart: two islands; closing with 0.05 mm merges them.
  const Mesh two = test::append(makeBox(0, 0, 0, 4, 4, 1), makeBox(4.02, 0, 0, 8, 4, 1));
  SliceOptions o;
  EXPECT_EQ(sliceMesh(two, o).layers[2].islands.size(), 2u);
  o.closingRadius = 0.05;
  const SliceResult r = sliceMesh(two, o);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.layers[2].islands.size(), 1u);
}

TEST(SliceMesh, StatusForBadInput) {
  // EmptyInput: no triangles; and a flat mesh (zero extent along d).
  EXPECT_EQ(sliceMesh(Mesh{}, SliceOptions{}).status, Status::EmptyInput);
  Mesh flat;
  flat.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  flat.triangles = {0, 1, 2};
  EXPECT_EQ(sliceMesh(flat, SliceOptions{}).status, Status::EmptyInput);
  // InvalidOption: zero / NaN direction, non-positive layer height, bad index.
  const Mesh box = makeBox(0, 0, 0, 1, 1, 1);
  SliceOptions o;
  o.direction = {0, 0, 0};
  EXPECT_EQ(sliceMesh(box, o).status, Status::InvalidOption);
  o.direction = {NAN, 0, 1};
  EXPECT_EQ(sliceMesh(box, o).status, Status::InvalidOption);
  o = SliceOptions{};
  o.layerHeight = 0;
  EXPECT_EQ(sliceMesh(box, o).status, Status::InvalidOption);
  o.layerHeight = 1e-9;  // 1e9 layers
  EXPECT_EQ(sliceMesh(box, o).status, Status::InvalidOption);
  Mesh bad = box;
  bad.triangles[5] = 99;
  EXPECT_EQ(sliceMesh(bad, SliceOptions{}).status, Status::InvalidOption);
  // NonFiniteVertex.
  Mesh nan = box;
  nan.positions[4] = NAN;
  EXPECT_EQ(sliceMesh(nan, SliceOptions{}).status, Status::NonFiniteVertex);
  // Cancelled: the callback says stop.
  int calls = 0;
  const SliceResult c = sliceMesh(box, SliceOptions{}, [&](const char* stage, double) {
    EXPECT_STREQ(stage, "slice");
    return ++calls < 2;
  });
  EXPECT_EQ(c.status, Status::Cancelled);
}

TEST(SliceMesh, OpenMeshReportsOpenChains) {
  Mesh open = makeBox(0, 0, 0, 2, 2, 2);
  open.triangles.resize(open.triangles.size() - 6);  // drop the -X... last side (two faces)
  const SliceResult r = sliceMesh(open, SliceOptions{});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.openChains, r.layers.size());  // one broken chain per layer
}


// Real models from ../shared/models, read and prepared as the pipeline does: every loop closes
// and the sliced volume is within 1 % of the divergence-theorem volume, along +Z and tilted
// directions. Kitten (genus 1), Stanford bunny, and a branching lattice with 17 handles.
TEST(SliceMesh, RealModelsAlongSeveralDirections) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  struct Model { const char* file; double scale; };
  for (const Model& model : {Model{"compas_bunny_closed_low_res.obj", 0.5}, Model{"pymdp_kitten.off", 1.0},
                             Model{"compas_branches_16_closed_mid_res.stl", 0.5}}) {
    const Mesh mesh = test::loadModel(model.file, model.scale);
    ASSERT_GT(mesh.faceCount(), 1000u) << model.file;
    const double volume = meshVolume(mesh);
    ASSERT_GT(volume, 0) << model.file;
    for (const Eigen::Vector3d& dir : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0.5),
                                       Eigen::Vector3d(0, -1, 0.3), Eigen::Vector3d(1, 1, 1)}) {
      SliceOptions o;
      o.direction = dir;
      o.layerHeight = 0.2;
      const SliceResult r = sliceMesh(mesh, o);
      expectWellFormed(r, mesh, 0.2, model.file);
      EXPECT_NEAR(slicedVolume(r), volume, 0.01 * volume) << model.file << " along " << dir.transpose();
    }
  }
}

}  // namespace
}  // namespace omnislice
