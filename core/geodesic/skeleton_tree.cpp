// SPDX-License-Identifier: MIT
// The skeleton tree of the IGDS (skeleton_tree.h, paper 002 Algorithm 1): a hash grid of the
// layers' open boundary segments, steepest paths on the boundary surface carrying the geodesic
// distance, and the links they make between consecutive layers' regions.
#include "geodesic/skeleton_tree.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

#include "common/stopwatch.h"
#include "geodesic/print_order_detail.h"

namespace omnislice {
namespace {

using Vec3 = Eigen::Vector3d;
using print_order_detail::closestOnSegment;
using print_order_detail::edgeKey;
using print_order_detail::regionValid;

// Boundary edges (used by exactly one triangle) of a region mesh, as vertex pairs.
std::vector<std::array<uint32_t, 2>> openEdges(const Mesh& m) {
  std::unordered_map<uint64_t, int> count;
  count.reserve(m.triangles.size());
  for (size_t f = 0; f < m.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) ++count[edgeKey(m.triangles[3 * f + k], m.triangles[3 * f + (k + 1) % 3])];
  std::vector<std::array<uint32_t, 2>> out;
  for (size_t f = 0; f < m.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
      if (count[edgeKey(a, b)] == 1) out.push_back({a, b});
    }
  return out;
}

// ------------------------------------------------------------------------------------------------
// Uniform hash grid of segments (nearest-segment queries within a radius).
class SegmentGrid {
 public:
  void build(std::vector<std::array<Vec3, 2>> segs, std::vector<uint32_t> owner, double cell) {
    segs_ = std::move(segs);
    owner_ = std::move(owner);
    cell_ = cell > 0 ? cell : 1.0;
    cells_.clear();
    for (uint32_t s = 0; s < segs_.size(); ++s) {
      const Vec3 lo = segs_[s][0].cwiseMin(segs_[s][1]), hi = segs_[s][0].cwiseMax(segs_[s][1]);
      const auto a = cellOf(lo), b = cellOf(hi);
      for (int64_t x = a[0]; x <= b[0]; ++x)
        for (int64_t y = a[1]; y <= b[1]; ++y)
          for (int64_t z = a[2]; z <= b[2]; ++z) cells_[key(x, y, z)].push_back(s);
    }
  }
  bool empty() const { return segs_.empty(); }
  // Owner of the nearest segment within radius (or -1), and its distance.
  int64_t nearest(const Vec3& p, double radius, double* dist = nullptr) const {
    const auto a = cellOf(p - Vec3::Constant(radius)), b = cellOf(p + Vec3::Constant(radius));
    double best = radius;
    int64_t who = -1;
    for (int64_t x = a[0]; x <= b[0]; ++x)
      for (int64_t y = a[1]; y <= b[1]; ++y)
        for (int64_t z = a[2]; z <= b[2]; ++z) {
          const auto it = cells_.find(key(x, y, z));
          if (it == cells_.end()) continue;
          for (uint32_t s : it->second) {
            const double d = (closestOnSegment(p, segs_[s][0], segs_[s][1]) - p).norm();
            if (d <= best) {
              best = d;
              who = owner_[s];
            }
          }
        }
    if (dist) *dist = best;
    return who;
  }
  // Nearest owner without radius limit (brute force; used for fallback links only).
  int64_t nearestAnywhere(const Vec3& p, double* dist) const {
    double best = std::numeric_limits<double>::infinity();
    int64_t who = -1;
    for (size_t s = 0; s < segs_.size(); ++s) {
      const double d = (closestOnSegment(p, segs_[s][0], segs_[s][1]) - p).squaredNorm();
      if (d < best) {
        best = d;
        who = owner_[s];
      }
    }
    *dist = std::sqrt(best);
    return who;
  }

