// SPDX-License-Identifier: MIT
// Isotropic remeshing and HC Laplacian smoothing of one IGDS region (see igds_remesh.h).
//
// Mesh representation: faces in a flat array F (3 per face), half-edge h = 3 f + k runs from
// F[h] to F[next(h)]; O[h] is its twin or -1 on the open boundary; out[v] is some half-edge
// leaving v. Dead faces keep F = -1. Vertices are never reused once collapsed away.
#include "common/det_math.h"
#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "geodesic/igds_remesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "geometry/aabb_tree.h"

namespace omnislice {

namespace {

inline int32_t nextH(int32_t h) { return h - h % 3 + (h % 3 + 1) % 3; }
inline int32_t prevH(int32_t h) { return h - h % 3 + (h % 3 + 2) % 3; }

class Remesher {
 public:
  Remesher(const RemeshInput& in, const RemeshParams& params) : params_(params) {
    P_ = in.positions;
    const size_t nf = in.triangles.size();
    steep_.assign(nf, 1.0);
    for (size_t f = 0; f < in.slope.size() && f < nf; ++f)
      if (in.slope[f] > 1 && std::isfinite(in.slope[f])) steep_[f] = in.slope[f];
    steepest_ = *std::max_element(steep_.begin(), steep_.end());
    F_.resize(3 * nf);
    for (size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) F_[3 * f + k] = int32_t(in.triangles[f][k]);
    buildTwins();
    faceCap_ = 16 * nf + 4096;
    const size_t nv = P_.size();
    bnd_.assign(nv, 0);
    corner_.assign(nv, 0);
    lock_.assign(nv, 0);
    // Projection targets: the interpolated triangles and the boundary polyline (segments as
    // degenerate triangles (a, b, b), which closestPointOnTriangle handles).
    Mesh surface, border;
    surface.positions.reserve(3 * nv);
    for (const Eigen::Vector3d& p : P_) surface.positions.insert(surface.positions.end(), {p.x(), p.y(), p.z()});
    border.positions = surface.positions;
    for (int32_t f : F_) surface.triangles.push_back(uint32_t(f));
    std::vector<int> boundaryDegree(nv, 0);
    for (size_t h = 0; h < F_.size(); ++h) {
      if (O_[h] >= 0) continue;
      const int32_t a = F_[h], b = F_[nextH(int32_t(h))];
      border.triangles.insert(border.triangles.end(), {uint32_t(a), uint32_t(b), uint32_t(b)});
      bnd_[a] = bnd_[b] = 1;
      ++boundaryDegree[a];
      ++boundaryDegree[b];
    }
    surface_ = std::make_unique<AabbTree>(surface);
    if (!border.triangles.empty()) border_ = std::make_unique<AabbTree>(border);
    // out[]: any outgoing half-edge; then lock vertices whose fan is not one disc / half disc
    // (non-manifold vertices of the input) and mark boundary corners.
    out_.assign(nv, -1);
    for (size_t h = 0; h < F_.size(); ++h) out_[F_[h]] = int32_t(h);
    std::vector<int> incident(nv, 0);
    for (int32_t v : F_) ++incident[v];
    std::vector<int32_t> ring;
    for (size_t v = 0; v < nv; ++v) {
      if (out_[v] < 0) {
        lock_[v] = 1;
        continue;
      }
      bool isBoundary = false;
      if (!fan(int32_t(v), ring, isBoundary) || int(ring.size()) != incident[v] ||
          (bnd_[v] && boundaryDegree[v] != 2)) {
        lock_[v] = 1;
        continue;
      }
      if (bnd_[v]) {
        const Eigen::Vector3d a = P_[F_[nextH(ring.front())]], b = P_[F_[prevH(ring.back())]];
        const Eigen::Vector3d e1 = P_[v] - b, e2 = a - P_[v];  // b -> v -> a along the boundary
        const double n1 = e1.norm(), n2 = e2.norm();
        if (n1 > 0 && n2 > 0) {
          const double c = std::clamp(e1.dot(e2) / (n1 * n2), -1.0, 1.0);
          if (det::acos(c) * 180 / kPi > params_.cornerDegrees) corner_[v] = 1;
        }
      }
    }
  }

  bool remesh(const ProgressFn& progress, double at) {
    const double L = params_.targetEdge;
    for (int it = 0; it < params_.remeshIterations; ++it) {
      splitLong(4.0 / 3.0 * L);
      collapseShort(4.0 / 5.0 * L, 4.0 / 3.0 * L);
      flipToValence();
      relax();
      if (!reportProgress(progress, "igds", at)) return false;
    }
    return true;
  }

