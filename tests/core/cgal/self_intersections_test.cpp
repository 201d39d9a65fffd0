// SPDX-License-Identifier: MIT
// findSelfIntersections against an independent O(n^2) plain-double test, and its adjacency rules.
#include "cgal/self_intersections.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <functional>
#include <random>
#include <set>

#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

using Pair = std::pair<uint32_t, uint32_t>;

double orient(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
              const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a);
}

// Point where segment pq crosses the plane of triangle abc and lies inside it, for segments not in
// that plane (generic positions). Returns false when there is none.
bool segmentHitsTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, const Eigen::Vector3d& c, Eigen::Vector3d& hit) {
  const double dp = orient(a, b, c, p), dq = orient(a, b, c, q);
  if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0) || dp == dq) return false;
  hit = p + (q - p) * (dp / (dp - dq));
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double s1 = (b - a).cross(hit - a).dot(n);
  const double s2 = (c - b).cross(hit - b).dot(n);
  const double s3 = (a - c).cross(hit - c).dot(n);
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

// Two triangles (not coplanar) intersect iff an edge of one meets the other. Points that are a
// shared vertex, and edges both contain, do not count: adjacency is not intersection.
std::set<Pair> bruteForcePairs(const Mesh& m) {
  std::set<Pair> out;
  for (uint32_t f = 0; f < m.faceCount(); ++f) {
    for (uint32_t g = f + 1; g < m.faceCount(); ++g) {
      const uint32_t* tf = &m.triangles[3 * f];
      const uint32_t* tg = &m.triangles[3 * g];
      std::vector<Eigen::Vector3d> shared;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          if (tf[i] == tg[j]) shared.push_back(m.vertex(tf[i]));
        }
      }
      bool found = false;
      for (int side = 0; side < 2 && !found; ++side) {
        const uint32_t* e = side ? tg : tf;
        const uint32_t* t = side ? tf : tg;
        for (int k = 0; k < 3 && !found; ++k) {
          // An edge both faces contain lies in both planes: it only shows adjacency (and its
          // rounding-level plane distances would fake a crossing).
          const bool sharedEdge = std::count(t, t + 3, e[k]) && std::count(t, t + 3, e[(k + 1) % 3]);
          if (sharedEdge) continue;
          Eigen::Vector3d hit;
          if (!segmentHitsTriangle(m.vertex(e[k]), m.vertex(e[(k + 1) % 3]), m.vertex(t[0]), m.vertex(t[1]),
                                   m.vertex(t[2]), hit)) {
            continue;
          }
          bool atShared = false;
          for (const auto& s : shared) atShared |= (hit - s).norm() < 1e-9;
          found = !atShared;
        }
      }
      if (found) out.insert({f, g});
    }
  }
  return out;
}

// A small mesh in generic position with many crossings and many adjacent pairs: two welded
// icospheres that overlap and a tilted box through both.
Mesh tangle() {
  Mesh m = test::append(test::makeIcosphere(10, 2), test::makeIcosphere(7, 2, {12.3, 1.7, -0.9}));
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.37, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(1.11, Eigen::Vector3d(0.2, 1, 0.3).normalized()))
                                .toRotationMatrix();
  return test::append(m, test::transformed(test::makeBox(-3, -2.5, -14, 4.1, 3.3, 16), R,
                                           Eigen::Vector3d(5.2, 0.4, 0.3)));
}

TEST(SelfIntersections, MatchesBruteForce) {
  const Mesh m = tangle();
  ASSERT_EQ(m.faceCount(), 652u);
  const std::set<Pair> expected = bruteForcePairs(m);
  ASSERT_GT(expected.size(), 20u);
  SelfIntersectionOptions o;
  o.cap = 0;
  const SelfIntersectionResult r = findSelfIntersections(m, o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_FALSE(r.capped);
  EXPECT_EQ(r.count, expected.size());
  const std::set<Pair> got(r.pairs.begin(), r.pairs.end());
  for (const Pair& p : expected) EXPECT_TRUE(got.count(p)) << "missing " << p.first << "," << p.second;
  for (const Pair& p : got) EXPECT_TRUE(expected.count(p)) << "extra " << p.first << "," << p.second;
  // Each shell alone is clean: adjacent faces are not reported.
  EXPECT_EQ(findSelfIntersections(test::makeIcosphere(10, 3), o).count, 0u);
  EXPECT_EQ(findSelfIntersections(test::makeBox(0, 0, 0, 1, 1, 1), o).count, 0u);
  EXPECT_EQ(findSelfIntersections(test::makeTorus(10, 3, 40, 20), o).count, 0u);
}

// Faces sharing an edge intersect only when folded flat onto each other.
TEST(SelfIntersections, FoldedEdgeNeighbours) {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0.3, 1, 0, 0.6, 0.8, 0, 0.5, -1, 0, 0.4, 0.7, 0.5};
  m.triangles = {0, 1, 2,   // reference face
                 1, 0, 3};  // same plane, same side of edge 0-1: folded onto it
  SelfIntersectionResult r = findSelfIntersections(m, {});
  EXPECT_EQ(r.count, 1u);
  m.triangles = {0, 1, 2, 1, 0, 4};  // same plane, other side: a flat neighbour
  EXPECT_EQ(findSelfIntersections(m, {}).count, 0u);
  m.triangles = {0, 1, 2, 1, 0, 5};  // out of plane: a hinge
  EXPECT_EQ(findSelfIntersections(m, {}).count, 0u);
}

