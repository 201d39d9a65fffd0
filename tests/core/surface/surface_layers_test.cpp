// SPDX-License-Identifier: MIT
// Layer-thickness statistics (paper 001 Fig. 15) on synthetic layer stacks with known spacings;
// regions clipped by a scalar (partial layers), per-layer thickness behind partial layers.
#include "surface/surface_layers.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace omnislice {
namespace {

// A flat square [x0, x0 + size]^2 at height z as an n x n grid of quads (2 triangles each).
LayerRegion square(double x0, double size, double z, int n) {
  LayerRegion r;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      r.mesh.positions.insert(r.mesh.positions.end(), {x0 + size * i / n, x0 + size * j / n, z});
  auto id = [&](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      r.mesh.triangles.insert(r.mesh.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      r.mesh.triangles.insert(r.mesh.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  r.boundaryVertex.assign(r.mesh.vertexCount(), 0);
  r.area = size * size;
  return r;
}

CurvedLayer flatLayer(double z, double size = 10, int n = 7) {
  CurvedLayer l;
  l.isoValue = z;
  l.regions.push_back(square(0, size, z, n));
  return l;
}

size_t total(const ThicknessStats& s) {
  return std::accumulate(s.histogram.begin(), s.histogram.end(), size_t{0});
}

TEST(SurfaceLayers, UniformSpacingHasZeroDeviation) {
  std::vector<CurvedLayer> layers;
  for (int i = 0; i < 6; ++i) layers.push_back(flatLayer(0.3 * i));
  const ThicknessStats s = layerThicknessStats(layers, 0.5);
  // 5 layers after the first, 100 mm^2 each, one sample per 0.25 mm^2.
  EXPECT_NEAR(static_cast<double>(s.samples), 5 * 400.0, 5.0);
  EXPECT_NEAR(s.mean, 0.3, 1e-12);
  EXPECT_LT(s.stddev, 1e-12);
  EXPECT_LT(s.maxDeviation, 1e-12);
  EXPECT_EQ(total(s), s.samples);
  // Zero deviation lands mid-bin: bins centred on multiples of the width.
  ASSERT_EQ(s.histogram.size(), 1u);
  EXPECT_NEAR(s.histogramMin, -0.5 * s.histogramBin, 1e-15);
  EXPECT_NEAR(s.histogramBin, 0.05 * 0.3, 1e-12);
}

TEST(SurfaceLayers, AlternatingSpacingFillsTwoBins) {
  // Planes at 0, 1, 3, 4, 6, 7, 9: spacings 1, 2, 1, 2, 1, 2; mean 1.5, deviations -0.5 / +0.5.
  std::vector<CurvedLayer> layers;
  for (double z : {0.0, 1.0, 3.0, 4.0, 6.0, 7.0, 9.0}) layers.push_back(flatLayer(z));
  const ThicknessStats s = layerThicknessStats(layers, 0.5);
  EXPECT_NEAR(s.mean, 1.5, 1e-9);
  EXPECT_NEAR(s.stddev, 0.5, 1e-9);
  EXPECT_NEAR(s.maxDeviation, 0.5, 1e-9);
  EXPECT_EQ(total(s), s.samples);
  auto binOf = [&](double dev) {
    return static_cast<size_t>(std::floor((dev - s.histogramMin) / s.histogramBin));
  };
  ASSERT_LT(binOf(0.5), s.histogram.size());
  EXPECT_EQ(s.histogram[binOf(-0.5)] + s.histogram[binOf(0.5)], s.samples);
  EXPECT_EQ(s.histogram[binOf(-0.5)], s.histogram[binOf(0.5)]);
  EXPECT_EQ(s.histogram.front(), s.histogram[binOf(-0.5)]);
  EXPECT_EQ(s.histogram.back(), s.histogram[binOf(0.5)]);
  for (size_t k = 0; k < s.histogram.size(); ++k)
    if (k != binOf(-0.5) && k != binOf(0.5)) {
      EXPECT_EQ(s.histogram[k], 0u) << k;
    }
}

TEST(SurfaceLayers, TiltedPlaneDistanceIsPerpendicular) {
  // A square tilted by 30 degrees over a horizontal one, z = 1 + slope x over the same footprint:
  // every sample's nearest point on the lower square is straight below it, so the distances are
  // 1 + slope x with x uniform in [0, 10]; compare with those exact moments.
  CurvedLayer base = flatLayer(0, 10, 10);
  CurvedLayer tilted;
  LayerRegion r = square(0, 10, 0, 10);
  const double slope = std::tan(M_PI / 6);
  for (size_t v = 0; v < r.mesh.vertexCount(); ++v)
    r.mesh.positions[3 * v + 2] = 1.0 + slope * r.mesh.positions[3 * v];
  r.area = 100 / std::cos(M_PI / 6);
  tilted.regions.push_back(r);
  const ThicknessStats s = layerThicknessStats({base, tilted}, 0.2);
  // Heights 1 + slope * x over x in [0, 10]; mean 1 + 5 slope.
  EXPECT_NEAR(s.mean, 1 + 5 * slope, 0.02);
  EXPECT_NEAR(s.maxDeviation, 5 * slope, 0.05);
  EXPECT_NEAR(s.stddev, 10 * slope / std::sqrt(12.0), 0.02);  // uniform spread
  EXPECT_EQ(total(s), s.samples);
}

TEST(SurfaceLayers, DegenerateInputsGiveEmptyStats) {
  EXPECT_EQ(layerThicknessStats({}, 0.5).samples, 0u);
  EXPECT_EQ(layerThicknessStats({flatLayer(0)}, 0.5).samples, 0u);
  EXPECT_EQ(layerThicknessStats({flatLayer(0), flatLayer(1)}, 0).samples, 0u);
  EXPECT_EQ(layerThicknessStats({flatLayer(0), flatLayer(1)}, -1).samples, 0u);
  EXPECT_EQ(layerThicknessStats({CurvedLayer{}, flatLayer(1)}, 0.5).samples, 0u);
}


double meshArea(const Mesh& m) {
  double a = 0;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d p = m.vertex(m.triangles[3 * f]), q = m.vertex(m.triangles[3 * f + 1]),
                          r = m.vertex(m.triangles[3 * f + 2]);
    a += 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

TEST(SurfaceLayers, ClipKeepsThePositiveSideInConnectedPieces) {
  // A 10 mm square (40 x 40 quads) clipped by |x - 5| > 2: two strips of 3 x 10 mm.
  CurvedLayer layer;
  layer.regions.push_back(square(0, 10, 1, 40));
  layer.regions[0].support = true;
  clipLayerRegions(layer, [](const Eigen::Vector3d& p) { return std::abs(p.x() - 5) - 2; }, 0.01);
  ASSERT_EQ(layer.regions.size(), 2u);
  for (const LayerRegion& r : layer.regions) {
    EXPECT_TRUE(r.support);
    // The cut runs along x = 3 or 7 up to the snap (a tenth of a 0.25 mm edge).
    EXPECT_NEAR(r.area, 30.0, 10 * 0.025 + 1e-9);
    EXPECT_NEAR(meshArea(r.mesh), r.area, 1e-9);
    ASSERT_EQ(r.boundaryVertex.size(), r.mesh.vertexCount());
    size_t cut = 0;
    for (size_t v = 0; v < r.mesh.vertexCount(); ++v) {
      const Eigen::Vector3d p = r.mesh.vertex(v);
      EXPECT_GE(std::abs(p.x() - 5), 2 - 0.025 - 1e-9);  // never into the dropped side past a snap
      EXPECT_NEAR(p.z(), 1, 1e-12);
      if (r.boundaryVertex[v]) {
        ++cut;
        EXPECT_NEAR(std::abs(p.x() - 5), 2, 0.025 + 1e-9);  // only cut vertices are flagged here
      }
    }
    EXPECT_GE(cut, 41u);  // the cut line has a vertex per row at least
    // Orientation kept: every triangle faces +Z as the input's.
    for (size_t f = 0; f < r.mesh.faceCount(); ++f) {
      const Eigen::Vector3d a = r.mesh.vertex(r.mesh.triangles[3 * f]), b = r.mesh.vertex(r.mesh.triangles[3 * f + 1]),
                            c = r.mesh.vertex(r.mesh.triangles[3 * f + 2]);
      EXPECT_GT((b - a).cross(c - a).z(), 0);
    }
  }
  // All positive: unchanged; all negative or NaN: dropped.
  CurvedLayer whole;
  whole.regions.push_back(square(0, 10, 1, 4));
  clipLayerRegions(whole, [](const Eigen::Vector3d&) { return 1.0; }, 0.01);
  ASSERT_EQ(whole.regions.size(), 1u);
  EXPECT_EQ(whole.regions[0].mesh.triangles, square(0, 10, 1, 4).mesh.triangles);
  clipLayerRegions(whole, [](const Eigen::Vector3d&) { return std::nan(""); }, 0.01);
  EXPECT_TRUE(whole.regions.empty());
  // Pieces under minArea are dropped: a 0.2 mm strip (2 mm^2) with minArea 3.
  CurvedLayer thin;
  thin.regions.push_back(square(0, 10, 1, 50));
  clipLayerRegions(thin, [](const Eigen::Vector3d& p) { return 0.1 - std::abs(p.x() - 5); }, 3);
  EXPECT_TRUE(thin.regions.empty());
}

TEST(SurfaceLayers, PartialLayerThicknessLooksBackToTheFullLayer) {
  // Full layers at 0 and 1, a partial one at 0.5 over x < 5, then a full one at 1.5: the full
  // layer at 1 measures 0.5 over the partial layer and 1 beyond it, the one at 1.5 measures 0.5.
  std::vector<CurvedLayer> layers;
  layers.push_back(flatLayer(0));
  CurvedLayer partial;
  partial.isoValue = 0.5;
  partial.partial = true;
  partial.regions.push_back(square(0, 10, 0.5, 20));
  clipLayerRegions(partial, [](const Eigen::Vector3d& p) { return 5 - p.x(); }, 0.01);
  layers.push_back(partial);
  layers.push_back(flatLayer(1));
  layers.push_back(flatLayer(1.5));
  const ThicknessStats s = layerThicknessStats(layers, 0.25);
  ASSERT_EQ(s.layers.size(), 4u);
  EXPECT_EQ(s.layers[0].samples, 0u);
  EXPECT_FALSE(s.layers[1].full);
  EXPECT_TRUE(s.layers[2].full);
  EXPECT_NEAR(s.layers[1].min, 0.5, 1e-12);
  EXPECT_NEAR(s.layers[1].max, 0.5, 1e-12);
  EXPECT_NEAR(s.layers[2].min, 0.5, 1e-12);
  EXPECT_NEAR(s.layers[2].max, 1.0, 1e-12);
  EXPECT_NEAR(s.layers[3].min, 0.5, 1e-12);
  EXPECT_NEAR(s.layers[3].max, 0.5, 1e-12);
  // The nominal height counts the full layers only.
  const double full = (s.layers[2].mean * double(s.layers[2].samples) + s.layers[3].mean * double(s.layers[3].samples)) /
                      double(s.layers[2].samples + s.layers[3].samples);
  EXPECT_NEAR(s.fullMean(), full, 1e-12);
  EXPECT_GT(s.fullMean(), s.mean);
}
}  // namespace
}  // namespace omnislice
