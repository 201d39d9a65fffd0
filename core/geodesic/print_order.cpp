// SPDX-License-Identifier: MIT
// Print order of the IGDS (paper 002 Section 3.1): skeleton tree by steepest paths on the part's
// boundary surface (Algorithm 1, Fig. 12), potential collision surfaces of the nozzle's bounding
// cone swept over each IGDS (Algorithm 2, Fig. 15) and the LPT / DPT / A3 traversals.
#include "common/det_math.h"
#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "geodesic/print_order.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace omnislice {
namespace {

using Vec3 = Eigen::Vector3d;


Vec3 unitNormal(const Vec3& a, const Vec3& b, const Vec3& c, double* area = nullptr) {
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  if (area) *area = 0.5 * len;
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

// Closest point of p to segment [a, b].
Vec3 closestOnSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  if (l2 <= 0) return a;
  const double t = std::clamp((p - a).dot(ab) / l2, 0.0, 1.0);
  return a + t * ab;
}

uint64_t edgeKey(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(a) << 32) | b;
}

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

bool regionValid(const LayerRegion& r) {
  const size_t n = r.mesh.vertexCount();
  if (r.mesh.positions.size() % 3 || r.mesh.triangles.size() % 3) return false;
  for (uint32_t v : r.mesh.triangles)
    if (v >= n) return false;
  for (double x : r.mesh.positions)
    if (!std::isfinite(x)) return false;
  return true;
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

}  // namespace

// ================================================================================================
SkeletonTree buildSkeletonTree(const std::vector<CurvedLayer>& layers, const Mesh& boundary,
                               const std::vector<double>& field, const SkeletonOptions& options) {
  const auto t0 = Clock::now();
  SkeletonTree out;
  auto fail = [&](Status s, std::string msg) {
    SkeletonTree r;
    r.status = s;
    r.message = std::move(msg);
    r.isTree = false;
    return r;
  };
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

  // Nodes, sorted by (layer, region).
  std::vector<uint32_t> firstNode(layers.size() + 1, 0);
  for (size_t i = 0; i < layers.size(); ++i) {
    firstNode[i] = uint32_t(out.nodes.size());
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
      out.nodes.push_back(std::move(n));
    }
  }
  firstNode[layers.size()] = uint32_t(out.nodes.size());
  if (out.nodes.empty()) return fail(Status::EmptyInput, "skeleton: no IGDS in the layers");
  if (boundary.triangles.empty()) return fail(Status::EmptyInput, "skeleton: empty boundary surface");

  SteepestTracer tracer(boundary, field);

  // Per layer: open boundary segments of its nodes, mean segment length.
  std::vector<std::vector<std::array<Vec3, 2>>> segs(layers.size());
  std::vector<std::vector<uint32_t>> segOwner(layers.size());
  double segTotal = 0;
  size_t segCount = 0;
  for (size_t i = 0; i < layers.size(); ++i)
    for (size_t r = 0; r < layers[i].regions.size(); ++r) {
      const Mesh& m = layers[i].regions[r].mesh;
      for (const auto& e : openEdges(m)) {
        segs[i].push_back({m.vertex(e[0]), m.vertex(e[1])});
        segOwner[i].push_back(uint32_t(firstNode[i] + r));
        segTotal += (m.vertex(e[0]) - m.vertex(e[1])).norm();
        ++segCount;
      }
    }
  // A crossing of phi_i on the boundary surface belongs to the node whose IGDS boundary passes
  // within tol (the IGDS boundary lies on that iso-curve, up to remeshing chords).
  const double meanSeg = segCount ? segTotal / segCount : tracer.meanEdge();
  const double tol = 0.75 * std::max(tracer.meanEdge(), meanSeg);

  // Boundary-surface edges crossing each layer's iso-value: phi_u < phi_i <= phi_w.
  std::vector<double> iso(layers.size());
  for (size_t i = 0; i < layers.size(); ++i) iso[i] = layers[i].isoValue;
  std::vector<std::vector<uint32_t>> crossing(layers.size());
  const auto& edges = tracer.edges();
  for (uint32_t e = 0; e < edges.size(); ++e) {
    const double fa = field[edges[e][0]], fb = field[edges[e][1]];
    const double lo = std::min(fa, fb), hi = std::max(fa, fb);
    if (lo == hi) continue;
    auto it = std::upper_bound(iso.begin(), iso.end(), lo);
    for (; it != iso.end() && *it <= hi; ++it) crossing[it - iso.begin()].push_back(e);
  }

  std::vector<SegmentGrid> grids(layers.size());
  // Cells at least an eighth of the layer's longest segment, so a long segment spans a bounded
  // number of cells.
  auto gridOf = [&](size_t i) -> const SegmentGrid& {
    if (grids[i].empty() && !segs[i].empty()) {
      double longest = 0;
      for (const auto& sg : segs[i]) longest = std::max(longest, (sg[1] - sg[0]).norm());
      grids[i].build(segs[i], segOwner[i], std::max(2 * tol, longest / 8));
    }
    return grids[i];
  };
  auto crossPoint = [&](uint32_t e, double v, uint32_t& lowV, uint32_t& highV) {
    uint32_t a = edges[e][0], b = edges[e][1];
    if (field[a] > field[b]) std::swap(a, b);
    lowV = a;
    highV = b;
    const double t = (v - field[a]) / (field[b] - field[a]);
    return Vec3(tracer.point(a) + t * (tracer.point(b) - tracer.point(a)));
  };

  // Starting points of each node: crossings assigned to it, spread by farthest-point picks.
  struct Start {
    uint32_t lowV, highV;
    Vec3 x;
  };
  std::vector<std::vector<Start>> starts(out.nodes.size());
  for (size_t i = 0; i < layers.size(); ++i) {
    if (layers[i].regions.empty()) continue;
    const SegmentGrid& grid = gridOf(i);
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
      for (size_t k : spreadPick(pts, size_t(options.pathsPerNode)))
        starts[firstNode[i] + r].push_back(all[r][k]);
    }
  }

  std::vector<std::vector<uint32_t>> lower(out.nodes.size()), upper(out.nodes.size());
  auto link = [&](uint32_t lo, uint32_t hi) {
    lower[hi].push_back(lo);
    upper[lo].push_back(hi);
  };
  for (size_t i = 0; i + 1 < layers.size(); ++i) {
    if (layers[i].regions.empty() || layers[i + 1].regions.empty()) continue;
    const SegmentGrid& gLo = gridOf(i);
    const SegmentGrid& gHi = gridOf(i + 1);
    // Ascending paths from layer i to phi_{i+1}.
    for (uint32_t a = firstNode[i]; a < firstNode[i + 1]; ++a)
      for (const Start& s : starts[a]) {
        Vec3 end;
        if (gHi.empty() || !tracer.trace(s.lowV, s.highV, s.x, +1, iso[i + 1], end)) continue;
        const int64_t b = gHi.nearest(end, tol);
        if (b >= 0) link(a, uint32_t(b));
      }
    // Descending paths from layer i + 1 to phi_i.
    for (uint32_t b = firstNode[i + 1]; b < firstNode[i + 2]; ++b)
      for (const Start& s : starts[b]) {
        Vec3 end;
        if (gLo.empty() || !tracer.trace(s.lowV, s.highV, s.x, -1, iso[i], end)) continue;
        const int64_t a = gLo.nearest(end, tol);
        if (a >= 0) link(uint32_t(a), b);
      }
  }
  for (auto& v : lower) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  // Fallback: a node above a non-empty layer left without a lower-node is linked to the previous
  // layer's node nearest to its boundary (all its vertices when it has no open boundary).
  for (size_t i = 1; i < layers.size(); ++i) {
    if (layers[i - 1].regions.empty()) continue;
    const SegmentGrid& gLo = gridOf(i - 1);
    for (uint32_t b = firstNode[i]; b < firstNode[i + 1]; ++b) {
      if (!lower[b].empty()) continue;
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
        link(uint32_t(who), b);
        ++out.fallbackLinks;
      }
    }
  }
  for (size_t n = 0; n < out.nodes.size(); ++n) {
    auto& lo = lower[n];
    std::sort(lo.begin(), lo.end());
    lo.erase(std::unique(lo.begin(), lo.end()), lo.end());
    auto& up = upper[n];
    std::sort(up.begin(), up.end());
    up.erase(std::unique(up.begin(), up.end()), up.end());
    out.nodes[n].lower = lo;
    out.nodes[n].upper = up;
    out.edges += lo.size();
    if (lo.size() > 1) out.isTree = false;
  }
  out.ms = msSince(t0);
  return out;
}

