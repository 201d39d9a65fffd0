// SPDX-License-Identifier: MIT
#include "cgal/hole_triangulation.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <exception>
#include <iterator>

namespace omnislice {

std::vector<std::array<uint32_t, 3>> triangulateHoleLoop(const std::vector<Eigen::Vector3d>& loop) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<std::array<uint32_t, 3>> out;
  const size_t n = loop.size();
  if (n < 3) return out;
  std::vector<Kernel::Point_3> points;
  points.reserve(n);
  for (const Eigen::Vector3d& p : loop) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<CGAL::Triple<int, int, int>> patch;
  try {
    CGAL::Polygon_mesh_processing::triangulate_hole_polyline(
        points, std::back_inserter(patch), CGAL::parameters::use_delaunay_triangulation(true));
  } catch (const std::exception&) {
    return out;
  }
  if (patch.size() != n - 2) return out;
  out.reserve(patch.size());
  for (const auto& t : patch) {
    std::array<int, 3> s = {t.first, t.second, t.third};
    std::sort(s.begin(), s.end());
    if (s[0] < 0 || s[2] >= static_cast<int>(n) || s[0] == s[1] || s[1] == s[2]) return {};
    out.push_back({static_cast<uint32_t>(s[0]), static_cast<uint32_t>(s[1]), static_cast<uint32_t>(s[2])});
  }
  return out;
}

}  // namespace omnislice