 private:
  std::array<int64_t, 3> cellOf(const Vec3& p) const {
    return {int64_t(std::floor(p.x() / cell_)), int64_t(std::floor(p.y() / cell_)),
            int64_t(std::floor(p.z() / cell_))};
  }
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return (uint64_t(x & 0x1fffff) << 42) | (uint64_t(y & 0x1fffff) << 21) | uint64_t(z & 0x1fffff);
  }
  std::vector<std::array<Vec3, 2>> segs_;
  std::vector<uint32_t> owner_;
  double cell_ = 1;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

// ------------------------------------------------------------------------------------------------
// Steepest paths on a triangle surface carrying a piecewise-linear field.
class SteepestTracer {
 public:
  SteepestTracer(const Mesh& m, const std::vector<double>& f) : m_(m), f_(f) {
    const size_t nv = m.vertexCount(), nf = m.faceCount();
    P_.resize(nv);
    for (size_t v = 0; v < nv; ++v) P_[v] = m.vertex(v);
    grad_.assign(nf, Vec3::Zero());
    for (size_t t = 0; t < nf; ++t) {
      const uint32_t* tri = &m.triangles[3 * t];
      const Vec3 e1 = P_[tri[1]] - P_[tri[0]], e2 = P_[tri[2]] - P_[tri[0]];
      const double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2), det = a * c - b * b;
      if (!(det > 1e-20 * a * c)) continue;  // degenerate triangle: no gradient
      const double r1 = f[tri[1]] - f[tri[0]], r2 = f[tri[2]] - f[tri[0]];
      const double al = (c * r1 - b * r2) / det, be = (a * r2 - b * r1) / det;
      grad_[t] = al * e1 + be * e2;
    }
    // Vertex -> triangles (CSR) and edge -> triangles.
    vstart_.assign(nv + 1, 0);
    for (uint32_t v : m.triangles) ++vstart_[v + 1];
    for (size_t v = 0; v < nv; ++v) vstart_[v + 1] += vstart_[v];
    vtris_.resize(m.triangles.size());
    std::vector<uint32_t> fill(vstart_.begin(), vstart_.end() - 1);
    for (size_t t = 0; t < nf; ++t)
      for (int k = 0; k < 3; ++k) vtris_[fill[m.triangles[3 * t + k]]++] = uint32_t(t);
    double total = 0;
    size_t count = 0;
    for (size_t t = 0; t < nf; ++t)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = m.triangles[3 * t + k], b = m.triangles[3 * t + (k + 1) % 3];
        if (a < b) {
          edges_.push_back({a, b});
          total += (P_[a] - P_[b]).norm();
          ++count;
        }
      }
    // Edges seen only as b < a (open boundary of a non-closed surface) are added too.
    for (size_t t = 0; t < nf; ++t)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = m.triangles[3 * t + k], b = m.triangles[3 * t + (k + 1) % 3];
        if (a > b && !hasTriangleWithDirectedEdge(b, a)) edges_.push_back({b, a});
      }
    meanEdge_ = count ? total / count : 1.0;
    maxSteps_ = 4 * nf + 1000;
  }

  double meanEdge() const { return meanEdge_; }
  const std::vector<std::array<uint32_t, 2>>& edges() const { return edges_; }
  const Vec3& point(uint32_t v) const { return P_[v]; }

  // Traces from point x on mesh edge (u, w) in direction sign (+1 ascending, -1 descending) until
  // the field reaches target; returns false when the path stalls (flat, local extremum, step cap).
  bool trace(uint32_t u, uint32_t w, const Vec3& x, int sign, double target, Vec3& end) const {
    State s;
    s.kind = State::OnEdge;
    s.a = u;
    s.b = w;
    s.x = x;
    s.g = sign * fieldAt(x, u, w);
    s.fromTri = -1;
    const double gTarget = sign * target;
    double bestG = s.g;
    size_t idle = 0;
    for (size_t step = 0; step < maxSteps_; ++step) {
      if (s.g >= gTarget) {
        end = s.x;
        return true;
      }
      if (s.g > bestG + 1e-12 * (1 + std::abs(bestG))) {
        bestG = s.g;
        idle = 0;
      } else if (++idle > 64) {
        return false;  // no progress: numerically stuck
      }
      bool done = false;
      switch (s.kind) {
        case State::OnEdge: done = stepEdge(s, sign, gTarget, end); break;
        case State::AtVertex: done = stepVertex(s, sign, gTarget, end); break;
        case State::InTri: done = stepTri(s, sign, gTarget, end); break;
        case State::Stalled: return false;
      }
      if (done) return true;
    }
    return false;
  }

 private:
  struct State {
    enum Kind { OnEdge, AtVertex, InTri, Stalled } kind = OnEdge;
    uint32_t a = 0, b = 0;  // edge (a, b) or vertex a
    int64_t tri = -1, fromTri = -1;
    Vec3 x = Vec3::Zero();
    double g = 0;  // sign * field at x
  };

  bool hasTriangleWithDirectedEdge(uint32_t a, uint32_t b) const {
    for (uint32_t i = vstart_[a]; i < vstart_[a + 1]; ++i) {
      const uint32_t* tri = &m_.triangles[3 * vtris_[i]];
      for (int k = 0; k < 3; ++k)
        if (tri[k] == a && tri[(k + 1) % 3] == b) return true;
    }
    return false;
  }

  double fieldAt(const Vec3& x, uint32_t u, uint32_t w) const {
    const Vec3 e = P_[w] - P_[u];
    const double l2 = e.squaredNorm();
    const double t = l2 > 0 ? std::clamp((x - P_[u]).dot(e) / l2, 0.0, 1.0) : 0.0;
    return f_[u] + t * (f_[w] - f_[u]);
  }

  uint32_t third(int64_t t, uint32_t a, uint32_t b) const {
    const uint32_t* tri = &m_.triangles[3 * t];
    for (int k = 0; k < 3; ++k)
      if (tri[k] != a && tri[k] != b) return tri[k];
    return tri[0];
  }

  // On edge (a, b): enter the adjacent triangle whose (signed) gradient points into it, else
  // slide along the edge toward its higher end (a ridge for ascent, a valley for descent).
  bool stepEdge(State& s, int sign, double gTarget, Vec3& end) const {
    int64_t best = -1;
    double bestNorm = 0;
    const Vec3 e = P_[s.b] - P_[s.a];
    for (uint32_t i = vstart_[s.a]; i < vstart_[s.a + 1]; ++i) {
      const int64_t t = vtris_[i];
      if (t == s.fromTri) continue;
      const uint32_t* tri = &m_.triangles[3 * t];
      if (tri[0] != s.b && tri[1] != s.b && tri[2] != s.b) continue;
      const Vec3 g = sign * grad_[t];
      const double gn = g.norm();
      if (gn <= 0) continue;
      const Vec3 toO = P_[third(t, s.a, s.b)] - P_[s.a];
      const Vec3 inward = toO - e * (toO.dot(e) / std::max(e.squaredNorm(), 1e-300));
      if (g.dot(inward) > 1e-9 * gn * inward.norm() && gn > bestNorm) {
        bestNorm = gn;
        best = t;
      }
    }
    if (best >= 0) {
      s.kind = State::InTri;
      s.tri = best;
      return false;
    }
    const uint32_t hi = sign * f_[s.b] >= sign * f_[s.a] ? s.b : s.a;
    const double gHi = sign * f_[hi];
    if (gHi <= s.g) {
      s.kind = State::Stalled;
      return false;
    }
    if (gHi >= gTarget) {
      const double t = (gTarget - s.g) / (gHi - s.g);
      end = s.x + t * (P_[hi] - s.x);
      return true;
    }
    s.kind = State::AtVertex;
    s.a = hi;
    s.x = P_[hi];
    s.g = gHi;
    return false;
  }

  // At vertex v: the incident triangle whose gradient lies in its corner at v (steepest), else the
  // steepest ascending incident edge.
  bool stepVertex(State& s, int sign, double gTarget, Vec3& end) const {
    const uint32_t v = s.a;
    int64_t best = -1;
    double bestNorm = 0;
    for (uint32_t i = vstart_[v]; i < vstart_[v + 1]; ++i) {
      const int64_t t = vtris_[i];
      const Vec3 g = sign * grad_[t];
      const double gn = g.norm();
      if (gn <= bestNorm) continue;
      const uint32_t* tri = &m_.triangles[3 * t];
      uint32_t o[2];
      int k = 0;
      for (int j = 0; j < 3; ++j)
        if (tri[j] != v) o[k++] = tri[j];
      if (k != 2) continue;
      const Vec3 e1 = P_[o[0]] - P_[v], e2 = P_[o[1]] - P_[v];
      const double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2), det = a * c - b * b;
      if (!(det > 0)) continue;
      const double r1 = g.dot(e1), r2 = g.dot(e2);
      const double al = (c * r1 - b * r2) / det, be = (a * r2 - b * r1) / det;
      const double eps = 1e-9 * (std::abs(al) + std::abs(be));
      if (al >= -eps && be >= -eps && al + be > 0) {
        best = t;
        bestNorm = gn;
      }
    }
    if (best >= 0) {
      s.kind = State::InTri;
      s.tri = best;
      return false;
    }
    int64_t next = -1;
    double bestSlope = 0;
    for (uint32_t i = vstart_[v]; i < vstart_[v + 1]; ++i) {
      const uint32_t* tri = &m_.triangles[3 * vtris_[i]];
      for (int j = 0; j < 3; ++j) {
        const uint32_t w = tri[j];
        if (w == v) continue;
        const double len = (P_[w] - P_[v]).norm();
        if (len <= 0) continue;
        const double slope = (sign * f_[w] - s.g) / len;
        if (slope > bestSlope) {
          bestSlope = slope;
          next = w;
        }
      }
    }
    if (next < 0) {
      s.kind = State::Stalled;
      return false;
    }
    const double gN = sign * f_[next];
    if (gN >= gTarget) {
      end = s.x + (gTarget - s.g) / (gN - s.g) * (P_[next] - s.x);
      return true;
    }
    s.a = uint32_t(next);
    s.x = P_[next];
    s.g = gN;
    return false;
  }

  // Inside triangle t from s.x along the gradient: reach the target or exit through an edge or a
  // vertex.
  bool stepTri(State& s, int sign, double gTarget, Vec3& end) const {
    const int64_t t = s.tri;
    const uint32_t* tri = &m_.triangles[3 * t];
    const Vec3 g = sign * grad_[t];
    const double g2 = g.squaredNorm();
    if (!(g2 > 0)) {
      s.kind = State::Stalled;
      return false;
    }
    const Vec3 p0 = P_[tri[0]], e1 = P_[tri[1]] - p0, e2 = P_[tri[2]] - p0;
    const double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2), det = a * c - b * b;
    if (!(det > 0)) {
      s.kind = State::Stalled;
      return false;
    }
    auto coords = [&](const Vec3& y, double& u, double& w) {
      const Vec3 d = y - p0;
      const double r1 = d.dot(e1), r2 = d.dot(e2);
      u = (c * r1 - b * r2) / det;
      w = (a * r2 - b * r1) / det;
    };
    double u, w, gu, gw;
    coords(s.x, u, w);
    {
      const double r1 = g.dot(e1), r2 = g.dot(e2);
      gu = (c * r1 - b * r2) / det;
      gw = (a * r2 - b * r1) / det;
    }
    double bary[3] = {std::max(0.0, 1 - u - w), std::max(0.0, u), std::max(0.0, w)};
    const double rate[3] = {-(gu + gw), gu, gw};
    const double rateScale = std::abs(gu) + std::abs(gw) + 1e-300;
    double sExit = std::numeric_limits<double>::infinity();
    // Rates within 1e-9 of the scale count as 0, the tolerance stepVertex uses for its corner
    // test (otherwise a path leaving a vertex could exit at once and loop back).
    for (int k = 0; k < 3; ++k)
      if (rate[k] < -1e-9 * rateScale) sExit = std::min(sExit, bary[k] / -rate[k]);
    const double sTarget = (gTarget - s.g) / g2;
    if (sTarget <= sExit) {
      end = s.x + sTarget * g;
      return true;
    }
    if (!std::isfinite(sExit)) {
      s.kind = State::Stalled;
      return false;
    }
    double nb[3];
    int zeros = 0, zeroK = -1, keepK = -1;
    for (int k = 0; k < 3; ++k) {
      nb[k] = bary[k] + sExit * rate[k];
      if (nb[k] <= 1e-9) {
        ++zeros;
        zeroK = k;
      } else {
        keepK = k;
      }
    }
    s.x = s.x + sExit * g;
    s.g += sExit * g2;
    if (zeros >= 2) {
      int vk = keepK;
      if (vk < 0) vk = 0;
      for (int k = 0; k < 3; ++k)
        if (nb[k] > nb[vk]) vk = k;
      s.kind = State::AtVertex;
      s.a = tri[vk];
      s.x = P_[s.a];
      s.g = std::max(s.g, sign * f_[s.a]);
      return false;
    }
    s.kind = State::OnEdge;
    s.a = tri[(zeroK + 1) % 3];
    s.b = tri[(zeroK + 2) % 3];
    s.fromTri = t;
    return false;
  }

  const Mesh& m_;
  const std::vector<double>& f_;
  std::vector<Vec3> P_, grad_;
  std::vector<uint32_t> vstart_, vtris_;
  std::vector<std::array<uint32_t, 2>> edges_;
  double meanEdge_ = 1;
  size_t maxSteps_ = 1000;
};