// ================================================================================================
// Collision model.
//
// The rule implemented (print_order.h; paper Fig. 15): the envelope of node i is the volume the
// nozzle cone sweeps over its IGDS S_i, closed as in the paper: the ring-like ruled surface of the
// cones along S_i's boundary on the sides, S_i itself below, and the top at axial length L. It is
// the union of two parts, each tested exactly on the triangle mesh:
//   interior (the IGDS's normal offset up to L; closes the ring where the paper fills holes):
//     face T (unit normal n):   q - h n projects into T with h = (q - T) . n in (c, L];
//     interior edge (faces n1, n2): the perpendicular foot p of q falls inside the edge, q - p lies
//                                in the planar sector between n1 and n2, |q - p| in (c, L];
//     interior vertex v:         |q - v| in (c, L] and angle(q - v, n_v) <= beta_v, n_v the
//                                area-weighted vertex normal, beta_v its largest angle to the
//                                incident face normals (fills the normal fan at a vertex);
//   ring (the cones of half-angle alpha along the open boundary, the ruled surface S(u, v)):
//     boundary edge (a, b):      the cone swept along the segment with axis n = the sum of the
//                                endpoints' vertex normals made orthogonal to the edge (a lip or
//                                sliver face at the boundary does not turn the ring), i.e.
//                                h = (q - a) . n in (c, L] and the in-plane distance from q - h n
//                                to [a, b] < h tan(alpha);
//     boundary vertex v:         h = (q - v) . n_v in (c, L], |q - v - h n_v| < h tan(alpha).
// c is the clearance, L the cone length. On a flat IGDS this is exactly the union of the cones
// placed at all its points; on a curved one the cones of interior points are replaced by the
// normal offset, as the paper's closed ring does (a wide cone at an interior point of a bowl would
// otherwise sweep over the bowl's own lower layers). Node j is a PCS of node i when one of j's test
// points (its vertices, points every sampleSpacing along its open boundary edges and, on
// triangles longer than 2 sampleSpacing, a barycentric grid at that spacing) is inside.
//
// Speed: per node, a bounding-volume hierarchy over the interior primitives (faces owning their
// crease edges and interior vertices) and one over the ring primitives (boundary edges owning
// their vertices), each node carrying a bounding sphere, a normal cone (axis a, spread beta: every
// inside direction from an apex is within gamma = alpha_eff + beta of a, alpha_eff = 0 for the
// interior, alpha for the ring) and its lowest point along a; and a hierarchy over the test points
// with spheres and extents along and across their mean normal. A pair of hierarchy nodes is culled
// when (1) D = |c_j - c_i| > r_i + r_j + reach (reach L for the interior, L / cos(alpha) for the
// ring), (2) gamma < 90 deg and every test point's projection on a is <= the lowest apex's plus
// c cos(gamma) (slab: inside points lie above every apex's plane along a), or (3) D > r_i + r_j and
// angle(c_j - c_i, a) >= gamma + asin(r_i / (D - r_j)) + asin(r_j / D). The traversal of a pair stops
// at the first point inside; k^2 root tests, the dual traversal only where the bounds meet.
namespace {

struct ConeParams {
  double tanA = 0, alpha = 0, length = 0, clearance = 0;
};

struct Sphere {
  Vec3 c = Vec3::Zero();
  double r = 0;
};

struct BvhNode {
  Sphere s;
  // Primitive hierarchies: normal cone (axis, half-angle spread) and lowest point along the axis.
  // Point hierarchy: a mean normal `axis` and the points' extents around the sphere centre along
  // it (hMin, hMax) and across it (rho), bounding the projection on any direction.
  Vec3 axis = Vec3::UnitZ();
  double spread = kPi;
  double lowAlongAxis = 0;
  double cosGamma = -1, sinGamma = 0;  // gamma = alphaEff + spread (primitive hierarchies)
  double hMin = 0, hMax = 0, rho = 0;
  uint32_t begin = 0, end = 0;
  int32_t left = -1, right = -1;
};

struct Crease {
  Vec3 a, b, n1, n2;
};
struct FanVertex {
  Vec3 v, n;
  double cosBeta, sinBeta;
};
struct RingEdge {
  Vec3 a, b, n;
};
struct RingVertex {
  Vec3 v, n;
};

struct NodeShape {
  // Interior primitives, grouped by owning face.
  std::vector<std::array<Vec3, 3>> tri;
  std::vector<Vec3> faceN;
  std::vector<std::vector<Crease>> creases;
  std::vector<std::vector<FanVertex>> fans;
  std::vector<uint32_t> faceOrder;
  std::vector<BvhNode> faceBvh;
  // Ring primitives, grouped by boundary edge.
  std::vector<RingEdge> ring;
  std::vector<std::vector<RingVertex>> ringVerts;
  std::vector<uint32_t> ringOrder;
  std::vector<BvhNode> ringBvh;
  // Test points and their normals (vertex normals, the owning face's normal for samples).
  std::vector<Vec3> pts, ptN;
  std::vector<BvhNode> ptBvh;
  size_t folded = 0;
};

double angleBetween(const Vec3& a, const Vec3& b) {
  const double na = a.norm(), nb = b.norm();
  if (!(na > 0) || !(nb > 0)) return 0;
  return det::atan2(a.cross(b).norm(), a.dot(b));
}

bool inPrism(const Vec3& q, const std::array<Vec3, 3>& t, const Vec3& n, const ConeParams& k) {
  const double h = (q - t[0]).dot(n);
  if (!(h > k.clearance) || h > k.length) return false;
  const Vec3 proj = q - h * n;
  // Inside the triangle: the three edge functions agree with the normal.
  for (int e = 0; e < 3; ++e)
    if ((t[(e + 1) % 3] - t[e]).cross(proj - t[e]).dot(n) < 0) return false;
  return true;
}

bool inCrease(const Vec3& q, const Crease& e, const ConeParams& k) {
  const Vec3 ab = e.b - e.a;
  const double l2 = ab.squaredNorm();
  if (!(l2 > 0)) return false;
  const double t = (q - e.a).dot(ab) / l2;
  if (t < 0 || t > 1) return false;
  const Vec3 d = q - (e.a + t * ab);
  const double len = d.norm();
  if (!(len > k.clearance) || len > k.length) return false;
  const Vec3 w = e.n1.cross(e.n2);
  return e.n1.cross(d).dot(w) >= 0 && d.cross(e.n2).dot(w) >= 0 && d.dot(e.n1 + e.n2) > 0;
}

bool inFan(const Vec3& q, const FanVertex& f, const ConeParams& k) {
  const Vec3 d = q - f.v;
  const double len = d.norm();
  if (!(len > k.clearance) || len > k.length) return false;
  return d.dot(f.n) >= f.cosBeta * len;
}

bool inRingEdge(const Vec3& q, const RingEdge& e, const ConeParams& k) {
  const double h = (q - e.a).dot(e.n);
  if (!(h > k.clearance) || h > k.length) return false;
  const Vec3 proj = q - h * e.n;
  const double r = h * k.tanA;
  return (closestOnSegment(proj, e.a, e.b) - proj).squaredNorm() < r * r;
}

bool inRingVertex(const Vec3& q, const RingVertex& v, const ConeParams& k) {
  const Vec3 d = q - v.v;
  const double h = d.dot(v.n);
  if (!(h > k.clearance) || h > k.length) return false;
  const double r = h * k.tanA;
  return (d - h * v.n).squaredNorm() < r * r;
}

bool insideFace(const Vec3& q, const NodeShape& s, uint32_t f, const ConeParams& k) {
  if (s.faceN[f].squaredNorm() > 0 && inPrism(q, s.tri[f], s.faceN[f], k)) return true;
  for (const auto& e : s.creases[f])
    if (inCrease(q, e, k)) return true;
  for (const auto& v : s.fans[f])
    if (inFan(q, v, k)) return true;
  return false;
}

bool insideRing(const Vec3& q, const NodeShape& s, uint32_t e, const ConeParams& k) {
  if (inRingEdge(q, s.ring[e], k)) return true;
  for (const auto& v : s.ringVerts[e])
    if (inRingVertex(q, v, k)) return true;
  return false;
}

// Median-split hierarchy over items (centres given); boundsOf fills a node from the item range
// [begin, end) of order.
template <class Bounds>
void buildBvh(const std::vector<Vec3>& centres, std::vector<uint32_t>& order,
              std::vector<BvhNode>& nodes, uint32_t leafSize, const Bounds& boundsOf) {
  order.resize(centres.size());
  std::iota(order.begin(), order.end(), 0u);
  nodes.clear();
  if (centres.empty()) return;
  struct Job {
    uint32_t node, begin, end;
  };
  std::vector<Job> stack;
  nodes.push_back({});
  stack.push_back({0, 0, uint32_t(centres.size())});
  while (!stack.empty()) {
    const Job j = stack.back();
    stack.pop_back();
    BvhNode nd;
    nd.begin = j.begin;
    nd.end = j.end;
    boundsOf(j.begin, j.end, nd);
    if (j.end - j.begin > leafSize) {
      Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (uint32_t i = j.begin; i < j.end; ++i) {
        lo = lo.cwiseMin(centres[order[i]]);
        hi = hi.cwiseMax(centres[order[i]]);
      }
      int axis = 0;
      const Vec3 ext = hi - lo;
      if (ext.y() > ext[axis]) axis = 1;
      if (ext.z() > ext[axis]) axis = 2;
      const uint32_t mid = j.begin + (j.end - j.begin) / 2;
      std::nth_element(order.begin() + j.begin, order.begin() + mid, order.begin() + j.end,
                       [&](uint32_t a, uint32_t b) { return centres[a][axis] < centres[b][axis]; });
      nd.left = int32_t(nodes.size());
      nd.right = int32_t(nodes.size() + 1);
      nodes.push_back({});
      nodes.push_back({});
      stack.push_back({uint32_t(nd.left), j.begin, mid});
      stack.push_back({uint32_t(nd.right), mid, j.end});
    }
    nodes[j.node] = nd;
  }
}

// Bounds of a primitive node: sphere over its points, normal cone over its directions (each given
// as a normal and an extra half-angle), lowest point along the axis.
template <class ForPoints, class ForNormals>
void primitiveBounds(uint32_t b, uint32_t e, BvhNode& nd, const ForPoints& forPoints,
                     const ForNormals& forNormals) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (uint32_t i = b; i < e; ++i)
    forPoints(i, [&](const Vec3& p) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    });
  nd.s.c = 0.5 * (lo + hi);
  double r2 = 0;
  for (uint32_t i = b; i < e; ++i)
    forPoints(i, [&](const Vec3& p) { r2 = std::max(r2, (p - nd.s.c).squaredNorm()); });
  nd.s.r = std::sqrt(r2) * (1 + 1e-12) + 1e-12;
  Vec3 axis = Vec3::Zero();
  for (uint32_t i = b; i < e; ++i) forNormals(i, [&](const Vec3& n, double, double) { axis += n; });
  const double al = axis.norm();
  nd.spread = kPi;
  nd.axis = Vec3::UnitZ();
  nd.lowAlongAxis = -std::numeric_limits<double>::infinity();
  if (al < 1e-9) return;
  nd.axis = axis / al;
  // Largest angle to the axis plus each normal's own half-angle (extra, as its cosine and sine):
  // the smallest cosine of the sum by the addition formula, one acos per node; a sum reaching pi
  // makes the cone the whole sphere. Normals are unit; the margin covers roundoff.
  double minCos = 1;
  bool whole = false;
  for (uint32_t i = b; i < e; ++i)
    forNormals(i, [&](const Vec3& n, double cosExtra, double sinExtra) {
      const double c = std::clamp(n.dot(nd.axis), -1.0, 1.0);
      if (c <= -cosExtra) whole = true;  // angle >= pi - extra
      const double sn = std::sqrt(std::max(0.0, 1 - c * c));
      minCos = std::min(minCos, c * cosExtra - sn * sinExtra);
    });
  nd.spread = whole ? kPi : det::acos(std::clamp(minCos, -1.0, 1.0)) + 1e-7;
  nd.lowAlongAxis = std::numeric_limits<double>::infinity();
  for (uint32_t i = b; i < e; ++i)
    forPoints(i, [&](const Vec3& p) { nd.lowAlongAxis = std::min(nd.lowAlongAxis, p.dot(nd.axis)); });
  nd.lowAlongAxis -= 1e-12 * (1 + std::abs(nd.lowAlongAxis));
}

