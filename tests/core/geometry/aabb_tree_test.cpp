// SPDX-License-Identifier: MIT
#include "geometry/aabb_tree.h"

#include <gtest/gtest.h>

#include <random>

#include "../program/test_toolpaths.h"
#include "cgal/mesh_distance_reference.h"
#include "../test_meshes.h"
#include "../test_support.h"

namespace omnislice {
namespace {

// Brute force over every face of the mesh.
double bruteDistance(const Mesh& m, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d q =
        closestPointOnTriangle(p, m.vertex(m.triangles[3 * f]), m.vertex(m.triangles[3 * f + 1]),
                               m.vertex(m.triangles[3 * f + 2]));
    best = std::min(best, (q - p).norm());
  }
  return best;
}

TEST(AabbTree, ClosestPointOnTriangleMatchesDenseSampling) {
  // Independent of the region logic: the minimum over a dense barycentric lattice bounds the
  // exact distance from above, and is within the lattice resolution of it.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)),
        c(u(rng), u(rng), u(rng)), p(u(rng), u(rng), u(rng));
    const double exact = (closestPointOnTriangle(p, a, b, c) - p).norm();
    const int n = 200;
    double sampled = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Eigen::Vector3d q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        sampled = std::min(sampled, (q - p).norm());
      }
    const double edge = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
    EXPECT_LE(exact, sampled + 1e-12) << "trial " << trial;
    EXPECT_GE(exact, sampled - 2.0 * edge / n) << "trial " << trial;
  }
}

TEST(AabbTree, DistanceMatchesBruteForceOnRandomPoints) {
  const Mesh sphere = test::makeUvSphere(10, 40, 20, {1, 2, 3});
  const Mesh box = test::makeBox(-3, -2, 0, 4, 5, 6);
  for (const Mesh* m : {&sphere, &box}) {
    const AabbTree tree(*m);
    ASSERT_EQ(tree.triangleCount(), m->faceCount());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-15, 15);
    for (int i = 0; i < 500; ++i) {
      const Eigen::Vector3d p(u(rng), u(rng), u(rng));
      const double brute = bruteDistance(*m, p);
      const ClosestPoint c = tree.closest(p);
      EXPECT_NEAR(c.distance, brute, 1e-12);
      EXPECT_NEAR((c.point - p).norm(), brute, 1e-12);
      // Bounded queries agree with the unbounded distance.
      EXPECT_EQ(tree.anyWithin(p, brute + 1e-9), true);
      EXPECT_EQ(tree.anyWithin(p, brute - 1e-9), false);
      const ClosestPoint bounded = tree.closest(p, 0.5 * brute);
      EXPECT_TRUE(std::isinf(bounded.distance));
    }
  }
}

TEST(AabbTree, InsideMatchesAnalyticSphereAndBox) {
  const int slices = 48, stacks = 24;
  const double R = 10;
  const Eigen::Vector3d centre(0.3, -0.2, 11);
  const Mesh sphere = test::makeUvSphere(R, slices, stacks, centre);
  const AabbTree tree(sphere);
  // The polyhedron lies between the inscribed radius (cos of half the angular step, squared for
  // both directions) and R.
  const double inner = R * std::cos(M_PI / slices) * std::cos(M_PI / stacks);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-13, 13);
  int checked = 0;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::Vector3d p = centre + Eigen::Vector3d(u(rng), u(rng), u(rng));
    const double r = (p - centre).norm();
    if (r < inner - 1e-6) {
      EXPECT_TRUE(tree.inside(p)) << p.transpose();
      ++checked;
    } else if (r > R + 1e-6) {
      EXPECT_FALSE(tree.inside(p)) << p.transpose();
      ++checked;
    }
  }
  EXPECT_GT(checked, 3500);

  // Box: points on the grid of integer coordinates hit edges and vertices of the faces' projection
  // exactly; the half-open rule must still give the right answer.
  const AabbTree boxTree(test::makeBox(0, 0, 0, 10, 10, 10));
  for (int x = -1; x <= 11; ++x)
    for (int y = -1; y <= 11; ++y)
      for (double z : {-0.5, 0.5, 5.0, 9.5, 10.5}) {
        if (x == 0 || x == 10 || y == 0 || y == 10) continue;  // on the surface: undefined
        const bool in = x > 0 && x < 10 && y > 0 && y < 10 && z > 0 && z < 10;
        EXPECT_EQ(boxTree.inside({double(x), double(y), z}), in) << x << " " << y << " " << z;
      }
}

TEST(AabbTree, ColumnCrossingsBalancedOnEdgesAndVertices) {
  // Columns through the diagonal edges of the box's top and bottom faces (x == y) and through
  // the vertices: each interior column crosses exactly once down-facing, once up-facing.
  const AabbTree tree(test::makeBox(0, 0, 0, 10, 10, 10));
  std::vector<ColumnCrossing> xs;
  for (int x = -1; x <= 11; ++x) {
    for (int y = -1; y <= 11; ++y) {
      tree.columnCrossings(x, y, xs);
      int net = 0;
      for (const ColumnCrossing& c : xs) net += c.sign;
      EXPECT_EQ(net, 0) << x << "," << y;
      if (x > 0 && x < 10 && y > 0 && y < 10) {
        ASSERT_EQ(xs.size(), 2u) << x << "," << y;
        std::sort(xs.begin(), xs.end(), [](auto& a, auto& b) { return a.z < b.z; });
        EXPECT_EQ(xs[0].sign, +1);
        EXPECT_DOUBLE_EQ(xs[0].z, 0.0);
        EXPECT_EQ(xs[1].sign, -1);
        EXPECT_DOUBLE_EQ(xs[1].z, 10.0);
      }
    }
  }
}

TEST(AabbTree, AgreesWithCgalReference) {
  // Independent implementation: CGAL AABB_tree distances and Side_of_triangle_mesh.
  const Mesh sphere = test::makeUvSphere(8, 64, 32, {0, 0, 8});
  const Mesh box = test::makeBox(-4, -3, 0, 6, 3, 7);
  for (const Mesh* m : {&sphere, &box}) {
    const AabbTree tree(*m);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-10, 18);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 3000; ++i) pts.emplace_back(u(rng) - 4, u(rng) - 4, u(rng));
    const MeshDistanceReference ref = meshDistanceReference(*m, pts);
    ASSERT_TRUE(ref.ok()) << ref.message;
    for (size_t i = 0; i < pts.size(); ++i) {
      const double d = tree.closest(pts[i]).distance;
      EXPECT_NEAR(d, ref.distances[i], 1e-9) << pts[i].transpose();
      if (d > 1e-6) {
        EXPECT_EQ(tree.inside(pts[i]), ref.inside[i] == 1) << pts[i].transpose();
      }
    }
  }
}

}  // namespace
}  // namespace omnislice
