// SPDX-License-Identifier: MIT
// LatticeHull against a brute-force containment oracle (p in conv(S) iff p is on the inner side of
// every plane through 3 points of S that has all of S on one side), on random small lattice sets
// with heavy coplanarity, flat, collinear and single-point sets, plus big sets (timing printed).
#include "voxel/lattice_hull.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cstdio>
#include <map>
#include <random>
#include <set>

namespace omnislice {
namespace {

using V3 = Eigen::Vector3i;

int64_t orient(const V3& a, const V3& b, const V3& c, const V3& d) {
  const Eigen::Matrix<int64_t, 3, 1> u = (b - a).cast<int64_t>(), v = (c - a).cast<int64_t>(),
                                     w = (d - a).cast<int64_t>();
  return u.cross(v).dot(w);
}

// Independent oracle. For flat sets, the in-plane edge planes are planes through a, b and a + n
// (n the set's plane normal); p must also lie in the plane. Collinear: p on the segment.
bool oracleInside(const std::vector<V3>& s, const V3& p) {
  const size_t n = s.size();
  // Find a non-degenerate triple and a fourth point off its plane.
  int ia = 0, ib = -1, ic = -1, id = -1;
  for (size_t i = 1; i < n && ib < 0; ++i)
    if (s[i] != s[0]) ib = static_cast<int>(i);
  if (ib < 0) return p == s[0];
  for (size_t i = 0; i < n && ic < 0; ++i) {
    const Eigen::Matrix<int64_t, 3, 1> c =
        (s[ib] - s[ia]).cast<int64_t>().cross((s[i] - s[ia]).cast<int64_t>());
    if (c != Eigen::Matrix<int64_t, 3, 1>::Zero()) ic = static_cast<int>(i);
  }
  if (ic < 0) {
    // Collinear: p on the line, between the extremes.
    const Eigen::Matrix<int64_t, 3, 1> d = (s[ib] - s[ia]).cast<int64_t>();
    if (d.cross((p - s[ia]).cast<int64_t>()) != Eigen::Matrix<int64_t, 3, 1>::Zero()) return false;
    int64_t lo = INT64_MAX, hi = INT64_MIN;
    for (const V3& q : s) {
      const int64_t t = d.dot((q - s[ia]).cast<int64_t>());
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
    const int64_t t = d.dot((p - s[ia]).cast<int64_t>());
    return t >= lo && t <= hi;
  }
  for (size_t i = 0; i < n && id < 0; ++i)
    if (orient(s[ia], s[ib], s[ic], s[i]) != 0) id = static_cast<int>(i);
  std::vector<V3> pts = s;
  if (id < 0) {
    if (orient(s[ia], s[ib], s[ic], p) != 0) return false;
    const Eigen::Matrix<int64_t, 3, 1> nn =
        (s[ib] - s[ia]).cast<int64_t>().cross((s[ic] - s[ia]).cast<int64_t>());
    // Auxiliary lifted copies make every in-plane edge plane a plane through 3 points.
    for (const V3& q : s) pts.push_back(q + nn.cast<int>());
  }
  const size_t m = pts.size();
  for (size_t a = 0; a < m; ++a)
    for (size_t b = a + 1; b < m; ++b)
      for (size_t c = b + 1; c < m; ++c) {
        int pos = 0, neg = 0;
        for (const V3& q : pts) {
          const int64_t o = orient(pts[a], pts[b], pts[c], q);
          pos += o > 0;
          neg += o < 0;
        }
        if (pos + neg == 0 || (pos > 0 && neg > 0)) continue;
        const int64_t op = orient(pts[a], pts[b], pts[c], p);
        if (pos > 0 && op < 0) return false;
        if (neg > 0 && op > 0) return false;
        // For the lifted flat case, the lifted copies must not widen the set within the plane:
        // the flat-plane test above already fixed p in the plane.
      }
  return true;
}

void expectMatchesOracle(const std::vector<V3>& s, const char* what) {
  const LatticeHull h(s);
  for (int x = -1; x <= 5; ++x)
    for (int y = -1; y <= 5; ++y)
      for (int z = -1; z <= 5; ++z) {
        const V3 p(x, y, z);
        const bool expect = oracleInside(s, p);
        ASSERT_EQ(h.inside(p, 0.0), expect)
            << what << ": point " << p.transpose() << " dim " << h.dimension() << " n " << s.size();
        if (h.dimension() == 3) {
          ASSERT_EQ(h.insideOrOn(p), expect);
          ASSERT_EQ(h.signedDistance(p) <= 0, expect);
        }
      }
}

TEST(LatticeHull, RandomSmallSetsMatchBruteForceOracle) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    std::uniform_int_distribution<int> coord(0, trial % 2 ? 2 : 4);
    std::uniform_int_distribution<int> count(1, 11);
    std::vector<V3> s;
    const int n = count(rng);
    for (int i = 0; i < n; ++i) s.emplace_back(coord(rng), coord(rng), coord(rng));
    expectMatchesOracle(s, "random");
  }
}

TEST(LatticeHull, FlatCollinearPointAndDuplicateSets) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> c(0, 4);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<V3> s;
    const int n = 3 + trial % 8;
    for (int i = 0; i < n; ++i) {
      const int x = c(rng), y = c(rng);
      if (trial % 3 == 0) s.emplace_back(x, y, 2);               // horizontal plane
      else if (trial % 3 == 1) s.emplace_back(x, y, std::clamp(4 - x - y + 2, 0, 8) == 4 - x - y + 2 ? 4 - x - y + 2 : 0);
      else s.emplace_back(x, x, y);                               // vertical slanted plane x = y
    }
    // Keep the slanted set coplanar: drop points that were clamped off x + y + z = 6.
    if (trial % 3 == 1) {
      std::vector<V3> t;
      for (const V3& p : s)
        if (p.sum() == 6) t.push_back(p);
      s = t;
      if (s.empty()) continue;
    }
    const LatticeHull h(s);
    EXPECT_LE(h.dimension(), 2);
    expectMatchesOracle(s, "flat");
  }
  // Collinear with duplicates.
  expectMatchesOracle({{0, 0, 0}, {2, 2, 2}, {1, 1, 1}, {1, 1, 1}, {4, 4, 4}}, "collinear");
  EXPECT_EQ(LatticeHull({{0, 0, 0}, {2, 2, 2}, {4, 4, 4}}).dimension(), 1);
  // Single point, repeated.
  expectMatchesOracle({{3, 1, 2}, {3, 1, 2}, {3, 1, 2}}, "point");
  EXPECT_EQ(LatticeHull({{3, 1, 2}, {3, 1, 2}}).dimension(), 0);
  EXPECT_EQ(LatticeHull(std::vector<V3>{}).dimension(), -1);
  EXPECT_FALSE(LatticeHull(std::vector<V3>{}).inside({0, 0, 0}, 0));
  // Flat hull with eps: within eps of the polygon counts as inside (header convention).
  const LatticeHull sq({{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {2, 2, 0}});
  EXPECT_EQ(sq.dimension(), 2);
  EXPECT_EQ(sq.vertices().size(), 4u);
  EXPECT_TRUE(sq.inside({2, 2, 0}, 0));
  EXPECT_FALSE(sq.inside({2, 2, 1}, 0.5));
  EXPECT_TRUE(sq.inside({2, 2, 1}, 1.0));
}