// Farthest-point selection of up to count indices among points (spread along a boundary).
std::vector<size_t> spreadPick(const std::vector<Vec3>& pts, size_t count) {
  std::vector<size_t> out;
  if (pts.empty() || count == 0) return out;
  if (pts.size() <= count) {
    out.resize(pts.size());
    std::iota(out.begin(), out.end(), size_t(0));
    return out;
  }
  std::vector<double> d(pts.size(), std::numeric_limits<double>::infinity());
  size_t cur = 0;
  for (size_t k = 0; k < count; ++k) {
    out.push_back(cur);
    size_t far = cur;
    double farD = -1;
    for (size_t i = 0; i < pts.size(); ++i) {
      d[i] = std::min(d[i], (pts[i] - pts[cur]).squaredNorm());
      if (d[i] > farD) {
        farD = d[i];
        far = i;
      }
    }
    cur = far;
  }
  return out;
}


SkeletonTree skeletonFailure(Status s, std::string msg) {
  SkeletonTree r;
  r.status = s;
  r.message = std::move(msg);
  r.isTree = false;
  return r;
}

// InvalidOption for a field, options, boundary or layers buildSkeletonTree cannot use.
Outcome checkSkeletonInput(const std::vector<CurvedLayer>& layers, const Mesh& boundary,
                           const std::vector<double>& field, const SkeletonOptions& options) {
  auto fail = [](Status s, std::string msg) { return failed<Outcome>(s, std::move(msg)); };
  if (field.size() != boundary.vertexCount())
    return fail(Status::InvalidOption, "skeleton: field has " + std::to_string(field.size()) +
                                           " values for " + std::to_string(boundary.vertexCount()) +
                                           " boundary vertices");
  if (options.pathsPerNode < 1 || options.pathsPerNode > 100000)
    return fail(Status::InvalidOption, "skeleton: pathsPerNode must be in [1, 100000]");
  for (double v : field)
    if (!std::isfinite(v)) return fail(Status::InvalidOption, "skeleton: non-finite field value");
  if (boundary.triangles.size() % 3 || boundary.positions.size() % 3)
    return fail(Status::InvalidOption, "skeleton: boundary mesh arrays are not multiples of 3");
  for (uint32_t v : boundary.triangles)
    if (v >= boundary.vertexCount())
      return fail(Status::InvalidOption, "skeleton: boundary triangle index out of range");
  for (size_t i = 0; i < layers.size(); ++i) {
    if (!std::isfinite(layers[i].isoValue))
      return fail(Status::InvalidOption, "skeleton: non-finite layer iso-value");
    if (i && !(layers[i].isoValue > layers[i - 1].isoValue))
      return fail(Status::InvalidOption, "skeleton: layer iso-values must increase");
    for (const LayerRegion& r : layers[i].regions)
      if (!regionValid(r))
        return fail(Status::InvalidOption,
                    "skeleton: layer " + std::to_string(i) + " has a malformed region mesh");
  }
  return {};
}