// gamma = alphaEff + spread, kept as its cosine and sine for the trig-free bound of mayMeet.
void setGamma(BvhNode& nd, double alphaEff) {
  const double g = alphaEff + nd.spread;
  if (g >= kPi) {
    nd.cosGamma = -1;
    nd.sinGamma = 0;
  } else {
    nd.cosGamma = det::cos(g);
    nd.sinGamma = det::sin(g);
  }
}

NodeShape makeShape(const LayerRegion& reg, double spacing, double alpha) {
  NodeShape s;
  const Mesh& m = reg.mesh;
  const size_t nv = m.vertexCount(), nf = m.faceCount();
  std::vector<Vec3> P(nv);
  for (size_t v = 0; v < nv; ++v) P[v] = m.vertex(v);
  s.tri.resize(nf);
  s.faceN.resize(nf);
  s.creases.resize(nf);
  s.fans.resize(nf);
  std::vector<Vec3> vn(nv, Vec3::Zero());
  std::vector<int64_t> vOwner(nv, -1);
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &m.triangles[3 * f];
    s.tri[f] = {P[t[0]], P[t[1]], P[t[2]]};
    double area = 0;
    s.faceN[f] = unitNormal(P[t[0]], P[t[1]], P[t[2]], &area);
    for (int k = 0; k < 3; ++k) {
      vn[t[k]] += area * s.faceN[f];
      if (vOwner[t[k]] < 0) vOwner[t[k]] = int64_t(f);
    }
  }
  for (size_t v = 0; v < nv; ++v) {
    const double l = vn[v].norm();
    if (l > 0) vn[v] /= l;
  }
  // A folded face (its normal opposes the sum of its corners' vertex normals: a flipped triangle
  // left by remeshing) gives no nozzle direction: its normal is zeroed, so it has no prism, no
  // crease, no ring cone and no part in the fans' spread.
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &m.triangles[3 * f];
    if (s.faceN[f].dot(vn[t[0]] + vn[t[1]] + vn[t[2]]) < 0) {
      s.faceN[f] = Vec3::Zero();
      ++s.folded;
    }
  }
  // Edges with their faces: (key, face) pairs sorted by key (no per-edge allocation).
  std::vector<std::pair<uint64_t, uint32_t>> edgeFace;
  edgeFace.reserve(3 * nf);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      edgeFace.push_back(
          {edgeKey(m.triangles[3 * f + k], m.triangles[3 * f + (k + 1) % 3]), uint32_t(f)});
  std::sort(edgeFace.begin(), edgeFace.end());
  std::vector<uint8_t> onRing(nv, 0);
  std::vector<std::pair<uint64_t, uint32_t>> ringEdges;  // (edge key, face), sorted by key
  std::vector<uint32_t> faces;
  for (size_t g = 0; g < edgeFace.size();) {
    const uint64_t key = edgeFace[g].first;
    faces.clear();
    for (; g < edgeFace.size() && edgeFace[g].first == key; ++g) faces.push_back(edgeFace[g].second);
    const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
    if (faces.size() == 1) {
      onRing[a] = onRing[b] = 1;
      ringEdges.push_back({key, faces[0]});
      continue;
    }
    if (faces.size() != 2) continue;
    const Vec3 n1 = s.faceN[faces[0]], n2 = s.faceN[faces[1]];
    if (n1.squaredNorm() == 0 || n2.squaredNorm() == 0 || n1.dot(n2) > 1 - 1e-12) continue;
    s.creases[std::min(faces[0], faces[1])].push_back({P[a], P[b], n1, n2});
  }
  // Interior vertices: the fan of normals between the incident faces' normals.
  std::vector<double> beta(nv, 0);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.triangles[3 * f + k];
      if (s.faceN[f].squaredNorm() > 0) beta[v] = std::max(beta[v], angleBetween(vn[v], s.faceN[f]));
    }
  for (size_t v = 0; v < nv; ++v)
    if (!onRing[v] && vOwner[v] >= 0 && vn[v].squaredNorm() > 0 && beta[v] > 1e-9)
      s.fans[vOwner[v]].push_back({P[v], vn[v], det::cos(beta[v]), det::sin(beta[v])});
  // Ring: boundary edges with their face normal; each boundary vertex owned by its first edge.
  std::vector<uint8_t> ringOwned(nv, 0);
  for (const auto& [key, f] : ringEdges) {
    const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
    // Axis: the endpoints' vertex normals (area-weighted over their fans, so a lip or sliver
    // face at the boundary does not turn the ring), made orthogonal to the edge so the cone
    // swept along it is exact.
    Vec3 n = vn[a] + vn[b];
    const Vec3 e = P[b] - P[a];
    if (e.squaredNorm() > 0) n -= e * (n.dot(e) / e.squaredNorm());
    const double nl = n.norm();
    s.ring.push_back({P[a], P[b], nl > 1e-12 ? Vec3(n / nl) : Vec3::Zero()});
    s.ringVerts.emplace_back();
    for (uint32_t v : {a, b})
      if (!ringOwned[v] && vn[v].squaredNorm() > 0) {
        ringOwned[v] = 1;
        s.ringVerts.back().push_back({P[v], vn[v]});
      }
  }
  // Test points: vertices, open-boundary samples, grids on large triangles (capped per element
  // so an absurdly small spacing cannot explode the count).
  s.pts = P;
  s.ptN = vn;
  for (const auto& [key, f] : ringEdges) {
    const Vec3 a = P[key >> 32], b = P[key & 0xffffffffu];
    const double len = (a - b).norm();
    const size_t n = len / spacing < 64.0 ? size_t(std::floor(len / spacing)) : 64;
    for (size_t i = 1; i < n; ++i) {
      s.pts.push_back(a + (b - a) * (double(i) / n));
      s.ptN.push_back(s.faceN[f]);
    }
  }
  for (size_t f = 0; f < nf; ++f) {
    const auto& t = s.tri[f];
    const double longest =
        std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    if (longest <= 2 * spacing) continue;
    const size_t n = longest / spacing < 16.0 ? size_t(std::ceil(longest / spacing)) : 16;
    for (size_t i = 1; i < n; ++i)
      for (size_t j = 1; i + j < n; ++j) {
        s.pts.push_back(t[0] + (t[1] - t[0]) * (double(i) / n) + (t[2] - t[0]) * (double(j) / n));
        s.ptN.push_back(s.faceN[f]);
      }
  }
  // Interior hierarchy.
  std::vector<Vec3> centres(nf);
  for (size_t f = 0; f < nf; ++f) centres[f] = (s.tri[f][0] + s.tri[f][1] + s.tri[f][2]) / 3.0;
  buildBvh(centres, s.faceOrder, s.faceBvh, 4, [&](uint32_t b, uint32_t e, BvhNode& nd) {
    primitiveBounds(
        b, e, nd,
        [&](uint32_t i, auto&& fn) {
          for (const Vec3& p : s.tri[s.faceOrder[i]]) fn(p);
        },
        [&](uint32_t i, auto&& fn) {
          const uint32_t f = s.faceOrder[i];
          if (s.faceN[f].squaredNorm() > 0) fn(s.faceN[f], 1.0, 0.0);
          for (const auto& c : s.creases[f]) {
            fn(c.n1, 1.0, 0.0);
            fn(c.n2, 1.0, 0.0);
          }
          for (const auto& v : s.fans[f]) fn(v.n, v.cosBeta, v.sinBeta);
        });
    setGamma(nd, 0.0);
  });
  // Ring hierarchy.
  std::vector<Vec3> ringCentres(s.ring.size());
  for (size_t e = 0; e < s.ring.size(); ++e) ringCentres[e] = 0.5 * (s.ring[e].a + s.ring[e].b);
  buildBvh(ringCentres, s.ringOrder, s.ringBvh, 4, [&](uint32_t b, uint32_t e, BvhNode& nd) {
    primitiveBounds(
        b, e, nd,
        [&](uint32_t i, auto&& fn) {
          fn(s.ring[s.ringOrder[i]].a);
          fn(s.ring[s.ringOrder[i]].b);
        },
        [&](uint32_t i, auto&& fn) {
          fn(s.ring[s.ringOrder[i]].n, 1.0, 0.0);
          for (const auto& v : s.ringVerts[s.ringOrder[i]]) fn(v.n, 1.0, 0.0);
        });
    setGamma(nd, alpha);
  });
  // Test points' hierarchy (points reordered to match).
  std::vector<uint32_t> order;
  const std::vector<Vec3> pts = s.pts, normals = s.ptN;
  buildBvh(pts, order, s.ptBvh, 8, [&](uint32_t b, uint32_t e, BvhNode& nd) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    Vec3 axis = Vec3::Zero();
    for (uint32_t i = b; i < e; ++i) {
      lo = lo.cwiseMin(pts[order[i]]);
      hi = hi.cwiseMax(pts[order[i]]);
      axis += normals[order[i]];
    }
    nd.s.c = 0.5 * (lo + hi);
    double r2 = 0;
    for (uint32_t i = b; i < e; ++i) r2 = std::max(r2, (pts[order[i]] - nd.s.c).squaredNorm());
    nd.s.r = std::sqrt(r2) * (1 + 1e-12) + 1e-12;
    nd.axis = axis.norm() > 1e-9 ? Vec3(axis.normalized()) : Vec3::UnitZ();
    nd.hMin = std::numeric_limits<double>::infinity();
    nd.hMax = -nd.hMin;
    double rho2 = 0;
    for (uint32_t i = b; i < e; ++i) {
      const Vec3 d = pts[order[i]] - nd.s.c;
      const double h = d.dot(nd.axis);
      nd.hMin = std::min(nd.hMin, h);
      nd.hMax = std::max(nd.hMax, h);
      rho2 = std::max(rho2, (d - h * nd.axis).squaredNorm());
    }
    nd.rho = std::sqrt(rho2) * (1 + 1e-12) + 1e-12;
    nd.hMin -= 1e-12 * (1 + std::abs(nd.hMin));
    nd.hMax += 1e-12 * (1 + std::abs(nd.hMax));
  });
  for (size_t i = 0; i < order.size(); ++i) {
    s.pts[i] = pts[order[i]];
    s.ptN[i] = normals[order[i]];
  }
  return s;
}

