// SPDX-License-Identifier: MIT
// Per-vertex differential geometry of a triangle surface and the test surfaces of paper 003.
//
// Curvature fit: in the vertex's frame (tU, tV, n) with the vertex at the origin, the 2-ring
// points (u, v, w) are fitted by least squares to
//   w = a u^2 + b uv + c v^2 + d u + e v + f w^2 + g uw + h vw,
// an implicit quadric F = Q(u, v, w) - w = 0 through the vertex normalised by its w coefficient.
// Every quadric surface through the vertex and transversal to n (spheres, cylinders, the saddle
// seen from any tilted frame) satisfies this exactly, so the fit reproduces them to rounding;
// the terms in w vanish on a plane (the minimum-norm solution then drops them). The sample's
// normal is the fitted one, -grad F / |grad F| (exact on quadrics, where area-weighted normals of
// an irregular triangulation are off by O(edge)); the second fundamental form in an orthonormal
// basis (e1, e2) of its tangent plane is -e_i^T Hess(F) e_j / |grad F| (dome seen from its normal
// side > 0).
#include "isoplanar/surface_samples.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

namespace omnislice {
namespace {

Eigen::Vector3d perpendicularTo(const Eigen::Vector3d& n) {
  // Project the world axis least aligned with n: x unless n is close to it.
  const Eigen::Vector3d axis = std::fabs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX()
                                                      : Eigen::Vector3d::UnitY();
  return (axis - axis.dot(n) * n).normalized();
}

// Implicit quadric F = Q(u, v, w) - w fitted to local points (u, v, w), vertex at the origin:
// Hessian of F and its gradient at the origin, in the frame's coordinates.
constexpr size_t kMaxPoints = 96;
using FitMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 96, 8>;
using FitVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 96, 1>;

struct QuadricFit {
  bool ok = false;
  bool full = false;  // all 8 terms determined (rank 8)
  Eigen::Matrix3d hess = Eigen::Matrix3d::Zero();
  Eigen::Vector3d grad{0, 0, -1};
};

QuadricFit fitQuadric(const std::vector<Eigen::Vector3d>& local, bool implicitTerms) {
  QuadricFit q;
  // At most kMaxPoints (the nearest rings first): fixed-capacity matrices, no heap per vertex.
  const size_t m = std::min(local.size(), kMaxPoints);
  if (m < 3) return q;
  double scale = 0;
  for (size_t i = 0; i < m; ++i) scale += local[i].x() * local[i].x() + local[i].y() * local[i].y();
  scale = std::sqrt(scale / m);
  if (!(scale > 0)) return q;
  const int cols = implicitTerms && m >= 10 ? 8 : (m >= 6 ? 5 : 3);
  FitMatrix A(m, cols);
  FitVector rhs(m);
  for (size_t i = 0; i < m; ++i) {
    const double u = local[i].x() / scale, v = local[i].y() / scale, w = local[i].z() / scale;
    A(i, 0) = u * u;
    A(i, 1) = u * v;
    A(i, 2) = v * v;
    if (cols > 3) {
      A(i, 3) = u;
      A(i, 4) = v;
    }
    if (cols > 5) {
      A(i, 5) = w * w;
      A(i, 6) = u * w;
      A(i, 7) = v * w;
    }
    rhs(i) = w;
  }
  Eigen::CompleteOrthogonalDecomposition<FitMatrix> cod(A);
  cod.setThreshold(1e-9);
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 8, 1> x = cod.solve(rhs);
  if (!x.allFinite()) return q;
  q.full = cols == 8 && cod.rank() == 8;
  q.hess(0, 0) = 2 * x(0);
  q.hess(0, 1) = q.hess(1, 0) = x(1);
  q.hess(1, 1) = 2 * x(2);
  if (cols > 3) q.grad.head<2>() << x(3), x(4);
  if (cols > 5) {
    q.hess(2, 2) = 2 * x(5);
    q.hess(0, 2) = q.hess(2, 0) = x(6);
    q.hess(1, 2) = q.hess(2, 1) = x(7);
  }
  q.hess /= scale;  // back to unscaled coordinates (the gradient is scale-free)
  q.ok = true;
  return q;
}

}  // namespace

Eigen::Matrix3d shapeTensor(const SurfaceSample& sample) {
  Eigen::Matrix<double, 3, 2> basis;
  basis.col(0) = sample.tangentU;
  basis.col(1) = sample.tangentV;
  return basis * sample.shape * basis.transpose();
}

double normalCurvature(const SurfaceSample& sample, const Eigen::Vector3d& direction) {
  Eigen::Vector3d t = direction - direction.dot(sample.normal) * sample.normal;
  const double len = t.norm();
  if (!(len > 1e-12 * std::max(1.0, direction.norm()))) return 0;
  t /= len;
  const double a = t.dot(sample.tangentU), b = t.dot(sample.tangentV);
  return a * a * sample.shape(0, 0) + 2 * a * b * sample.shape(0, 1) + b * b * sample.shape(1, 1);
}

SurfaceSamplesResult surfaceSamples(const Mesh& surface, double layerHeight) {
  SurfaceSamplesResult r;
  if (!std::isfinite(layerHeight) || layerHeight <= 0) {
    r.status = Status::InvalidOption;
    r.message = "layer height must be a positive number of mm";
    return r;
  }
  if (surface.empty() || surface.vertexCount() == 0) {
    r.status = Status::EmptyInput;
    r.message = "the surface has no triangles";
    return r;
  }
  const size_t nv = surface.vertexCount(), nf = surface.faceCount();
  for (double c : surface.positions)
    if (!std::isfinite(c)) {
      r.status = Status::NonFiniteVertex;
      r.message = "the surface has a non-finite vertex coordinate";
      return r;
    }
  for (uint32_t i : surface.triangles)
    if (i >= nv) {
      r.status = Status::EmptyInput;
      r.message = "a triangle refers to vertex " + std::to_string(i) + " of " +
                  std::to_string(nv);
      return r;
    }
  std::vector<Eigen::Vector3d> normals(nv, Eigen::Vector3d::Zero());
  std::vector<std::vector<uint32_t>> adjacent(nv);
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &surface.triangles[3 * f];
    const Eigen::Vector3d a = surface.vertex(t[0]), b = surface.vertex(t[1]),
                          c = surface.vertex(t[2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);  // twice the area, along the normal
    for (int k = 0; k < 3; ++k) {
      normals[t[k]] += n;
      for (int j = 1; j < 3; ++j) adjacent[t[k]].push_back(t[(k + j) % 3]);
    }
  }
  for (auto& list : adjacent) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  r.samples.resize(nv);
  std::vector<uint32_t> mark(nv, 0), ring;
  std::vector<Eigen::Vector3d> local;
  uint32_t stamp = 0;
  for (size_t v = 0; v < nv; ++v) {
    SurfaceSample& s = r.samples[v];
    s.position = surface.vertex(v);
    s.height = layerHeight;
    const double len = normals[v].norm();
    if (!(len > 0)) continue;  // isolated or only degenerate faces: default frame, flat
    s.normal = normals[v] / len;
    s.tangentU = perpendicularTo(s.normal);
    s.tangentV = s.normal.cross(s.tangentU);
    // 2-ring; grown to the 3- and 4-ring while the full fit is not determined (too few points,
    // or points on too few lines, as on a cylinder's boundary row).
    ++stamp;
    ring.assign(1, static_cast<uint32_t>(v));
    mark[v] = stamp;
    size_t begin = 0;
    const Eigen::Vector3d fu = s.tangentU, fv = s.tangentV, fn = s.normal;
    QuadricFit q;
    local.clear();
    for (int depth = 1; depth <= 4; ++depth) {
      const size_t end = ring.size();
      for (size_t i = begin; i < end; ++i)
        for (uint32_t w : adjacent[ring[i]])
          if (mark[w] != stamp) {
            mark[w] = stamp;
            ring.push_back(w);
            const Eigen::Vector3d d = surface.vertex(w) - s.position;
            local.emplace_back(d.dot(fu), d.dot(fv), d.dot(fn));
          }
      begin = end;
      if (depth < 2) continue;
      q = fitQuadric(local, true);
      if (q.ok && q.full) break;
      if (ring.size() == end) break;  // nothing more to add
    }
    if (!q.ok || !q.full) q = fitQuadric(local, false);  // plain quadric height field
    if (!q.ok) continue;
    // Fitted normal (on the side of the area-weighted one); kept only when it agrees within
    // ~37 degrees (a fit across a crease or on a ragged patch falls back to the mesh normal).
    const Eigen::Vector3d m = -q.grad / q.grad.norm();  // frame coordinates, m.z() > 0
    if (m.z() > 0.8) {
      s.normal = (m.x() * fu + m.y() * fv + m.z() * fn).normalized();
      s.tangentU = perpendicularTo(s.normal);
      s.tangentV = s.normal.cross(s.tangentU);
    }
    // Second fundamental form of F = 0 along the sample's tangents (projected onto the fitted
    // tangent plane when the normal fell back).
    Eigen::Vector3d e[2];
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d t = k == 0 ? s.tangentU : s.tangentV;
      e[k] = Eigen::Vector3d(t.dot(fu), t.dot(fv), t.dot(fn));
      e[k] -= e[k].dot(m) * m;
    }
    const double g = q.grad.norm();
    s.shape(0, 0) = -e[0].dot(q.hess * e[0]) / g;
    s.shape(0, 1) = s.shape(1, 0) = -e[0].dot(q.hess * e[1]) / g;
    s.shape(1, 1) = -e[1].dot(q.hess * e[1]) / g;
  }
  return r;
}