// The nodes, sorted by (layer, region), with their areas and area-weighted centroids (the
// vertices' mean for a region of zero area); firstNode[i] = the first node of layer i, and
// firstNode[layers.size()] = the node count.
std::vector<SkeletonNode> skeletonNodes(const std::vector<CurvedLayer>& layers, std::vector<uint32_t>& firstNode) {
  std::vector<SkeletonNode> nodes;
  firstNode.assign(layers.size() + 1, 0);
  for (size_t i = 0; i < layers.size(); ++i) {
    firstNode[i] = uint32_t(nodes.size());
    for (size_t r = 0; r < layers[i].regions.size(); ++r) {
      SkeletonNode n;
      n.layer = uint32_t(i);
      n.region = uint32_t(r);
      n.isoValue = layers[i].isoValue;
      const Mesh& m = layers[i].regions[r].mesh;
      Vec3 acc = Vec3::Zero();
      for (size_t f = 0; f < m.faceCount(); ++f) {
        const Vec3 a = m.vertex(m.triangles[3 * f]), b = m.vertex(m.triangles[3 * f + 1]),
                   c = m.vertex(m.triangles[3 * f + 2]);
        const double ar = 0.5 * (b - a).cross(c - a).norm();
        n.area += ar;
        acc += ar * (a + b + c) / 3.0;
      }
      if (n.area > 0) {
        n.centroid = acc / n.area;
      } else if (m.vertexCount()) {
        for (size_t v = 0; v < m.vertexCount(); ++v) n.centroid += m.vertex(v);
        n.centroid /= double(m.vertexCount());
      }
      nodes.push_back(std::move(n));
    }
  }
  firstNode[layers.size()] = uint32_t(nodes.size());
  return nodes;
}

