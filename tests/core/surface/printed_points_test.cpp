// SPDX-License-Identifier: MIT
// The spatial index of the gouging check against a plain scan over every point: the same
// answers for random clouds and cones (points on both sides of the origin, sequence limits,
// retired points), and the same sum of lateral directions up to rounding; on points at the cone's
// boundaries, the same answers and sums to the bit as the block scan the header defines.
#include "surface/printed_points.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>
#include <vector>

namespace omnislice {
namespace {

using Eigen::Vector3d;

struct Printed {
  Vector3d p;
  uint32_t seq;
  bool retired = false;
};

// The rule of the header, point by point.
bool scanHit(const std::vector<Printed>& pts, const Vector3d& s, const Vector3d& u, uint32_t limit,
             const GougingCone& cone, Vector3d* away) {
  bool any = false;
  for (const Printed& q : pts) {
    if (q.retired || q.seq >= limit) continue;
    const Vector3d d = q.p - s;
    const double a = d.dot(u);
    if (a <= cone.clearance || d.squaredNorm() >= cone.length * cone.length) continue;
    const Vector3d lateral = d - a * u;
    const double lat = lateral.norm();
    if (lat >= a * cone.tanAngle + cone.radius) continue;
    any = true;
    if (away && lat > 1e-9) *away -= lateral / lat;
  }
  return any;
}

GougingCone testCone() {
  GougingCone c;
  c.clearance = 0.6;
  c.length = 25;
  c.tanAngle = std::tan(43.0 * 3.14159265358979323846 / 180.0);
  c.radius = 0.25;
  return c;
}

// Printed material as a stack of wavy sheets 0.6 mm apart, points 0.5 mm apart, over
// [-30, 30] x [-30, 30] mm (cells on both sides of zero), printed sheet by sheet.
std::vector<Printed> sheets(int count) {
  std::vector<Printed> pts;
  uint32_t seq = 0;
  for (int k = 0; k < count; ++k) {
    for (double x = -30; x <= 30; x += 0.5) {
      for (double y = -30; y <= 30; y += 0.5) {
        const double z = -5 + 0.6 * k + 2 * std::sin(0.1 * x) * std::cos(0.13 * y);
        pts.push_back({Vector3d(x, y, z), seq++});
      }
    }
  }
  return pts;
}

TEST(PrintedPoints, AnswersAsAScanOverEveryPoint) {
  std::vector<Printed> pts = sheets(8);
  PrintedPoints index;
  for (const Printed& q : pts) index.add(q.p, q.seq);
  const GougingCone cone = testCone();
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> coord(-35, 35), height(-8, 6), unit(-1, 1);
  std::uniform_int_distribution<uint32_t> limit(0, uint32_t(pts.size()));
  int hits = 0, misses = 0;
  for (int n = 0; n < 4000; ++n) {
    const Vector3d s(coord(rng), coord(rng), height(rng));
    Vector3d u(unit(rng), unit(rng), unit(rng));
    if (u.norm() < 1e-3) continue;
    u.normalize();
    const uint32_t lim = n % 4 == 0 ? uint32_t(pts.size()) : limit(rng);
    const bool expected = scanHit(pts, s, u, lim, cone, nullptr);
    EXPECT_EQ(index.hit(s, u, lim, cone), expected) << "query " << n;
    Vector3d awayScan = Vector3d::Zero(), awayIndex = Vector3d::Zero();
    scanHit(pts, s, u, lim, cone, &awayScan);
    EXPECT_EQ(index.hit(s, u, lim, cone, &awayIndex), expected) << "query " << n << " (away)";
    EXPECT_LT((awayScan - awayIndex).norm(), 1e-9 * (1 + awayScan.norm())) << "query " << n;
    (expected ? hits : misses) += 1;
  }
  // Both answers were exercised.
  EXPECT_GT(hits, 400);
  EXPECT_GT(misses, 400);
}

// As the gouging search asks: rings of axes around one at a tip, the limit changing between
// queries, so the recently hitting points answer many of them, or must not (seq >= limit).
TEST(PrintedPoints, RingQueriesAnswerAsTheScan) {
  std::vector<Printed> pts = sheets(8);
  PrintedPoints index;
  for (const Printed& q : pts) index.add(q.p, q.seq);
  const GougingCone cone = testCone();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> coord(-30, 30), height(-4, 4);
  std::uniform_int_distribution<uint32_t> limit(0, uint32_t(pts.size()));
  int hits = 0, misses = 0;
  for (int n = 0; n < 12; ++n) {
    const Vector3d s(coord(rng), coord(rng), height(rng));
    const uint32_t lims[2] = {uint32_t(pts.size()), limit(rng)};
    const Vector3d u = Vector3d(0.3 * n - 2, 0.5, 1).normalized();
    const Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
    for (int ring = 0; ring <= 30; ring += 3) {
      for (int k = 0; k < 48; ++k) {
        const double d = ring * 2 * 3.14159265358979 / 180, phi = k * 2 * 3.14159265358979 / 48;
        const Vector3d c = (std::cos(d) * u + std::sin(d) * (std::cos(phi) * e1 + std::sin(phi) * e2)).normalized();
        const uint32_t lim = lims[(ring + k) % 7 == 0 ? 1 : 0];
        const bool expected = scanHit(pts, s, c, lim, cone, nullptr);
        ASSERT_EQ(index.hit(s, c, lim, cone), expected) << n << " " << ring << " " << k;
        (expected ? hits : misses) += 1;
      }
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 1000);
}

TEST(PrintedPoints, RetiredPointsAreNotSeen) {
  // One sheet (z = -5 at the origin); a cone 3 mm below it looking up meets it near the axis only.
  std::vector<Printed> pts = sheets(1);
  PrintedPoints index;
  for (const Printed& q : pts) index.add(q.p, q.seq);
  const GougingCone cone = testCone();
  const uint32_t all = uint32_t(pts.size());
  const Vector3d s(0, 0, -8), up(0, 0, 1);
  EXPECT_TRUE(index.hit(s, up, all, cone));
  // A segment left out: the points within 6 mm of the axis are retired.
  for (Printed& q : pts) {
    if (q.p.head<2>().norm() < 6) {
      index.retire(q.p, q.seq);
      q.retired = true;
    }
  }
  EXPECT_FALSE(scanHit(pts, s, up, all, cone, nullptr));
  EXPECT_FALSE(index.hit(s, up, all, cone));
  for (double tilt : {0.2, 0.5, 0.8}) {
    const Vector3d u(std::sin(tilt), 0, std::cos(tilt));
    EXPECT_EQ(index.hit(s, u, all, cone), scanHit(pts, s, u, all, cone, nullptr)) << tilt;
  }
}

// The header's definition, literally: 8 mm blocks of 2 mm cells in creation order, each box's
// bounding sphere tested against the cone before its points (the box test the index's cells and
// blocks must answer as, rounding included).
bool scanBoxTest(const Vector3d& lo, const Vector3d& hi, const Vector3d& s, const Vector3d& u, const GougingCone& cone) {
  double top = 0;
  for (int k = 0; k < 3; ++k) top += u[k] * ((u[k] > 0 ? hi[k] : lo[k]) - s[k]);
  if (top <= cone.clearance) return false;
  const Vector3d q = s.cwiseMax(lo).cwiseMin(hi);
  if ((q - s).squaredNorm() >= cone.length * cone.length) return false;
  const double cosT = 1 / std::sqrt(1 + cone.tanAngle * cone.tanAngle), sinT = cone.tanAngle * cosT;
  const Vector3d c = 0.5 * (lo + hi);
  const double r = 0.5 * (hi - lo).norm() + cone.radius;
  const Vector3d d = c - s;
  const double a = d.dot(u);
  const double lat = (d - a * u).norm();
  if (lat <= a * cone.tanAngle) return true;
  const double along = a * cosT + lat * sinT;
  return (along >= 0 ? lat * cosT - a * sinT : d.norm()) < r;
}

struct BlockScan {
  struct Box {
    Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
    std::vector<size_t> items;  // cells of a block, points of a cell
  };
  std::vector<Box> blocks, cells;
  std::map<std::tuple<int64_t, int64_t, int64_t>, size_t> blockOf, cellOf;

  explicit BlockScan(const std::vector<Printed>& pts) {
    for (size_t i = 0; i < pts.size(); ++i) {
      auto grid = [&](double edge) {
        const Eigen::Array3d g = (pts[i].p.array() / edge).floor();
        return std::make_tuple(int64_t(g.x()), int64_t(g.y()), int64_t(g.z()));
      };
      auto [b, newBlock] = blockOf.try_emplace(grid(8.0), blocks.size());
      if (newBlock) blocks.emplace_back();
      auto [c, newCell] = cellOf.try_emplace(grid(2.0), cells.size());
      if (newCell) {
        cells.emplace_back();
        blocks[b->second].items.push_back(c->second);
      }
      for (Box* box : {&blocks[b->second], &cells[c->second]}) {
        box->lo = box->lo.cwiseMin(pts[i].p);
        box->hi = box->hi.cwiseMax(pts[i].p);
      }
      cells[c->second].items.push_back(i);
    }
  }

  bool hit(const std::vector<Printed>& pts, const Vector3d& s, const Vector3d& u, uint32_t limit,
           const GougingCone& cone, Vector3d* away) const {
    bool any = false;
    for (const Box& b : blocks) {
      if (!scanBoxTest(b.lo, b.hi, s, u, cone)) continue;
      for (size_t c : b.items) {
        if (!scanBoxTest(cells[c].lo, cells[c].hi, s, u, cone)) continue;
        std::vector<Printed> cellPoints;
        for (size_t i : cells[c].items) cellPoints.push_back(pts[i]);
        any = scanHit(cellPoints, s, u, limit, cone, away) || any;
      }
    }
    return any;
  }
};

// Points on the cone's boundaries to the last bit (the clearance plane, the side widened by the
// radius, the length), one per cone, where the search's box tests reject by a margin and the
// answers hang on the scan's rounding. On the clearance plane the box test sums (p - s).u in
// another order than the point test: the points there are drawn until the point test takes them and
// the scan's test of their box does not, so the scan's answer is no; or they are the top corner of a
// box with a second point below, nudged in their last bits until the point test just takes them.
TEST(PrintedPoints, BoundaryPointsAnswerAsTheBlockScan) {
  const GougingCone cone = testCone();
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> coord(-60, 60), unit(-1, 1), share(0, 1);
  std::uniform_int_distribution<int> axis(0, 2);
  std::vector<std::pair<Vector3d, Vector3d>> queries;
  std::vector<Printed> pts;
  for (int n = 0; n < 1200; ++n) {
    const Vector3d s(coord(rng), coord(rng), coord(rng));
    Vector3d u(unit(rng), unit(rng), unit(rng));
    if (u.norm() < 1e-3) continue;
    u.normalize();
    queries.emplace_back(s, u);
    const Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
    const double phi = 6.283185307179586 * share(rng);
    const Vector3d w = std::cos(phi) * e1 + std::sin(phi) * e2;
    const double a = cone.clearance + (cone.length - cone.clearance) * 0.7 * share(rng);
    Vector3d p;
    switch (n % 4) {
      case 0: {
        // Across the axis on the plane: the rounding of (p - s).u varies, its value does not.
        for (int t = 0; t < 3000; ++t) {
          p = s + cone.clearance * u + (cone.clearance * cone.tanAngle + cone.radius) * share(rng) * w;
          if (scanHit({{p, 0}}, s, u, 1, cone, nullptr) && !scanBoxTest(p, p, s, u, cone)) break;
        }
        break;
      }
      case 1: p = s + a * u + (a * cone.tanAngle + cone.radius) * w; break;
      case 2: p = s + cone.length * (u + 0.3 * share(rng) * w).normalized(); break;
      case 3: {
        // The box's corner farthest along u is p (which has the least (p - s).u the point test takes).
        p = s + cone.clearance * u + 0.5 * (cone.clearance * cone.tanAngle + cone.radius) * w;
        const Vector3d below = p - 0.2 * u.cwiseSign();
        for (int down = 1; down >= 0; --down) {
          for (int t = 0; t < 1000 && scanHit({{p, 0}}, s, u, 1, cone, nullptr) == bool(down); ++t) {
            const int k = axis(rng);
            p[k] = std::nextafter(p[k], (u[k] > 0) == bool(down) ? -1e300 : 1e300);
          }
        }
        pts.push_back({below, uint32_t(pts.size())});
        break;
      }
    }
    pts.push_back({p, uint32_t(pts.size())});
  }
  PrintedPoints index;
  for (const Printed& q : pts) index.add(q.p, q.seq);
  const BlockScan scan(pts);
  const uint32_t all = uint32_t(pts.size());
  int hits = 0, pointOnly = 0;
  for (size_t n = 0; n < queries.size(); ++n) {
    const auto& [s, u] = queries[n];
    const bool expected = scan.hit(pts, s, u, all, cone, nullptr);
    EXPECT_EQ(index.hit(s, u, all, cone), expected) << "query " << n;
    Vector3d awayScan = Vector3d::Zero(), awayIndex = Vector3d::Zero();
    scan.hit(pts, s, u, all, cone, &awayScan);
    EXPECT_EQ(index.hit(s, u, all, cone, &awayIndex), expected) << "query " << n << " (away)";
    EXPECT_EQ(awayScan, awayIndex) << "query " << n;  // the same sum in the same order
    hits += expected;
    pointOnly += expected != scanHit(pts, s, u, all, cone, nullptr);
  }
  EXPECT_GT(hits, 200);
  // The scan's box tests decided some answers (else this test would not check them).
  EXPECT_GT(pointOnly, 0);
}

}  // namespace
}  // namespace omnislice
