// SPDX-License-Identifier: MIT
// uniteOverlappingShells and prepareMesh's uniteShells: overlapping boxes against the lattice
// union of the same boxes (an independent construction), overlapping icospheres against a
// point-sampled volume and the "no vertex inside the other" property, and what must be left alone
// (disjoint shells, cavities).
#include "cgal/shell_union.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <random>

#include "mesh/prepare_mesh.h"
#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

PrepareMeshResult prepareUnited(const Mesh& m) {
  PrepareOptions o;
  o.closeSolid = true;
  o.uniteShells = true;
  return prepareMesh(m, o);
}

PrepareMeshResult prepareOnly(const Mesh& m) {
  PrepareOptions o;
  o.checkSelfIntersections = false;
  return prepareMesh(m, o);
}

// Random boxes with real coordinates (so no two touch along an edge only), two to four of them,
// many overlapping: the united solid has the volume, the area and the shell count of the lattice
// surface of the same boxes.
TEST(ShellUnion, OverlappingBoxesMatchTheLatticeUnion) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> corner(0, 14), size(3, 10);
  std::uniform_int_distribution<int> count(2, 4);
  int united = 0;
  for (int trial = 0; trial < 30; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    std::vector<test::Box> boxes;
    Mesh soup;
    for (int b = count(rng); b > 0; --b) {
      const double x = corner(rng), y = corner(rng), z = corner(rng);
      const test::Box box{x, y, z, x + size(rng), y + size(rng), z + size(rng)};
      boxes.push_back(box);
      soup = test::append(soup, test::makeBox(box.x0, box.y0, box.z0, box.x1, box.y1, box.z1));
    }
    const PrepareMeshResult lattice = prepareOnly(test::makeBoxUnion(boxes));
    const PrepareMeshResult r = prepareUnited(soup);
    ASSERT_TRUE(r.ok() && r.solid.ok()) << r.solid.message;
    EXPECT_TRUE(r.info.closed && r.info.manifold && r.info.oriented);
    EXPECT_NEAR(r.info.volumeMm3, lattice.info.volumeMm3, 1e-6 * lattice.info.volumeMm3);
    EXPECT_NEAR(r.info.areaMm2, lattice.info.areaMm2, 1e-6 * lattice.info.areaMm2);
    EXPECT_EQ(r.info.shells, lattice.info.shells);
    EXPECT_EQ(r.info.selfIntersections, 0u);
    if (r.info.shellsUnited > 0) {
      ++united;
      EXPECT_EQ(r.info.shells + r.info.shellsUnited - r.info.shellUnions, boxes.size());
      // The surface removed is what the boxes had beyond the union's.
      double boxesArea = 0;
      for (const test::Box& b : boxes) {
        boxesArea += 2 * ((b.x1 - b.x0) * (b.y1 - b.y0) + (b.y1 - b.y0) * (b.z1 - b.z0) +
                          (b.z1 - b.z0) * (b.x1 - b.x0));
      }
      EXPECT_NEAR(r.info.unitedInnerAreaMm2, boxesArea - lattice.info.areaMm2, 1e-6 * boxesArea);
      EXPECT_TRUE(nlohmann::json::parse(meshInfoJson(r.info)).contains("shells_united"));
    } else {
      EXPECT_EQ(r.info.shells, boxes.size());  // nothing overlapped
    }
  }
  EXPECT_GE(united, 15);  // the draw makes most trials overlap
}

// A box inside another, with the same orientation: the union is the outer box.
TEST(ShellUnion, NestedShellOfTheSameOrientationIsAbsorbed) {
  const Mesh m = test::append(test::makeBox(0, 0, 0, 20, 20, 20), test::makeBox(5, 5, 5, 10, 10, 10));
  const PrepareMeshResult r = prepareUnited(m);
  ASSERT_TRUE(r.ok() && r.solid.ok());
  EXPECT_EQ(r.info.shells, 1u);
  EXPECT_NEAR(r.info.volumeMm3, 8000, 1e-9);
  EXPECT_NEAR(r.info.areaMm2, 2400, 1e-9);
  EXPECT_EQ(r.info.shellsUnited, 2u);
}

// A cavity (an inward box inside a box) and a separate box: nothing is united, the mesh is kept.
TEST(ShellUnion, CavitiesAndDisjointShellsAreLeftAlone) {
  const Mesh m = test::append(test::append(test::makeBox(0, 0, 0, 20, 20, 20),
                                           test::flipped(test::makeBox(5, 5, 5, 10, 10, 10))),
                              test::makeBox(30, 0, 0, 40, 10, 10));
  const ShellUnionResult u = uniteOverlappingShells(m);
  ASSERT_TRUE(u.ok());
  EXPECT_EQ(u.shellsIn, 2u);  // the outward ones
  EXPECT_EQ(u.groups, 0u);
  EXPECT_EQ(u.mesh.triangles, m.triangles);
  EXPECT_EQ(u.mesh.positions, m.positions);
  const PrepareMeshResult r = prepareUnited(m);
  ASSERT_TRUE(r.ok() && r.solid.ok());
  EXPECT_EQ(r.info.shells, 3u);
  EXPECT_NEAR(r.info.volumeMm3, 8000 - 125 + 1000, 1e-9);
  EXPECT_EQ(r.info.shellsUnited, 0u);
}

// Whether p lies inside the convex polyhedron m (every face plane has p behind it, by margin).
bool insideConvex(const Mesh& m, const Eigen::Vector3d& p, double margin) {
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d a = m.vertex(m.triangles[3 * f]), b = m.vertex(m.triangles[3 * f + 1]),
                          c = m.vertex(m.triangles[3 * f + 2]);
    if ((b - a).cross(c - a).normalized().dot(p - a) > -margin) return false;
  }
  return true;
}

// Two overlapping icospheres (crossings at inexact points): closed, one shell, the volume of a
// point sample of the union, and no vertex of the result strictly inside either sphere.
TEST(ShellUnion, OverlappingSpheresKeepTheUnionVolumeAndNoInnerSurface) {
  const Mesh a = test::makeIcosphere(10, 3), b = test::makeIcosphere(8, 3, {9, 3, 2});
  const PrepareMeshResult r = prepareUnited(test::append(a, b));
  ASSERT_TRUE(r.ok() && r.solid.ok()) << r.solid.message;
  EXPECT_TRUE(r.info.closed && r.info.manifold);
  EXPECT_EQ(r.info.shells, 1u);
  EXPECT_EQ(r.info.shellsUnited, 2u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-10, 17), y(-10, 11), z(-10, 10);
  const double boxVolume = 27.0 * 21 * 20;
  const int samples = 200000;
  int in = 0;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector3d p(x(rng), y(rng), z(rng));
    in += insideConvex(a, p, 0) || insideConvex(b, p, 0);
  }
  const double sampled = boxVolume * in / samples;  // standard error about 0.3 %
  EXPECT_NEAR(r.info.volumeMm3, sampled, 0.015 * sampled);
  for (size_t v = 0; v < r.mesh.vertexCount(); ++v) {
    const Eigen::Vector3d p = r.mesh.vertex(v);
    EXPECT_FALSE(insideConvex(a, p, 1e-6) || insideConvex(b, p, 1e-6)) << "vertex " << v;
  }
}

}  // namespace
}  // namespace omnislice
