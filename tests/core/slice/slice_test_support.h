// SPDX-License-Identifier: MIT
// Generated closed meshes and independent geometry checks for the slicing tests.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <string>
#include <cmath>
#include <limits>
#include <vector>

#include "../test_support.h"
#include "mesh/mesh.h"
#include "slice/slice_mesh.h"

namespace omnislice::test {

inline void flipFaces(Mesh& m) {
  for (size_t f = 0; f < m.faceCount(); ++f) std::swap(m.triangles[3 * f + 1], m.triangles[3 * f + 2]);
}

// Closed surface of revolution-like grid: nu x nv quads with periodic u; v either periodic (torus)
// or capped by two pole vertices (sphere). Faces are flipped when needed so the volume is > 0.
inline Mesh makeSphere(const Eigen::Vector3d& c, double r, int nLat, int nLon) {
  Mesh m;
  auto add = [&](const Eigen::Vector3d& p) {
    m.positions.push_back(p.x());
    m.positions.push_back(p.y());
    m.positions.push_back(p.z());
    return static_cast<uint32_t>(m.vertexCount() - 1);
  };
  const uint32_t south = add(c + Eigen::Vector3d(0, 0, -r));
  for (int i = 1; i < nLat; ++i) {
    const double th = M_PI * i / nLat - M_PI / 2;
    for (int j = 0; j < nLon; ++j) {
      const double ph = 2 * M_PI * j / nLon;
      add(c + r * Eigen::Vector3d(std::cos(th) * std::cos(ph), std::cos(th) * std::sin(ph), std::sin(th)));
    }
  }
  const uint32_t north = add(c + Eigen::Vector3d(0, 0, r));
  auto ring = [&](int i, int j) { return static_cast<uint32_t>(1 + (i - 1) * nLon + (j % nLon)); };
  for (int j = 0; j < nLon; ++j) {
    m.triangles.insert(m.triangles.end(), {south, ring(1, j + 1), ring(1, j)});
    m.triangles.insert(m.triangles.end(), {north, ring(nLat - 1, j), ring(nLat - 1, j + 1)});
    for (int i = 1; i + 1 < nLat; ++i) {
      m.triangles.insert(m.triangles.end(), {ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  }
  if (meshVolume(m) < 0) flipFaces(m);
  return m;
}

// Torus around the Z axis through c: major radius R, tube radius r.
inline Mesh makeTorus(const Eigen::Vector3d& c, double R, double r, int nu, int nv) {
  Mesh m;
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * M_PI * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double v = 2 * M_PI * j / nv;
      const Eigen::Vector3d p = c + Eigen::Vector3d((R + r * std::cos(v)) * std::cos(u),
                                                    (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
      m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
    }
  }
  auto id = [&](int i, int j) { return static_cast<uint32_t>((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  if (meshVolume(m) < 0) flipFaces(m);
  return m;
}

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
  if (meshVolume(m) < 0) flipFaces(m);
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
  if (meshVolume(m) < 0) flipFaces(m);
  return m;
}

// Union of vertex/face lists (separate shells).
inline Mesh appendMesh(Mesh a, const Mesh& b) {
  const uint32_t off = static_cast<uint32_t>(a.vertexCount());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (uint32_t t : b.triangles) a.triangles.push_back(t + off);
  return a;
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
