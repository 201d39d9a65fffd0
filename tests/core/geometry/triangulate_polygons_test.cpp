// SPDX-License-Identifier: MIT
// triangulatePolygons: areas, triangle counts, no inverted or zero-area triangle, and the edge
// pairing that keeps a capped mesh closed (every loop edge covered once in its direction, every
// other edge twice in opposite directions), on holes, nesting, touching loops, collinear points,
// combs, large polygons with many holes (timed, printed), orphan holes and bad input.
#include "geometry/triangulate_polygons.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace omnislice {
namespace {

using Pts = std::vector<Eigen::Vector2d>;
using Loops = std::vector<std::vector<uint32_t>>;

double twiceArea(const Pts& p, uint32_t a, uint32_t b, uint32_t c) {
  return (p[b] - p[a]).x() * (p[c] - p[a]).y() - (p[b] - p[a]).y() * (p[c] - p[a]).x();
}

double loopArea(const Pts& p, const std::vector<uint32_t>& loop) {
  double s = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const Eigen::Vector2d& a = p[loop[i]];
    const Eigen::Vector2d& b = p[loop[(i + 1) % loop.size()]];
    s += a.x() * b.y() - b.x() * a.y();
  }
  return s / 2;
}

// Edge pairing: each directed loop edge appears once in the triangles, its reverse never; each
// other directed triangle edge appears once and so does its reverse.
void expectPaired(const PolygonTriangulation& t, const Loops& loops, const std::string& what) {
  std::map<std::pair<uint32_t, uint32_t>, int> tri, loop;
  for (size_t i = 0; i < t.triangles.size(); i += 3) {
    for (int k = 0; k < 3; ++k) ++tri[{t.triangles[i + k], t.triangles[i + (k + 1) % 3]}];
  }
  for (const auto& l : loops) {
    for (size_t i = 0; i < l.size(); ++i) ++loop[{l[i], l[(i + 1) % l.size()]}];
  }
  size_t bad = 0;
  for (const auto& [e, n] : loop) {
    if (tri[e] != n) ++bad;
  }
  for (const auto& [e, n] : tri) {
    if (n == 0 || loop.count(e)) continue;
    const auto r = tri.find({e.second, e.first});
    if (n != 1 || r == tri.end() || r->second != 1) ++bad;
  }
  EXPECT_EQ(bad, 0u) << what << ": edges not paired";
}

// A valid triangulation of a valid region: paired, every triangle counter-clockwise with a
// non-negligible area, the total equal to the loops' signed area sum, nothing forced.
void expectValid(const Pts& p, const Loops& loops, const PolygonTriangulation& t,
                 const std::string& what) {
  ASSERT_TRUE(t.ok()) << what << ": " << t.message;
  expectPaired(t, loops, what);
  double expected = 0, scale = 0;
  for (const auto& l : loops) expected += loopArea(p, l);
  for (const auto& q : p) scale = std::max(scale, q.cwiseAbs().maxCoeff());
  size_t inverted = 0;
  for (size_t i = 0; i < t.triangles.size(); i += 3) {
    if (!(twiceArea(p, t.triangles[i], t.triangles[i + 1], t.triangles[i + 2]) >
          1e-14 * scale * scale))
      ++inverted;
  }
  EXPECT_EQ(inverted, 0u) << what << ": inverted or zero-area triangles";
  EXPECT_NEAR(t.area, expected, 1e-9 * std::max(1.0, std::abs(expected))) << what;
  EXPECT_EQ(t.forcedTriangles, 0u) << what;
  EXPECT_EQ(t.orphanHoles, 0u) << what;
}

// Appends a loop of points, returns its indices.
std::vector<uint32_t> addLoop(Pts& p, const std::vector<Eigen::Vector2d>& q) {
  std::vector<uint32_t> l;
  for (const auto& x : q) {
    l.push_back(static_cast<uint32_t>(p.size()));
    p.push_back(x);
  }
  return l;
}

std::vector<Eigen::Vector2d> square(double x0, double y0, double s, bool ccw = true) {
  std::vector<Eigen::Vector2d> q = {{x0, y0}, {x0 + s, y0}, {x0 + s, y0 + s}, {x0, y0 + s}};
  if (!ccw) std::reverse(q.begin(), q.end());
  return q;
}

std::vector<Eigen::Vector2d> circle(double cx, double cy, double r, int n, bool ccw = true) {
  std::vector<Eigen::Vector2d> q;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n * (ccw ? 1 : -1);
    q.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  return q;
}

