// SPDX-License-Identifier: MIT
// The generated meshes of the C++ tests, one set: closed solids (box, union of boxes, icosphere,
// torus), an open Moebius strip, tetrahedral grids, and operations on meshes (toSoup, append,
// flipped, transformed). Lengths in mm. "Closed outward": edge-manifold, every edge used once in
// each direction, faces counter-clockwise seen from outside, so the signed volume is positive;
// flipped() turns a mesh inward.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "mesh/mesh.h"
#include "tet/tet_mesh.h"

namespace omnislice::test {

// Axis-aligned box [x0,x1]x[y0,y1]x[z0,z1] as 8 vertices / 12 outward-oriented triangles.
inline Mesh makeBox(double x0, double y0, double z0, double x1, double y1, double z1) {
  Mesh m;
  m.positions = {x0, y0, z0, x1, y0, z0, x1, y1, z0, x0, y1, z0,
                 x0, y0, z1, x1, y0, z1, x1, y1, z1, x0, y1, z1};
  m.triangles = {0, 2, 1, 0, 3, 2,  4, 5, 6, 4, 6, 7,  0, 1, 5, 0, 5, 4,
                 1, 2, 6, 1, 6, 5,  2, 3, 7, 2, 7, 6,  3, 0, 4, 3, 4, 7};
  return m;
}

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

// Closed outward icosphere: 20 * 4^level faces, vertices on the sphere of the given radius.
inline Mesh makeIcosphere(double radius, int level, Eigen::Vector3d centre = Eigen::Vector3d::Zero()) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> v = {{-1, g, 0}, {1, g, 0},  {-1, -g, 0}, {1, -g, 0},
                                    {0, -1, g}, {0, 1, g},  {0, -1, -g}, {0, 1, -g},
                                    {g, 0, -1}, {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<uint32_t> f = {0, 11, 5, 0, 5,  1, 0,  1, 7, 0,  7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                             4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3, 4,  2, 3, 2, 6, 3,
                             6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8, 6, 7, 9, 8, 1};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      const uint32_t id = static_cast<uint32_t>(v.size() - 1);
      mid.emplace(key, id);
      return id;
    };
    std::vector<uint32_t> next;
    for (size_t i = 0; i < f.size(); i += 3) {
      const uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f.swap(next);
  }
  Mesh m;
  for (const auto& p : v) {
    const Eigen::Vector3d q = centre + radius * p;
    m.positions.insert(m.positions.end(), {q.x(), q.y(), q.z()});
  }
  m.triangles = f;
  return m;
}

// Closed outward torus around the z axis: major radius R, minor radius r, nu x nv quads,
// 2 * nu * nv faces, genus 1.
inline Mesh makeTorus(double R, double r, int nu, int nv) {
  Mesh m;
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * M_PI * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double w = 2 * M_PI * j / nv;
      const double rho = R + r * std::cos(w);
      m.positions.insert(m.positions.end(), {rho * std::cos(u), rho * std::sin(u), r * std::sin(w)});
    }
  }
  auto id = [&](int i, int j) { return static_cast<uint32_t>((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

// Moebius strip: n quads around a circle of radius R, width 2w, half a twist. Non-orientable,
// one boundary curve of 2n edges.
inline Mesh makeMoebius(double R, double w, int n) {
  Mesh m;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    for (int s = -1; s <= 1; s += 2) {
      const double off = s * w;
      const double rho = R + off * std::cos(t / 2);
      m.positions.insert(m.positions.end(), {rho * std::cos(t), rho * std::sin(t), off * std::sin(t / 2)});
    }
  }
  for (int i = 0; i < n; ++i) {
    const uint32_t a = 2 * i, b = 2 * i + 1;
    uint32_t c, d;  // next rung; the last one joins the first with its sides swapped
    if (i + 1 < n) {
      c = 2 * (i + 1);
      d = 2 * (i + 1) + 1;
    } else {
      c = 1;
      d = 0;
    }
    m.triangles.insert(m.triangles.end(), {a, c, d, a, d, b});
  }
  return m;
}

// Structured grid of nx*ny*nz cubes, each split into 6 tets around its main diagonal (Kuhn
// split, conforming across cubes), vertex (i, j, k) at map(i/nx, j/ny, k/nz) with index
// (k (ny + 1) + j) (nx + 1) + i; every tet positively oriented.
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

// ---- operations ----

// The same faces with 3 private vertices each, as an STL file stores them.
inline Mesh toSoup(const Mesh& m) {
  Mesh s;
  for (uint32_t v : m.triangles) {
    s.positions.insert(s.positions.end(), m.positions.begin() + 3 * v, m.positions.begin() + 3 * v + 3);
    s.triangles.push_back(static_cast<uint32_t>(s.triangles.size()));
  }
  return s;
}

// Concatenate b after a (no welding).
inline Mesh append(Mesh a, const Mesh& b) {
  const uint32_t base = static_cast<uint32_t>(a.vertexCount());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (uint32_t v : b.triangles) a.triangles.push_back(base + v);
  return a;
}

// Reverse every face.
inline Mesh flipped(Mesh m) {
  for (size_t f = 0; f < m.faceCount(); ++f) std::swap(m.triangles[3 * f + 1], m.triangles[3 * f + 2]);
  return m;
}

// p -> R p + t for every vertex.
inline Mesh transformed(Mesh m, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  for (size_t i = 0; i < m.vertexCount(); ++i) {
    const Eigen::Vector3d q = R * m.vertex(i) + t;
    for (int k = 0; k < 3; ++k) m.positions[3 * i + k] = q[k];
  }
  return m;
}

}  // namespace omnislice::test