SurfaceSample blendSamples(const SurfaceSample& a, const SurfaceSample& b, double t) {
  SurfaceSample s;
  s.position = (1 - t) * a.position + t * b.position;
  Eigen::Vector3d n = (1 - t) * a.normal + t * b.normal;
  s.normal = n.norm() > 1e-12 ? Eigen::Vector3d(n.normalized()) : a.normal;
  Eigen::Vector3d u = (1 - t) * a.tangentU + t * b.tangentU;
  u -= u.dot(s.normal) * s.normal;
  s.tangentU = u.norm() > 1e-9 ? Eigen::Vector3d(u.normalized()) : perpendicularTo(s.normal);
  s.tangentV = s.normal.cross(s.tangentU);
  const Eigen::Matrix3d T = (1 - t) * shapeTensor(a) + t * shapeTensor(b);
  s.shape(0, 0) = s.tangentU.dot(T * s.tangentU);
  s.shape(0, 1) = s.shape(1, 0) = s.tangentU.dot(T * s.tangentV);
  s.shape(1, 1) = s.tangentV.dot(T * s.tangentV);
  s.height = (1 - t) * a.height + t * b.height;
  return s;
}

namespace {

// Regular (ns x nt) grid over a parametric rectangle, quads split along alternating diagonals,
// counter-clockwise seen from +Z when the map keeps the orientation of (s, t).
template <class Map>
Mesh gridSurface(int ns, int nt, Map map) {
  Mesh m;
  m.positions.reserve(3 * static_cast<size_t>(ns) * nt);
  for (int j = 0; j < nt; ++j)
    for (int i = 0; i < ns; ++i) {
      const Eigen::Vector3d p = map(static_cast<double>(i) / (ns - 1),
                                    static_cast<double>(j) / (nt - 1));
      m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
    }
  auto id = [ns](int i, int j) { return static_cast<uint32_t>(j * ns + i); };
  for (int j = 0; j + 1 < nt; ++j)
    for (int i = 0; i + 1 < ns; ++i) {
      const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0) m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
      else m.triangles.insert(m.triangles.end(), {a, b, d, b, c, d});
    }
  return m;
}

}  // namespace