TEST(TriangulatePolygons, SquareAndSquareWithHole) {
  Pts p;
  Loops loops = {addLoop(p, square(0, 0, 1))};
  PolygonTriangulation t = triangulatePolygons(p, loops);
  expectValid(p, loops, t, "square");
  EXPECT_EQ(t.triangles.size(), 6u);
  loops.push_back(addLoop(p, square(0.25, 0.25, 0.5, false)));
  t = triangulatePolygons(p, loops);
  expectValid(p, loops, t, "square with hole");
  EXPECT_EQ(t.triangles.size() / 3, 8u);  // n + 2h - 2
  EXPECT_NEAR(t.area, 0.75, 1e-15);
  EXPECT_EQ(t.outerLoops, 1u);
  EXPECT_EQ(t.holeLoops, 1u);
}

// Straight vertices (many collinear points along the sides): never a zero-area triangle.
TEST(TriangulatePolygons, CollinearPoints) {
  Pts p;
  std::vector<Eigen::Vector2d> q;
  const int k = 50;
  for (int i = 0; i < k; ++i) q.push_back({double(i) / k * 3, 0});
  for (int i = 0; i < k; ++i) q.push_back({3, double(i) / k});
  for (int i = 0; i < k; ++i) q.push_back({3 - double(i) / k * 3, 1});
  for (int i = 0; i < k; ++i) q.push_back({0, 1 - double(i) / k});
  Loops loops = {addLoop(p, q)};
  // A hole with collinear points too, lined up with the outer points.
  std::vector<Eigen::Vector2d> h;
  for (int i = 0; i < 10; ++i) h.push_back({1 + 0.1 * i, 0.5});
  h.push_back({2, 0.7});
  loops.push_back(addLoop(p, std::vector<Eigen::Vector2d>(h.rbegin(), h.rend())));
  const PolygonTriangulation t = triangulatePolygons(p, loops);
  expectValid(p, loops, t, "collinear");
  EXPECT_EQ(t.triangles.size() / 3, 4u * k + 11 + 2 - 2);
}

// A comb: many reflex vertices.
TEST(TriangulatePolygons, Comb) {
  Pts p;
  std::vector<Eigen::Vector2d> q = {{0, 0}, {100, 0}};
  for (int i = 100; i > 0; --i) {
    q.push_back({double(i), 10});
    q.push_back({i - 0.5, 1});
  }
  q.push_back({0, 10});
  Loops loops = {addLoop(p, q)};
  const PolygonTriangulation t = triangulatePolygons(p, loops);
  expectValid(p, loops, t, "comb");
  EXPECT_EQ(t.triangles.size() / 3, q.size() - 2);
}

// Outer > hole > island > hole: each hole to the innermost outer containing it.
TEST(TriangulatePolygons, NestedIslands) {
  Pts p;
  Loops loops = {addLoop(p, square(0, 0, 10)), addLoop(p, square(1, 1, 8, false)),
                 addLoop(p, square(2, 2, 6)),  addLoop(p, square(3, 3, 4, false)),
                 addLoop(p, square(4, 4, 2)),  addLoop(p, square(20, 0, 1))};
  const PolygonTriangulation t = triangulatePolygons(p, loops);
  expectValid(p, loops, t, "nested");
  EXPECT_EQ(t.outerLoops, 4u);
  EXPECT_EQ(t.holeLoops, 2u);
  EXPECT_NEAR(t.area, 100 - 64 + 36 - 16 + 4 + 1, 1e-12);
}

