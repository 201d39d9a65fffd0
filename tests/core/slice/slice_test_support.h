// SPDX-License-Identifier: MIT
// Closed prisms and bipyramids for the slicing tests, and independent 2D geometry checks (the
// spheres, tori and boxes are in test_meshes.h).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "../test_meshes.h"
#include "../test_support.h"
#include "mesh/mesh.h"
#include "slice/slice_mesh.h"

namespace omnislice::test {

// Prism: a polygon in the XZ plane (star-shaped from profile[0], listed CCW) extruded along Y
// from y0 to y1. Caps are fans from profile[0].
inline Mesh makePrismXZ(const std::vector<Eigen::Vector2d>& profile, double y0, double y1) {
  Mesh m;
  const uint32_t n = static_cast<uint32_t>(profile.size());
  for (double y : {y0, y1}) {
    for (const auto& p : profile) m.positions.insert(m.positions.end(), {p.x(), y, p.y()});
  }
  for (uint32_t i = 1; i + 1 < n; ++i) {
    m.triangles.insert(m.triangles.end(), {0, i, i + 1});
    m.triangles.insert(m.triangles.end(), {n, n + i + 1, n + i});
  }
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    m.triangles.insert(m.triangles.end(), {i, n + i, n + j});
    m.triangles.insert(m.triangles.end(), {i, n + j, j});
  }
  if (meshVolume(m) < 0) m = flipped(m);
  return m;
}

// Two square pyramids joined at a square equator of half-size a at height zEq, apexes at zLo, zHi.
inline Mesh makeBipyramid(double a, double zLo, double zEq, double zHi) {
  Mesh m;
  m.positions = {-a, -a, zEq, a, -a, zEq, a, a, zEq, -a, a, zEq, 0, 0, zLo, 0, 0, zHi};
  for (uint32_t i = 0; i < 4; ++i) {
    const uint32_t j = (i + 1) % 4;
    m.triangles.insert(m.triangles.end(), {i, j, 5});
    m.triangles.insert(m.triangles.end(), {j, i, 4});
  }
  if (meshVolume(m) < 0) m = flipped(m);
  return m;
}

// ---- independent 2D checks ----
inline bool insidePolygon(const Polygon2& poly, const Eigen::Vector2d& p) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      in = !in;
    }
  }
  return in;
}
inline double distanceToPolygon(const Polygon2& poly, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d ab = poly[i] - poly[j];
    const double t = std::clamp((p - poly[j]).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (poly[j] + t * ab - p).norm());
  }
  return best;
}
inline bool insideIsland(const ExPolygon2& island, const Eigen::Vector2d& p) {
  if (!insidePolygon(island.contour, p)) return false;
  for (const Polygon2& hole : island.holes) {
    if (insidePolygon(hole, p)) return false;
  }
  return true;
}
inline double distanceToIslandBoundary(const ExPolygon2& island, const Eigen::Vector2d& p) {
  double d = distanceToPolygon(island.contour, p);
  for (const Polygon2& hole : island.holes) d = std::min(d, distanceToPolygon(hole, p));
  return d;
}
inline double layerArea(const SliceLayer& layer) {
  double a = 0;
  for (const ExPolygon2& island : layer.islands) a += islandArea(island);
  return a;
}
inline double slicedVolume(const SliceResult& r) {
  double v = 0;
  for (const SliceLayer& layer : r.layers) v += layerArea(layer) * (layer.top - layer.bottom);
  return v;
}

}  // namespace omnislice::test
