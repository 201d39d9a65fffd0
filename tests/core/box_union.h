// SPDX-License-Identifier: MIT
// Closed test solids made of axis-aligned boxes (L-brackets, T-bars, arches) for the multidir tests.
#pragma once
#include <algorithm>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "mesh/mesh.h"

namespace omnislice::test {

struct Box {
  double x0, y0, z0, x1, y1, z1;
};

// Closed, outward mesh of a union of axis-aligned boxes: the rectilinear lattice through every box
// coordinate, a quad (two triangles) wherever a solid lattice cell meets an empty one. Shapes
// must not touch themselves along an edge only (that would be non-manifold).
inline Mesh makeBoxUnion(const std::vector<Box>& boxes) {
  std::vector<double> xs, ys, zs;
  for (const Box& b : boxes) {
    xs.insert(xs.end(), {b.x0, b.x1});
    ys.insert(ys.end(), {b.y0, b.y1});
    zs.insert(zs.end(), {b.z0, b.z1});
  }
  for (auto* v : {&xs, &ys, &zs}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  const int nx = static_cast<int>(xs.size()) - 1, ny = static_cast<int>(ys.size()) - 1,
            nz = static_cast<int>(zs.size()) - 1;
  auto solid = [&](int i, int j, int k) {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return false;
    const double x = (xs[i] + xs[i + 1]) / 2, y = (ys[j] + ys[j + 1]) / 2, z = (zs[k] + zs[k + 1]) / 2;
    for (const Box& b : boxes) {
      if (x > b.x0 && x < b.x1 && y > b.y0 && y < b.y1 && z > b.z0 && z < b.z1) return true;
    }
    return false;
  };
  Mesh m;
  std::map<std::tuple<int, int, int>, uint32_t> index;
  auto vertex = [&](int i, int j, int k) {
    auto [it, fresh] = index.emplace(std::make_tuple(i, j, k), static_cast<uint32_t>(m.vertexCount()));
    if (fresh) m.positions.insert(m.positions.end(), {xs[i], ys[j], zs[k]});
    return it->second;
  };
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      for (int k = 0; k < nz; ++k) {
        if (!solid(i, j, k)) continue;
        for (int axis = 0; axis < 3; ++axis) {
          for (int side = 0; side < 2; ++side) {
            int d[3] = {0, 0, 0};
            d[axis] = side ? 1 : -1;
            if (solid(i + d[0], j + d[1], k + d[2])) continue;
            // Corners of the face on the lattice, counter-clockwise seen from outside.
            const int c[3] = {i, j, k};
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            auto corner = [&](int du, int dv) {
              int p[3] = {c[0], c[1], c[2]};
              p[axis] += side;
              p[u] += du;
              p[v] += dv;
              return vertex(p[0], p[1], p[2]);
            };
            uint32_t q[4] = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
            if (!side) std::swap(q[1], q[3]);
            m.triangles.insert(m.triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
          }
        }
      }
    }
  }
  return m;
}

}  // namespace omnislice::test