// Loops sharing points: a hole touching its contour at a vertex, two holes touching each other,
// and two islands touching at a point (a figure eight, as a plane through a saddle vertex gives).
TEST(TriangulatePolygons, TouchingLoops) {
  {
    // Triangular hole with a corner on the contour's corner (0,0).
    const Pts p = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {2, 1}, {3, 2}};
    const Loops loops = {{0, 1, 2, 3}, {0, 5, 4}};
    ASSERT_LT(loopArea(p, loops[1]), 0);
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    expectValid(p, loops, t, "hole touching contour");
  }
  {
    const Pts p = {{0, 0}, {6, 0}, {6, 4}, {0, 4}, {1, 1}, {3, 2}, {1, 3}, {5, 1}, {5, 3}};
    // Two triangular holes sharing (3,2).
    const Loops loops = {{0, 1, 2, 3}, {4, 6, 5}, {5, 8, 7}};
    ASSERT_LT(loopArea(p, loops[1]), 0);
    ASSERT_LT(loopArea(p, loops[2]), 0);
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    expectValid(p, loops, t, "holes touching");
  }
  {
    // Point 2 = (1,1) shared: two squares meeting at a corner, as two loops.
    const Pts p = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 1}, {2, 2}, {1, 2}};
    const Loops loops = {{0, 1, 2, 3}, {2, 4, 5, 6}};
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    expectValid(p, loops, t, "figure eight");
    EXPECT_NEAR(t.area, 2, 1e-15);
  }
  {
    // A hole touching the contour at two points: a region made of two parts as one outer loop
    // and one hole.
    const Pts p = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {2, 0}, {3, 2}, {2, 4}, {1, 2}};
    const Loops loops = {{0, 4, 1, 2, 6, 3}, {4, 7, 6, 5}};
    ASSERT_LT(loopArea(p, loops[1]), 0);
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    expectValid(p, loops, t, "hole touching twice");
    EXPECT_NEAR(t.area, 16 - 4, 1e-12);
  }
}

// Thousands of points and hundreds of holes (timed, printed).
TEST(TriangulatePolygons, LargeWithManyHoles) {
  Pts p;
  const int n = 10000;
  Loops loops = {addLoop(p, circle(0, 0, 100, n))};
  int holes = 0;
  for (int i = -6; i <= 6; ++i) {
    for (int j = -6; j <= 6; ++j) {
      if (i * i + j * j > 40) continue;
      loops.push_back(addLoop(p, (i + j) % 2 ? square(i * 12.0, j * 12.0, 6, false)
                                             : circle(i * 12.0, j * 12.0, 4, 40, false)));
      ++holes;
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  const PolygonTriangulation t = triangulatePolygons(p, loops);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  expectValid(p, loops, t, "large");
  EXPECT_EQ(t.holeLoops, size_t(holes));
  EXPECT_EQ(t.triangles.size() / 3, p.size() + 2 * holes - 2);
  std::printf("triangulatePolygons: %zu points, %d holes -> %zu triangles in %.1f ms\n", p.size(),
              holes, t.triangles.size() / 3, ms);
}

// Random star-shaped polygons (simple, strongly non-convex) with a random hole near the centre.
TEST(TriangulatePolygons, RandomStars) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> radius(0.2, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 50 + 40 * trial;
    Pts p;
    std::vector<Eigen::Vector2d> q;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n, r = radius(rng);
      q.push_back({r * std::cos(a), r * std::sin(a)});
    }
    Loops loops = {addLoop(p, q)};
    if (trial % 2) loops.push_back(addLoop(p, circle(0.02, -0.01, 0.1, 7 + trial, false)));
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    expectValid(p, loops, t, "star " + std::to_string(trial));
  }
}

// A clockwise loop in no outer loop: triangulated alone, clockwise, still paired.
TEST(TriangulatePolygons, OrphanHole) {
  Pts p;
  const Loops loops = {addLoop(p, square(0, 0, 1, false))};
  const PolygonTriangulation t = triangulatePolygons(p, loops);
  ASSERT_TRUE(t.ok());
  expectPaired(t, loops, "orphan");
  EXPECT_EQ(t.orphanHoles, 1u);
  EXPECT_NEAR(t.area, -1, 1e-15);
}

// Degenerate loops (zero area, repeated positions, crossing): no crash, still paired.
TEST(TriangulatePolygons, DegenerateLoopsStayPaired) {
  {
    const Pts p = {{0, 0}, {1, 0}, {2, 0}, {3, 0}};
    const Loops loops = {{0, 1, 2, 3}};
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    ASSERT_TRUE(t.ok());
    expectPaired(t, loops, "flat");
    EXPECT_EQ(t.triangles.size() / 3, 2u);
  }
  {
    const Pts p = {{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}};
    const Loops loops = {{0, 1, 2, 3, 4}};
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    ASSERT_TRUE(t.ok());
    expectPaired(t, loops, "repeated position");
  }
  {
    const Pts p = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};  // bow tie
    const Loops loops = {{0, 1, 2, 3}};
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    ASSERT_TRUE(t.ok());
    expectPaired(t, loops, "bow tie");
  }
  {
    Pts p;
    const Loops loops = {addLoop(p, square(0, 0, 1)),
                         addLoop(p, square(0.5, 0.5, 1, false))};  // hole sticks out
    const PolygonTriangulation t = triangulatePolygons(p, loops);
    ASSERT_TRUE(t.ok());
    expectPaired(t, loops, "crossing hole");
  }
}

