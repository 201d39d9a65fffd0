// SPDX-License-Identifier: MIT
// Test surfaces for the boundary-distance and Fermat-spiral tests: planar domains given by an
// implicit function (negative inside) meshed on a regular grid whose triangles are clipped by the
// zero set (boundary vertices snapped onto it), optionally mapped onto a curved surface.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "mesh/mesh.h"

namespace omnislice::test {

using Implicit2D = std::function<double(const Eigen::Vector2d&)>;
using Map3D = std::function<Eigen::Vector3d(const Eigen::Vector2d&)>;

// Planar mesh of {f <= 0} inside the box [lo, hi], grid step h (alternating diagonals), boundary
// on the zero set of f (Newton-projected). Triangles counter-clockwise seen from +z (before map).
inline Mesh meshImplicit2D(const Implicit2D& f, Eigen::Vector2d lo, Eigen::Vector2d hi, double h,
                           const Map3D& map = {}) {
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / h)) + 1;
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / h)) + 1;
  auto project = [&](Eigen::Vector2d p) {
    for (int it = 0; it < 20; ++it) {
      const double v = f(p);
      if (std::abs(v) < 1e-12) break;
      const double e = 1e-7;
      const Eigen::Vector2d g((f(p + Eigen::Vector2d(e, 0)) - f(p - Eigen::Vector2d(e, 0))) / (2 * e),
                              (f(p + Eigen::Vector2d(0, e)) - f(p - Eigen::Vector2d(0, e))) / (2 * e));
      if (g.squaredNorm() < 1e-20) break;
      p -= v * g / g.squaredNorm();
    }
    return p;
  };
  std::vector<Eigen::Vector2d> pts;
  std::vector<double> val;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      Eigen::Vector2d p(lo.x() + i * h, lo.y() + j * h);
      double v = f(p);
      if (std::abs(v) < 0.3 * h && std::abs(v) > 0) {
        p = project(p);
        v = 0;
      }
      pts.push_back(p);
      val.push_back(v);
    }
  }
  std::map<std::pair<int, int>, int> crossings;
  auto crossing = [&](int a, int b) {
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    auto it = crossings.find(key);
    if (it != crossings.end()) return it->second;
    const double t = val[a] / (val[a] - val[b]);
    Eigen::Vector2d p = project(pts[a] + t * (pts[b] - pts[a]));
    pts.push_back(p);
    val.push_back(0);
    crossings[key] = static_cast<int>(pts.size()) - 1;
    return static_cast<int>(pts.size()) - 1;
  };
  std::vector<int> tris;
  auto clipTriangle = [&](int a, int b, int c) {
    const int v[3] = {a, b, c};
    std::vector<int> poly;
    for (int k = 0; k < 3; ++k) {
      const int p = v[k], q = v[(k + 1) % 3];
      if (val[p] <= 0) poly.push_back(p);
      if ((val[p] < 0 && val[q] > 0) || (val[p] > 0 && val[q] < 0)) poly.push_back(crossing(p, q));
    }
    for (size_t k = 1; k + 1 < poly.size(); ++k) {
      const Eigen::Vector2d e1 = pts[poly[k]] - pts[poly[0]], e2 = pts[poly[k + 1]] - pts[poly[0]];
      if (e1.x() * e2.y() - e1.y() * e2.x() > 1e-12 * h * h) {
        tris.insert(tris.end(), {poly[0], poly[k], poly[k + 1]});
      }
    }
  };
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const int v00 = j * nx + i, v10 = v00 + 1, v01 = v00 + nx, v11 = v01 + 1;
      if ((i + j) % 2 == 0) {
        clipTriangle(v00, v10, v11);
        clipTriangle(v00, v11, v01);
      } else {
        clipTriangle(v00, v10, v01);
        clipTriangle(v10, v11, v01);
      }
    }
  }
  std::vector<int> remap(pts.size(), -1);
  Mesh m;
  for (int v : tris) {
    if (remap[v] < 0) {
      remap[v] = static_cast<int>(m.positions.size() / 3);
      const Eigen::Vector3d p = map ? map(pts[v]) : Eigen::Vector3d(pts[v].x(), pts[v].y(), 0.0);
      m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
    }
    m.triangles.push_back(static_cast<uint32_t>(remap[v]));
  }
  return m;
}

