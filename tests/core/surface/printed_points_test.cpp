// SPDX-License-Identifier: MIT
// The spatial index of the gouging check against a plain scan over every point: the same
// answers for random clouds and cones (points on both sides of the origin, sequence limits,
// retired points), and the same sum of lateral directions up to rounding.
#include "surface/printed_points.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
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

}  // namespace
}  // namespace omnislice
