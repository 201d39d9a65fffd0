// SPDX-License-Identifier: MIT
// Fixtures for pipeline and CLI tests: meshes as file bytes.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace omnislice::test {

// Binary STL bytes of a mesh (80-byte header, count, 50 bytes per face).
inline std::vector<uint8_t> binaryStl(const Mesh& m, const std::string& header = "omnislice test") {
  std::vector<uint8_t> out(84 + 50 * m.faceCount(), 0);
  std::memcpy(out.data(), header.data(), std::min<size_t>(header.size(), 80));
  const uint32_t n = static_cast<uint32_t>(m.faceCount());
  std::memcpy(out.data() + 80, &n, 4);
  for (size_t f = 0; f < m.faceCount(); ++f) {
    uint8_t* rec = out.data() + 84 + 50 * f;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.triangles[3 * f + k];
      for (int c = 0; c < 3; ++c) {
        const float x = static_cast<float>(m.positions[3 * v + c]);
        std::memcpy(rec + 12 + 12 * k + 4 * c, &x, 4);
      }
    }
  }
  return out;
}

// Closed, outward-oriented UV sphere (stacks >= 2, slices >= 3).
inline Mesh makeSphere(double r, int stacks, int slices, double cx = 0, double cy = 0, double cz = 0) {
  Mesh m;
  auto add = [&](double x, double y, double z) {
    m.positions.insert(m.positions.end(), {cx + x, cy + y, cz + z});
    return static_cast<uint32_t>(m.vertexCount() - 1);
  };
  const uint32_t south = add(0, 0, -r);
  std::vector<uint32_t> ring;
  for (int i = 1; i < stacks; ++i) {
    const double phi = -M_PI / 2 + M_PI * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double th = 2 * M_PI * j / slices;
      ring.push_back(add(r * std::cos(phi) * std::cos(th), r * std::cos(phi) * std::sin(th),
                         r * std::sin(phi)));
    }
  }
  const uint32_t north = add(0, 0, r);
  auto at = [&](int i, int j) { return ring[static_cast<size_t>(i * slices + (j % slices))]; };
  for (int j = 0; j < slices; ++j) m.triangles.insert(m.triangles.end(), {south, at(0, j + 1), at(0, j)});
  for (int i = 0; i + 1 < stacks - 1; ++i) {
    for (int j = 0; j < slices; ++j) {
      m.triangles.insert(m.triangles.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  for (int j = 0; j < slices; ++j) {
    m.triangles.insert(m.triangles.end(), {north, at(stacks - 2, j), at(stacks - 2, j + 1)});
  }
  return m;
}

}  // namespace omnislice::test
