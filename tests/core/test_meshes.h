// SPDX-License-Identifier: MIT
// The generated meshes of the C++ tests, one set: closed solids (box, union of boxes, voxel solid,
// L-bracket, UV sphere, icosphere, torus), an open Moebius strip, tetrahedral grids, and
// operations on meshes (append, flipped, transformed, translated, onPlatform, toSoup). Lengths in
// mm. "Closed outward": edge-manifold, every edge used once in each direction, faces
// counter-clockwise seen from outside, so the signed volume is positive; flipped() turns a mesh
// inward.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <limits>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "common/math_constants.h"
#include "mesh/mesh.h"
#include "tet/tet_mesh.h"

namespace omnislice::test {

// Axis-aligned box [x0,x1]x[y0,y1]x[z0,z1]: 8 vertices, 12 triangles, closed outward.
inline Mesh makeBox(double x0, double y0, double z0, double x1, double y1, double z1) {
  Mesh m;
  m.positions = {x0, y0, z0, x1, y0, z0, x1, y1, z0, x0, y1, z0,
                 x0, y0, z1, x1, y0, z1, x1, y1, z1, x0, y1, z1};
  m.triangles = {0, 2, 1, 0, 3, 2,  4, 5, 6, 4, 6, 7,  0, 1, 5, 0, 5, 4,
                 1, 2, 6, 1, 6, 5,  2, 3, 7, 2, 7, 6,  3, 0, 4, 3, 4, 7};
  return m;
}

// Surface of the solid cells of a rectilinear lattice: xs, ys, zs are the increasing lattice
// coordinates, cell (i, j, k) spans [xs[i], xs[i+1]] x [ys[j], ys[j+1]] x [zs[k], zs[k+1]] and is
// solid when solid(i, j, k). One quad (two triangles, diagonal from the quad's lowest (u, v)
// corner) wherever a solid cell meets an empty one or the outside; vertices numbered in order of
// first use. Closed outward; cells touching along an edge only give non-manifold edges.
inline Mesh latticeSurface(const std::vector<double>& xs, const std::vector<double>& ys,
                           const std::vector<double>& zs,
                           const std::function<bool(int, int, int)>& solid) {
  const int n[3] = {static_cast<int>(xs.size()) - 1, static_cast<int>(ys.size()) - 1,
                    static_cast<int>(zs.size()) - 1};
  auto at = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < n[0] && j < n[1] && k < n[2] && solid(i, j, k);
  };
  Mesh m;
  std::map<std::tuple<int, int, int>, uint32_t> index;
  auto vertex = [&](int i, int j, int k) {
    auto [it, fresh] = index.emplace(std::make_tuple(i, j, k), static_cast<uint32_t>(m.vertexCount()));
    if (fresh) m.positions.insert(m.positions.end(), {xs[i], ys[j], zs[k]});
    return it->second;
  };
  for (int i = 0; i < n[0]; ++i) {
    for (int j = 0; j < n[1]; ++j) {
      for (int k = 0; k < n[2]; ++k) {
        if (!at(i, j, k)) continue;
        for (int axis = 0; axis < 3; ++axis) {
          for (int side = 0; side < 2; ++side) {
            int d[3] = {0, 0, 0};
            d[axis] = side ? 1 : -1;
            if (at(i + d[0], j + d[1], k + d[2])) continue;
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

struct Box {
  double x0, y0, z0, x1, y1, z1;
};

// Union of axis-aligned boxes (L-brackets, T-bars, arches) as one closed outward shell per
// connected part: latticeSurface on the lattice through every box coordinate. The boxes must not
// touch one another along an edge only (that would be non-manifold).
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
  return latticeSurface(xs, ys, zs, [&](int i, int j, int k) {
    const double x = (xs[i] + xs[i + 1]) / 2, y = (ys[j] + ys[j + 1]) / 2, z = (zs[k] + zs[k + 1]) / 2;
    for (const Box& b : boxes) {
      if (x > b.x0 && x < b.x1 && y > b.y0 && y < b.y1 && z > b.z0 && z < b.z1) return true;
    }
    return false;
  });
}

// Unit voxels: cell (i, j, k) of an nx x ny x nz grid (the cube [i, i+1] x [j, j+1] x [k, k+1])
// is solid when filled(i, j, k). latticeSurface on the integer lattice.
inline Mesh makeVoxelSolid(int nx, int ny, int nz, const std::function<bool(int, int, int)>& filled) {
  auto integers = [](int n) {
    std::vector<double> v;
    for (int i = 0; i <= n; ++i) v.push_back(i);
    return v;
  };
  return latticeSurface(integers(nx), integers(ny), integers(nz), filled);
}

// L-bracket of arm thickness a: a post [0,a]x[0,a]x[0,3a] carrying at its top an arm
// [a,3a]x[0,a]x[2a,3a] that overhangs along +x. Closed outward (makeBoxUnion).
inline Mesh makeLBracket(double a) {
  return makeBoxUnion({{0, 0, 0, a, a, 3 * a}, {a, 0, 2 * a, 3 * a, a, 3 * a}});
}

// UV (latitude-longitude) sphere of the given radius about centre, closed outward: a vertex at each
// pole and stacks - 1 rings of latitude with `slices` vertices each (stacks >= 2, slices >= 3),
// 2 slices (stacks - 1) faces. Vertex order: south pole, the rings from south to north (vertex j
// of a ring at longitude 2 pi j / slices, from +x towards +y), north pole. Faces column by column
// (longitude j): the south-pole triangle, the north-pole one, then the quads from south to north,
// each split along the diagonal from (ring i, j) to (ring i+1, j+1).
inline Mesh makeUvSphere(double radius, int slices, int stacks,
                         const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  Mesh m;
  auto add = [&](const Eigen::Vector3d& p) {
    // push_back, not insert of a list into the empty vector: GCC 12 warns (stringop-overflow) there.
    m.positions.push_back(p.x());
    m.positions.push_back(p.y());
    m.positions.push_back(p.z());
    return static_cast<uint32_t>(m.vertexCount() - 1);
  };
  const uint32_t south = add(centre - Eigen::Vector3d(0, 0, radius));
  for (int i = 1; i < stacks; ++i) {
    const double lat = kPi * i / stacks - kPi / 2;
    for (int j = 0; j < slices; ++j) {
      const double lon = 2 * kPi * j / slices;
      add(centre + radius * Eigen::Vector3d(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon),
                                            std::sin(lat)));
    }
  }
  const uint32_t north = add(centre + Eigen::Vector3d(0, 0, radius));
  auto ring = [&](int i, int j) { return static_cast<uint32_t>(1 + (i - 1) * slices + (j % slices)); };
  for (int j = 0; j < slices; ++j) {
    m.triangles.insert(m.triangles.end(), {south, ring(1, j + 1), ring(1, j)});
    m.triangles.insert(m.triangles.end(), {north, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
    for (int i = 1; i + 1 < stacks; ++i) {
      m.triangles.insert(m.triangles.end(), {ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  }
  return m;
}

// Icosphere of the given radius about centre, closed outward: the icosahedron with every face
// split in four `level` times, new vertices pushed onto the sphere; 20 * 4^level faces.
inline Mesh makeIcosphere(double radius, int level, const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
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

// Torus about the z axis through centre, closed outward, genus 1: major radius R, tube radius r,
// nu steps around the axis times nv around the tube, vertex (i, j) at index i nv + j, 2 nu nv
// faces.
inline Mesh makeTorus(double R, double r, int nu, int nv,
                      const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  Mesh m;
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * kPi * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double w = 2 * kPi * j / nv;
      const double rho = R + r * std::cos(w);
      const Eigen::Vector3d p =
          centre + Eigen::Vector3d(rho * std::cos(u), rho * std::sin(u), r * std::sin(w));
      m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
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

// Moebius strip: n quads around a circle of radius R in the xy plane, width 2w, half a twist.
// Open and non-orientable: one boundary curve of 2n edges.
inline Mesh makeMoebius(double R, double w, int n) {
  Mesh m;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * kPi * i / n;
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

// ---- tetrahedral meshes ----

// Appends to m the 6 tets of the Kuhn split of lattice cube (i, j, k): one per order of stepping
// +x, +y, +z from its corner (i, j, k) to the opposite one, so the split is conforming across
// cubes; each tet positively oriented. id(i, j, k) is the index in m of lattice vertex (i, j, k)
// (it may add the vertex).
inline void addKuhnTets(TetMesh& m, int i, int j, int k, const std::function<uint32_t(int, int, int)>& id) {
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& perm : perms) {
    int c[3] = {i, j, k};
    uint32_t t[4];
    t[0] = id(c[0], c[1], c[2]);
    for (int s = 0; s < 3; ++s) {
      ++c[perm[s]];
      t[s + 1] = id(c[0], c[1], c[2]);
    }
    const Eigen::Vector3d a = m.vertex(t[0]);
    if ((m.vertex(t[1]) - a).dot((m.vertex(t[2]) - a).cross(m.vertex(t[3]) - a)) < 0) std::swap(t[2], t[3]);
    m.tets.insert(m.tets.end(), t, t + 4);
  }
}

// Structured grid of nx * ny * nz cubes, each split into 6 tets (addKuhnTets), vertex (i, j, k) at
// map(i/nx, j/ny, k/nz) with index (k (ny + 1) + j) (nx + 1) + i.
inline TetMesh gridTets(int nx, int ny, int nz,
                        const std::function<Eigen::Vector3d(double, double, double)>& map) {
  TetMesh m;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const Eigen::Vector3d p = map(double(i) / nx, double(j) / ny, double(k) / nz);
        m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
      }
  auto id = [&](int i, int j, int k) { return uint32_t((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) addKuhnTets(m, i, j, k, id);
  return m;
}

// ---- operations ----

// b's vertices and faces after a's (separate shells, nothing welded).
inline Mesh append(Mesh a, const Mesh& b) {
  const uint32_t base = static_cast<uint32_t>(a.vertexCount());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (uint32_t v : b.triangles) a.triangles.push_back(base + v);
  return a;
}

// m without the faces whose centroid `cut` selects (holes cut into a model); vertices are kept.
inline Mesh withoutFaces(const Mesh& m, const std::function<bool(const Eigen::Vector3d&)>& cut) {
  Mesh out = m;
  out.triangles.clear();
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d c =
        (m.vertex(m.triangles[3 * f]) + m.vertex(m.triangles[3 * f + 1]) + m.vertex(m.triangles[3 * f + 2])) / 3;
    if (!cut(c)) out.triangles.insert(out.triangles.end(), m.triangles.begin() + 3 * f, m.triangles.begin() + 3 * f + 3);
  }
  return out;
}

// m without the faces whose centroid lies within radius of one of `holes` random vertices.
inline Mesh withHolesCut(const Mesh& m, int holes, double radius, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Eigen::Vector3d> centres;
  for (int h = 0; h < holes; ++h) centres.push_back(m.vertex(rng() % m.vertexCount()));
  return withoutFaces(m, [&](const Eigen::Vector3d& c) {
    for (const Eigen::Vector3d& q : centres) {
      if ((c - q).norm() < radius) return true;
    }
    return false;
  });
}

// Every face reversed (outward <-> inward).
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

// p -> p + t for every vertex.
inline Mesh translated(Mesh m, const Eigen::Vector3d& t) {
  for (size_t i = 0; i < m.vertexCount(); ++i) {
    for (int k = 0; k < 3; ++k) m.positions[3 * i + k] += t[k];
  }
  return m;
}

// Moved along z so its lowest vertex lies on the platform, z = 0 exactly (x, y kept).
inline Mesh onPlatform(Mesh m) {
  double zmin = std::numeric_limits<double>::infinity();
  for (size_t v = 0; v < m.vertexCount(); ++v) zmin = std::min(zmin, m.positions[3 * v + 2]);
  for (size_t v = 0; v < m.vertexCount(); ++v) m.positions[3 * v + 2] -= zmin;
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

}  // namespace omnislice::test