  // HC algorithm of Vollmer et al.: Laplacian step, then push back by the blended differences.
  bool smooth(const ProgressFn& progress, double at) {
    const double alpha = 0.0, beta = 0.5;
    const size_t nv = P_.size();
    std::vector<Eigen::Vector3d> orig = P_, q(nv), b(nv);
    std::vector<std::vector<int32_t>> nbrs(nv);
    std::vector<uint8_t> movable(nv, 0);
    std::vector<int32_t> ring;
    for (size_t v = 0; v < nv; ++v) {
      if (out_[v] < 0 || lock_[v] || corner_[v]) continue;
      bool isB = false;
      if (!fan(int32_t(v), ring, isB)) continue;
      if (bnd_[v]) {
        nbrs[v] = {F_[nextH(ring.front())], F_[prevH(ring.back())]};
      } else {
        for (int32_t h : ring) nbrs[v].push_back(F_[nextH(h)]);
      }
      movable[v] = 1;
    }
    for (int it = 0; it < params_.smoothIterations; ++it) {
      for (size_t v = 0; v < nv; ++v) {
        q[v] = P_[v];
        if (!movable[v]) continue;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int32_t w : nbrs[v]) c += P_[w];
        q[v] = c / double(nbrs[v].size());
      }
      for (size_t v = 0; v < nv; ++v) b[v] = q[v] - (alpha * orig[v] + (1 - alpha) * P_[v]);
      for (size_t v = 0; v < nv; ++v) {
        if (!movable[v]) continue;
        Eigen::Vector3d avg = Eigen::Vector3d::Zero();
        for (int32_t w : nbrs[v]) avg += b[w];
        avg /= double(nbrs[v].size());
        const Eigen::Vector3d target = q[v] - (beta * b[v] + (1 - beta) * avg);
        tryMove(int32_t(v), target);
      }
      if (!reportProgress(progress, "igds", at)) return false;
    }
    return true;
  }

  // True when some triangle centroid lies farther than limit from the interpolated surface.
  // A centroid farther from the input surface than limit, or than limit / slope of the nearest
  // input triangle where that is steeper than 1.
  bool centroidBeyond(double limit) const {
    for (size_t f = 0; 3 * f < F_.size(); ++f) {
      if (F_[3 * f] < 0) continue;
      const Eigen::Vector3d c = (P_[F_[3 * f]] + P_[F_[3 * f + 1]] + P_[F_[3 * f + 2]]) / 3;
      if (surface_->anyWithin(c, limit / steepest_)) continue;
      const ClosestPoint q = surface_->closest(c);
      if (q.triangle < 0 || q.distance > limit / steep_[size_t(q.triangle)]) return true;
    }
    return false;
  }

  void output(LayerRegion& region) const {
    std::vector<int32_t> map(P_.size(), -1);
    Mesh& m = region.mesh;
    m = Mesh{};
    for (size_t f = 0; 3 * f < F_.size(); ++f) {
      if (F_[3 * f] < 0) continue;
      for (int k = 0; k < 3; ++k) {
        const int32_t v = F_[3 * f + k];
        if (map[v] < 0) {
          map[v] = int32_t(m.vertexCount());
          m.positions.insert(m.positions.end(), {P_[v].x(), P_[v].y(), P_[v].z()});
        }
        m.triangles.push_back(uint32_t(map[v]));
      }
    }
    region.boundaryVertex.assign(m.vertexCount(), 0);
    for (size_t h = 0; h < F_.size(); ++h) {
      if (F_[h] < 0 || O_[h] >= 0) continue;
      region.boundaryVertex[map[F_[h]]] = 1;
      region.boundaryVertex[map[F_[nextH(int32_t(h))]]] = 1;
    }
    region.area = 0;
    for (size_t f = 0; f < m.faceCount(); ++f) {
      const Eigen::Vector3d a = m.vertex(m.triangles[3 * f]), b = m.vertex(m.triangles[3 * f + 1]),
                            c = m.vertex(m.triangles[3 * f + 2]);
      region.area += 0.5 * (b - a).cross(c - a).norm();
    }
  }

