// SPDX-License-Identifier: MIT
// Internal to core/slice: travel inside the part ("combing"). A region (closed loops, contours
// counter-clockwise and holes clockwise, as Clipper gives them) and routes from a point to another
// that stay in it: the straight segment where it stays inside; else, where it leaves the region,
// the shorter way along the loop it crossed, from where it leaves to where it comes back; then
// each point joined to the farthest next one it sees, so the route hugs the boundary only where
// it must.
#pragma once
#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace omnislice {

class CombRegion {
 public:
  explicit CombRegion(std::vector<std::vector<Eigen::Vector2d>> loops);

  bool empty() const { return loops_.empty(); }

  // The route from a to b inside the region: the points after a, ending with b. False when there
  // is none this way (a or b outside the region, or the segment leaves it into another piece):
  // the caller travels straight.
  bool route(const Eigen::Vector2d& a, const Eigen::Vector2d& b, std::vector<Eigen::Vector2d>& out) const;

  // True when the segment crosses none of the region's loops.
  bool clear(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;

 private:
  struct Crossing {
    double t;        // along a -> b
    size_t loop;
    size_t edge;     // edge i runs from vertex i to vertex i + 1
    Eigen::Vector2d point;
  };
  void crossings(const Eigen::Vector2d& a, const Eigen::Vector2d& b, std::vector<Crossing>& out,
                 bool firstOnly) const;
  bool inside(const Eigen::Vector2d& p) const;  // even-odd over the loops
  void walk(const Crossing& from, const Crossing& to, std::vector<Eigen::Vector2d>& out) const;

  std::vector<std::vector<Eigen::Vector2d>> loops_;
  // Uniform grid over the edges: cell -> (loop, edge) pairs.
  Eigen::Vector2d origin_{0, 0};
  double cell_ = 1;
  long nx_ = 0, ny_ = 0;
  std::vector<size_t> cellStart_;
  std::vector<std::pair<size_t, size_t>> cellEdges_;
  mutable std::vector<unsigned> stamp_;  // per edge (flattened), the query that saw it last
  mutable unsigned query_ = 0;
  std::vector<size_t> edgeBase_;         // flattened index of each loop's first edge
};

}  // namespace omnislice