// Can points of point-hierarchy node b be inside primitives of node a (gamma = alphaEff + spread
// precomputed as cos/sin, slant reach)? The angle test angle(v, a) < gamma + asin(x1) + asin(x2)
// is evaluated without trigonometry: with delta = asin(x1) + asin(x2) (cos and sin from the
// addition formulas), the bound reaches pi when cos(delta) <= -cos(gamma), else the test is
// v . a / D > cos(gamma + delta).
bool mayMeet(const BvhNode& a, const BvhNode& b, double reach, double clearance) {
  const Vec3 v = b.s.c - a.s.c;
  const double D = v.norm();
  if (D > a.s.r + b.s.r + reach) return false;
  if (a.cosGamma > 0) {  // gamma < 90 deg: slab test
    const double t = a.axis.dot(b.axis);
    const double across = std::sqrt(std::max(0.0, 1 - t * t));
    const double maxProj = b.s.c.dot(a.axis) + std::max(b.hMax * t, b.hMin * t) + b.rho * across;
    if (maxProj <= a.lowAlongAxis + clearance * a.cosGamma) return false;
  }
  if (D <= a.s.r + b.s.r) return true;
  if (a.cosGamma <= -1) return true;
  const double x1 = std::min(1.0, a.s.r / (D - b.s.r)), x2 = std::min(1.0, b.s.r / D);
  const double c1 = std::sqrt(std::max(0.0, 1 - x1 * x1)), c2 = std::sqrt(std::max(0.0, 1 - x2 * x2));
  const double cosD = c1 * c2 - x1 * x2, sinD = x1 * c2 + x2 * c1;
  if (cosD <= -a.cosGamma) return true;
  const double cosBound = a.cosGamma * cosD - a.sinGamma * sinD;
  // Small margin toward "may meet" against roundoff.
  return v.dot(a.axis) > (cosBound - 1e-12) * D;
}

