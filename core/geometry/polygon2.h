// SPDX-License-Identifier: MIT
// Planar polygons in a layer's plane coordinates (mm): the islands the planar slicer makes and
// the support, fill and sampling steps read. Outer contours counter-clockwise, holes clockwise.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace omnislice {

using Polygon2 = std::vector<Eigen::Vector2d>;

// One island: an outer contour and its holes.
struct ExPolygon2 {
  Polygon2 contour;
  std::vector<Polygon2> holes;
};

// Even-odd point-in-polygon (a point on an edge may count either way).
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

// Inside the island's contour and outside its holes (contours of fewer than 3 points ignored).
inline bool insideIsland(const ExPolygon2& island, const Eigen::Vector2d& p) {
  if (island.contour.size() < 3 || !insidePolygon(island.contour, p)) return false;
  for (const Polygon2& hole : island.holes) {
    if (hole.size() >= 3 && insidePolygon(hole, p)) return false;
  }
  return true;
}

}  // namespace omnislice
