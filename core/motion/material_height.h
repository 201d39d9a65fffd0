// SPDX-License-Identifier: MIT
// How high printed material can reach while a platform turns (rotary4, table5): the machine Z of a
// part-frame point q at a pose whose nozzle axis in the part frame is u is P.z + (q - P) . u (the
// platform turns about the pivot P and the nozzle points along machine +Z), so the highest point
// of the material at that pose is P.z + h(u), h the support function of the printed points about P.
// MaterialHeight keeps an upper bound of h: the largest (q - P) . d over a fixed set of unit
// directions d (a Fibonacci sphere) and the largest |q - P|, R; for a unit u and a direction d at
// angle t < 90 deg, (q - P) . u <= cos t max((q - P) . d) + sin t R, so the least such value over
// the directions bounds h(u) (at most 2 R sin 3.1 deg above it with 2048 directions, every axis
// lying within 3.05 deg of one). Points are taken once per cell of a grid; the bound adds the
// cell's diagonal.
#pragma once
#include <Eigen/Core>

#include <cstdint>
#include <unordered_set>
#include <vector>

namespace omnislice {

class MaterialHeight {
 public:
  explicit MaterialHeight(const Eigen::Vector3d& pivot, double cellMm = 1.0, int directions = 2048);
  // A printed point (part frame).
  void add(const Eigen::Vector3d& q);
  bool empty() const { return cells_.empty(); }
  double radius() const { return radius_; }  // largest |q - pivot| of the points taken
  // An upper bound of max over the added q of (q - pivot) . u, u a unit vector; -infinity when
  // nothing was added.
  double bound(const Eigen::Vector3d& u) const;

 private:
  Eigen::Vector3d pivot_;
  double cell_;
  std::vector<Eigen::Vector3d> dirs_;
  std::vector<double> maxDot_;
  double radius_ = 0;
  std::unordered_set<int64_t> cells_;
};

}  // namespace omnislice