// Is any test point of sj inside the primitives of hierarchy `prims` of si? Dual traversal.
template <class Inside>
bool dualHit(const std::vector<BvhNode>& prims, const std::vector<uint32_t>& primOrder,
             const NodeShape& sj, double reach, double clearance,
             const Inside& inside) {
  if (prims.empty() || sj.ptBvh.empty()) return false;
  std::vector<std::pair<uint32_t, uint32_t>> stack;
  stack.push_back({0, 0});
  while (!stack.empty()) {
    const auto [ai, bi] = stack.back();
    stack.pop_back();
    const BvhNode& a = prims[ai];
    const BvhNode& b = sj.ptBvh[bi];
    if (!mayMeet(a, b, reach, clearance)) continue;
    const bool aLeaf = a.left < 0, bLeaf = b.left < 0;
    if (aLeaf && bLeaf) {
      for (uint32_t p = b.begin; p < b.end; ++p)
        for (uint32_t i = a.begin; i < a.end; ++i)
          if (inside(sj.pts[p], primOrder[i])) return true;
      continue;
    }
    if (bLeaf || (!aLeaf && a.s.r >= b.s.r)) {
      stack.push_back({uint32_t(a.right), bi});
      stack.push_back({uint32_t(a.left), bi});
    } else {
      stack.push_back({ai, uint32_t(b.right)});
      stack.push_back({ai, uint32_t(b.left)});
    }
  }
  return false;
}

bool treeMatchesLayers(const std::vector<CurvedLayer>& layers, const SkeletonTree& tree,
                       std::string& why) {
  if (!tree.ok()) {
    why = "the skeleton tree carries an error status";
    return false;
  }
  size_t n = 0;
  for (size_t i = 0; i < layers.size(); ++i)
    for (size_t r = 0; r < layers[i].regions.size(); ++r, ++n)
      if (n >= tree.nodes.size() || tree.nodes[n].layer != i || tree.nodes[n].region != r) {
        why = "the skeleton tree was not built from these layers (node " + std::to_string(n) + ")";
        return false;
      }
  if (n != tree.nodes.size()) {
    why = "the skeleton tree has " + std::to_string(tree.nodes.size()) + " nodes for " +
          std::to_string(n) + " regions";
    return false;
  }
  return true;
}

}  // namespace

CollisionModel potentialCollisionSurfaces(const std::vector<CurvedLayer>& layers,
                                          const SkeletonTree& tree,
                                          const CollisionConeOptions& options,
                                          const ProgressFn& progress) {
  const auto t0 = Clock::now();
  CollisionModel out;
  auto fail = [](Status s, std::string msg) { return failed<CollisionModel>(s, std::move(msg)); };
  if (!(options.angleDegrees > 0 && options.angleDegrees < 90))
    return fail(Status::InvalidOption, "collision: nozzle angle must be in (0, 90) degrees");
  if (!(options.length > 0) || !std::isfinite(options.length))
    return fail(Status::InvalidOption, "collision: cone length must be > 0 mm");
  if (!(options.clearance >= 0) || !(options.clearance < options.length))
    return fail(Status::InvalidOption, "collision: clearance must be in [0, length) mm");
  if (!(options.sampleSpacing > 0) || !std::isfinite(options.sampleSpacing))
    return fail(Status::InvalidOption, "collision: sampleSpacing must be > 0 mm");
  std::string why;
  if (!treeMatchesLayers(layers, tree, why)) return fail(Status::InvalidOption, "collision: " + why);
  for (const CurvedLayer& l : layers)
    for (const LayerRegion& r : l.regions)
      if (!regionValid(r)) return fail(Status::InvalidOption, "collision: malformed region mesh");

  ConeParams k;
  k.alpha = options.angleDegrees * kPi / 180;
  k.tanA = std::tan(k.alpha);
  k.length = options.length;
  k.clearance = options.clearance;
  const double ringReach = options.length / det::cos(k.alpha);

  const size_t n = tree.nodes.size();
  std::vector<NodeShape> shapes(n);
  for (size_t i = 0; i < n; ++i) {
    if (i % 64 == 0 && !reportProgress(progress, "collision", 0.1 * double(i) / double(n)))
      return fail(Status::Cancelled, "collision: cancelled");
    shapes[i] = makeShape(layers[tree.nodes[i].layer].regions[tree.nodes[i].region],
                          options.sampleSpacing, k.alpha);
    out.foldedFaces += shapes[i].folded;
  }
  out.pcs.assign(n, {});
  for (size_t i = 0; i < n; ++i) {
    if (!reportProgress(progress, "collision", 0.1 + 0.9 * double(i) / double(n)))
      return fail(Status::Cancelled, "collision: cancelled");
    const NodeShape& si = shapes[i];
    auto inFace = [&](const Vec3& q, uint32_t f) { return insideFace(q, si, f, k); };
    auto inRing = [&](const Vec3& q, uint32_t e) { return insideRing(q, si, e, k); };
    for (size_t j = 0; j < n; ++j) {
      const NodeShape& sj = shapes[j];
      if (j == i || sj.ptBvh.empty()) continue;
      const bool meetF =
          !si.faceBvh.empty() && mayMeet(si.faceBvh[0], sj.ptBvh[0], k.length, k.clearance);
      const bool meetR =
          !si.ringBvh.empty() && mayMeet(si.ringBvh[0], sj.ptBvh[0], ringReach, k.clearance);
      if (!meetF && !meetR) continue;
      ++out.pairsTested;
      if ((meetF && dualHit(si.faceBvh, si.faceOrder, sj, k.length, k.clearance, inFace)) ||
          (meetR && dualHit(si.ringBvh, si.ringOrder, sj, ringReach, k.clearance, inRing)))
        out.pcs[i].push_back(uint32_t(j));
    }
  }
  reportProgress(progress, "collision", 1.0);
  out.ms = msSince(t0);
  return out;
}

// ================================================================================================
const char* traversalName(TraversalKind kind) {
  switch (kind) {
    case TraversalKind::LPT: return "LPT";
    case TraversalKind::DPT: return "DPT";
    case TraversalKind::A3: return "A3";
  }
  return "A3";
}

