// SPDX-License-Identifier: MIT
// Internal to core/slice: conversions between the plain 2D polygon types and Clipper's integer
// paths (scale kClipperScale units per mm), plus the few Clipper operations the slicer uses. Only
// .cpp files include this header (it pulls in Clipper).
#pragma once
#include <clipper.hpp>

#include <vector>

#include "slice/slice_mesh.h"

namespace omnislice::clip {

// Integer units per mm: 1e5 gives 10 nm resolution; Clipper's fast 62-bit-product range
// (|coordinate| <= 2^30 - 1 units) then covers parts up to +-10.7 m from the frame origin.
constexpr double kClipperScale = 1e5;
// Largest |coordinate| (mm) accepted; Clipper's full range (2^62 units) is far above it.
constexpr double kMaxCoordinateMm = 1e6;

inline ClipperLib::cInt toUnits(double mm) {
  return static_cast<ClipperLib::cInt>(mm * kClipperScale + (mm >= 0 ? 0.5 : -0.5));
}
inline double toMm(ClipperLib::cInt units) { return static_cast<double>(units) / kClipperScale; }
inline ClipperLib::IntPoint toPoint(const Eigen::Vector2d& p) {
  return ClipperLib::IntPoint(toUnits(p.x()), toUnits(p.y()));
}
inline Eigen::Vector2d toVec(const ClipperLib::IntPoint& p) { return {toMm(p.X), toMm(p.Y)}; }

ClipperLib::Path toPath(const Polygon2& polygon);
Polygon2 toPolygon(const ClipperLib::Path& path);
// Contour and holes of each island as one flat list of closed paths.
ClipperLib::Paths toPaths(const ExPolygon2& island);
ClipperLib::Paths toPaths(const std::vector<ExPolygon2>& islands);

// Islands from a PolyTree: every outer node becomes a contour (CCW) with its child holes (CW);
// islands nested in holes become further islands.
std::vector<ExPolygon2> toIslands(const ClipperLib::PolyTree& tree);
// Each outer node of the tree with its holes, as Clipper paths (contour first).
std::vector<ClipperLib::Paths> islandPaths(const ClipperLib::PolyTree& tree);

// Boolean operations on closed regions (non-zero fill); results are clean closed paths.
ClipperLib::Paths unite(const ClipperLib::Paths& a);
ClipperLib::Paths intersect(const ClipperLib::Paths& a, const ClipperLib::Paths& b);
ClipperLib::Paths subtract(const ClipperLib::Paths& a, const ClipperLib::Paths& b);
// Offset of a closed region by deltaMm (< 0 shrinks), mitred joins (limit 2).
ClipperLib::Paths offset(const ClipperLib::Paths& region, double deltaMm);
// Open polylines clipped to a closed region: the pieces inside.
ClipperLib::Paths clipLines(const ClipperLib::Paths& lines, const ClipperLib::Paths& region);
// Area (mm^2) of a region given as closed paths with outer CCW / holes CW.
double areaMm2(const ClipperLib::Paths& region);

}  // namespace omnislice::clip