// Structural invariants: every input point inside or on every plane, every vertex an input
// point, closed triangulated surface (V - E + F = 2), coplanar triangles share one plane.
void expectValidHull(const std::vector<V3>& s, const LatticeHull& h) {
  ASSERT_EQ(h.dimension(), 3);
  std::set<std::array<int, 3>> input;
  for (const V3& p : s) input.insert({p.x(), p.y(), p.z()});
  for (const V3& v : h.vertices()) ASSERT_TRUE(input.count({v.x(), v.y(), v.z()}));
  for (const LatticeHull::Plane& pl : h.planes())
    for (const V3& p : s) ASSERT_LE(pl.nx * p.x() + pl.ny * p.y() + pl.nz * p.z(), pl.offset);
  std::set<std::array<int64_t, 3>> normals;
  for (const LatticeHull::Plane& pl : h.planes())
    ASSERT_TRUE(normals.insert({pl.nx, pl.ny, pl.nz}).second) << "duplicate plane";
  std::map<std::pair<int, int>, int> edges;
  for (size_t f = 0; f < h.facets().size(); ++f) {
    const V3& t = h.facets()[f];
    const LatticeHull::Plane& pl = h.planes()[h.facetPlanes()[f]];
    for (int e = 0; e < 3; ++e) {
      const V3& v = h.vertices()[t[e]];
      ASSERT_EQ(pl.nx * v.x() + pl.ny * v.y() + pl.nz * v.z(), pl.offset);
      ++edges[{std::min(t[e], t[(e + 1) % 3]), std::max(t[e], t[(e + 1) % 3])}];
    }
  }
  for (const auto& e : edges) ASSERT_EQ(e.second, 2) << "edge not shared by two facets";
  EXPECT_EQ(static_cast<int64_t>(h.vertices().size()) - static_cast<int64_t>(edges.size()) +
                static_cast<int64_t>(h.facets().size()),
            2);
}

