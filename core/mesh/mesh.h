// SPDX-License-Identifier: MIT
// The one exchange mesh of the core: flat positions plus uint32 triangle indices.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace omnislice {

// Triangle mesh. positions: #V*3 doubles (x,y,z per vertex, mm once placed);
// triangles: #F*3 vertex indices, counter-clockwise seen from outside for an oriented solid.
struct Mesh {
  std::vector<double> positions;
  std::vector<uint32_t> triangles;

  size_t vertexCount() const { return positions.size() / 3; }
  size_t faceCount() const { return triangles.size() / 3; }
  Eigen::Vector3d vertex(size_t i) const {
    return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
  }
  bool empty() const { return triangles.empty(); }
};

struct BoundingBox {
  Eigen::Vector3d min{0, 0, 0};
  Eigen::Vector3d max{0, 0, 0};
};

// Axis-aligned bounds of the referenced and unreferenced vertices; zero box for an empty mesh.
BoundingBox boundingBox(const Mesh& mesh);

}  // namespace omnislice
