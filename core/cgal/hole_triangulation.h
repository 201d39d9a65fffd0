// SPDX-License-Identifier: MIT
// Triangulation of one hole's boundary loop (CGAL behind a plain-data interface).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace omnislice {

// Triangles (indices into loop, each ascending, so that all run the loop's way round) of a
// surface spanning the closed polygon loop (first point not repeated at the end), by CGAL's
// Polygon_mesh_processing::triangulate_hole_polyline: Liepa's dynamic programme, which minimises
// the worst dihedral angle between neighbouring triangles and then the area, searched over the
// faces of the loop's 3D Delaunay triangulation (all O(n^3) triangles when that fails). Returns
// loop.size() - 2 triangles, or nothing when CGAL finds no triangulation (the caller falls back).
// No vertex is added. Cost grows with n^2-n^3: keep loops to a few hundred points.
std::vector<std::array<uint32_t, 3>> triangulateHoleLoop(const std::vector<Eigen::Vector3d>& loop);

}  // namespace omnislice
