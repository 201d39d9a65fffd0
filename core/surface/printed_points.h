// SPDX-License-Identifier: MIT
// The points printed so far, for the gouging check of the curved tool-path (paper 001 Section
// 6.2.3): is any earlier point inside the nozzle cone at a tip position? A spatial index over
// the points (cubic cells of 2 mm, grouped in an octree of boxes) so a query visits only the
// boxes near the cone instead of every block printed before.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <unordered_map>
#include <vector>

namespace omnislice {

// The nozzle cone of the gouging check: apex s (the tip), axis u (unit), points p with
// d = p - s counted when d.u > clearance, |d| < length and their distance from the axis is
// < d.u tanAngle + radius (radius: the sample points blown up to balls, for the positions
// between samples).
struct GougingCone {
  double clearance = 0;  // mm along the axis ignored above the tip
  double length = 0;     // mm, > 0
  double tanAngle = 0;   // tangent of the half-angle, > 0
  double radius = 0;     // mm added to the cone's radius, >= 0
};

// Points with sequence numbers (their print order). Queries see only points with seq < limit.
// The answers are those of a scan over 8 mm blocks of 2 mm cells in creation order, each box
// tested against the cone before its points: the search's box tests (every octree level, 2 to
// 64 mm) only skip boxes that cannot hold a point in the cone, with a margin far above rounding,
// and a point in the cone counts when its cell and block pass the scan's tests, so neither the
// answers nor the order of the sum in hit's `away` depend on the octree.
class PrintedPoints {
 public:
  PrintedPoints();
  ~PrintedPoints();
  PrintedPoints(const PrintedPoints&) = delete;
  PrintedPoints& operator=(const PrintedPoints&) = delete;

  // Adds point p (mm, finite) printed with sequence number seq.
  void add(const Eigen::Vector3d& p, uint32_t seq);

  // Takes the point p added with seq out of every later query (a segment that is not printed).
  void retire(const Eigen::Vector3d& p, uint32_t seq);

  // True when a point with seq < limit lies in the cone at s along u. away (optional): adds the
  // sum of the unit lateral directions from the axis toward every such point, subtracted (no
  // early exit; the sum runs over blocks, then cells, in creation order).
  bool hit(const Eigen::Vector3d& s, const Eigen::Vector3d& u, uint32_t limit, const GougingCone& cone,
           Eigen::Vector3d* away = nullptr) const;

 private:
  struct Node;
  struct Query;
  bool mayHold(const Node& node, const Query& q) const;
  bool visit(const Node& node, int level, const Query& q) const;
  bool scanTakes(const Node& cell, const Query& q) const;

  std::vector<std::unordered_map<int64_t, std::unique_ptr<Node>>> levels_;  // [0] cells ... [top]
  std::vector<Node*> roots_;                                                // top level, creation order
  uint32_t cellCount_ = 0, blockCount_ = 0;
  // The points that answered the last hits without `away`, latest first (tried before the scan:
  // the gouging search asks about many axes around one, and a few points block most of them).
  static constexpr int kRecent = 8;
  mutable const Node* recentCell_[kRecent] = {};
  mutable size_t recentIndex_[kRecent] = {};
};

}  // namespace omnislice
