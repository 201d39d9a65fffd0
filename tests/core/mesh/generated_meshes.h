// SPDX-License-Identifier: MIT
// Generated meshes for the mesh-preparation tests: icosphere, torus, Moebius strip, triangle soups,
// transforms, and independent (plain double) volume / area sums.
#pragma once
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "mesh/mesh.h"

#include "../test_support.h"

namespace omnislice::test {

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

inline double surfaceArea(const Mesh& m) {
  double a = 0;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d p = m.vertex(m.triangles[3 * f]);
    a += (m.vertex(m.triangles[3 * f + 1]) - p).cross(m.vertex(m.triangles[3 * f + 2]) - p).norm() / 2;
  }
  return a;
}

}  // namespace omnislice::test
