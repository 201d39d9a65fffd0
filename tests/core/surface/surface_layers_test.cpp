// SPDX-License-Identifier: MIT
// Layer-thickness statistics (paper 001 Fig. 15) on synthetic layer stacks with known spacings.
#include "surface/surface_layers.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace omnislice
