// SPDX-License-Identifier: MIT
// Heat-method geodesic field on tets (paper 002 Section 2.1): operator properties, accuracy
// against analytic distances on boxes and cylinders under refinement, reuse, bad input, timings.
#include "geodesic/heat_geodesic.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <queue>
#include <sstream>
#include <string>

#include "../test_meshes.h"
#include "../test_support.h"

namespace omnislice {
namespace {

using test::gridTets;

TetMesh box(int n, double sx, double sy, double sz) {
  return gridTets(n, n, n, [&](double u, double v, double w) {
    return Eigen::Vector3d(u * sx, v * sy, w * sz);
  });
}

// Cylinder of radius r and height h: the square [-1, 1]^2 mapped onto the disc (elliptical
// square-to-disc map, smooth inside), n x n cells across, nz layers.
TetMesh cylinder(int n, int nz, double r, double h) {
  return gridTets(n, n, nz, [&](double u, double v, double w) {
    const double x = 2 * u - 1, y = 2 * v - 1;
    return Eigen::Vector3d(r * x * std::sqrt(1 - y * y / 2), r * y * std::sqrt(1 - x * x / 2),
                           w * h);
  });
}

double tetVolumeSum(const TetMesh& m) {
  double v = 0;
  for (size_t k = 0; k < m.tetCount(); ++k) {
    const Eigen::Vector3d a = m.vertex(m.tets[4 * k]);
    v += (m.vertex(m.tets[4 * k + 1]) - a)
             .dot((m.vertex(m.tets[4 * k + 2]) - a).cross(m.vertex(m.tets[4 * k + 3]) - a)) /
         6;
  }
  return v;
}

struct Errors {
  double mean = 0, max = 0;
};

Errors compare(const TetMesh& m, const std::vector<double>& d,
               const std::function<double(const Eigen::Vector3d&)>& exact,
               const std::function<bool(const Eigen::Vector3d&)>& include) {
  Errors e;
  size_t count = 0;
  for (size_t i = 0; i < m.vertexCount(); ++i) {
    const Eigen::Vector3d p = m.vertex(i);
    if (!include(p)) continue;
    const double err = std::abs(d[i] - exact(p));
    e.mean += err;
    e.max = std::max(e.max, err);
    ++count;
  }
  e.mean /= double(count);
  return e;
}

TEST(HeatGeodesic, LaplacianExactOnLinearFunctionsSymmetricZeroRowSums) {
  // A sheared, non-uniform box so the cotangent weights are not all the same.
  const TetMesh m = gridTets(4, 5, 6, [](double u, double v, double w) {
    return Eigen::Vector3d(10 * u + 2 * w, 7 * v * v + 3 * v, 5 * w + u);
  });
  const TetLaplacian lap = tetCotanLaplacian(m);
  ASSERT_TRUE(lap.ok()) << lap.message;
  const Eigen::MatrixXd L(lap.cotan);
  const Eigen::Index n = L.rows();
  EXPECT_LT((L - L.transpose()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(L.rowwise().sum().cwiseAbs().maxCoeff(), 1e-10);
  // Negative semi-definite with positive diagonal magnitude.
  for (Eigen::Index i = 0; i < n; ++i) EXPECT_LT(L(i, i), 0);
  // Interior vertices: L_c f = 0 for f = x, y, z, and an arbitrary linear function.
  Eigen::MatrixXd f(n, 4);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = m.vertex(size_t(i));
    f.row(i) << p.x(), p.y(), p.z(), 3 * p.x() - 2 * p.y() + 0.5 * p.z() + 7;
  }
  const Eigen::MatrixXd Lf = L * f;
  int interior = 0;
  for (int k = 1; k < 6; ++k)
    for (int j = 1; j < 5; ++j)
      for (int i = 1; i < 4; ++i) {
        const int v = (k * 6 + j) * 5 + i;
        EXPECT_LT(Lf.row(v).cwiseAbs().maxCoeff(), 1e-9) << "vertex " << v;
        ++interior;
      }
  EXPECT_EQ(interior, 3 * 4 * 5);
  // Independent check: Eq. 3 equals the P1 finite-element stiffness -vol grad(l_i).grad(l_j).
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (size_t k = 0; k < m.tetCount(); ++k) {
    Eigen::Matrix3d E;
    const Eigen::Vector3d a = m.vertex(m.tets[4 * k]);
    for (int c = 0; c < 3; ++c) E.row(c) = (m.vertex(m.tets[4 * k + 1 + c]) - a).transpose();
    const Eigen::Matrix3d Einv = E.inverse();  // columns: gradients of barycentrics 1..3
    Eigen::Matrix<double, 3, 4> G;
    G.col(0) = -Einv.rowwise().sum();
    G.rightCols<3>() = Einv;
    const double vol = std::abs(E.determinant()) / 6;
    const Eigen::Matrix4d local = vol * G.transpose() * G;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) K(m.tets[4 * k + r], m.tets[4 * k + c]) += local(r, c);
  }
  EXPECT_LT((L + K).cwiseAbs().maxCoeff(), 1e-10 * K.cwiseAbs().maxCoeff());
}

TEST(HeatGeodesic, VertexVolumesSumToMeshVolume) {
  const TetMesh c = cylinder(8, 5, 10, 20);
  const TetLaplacian lap = tetCotanLaplacian(c);
  ASSERT_TRUE(lap.ok());
  double sum = 0;
  for (double v : lap.vertexVolume) sum += v;
  const double volume = tetVolumeSum(c);
  EXPECT_NEAR(sum, volume, 1e-9 * volume);
  // The mapped disc approaches pi r^2 h from below.
  EXPECT_GT(volume, 0.9 * M_PI * 100 * 20);
  EXPECT_LT(volume, M_PI * 100 * 20);
  const TetMesh b = box(3, 2, 3, 4);
  const TetLaplacian lb = tetCotanLaplacian(b);
  sum = 0;
  for (double v : lb.vertexVolume) sum += v;
  EXPECT_NEAR(sum, 24.0, 1e-12);
  // Mean edge: box of 3^3 cubes of 1 x 1 x 1 ... here cells are (2/3, 1, 4/3): all edges positive.
  EXPECT_GT(lb.meanEdge, 2.0 / 3);
}

TEST(HeatGeodesic, PlatformVerticesAreTheBottomFace) {
  const TetMesh b = box(4, 10, 10, 10);
  const std::vector<uint32_t> p = platformVertices(b);
  EXPECT_EQ(p.size(), 25u);
  for (uint32_t v : p) EXPECT_EQ(b.vertex(v).z(), 0);
  // A vertex not in any tet below the platform is not a boundary vertex: ignored.
  TetMesh extra = b;
  extra.positions.insert(extra.positions.end(), {5, 5, -3});
  EXPECT_EQ(platformVertices(extra).size(), 25u);
  EXPECT_TRUE(platformVertices(TetMesh{}).empty());
}

TEST(HeatGeodesic, BoxBottomFaceDistanceIsHeightAndConverges) {
  // Distance from the bottom face of a 20 x 20 x 30 mm box is z.
  // Stated bounds per resolution (measured mean / max: 0.142 / 1.173, 0.047 / 0.547,
  // 0.023 / 0.348 mm), about 15 % above the measurements. (Solving Eq. 9 free and shifting the
  // sources' mean to 0, as before the sources were held at 0: 0.214 / 1.194, 0.065 / 0.564,
  // 0.031 / 0.380 mm.)
  const double meanBound[3] = {0.163, 0.054, 0.027}, maxBound[3] = {1.35, 0.63, 0.40};
  double lastMean = 1e9, lastMax = 1e9;
  int r = 0;
  for (int n : {6, 12, 18}) {
    const TetMesh m = box(n, 20, 20, 30);
    const HeatGeodesic hg(m);
    ASSERT_TRUE(hg.status().ok()) << hg.status().message;
    const GeodesicField f = hg.distanceFrom(platformVertices(m));
    ASSERT_TRUE(f.ok()) << f.message;
    const Errors e = compare(
        m, f.distance, [](const Eigen::Vector3d& p) { return p.z(); },
        [](const Eigen::Vector3d&) { return true; });
    std::printf("box %d^3 (%zu tets) bottom face: mean error %.4f mm, max %.4f mm, max distance "
                "%.3f (height 30), iterations heat %d Poisson %d\n",
                n, m.tetCount(), e.mean, e.max, f.maxDistance, f.heatIterations,
                f.poissonIterations);
    EXPECT_LT(e.mean, meanBound[r]);
    EXPECT_LT(e.max, maxBound[r]);
    ++r;
    EXPECT_LT(e.mean, lastMean);
    EXPECT_LE(e.max, lastMax * 1.0001);
    EXPECT_NEAR(f.maxDistance, 30, 0.04 * 30);
    lastMean = e.mean;
    lastMax = e.max;
  }
}

TEST(HeatGeodesic, CylinderBottomFaceDistanceMonotoneAlongAxis) {
  // Stated bounds per resolution (measured mean / max: 0.075 / 0.428, 0.031 / 0.202 mm; shifted
  // instead of held: 0.109 / 0.471, 0.040 / 0.237 mm).
  const double meanBound[2] = {0.087, 0.036}, maxBound[2] = {0.49, 0.232};
  double lastMean = 1e9, lastMax = 1e9;
  int r = 0;
  for (int n : {6, 12}) {
    const TetMesh m = cylinder(n, 2 * n, 8, 40);
    const HeatGeodesic hg(m);
    ASSERT_TRUE(hg.status().ok()) << hg.status().message;
    const GeodesicField f = hg.distanceFrom(platformVertices(m));
    ASSERT_TRUE(f.ok()) << f.message;
    const Errors e = compare(
        m, f.distance, [](const Eigen::Vector3d& p) { return p.z(); },
        [](const Eigen::Vector3d&) { return true; });
    std::printf("cylinder r 8 h 40, %d x %d x %d (%zu tets): mean error %.4f mm, max %.4f mm, "
                "max distance %.3f\n",
                n, n, 2 * n, m.tetCount(), e.mean, e.max, f.maxDistance);
    EXPECT_EQ(platformVertices(m).size(), size_t((n + 1) * (n + 1)));
    EXPECT_LT(e.mean, meanBound[r]);
    EXPECT_LT(e.max, maxBound[r]);
    ++r;
    EXPECT_LT(e.mean, lastMean);
    EXPECT_LT(e.max, lastMax);
    lastMean = e.mean;
    lastMax = e.max;
    EXPECT_NEAR(f.maxDistance, 40, 0.04 * 40);
    // Monotone along the axis (the grid's central column, i = j = n/2) and along every column.
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        for (int k = 1; k <= 2 * n; ++k) {
          const size_t a = size_t(((k - 1) * (n + 1) + j) * (n + 1) + i);
          const size_t b = size_t((k * (n + 1) + j) * (n + 1) + i);
          EXPECT_GT(f.distance[b], f.distance[a]) << "column " << i << "," << j << " layer " << k;
        }
  }
}

TEST(HeatGeodesic, CornerPointSourceMatchesEuclideanDistance) {
  // Stated bounds per resolution beyond 2.5 mm of the source (measured mean / max: 0.331 / 1.211,
  // 0.166 / 0.852 mm on a 17.3 mm diagonal).
  const double meanBound[2] = {0.38, 0.19}, maxBound[2] = {1.4, 0.98};
  double lastMean = 1e9, lastMax = 1e9;
  int r = 0;
  for (int n : {8, 16}) {
    const TetMesh m = box(n, 10, 10, 10);
    const HeatGeodesic hg(m);
    ASSERT_TRUE(hg.status().ok());
    const GeodesicField f = hg.distanceFrom({0});  // vertex 0 is the corner (0, 0, 0)
    ASSERT_TRUE(f.ok()) << f.message;
    EXPECT_EQ(f.distance[0], 0);
    const Errors e = compare(
        m, f.distance, [](const Eigen::Vector3d& p) { return p.norm(); },
        [](const Eigen::Vector3d& p) { return p.norm() > 2.5; });
    std::printf("box %d^3 corner source: mean error %.4f mm, max %.4f mm (beyond 2.5 mm; "
                "diagonal %.3f, max distance %.3f)\n",
                n, e.mean, e.max, std::sqrt(300.0), f.maxDistance);
    EXPECT_LT(e.mean, meanBound[r]);
    EXPECT_LT(e.max, maxBound[r]);
    ++r;
    EXPECT_LT(e.mean, lastMean);
    EXPECT_LT(e.max, lastMax);
    lastMean = e.mean;
    lastMax = e.max;
  }
}

TEST(HeatGeodesic, ReuseEqualsFreshObject) {
  const TetMesh m = box(8, 10, 12, 14);
  HeatGeodesic reused(m);
  ASSERT_TRUE(reused.status().ok());
  const GeodesicField first = reused.distanceFrom(platformVertices(m));
  ASSERT_TRUE(first.ok());
  const std::vector<uint32_t> second = {100, 200, uint32_t(m.vertexCount() - 1)};
  const GeodesicField again = reused.distanceFrom(second);
  const GeodesicField fresh = HeatGeodesic(m).distanceFrom(second);
  ASSERT_TRUE(again.ok() && fresh.ok());
  ASSERT_EQ(again.distance.size(), fresh.distance.size());
  for (size_t i = 0; i < fresh.distance.size(); ++i)
    EXPECT_NEAR(again.distance[i], fresh.distance[i], 1e-9);
  // And the second source set really differs from the first field.
  double diff = 0;
  for (size_t i = 0; i < fresh.distance.size(); ++i)
    diff = std::max(diff, std::abs(fresh.distance[i] - first.distance[i]));
  EXPECT_GT(diff, 1.0);
  // Moved-to object still works.
  HeatGeodesic moved = std::move(reused);
  EXPECT_TRUE(moved.distanceFrom(second).ok());
}

// Sources taken within a tolerance of the platform (here the bottom face and the side walls'
// first row, 2.5 mm up) are held at their given distance, exactly their height. The heat step
// still spreads from the first row sideways, so the field is less accurate than from the bottom
// face alone (measured mean error 0.20 against 0.047 mm), but held at 0 the first row pulls the
// whole field down by about its height (1.02 mm). The pipeline takes a quarter interval.
TEST(HeatGeodesic, SourcesHeldAtTheirDistance) {
  const TetMesh m = box(12, 20, 20, 30);
  const HeatGeodesic hg(m);
  ASSERT_TRUE(hg.status().ok()) << hg.status().message;
  const std::vector<uint32_t> bottom = platformVertices(m), rows = platformVertices(m, 2.6);
  ASSERT_GT(rows.size(), bottom.size());
  const std::vector<double> heights = heightsAboveLowest(m, rows);
  const GeodesicField base = hg.distanceFrom(bottom), held = hg.distanceFrom(rows, heights),
                      zero = hg.distanceFrom(rows);
  ASSERT_TRUE(base.ok() && held.ok() && zero.ok()) << held.message << zero.message;
  for (size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(held.distance[rows[k]], heights[k]);
    EXPECT_EQ(heights[k], m.positions[3 * rows[k] + 2]);
    EXPECT_EQ(zero.distance[rows[k]], 0.0);
  }
  auto height = [](const Eigen::Vector3d& p) { return p.z(); };
  auto all = [](const Eigen::Vector3d&) { return true; };
  const Errors eb = compare(m, base.distance, height, all), eh = compare(m, held.distance, height, all),
               ez = compare(m, zero.distance, height, all);
  std::printf("box 12^3: mean error from the bottom face %.4f mm, from two rows held at their "
              "heights %.4f mm, held at 0 %.4f mm\n", eb.mean, eh.mean, ez.mean);
  EXPECT_LT(eh.mean, 0.25 * ez.mean);
  EXPECT_LT(eb.mean, eh.mean);
  // One distance per source, finite and >= 0.
  EXPECT_EQ(hg.distanceFrom(rows, std::vector<double>(rows.size() - 1, 0.0)).status,
            Status::InvalidOption);
  std::vector<double> bad = heights;
  bad[0] = -1;
  EXPECT_EQ(hg.distanceFrom(rows, bad).status, Status::InvalidOption);
  bad[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(hg.distanceFrom(rows, bad).status, Status::InvalidOption);
}

TEST(HeatGeodesic, BadInputReturnsStatus) {
  const TetMesh m = box(4, 10, 10, 10);
  const HeatGeodesic hg(m);
  ASSERT_TRUE(hg.status().ok());
  EXPECT_EQ(hg.distanceFrom({}).status, Status::InvalidOption);
  const GeodesicField out = hg.distanceFrom({0, uint32_t(m.vertexCount())});
  EXPECT_EQ(out.status, Status::InvalidOption);
  EXPECT_FALSE(out.message.empty());
  EXPECT_TRUE(out.distance.empty());

  const HeatGeodesic empty{TetMesh{}};
  EXPECT_EQ(empty.status().status, Status::DegenerateInput);
  EXPECT_EQ(empty.distanceFrom({0}).status, Status::DegenerateInput);

  TetMesh badIndex = m;
  badIndex.tets[5] = 100000;
  EXPECT_EQ(HeatGeodesic(badIndex).status().status, Status::DegenerateInput);
  TetMesh flat = m;
  flat.tets[1] = flat.tets[0];  // repeated vertex: zero volume
  EXPECT_EQ(HeatGeodesic(flat).status().status, Status::DegenerateInput);
  TetMesh nan = m;
  nan.positions[4] = std::nan("");
  EXPECT_EQ(HeatGeodesic(nan).status().status, Status::DegenerateInput);
  HeatGeodesicOptions bad;
  bad.timeFactor = 0;
  EXPECT_EQ(HeatGeodesic(m, bad).status().status, Status::InvalidOption);
  bad = {};
  bad.tolerance = 2;
  EXPECT_EQ(HeatGeodesic(m, bad).status().status, Status::InvalidOption);
  for (double t : {0.0, 1.0, std::nan("")}) {
    bad = {};
    bad.heatTolerance = t;
    EXPECT_EQ(HeatGeodesic(m, bad).status().status, Status::InvalidOption) << t;
  }

  // Cancel: at the start, and in the middle of the solves (after the heat stage).
  int calls = 0;
  const GeodesicField c0 = hg.distanceFrom({0}, [&](const char* stage, double) {
    EXPECT_STREQ(stage, "field");
    ++calls;
    return false;
  });
  EXPECT_EQ(c0.status, Status::Cancelled);
  EXPECT_EQ(calls, 1);
  const GeodesicField c1 =
      hg.distanceFrom({0}, [&](const char*, double fraction) { return fraction < 0.5; });
  EXPECT_EQ(c1.status, Status::Cancelled);
  // Too few iterations: Internal, not a wrong field.
  HeatGeodesicOptions few;
  few.maxIterations = 2;
  EXPECT_EQ(HeatGeodesic(m, few).distanceFrom({0}).status, Status::Internal);
  // Negatively oriented tets are accepted and give the same field.
  TetMesh flipped = m;
  for (size_t k = 0; k < flipped.tetCount(); k += 2) std::swap(flipped.tets[4 * k], flipped.tets[4 * k + 1]);
  const GeodesicField a = hg.distanceFrom({0}), b = HeatGeodesic(flipped).distanceFrom({0});
  ASSERT_TRUE(a.ok() && b.ok());
  for (size_t i = 0; i < a.distance.size(); ++i) EXPECT_NEAR(a.distance[i], b.distance[i], 1e-9);
}

TEST(HeatGeodesic, UnusedVerticesAndSecondComponentDoNotDisturbTheField) {
  const TetMesh a = box(5, 10, 10, 10), other = box(4, 8, 9, 12);
  TetMesh two = a;
  const uint32_t offset = uint32_t(a.vertexCount());
  for (size_t i = 0; i < other.vertexCount(); ++i)
    two.positions.insert(two.positions.end(), {other.positions[3 * i] + 30,
                                               other.positions[3 * i + 1] - 7,
                                               other.positions[3 * i + 2] + 0.5});
  for (uint32_t v : other.tets) two.tets.push_back(v + offset);
  two.positions.insert(two.positions.end(), {-50, -50, -50});  // in no tet
  const uint32_t unused = uint32_t(two.vertexCount() - 1);
  const HeatGeodesic hg(two);
  ASSERT_TRUE(hg.status().ok()) << hg.status().message;
  const GeodesicField f = hg.distanceFrom(platformVertices(a));
  // t = h^2 uses the mean edge of the whole mesh: give the references the same t.
  const double h = tetCotanLaplacian(two).meanEdge;
  auto sameTime = [h](const TetMesh& part) {
    HeatGeodesicOptions o;
    o.timeFactor = std::pow(h / tetCotanLaplacian(part).meanEdge, 2);
    return o;
  };
  const GeodesicField ref = HeatGeodesic(a, sameTime(a)).distanceFrom(platformVertices(a));
  ASSERT_TRUE(f.ok() && ref.ok()) << f.message;
  for (size_t i = 0; i < a.vertexCount(); ++i) EXPECT_NEAR(f.distance[i], ref.distance[i], 1e-6);
  for (size_t i = offset; i < two.vertexCount(); ++i) EXPECT_EQ(f.distance[i], 0);  // no heat
  EXPECT_NEAR(f.maxDistance, ref.maxDistance, 1e-6);
  // Sources in both components: each component gets its own bottom-face field.
  std::vector<uint32_t> both = platformVertices(a);
  const GeodesicField refOther =
      HeatGeodesic(other, sameTime(other)).distanceFrom(platformVertices(other));
  for (uint32_t v : platformVertices(other)) both.push_back(v + offset);
  const GeodesicField g = hg.distanceFrom(both);
  ASSERT_TRUE(g.ok() && refOther.ok());
  for (size_t i = 0; i < a.vertexCount(); ++i) EXPECT_NEAR(g.distance[i], ref.distance[i], 1e-6);
  for (size_t i = 0; i < other.vertexCount(); ++i)
    EXPECT_NEAR(g.distance[i + offset], refOther.distance[i], 1e-6);
  EXPECT_NEAR(g.maxDistance, std::max(ref.maxDistance, refOther.maxDistance), 1e-6);
  EXPECT_EQ(hg.distanceFrom({unused}).status, Status::InvalidOption);
}

TEST(HeatGeodesic, TimingsOn64kTets) {
  const TetMesh m = box(22, 50, 50, 50);
  ASSERT_EQ(m.tetCount(), 63888u);
  const HeatGeodesic hg(m);
  ASSERT_TRUE(hg.status().ok());
  const GeodesicField f = hg.distanceFrom(platformVertices(m));
  ASSERT_TRUE(f.ok());
  const GeodesicField g = hg.distanceFrom({0});
  ASSERT_TRUE(g.ok());
  for (const GeodesicField* r : {&f, &g})
    std::printf("22^3 box, 63,888 tets, %zu vertices: setup %.1f ms, heat %.1f ms (%d it), "
                "gradient %.1f ms, Poisson %.1f ms (%d it), field total %.1f ms\n",
                m.vertexCount(), r->setupMs, r->heatMs, r->heatIterations, r->gradientMs,
                r->poissonMs, r->poissonIterations, r->heatMs + r->gradientMs + r->poissonMs);
  const Errors e = compare(
      m, f.distance, [](const Eigen::Vector3d& p) { return p.z(); },
      [](const Eigen::Vector3d&) { return true; });
  std::printf("22^3 box bottom face: mean error %.4f mm, max %.4f mm\n", e.mean, e.max);
  EXPECT_LT(e.mean, 0.015 * 50);
}

// Minimal `.tet` reader for the test (the project's reader belongs to tet_mesh.cpp).
TetMesh loadTet(const std::filesystem::path& path) {
  std::ifstream in(path);
  TetMesh m;
  size_t nv = 0, nt = 0;
  std::string word;
  in >> nv >> word >> nt >> word;
  m.positions.resize(3 * nv);
  for (double& c : m.positions) in >> c;
  m.tets.resize(4 * nt);
  for (size_t k = 0; k < nt; ++k) {
    int four = 0;
    in >> four >> m.tets[4 * k] >> m.tets[4 * k + 1] >> m.tets[4 * k + 2] >> m.tets[4 * k + 3];
  }
  return in ? m : TetMesh{};
}

// Shortest paths along tet edges from the sources: an upper bound of the true distance in the solid
// (for a convex solid's interior the straight segment to the nearest source is a lower bound).
std::vector<double> edgeDijkstra(const TetMesh& m, const std::vector<uint32_t>& sources) {
  std::vector<std::vector<uint32_t>> adj(m.vertexCount());
  for (size_t k = 0; k < m.tetCount(); ++k)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        if (a != b) adj[m.tets[4 * k + a]].push_back(m.tets[4 * k + b]);
  std::vector<double> d(m.vertexCount(), 1e300);
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  for (uint32_t s : sources) {
    d[s] = 0;
    q.push({0, s});
  }
  while (!q.empty()) {
    const auto [dist, v] = q.top();
    q.pop();
    if (dist > d[v]) continue;
    for (uint32_t w : adj[v]) {
      const double nd = dist + (m.vertex(v) - m.vertex(w)).norm();
      if (nd < d[w]) {
        d[w] = nd;
        q.push({nd, w});
      }
    }
  }
  return d;
}

TEST(HeatGeodesic, RealTetModelsBoundedByEdgePathsAndTimed) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* name : {"reinforcedfdm_YogaNew.tet", "reinforcedfdm_bunnyhead.tet",
                           "reinforcedfdm_topopt_new.tet"}) {
    const TetMesh m = loadTet(test::sharedModelsDir() / name);
    ASSERT_GT(m.tetCount(), 50000u) << name;
    const HeatGeodesic hg(m);
    ASSERT_TRUE(hg.status().ok()) << name << ": " << hg.status().message;
    const std::vector<uint32_t> sources = platformVertices(m, 1.0);
    ASSERT_GT(sources.size(), 3u) << name;
    const GeodesicField f = hg.distanceFrom(sources);
    ASSERT_TRUE(f.ok()) << name << ": " << f.message;
    const std::vector<double> upper = edgeDijkstra(m, sources);
    // Lower bound: Euclidean distance to the nearest source (straight lines are shortest).
    double meanRatio = 0, worstOver = 0, worstUnder = 0, upperMax = 0;
    size_t count = 0;
    for (size_t i = 0; i < m.vertexCount(); ++i) {
      double lower = 1e300;
      for (uint32_t s : sources) lower = std::min(lower, (m.vertex(i) - m.vertex(s)).norm());
      upperMax = std::max(upperMax, upper[i]);
      worstOver = std::max(worstOver, f.distance[i] - upper[i]);
      worstUnder = std::max(worstUnder, lower - f.distance[i]);
      if (upper[i] > 5) {
        meanRatio += f.distance[i] / upper[i];
        ++count;
      }
    }
    meanRatio /= double(count);
    std::printf("%s: %zu tets, %zu vertices, %zu sources; setup %.1f ms, heat %.1f ms (%d it), "
                "gradient %.1f ms, Poisson %.1f ms (%d it); max distance %.2f (edge paths %.2f); "
                "mean heat/edge-path ratio %.3f; above edge paths by <= %.3f mm, below Euclidean by "
                "<= %.3f mm\n",
                name, m.tetCount(), m.vertexCount(), sources.size(), f.setupMs, f.heatMs,
                f.heatIterations, f.gradientMs, f.poissonMs, f.poissonIterations, f.maxDistance,
                upperMax, meanRatio, worstOver, worstUnder);
    // Edge paths overestimate the distance by a few percent; the heat field sits between the
    // Euclidean lower bound and the edge-path upper bound up to the method's smoothing near the
    // sources and sharp features (measured: mean ratio 0.978-0.983, above the edge paths by at
    // most 2.6-5.5 mm = 1.9-3.0 % of the range, below the Euclidean bound by at most 1.6-3.0 mm).
    EXPECT_GT(meanRatio, 0.95) << name;
    EXPECT_LT(meanRatio, 1.0) << name;
    EXPECT_LT(worstOver, 0.04 * upperMax) << name;
    EXPECT_LT(worstUnder, 0.025 * upperMax) << name;
    EXPECT_LT(f.maxDistance, 1.01 * upperMax) << name;
    EXPECT_GT(f.maxDistance, 0.95 * upperMax) << name;
  }
}

// The default heat solve (ordered Gauss-Seidel sweeps) against the direct LDLT solve: the same
// distances also where the heat is exponentially small.
void expectSweepsEqualDirect(const std::string& name, const TetMesh& mesh,
                             const std::vector<uint32_t>& sources) {
  HeatGeodesicOptions direct;
  direct.heatSolver = HeatSolver::Direct;
  const GeodesicField a = HeatGeodesic(mesh).distanceFrom(sources);
  const GeodesicField b = HeatGeodesic(mesh, direct).distanceFrom(sources);
  ASSERT_TRUE(a.ok() && b.ok()) << name << ": " << a.message << b.message;
  double worst = 0;
  for (size_t i = 0; i < a.distance.size(); ++i)
    worst = std::max(worst, std::abs(a.distance[i] - b.distance[i]));
  std::printf("%s: sweeps %d (heat %.1f ms) vs LDLT (setup %.1f ms, heat %.1f ms): max distance "
              "%.3f mm, largest difference %.2e mm\n",
              name.c_str(), a.heatIterations, a.heatMs, b.setupMs, b.heatMs, a.maxDistance, worst);
  EXPECT_GT(a.heatIterations, 0) << name;
  EXPECT_EQ(b.heatIterations, 0) << name;
  EXPECT_LT(worst, 1e-6 * a.maxDistance) << name;
}

TEST(HeatGeodesic, SweepsEqualTheDirectSolveFromACorner) {
  // A point source: the far corner is ~50 edges away, where u ~ e^-50.
  expectSweepsEqualDirect("16^3 box, corner source", box(16, 40, 40, 40), {0});
  const TetMesh b = box(16, 40, 40, 40);
  expectSweepsEqualDirect("16^3 box, bottom face", b, platformVertices(b));
}

TEST(HeatGeodesic, SweepsEqualTheDirectSolveOnRealTetModels) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* name : {"reinforcedfdm_YogaNew.tet", "reinforcedfdm_bunnyhead.tet"}) {
    const TetMesh m = loadTet(test::sharedModelsDir() / name);
    expectSweepsEqualDirect(name, m, platformVertices(m, 1.0));
  }
}

