// SPDX-License-Identifier: MIT
#include "mesh/mesh_measures.h"

#include <Eigen/Geometry>

namespace omnislice {

double signedVolume(const Mesh& mesh) {
  if (mesh.empty()) return 0;
  const BoundingBox box = boundingBox(mesh);
  const Eigen::Vector3d o = 0.5 * (box.min + box.max);
  double v = 0;
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]) - o;
    const Eigen::Vector3d b = mesh.vertex(mesh.triangles[3 * f + 1]) - o;
    const Eigen::Vector3d c = mesh.vertex(mesh.triangles[3 * f + 2]) - o;
    v += a.dot(b.cross(c));
  }
  return v / 6;
}

double surfaceArea(const Mesh& mesh) {
  double area = 0;
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]);
    const Eigen::Vector3d b = mesh.vertex(mesh.triangles[3 * f + 1]);
    const Eigen::Vector3d c = mesh.vertex(mesh.triangles[3 * f + 2]);
    area += (b - a).cross(c - a).norm();
  }
  return area / 2;
}

}  // namespace omnislice