// Per layer: the open boundary segments of its nodes with their owners (node indices), and
// their hash grids, built on first use.
class LayerBoundaries {
 public:
  LayerBoundaries(const std::vector<CurvedLayer>& layers, const std::vector<uint32_t>& firstNode)
      : segs_(layers.size()), owner_(layers.size()), grids_(layers.size()) {
    for (size_t i = 0; i < layers.size(); ++i)
      for (size_t r = 0; r < layers[i].regions.size(); ++r) {
        const Mesh& m = layers[i].regions[r].mesh;
        for (const auto& e : openEdges(m)) {
          segs_[i].push_back({m.vertex(e[0]), m.vertex(e[1])});
          owner_[i].push_back(uint32_t(firstNode[i] + r));
          total_ += (m.vertex(e[0]) - m.vertex(e[1])).norm();
          ++count_;
        }
      }
  }

  // The segments' mean length (fallback when there is none).
  double meanLength(double fallback) const { return count_ ? total_ / count_ : fallback; }

  // Layer i's grid. Cells at least an eighth of the layer's longest segment, so a long segment
  // spans a bounded number of cells, and at least minCell.
  const SegmentGrid& grid(size_t i, double minCell) {
    if (grids_[i].empty() && !segs_[i].empty()) {
      double longest = 0;
      for (const auto& sg : segs_[i]) longest = std::max(longest, (sg[1] - sg[0]).norm());
      grids_[i].build(segs_[i], owner_[i], std::max(minCell, longest / 8));
    }
    return grids_[i];
  }