TEST(LatticeHull, FullLatticeCubeHasEightVerticesAndSixPlanes) {
  std::vector<V3> s;
  for (int z = 0; z < 40; ++z)
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) s.emplace_back(x, y, z);
  const auto t0 = std::chrono::steady_clock::now();
  const LatticeHull h(s);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ timing ] full 40^3 lattice cube (64k points): %.1f ms\n", ms);
  EXPECT_EQ(h.vertices().size(), 8u);
  EXPECT_EQ(h.planes().size(), 6u);
  expectValidHull(s, h);
  // Definition 3 with eps: (20,20,0) lies on the boundary, (20,20,1) is 1 deep.
  EXPECT_FALSE(h.inside({20, 20, 0}, 0.5));
  EXPECT_TRUE(h.inside({20, 20, 1}, 0.5));
  EXPECT_TRUE(h.inside({20, 20, 1}, 1.0));
  EXPECT_FALSE(h.inside({20, 20, 1}, 1.01));
  EXPECT_NEAR(h.signedDistance({20, 20, 45}), 6.0, 1e-12);
}

TEST(LatticeHull, BigRandomBallAndIncrementalExtensionAgree) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> c(-60, 60);
  std::vector<V3> s;
  while (s.size() < 200000) {
    const V3 p(c(rng), c(rng), c(rng));
    if (p.cast<double>().norm() <= 60) s.push_back(p);
  }
  auto t0 = std::chrono::steady_clock::now();
  const LatticeHull h(s);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ timing ] 200k lattice points in a ball: %.1f ms, %zu vertices, %zu planes\n", ms,
              h.vertices().size(), h.planes().size());
  expectValidHull(s, h);
  // Incremental: grow in 20 slabs by z, extending the previous hull each time.
  t0 = std::chrono::steady_clock::now();
  LatticeHull inc;
  for (int slab = 0; slab < 20; ++slab) {
    std::vector<V3> layer;
    for (const V3& p : s)
      if (p.z() + 60 >= slab * 121 / 20 && p.z() + 60 < (slab + 1) * 121 / 20) layer.push_back(p);
    inc = slab == 0 ? LatticeHull(layer) : inc.extended(layer);
  }
  const double msInc = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ timing ] same points in 20 incremental extensions: %.1f ms\n", msInc);
  // Same distinct facet planes (vertex lists may differ by non-extreme points lying inside a
  // coplanar facet polygon, which a triangulation may keep).
  std::set<std::array<int64_t, 4>> a, b;
  for (const auto& pl : inc.planes()) a.insert({pl.nx, pl.ny, pl.nz, pl.offset});
  for (const auto& pl : h.planes()) b.insert({pl.nx, pl.ny, pl.nz, pl.offset});
  ASSERT_EQ(a, b);
  std::uniform_int_distribution<int> q(-64, 64);
  for (int i = 0; i < 20000; ++i) {
    const V3 p(q(rng), q(rng), q(rng));
    ASSERT_EQ(inc.insideOrOn(p), h.insideOrOn(p));
    ASSERT_EQ(inc.inside(p, 0.5), h.inside(p, 0.5));
    // inside(eps) agrees with the plane distances.
    ASSERT_EQ(h.inside(p, 0.5), h.signedDistance(p) <= -0.5);
  }
}

TEST(LatticeHull, HintDoesNotChangeAnswers) {
  std::vector<V3> s;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) s.emplace_back(i, j, (i * i + j * j) / 40);
  const LatticeHull h(s);
  int hint = 0;
  for (int x = -2; x < 33; ++x)
    for (int y = -2; y < 33; ++y)
      for (int z = -2; z < 25; ++z) {
        const V3 p(x, y, z);
        ASSERT_EQ(h.inside(p, 0.3, &hint), h.inside(p, 0.3));
        ASSERT_GE(hint, 0);
        ASSERT_LT(hint, static_cast<int>(h.planes().size()));
      }
}

TEST(LatticeHull, LargeCoordinatesUseWideArithmetic) {
  const int big = 1 << 19;
  std::vector<V3> s = {{0, 0, 0}, {big, 0, 0}, {0, big, 0}, {0, 0, big}, {big, big, big},
                       {big / 2, big / 2, big / 2}, {big - 1, 1, big - 3}};
  const LatticeHull h(s);
  ASSERT_EQ(h.dimension(), 3);
  for (const V3& p : s) EXPECT_TRUE(h.insideOrOn(p));
  EXPECT_FALSE(h.insideOrOn({big + 1, big, big}));
}

}  // namespace
}  // namespace omnislice
