// SPDX-License-Identifier: MIT
// Test meshes for the geodesic tests: a structured grid of nx*ny*nz cubes, each split into 6 tets
// around its main diagonal (Kuhn split, conforming across cubes), vertex (i, j, k) at
// map(i/nx, j/ny, k/nz) with index (k (ny + 1) + j) (nx + 1) + i; every tet positively oriented.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <utility>

#include "tet/tet_mesh.h"

namespace omnislice::test {

inline TetMesh gridTets(int nx, int ny, int nz,
                        const std::function<Eigen::Vector3d(double, double, double)>& map) {
  TetMesh m;
  auto id = [&](int i, int j, int k) { return uint32_t((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const Eigen::Vector3d p = map(double(i) / nx, double(j) / ny, double(k) / nz);
        m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
      }
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& perm : perms) {
          int c[3] = {i, j, k};
          uint32_t t[4];
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[perm[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          const Eigen::Vector3d a = m.vertex(t[0]);
          if ((m.vertex(t[1]) - a).dot((m.vertex(t[2]) - a).cross(m.vertex(t[3]) - a)) < 0)
            std::swap(t[2], t[3]);
          m.tets.insert(m.tets.end(), t, t + 4);
        }
  return m;
}

}  // namespace omnislice::test