 private:
  std::vector<std::vector<std::array<Vec3, 2>>> segs_;
  std::vector<std::vector<uint32_t>> owner_;
  std::vector<SegmentGrid> grids_;
  double total_ = 0;
  size_t count_ = 0;
};

// Boundary-surface edges crossing each layer's iso-value: phi_u < phi_i <= phi_w.
std::vector<std::vector<uint32_t>> crossingEdges(const std::vector<std::array<uint32_t, 2>>& edges,
                                                 const std::vector<double>& field, const std::vector<double>& iso) {
  std::vector<std::vector<uint32_t>> crossing(iso.size());
  for (uint32_t e = 0; e < edges.size(); ++e) {
    const double fa = field[edges[e][0]], fb = field[edges[e][1]];
    const double lo = std::min(fa, fb), hi = std::max(fa, fb);
    if (lo == hi) continue;
    auto it = std::upper_bound(iso.begin(), iso.end(), lo);
    for (; it != iso.end() && *it <= hi; ++it) crossing[it - iso.begin()].push_back(e);
  }
  return crossing;
}

// A path's starting point: x on the boundary-surface edge from lowV to highV (field increasing).
struct Start {
  uint32_t lowV, highV;
  Vec3 x;
};

// Starting points of each node: the crossings of its layer's iso-value assigned to it (its IGDS
// boundary passes within tol), spread by farthest-point picks.
std::vector<std::vector<Start>> pathStarts(const std::vector<CurvedLayer>& layers,
                                           const std::vector<uint32_t>& firstNode, const SteepestTracer& tracer,
                                           const std::vector<double>& field, const std::vector<double>& iso,
                                           const std::vector<std::vector<uint32_t>>& crossing,
                                           LayerBoundaries& bounds, double tol, int pathsPerNode) {
  const auto& edges = tracer.edges();
  auto crossPoint = [&](uint32_t e, double v, uint32_t& lowV, uint32_t& highV) {
    uint32_t a = edges[e][0], b = edges[e][1];
    if (field[a] > field[b]) std::swap(a, b);
    lowV = a;
    highV = b;
    const double t = (v - field[a]) / (field[b] - field[a]);
    return Vec3(tracer.point(a) + t * (tracer.point(b) - tracer.point(a)));
  };
  std::vector<std::vector<Start>> starts(firstNode.back());
  for (size_t i = 0; i < layers.size(); ++i) {
    if (layers[i].regions.empty()) continue;
    const SegmentGrid& grid = bounds.grid(i, 2 * tol);
    if (grid.empty()) continue;
    std::vector<std::vector<Start>> all(layers[i].regions.size());
    for (uint32_t e : crossing[i]) {
      Start s;
      s.x = crossPoint(e, iso[i], s.lowV, s.highV);
      const int64_t who = grid.nearest(s.x, tol);
      if (who >= 0) all[who - firstNode[i]].push_back(s);
    }
    for (size_t r = 0; r < all.size(); ++r) {
      std::vector<Vec3> pts;
      for (const Start& s : all[r]) pts.push_back(s.x);
      for (size_t k : spreadPick(pts, size_t(pathsPerNode)))
        starts[firstNode[i] + r].push_back(all[r][k]);
    }
  }
  return starts;
}

