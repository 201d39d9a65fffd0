// SPDX-License-Identifier: MIT
// Layer-thickness statistics of paper 001 Section 6.2.1 (Fig. 15): sample every layer after the
// first into points, measure each point's distance to the previous layer's surface.
#include "surface/surface_layers.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

#include "common/disjoint_sets.h"
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
  std::vector<LayerThickness> perLayer(layers.size());
  for (size_t i = 0; i < layers.size(); ++i) perLayer[i].full = !layers[i].partial;
  uint64_t counter = 0;
  for (size_t i = 1; i < layers.size(); ++i) {
    // The layers below back to the last full one: a partial layer covers only part of it.
    Mesh previous;
    for (size_t j = i; j-- > 0;) {
      const Mesh m = layerMesh(layers[j]);
      const uint32_t base = static_cast<uint32_t>(previous.vertexCount());
      previous.positions.insert(previous.positions.end(), m.positions.begin(), m.positions.end());
      for (uint32_t v : m.triangles) previous.triangles.push_back(base + v);
      if (!layers[j].partial) break;
    }
    if (previous.empty()) continue;
    const AabbTree tree(previous);
    LayerThickness& lt = perLayer[i];
    lt.min = std::numeric_limits<double>::infinity();
    double layerSum = 0;
    // Consecutive samples are close together, so the previous distance (plus the spacing) bounds
    // the search first; a full search only when nothing lies that close.
    double hint = std::numeric_limits<double>::infinity();
    samplePoints(layers[i], sampleSpacing, counter, [&](const Eigen::Vector3d& p) {
      // The platform z = 0 lies under every layer.
      const double platform = std::max(0.0, p.z());
      ClosestPoint cp = tree.closest(p, std::min(platform, 1.5 * hint + sampleSpacing));
      if (!std::isfinite(cp.distance)) cp = tree.closest(p, platform);
      if (!std::isfinite(cp.distance)) cp.distance = platform;
      if (std::isfinite(cp.distance)) {
        distances.push_back(cp.distance);
        hint = cp.distance;
        ++lt.samples;
        layerSum += cp.distance;
        lt.min = std::min(lt.min, cp.distance);
        lt.max = std::max(lt.max, cp.distance);
      }
    });
    if (lt.samples > 0) lt.mean = layerSum / static_cast<double>(lt.samples);
    else lt.min = 0;
  }
  stats.layers = std::move(perLayer);
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


double ThicknessStats::fullMean() const {
  if (std::all_of(layers.begin(), layers.end(), [](const LayerThickness& lt) { return lt.full; })) return mean;
  double sum = 0;
  size_t n = 0;
  for (const LayerThickness& lt : layers) {
    if (lt.full) {
      sum += lt.mean * static_cast<double>(lt.samples);
      n += lt.samples;
    }
  }
  return n > 0 ? sum / static_cast<double>(n) : mean;
}

Mesh layerMesh(const CurvedLayer& layer) {
  Mesh out;
  for (const LayerRegion& r : layer.regions) {
    const uint32_t base = static_cast<uint32_t>(out.vertexCount());
    out.positions.insert(out.positions.end(), r.mesh.positions.begin(), r.mesh.positions.end());
    for (uint32_t v : r.mesh.triangles) out.triangles.push_back(base + v);
  }
  return out;
}