bool parseTraversal(const std::string& text, TraversalKind& kind) {
  std::string t;
  for (char c : text) t += char(std::toupper(static_cast<unsigned char>(c)));
  if (t == "LPT") kind = TraversalKind::LPT;
  else if (t == "DPT") kind = TraversalKind::DPT;
  else if (t == "A3") kind = TraversalKind::A3;
  else return false;
  return true;
}

namespace {

// Strongly connected components (iterative Tarjan) of a graph on n nodes whose successors of v
// are given by successor(v, k, w): true and the k-th successor in w, false past the last one.
// comp[v] gets its component; returns the number of components.
template <class Successor>
uint32_t strongComponents(size_t n, const Successor& successor, std::vector<uint32_t>& comp) {
  constexpr uint32_t kUnseen = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> index(n, kUnseen), low(n, 0), stack;
  comp.assign(n, kUnseen);
  std::vector<uint8_t> onStack(n, 0);
  std::vector<std::pair<uint32_t, size_t>> call;  // (node, next successor)
  uint32_t next = 0, comps = 0;
  for (uint32_t root = 0; root < n; ++root) {
    if (index[root] != kUnseen) continue;
    call.push_back({root, 0});
    index[root] = low[root] = next++;
    stack.push_back(root);
    onStack[root] = 1;
    while (!call.empty()) {
      auto& [v, k] = call.back();
      uint32_t w = 0;
      if (successor(v, k, w)) {
        ++k;
        if (index[w] == kUnseen) {
          index[w] = low[w] = next++;
          stack.push_back(w);
          onStack[w] = 1;
          call.push_back({w, 0});
        } else if (onStack[w]) {
          low[v] = std::min(low[v], index[w]);
        }
        continue;
      }
      if (low[v] == index[v]) {
        uint32_t x;
        do {
          x = stack.back();
          stack.pop_back();
          onStack[x] = 0;
          comp[x] = comps;
        } while (x != v);
        ++comps;
      }
      const uint32_t done = v;
      call.pop_back();
      if (!call.empty()) low[call.back().first] = std::min(low[call.back().first], low[done]);
    }
  }
  return comps;
}

// The precedence graph: lower-node -> node (Criterion 1) and u -> x for x in links[u] unless u
// is exempt (Criterion 2). Its strongly connected components in comp; returns which of them hold
// a link u -> x of a non-exempt u (a cycle of constraints: every order breaks one such link).
std::vector<uint8_t> cyclicComponents(const SkeletonTree& tree,
                                      const std::vector<std::vector<uint32_t>>& links,
                                      const std::vector<uint8_t>& exempt,
                                      std::vector<uint32_t>& comp) {
  const size_t n = tree.nodes.size();
  auto successor = [&](uint32_t v, size_t k, uint32_t& w) {
    const auto& up = tree.nodes[v].upper;
    if (k < up.size()) {
      w = up[k];
      return true;
    }
    k -= up.size();
    if (exempt[v] || k >= links[v].size()) return false;
    w = links[v][k];
    return true;
  };
  const uint32_t comps = strongComponents(n, successor, comp);
  std::vector<uint8_t> cyclic(comps, 0);
  for (uint32_t u = 0; u < n; ++u)
    if (!exempt[u])
      for (uint32_t x : links[u])
        if (comp[x] == comp[u]) cyclic[comp[u]] = 1;
  return cyclic;
}

// A component holding a PCS link u -> x is a cycle of constraints, so every order breaks one of
// its PCS links and makes one of its nodes collide; components are disjoint, so their count
// bounds the colliding nodes from below.
size_t cyclesWithPcsLink(const SkeletonTree& tree, const CollisionModel& collisions) {
  std::vector<uint32_t> comp;
  const std::vector<uint8_t> none(tree.nodes.size(), 0);
  size_t count = 0;
  for (uint8_t c : cyclicComponents(tree, collisions.pcs, none, comp)) count += c;
  return count;
}

// Gives back, in the order given, every exemption whose links close no cycle (no target of
// u's links reaches u; the graph without u's links is acyclic already).
void giveBack(const SkeletonTree& tree, const std::vector<std::vector<uint32_t>>& links,
              const std::vector<uint32_t>& order, std::vector<uint8_t>& exempt) {
  const size_t n = tree.nodes.size();
  std::vector<uint32_t> seen(n, 0), stack;
  uint32_t stamp = 0;
  for (uint32_t u : order) {
    if (!exempt[u] || links[u].empty()) continue;
    ++stamp;
    stack.assign(links[u].begin(), links[u].end());
    for (uint32_t x : stack) seen[x] = stamp;
    bool cycle = false;
    while (!stack.empty() && !cycle) {
      const uint32_t v = stack.back();
      stack.pop_back();
      auto visit = [&](uint32_t w) {
        if (w == u) cycle = true;
        if (seen[w] == stamp) return;
        seen[w] = stamp;
        stack.push_back(w);
      };
      for (uint32_t w : tree.nodes[v].upper) visit(w);
      if (!exempt[v])
        for (uint32_t w : links[v]) visit(w);
    }
    if (!cycle) exempt[u] = 0;
  }
}

// Nodes allowed to collide so that the precedence graph without their Criterion-2 links is
// acyclic (a feedback set over PCS sources), greedily: from the nodes that collide in any order
// (stuck), while a component holds a cycle, exempt in each such component the node with the most
// links inside it (ties: lower index); then give back every exemption (latest first) whose links
// close no cycle. Every order consistent with the rest makes at most the exempt nodes collide.
std::vector<uint8_t> feedbackExemptions(const SkeletonTree& tree,
                                        const std::vector<std::vector<uint32_t>>& links,
                                        const std::vector<uint8_t>& stuck) {
  const size_t n = tree.nodes.size();
  std::vector<uint8_t> exempt = stuck;
  std::vector<uint32_t> comp, added;
  for (;;) {
    const std::vector<uint8_t> cyclic = cyclicComponents(tree, links, exempt, comp);
    std::vector<uint32_t> bestNode(cyclic.size(), 0), bestLinks(cyclic.size(), 0);
    for (uint32_t u = 0; u < n; ++u) {
      if (exempt[u] || !cyclic[comp[u]]) continue;
      uint32_t inside = 0;
      for (uint32_t x : links[u]) inside += comp[x] == comp[u];
      if (inside > bestLinks[comp[u]]) {
        bestLinks[comp[u]] = inside;
        bestNode[comp[u]] = u;
      }
    }
    const size_t before = added.size();
    for (size_t c = 0; c < cyclic.size(); ++c)
      if (cyclic[c] && bestLinks[c] > 0) {
        exempt[bestNode[c]] = 1;
        added.push_back(bestNode[c]);
      }
    if (added.size() == before) break;
  }
  giveBack(tree, links, std::vector<uint32_t>(added.rbegin(), added.rend()), exempt);
  return exempt;
}

// A lower bound on the colliding nodes of any order: cycles of the precedence graph whose PCS
// links come from pairwise different nodes (each cycle makes one of its link sources collide).
// The stuck nodes are one-link cycles; the others are packed greedily, by 0-1 breadth-first
// search (a lower-node link costs 0, a PCS link 1) for the cycle through each node u with the
// fewest other sources, accepting cycles of at most 1, 2 and then 4 other sources, over links of
// sources not used yet. links holds the lowest PCS entries (the cycles are the same).
size_t packedCycles(const SkeletonTree& tree, const std::vector<std::vector<uint32_t>>& links,
                    const std::vector<uint8_t>& stuck) {
  const size_t n = tree.nodes.size();
  constexpr uint32_t kFar = std::numeric_limits<uint32_t>::max();
  std::vector<uint8_t> used = stuck;
  size_t count = 0;
  for (uint8_t s : stuck) count += s;
  std::vector<uint32_t> cost(n, kFar), from(n, kFar), touched;
  std::deque<uint32_t> queue;
  std::vector<uint32_t> comp;
  const std::vector<uint8_t> cyclic = cyclicComponents(tree, links, stuck, comp);
  for (const uint32_t limit : {1u, 2u, 4u}) {
    for (uint32_t u = 0; u < n; ++u) {
      if (used[u] || !cyclic[comp[u]]) continue;
      for (uint32_t v : touched) cost[v] = kFar;
      touched.clear();
      queue.clear();
      for (uint32_t x : links[u])
        if (cost[x] != 0) {
          cost[x] = 0;
          from[x] = u;
          touched.push_back(x);
          queue.push_back(x);
        }
      while (!queue.empty() && cost[u] == kFar) {
        const uint32_t v = queue.front();
        queue.pop_front();
        if (cost[v] > limit) break;
        auto relax = [&](uint32_t w, uint32_t c, bool front) {
          if (c >= cost[w]) return;
          if (cost[w] == kFar) touched.push_back(w);
          cost[w] = c;
          from[w] = v;
          front ? queue.push_front(w) : queue.push_back(w);
        };
        for (uint32_t w : tree.nodes[v].upper) relax(w, cost[v], true);
        if (v != u && !used[v])
          for (uint32_t w : links[v]) relax(w, cost[v] + 1, false);
      }
      if (cost[u] > limit) continue;
      // Walk back from u to one of its own link targets, marking the sources of PCS links.
      used[u] = 1;
      for (uint32_t w = u; cost[w] != 0 || from[w] != u;) {
        const uint32_t v = from[w];
        if (cost[v] != cost[w]) used[v] = 1;  // v -> w was a PCS link
        w = v;
      }
      ++count;
    }
  }
  return count;
}

}  // namespace