// Faces sharing a vertex intersect when one pierces the other away from it.
TEST(SelfIntersections, VertexNeighbours) {
  Mesh m;
  m.positions = {0, 0, 0, 2, 0, 0, 0, 2, 0,     // face in z = 0 at the origin
                 0.5, 0.5, -1, 0.6, 0.4, 1,     // pierces it
                 -1, -1, -1, -1, -2, 1};        // stays outside
  m.triangles = {0, 1, 2, 0, 3, 4};
  EXPECT_EQ(findSelfIntersections(m, {}).count, 1u);
  m.triangles = {0, 1, 2, 0, 5, 6};
  EXPECT_EQ(findSelfIntersections(m, {}).count, 0u);
}

// Random triangles with corners on two 7 x 7 grids of points, grid(plane, a, b) for plane 0
// and 1 and a, b in 0..6, and on ten points off both (shared corners, shared edges, folds,
// touching edges, collinear corners, duplicates): 40 trials of 60 faces. With `mixed`, a third
// of the faces meant for plane 1 get two corners on plane 0 and one off it instead (faces
// touching plane 0 along an edge). Every trial finds the same pairs with the shortcuts as with
// CGAL alone (the reference).
struct ShortcutTally {
  size_t intersecting = 0, candidates = 0, planarDecided = 0, orientDecided = 0;
};
ShortcutTally expectShortcutsAgreeWithCgal(const std::function<Eigen::Vector3d(int, int, int)>& grid,
                                           bool mixed = false) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> coord(0, 6), axisPick(0, 9);
  ShortcutTally tally;
  for (int trial = 0; trial < 40; ++trial) {
    Mesh m;
    for (int plane = 0; plane < 2; ++plane)
      for (int a = 0; a <= 6; ++a)
        for (int b = 0; b <= 6; ++b) {
          const Eigen::Vector3d p = grid(plane, a, b);
          m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
        }
    for (int k = 0; k < 10; ++k)
      m.positions.insert(m.positions.end(), {0.37 * coord(rng), 0.41 * coord(rng), 0.29 * coord(rng) - 0.9});
    const uint32_t offPlane = 98;
    for (int f = 0; f < 60; ++f) {
      const int pick = axisPick(rng);
      uint32_t v[3];
      for (int k = 0; k < 3; ++k) {
        uint32_t& x = v[k];
        if (pick < 6) x = uint32_t(7 * coord(rng) + coord(rng));              // plane 0
        else if (mixed && pick == 6) x = k < 2 ? uint32_t(7 * coord(rng) + coord(rng)) : offPlane + uint32_t(coord(rng)) % 10;
        else if (pick < 9) x = uint32_t(49 + 7 * coord(rng) + coord(rng));    // plane 1
        else x = offPlane + uint32_t(coord(rng)) % 10;
      }
      m.triangles.insert(m.triangles.end(), {v[0], v[1], v[2]});
    }
    SelfIntersectionOptions fast, reference;
    fast.cap = reference.cap = 0;
    reference.planarShortcuts = false;
    const SelfIntersectionResult a = findSelfIntersections(m, fast), b = findSelfIntersections(m, reference);
    EXPECT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a.pairs, b.pairs) << "trial " << trial;
    EXPECT_EQ(b.planarDecided + b.orientDecided, 0u);
    tally.intersecting += b.count;
    tally.candidates += a.candidates;
    tally.planarDecided += a.planarDecided;
    tally.orientDecided += a.orientDecided;
  }
  return tally;
}

// The axis-plane shortcuts decide exactly as CGAL does: grids in the planes z = 0 and x = 3.
TEST(SelfIntersections, PlanarShortcutsAgreeWithCgal) {
  const ShortcutTally t = expectShortcutsAgreeWithCgal([](int plane, int a, int b) {
    return plane == 0 ? Eigen::Vector3d(0.5 * a, 0.5 * b, 0.0) : Eigen::Vector3d(3.0, 0.5 * a, 0.5 * b - 1);
  });
  EXPECT_GT(t.intersecting, 200u);  // the cases do intersect, often
  std::printf("axis planes: shortcuts decided %zu + %zu (orientations) of %zu candidate pairs\n", t.planarDecided,
              t.orientDecided, t.candidates);
  // Exact orientations and the collinear cases (rays along one line, a face touching another's
  // edge line) decide 23.4k of 32.2k here; the static filter alone decided 12.9k.
  EXPECT_GT(t.planarDecided, 2 * t.candidates / 3);
}