// lower[n] and upper[n] of every node, as links are found (duplicates allowed until sorted).
struct Links {
  std::vector<std::vector<uint32_t>> lower, upper;
  explicit Links(size_t n) : lower(n), upper(n) {}
  void link(uint32_t lo, uint32_t hi) {
    lower[hi].push_back(lo);
    upper[lo].push_back(hi);
  }
};

// Sorts each list and drops repeats.
void sortUnique(std::vector<uint32_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// Links of consecutive layers by steepest paths (Fig. 12): ascending from layer i's starts to
// phi_{i+1}, descending from layer i + 1's to phi_i; a path's end names the node whose boundary
// passes within tol.
void linkBySteepestPaths(const std::vector<CurvedLayer>& layers, const std::vector<uint32_t>& firstNode,
                         const SteepestTracer& tracer, const std::vector<double>& iso,
                         const std::vector<std::vector<Start>>& starts, LayerBoundaries& bounds, double tol,
                         Links& links) {
  for (size_t i = 0; i + 1 < layers.size(); ++i) {
    if (layers[i].regions.empty() || layers[i + 1].regions.empty()) continue;
    const SegmentGrid& gLo = bounds.grid(i, 2 * tol);
    const SegmentGrid& gHi = bounds.grid(i + 1, 2 * tol);
    // Ascending paths from layer i to phi_{i+1}.
    for (uint32_t a = firstNode[i]; a < firstNode[i + 1]; ++a)
      for (const Start& s : starts[a]) {
        Vec3 end;
        if (gHi.empty() || !tracer.trace(s.lowV, s.highV, s.x, +1, iso[i + 1], end)) continue;
        const int64_t b = gHi.nearest(end, tol);
        if (b >= 0) links.link(a, uint32_t(b));
      }
    // Descending paths from layer i + 1 to phi_i.
    for (uint32_t b = firstNode[i + 1]; b < firstNode[i + 2]; ++b)
      for (const Start& s : starts[b]) {
        Vec3 end;
        if (gLo.empty() || !tracer.trace(s.lowV, s.highV, s.x, -1, iso[i], end)) continue;
        const int64_t a = gLo.nearest(end, tol);
        if (a >= 0) links.link(uint32_t(a), b);
      }
  }
}

// Fallback: a node above a non-empty layer left without a lower-node is linked to the previous
// layer's node nearest to its boundary (all its vertices when it has no open boundary). Returns
// the number of such links.
size_t linkFallbacks(const std::vector<CurvedLayer>& layers, const std::vector<uint32_t>& firstNode,
                     LayerBoundaries& bounds, double tol, Links& links) {
  size_t made = 0;
  for (size_t i = 1; i < layers.size(); ++i) {
    if (layers[i - 1].regions.empty()) continue;
    const SegmentGrid& gLo = bounds.grid(i - 1, 2 * tol);
    for (uint32_t b = firstNode[i]; b < firstNode[i + 1]; ++b) {
      if (!links.lower[b].empty()) continue;
      const LayerRegion& reg = layers[i].regions[b - firstNode[i]];
      std::vector<Vec3> probe;
      for (const auto& e : openEdges(reg.mesh)) probe.push_back(reg.mesh.vertex(e[0]));
      if (probe.empty())
        for (size_t v = 0; v < reg.mesh.vertexCount(); ++v) probe.push_back(reg.mesh.vertex(v));
      // At most 32 probes (spread), each a brute-force search: fallbacks are rare.
      if (probe.size() > 32) {
        std::vector<Vec3> few;
        for (size_t k : spreadPick(probe, 32)) few.push_back(probe[k]);
        probe.swap(few);
      }
      double best = std::numeric_limits<double>::infinity();
      int64_t who = -1;
      for (const Vec3& p : probe) {
        double d = 0;
        int64_t w = -1;
        if (!gLo.empty()) {
          w = gLo.nearestAnywhere(p, &d);
        } else {
          // Previous layer without open boundary: nearest by vertices.
          for (uint32_t a = firstNode[i - 1]; a < firstNode[i]; ++a) {
            const Mesh& m = layers[i - 1].regions[a - firstNode[i - 1]].mesh;
            for (size_t v = 0; v < m.vertexCount(); ++v) {
              const double dd = (m.vertex(v) - p).norm();
              if (w < 0 || dd < d) {
                d = dd;
                w = a;
              }
            }
          }
        }
        if (w >= 0 && d < best) {
          best = d;
          who = w;
        }
      }
      if (who >= 0) {
        links.link(uint32_t(who), b);
        ++made;
      }
    }
  }
  return made;
}

}  // namespace