 private:
  void buildTwins() {
    struct Key {
      int32_t lo, hi, h;
    };
    std::vector<Key> keys(F_.size());
    for (size_t h = 0; h < F_.size(); ++h) {
      const int32_t a = F_[h], b = F_[nextH(int32_t(h))];
      keys[h] = {std::min(a, b), std::max(a, b), int32_t(h)};
    }
    std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
      return x.lo != y.lo ? x.lo < y.lo : (x.hi != y.hi ? x.hi < y.hi : x.h < y.h);
    });
    O_.assign(F_.size(), -1);
    for (size_t i = 0; i < keys.size();) {
      size_t j = i;
      while (j < keys.size() && keys[j].lo == keys[i].lo && keys[j].hi == keys[i].hi) ++j;
      if (j - i == 2 && F_[keys[i].h] != F_[keys[i + 1].h]) {
        O_[keys[i].h] = keys[i + 1].h;
        O_[keys[i + 1].h] = keys[i].h;
      }
      i = j;
    }
  }

  // Outgoing half-edges of v in fan order (counter-clockwise); for a boundary vertex the first
  // one has no twin. False when the fan is inconsistent.
  bool fan(int32_t v, std::vector<int32_t>& ring, bool& isBoundary) const {
    ring.clear();
    isBoundary = false;
    const int32_t h0 = out_[v];
    if (h0 < 0 || F_[h0] != v) return false;
    int32_t start = h0;
    for (int guard = 0; guard < 4096; ++guard) {  // rotate clockwise to the first face
      const int32_t t = O_[start];
      if (t < 0) {
        isBoundary = true;
        break;
      }
      const int32_t nh = nextH(t);
      if (nh == h0) break;
      start = nh;
      if (guard == 4095) return false;
    }
    int32_t h = start;
    for (int guard = 0; guard < 4096; ++guard) {
      if (F_[h] != v) return false;
      ring.push_back(h);
      const int32_t t = O_[prevH(h)];
      if (t < 0) return isBoundary;
      if (t == start) return !isBoundary;
      h = t;
    }
    return false;
  }

  Eigen::Vector3d faceNormal(int32_t f) const {
    return (P_[F_[3 * f + 1]] - P_[F_[3 * f]]).cross(P_[F_[3 * f + 2]] - P_[F_[3 * f]]);
  }

  // Closest point on the interpolated surface; moves are short, so a bounded search first.
  Eigen::Vector3d projectInterior(const Eigen::Vector3d& p) const {
    ClosestPoint c = surface_->closest(p, 0.25 * params_.targetEdge);
    if (c.triangle < 0) c = surface_->closest(p);
    return c.triangle >= 0 ? c.point : p;
  }

  // Closest point on the boundary polyline; false when it is not near (another boundary part).
  bool projectBoundary(const Eigen::Vector3d& p, double maxDistance, Eigen::Vector3d& q) const {
    if (!border_) return false;
    const ClosestPoint c = border_->closest(p, maxDistance);
    if (c.triangle < 0) return false;
    q = c.point;
    return true;
  }

  int32_t addVertex(const Eigen::Vector3d& p, uint8_t boundary) {
    P_.push_back(p);
    bnd_.push_back(boundary);
    corner_.push_back(0);
    lock_.push_back(0);
    out_.push_back(-1);
    return int32_t(P_.size() - 1);
  }

  void setTwin(int32_t a, int32_t b) {
    if (a >= 0) O_[a] = b;
    if (b >= 0) O_[b] = a;
  }

  // Splits edges longer than maxLen at their midpoint projected onto the interpolated surface.
  void splitLong(double maxLen) {
    const double max2 = maxLen * maxLen;
    for (size_t h0 = 0; h0 < F_.size(); ++h0) {
      const int32_t h = int32_t(h0);
      if (F_[h] < 0 || (O_[h] >= 0 && O_[h] < h)) continue;
      if (F_.size() / 3 > faceCap_) return;
      const int32_t v0 = F_[h], v1 = F_[nextH(h)];
      const double len2 = (P_[v0] - P_[v1]).squaredNorm();
      if (len2 <= max2) continue;
      if (lock_[v0] && lock_[v1]) continue;
      const Eigen::Vector3d mid = 0.5 * (P_[v0] + P_[v1]);
      Eigen::Vector3d p = mid;
      const int32_t t = O_[h];
      if (t < 0) {
        if (!projectBoundary(mid, 0.5 * std::sqrt(len2), p)) continue;
      } else {
        p = projectInterior(mid);
      }
      // A projection landing far away (another sheet of a folded region) or turning a triangle
      // over is not followed: the edge stays long (every vertex stays on the surface).
      if ((p - mid).squaredNorm() > 0.0625 * len2 || !splitKeepsOrientation(h, p)) continue;
      split(h, p);
    }
  }

  // The four (two) triangles a split at p creates turn the same way as the ones they replace.
  bool splitKeepsOrientation(int32_t h, const Eigen::Vector3d& p) const {
    for (int32_t e : {h, O_[h]}) {
      if (e < 0) continue;
      const Eigen::Vector3d a = P_[F_[e]], b = P_[F_[nextH(e)]], c = P_[F_[prevH(e)]];
      const Eigen::Vector3d n = (b - a).cross(c - a);
      const Eigen::Vector3d n1 = (p - a).cross(c - a), n2 = (b - p).cross(c - p);
      if (n1.dot(n) <= 0 || n2.dot(n) <= 0) return false;
    }
    return true;
  }

  void split(int32_t h, const Eigen::Vector3d& p) {
    const int32_t t = O_[h];
    const int32_t m = addVertex(p, t < 0 ? 1 : 0);
    const int32_t n = nextH(h), pr = prevH(h);
    const int32_t v1 = F_[n], a = F_[pr];
    const int32_t oldN = O_[n];
    // f0 = (v0, m, a); new f2 = (m, v1, a).
    F_[n] = m;
    const int32_t g0 = int32_t(F_.size());
    F_.insert(F_.end(), {m, v1, a});
    O_.insert(O_.end(), {-1, -1, -1});
    setTwin(g0 + 1, oldN);
    setTwin(n, g0 + 2);
    out_[m] = n;
    out_[v1] = g0 + 1;
    ++liveFaces_;
    if (t < 0) {
      O_[h] = -1;
      O_[g0] = -1;
      return;
    }
    const int32_t tn = nextH(t), tp = prevH(t);
    const int32_t b = F_[tp];
    const int32_t oldTp = O_[tp];
    // f1 = (m, v0, b); new f3 = (v1, m, b).
    F_[t] = m;
    const int32_t k0 = int32_t(F_.size());
    F_.insert(F_.end(), {v1, m, b});
    O_.insert(O_.end(), {-1, -1, -1});
    setTwin(k0 + 2, oldTp);
    setTwin(tp, k0 + 1);
    setTwin(h, t);
    setTwin(g0, k0);
    ++liveFaces_;
    (void)tn;
  }

  bool ringNeighbours(int32_t v, std::vector<int32_t>& ring, std::vector<int32_t>& nb) const {
    bool isB = false;
    if (!fan(v, ring, isB)) return false;
    nb.clear();
    for (int32_t h : ring) nb.push_back(F_[nextH(h)]);
    if (isB) nb.push_back(F_[prevH(ring.back())]);
    return true;
  }

  // Collapse half-edge h (u -> v): u disappears, v moves to p. Checks everything first.
  bool tryCollapse(int32_t h, const Eigen::Vector3d& p, double maxLen) {
    const int32_t u = F_[h], v = F_[nextH(h)], t = O_[h];
    if (!ringNeighbours(u, ringU_, nbU_) || !ringNeighbours(v, ringV_, nbV_)) return false;
    // Link condition: the common neighbours are exactly the faces' opposite vertices.
    const int32_t a = F_[prevH(h)], b = t >= 0 ? F_[prevH(t)] : -1;
    int common = 0;
    for (int32_t x : nbU_) {
      if (std::find(nbV_.begin(), nbV_.end(), x) == nbV_.end()) continue;
      if (x != a && x != b) return false;
      ++common;
    }
    if (common != (t >= 0 ? 2 : 1)) return false;
    if (lock_[a] || (b >= 0 && lock_[b])) return false;
    const double max2 = maxLen * maxLen;
    for (int32_t x : nbU_)
      if (x != v && (P_[x] - p).squaredNorm() > max2) return false;
    for (int32_t x : nbV_)
      if (x != u && (P_[x] - p).squaredNorm() > max2) return false;
    // Valence of the opposite vertices drops by one; keep >= 3 (interior) / >= 2 (boundary).
    auto valence = [&](int32_t x) {
      bool isB = false;
      fan(x, scratch_, isB);
      return int(scratch_.size()) + (isB ? 1 : 0);
    };
    if (valence(a) - 1 < (bnd_[a] ? 2 : 3)) return false;
    if (b >= 0 && valence(b) - 1 < (bnd_[b] ? 2 : 3)) return false;
    // No face turns over.
    const int32_t f0 = h / 3, f1 = t >= 0 ? t / 3 : -1;
    auto checkFaces = [&](const std::vector<int32_t>& ring, int32_t moved) {
      for (int32_t r : ring) {
        const int32_t f = r / 3;
        if (f == f0 || f == f1) continue;
        Eigen::Vector3d q[3];
        for (int k = 0; k < 3; ++k) {
          const int32_t w = F_[3 * f + k];
          q[k] = (w == moved) ? p : P_[w];
        }
        const Eigen::Vector3d nNew = (q[1] - q[0]).cross(q[2] - q[0]);
        const Eigen::Vector3d nOld = faceNormal(f);
        if (nNew.dot(nOld) <= 0 || nNew.squaredNorm() <= 1e-24 * (1 + nOld.squaredNorm()))
          return false;
      }
      return true;
    };
    if (!checkFaces(ringU_, u) || !checkFaces(ringV_, v)) return false;
    if (liveFaces_ <= 8) return false;
    // Apply: every half-edge leaving u now leaves v.
    for (int32_t r : ringU_) F_[r] = v;
    P_[v] = p;
    const int32_t n0 = nextH(h), p0 = prevH(h);
    const int32_t x0 = O_[n0], y0 = O_[p0];  // a -> v, u -> a (now v -> a)
    setTwin(x0, y0);
    int32_t x1 = -1, y1 = -1;
    if (t >= 0) {
      const int32_t n1 = nextH(t), p1 = prevH(t);
      x1 = O_[n1];  // b -> u (now b -> v)
      y1 = O_[p1];  // v -> b
      setTwin(x1, y1);
      for (int k = 0; k < 3; ++k) {
        F_[3 * f1 + k] = -1;
        O_[3 * f1 + k] = -1;
      }
      --liveFaces_;
    }
    for (int k = 0; k < 3; ++k) {
      F_[3 * f0 + k] = -1;
      O_[3 * f0 + k] = -1;
    }
    --liveFaces_;
    out_[u] = -1;
    out_[v] = -1;
    for (int32_t r : ringU_)
      if (F_[r] == v) out_[v] = r;
    for (int32_t r : ringV_)
      if (F_[r] == v) out_[v] = r;
    out_[a] = x0 >= 0 ? x0 : nextH(y0);
    if (b >= 0) out_[b] = x1 >= 0 ? x1 : nextH(y1);
    return true;
  }

  void collapseShort(double minLen, double maxLen) {
    const double min2 = minLen * minLen;
    for (size_t h0 = 0; h0 < F_.size(); ++h0) {
      const int32_t h = int32_t(h0);
      if (F_[h] < 0 || (O_[h] >= 0 && O_[h] < h)) continue;
      const int32_t u = F_[h], v = F_[nextH(h)];
      if ((P_[u] - P_[v]).squaredNorm() >= min2) continue;
      if (lock_[u] || lock_[v]) continue;
      const bool boundaryEdge = O_[h] < 0;
      auto removable = [&](int32_t x, int32_t keep) {
        if (corner_[x]) return false;
        if (!bnd_[x]) return true;
        return boundaryEdge && bnd_[keep];
      };
      if (!boundaryEdge && bnd_[u] && bnd_[v]) continue;  // would pinch the region
      // Interior into boundary keeps the boundary vertex; two interior ones meet at the middle.
      if (!bnd_[u] && !bnd_[v]) {
        Eigen::Vector3d p = projectInterior(0.5 * (P_[u] + P_[v]));
        if ((p - 0.5 * (P_[u] + P_[v])).squaredNorm() > 0.25 * min2) continue;
        if (!tryCollapse(h, p, maxLen) && O_[h] >= 0) tryCollapse(O_[h], p, maxLen);
        continue;
      }
      if (removable(u, v)) {
        if (tryCollapse(h, P_[v], maxLen)) continue;
      }
      if (removable(v, u)) {
        if (boundaryEdge) {
          // Reverse direction of a boundary edge has no half-edge: collapse v into u through h's
          // geometry is not expressible, so only u -> v collapses are done on the boundary.
          continue;
        }
        if (O_[h] >= 0) tryCollapse(O_[h], P_[u], maxLen);
      }
    }
  }

  void flipToValence() {
    const size_t nv = P_.size();
    std::vector<int> val(nv, 0);
    for (size_t h = 0; h < F_.size(); ++h) {
      if (F_[h] < 0) continue;
      ++val[F_[h]];
      if (O_[h] < 0) ++val[F_[nextH(int32_t(h))]];
    }
    auto target = [&](int32_t x) { return bnd_[x] ? 4 : 6; };
    for (size_t h0 = 0; h0 < F_.size(); ++h0) {
      const int32_t h = int32_t(h0), t = O_[h];
      if (F_[h] < 0 || t < 0 || t < h) continue;
      const int32_t u = F_[h], v = F_[nextH(h)], a = F_[prevH(h)], b = F_[prevH(t)];
      if (a == b || lock_[u] || lock_[v] || lock_[a] || lock_[b]) continue;
      if (val[u] <= 3 || val[v] <= 3) continue;
      const int before = std::abs(val[u] - target(u)) + std::abs(val[v] - target(v)) +
                         std::abs(val[a] - target(a)) + std::abs(val[b] - target(b));
      const int after = std::abs(val[u] - 1 - target(u)) + std::abs(val[v] - 1 - target(v)) +
                        std::abs(val[a] + 1 - target(a)) + std::abs(val[b] + 1 - target(b));
      if (after >= before) continue;
      // Edge a-b must not exist already.
      bool isB = false;
      if (!fan(a, ringU_, isB)) continue;
      bool exists = false;
      for (int32_t r : ringU_) exists = exists || F_[nextH(r)] == b;
      if (isB && F_[prevH(ringU_.back())] == b) exists = true;
      if (exists) continue;
      const Eigen::Vector3d n0 = faceNormal(h / 3), n1 = faceNormal(t / 3);
      const Eigen::Vector3d nA = (P_[b] - P_[u]).cross(P_[a] - P_[u]);
      const Eigen::Vector3d nB = (P_[v] - P_[b]).cross(P_[a] - P_[b]);
      const Eigen::Vector3d nSum = n0 + n1;
      if (nA.dot(nSum) <= 0 || nB.dot(nSum) <= 0 || nA.dot(nB) <= 0) continue;
      const double areaOld = n0.norm() + n1.norm();
      if (nA.norm() < 1e-3 * areaOld || nB.norm() < 1e-3 * areaOld) continue;
      flip(h);
      --val[u];
      --val[v];
      ++val[a];
      ++val[b];
    }
  }

  void flip(int32_t h) {
    const int32_t t = O_[h];
    const int32_t n0 = nextH(h), p0 = prevH(h), n1 = nextH(t), p1 = prevH(t);
    const int32_t u = F_[h], v = F_[n0], a = F_[p0], b = F_[p1];
    const int32_t on0 = O_[n0], op0 = O_[p0], on1 = O_[n1], op1 = O_[p1];
    // f0 = (b, a, u): h b->a, n0 a->u, p0 u->b; f1 = (a, b, v): t a->b, n1 b->v, p1 v->a.
    F_[h] = b;
    F_[n0] = a;
    F_[p0] = u;
    F_[t] = a;
    F_[n1] = b;
    F_[p1] = v;
    setTwin(n0, op0);
    setTwin(p0, on1);
    setTwin(n1, op1);
    setTwin(p1, on0);
    setTwin(h, t);
    out_[u] = p0;
    out_[v] = p1;
    out_[a] = n0;
    out_[b] = n1;
  }

  // Moves v to target (projected); reverts when a face of its fan would turn over.
  bool tryMove(int32_t v, const Eigen::Vector3d& target) {
    bool isB = false;
    if (!fan(v, ringU_, isB)) return false;
    Eigen::Vector3d p;
    if (bnd_[v]) {
      if (!projectBoundary(target, 0.5 * params_.targetEdge, p)) return false;
    } else {
      p = projectInterior(target);
      if ((p - target).squaredNorm() > 0.25 * params_.targetEdge * params_.targetEdge) return false;
    }
    const Eigen::Vector3d old = P_[v];
    std::vector<Eigen::Vector3d>& before = normals_;
    before.clear();
    for (int32_t r : ringU_) before.push_back(faceNormal(r / 3));
    P_[v] = p;
    for (size_t i = 0; i < ringU_.size(); ++i) {
      const Eigen::Vector3d n = faceNormal(ringU_[i] / 3);
      if (n.dot(before[i]) <= 0 || n.squaredNorm() <= 1e-24 * (1 + before[i].squaredNorm())) {
        P_[v] = old;
        return false;
      }
    }
    return true;
  }

  // Tangential relaxation: move toward the neighbours' centroid within the tangent plane.
  void relax() {
    for (size_t v0 = 0; v0 < P_.size(); ++v0) {
      const int32_t v = int32_t(v0);
      if (out_[v] < 0 || lock_[v] || corner_[v]) continue;
      bool isB = false;
      if (!fan(v, ringV_, isB)) continue;
      if (bnd_[v]) {
        const Eigen::Vector3d a = P_[F_[nextH(ringV_.front())]], b = P_[F_[prevH(ringV_.back())]];
        tryMove(v, 0.5 * (a + b));
        continue;
      }
      Eigen::Vector3d c = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
      for (int32_t r : ringV_) {
        c += P_[F_[nextH(r)]];
        n += faceNormal(r / 3);
      }
      c /= double(ringV_.size());
      const double nn = n.norm();
      if (nn <= 0) continue;
      n /= nn;
      const Eigen::Vector3d d = c - P_[v];
      tryMove(v, P_[v] + d - n * n.dot(d));
    }
  }

 public:
  size_t liveFaces_ = 0;

 private:
  RemeshParams params_;
  size_t faceCap_ = 0;
  std::vector<Eigen::Vector3d> P_;
  std::vector<int32_t> F_, O_, out_;
  std::vector<uint8_t> bnd_, corner_, lock_;
  std::unique_ptr<AabbTree> surface_, border_;
  std::vector<double> steep_;  // per input triangle: max(1, slope)
  double steepest_ = 1;
  std::vector<int32_t> ringU_, ringV_, nbU_, nbV_, scratch_;
  std::vector<Eigen::Vector3d> normals_;
};