// With minArea, a tiny ear (a corner bulging 1e-6 out of a long edge) is avoided when larger
// triangles can take that corner.
TEST(TriangulatePolygons, MinAreaAvoidsSlivers) {
  const Pts p = {{0, 0}, {1, -1e-6}, {2, 0}, {2, 1}, {0, 1}};
  const Loops loops = {{0, 1, 2, 3, 4}};
  TriangulateOptions options;
  options.minArea = 1e-3;
  const PolygonTriangulation t = triangulatePolygons(p, loops, options);
  expectValid(p, loops, t, "min area");
  for (size_t i = 0; i < t.triangles.size(); i += 3) {
    EXPECT_GT(0.5 * twiceArea(p, t.triangles[i], t.triangles[i + 1], t.triangles[i + 2]), 1e-3);
  }
  // Where nothing else is possible (a tiny polygon), small ears are still cut.
  const Pts tiny = {{0, 0}, {1e-3, 0}, {0, 1e-3}};
  const PolygonTriangulation s = triangulatePolygons(tiny, {{0, 1, 2}}, options);
  expectValid(tiny, {{0, 1, 2}}, s, "tiny");
  options.minArea = -1;
  EXPECT_EQ(triangulatePolygons(p, loops, options).status, Status::InvalidOption);
}

// avoidEdges: a square takes the other diagonal; a concave quad, whose only diagonal is avoided,
// still gets it (nothing else is left).
TEST(TriangulatePolygons, AvoidEdges) {
  const Pts p = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const Loops loops = {{0, 1, 2, 3}};
  for (const std::array<uint32_t, 2> avoid : {std::array<uint32_t, 2>{0, 2}, {3, 1}}) {
    TriangulateOptions options;
    options.avoidEdges = {avoid};
    const PolygonTriangulation t = triangulatePolygons(p, loops, options);
    expectValid(p, loops, t, "square");
    for (size_t i = 0; i < t.triangles.size(); i += 3) {
      int hits = 0;
      for (int k = 0; k < 3; ++k)
        hits += t.triangles[i + k] == avoid[0] || t.triangles[i + k] == avoid[1];
      EXPECT_LT(hits, 2) << "avoided edge used";
    }
  }
  const Pts dart = {{0, 0}, {2, 1}, {0, 2}, {1, 1}};  // reflex at 3: only diagonal 1-3
  TriangulateOptions options;
  options.avoidEdges = {{1, 3}};
  const PolygonTriangulation t = triangulatePolygons(dart, {{0, 1, 2, 3}}, options);
  expectValid(dart, {{0, 1, 2, 3}}, t, "dart");
}

// A hole whose bridge would run along a line through other vertices (a hole edge collinear with
// the contour's vertices, as voxel-like cross-sections have): no overlapping bridge, no
// zero-area triangle.
TEST(TriangulatePolygons, CollinearBridge) {
  Pts p = {{0, 0}, {6, 0}, {6, 1}, {5, 1}, {5, 2}, {6, 2}, {6, 3}, {0, 3}};
  Loops loops = {{0, 1, 2, 3, 4, 5, 6, 7}};
  // Two triangular holes with their top edges on y = 1, the line of the contour's notch.
  loops.push_back(addLoop(p, {{1, 1}, {2, 1}, {1.5, 0.5}}));
  loops.push_back(addLoop(p, {{3, 1}, {4, 1}, {3.5, 0.5}}));
  ASSERT_LT(loopArea(p, loops[1]), 0);
  const PolygonTriangulation t = triangulatePolygons(p, loops);
  expectValid(p, loops, t, "collinear bridge");
}

TEST(TriangulatePolygons, BadInput) {
  const Pts p = {{0, 0}, {1, 0}, {0, 1}};
  EXPECT_EQ(triangulatePolygons(p, {{0, 1, 3}}).status, Status::InvalidOption);
  const Pts nan = {{0, 0}, {1, std::nan("")}, {0, 1}};
  EXPECT_EQ(triangulatePolygons(nan, {{0, 1, 2}}).status, Status::InvalidOption);
  const PolygonTriangulation t = triangulatePolygons(p, {{0, 1}});
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t.skippedLoops, 1u);
  EXPECT_TRUE(t.triangles.empty());
  EXPECT_TRUE(triangulatePolygons({}, {}).ok());
}

}  // namespace
}  // namespace omnislice
