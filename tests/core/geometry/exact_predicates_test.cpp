// SPDX-License-Identifier: MIT
// The exact orientation predicates: their exact paths against each other and against
// configurations whose sign is known by construction (points in a plane, a plane lifted by a
// known offset), with coordinates of mixed magnitudes so that differences are not exact.
#include "geometry/exact_predicates.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace omnislice {
namespace {

using V = Eigen::Vector3d;

// The 3D determinant in long double (64-bit mantissa), for cases far from zero.
long double det3(const V& p, const V& q, const V& r, const V& s) {
  long double a[3], b[3], c[3];
  for (int k = 0; k < 3; ++k) {
    a[k] = (long double)q[k] - p[k];
    b[k] = (long double)r[k] - p[k];
    c[k] = (long double)s[k] - p[k];
  }
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

// Points of an axis plane with coordinates of mixed magnitudes (differences need up to 80 bits),
// permuted into any of the three axis planes: coplanar exactly, so every path must say 0; lifting
// the fourth point off the plane by +/- 2^-40 gives the sign of that lift times the 2D orientation.
TEST(ExactPredicates, OrientationsOfMixedMagnitudesAreExact) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-20, 40), axisPick(0, 2);
  size_t expandedCalls = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int k = axisPick(rng), i = (k + 1) % 3, j = (k + 2) % 3;
    const double level = std::ldexp(unit(rng), exponent(rng));
    std::array<V, 4> pts;
    for (V& p : pts) {
      p[i] = std::ldexp(unit(rng), exponent(rng));
      p[j] = std::ldexp(unit(rng), exponent(rng));
      p[k] = level;
    }
    // The 2D orientation of the first three in (i, j), exact.
    const int o2 = exact::orient2(pts[0], pts[1], pts[2], i, j);
    EXPECT_EQ(o2, exact::orient2Exact(pts[0], pts[1], pts[2], i, j));
    EXPECT_EQ(exact::orient3(pts[0], pts[1], pts[2], pts[3]), 0) << "trial " << trial;
    EXPECT_EQ(exact::orient3Exact(pts[0], pts[1], pts[2], pts[3]), 0);
    EXPECT_EQ(exact::orient3Expanded(pts[0], pts[1], pts[2], pts[3]), 0);
    ++expandedCalls;
    if (o2 == 0) continue;
    for (double lift : {std::ldexp(1.0, -40), -std::ldexp(1.0, -40)}) {
      V s = pts[3];
      s[k] = level + lift;
      if (s[k] == level) continue;  // the lift vanished in rounding at this level
      // det[q-p; r-p; s-p] = (s_k - level) * (2D orientation of p, q, r in (i, j)), i = k+1, j = k+2.
      const int expected = (s[k] > level ? 1 : -1) * o2;
      EXPECT_EQ(exact::orient3(pts[0], pts[1], pts[2], s), expected) << "trial " << trial;
      EXPECT_EQ(exact::orient3Expanded(pts[0], pts[1], pts[2], s), expected) << "trial " << trial;
      EXPECT_EQ(exact::orient3Exact(pts[0], pts[1], pts[2], s), expected) << "trial " << trial;
    }
  }
  EXPECT_EQ(expandedCalls, 2000u);
}

// Random points far from degenerate: the filter, both exact paths and a long-double determinant
// agree; swapping two points flips the sign.
TEST(ExactPredicates, GenericOrientationsAgreeWithTheDeterminant) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> coord(-50, 50);
  size_t decided = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    V p(coord(rng), coord(rng), coord(rng)), q(coord(rng), coord(rng), coord(rng)),
        r(coord(rng), coord(rng), coord(rng)), s(coord(rng), coord(rng), coord(rng));
    const long double d = det3(p, q, r, s);
    if (std::abs((double)d) < 1e-6) continue;
    const int expected = d > 0 ? 1 : -1;
    EXPECT_EQ(exact::orient3(p, q, r, s), expected);
    EXPECT_EQ(exact::orient3Exact(p, q, r, s), expected);
    EXPECT_EQ(exact::orient3Expanded(p, q, r, s), expected);
    EXPECT_EQ(exact::orient3(q, p, r, s), -expected);
    ++decided;
  }
  EXPECT_GT(decided, 4900u);
}

// Points exactly in an inclined plane (integer combinations of dyadic steps): 0, and off it by one
// unit in the last place of a coordinate: the sign of the normal's component along that axis.
TEST(ExactPredicates, InclinedPlaneAndOneUlpOff) {
  const V o(1.25, -3.5, 7.0), u(0.5, 0.25, 0.75), w(0.25, -0.5, 0.125);
  const V n = u.cross(w);  // exact: dyadic products
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> step(-40, 40);
  for (int trial = 0; trial < 1000; ++trial) {
    std::array<V, 4> pts;
    for (V& p : pts) p = o + double(step(rng)) * u + double(step(rng)) * w;
    const int o3 = exact::orient3(pts[0], pts[1], pts[2], pts[3]);
    EXPECT_EQ(o3, 0) << "trial " << trial;
    const V e1 = pts[1] - pts[0], e2 = pts[2] - pts[0];
    const double along = e1.cross(e2).dot(n);  // the orientation of the first three about n
    if (along == 0) continue;
    V s = pts[3];
    s.z() = std::nextafter(s.z(), 1e9);
    // det[e1; e2; s - p0] = (e1 x e2) . (s - p0) = (e1 x e2).z * (nudge) since s - p0 was in the plane.
    const double nz = e1.cross(e2).z();
    if (nz == 0) continue;
    EXPECT_EQ(exact::orient3(pts[0], pts[1], pts[2], s), nz > 0 ? 1 : -1) << "trial " << trial;
    EXPECT_EQ(exact::orient3Expanded(pts[0], pts[1], pts[2], s), nz > 0 ? 1 : -1) << "trial " << trial;
  }
}

TEST(ExactPredicates, CoordinateRange) {
  EXPECT_TRUE(exact::coordinatesInExactRange(std::vector<double>{0, 1, -1e29, 3e-29}));
  EXPECT_FALSE(exact::coordinatesInExactRange(std::vector<double>{1, 1e31}));
  EXPECT_FALSE(exact::coordinatesInExactRange(std::vector<double>{1e-31, 2}));
}

}  // namespace
}  // namespace omnislice