// The exact 3D orientations decide exactly as CGAL does on two inclined planes whose grid points
// lie in them exactly (dyadic steps): coplanar faces decided in 2D, faces apart by sides, faces
// touching a plane along an edge from a shared corner (mixed).
TEST(SelfIntersections, OrientationShortcutsAgreeWithCgalOnInclinedPlanes) {
  const ShortcutTally t = expectShortcutsAgreeWithCgal([](int plane, int a, int b) {
    if (plane == 0) return Eigen::Vector3d(1 + 0.5 * a + 0.25 * b, 2 + 0.25 * a - 0.5 * b, 3 + 0.75 * a + 0.125 * b);
    return Eigen::Vector3d(2.5 + 0.375 * a, -1 + 0.5 * b, 0.5 - 0.25 * a + 0.625 * b);
  }, true);
  EXPECT_GT(t.intersecting, 200u);
  std::printf("inclined planes: shortcuts decided %zu + %zu (orientations) of %zu candidate pairs\n",
              t.planarDecided, t.orientDecided, t.candidates);
  EXPECT_GT(t.planarDecided + t.orientDecided, 2 * t.candidates / 3);
}

// A saddle z = (x^2 - y^2) / 8 on a grid of step 1/4: every grid quad is exactly planar (no xy
// term), so its two triangles are a coplanar pair that CGAL's filters leave to exact
// arithmetic. No pair intersects, as CGAL alone finds; the orientations decide every coplanar
// pair and the pairs apart (faces sharing a corner on a saddle mostly cross each other's planes:
// CGAL, whose filters decide those).
TEST(SelfIntersections, PlanarQuadsOfASaddleAreDecidedExactly) {
  Mesh m;
  const int n = 24;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = 0.25 * (i - n / 2), y = 0.25 * (j - n / 2);
      m.positions.insert(m.positions.end(), {x, y, (x * x - y * y) / 8});
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const uint32_t v = uint32_t(i * (n + 1) + j);
      m.triangles.insert(m.triangles.end(), {v, v + n + 1, v + n + 2, v, v + n + 2, v + 1});
    }
  SelfIntersectionOptions fast, reference;
  fast.cap = reference.cap = 0;
  reference.planarShortcuts = false;
  const SelfIntersectionResult a = findSelfIntersections(m, fast), b = findSelfIntersections(m, reference);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a.count, 0u);
  EXPECT_EQ(b.count, 0u);
  EXPECT_GT(a.candidates, 5000u);
  std::printf("saddle: orientations decided %zu of %zu candidate pairs\n", a.orientDecided, a.candidates);
  EXPECT_GE(a.orientDecided, size_t(n * n));  // at least the n^2 quads' coplanar pairs
  // Folding one quad's triangle onto its partner (the far corner moved across the shared
  // diagonal, within the plane) is found by both.
  Mesh folded = m;
  const uint32_t v = uint32_t(5 * (n + 1) + 7);
  // Triangle (v, v+n+2, v+1) becomes (v, v+n+2, w), w = the mirror of v+1 across the diagonal,
  // i.e. the quad's fourth corner v+n+1: it lies on the other triangle's side, in the same plane.
  for (size_t t = 0; t < folded.faceCount(); ++t) {
    uint32_t* tri = &folded.triangles[3 * t];
    if (tri[0] == v && tri[1] == v + n + 2 && tri[2] == v + 1) tri[2] = v + n + 1;
  }
  const SelfIntersectionResult fa = findSelfIntersections(folded, fast), fb = findSelfIntersections(folded, reference);
  ASSERT_TRUE(fa.ok() && fb.ok());
  EXPECT_EQ(fa.pairs, fb.pairs);
  EXPECT_GE(fa.count, 1u);
}

// The cap stops the search; progress can cancel it.
TEST(SelfIntersections, CapAndCancel) {
  const Mesh m = tangle();
  SelfIntersectionOptions o;
  o.cap = 5;
  const SelfIntersectionResult r = findSelfIntersections(m, o);
  EXPECT_EQ(r.count, 5u);
  EXPECT_TRUE(r.capped);
  EXPECT_EQ(r.pairs.size(), 5u);
  const SelfIntersectionResult c =
      findSelfIntersections(m, {}, [](const char*, double) { return false; });
  EXPECT_EQ(c.status, Status::Cancelled);
}

}  // namespace
}  // namespace omnislice
