// SPDX-License-Identifier: MIT
#include "mesh/mesh.h"

#include <algorithm>
#include <limits>

namespace omnislice {

BoundingBox boundingBox(const Mesh& mesh) {
  BoundingBox box;
  if (mesh.vertexCount() == 0) return box;
  const double inf = std::numeric_limits<double>::infinity();
  box.min = Eigen::Vector3d(inf, inf, inf);
  box.max = -box.min;
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    const Eigen::Vector3d p = mesh.vertex(i);
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

}  // namespace omnislice
