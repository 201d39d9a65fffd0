// SPDX-License-Identifier: MIT
#include "slice/clipper_adapter.h"

namespace omnislice::clip {

using namespace ClipperLib;

Path toPath(const Polygon2& polygon) {
  Path path;
  path.reserve(polygon.size());
  for (const Eigen::Vector2d& p : polygon) path.push_back(toPoint(p));
  return path;
}

Polygon2 toPolygon(const Path& path) {
  Polygon2 polygon;
  polygon.reserve(path.size());
  for (const IntPoint& p : path) polygon.push_back(toVec(p));
  return polygon;
}

Paths toPaths(const ExPolygon2& island) {
  Paths paths;
  paths.reserve(1 + island.holes.size());
  paths.push_back(toPath(island.contour));
  for (const Polygon2& hole : island.holes) paths.push_back(toPath(hole));
  return paths;
}

Paths toPaths(const std::vector<ExPolygon2>& islands) {
  Paths paths;
  for (const ExPolygon2& island : islands) {
    Paths p = toPaths(island);
    paths.insert(paths.end(), p.begin(), p.end());
  }
  return paths;
}

namespace {
// Outer nodes are reached from the root and from holes; each one collects its direct hole children.
void collectIslands(const PolyNode& node, std::vector<Paths>& out) {
  for (const PolyNode* child : node.Childs) {
    if (child->IsHole()) {
      collectIslands(*child, out);
      continue;
    }
    Paths island;
    island.push_back(child->Contour);
    for (const PolyNode* hole : child->Childs) island.push_back(hole->Contour);
    out.push_back(std::move(island));
    for (const PolyNode* hole : child->Childs) collectIslands(*hole, out);
  }
}
}  // namespace

std::vector<Paths> islandPaths(const PolyTree& tree) {
  std::vector<Paths> out;
  collectIslands(tree, out);
  return out;
}

std::vector<ExPolygon2> toIslands(const PolyTree& tree) {
  std::vector<ExPolygon2> islands;
  for (const Paths& paths : islandPaths(tree)) {
    ExPolygon2 island;
    island.contour = toPolygon(paths[0]);
    for (size_t i = 1; i < paths.size(); ++i) island.holes.push_back(toPolygon(paths[i]));
    islands.push_back(std::move(island));
  }
  return islands;
}

Paths unite(const Paths& a) {
  Clipper c;
  c.AddPaths(a, ptSubject, true);
  Paths out;
  c.Execute(ctUnion, out, pftNonZero, pftNonZero);
  return out;
}

Paths intersect(const Paths& a, const Paths& b) {
  if (a.empty() || b.empty()) return {};
  Clipper c;
  c.AddPaths(a, ptSubject, true);
  c.AddPaths(b, ptClip, true);
  Paths out;
  c.Execute(ctIntersection, out, pftNonZero, pftNonZero);
  return out;
}

Paths subtract(const Paths& a, const Paths& b) {
  if (a.empty()) return {};
  if (b.empty()) return a;
  Clipper c;
  c.AddPaths(a, ptSubject, true);
  c.AddPaths(b, ptClip, true);
  Paths out;
  c.Execute(ctDifference, out, pftNonZero, pftNonZero);
  return out;
}

Paths offset(const Paths& region, double deltaMm) {
  if (region.empty()) return {};
  ClipperOffset o(2.0, 0.005 * kClipperScale);
  o.AddPaths(region, jtMiter, etClosedPolygon);
  Paths out;
  o.Execute(out, deltaMm * kClipperScale);
  return out;
}

Paths clipLines(const Paths& lines, const Paths& region) {
  if (lines.empty() || region.empty()) return {};
  Clipper c;
  c.AddPaths(lines, ptSubject, false);
  c.AddPaths(region, ptClip, true);
  PolyTree tree;
  c.Execute(ctIntersection, tree, pftNonZero, pftNonZero);
  Paths out;
  OpenPathsFromPolyTree(tree, out);
  return out;
}

double areaMm2(const Paths& region) {
  double a = 0;
  for (const Path& p : region) a += Area(p);
  return a / (kClipperScale * kClipperScale);
}

}  // namespace omnislice::clip