// ---- self-intersection check of a remeshed region (non-adjacent triangles only) ----

using Tri = std::array<Eigen::Vector3d, 3>;

// Segment pq crosses triangle t (ends strictly on opposite sides, crossing inside t).
bool segmentCrossesTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Tri& t,
                            double eps) {
  const Eigen::Vector3d n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double nn = n.norm();
  if (nn <= 0) return false;
  const double dp = n.dot(p - t[0]) / nn, dq = n.dot(q - t[0]) / nn;
  if ((dp > eps && dq > eps) || (dp < -eps && dq < -eps)) return false;
  if (std::abs(dp) <= eps && std::abs(dq) <= eps) return false;
  const Eigen::Vector3d x = p + (q - p) * (dp / (dp - dq));
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = t[(k + 1) % 3] - t[k];
    if (n.dot(e.cross(x - t[k])) / nn < -eps * e.norm()) return false;
  }
  return true;
}

bool coplanarOverlap(const Tri& a, const Tri& b, const Eigen::Vector3d& n, double eps) {
  int ax = 0;
  n.cwiseAbs().maxCoeff(&ax);
  const int u = (ax + 1) % 3, v = (ax + 2) % 3;
  Eigen::Vector2d A[3], B[3];
  for (int k = 0; k < 3; ++k) {
    A[k] = {a[k][u], a[k][v]};
    B[k] = {b[k][u], b[k][v]};
  }
  auto separated = [&](const Eigen::Vector2d* P, const Eigen::Vector2d* Q) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d e = P[(k + 1) % 3] - P[k], nrm(-e.y(), e.x());
      double pmin = 1e300, pmax = -1e300, qmin = 1e300, qmax = -1e300;
      for (int j = 0; j < 3; ++j) {
        pmin = std::min(pmin, nrm.dot(P[j]));
        pmax = std::max(pmax, nrm.dot(P[j]));
        qmin = std::min(qmin, nrm.dot(Q[j]));
        qmax = std::max(qmax, nrm.dot(Q[j]));
      }
      const double tol = eps * nrm.norm();
      if (pmax <= qmin + tol || qmax <= pmin + tol) return true;
    }
    return false;
  };
  return !separated(A, B) && !separated(B, A);
}