void clipLayerRegions(CurvedLayer& layer, const std::function<double(const Eigen::Vector3d&)>& value,
                      double minArea) {
  std::vector<LayerRegion> kept;
  for (const LayerRegion& region : layer.regions) {
    const Mesh& m = region.mesh;
    const size_t nv = m.vertexCount();
    std::vector<double> f(nv);
    bool any = false, all = true;
    for (size_t v = 0; v < nv; ++v) {
      f[v] = value(m.vertex(v));
      if (!std::isfinite(f[v])) f[v] = -1;
      any = any || f[v] > 0;
      all = all && f[v] > 0;
    }
    if (!any) continue;
    if (all) {
      kept.push_back(region);
      continue;
    }
    // The clipped triangle soup: kept vertices keep their index; a cut edge gets one new vertex
    // (or its snapped end).
    std::vector<Eigen::Vector3d> pos(nv);
    std::vector<uint8_t> boundary(region.boundaryVertex);
    boundary.resize(nv, 0);
    for (size_t v = 0; v < nv; ++v) pos[v] = m.vertex(v);
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> cut;
    auto cutVertex = [&](uint32_t a, uint32_t b) {  // f[a] > 0 >= f[b]
      const double t = f[a] / (f[a] - f[b]);
      if (t < 0.1) {
        boundary[a] = 1;
        return a;
      }
      if (t > 0.9) {
        // The crossing sits at b: keep b itself, on the cut.
        boundary[b] = 1;
        return b;
      }
      const auto key = std::minmax(a, b);
      auto it = cut.find(key);
      if (it != cut.end()) return it->second;
      const uint32_t id = static_cast<uint32_t>(pos.size());
      pos.push_back(pos[a] + t * (pos[b] - pos[a]));
      boundary.push_back(1);
      cut.emplace(key, id);
      return id;
    };
    std::vector<std::array<uint32_t, 3>> tris;
    auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
      if (a != b && b != c && a != c) tris.push_back({a, b, c});
    };
    for (size_t t = 0; t < m.faceCount(); ++t) {
      const uint32_t v[3] = {m.triangles[3 * t], m.triangles[3 * t + 1], m.triangles[3 * t + 2]};
      const bool in[3] = {f[v[0]] > 0, f[v[1]] > 0, f[v[2]] > 0};
      const int count = in[0] + in[1] + in[2];
      if (count == 0) continue;
      if (count == 3) {
        emit(v[0], v[1], v[2]);
        continue;
      }
      // Rotate so the lone vertex (inside for count 1, outside for count 2) comes first.
      int k = 0;
      while ((in[k] ? 1 : 0) != (count == 1 ? 1 : 0)) ++k;
      const uint32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
      if (count == 1) {
        emit(a, cutVertex(a, b), cutVertex(a, c));
      } else {
        const uint32_t ab = cutVertex(b, a), ac = cutVertex(c, a);
        emit(ab, b, c);
        emit(ab, c, ac);
      }
    }
    // Connected pieces (triangles sharing a vertex), compacted.
    DisjointSets sets(pos.size());
    for (const auto& t : tris) {
      sets.unite(t[0], t[1]);
      sets.unite(t[0], t[2]);
    }
    std::map<uint32_t, size_t> pieceOf;
    std::vector<std::vector<size_t>> pieces;
    for (size_t t = 0; t < tris.size(); ++t) {
      const uint32_t root = sets.find(tris[t][0]);
      auto it = pieceOf.find(root);
      if (it == pieceOf.end()) {
        it = pieceOf.emplace(root, pieces.size()).first;
        pieces.emplace_back();
      }
      pieces[it->second].push_back(t);
    }
    std::vector<uint32_t> local(pos.size(), UINT32_MAX);
    for (const auto& piece : pieces) {
      LayerRegion out;
      out.support = region.support;
      for (size_t t : piece) {
        const auto& tri = tris[t];
        out.area += 0.5 * (pos[tri[1]] - pos[tri[0]]).cross(pos[tri[2]] - pos[tri[0]]).norm();
        for (uint32_t v : tri) {
          if (local[v] == UINT32_MAX) {
            local[v] = static_cast<uint32_t>(out.boundaryVertex.size());
            out.boundaryVertex.push_back(boundary[v]);
            out.mesh.positions.insert(out.mesh.positions.end(), {pos[v].x(), pos[v].y(), pos[v].z()});
          }
          out.mesh.triangles.push_back(local[v]);
        }
      }
      for (size_t t : piece)
        for (uint32_t v : tris[t]) local[v] = UINT32_MAX;
      if (out.area >= minArea) kept.push_back(std::move(out));
    }
  }
  layer.regions = std::move(kept);
}

}  // namespace omnislice
