// SPDX-License-Identifier: MIT
// Reference point-to-mesh distances and inside tests computed with CGAL (AABB_tree and
// Side_of_triangle_mesh). Used only by tests, to check the fast double-precision AabbTree of
// core/geometry against an independent implementation.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct MeshDistanceReference : Outcome {
  std::vector<double> distances;  // unsigned distance to the surface per point, mm
  std::vector<uint8_t> inside;    // 1 when CGAL classifies the point as strictly inside
};

// mesh: closed, oriented triangle mesh. EmptyInput for no triangles, Internal when CGAL throws.
MeshDistanceReference meshDistanceReference(const Mesh& mesh,
                                            const std::vector<Eigen::Vector3d>& points);

}  // namespace omnislice