bool trianglesIntersect(const Tri& a, const Tri& b, double eps) {
  const Eigen::Vector3d na = (a[1] - a[0]).cross(a[2] - a[0]);
  const Eigen::Vector3d nb = (b[1] - b[0]).cross(b[2] - b[0]);
  if (na.norm() > 0 && nb.norm() > 0 && na.cross(nb).norm() <= 1e-9 * na.norm() * nb.norm() &&
      std::abs(na.normalized().dot(b[0] - a[0])) <= eps)
    return coplanarOverlap(a, b, na, eps);
  for (int k = 0; k < 3; ++k)
    if (segmentCrossesTriangle(a[k], a[(k + 1) % 3], b, eps) ||
        segmentCrossesTriangle(b[k], b[(k + 1) % 3], a, eps))
      return true;
  return false;
}

// True when two triangles sharing no vertex intersect (uniform grid of cell size `cell`).
bool selfIntersects(const Mesh& m, double cell) {
  const size_t nf = m.faceCount();
  if (nf < 2 || !(cell > 0)) return false;
  BoundingBox bb = boundingBox(m);
  const Eigen::Vector3d ext = bb.max - bb.min;
  // Keep the grid small: at most about 4 cells per triangle.
  double c = cell;
  while ((std::floor(ext.x() / c) + 1) * (std::floor(ext.y() / c) + 1) * (std::floor(ext.z() / c) + 1) >
         4.0 * double(nf) + 64)
    c *= 1.5;
  const int nx = int(ext.x() / c) + 1, ny = int(ext.y() / c) + 1, nz = int(ext.z() / c) + 1;
  std::vector<std::vector<uint32_t>> grid(size_t(nx) * ny * nz);
  std::vector<Tri> tris(nf);
  std::vector<std::array<int, 6>> box(nf);
  auto idx = [&](double x, double lo, int n) { return std::clamp(int((x - lo) / c), 0, n - 1); };
  for (size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) tris[f][k] = m.vertex(m.triangles[3 * f + k]);
    const Eigen::Vector3d lo = tris[f][0].cwiseMin(tris[f][1]).cwiseMin(tris[f][2]);
    const Eigen::Vector3d hi = tris[f][0].cwiseMax(tris[f][1]).cwiseMax(tris[f][2]);
    box[f] = {idx(lo.x(), bb.min.x(), nx), idx(lo.y(), bb.min.y(), ny), idx(lo.z(), bb.min.z(), nz),
              idx(hi.x(), bb.min.x(), nx), idx(hi.y(), bb.min.y(), ny), idx(hi.z(), bb.min.z(), nz)};
    for (int z = box[f][2]; z <= box[f][5]; ++z)
      for (int y = box[f][1]; y <= box[f][4]; ++y)
        for (int x = box[f][0]; x <= box[f][3]; ++x)
          grid[(size_t(z) * ny + y) * nx + x].push_back(uint32_t(f));
  }
  const double eps = 1e-9 * std::max(1.0, ext.norm());
  std::vector<uint32_t> stamp(nf, UINT32_MAX);
  for (size_t f = 0; f < nf; ++f)
    for (int z = box[f][2]; z <= box[f][5]; ++z)
      for (int y = box[f][1]; y <= box[f][4]; ++y)
        for (int x = box[f][0]; x <= box[f][3]; ++x)
          for (uint32_t g : grid[(size_t(z) * ny + y) * nx + x]) {
            if (g <= f || stamp[g] == f) continue;
            stamp[g] = uint32_t(f);
            bool shared = false;
            for (int i = 0; i < 3; ++i)
              for (int j = 0; j < 3; ++j)
                shared = shared || m.triangles[3 * f + i] == m.triangles[3 * g + j];
            if (!shared && trianglesIntersect(tris[f], tris[g], eps)) return true;
          }
  return false;
}

}  // namespace

RemeshStats remeshIgdsRegion(const RemeshInput& in, const RemeshParams& params, LayerRegion& out,
                             const ProgressFn& progress, double progressAt) {
  RemeshStats stats;
  const double t0 = nowMs();
  Remesher r(in, params);
  r.liveFaces_ = in.triangles.size();
  if (!r.remesh(progress, progressAt)) {
    stats.cancelled = true;
    return stats;
  }
  const double t1 = nowMs();
  if (!r.smooth(progress, progressAt)) {
    stats.cancelled = true;
    return stats;
  }
  const double t2 = nowMs();
  stats.deviates = params.maxDeviation > 0 && r.centroidBeyond(params.maxDeviation);
  r.output(out);
  stats.selfIntersecting = selfIntersects(out.mesh, 2 * params.targetEdge);
  stats.remeshMs = t1 - t0;
  stats.smoothMs = t2 - t1;
  return stats;
}

}  // namespace omnislice
