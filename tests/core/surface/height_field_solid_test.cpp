// SPDX-License-Identifier: MIT
#include "surface/height_field_solid.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <map>

#include "../test_meshes.h"
#include "../test_support.h"
#include "geometry/aabb_tree.h"
#include "isoplanar/surface_samples.h"
#include "mesh/prepare_mesh.h"

namespace omnislice {
namespace {

// The solid passes the project's own solid checks without any repair.
void expectValidSolid(const HeightFieldSolid& r) {
  ASSERT_TRUE(r.ok()) << r.message;
  PrepareOptions opt;
  const PrepareMeshResult p = prepareMesh(r.solid, opt);
  ASSERT_TRUE(p.ok()) << p.message;
  EXPECT_TRUE(p.solid.ok()) << p.solid.message;
  EXPECT_TRUE(p.info.closed);
  EXPECT_TRUE(p.info.manifold);
  EXPECT_TRUE(p.info.oriented);
  EXPECT_EQ(p.info.shells, 1u);
  EXPECT_EQ(p.info.selfIntersections, 0u);
  EXPECT_TRUE(p.info.repairs.empty()) << p.info.repairs.front();  // already outward, welded
  EXPECT_GT(test::meshVolume(r.solid), 0);                         // outward as built
  EXPECT_NEAR(p.info.volumeMm3, test::meshVolume(r.solid), 1e-6 * p.info.volumeMm3);
}

TEST(HeightFieldSolid, SaddleVolumeAndSolidChecks) {
  const double R = 100, half = 37.5, c = 20;
  const Mesh top = test::translated(makeSaddleSurface(R, half, 10000), {0, 0, c});
  const HeightFieldSolid r = heightFieldSolid(top);
  expectValidSolid(r);
  // Integral of c + (x^2 - y^2)/R over the square: the quadratic terms cancel.
  const double exact = 4 * half * half * c;
  EXPECT_NEAR(test::meshVolume(r.solid), exact, 1e-9 * exact);
  double lowest = 1e9;
  for (size_t i = 0; i < top.vertexCount(); ++i) lowest = std::min(lowest, top.vertex(i).z());
  EXPECT_EQ(r.minTopZ, lowest);
  EXPECT_NEAR(r.minTopZ, c - half * half / R, 0.01);
  EXPECT_EQ(r.top.triangles, top.triangles);
  EXPECT_EQ(r.solid.faceCount(), 2 * top.faceCount() + 2 * 4 * (100 - 1));
}

TEST(HeightFieldSolid, BowlVolumeWithinMeshError) {
  // z = c + (x^2 + y^2)/R: integral 4 h^2 c + 8 h^4 / (3R); the linear interpolant over a grid of
  // spacing d overestimates each square term by d^2/6 per unit area.
  const double R = 60, h = 30, c = 5;
  Mesh m = makeSaddleSurface(R, h, 2500);
  for (size_t i = 0; i < m.vertexCount(); ++i) {
    const double x = m.positions[3 * i], y = m.positions[3 * i + 1];
    m.positions[3 * i + 2] = c + (x * x + y * y) / R;
  }
  const HeightFieldSolid r = heightFieldSolid(m);
  expectValidSolid(r);
  const double exact = 4 * h * h * c + 8 * std::pow(h, 4) / (3 * R);
  const double d = 2 * h / 49;
  const double interpolation = 2 * (4 * h * h) * d * d / (6 * R);
  EXPECT_NEAR(test::meshVolume(r.solid), exact + interpolation, 1e-6 * exact);
}

TEST(HeightFieldSolid, SeatSolidAndOffsetTop) {
  const Mesh seat = test::translated(makeSeatSurface(110, 6000), {0, 0, 25});
  const HeightFieldSolid r = heightFieldSolid(seat);
  expectValidSolid(r);
  const double offset = 0.4;
  const HeightFieldSolid o = heightFieldSolid(seat, offset);
  expectValidSolid(o);
  EXPECT_LT(test::meshVolume(o.solid), test::meshVolume(r.solid));
  // Every offset top vertex lies `offset` from the surface; the interior ones below it (inside
  // the first solid: boundary vertices move sideways out of its walls on the sloping sides).
  std::vector<char> boundary(seat.vertexCount(), 0);
  {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t f = 0; f < seat.faceCount(); ++f)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = seat.triangles[3 * f + k], b = seat.triangles[3 * f + (k + 1) % 3];
        ++edges[{std::min(a, b), std::max(a, b)}];
      }
    for (const auto& [e, n] : edges)
      if (n == 1) boundary[e.first] = boundary[e.second] = 1;
  }
  const AabbTree tree(seat);
  const AabbTree solidTree(r.solid);
  double worst = 0;
  ASSERT_EQ(o.top.vertexCount(), seat.vertexCount());
  for (size_t v = 0; v < o.top.vertexCount(); ++v) {
    const Eigen::Vector3d p = o.top.vertex(v);
    worst = std::max(worst, std::fabs(tree.closest(p).distance - offset));
    if (!boundary[v]) {
      EXPECT_TRUE(solidTree.inside(p + Eigen::Vector3d(1e-7, 2e-7, 0))) << v;
    }
    EXPECT_NEAR((p - seat.vertex(v)).norm(), offset, 1e-12);
    EXPECT_LT(p.z(), seat.vertex(v).z());
  }
  EXPECT_LT(worst, 0.01 * offset);
  std::printf("seat offset %.2f: worst |distance - offset| %.2e mm\n", offset, worst);
}