// |grad phi| per tet (1 for a distance): the share outside [2/3, 3/2], where iso-surfaces one
// interval apart in phi lie more than 1.5 or less than 2/3 intervals apart in space.
double unevenShare(const TetMesh& m, const std::vector<double>& phi) {
  size_t uneven = 0;
  for (size_t k = 0; k < m.tetCount(); ++k) {
    const uint32_t* t = &m.tets[4 * k];
    Eigen::Matrix3d a;
    Eigen::Vector3d b;
    for (int r = 0; r < 3; ++r) {
      a.row(r) = (m.vertex(t[r + 1]) - m.vertex(t[0])).transpose();
      b[r] = phi[t[r + 1]] - phi[t[0]];
    }
    const double g = a.fullPivLu().solve(b).norm();
    uneven += g < 2.0 / 3.0 || g > 1.5;
  }
  return double(uneven) / double(m.tetCount());
}

// One renormalisation pass (X from phi's own gradient, Eq. 9 again) evens the layer spacing from
// a broad source: fewer tets whose slope is off by more than half, and a smaller error against the
// exact distance from a box's bottom face (0.047 -> 0.040 mm at 12^3) and on the shared tet models
// from their flat base.
TEST(HeatGeodesic, RenormalisationEvensTheSpacing) {
  HeatGeodesicOptions once;
  once.renormalizations = 1;
  {
    const TetMesh m = box(12, 20, 20, 30);
    const std::vector<uint32_t> src = platformVertices(m);
    const GeodesicField f0 = HeatGeodesic(m).distanceFrom(src), f1 = HeatGeodesic(m, once).distanceFrom(src);
    ASSERT_TRUE(f0.ok() && f1.ok());
    auto height = [](const Eigen::Vector3d& p) { return p.z(); };
    auto all = [](const Eigen::Vector3d&) { return true; };
    const Errors e0 = compare(m, f0.distance, height, all), e1 = compare(m, f1.distance, height, all);
    std::printf("box 12^3 bottom face: mean error %.4f -> %.4f mm, max %.4f -> %.4f mm\n", e0.mean,
                e1.mean, e0.max, e1.max);
    EXPECT_LT(e1.mean, 0.9 * e0.mean);
    EXPECT_LT(e1.max, e0.max);
    for (uint32_t s : src) EXPECT_EQ(f1.distance[s], 0.0);
  }
  HeatGeodesicOptions bad;
  bad.renormalizations = 11;
  EXPECT_EQ(HeatGeodesic(box(2, 1, 1, 1), bad).status().status, Status::InvalidOption);
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* name : {"reinforcedfdm_YogaNew.tet", "reinforcedfdm_bunnyhead.tet"}) {
    const TetMesh m = loadTet(test::sharedModelsDir() / name);
    const std::vector<uint32_t> src = platformVertices(m, 1.0);
    const std::vector<double> held = heightsAboveLowest(m, src);
    const GeodesicField f0 = HeatGeodesic(m).distanceFrom(src, held),
                        f1 = HeatGeodesic(m, once).distanceFrom(src, held);
    ASSERT_TRUE(f0.ok() && f1.ok()) << name;
    const double u0 = unevenShare(m, f0.distance), u1 = unevenShare(m, f1.distance);
    std::printf("%s: tets with |grad phi| outside [2/3, 3/2]: %.2f %% -> %.2f %%; max distance "
                "%.2f -> %.2f mm\n", name, 100 * u0, 100 * u1, f0.maxDistance, f1.maxDistance);
    EXPECT_LT(u1, 0.5 * u0) << name;
  }
}

}  // namespace
}  // namespace omnislice