PrintSequence printSequence(const SkeletonTree& tree, const CollisionModel& collisions,
                            TraversalKind kind) {
  const auto t0 = Clock::now();
  PrintSequence out;
  out.kind = kind;
  const size_t n = tree.nodes.size();
  auto fail = [&](Status s, std::string msg) {
    PrintSequence r;
    r.kind = kind;
    r.status = s;
    r.message = std::move(msg);
    r.collisionFree = false;
    return r;
  };
  if (!tree.ok()) return fail(Status::InvalidOption, "sequence: the skeleton tree carries an error");
  if (n == 0) return fail(Status::EmptyInput, "sequence: empty skeleton tree");
  if (!collisions.ok())
    return fail(Status::InvalidOption, "sequence: the collision model carries an error");
  if (collisions.pcs.size() != n)
    return fail(Status::InvalidOption, "sequence: collision model has " +
                                           std::to_string(collisions.pcs.size()) +
                                           " entries for " + std::to_string(n) + " nodes");
  for (size_t i = 0; i < n; ++i) {
    const SkeletonNode& nd = tree.nodes[i];
    if (i && (nd.layer < tree.nodes[i - 1].layer ||
              (nd.layer == tree.nodes[i - 1].layer && nd.region <= tree.nodes[i - 1].region)))
      return fail(Status::InvalidOption, "sequence: nodes not sorted by (layer, region)");
    for (uint32_t l : nd.lower)
      if (l >= n || tree.nodes[l].layer + 1 != nd.layer ||
          !std::binary_search(tree.nodes[l].upper.begin(), tree.nodes[l].upper.end(), uint32_t(i)))
        return fail(Status::InvalidOption, "sequence: node " + std::to_string(i) +
                                               " has an inconsistent lower-node link");
    for (uint32_t u : nd.upper)
      if (u >= n || !std::binary_search(tree.nodes[u].lower.begin(), tree.nodes[u].lower.end(),
                                        uint32_t(i)))
        return fail(Status::InvalidOption, "sequence: node " + std::to_string(i) +
                                               " has an inconsistent upper-node link");
    for (uint32_t j : collisions.pcs[i])
      if (j >= n || j == i)
        return fail(Status::InvalidOption, "sequence: collision model index out of range");
  }

  std::vector<uint32_t> lowerLeft0(n), blockers0(n, 0);
  for (size_t i = 0; i < n; ++i) lowerLeft0[i] = uint32_t(tree.nodes[i].lower.size());
  // Ancestors (through lower-nodes) as bitsets, nodes in (layer, region) order so lower-nodes
  // come first.
  const size_t words = (n + 63) / 64;
  std::vector<uint64_t> anc(n * words, 0);
  for (size_t i = 0; i < n; ++i)
    for (uint32_t l : tree.nodes[i].lower) {
      anc[i * words + l / 64] |= uint64_t(1) << (l % 64);
      for (size_t w = 0; w < words; ++w) anc[i * words + w] |= anc[size_t(l) * words + w];
    }
  auto isAncestor = [&](uint32_t x, size_t of) {
    return (anc[of * words + x / 64] >> (x % 64)) & 1;
  };
  // Criterion 2: x may be printed only once every u with x in pcs[u] is printed, except where x
  // is an ancestor of u (that collision happens in every order).
  std::vector<std::vector<uint32_t>> avoidable(n), blockedBy(n);
  std::vector<uint8_t> stuck(n, 0);
  size_t unavoidable = 0;
  for (size_t u = 0; u < n; ++u) {
    for (uint32_t x : collisions.pcs[u]) {
      if (isAncestor(x, u)) {
        stuck[u] = 1;
        continue;
      }
      avoidable[u].push_back(x);
      blockedBy[x].push_back(uint32_t(u));
      ++blockers0[x];
    }
    unavoidable += stuck[u];
  }
  auto dist = [&](uint32_t a, uint32_t b) {
    return (tree.nodes[a].centroid - tree.nodes[b].centroid).norm();
  };
  auto isUpper = [&](uint32_t a, uint32_t b) {
    const auto& up = tree.nodes[a].upper;
    return std::binary_search(up.begin(), up.end(), b);
  };
  // Start: the first layer's lowest centroid (first non-empty layer = nodes[0].layer).
  uint32_t lowest = 0;
  for (uint32_t i = 0; i < n && tree.nodes[i].layer == tree.nodes[0].layer; ++i)
    if (tree.nodes[i].centroid.z() < tree.nodes[lowest].centroid.z()) lowest = i;

  // Where A3 must break Criterion 2 (no candidate meets it), four policies (Relaxation); A3
  // keeps the order with the fewest colliding nodes, then retractions, then air moves.
  enum class Relaxation {
    Blockers,   // the candidates with the fewest unprinted blockers
    Undecided,  // ... the fewest blockers whose collision is not yet decided
    Release,    // a node whose collision is decided (a node of its PCS printed first) stops
                // blocking the rest of its PCS: that would only shift collisions onto others
    Exempt,     // as Release, and a feedback set of nodes (feedbackExemptions), chosen before
                // the walk so that the remaining constraints are acyclic, never blocks
  };
  // Only the lowest entries of each PCS matter for cycles and collisions: x in pcs[u] above
  // another entry y (y an ancestor of x) is printed after y anyway.
  std::vector<std::vector<uint32_t>> lowestLinks(n);
  {
    std::vector<uint64_t> mask(words, 0);
    for (size_t u = 0; u < n; ++u) {
      for (uint32_t x : avoidable[u]) mask[x / 64] |= uint64_t(1) << (x % 64);
      for (uint32_t x : avoidable[u]) {
        bool above = false;
        for (size_t w = 0; w < words && !above; ++w) above = (anc[x * words + w] & mask[w]) != 0;
        if (!above) lowestLinks[u].push_back(x);
      }
      for (uint32_t x : avoidable[u]) mask[x / 64] = 0;
    }
  }
  // Per node: does the order print one of its (lowest) avoidable PCS entries before it?
  auto breaksLinks = [&](const std::vector<uint32_t>& order) {
    std::vector<size_t> pos(n);
    for (size_t i = 0; i < n; ++i) pos[order[i]] = i;
    std::vector<uint8_t> breaks(n, 0);
    for (uint32_t u = 0; u < n; ++u)
      for (uint32_t x : lowestLinks[u]) breaks[u] = breaks[u] || pos[x] < pos[u];
    return breaks;
  };
  std::vector<uint8_t> exempt;
  auto run = [&](TraversalKind kind, Relaxation policy, PrintSequence& seq) -> bool {
    seq.kind = kind;
    std::vector<uint32_t> lowerLeft = lowerLeft0, blockersLeft = blockers0;
    std::vector<uint8_t> printed(n, 0), released(n, 0), decided(n, 0);
    auto release = [&](uint32_t u) {
      if (released[u]) return;
      released[u] = 1;
      for (uint32_t x : avoidable[u]) --blockersLeft[x];
    };
    if (policy == Relaxation::Exempt) {
      for (uint32_t u = 0; u < n; ++u)
        if (exempt[u]) release(u);
    }
    auto c2 = [&](uint32_t x) { return blockersLeft[x] == 0; };
    auto cost = [&](uint32_t c) {
      if (policy != Relaxation::Undecided) return blockersLeft[c];
      uint32_t k = 0;
      for (uint32_t u : blockedBy[c]) k += !printed[u] && !decided[u];
      return k;
    };
    std::vector<uint32_t> avail;  // Criterion-1 candidates
    for (uint32_t i = 0; i < n; ++i)
      if (lowerLeft[i] == 0) avail.push_back(i);
    int64_t cur = -1;
    while (seq.order.size() < n) {
      if (avail.empty()) return false;
      const Eigen::Vector3d from = cur >= 0 ? tree.nodes[cur].centroid : tree.nodes[lowest].centroid;
      auto nearestOf = [&](auto&& pred) {
        int64_t best = -1;
        double bestD = std::numeric_limits<double>::infinity();
        for (uint32_t c : avail) {
          if (!pred(c)) continue;
          const double d = (tree.nodes[c].centroid - from).norm();
          if (d < bestD || (d == bestD && c < best)) {
            bestD = d;
            best = c;
          }
        }
        return best;
      };
      int64_t pick = -1;
      switch (kind) {
        case TraversalKind::LPT: {
          uint32_t minLayer = std::numeric_limits<uint32_t>::max();
          for (uint32_t c : avail) minLayer = std::min(minLayer, tree.nodes[c].layer);
          pick = nearestOf([&](uint32_t c) { return tree.nodes[c].layer == minLayer; });
          break;
        }
        case TraversalKind::DPT:
          if (cur >= 0) pick = nearestOf([&](uint32_t c) { return isUpper(uint32_t(cur), c); });
          if (pick < 0) pick = nearestOf([](uint32_t) { return true; });
          break;
        case TraversalKind::A3:
          if (cur >= 0)
            pick = nearestOf([&](uint32_t c) { return c2(c) && isUpper(uint32_t(cur), c); });
          if (pick < 0) pick = nearestOf([&](uint32_t c) { return c2(c); });
          if (pick < 0) {
            // No candidate meets Criterion 2 (cycles of potential collisions, e.g. where two
            // fronts close a loop): among the candidates that would break it for the fewest
            // nodes, an upper-node of the current node first, else the nearest.
            uint32_t fewest = std::numeric_limits<uint32_t>::max();
            for (uint32_t c : avail) fewest = std::min(fewest, cost(c));
            if (cur >= 0)
              pick = nearestOf([&](uint32_t c) { return cost(c) == fewest && isUpper(uint32_t(cur), c); });
            if (pick < 0) pick = nearestOf([&](uint32_t c) { return cost(c) == fewest; });
            ++seq.criterion2Relaxed;
          }
          break;
      }
      const uint32_t p = uint32_t(pick);
      if (cur >= 0 && !isUpper(uint32_t(cur), p)) {
        ++seq.retractions;
        seq.airMoveMm += dist(uint32_t(cur), p);
      }
      seq.order.push_back(p);
      printed[p] = 1;
      avail.erase(std::find(avail.begin(), avail.end(), p));
      release(p);
      for (uint32_t u : blockedBy[p]) {
        if (printed[u]) continue;
        decided[u] = 1;  // p printed before u: u collides whatever comes next
        if (policy == Relaxation::Release || policy == Relaxation::Exempt) release(u);
      }
      for (uint32_t u : tree.nodes[p].upper)
        if (--lowerLeft[u] == 0) avail.push_back(u);
      cur = p;
    }
    // Collision check: node u printed after some x in pcs[u].
    std::vector<size_t> pos(n);
    for (size_t i = 0; i < n; ++i) pos[seq.order[i]] = i;
    if (policy == Relaxation::Exempt)  // the nodes whose avoidable entries the order breaks
      for (uint8_t b : breaksLinks(seq.order)) seq.criterion2Relaxed += b;
    for (size_t u = 0; u < n; ++u)
      for (uint32_t x : collisions.pcs[u])
        if (pos[x] < pos[u]) {
          ++seq.collidingNodes;
          break;
        }
    seq.collisionFree = seq.collidingNodes == 0;
    return true;
  };
  auto better = [](const PrintSequence& a, const PrintSequence& b) {
    return a.collidingNodes < b.collidingNodes ||
           (a.collidingNodes == b.collidingNodes &&
            (a.retractions < b.retractions ||
             (a.retractions == b.retractions && a.airMoveMm < b.airMoveMm)));
  };
  const char* cyclicLinks = "sequence: no node meets Criterion 1 (cyclic links)";
  if (!run(kind, Relaxation::Blockers, out)) return fail(Status::Internal, cyclicLinks);
  if (kind == TraversalKind::A3 && out.criterion2Relaxed > 0) {
    for (const Relaxation policy : {Relaxation::Undecided, Relaxation::Release}) {
      PrintSequence seq;
      if (!run(kind, policy, seq)) return fail(Status::Internal, cyclicLinks);
      if (better(seq, out)) out = std::move(seq);
    }
    // Exempt: the smallest of the greedy feedback set and the colliding nodes of the best order
    // so far, of LPT's and of DPT's, each with every exemption given back (latest printed first)
    // whose links close no cycle. So A3 never collides on more nodes than LPT or DPT.
    auto count = [&](const std::vector<uint8_t>& e) {
      size_t k = 0;
      for (size_t u = 0; u < n; ++u) k += e[u] && !stuck[u];
      return k;
    };
    exempt = feedbackExemptions(tree, lowestLinks, stuck);
    std::vector<PrintSequence> seeds(3);
    seeds[0] = out;
    if (!run(TraversalKind::LPT, Relaxation::Blockers, seeds[1]) ||
        !run(TraversalKind::DPT, Relaxation::Blockers, seeds[2]))
      return fail(Status::Internal, cyclicLinks);
    for (const PrintSequence& seed : seeds) {
      std::vector<uint8_t> seeded = breaksLinks(seed.order);
      for (uint32_t u = 0; u < n; ++u) seeded[u] = seeded[u] || stuck[u];
      std::vector<uint32_t> latestFirst;
      for (auto it = seed.order.rbegin(); it != seed.order.rend(); ++it)
        if (!stuck[*it]) latestFirst.push_back(*it);
      giveBack(tree, lowestLinks, latestFirst, seeded);
      if (count(seeded) < count(exempt)) exempt.swap(seeded);
    }
    PrintSequence seq;
    if (!run(kind, Relaxation::Exempt, seq)) return fail(Status::Internal, cyclicLinks);
    if (better(seq, out)) out = std::move(seq);
  }
  out.unavoidableNodes = unavoidable;
  out.collidingLowerBound =
      std::max(cyclesWithPcsLink(tree, collisions), packedCycles(tree, lowestLinks, stuck));
  out.ms = msSince(t0);
  return out;
}

}  // namespace omnislice