TEST(HeightFieldSolid, DownFacingSurfaceIsFlipped) {
  const Mesh m = test::flipped(test::translated(makeSaddleSurface(100, 20, 900), {0, 0, 10}));
  const HeightFieldSolid r = heightFieldSolid(m);
  expectValidSolid(r);
  EXPECT_NEAR(test::meshVolume(r.solid), 4 * 20 * 20 * 10, 1e-6);
  const Eigen::Vector3d a = r.top.vertex(r.top.triangles[0]), b = r.top.vertex(r.top.triangles[1]),
                        c = r.top.vertex(r.top.triangles[2]);
  EXPECT_GT((b - a).cross(c - a).z(), 0);
}

TEST(HeightFieldSolid, AnnulusWithHole) {
  // A grid with the middle quads removed: two boundary loops (outer CCW, inner CW).
  Mesh m = test::translated(makeSaddleSurface(100, 20, 441), {0, 0, 10});  // 21 x 21
  Mesh cut = m;
  cut.triangles.clear();
  for (size_t f = 0; f < m.faceCount(); ++f) {
    Eigen::Vector3d c = (m.vertex(m.triangles[3 * f]) + m.vertex(m.triangles[3 * f + 1]) +
                         m.vertex(m.triangles[3 * f + 2])) / 3;
    if (std::fabs(c.x()) < 6 && std::fabs(c.y()) < 6) continue;
    cut.triangles.insert(cut.triangles.end(), m.triangles.begin() + 3 * f, m.triangles.begin() + 3 * f + 3);
  }
  const HeightFieldSolid r = heightFieldSolid(cut);
  expectValidSolid(r);
  EXPECT_LT(r.solid.vertexCount(), 2 * m.vertexCount());  // unused hole vertices dropped
}

TEST(HeightFieldSolid, Refusals) {
  const Mesh good = test::translated(makeSaddleSurface(100, 10, 121), {0, 0, 5});
  EXPECT_EQ(heightFieldSolid(Mesh{}).status, Status::EmptyInput);
  Mesh nan = good;
  nan.positions[7] = NAN;
  EXPECT_EQ(heightFieldSolid(nan).status, Status::NonFiniteVertex);
  EXPECT_EQ(heightFieldSolid(good, -1).status, Status::InvalidOption);
  EXPECT_EQ(heightFieldSolid(good, INFINITY).status, Status::InvalidOption);
  // Vertices at or below the platform (also after the offset).
  EXPECT_EQ(heightFieldSolid(makeSaddleSurface(100, 10, 121)).status, Status::DegenerateInput);
  const double lowest = 5 - 1.0;  // z of the lowest vertex
  EXPECT_TRUE(heightFieldSolid(good, 0.5 * lowest).ok());
  EXPECT_EQ(heightFieldSolid(good, 1.5 * lowest).status, Status::DegenerateInput);
  // Closed surface: a tetrahedron.
  Mesh tet;
  tet.positions = {0, 0, 1, 1, 0, 1, 0, 1, 1, 0, 0, 2};
  tet.triangles = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3};
  const HeightFieldSolid closed = heightFieldSolid(tet);
  EXPECT_EQ(closed.status, Status::DegenerateInput);
  EXPECT_NE(closed.message.find("closed"), std::string::npos);
  // Edge shared by three triangles.
  Mesh fin;
  fin.positions = {0, 0, 1, 1, 0, 1, 0.5, 1, 1, 0.5, -1, 1, 0.5, 0.2, 2};
  fin.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  EXPECT_EQ(heightFieldSolid(fin).status, Status::NonManifoldInput);
  // Inconsistent orientation.
  Mesh flipped;
  flipped.positions = {0, 0, 1, 1, 0, 1, 0.5, 1, 1, 0.5, -1, 1};
  flipped.triangles = {0, 1, 2, 0, 1, 3};
  EXPECT_EQ(heightFieldSolid(flipped).status, Status::NonManifoldInput);
  // A fold: a strip that turns back over itself (the folded part faces down).
  Mesh fold;
  fold.positions = {0, 0, 1, 2, 0, 1, 2, 1, 1, 0, 1, 1, 1, 0, 2, 1, 1, 2};
  fold.triangles = {0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2};
  const HeightFieldSolid folded = heightFieldSolid(fold);
  EXPECT_EQ(folded.status, Status::DegenerateInput);
  EXPECT_NE(folded.message.find("fold"), std::string::npos);
  // Two stacked sheets, both facing up: covered twice.
  const Mesh stacked = test::append(good, test::translated(makeSaddleSurface(100, 5, 36), {0, 0, 20}));
  const HeightFieldSolid twice = heightFieldSolid(stacked);
  EXPECT_EQ(twice.status, Status::DegenerateInput);
  EXPECT_NE(twice.message.find("2 times"), std::string::npos) << twice.message;
  // Two sheets whose outlines cross (both up): the boundaries intersect seen from above.
  const Mesh crossing = test::append(good, test::translated(makeSaddleSurface(100, 5, 36), {10, 0, 20}));
  EXPECT_EQ(heightFieldSolid(crossing).status, Status::DegenerateInput);
  // Steep faces below minNormalZ are refused, accepted with a lower limit.
  Mesh steep;
  steep.positions = {0, 0, 1, 1, 0, 1, 0, 0.1, 5};
  steep.triangles = {0, 1, 2};
  EXPECT_EQ(heightFieldSolid(steep, 0, 0.2).status, Status::DegenerateInput);
  EXPECT_TRUE(heightFieldSolid(steep, 0, 0.01).ok());
  // Out-of-range index.
  Mesh bad = good;
  bad.triangles[5] = 100000;
  EXPECT_EQ(heightFieldSolid(bad).status, Status::DegenerateInput);
}

}  // namespace
}  // namespace omnislice