SkeletonTree buildSkeletonTree(const std::vector<CurvedLayer>& layers, const Mesh& boundary,
                               const std::vector<double>& field, const SkeletonOptions& options) {
  const auto t0 = Clock::now();
  const Outcome input = checkSkeletonInput(layers, boundary, field, options);
  if (!input.ok()) return skeletonFailure(input.status, input.message);
  SkeletonTree out;
  std::vector<uint32_t> firstNode;
  out.nodes = skeletonNodes(layers, firstNode);
  if (out.nodes.empty()) return skeletonFailure(Status::EmptyInput, "skeleton: no IGDS in the layers");
  if (boundary.triangles.empty()) return skeletonFailure(Status::EmptyInput, "skeleton: empty boundary surface");

  SteepestTracer tracer(boundary, field);
  LayerBoundaries bounds(layers, firstNode);
  // A crossing of phi_i on the boundary surface belongs to the node whose IGDS boundary passes
  // within tol (the IGDS boundary lies on that iso-curve, up to remeshing chords).
  const double meanSeg = bounds.meanLength(tracer.meanEdge());
  const double tol = 0.75 * std::max(tracer.meanEdge(), meanSeg);
  std::vector<double> iso(layers.size());
  for (size_t i = 0; i < layers.size(); ++i) iso[i] = layers[i].isoValue;
  const std::vector<std::vector<uint32_t>> crossing = crossingEdges(tracer.edges(), field, iso);
  const std::vector<std::vector<Start>> starts =
      pathStarts(layers, firstNode, tracer, field, iso, crossing, bounds, tol, options.pathsPerNode);

  Links links(out.nodes.size());
  linkBySteepestPaths(layers, firstNode, tracer, iso, starts, bounds, tol, links);
  for (auto& v : links.lower) sortUnique(v);
  out.fallbackLinks = linkFallbacks(layers, firstNode, bounds, tol, links);
  for (size_t n = 0; n < out.nodes.size(); ++n) {
    auto& lo = links.lower[n];
    sortUnique(lo);
    auto& up = links.upper[n];
    sortUnique(up);
    out.nodes[n].lower = lo;
    out.nodes[n].upper = up;
    out.edges += lo.size();
    if (lo.size() > 1) out.isTree = false;
  }
  out.ms = msSince(t0);
  return out;
}

}  // namespace omnislice