Mesh makeSaddleSurface(double radius, double half, int vertices) {
  if (!(radius > 0) || !(half > 0) || !std::isfinite(radius) || !std::isfinite(half)) return {};
  const int n = std::max(2, static_cast<int>(std::lround(std::sqrt(std::max(vertices, 4)))));
  return gridSurface(n, n, [&](double s, double t) {
    const double x = -half + 2 * half * s, y = -half + 2 * half * t;
    return Eigen::Vector3d(x, y, (x * x - y * y) / radius);
  });
}

// Bicycle-seat-like surface, all dimensions relative to the length L along x (rear at -L/2,
// nose at +L/2). Parameters (s, t) in [0, 1]^2, xi = s from rear to nose, tau = 2t - 1 across.
//  - outline: half-width W(xi) = L (0.065 + 0.21 S(xi)), S a smoothstep from 1 (xi <= 0.3) to
//    0 (xi >= 0.75): wide rear (0.55 L), narrow nose (0.13 L); the rear edge bows back by 0.08 L
//    at the middle (corners forward) and the nose is rounded by 0.03 L;
//  - height: z = zc(xi) - 0.12 L (W / 0.275 L) tau^2 (convex across, falling towards the sides,
//    less at the narrow nose), zc a C1 dip: 0.03 L higher at the rear, 0.08 L higher at the nose
//    than at its lowest point xi = 0.35.
Mesh makeSeatSurface(double length, int vertices) {
  if (!(length > 0) || !std::isfinite(length)) return {};
  const double L = length;
  const int total = std::max(vertices, 9);
  const int ns = std::max(3, static_cast<int>(std::lround(std::sqrt(total * 1.6))));
  int nt = std::max(3, static_cast<int>(std::lround(static_cast<double>(total) / ns)));
  if (nt % 2 == 0) ++nt;  // odd: a row of vertices on the symmetry axis y = 0
  auto halfWidth = [L](double xi) {
    double u = (xi - 0.3) / 0.45;
    u = std::min(1.0, std::max(0.0, u));
    const double S = 1 - u * u * (3 - 2 * u);
    return L * (0.065 + 0.21 * S);
  };
  auto centre = [L](double xi) {
    if (xi < 0.35) {
      const double u = (0.35 - xi) / 0.35;
      return 0.03 * L * u * u;
    }
    const double u = (xi - 0.35) / 0.65;
    return 0.08 * L * u * u;
  };
  return gridSurface(ns, nt, [&](double s, double t) {
    const double tau = 2 * t - 1;
    const double xRear = -L / 2 + 0.08 * L * tau * tau;
    const double xNose = L / 2 - 0.03 * L * tau * tau;
    const double x = (1 - s) * xRear + s * xNose;
    const double W = halfWidth(s);
    const double y = tau * W;
    const double z = centre(s) - 0.12 * L * (W / (0.275 * L)) * tau * tau;
    return Eigen::Vector3d(x, y, z);
  });
}

}  // namespace omnislice