inline double boxSdf(const Eigen::Vector2d& p, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const Eigen::Vector2d c = 0.5 * (lo + hi), r = 0.5 * (hi - lo);
  const Eigen::Vector2d d = (p - c).cwiseAbs() - r;
  return d.cwiseMax(0.0).norm() + std::min(std::max(d.x(), d.y()), 0.0);
}

inline Mesh makeDisc(double radius, double h) {
  return meshImplicit2D([=](const Eigen::Vector2d& p) { return p.norm() - radius; },
                        Eigen::Vector2d(-radius - h, -radius - h), Eigen::Vector2d(radius + h, radius + h), h);
}

inline Mesh makeRectangle(double w, double hgt, double h, const Map3D& map = {}) {
  return meshImplicit2D(
      [=](const Eigen::Vector2d& p) { return boxSdf(p, {0, 0}, {w, hgt}); }, Eigen::Vector2d(-h, -h),
      Eigen::Vector2d(w + h, hgt + h), h, map);
}

// L shape: [0, 2a]^2 minus [a, 2a]^2.
inline Mesh makeLShape(double a, double h) {
  return meshImplicit2D(
      [=](const Eigen::Vector2d& p) {
        return std::max(boxSdf(p, {0, 0}, {2 * a, 2 * a}), -boxSdf(p, {a, a}, {2 * a + 1, 2 * a + 1}));
      },
      Eigen::Vector2d(-h, -h), Eigen::Vector2d(2 * a + h, 2 * a + h), h);
}

inline Mesh makeAnnulus(double r0, double r1, double h) {
  return meshImplicit2D([=](const Eigen::Vector2d& p) { return std::max(p.norm() - r1, r0 - p.norm()); },
                        Eigen::Vector2d(-r1 - h, -r1 - h), Eigen::Vector2d(r1 + h, r1 + h), h);
}

// Two discs of radius r centred at (+-c, 0) joined by a neck of half-width w.
inline Mesh makeDumbbell(double r, double c, double w, double h) {
  return meshImplicit2D(
      [=](const Eigen::Vector2d& p) {
        const double d1 = (p - Eigen::Vector2d(-c, 0)).norm() - r;
        const double d2 = (p - Eigen::Vector2d(c, 0)).norm() - r;
        const double neck = boxSdf(p, {-c, -w}, {c, w});
        return std::min({d1, d2, neck});
      },
      Eigen::Vector2d(-c - r - h, -r - h), Eigen::Vector2d(c + r + h, r + h), h);
}

// Spherical cap of sphere radius R whose rim lies at geodesic distance rho from the pole; the
// disc is mapped by the azimuthal equidistant map, so the exact geodesic distance to the rim of
// a point at planar radius q is rho - q.
inline Mesh makeSphericalCap(double R, double rho, double h) {
  return meshImplicit2D(
      [=](const Eigen::Vector2d& p) { return p.norm() - rho; }, Eigen::Vector2d(-rho - h, -rho - h),
      Eigen::Vector2d(rho + h, rho + h), h, [=](const Eigen::Vector2d& p) {
        const double q = p.norm();
        if (q < 1e-15) return Eigen::Vector3d(0, 0, R);
        const double phi = q / R;
        return Eigen::Vector3d(R * std::sin(phi) * p.x() / q, R * std::sin(phi) * p.y() / q,
                               R * std::cos(phi));
      });
}

// Boundary edges (vertex pairs) of a mesh: edges used by one triangle.
inline std::vector<std::pair<uint32_t, uint32_t>> boundaryEdges(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> count;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (const auto& [e, c] : count) {
    if (c == 1) out.push_back(e);
  }
  return out;
}

inline double pointSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace omnislice::test
