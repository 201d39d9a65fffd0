// SPDX-License-Identifier: MIT
// weldVertices: exact and tolerance welding against brute-force properties.
#include "mesh/weld_vertices.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace omnislice {
namespace {

double dist(const double* a, const double* b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

TEST(PrepareMeshWeld, ExactMergesBitIdenticalOnly) {
  Mesh m;
  m.positions = {1, 2, 3,  0.0, 5, 6,  1, 2, 3,  -0.0, 5, 6,  1, 2, std::nextafter(3.0, 4.0),
                 std::numeric_limits<double>::quiet_NaN(), 0, 0,  std::numeric_limits<double>::quiet_NaN(), 0, 0};
  const WeldResult w = weldVertices(m);
  EXPECT_EQ(w.remap, (std::vector<uint32_t>{0, 1, 0, 1, 2, 3, 4}));  // NaN vertices never merge
  EXPECT_EQ(w.merged, 2u);
  EXPECT_EQ(w.positions.size(), 15u);
  EXPECT_EQ(w.positions[5], 6.0);
}

// Tolerance weld: every vertex lies within the tolerance of its representative, and kept
// representatives are pairwise farther apart than the tolerance (checked O(n^2)).
TEST(PrepareMeshWeld, ToleranceMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1, 1);
  for (double tol : {0.01, 0.05, 0.2}) {
    Mesh m;
    for (int i = 0; i < 1500; ++i) {
      if (i > 0 && rng() % 4 == 0) {  // a near copy of an earlier point
        const size_t j = rng() % (m.positions.size() / 3);
        for (int k = 0; k < 3; ++k) m.positions.push_back(m.positions[3 * j + k] + 0.3 * tol * coord(rng));
      } else {
        for (int k = 0; k < 3; ++k) m.positions.push_back(coord(rng));
      }
    }
    const WeldResult w = weldVertices(m, tol);
    const size_t kept = w.positions.size() / 3;
    EXPECT_EQ(w.merged, m.vertexCount() - kept);
    for (size_t i = 0; i < m.vertexCount(); ++i) {
      ASSERT_LT(w.remap[i], kept);
      EXPECT_LE(dist(m.positions.data() + 3 * i, w.positions.data() + 3 * w.remap[i]), tol) << i;
    }
    for (size_t a = 0; a < kept; ++a) {
      for (size_t b = a + 1; b < kept; ++b) {
        ASSERT_GT(dist(w.positions.data() + 3 * a, w.positions.data() + 3 * b), tol) << a << " " << b;
      }
    }
    EXPECT_GT(w.merged, 100u);
  }
}

}  // namespace
}  // namespace omnislice
