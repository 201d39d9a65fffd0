// SPDX-License-Identifier: MIT
// Layer-thickness statistics of paper 001 Section 6.2.1 (Fig. 15): sample every layer after the
// first into points, measure each point's distance to the previous layer's surface.
#include "surface/surface_layers.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/aabb_tree.h"

namespace omnislice {

namespace {

// Samples points over the triangles of one layer, about one per spacing^2 of area: each triangle
// receives floor(carry + area / spacing^2) points, the fraction carried to the next, placed by the
// R2 low-discrepancy sequence warped onto the triangle (deterministic, area-uniform).
template <class Visit>
void samplePoints(const CurvedLayer& layer, double spacing, uint64_t& counter, Visit&& visit) {
  constexpr double kA1 = 0.7548776662466927, kA2 = 0.5698402909980532;  // R2 sequence
  double carry = 0.5;
  const double perArea = 1.0 / (spacing * spacing);
  for (const LayerRegion& region : layer.regions) {
    const Mesh& m = region.mesh;
    const size_t nv = m.vertexCount();
    for (size_t f = 0; f < m.faceCount(); ++f) {
      const uint32_t i = m.triangles[3 * f], j = m.triangles[3 * f + 1], k = m.triangles[3 * f + 2];
      if (i >= nv || j >= nv || k >= nv) continue;
      const Eigen::Vector3d a = m.vertex(i), b = m.vertex(j), c = m.vertex(k);
      const double area = 0.5 * (b - a).cross(c - a).norm();
      if (!std::isfinite(area)) continue;
      carry += area * perArea;
      const double count = std::floor(carry);
      carry -= count;
      for (double s = 0; s < count; ++s) {
        ++counter;
        const double u = std::fmod(0.5 + kA1 * static_cast<double>(counter), 1.0);
        const double v = std::fmod(0.5 + kA2 * static_cast<double>(counter), 1.0);
        const double r = std::sqrt(u);
        visit(Eigen::Vector3d((1 - r) * a + r * (1 - v) * b + r * v * c));
      }
    }
  }
}

double layerArea(const CurvedLayer& layer) {
  double area = 0;
  for (const LayerRegion& r : layer.regions) area += r.area;
  return area;
}

}  // namespace

ThicknessStats layerThicknessStats(const std::vector<CurvedLayer>& layers, double sampleSpacing) {
  ThicknessStats stats;
  if (!(sampleSpacing > 0) || !std::isfinite(sampleSpacing) || layers.size() < 2) return stats;
  // Keep the sample count bounded (about two million) on huge layer sets or tiny spacings.
  double area = 0;
  for (size_t i = 1; i < layers.size(); ++i) area += layerArea(layers[i]);
  constexpr double kMaxSamples = 2e6;
  if (area / (sampleSpacing * sampleSpacing) > kMaxSamples) sampleSpacing = std::sqrt(area / kMaxSamples);

  std::vector<double> distances;
  uint64_t counter = 0;
  for (size_t i = 1; i < layers.size(); ++i) {
    Mesh previous;
    for (const LayerRegion& r : layers[i - 1].regions) {
      const uint32_t base = static_cast<uint32_t>(previous.vertexCount());
      previous.positions.insert(previous.positions.end(), r.mesh.positions.begin(),
                                r.mesh.positions.end());
      for (uint32_t v : r.mesh.triangles) previous.triangles.push_back(base + v);
    }
    if (previous.empty()) continue;
    const AabbTree tree(previous);
    // Consecutive samples are close together, so the previous distance (plus the spacing) bounds
    // the search first; a full search only when nothing lies that close.
    double hint = std::numeric_limits<double>::infinity();
    samplePoints(layers[i], sampleSpacing, counter, [&](const Eigen::Vector3d& p) {
      ClosestPoint cp = tree.closest(p, 1.5 * hint + sampleSpacing);
      if (!std::isfinite(cp.distance)) cp = tree.closest(p);
      if (std::isfinite(cp.distance)) {
        distances.push_back(cp.distance);
        hint = cp.distance;
      }
    });
  }
  if (distances.empty()) return stats;
  stats.samples = distances.size();
  double sum = 0;
  for (double d : distances) sum += d;
  stats.mean = sum / static_cast<double>(distances.size());
  double var = 0, lo = 0, hi = 0;
  for (double d : distances) {
    const double dev = d - stats.mean;
    var += dev * dev;
    lo = std::min(lo, dev);
    hi = std::max(hi, dev);
  }
  stats.stddev = std::sqrt(var / static_cast<double>(distances.size()));
  stats.maxDeviation = std::max(-lo, hi);
  // Bins 5% of the mean wide, centred on multiples of the width (zero deviation mid-bin), at most
  // 400 of them (wider bins when the deviations spread further).
  double bin = stats.mean > 0 ? 0.05 * stats.mean : 1e-3;
  constexpr double kMaxBins = 400;
  if ((hi - lo) / bin + 2 > kMaxBins) bin = (hi - lo) / (kMaxBins - 2);
  const double kLo = std::floor(lo / bin + 0.5), kHi = std::floor(hi / bin + 0.5);
  const size_t bins = static_cast<size_t>(kHi - kLo) + 1;
  stats.histogramBin = bin;
  stats.histogramMin = (kLo - 0.5) * bin;
  stats.histogram.assign(bins, 0);
  for (double d : distances) {
    const double x = (d - stats.mean - stats.histogramMin) / bin;
    const size_t k = static_cast<size_t>(std::clamp(std::floor(x), 0.0, static_cast<double>(bins - 1)));
    ++stats.histogram[k];
  }
  return stats;
}

}  // namespace omnislice
