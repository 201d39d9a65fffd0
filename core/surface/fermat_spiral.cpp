// SPDX-License-Identifier: MIT
// Connected Fermat spirals on a surface region (paper 001 Section 5.1, after the idea of Zhao et
// al. 2016), written from the idea:
//  1. boundary geodesic distance phi (heat method, boundary_distance.h);
//  2. iso-contours of phi at spacing/2 + k*step by marching triangles (step chosen near the spacing
//     so no ridge of the field sits just above a level, see fermat_spiral.h); each contour point lies
//     on a mesh edge, each contour segment inside one triangle. Contours are closed because phi
//     is 0 on the boundary and every level is > 0;
//  3. "pieces": connected components of the bands between consecutive levels (cells = the part of
//     a triangle inside one band, united across shared edges). Every contour separates two
//     pieces; on a planar-like region the bipartite graph pieces/contours is a tree. Pieces of the
//     lowest band touch the boundary and connect nothing (no path within spacing/2 of the edge);
//  4. chains: runs of contours joined by pieces bounded by exactly two contours (nested bands, and
//     the ridge cap of an annulus, which joins its outer and inner runs into one run). A chain is
//     oriented so the next contour lies on the left of each contour. Each chain becomes a Fermat
//     spiral: every contour is cut at a break point (the break points aligned along a cut line
//     made by successive closest points); even contours are run forward (in), odd contours
//     backward (out); the hops between contour k and k+2 pass through the gap of contour k+1 and
//     form two families of parallel diagonals, so in and out never cross. Both ends of a spiral
//     lie at its outer contour, one contour apart;
//  5. branches (pieces bounded by 3+ contours): the contours of the piece are joined by a minimum
//     spanning tree of their mutual distances, rooted at the contour we arrived by; each child
//     spiral is spliced into its host contour through a small gap at the host point closest to
//     the child (away from the other gaps of that host). So every component of {phi >= spacing/2}
//     yields ONE polyline; components separated by necks narrower than one bead yield one each;
//  6. hops are traced on the surface (closest points), the polyline is re-sampled at the output
//     step keeping corners (an original vertex is kept wherever the chord would cut the path by
//     more than 0.05 mm), normals are the normals of the triangles the points lie in (faces
//     oriented consistently by a breadth-first walk, majority orientation kept).
#include "surface/fermat_spiral.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "common/stopwatch.h"
#include "geometry/aabb_tree.h"
#include "mesh/mesh_topology.h"
#include "mesh/weld_vertices.h"
#include "surface/boundary_distance.h"
#include "surface/fermat_contours.h"

namespace omnislice {
namespace {

using namespace fermat_detail;

constexpr double kCornerTolerance = 0.05;  // mm: max chord deviation of the re-sampled path
constexpr int kMaxLevels = 20000;

// A point of an assembled path; tri = triangle containing the segment that arrives at this point
// (-1: a hop between contours, or the first point).
struct PathPoint {
  Eigen::Vector3d p;
  int tri = -1;
};

// A run of contours joined by pieces bounded by exactly two contours (step 4).
struct Chain {
  std::vector<int> contours;
};

// Uniform hash grid over the points of one contour: nearest point queries.
class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3d>& pts, double cell) : pts_(pts), cell_(cell) {
    for (size_t i = 0; i < pts.size(); ++i) cells_[key(pts[i])].push_back(static_cast<int>(i));
  }
  // Nearest point within ~cell (exact when the nearest is within one cell), else brute force.
  std::pair<double, int> nearest(const Eigen::Vector3d& q) const {
    double best = std::numeric_limits<double>::infinity();
    int idx = -1;
    const int64_t cx = coord(q.x()), cy = coord(q.y()), cz = coord(q.z());
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = cells_.find(pack(cx + dx, cy + dy, cz + dz));
          if (it == cells_.end()) continue;
          for (int i : it->second) {
            const double d = (pts_[i] - q).squaredNorm();
            if (d < best) {
              best = d;
              idx = i;
            }
          }
        }
    if (idx >= 0 && best <= cell_ * cell_) return {std::sqrt(best), idx};
    for (size_t i = 0; i < pts_.size(); ++i) {
      const double d = (pts_[i] - q).squaredNorm();
      if (d < best) {
        best = d;
        idx = static_cast<int>(i);
      }
    }
    return {std::sqrt(best), idx};
  }

 private:
  int64_t coord(double x) const { return static_cast<int64_t>(std::floor(x / cell_)); }
  static uint64_t pack(int64_t x, int64_t y, int64_t z) {
    return (static_cast<uint64_t>(x & 0x1FFFFF) << 42) | (static_cast<uint64_t>(y & 0x1FFFFF) << 21) |
           static_cast<uint64_t>(z & 0x1FFFFF);
  }
  uint64_t key(const Eigen::Vector3d& p) const { return pack(coord(p.x()), coord(p.y()), coord(p.z())); }
  std::vector<Eigen::Vector3d> pts_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<int>> cells_;
};

// Everything the construction shares.
struct Builder {
  const Mesh& mesh;
  const std::vector<double>& phi;
  const std::vector<Eigen::Vector3d>& faceNormal;
  const AabbTree& tree;
  double spacing;
  double hopStep;  // max length of a straight piece of a hop before it is projected
  std::vector<Contour> contours;
  std::vector<Chain> chains;

  // Gap half width of a contour: one bead (the two hop families then run 0.7 spacing apart),
  // less on short contours so something is left to print.
  double gapOf(const Contour& c) const { return std::min(spacing, c.length() / 8.0); }

  // from and to by value: from is usually out.back(), which push_back may move.
  void emitHop(const Eigen::Vector3d from, const Eigen::Vector3d to, std::vector<PathPoint>& out) const {
    const double len = (to - from).norm();
    const int pieces = static_cast<int>(std::ceil(len / hopStep));
    for (int i = 1; i < pieces; ++i) {
      const Eigen::Vector3d q = from + (to - from) * (static_cast<double>(i) / pieces);
      const ClosestPoint cp = tree.closest(q);
      out.push_back({cp.triangle >= 0 ? cp.point : q, -1});
    }
  }

  void appendPoint(const PathPoint& p, std::vector<PathPoint>& out) const {
    if (!out.empty() && p.tri < 0) emitHop(out.back().p, p.p, out);
    out.push_back(p);
  }

  // Plain arc without splices: from arc position s0 over len in direction dir.
  void emitPlain(const Contour& c, double s0, int dir, double len, std::vector<PathPoint>& out) const {
    const double L = c.length();
    size_t seg = 0;
    appendPoint({c.at(s0, &seg), -1}, out);
    if (len <= 0) return;
    const size_t n = c.size();
    // Walk vertex by vertex.
    double travelled = 0;
    double s = std::fmod(s0, L);
    if (s < 0) s += L;
    size_t i = seg;  // s lies on segment i: [cum[i], cum[i+1]]
    while (true) {
      double toNext;
      size_t vertex;
      if (dir > 0) {
        toNext = c.cum[i + 1] - s;
        vertex = (i + 1) % n;
      } else {
        toNext = s - c.cum[i];
        vertex = i;
      }
      if (travelled + toNext >= len) {
        const double rest = len - travelled;
        out.push_back({c.at(dir > 0 ? s + rest : s - rest), c.tri[i]});
        return;
      }
      travelled += toNext;
      out.push_back({c.pts[vertex], c.tri[i]});
      if (dir > 0) {
        i = (i + 1) % n;
        s = c.cum[i];
      } else {
        i = (i + n - 1) % n;
        s = c.cum[i + 1];
      }
    }
  }

  // Arc of contour ci from s0 over len in direction dir, detouring into spliced children.
  void emitArc(int ci, double s0, int dir, double len, std::vector<PathPoint>& out) const {
    const Contour& c = contours[ci];
    const double L = c.length();
    const double g = c.gap;
    std::vector<std::pair<double, const Splice*>> inside;
    for (const Splice& sp : c.splices) {
      double d = dir > 0 ? sp.pos - s0 : s0 - sp.pos;
      d = std::fmod(d, L);
      if (d < 0) d += L;
      if (d - g > 0 && d + g < len) inside.push_back({d, &sp});
    }
    std::sort(inside.begin(), inside.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    double cursor = 0;
    for (const auto& [d, sp] : inside) {
      emitPlain(c, s0 + dir * cursor, dir, d - g - cursor, out);
      std::vector<PathPoint> sub;
      emitChain(sp->chain, sub);
      if (dir * sp->side > 0) reversePath(sub);
      for (const PathPoint& p : sub) appendPoint(p, out);
      cursor = d + g;
    }
    emitPlain(c, s0 + dir * cursor, dir, len - cursor, out);
  }

  static void reversePath(std::vector<PathPoint>& path) {
    const size_t n = path.size();
    std::vector<PathPoint> r(n);
    for (size_t i = 0; i < n; ++i) {
      r[i].p = path[n - 1 - i].p;
      r[i].tri = i == 0 ? -1 : path[n - i].tri;
    }
    path.swap(r);
  }

  // The Fermat spiral of one chain: even contours forward (in), odd contours backward (out).
  void emitChain(int chainId, std::vector<PathPoint>& out) const {
    const Chain& ch = chains[chainId];
    const size_t n = ch.contours.size();
    for (size_t j = 0; j < n; j += 2) {
      const Contour& c = contours[ch.contours[j]];
      emitArc(ch.contours[j], c.breakPos + c.gap, +1, c.length() - 2 * c.gap, out);
    }
    const size_t lastOdd = n % 2 == 0 ? n - 1 : n - 2;
    for (size_t j = lastOdd; j < n && j >= 1; j -= 2) {
      const Contour& c = contours[ch.contours[j]];
      emitArc(ch.contours[j], c.breakPos - c.gap, -1, c.length() - 2 * c.gap, out);
      if (j == 1) break;
    }
  }
};

// Re-sample a path at step keeping corners; points on contour segments keep their triangle,
// points on hops are projected onto the surface.
SurfacePath resamplePath(const std::vector<PathPoint>& raw, double step, const AabbTree& tree,
                         const std::vector<Eigen::Vector3d>& faceNormal) {
  std::vector<PathPoint> pts;
  for (const PathPoint& p : raw) {
    if (!pts.empty() && (p.p - pts.back().p).squaredNorm() <= 1e-20) continue;
    pts.push_back(p);
  }
  SurfacePath out;
  if (pts.empty()) return out;
  const size_t n = pts.size();
  std::vector<double> cum(n, 0.0);
  for (size_t i = 1; i < n; ++i) cum[i] = cum[i - 1] + (pts[i].p - pts[i - 1].p).norm();
  auto emit = [&](const Eigen::Vector3d& p, int tri) {
    if (tri >= 0) {
      out.points.push_back(p);
      out.normals.push_back(faceNormal[tri]);
      return;
    }
    const ClosestPoint cp = tree.closest(p);
    if (cp.triangle >= 0) {
      out.points.push_back(cp.point);
      out.normals.push_back(faceNormal[cp.triangle]);
    } else {
      out.points.push_back(p);
      out.normals.push_back(Eigen::Vector3d(0, 0, 1));
    }
  };
  // Position at arc s (segment k from pts[k] to pts[k+1]).
  auto pointAt = [&](double s, size_t& k) {
    k = static_cast<size_t>(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin());
    k = std::min(std::max<size_t>(k, 1), n - 1) - 1;
    const double len = cum[k + 1] - cum[k];
    const double t = len > 0 ? (s - cum[k]) / len : 0.0;
    return Eigen::Vector3d(pts[k].p + t * (pts[k + 1].p - pts[k].p));
  };
  emit(pts[0].p, n > 1 ? pts[1].tri : -1);
  if (n == 1) return out;
  double s = 0;
  size_t lastVertex = 0;  // last original vertex at or before s
  Eigen::Vector3d last = pts[0].p;
  while (s < cum[n - 1] - 1e-12) {
    const double target = std::min(s + step, cum[n - 1]);
    size_t k;
    const Eigen::Vector3d cand = pointAt(target, k);
    // Original vertices strictly between s and target: lastVertex+1 .. k (cum < target).
    auto deviation = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, size_t from, size_t to) {
      double worst = 0;
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      for (size_t v = from; v <= to && v < n; ++v) {
        const double t = len2 > 0 ? std::clamp((pts[v].p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
        worst = std::max(worst, (a + t * ab - pts[v].p).norm());
      }
      return worst;
    };
    size_t firstInside = lastVertex + 1;
    while (firstInside < n && cum[firstInside] <= s + 1e-12) ++firstInside;
    size_t lastInside = firstInside;
    while (lastInside < n && cum[lastInside] < target - 1e-12) ++lastInside;
    // Vertices firstInside .. lastInside-1 lie strictly inside (s, target).
    if (lastInside == firstInside || deviation(last, cand, firstInside, lastInside - 1) <= kCornerTolerance) {
      emit(cand, pts[k + 1].tri);
      s = target;
      last = cand;
      lastVertex = (k + 1 < n && cum[k + 1] <= target + 1e-12) ? k + 1 : k;
      if (cum[lastVertex] > s) lastVertex = k;
      continue;
    }
    // Keep the farthest original vertex whose chord keeps every vertex in between in tolerance.
    size_t keep = firstInside;
    for (size_t v = firstInside + 1; v < lastInside; ++v) {
      if (deviation(last, pts[v].p, firstInside, v - 1) <= kCornerTolerance) keep = v;
      else break;
    }
    const int tri = pts[keep].tri >= 0 ? pts[keep].tri : (keep + 1 < n ? pts[keep + 1].tri : -1);
    emit(pts[keep].p, tri);
    s = cum[keep];
    last = pts[keep].p;
    lastVertex = keep;
  }
  return out;
}

// Fraction of points (every spacing/2 along the paths) that come closer than 0.6 spacing to a part
// of a path more than 2 spacing away along it: the self-overlap measure used to pick the levels.
// Points are sorted by a hash cell of twice the radius, so a query visits the 8 cells its ball
// can touch.
double selfOverlapFraction(const std::vector<std::vector<PathPoint>>& paths, double spacing) {
  std::vector<Eigen::Vector3d> pts;
  std::vector<double> arc;
  double offset = 0;
  const double step = spacing / 2;
  for (const auto& path : paths) {
    double a = offset;
    for (size_t i = 0; i + 1 < path.size(); ++i) {
      const double len = (path[i + 1].p - path[i].p).norm();
      const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
      for (int k = 0; k < n; ++k) {
        pts.push_back(path[i].p + (path[i + 1].p - path[i].p) * (static_cast<double>(k) / n));
        arc.push_back(a + len * k / n);
      }
      a += len;
    }
    offset = a + 1e9;
  }
  if (pts.empty()) return 0;
  const double r = 0.6 * spacing, cell = 2 * r;
  auto pack = [](int64_t x, int64_t y, int64_t z) {
    return (static_cast<uint64_t>(x & 0x1FFFFF) << 42) | (static_cast<uint64_t>(y & 0x1FFFFF) << 21) |
           static_cast<uint64_t>(z & 0x1FFFFF);
  };
  std::vector<std::pair<uint64_t, uint32_t>> keyed(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    keyed[i] = {pack(static_cast<int64_t>(std::floor(pts[i].x() / cell)),
                     static_cast<int64_t>(std::floor(pts[i].y() / cell)),
                     static_cast<int64_t>(std::floor(pts[i].z() / cell))),
                static_cast<uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> ranges;  // key -> [first, last)
  ranges.reserve(pts.size() / 2 + 16);
  for (size_t i = 0; i < keyed.size();) {
    size_t j = i;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    ranges[keyed[i].first] = {static_cast<uint32_t>(i), static_cast<uint32_t>(j)};
    i = j;
  }
  size_t bad = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    int64_t c[3], o[3];
    for (int k = 0; k < 3; ++k) {
      const double x = pts[i][k] / cell;
      c[k] = static_cast<int64_t>(std::floor(x));
      o[k] = x - static_cast<double>(c[k]) < 0.5 ? -1 : 1;
    }
    bool hit = false;
    for (int m = 0; m < 8 && !hit; ++m) {
      auto it = ranges.find(pack(c[0] + ((m & 1) ? o[0] : 0), c[1] + ((m & 2) ? o[1] : 0),
                                 c[2] + ((m & 4) ? o[2] : 0)));
      if (it == ranges.end()) continue;
      for (uint32_t q = it->second.first; q < it->second.second; ++q) {
        const uint32_t j = keyed[q].second;
        if (std::abs(arc[j] - arc[i]) > 2 * spacing && (pts[j] - pts[i]).squaredNorm() < r * r) {
          hit = true;
          break;
        }
      }
    }
    if (hit) ++bad;
  }
  return static_cast<double>(bad) / static_cast<double>(pts.size());
}

SpiralResult fail(Status s, std::string message) { return failed<SpiralResult>(s, std::move(message)); }

}  // namespace

namespace {

constexpr size_t kCoarseRegionVertices = 64;

// True when some vertex of a face lies on no boundary edge (an edge used by one face).
bool hasInteriorVertex(const Mesh& m) {
  const MeshEdges edges = buildEdges(m);
  std::vector<uint8_t> onBoundary(m.vertexCount(), 0);
  for (size_t e = 0; e < edges.edgeCount(); ++e)
    if (edges.faceCount[e] == 1) onBoundary[edges.keys[e] >> 32] = onBoundary[edges.keys[e] & 0xffffffffu] = 1;
  for (uint32_t v : m.triangles)
    if (!onBoundary[v]) return true;
  return false;
}

// Each triangle split into four at its edge midpoints (shared midpoints welded): the same surface.
Mesh subdivideMidpoints(const Mesh& m) {
  Mesh out;
  out.positions = m.positions;
  std::unordered_map<uint64_t, uint32_t> mid;
  auto midpoint = [&](uint32_t a, uint32_t b) {
    const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
    auto [it, fresh] = mid.try_emplace(key, uint32_t(out.vertexCount()));
    if (fresh)
      for (int d = 0; d < 3; ++d)
        out.positions.push_back(0.5 * (m.positions[3 * size_t(a) + d] + m.positions[3 * size_t(b) + d]));
    return it->second;
  };
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const uint32_t a = m.triangles[3 * f], b = m.triangles[3 * f + 1], c = m.triangles[3 * f + 2];
    const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    out.triangles.insert(out.triangles.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
  }
  return out;
}

// The options and region: InvalidOption when unusable.
Outcome checkSpiralInput(const Mesh& region, const SpiralOptions& options) {
  auto bad = [](std::string message) { return failed<Outcome>(Status::InvalidOption, std::move(message)); };
  if (!(options.spacing > 0) || !std::isfinite(options.spacing)) {
    return bad("fermat spiral: spacing must be finite and > 0");
  }
  if (!(options.resample > 0) || !std::isfinite(options.resample)) {
    return bad("fermat spiral: resample must be finite and > 0");
  }
  if (region.positions.size() % 3 != 0 || region.triangles.size() % 3 != 0) {
    return bad("fermat spiral: positions/triangles not multiples of 3");
  }
  for (uint32_t v : region.triangles) {
    if (v >= region.vertexCount()) return bad("fermat spiral: triangle index out of range");
  }
  return {};
}

// The region welded and, when coarse, subdivided.
Mesh weldedRegion(const Mesh& region) {
  // Weld bit-identical positions first: an unwelded region (one vertex per corner) would look
  // like loose triangles, all boundary, and yield no path.
  Mesh welded;
  {
    const WeldResult weld = weldVertices(region, 0);
    welded.positions = weld.positions;
    welded.triangles.reserve(region.triangles.size());
    for (uint32_t v : region.triangles) welded.triangles.push_back(weld.remap[v]);
  }
  // A coarse region (remeshed IGDS slivers of a dozen triangles, every vertex or all but one on
  // the boundary) cannot resolve its own width: its boundary distance came out near 0 (branches_16
  // at 30k tets: D 0.03-0.05 mm on 1.1-1.9 mm^2 slivers), it printed nothing and the layer above
  // read unsupported. Split its triangles at the edge midpoints (the same surface) while it has
  // fewer than 64 vertices or none inside, at most twice.
  for (int round = 0; round < 2 && welded.faceCount() > 0 &&
                      (welded.vertexCount() < kCoarseRegionVertices || !hasInteriorVertex(welded));
       ++round)
    welded = subdivideMidpoints(welded);
  return welded;
}

// Same cleaning as the distance: faces repeating a vertex are dropped.
Mesh withoutRepeatedVertices(const Mesh& welded) {
  Mesh mesh;
  mesh.positions = welded.positions;
  for (size_t f = 0; f < welded.faceCount(); ++f) {
    const uint32_t a = welded.triangles[3 * f], b = welded.triangles[3 * f + 1], c = welded.triangles[3 * f + 2];
    if (a != b && b != c && a != c) mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
  }
  return mesh;
}

// Mean edge length (hop tracing step).
double meanEdgeLength(const Mesh& mesh, const MeshEdges& edges) {
  double edgeSum = 0;
  for (size_t e = 0; e < edges.edgeCount(); ++e) {
    edgeSum += (mesh.vertex(edges.keys[e] >> 32) - mesh.vertex(edges.keys[e] & 0xFFFFFFFFu)).norm();
  }
  return edgeSum / static_cast<double>(std::max<size_t>(edges.edgeCount(), 1));
}

// Levels spacing/2 + k * step. The step is adjusted (within 15 %) so the last level lies
// spacing/2 below the highest ridge: a level just under a ridge plateau would break into
// specks around the field's noise and leave a loop thinner than one bead.
// Level step. Uniform levels sit at arbitrary heights under the ridges (medial axis) of the
// field; a ridge just above a level gives a loop thinner than half a bead folded on itself
// (or specks around the field's noise), a ridge far above the last level leaves a gap. Ridge
// vertices (|grad phi| < 0.5: the heat distance is smooth across the medial axis) score each
// candidate step in [0.85, 1.05] x spacing: area with the ridge less than 0.3 spacing above the
// level below it counts 1, more than 0.8 spacing above it 0.5. The lowest score wins, ties to
// the step closest to the spacing. Returns the candidate steps in rank order.
std::vector<double> candidateSteps(const Mesh& mesh, const std::vector<double>& phi, double s, double D) {
  std::vector<double> steps;
  std::vector<double> gradSum(mesh.vertexCount(), 0.0);
  std::vector<double> mass(mesh.vertexCount(), 0.0);
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const uint32_t i[3] = {mesh.triangles[3 * f], mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2]};
    const Eigen::Vector3d p0 = mesh.vertex(i[0]), p1 = mesh.vertex(i[1]), p2 = mesh.vertex(i[2]);
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
    const double twiceArea = n.norm();
    if (!(twiceArea > 0)) continue;
    const Eigen::Vector3d u = n / twiceArea;
    const Eigen::Vector3d g = (phi[i[0]] * u.cross(p2 - p1) + phi[i[1]] * u.cross(p0 - p2) +
                               phi[i[2]] * u.cross(p1 - p0)) / twiceArea;
    for (uint32_t v : i) {
      mass[v] += twiceArea / 6;
      gradSum[v] += g.norm() * twiceArea / 6;
    }
  }
  std::vector<std::pair<double, double>> ridge;  // (phi, mass)
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (mass[v] > 0 && gradSum[v] < 0.5 * mass[v] && phi[v] > s / 2) ridge.push_back({phi[v], mass[v]});
  }
  std::vector<std::pair<double, double>> scored;  // (score, step), stable: ties keep order
  for (const double factor : {1.0, 0.975, 1.025, 0.95, 1.05, 0.925, 0.9, 0.875, 0.85}) {
    const double t = factor * s;
    double score = 0;
    for (const auto& [value, m] : ridge) {
      const double above = std::fmod(value - s / 2, t);
      if (above < 0.3 * s) score += m;
      else if (above > 0.8 * s) score += 0.5 * m;
    }
    scored.push_back({score, t});
  }
  std::stable_sort(scored.begin(), scored.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first - 1e-12; });
  for (size_t i = 0; i < std::min<size_t>(2, scored.size()); ++i) steps.push_back(scored[i].second);
  // And the step putting the last level spacing/2 under the highest ridge.
  if (D - s > 0) {
    const double span = D - s;
    const double up = span / std::ceil(span / s);
    if (up >= 0.85 * s) steps.push_back(up);
  }
  return steps;
}

// What the contour paths are built on: the cleaned region, its edges, the boundary distance,
// the oriented face normals and an AABB tree.
struct SpiralSurface {
  const Mesh& mesh;
  const MeshEdges& edges;
  const std::vector<double>& phi;
  const std::vector<Eigen::Vector3d>& faceNormal;
  const AabbTree& tree;
};

// Narrow regions: each ridge loop cut at its two tips (farthest points), one side kept: a
// centre line.
void centreLines(const std::vector<Contour>& C, double s, std::vector<std::vector<PathPoint>>& raw) {
  for (const Contour& c : C) {
    if (c.length() < s / 2) continue;
    size_t a = 0, b = 0;
    for (size_t i = 0; i < c.size(); ++i) {
      if ((c.pts[i] - c.pts[0]).squaredNorm() > (c.pts[a] - c.pts[0]).squaredNorm()) a = i;
    }
    for (size_t i = 0; i < c.size(); ++i) {
      if ((c.pts[i] - c.pts[a]).squaredNorm() > (c.pts[b] - c.pts[a]).squaredNorm()) b = i;
    }
    std::vector<PathPoint> path;
    for (size_t i = a;; i = (i + 1) % c.size()) {
      path.push_back({c.pts[i], path.empty() ? -1 : c.tri[(i + c.size() - 1) % c.size()]});
      if (i == b) break;
    }
    raw.push_back(std::move(path));
  }
}

// Steps 4 and 5 of the file's comment: the contours joined into chains (Fermat spirals) and
// branches spliced into their hosts, one polyline per component.
class SpiralConnector {
 public:
  // Pieces and the contours bounding them; contours shorter than a bead are dropped.
  SpiralConnector(Builder& B, int pieces, const std::vector<int>& pieceBand, double s)
      : B_(B), C_(B.contours), pieceBand_(pieceBand), s_(s), pieceContours_(pieces), pieceUsed_(pieces, 0) {
    std::vector<Contour>& C = C_;
    for (size_t i = 0; i < C.size(); ++i) {
      if (C[i].length() < s) {
        C[i].dropped = true;  // a speck (diameter under one bead) around a bump of the field
        continue;
      }
      pieceContours_[C[i].lower].push_back(static_cast<int>(i));
      if (C[i].upper != C[i].lower) pieceContours_[C[i].upper].push_back(static_cast<int>(i));
    }
  }

  // Roots: one per component, the longest contour next to the boundary band first; each root's
  // chain with its branches spliced in becomes one path (plus the children no host had room for).
  void connect(std::vector<std::vector<PathPoint>>& raw) {
    while (true) {
      const int root = nextRoot();
      if (root < 0) break;
      const int back = C_[root].lower;  // the boundary side: the spiral starts at the outside
      const int chainId = buildChain(root, back);
      placeBreaks(chainId, 0.0);
      processBranches();
      std::vector<PathPoint> path;
      B_.emitChain(chainId, path);
      raw.push_back(std::move(path));
      for (const int extra : separateChains_) {
        std::vector<PathPoint> own;
        B_.emitChain(extra, own);
        raw.push_back(std::move(own));
      }
      separateChains_.clear();
    }
  }

 private:
  struct Branch {
    int piece;
    int entry;
  };

  bool isBottom(int piece) const { return pieceBand_[piece] == 0; }

  int nextRoot() const {
    const std::vector<Contour>& C = C_;
    int root = -1;
    for (size_t i = 0; i < C.size(); ++i) {
      if (C[i].dropped || C[i].chain >= 0) continue;
      const bool touches = isBottom(C[i].lower) || isBottom(C[i].upper);
      if (root < 0) {
        root = static_cast<int>(i);
        continue;
      }
      const bool rootTouches = isBottom(C[root].lower) || isBottom(C[root].upper);
      if ((touches && !rootTouches) || (touches == rootTouches && C[i].length() > C[root].length())) {
        root = static_cast<int>(i);
      }
    }
    return root;
  }

  // Build the chain starting at contour start coming from piece back; orient its contours.
  int buildChain(int start, int back) {
    std::vector<Contour>& C = C_;
    const int id = static_cast<int>(B_.chains.size());
    B_.chains.emplace_back();
    int cur = start;
    while (true) {
      Contour& c = C[cur];
      c.chain = id;
      B_.chains[id].contours.push_back(cur);
      const int fwd = c.lower == back ? c.upper : c.lower;
      c.forward = fwd;
      if (fwd == c.lower && c.lower != c.upper) c.reverse();  // forward piece on the left
      c.gap = B_.gapOf(c);
      if (isBottom(fwd) || pieceUsed_[fwd]) break;
      pieceUsed_[fwd] = 1;
      std::vector<int> others;
      for (int o : pieceContours_[fwd]) {
        if (o != cur && C[o].chain < 0) others.push_back(o);
      }
      if (others.empty()) break;
      if (others.size() == 1) {
        back = fwd;
        cur = others[0];
        continue;
      }
      branches_.push_back({fwd, cur});
      break;
    }
    return id;
  }

  // Cut line: break points by successive closest points from the first contour's break.
  void placeBreaks(int chainId, double firstBreak) {
    std::vector<Contour>& C = C_;
    const Chain& ch = B_.chains[chainId];
    C[ch.contours[0]].breakPos = firstBreak;
    for (size_t j = 1; j < ch.contours.size(); ++j) {
      const Contour& prev = C[ch.contours[j - 1]];
      C[ch.contours[j]].breakPos = C[ch.contours[j]].closestPosition(prev.at(prev.breakPos));
    }
  }

  // Splice point on host for a child: the host vertex closest to the child among those far
  // enough from the gaps already cut in the host (preferably two beads clear, at least so
  // the gaps do not overlap). -1 when the host has no room left.
  double chooseSplice(int host, const PointGrid& childGrid) const {
    const Contour& H = C_[host];
    const double s = s_;
    std::vector<double> cuts{H.breakPos};
    for (const Splice& sp : H.splices) cuts.push_back(sp.pos);
    for (const double clearance : {2 * H.gap + 2 * s, 2 * H.gap + 0.02 * s}) {
      double best = std::numeric_limits<double>::infinity();
      double pos = -1;
      for (size_t i = 0; i < H.size(); ++i) {
        bool free = true;
        for (double q : cuts) {
          double a = std::fmod(std::abs(H.cum[i] - q), H.length());
          a = std::min(a, H.length() - a);
          if (a < clearance) free = false;
        }
        if (!free) continue;
        const double d = childGrid.nearest(H.pts[i]).first;
        if (d < best) {
          best = d;
          pos = H.cum[i];
        }
      }
      if (pos >= 0) return pos;
    }
    return -1.0;
  }

  void processBranches() {
    while (!branches_.empty()) {
      const Branch br = branches_.front();
      branches_.pop_front();
      spliceBranch(br);
    }
  }

  // The contours of a branch piece joined by a minimum spanning tree of their distances (Prim,
  // from the entry contour); each new member's chain is spliced into its tree parent (or the
  // nearest member with room), or kept separate.
  void spliceBranch(const Branch& br) {
    std::vector<Contour>& C = C_;
    std::vector<int> members{br.entry};
    for (int o : pieceContours_[br.piece]) {
      if (o != br.entry && C[o].chain < 0) members.push_back(o);
    }
    const size_t m = members.size();
    std::vector<PointGrid> grids;
    grids.reserve(m);
    for (int c : members) grids.emplace_back(C[c].pts, 2 * s_);
    const std::vector<double> dist = memberDistances(members, grids);
    // Prim from the entry contour; each new member is spliced into its tree parent.
    std::vector<uint8_t> inTree(m, 0);
    std::vector<double> key(m, std::numeric_limits<double>::infinity());
    std::vector<size_t> parent(m, 0);
    inTree[0] = 1;
    for (size_t j = 1; j < m; ++j) key[j] = dist[j];
    for (size_t step = 1; step < m; ++step) {
      size_t next = 0;
      double bestKey = std::numeric_limits<double>::infinity();
      for (size_t j = 1; j < m; ++j) {
        if (!inTree[j] && key[j] <= bestKey) {
          bestKey = key[j];
          next = j;
        }
      }
      if (next == 0) break;
      inTree[next] = 1;
      // Host: the tree parent, or (when it has no room left, e.g. a short contour) the
      // nearest member already joined that has room.
      std::vector<size_t> hosts{parent[next]};
      for (size_t j = 0; j < m; ++j) {
        if (inTree[j] && j != next && j != parent[next]) hosts.push_back(j);
      }
      std::sort(hosts.begin() + 1, hosts.end(),
                [&](size_t x, size_t y) { return dist[next * m + x] < dist[next * m + y]; });
      int host = members[parent[next]];
      double q = -1;
      for (size_t j : hosts) {
        q = chooseSplice(members[j], grids[next]);
        if (q >= 0) {
          host = members[j];
          break;
        }
      }
      const int child = members[next];
      const int chainId = buildChain(child, br.piece);
      if (q < 0) {
        placeBreaks(chainId, 0.0);
        separateChains_.push_back(chainId);
      } else {
        // Child oriented now: its break is the point closest to the host's splice point.
        placeBreaks(chainId, C[child].closestPosition(C[host].at(q)));
        const int side = C[host].forward == br.piece ? 1 : -1;
        C[host].splices.push_back({q, chainId, side});
      }
      for (size_t j = 1; j < m; ++j) {
        if (!inTree[j] && dist[next * m + j] < key[j]) {
          key[j] = dist[next * m + j];
          parent[j] = next;
        }
      }
    }
  }

  // Pairwise contour distances (min over the points of the first), m x m.
  std::vector<double> memberDistances(const std::vector<int>& members, const std::vector<PointGrid>& grids) const {
    const std::vector<Contour>& C = C_;
    const size_t m = members.size();
    std::vector<double> dist(m * m, std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < m; ++i) {
      for (size_t j = i + 1; j < m; ++j) {
        double d = std::numeric_limits<double>::infinity();
        const Contour& a = C[members[i]].size() <= C[members[j]].size() ? C[members[i]] : C[members[j]];
        const PointGrid& g = C[members[i]].size() <= C[members[j]].size() ? grids[j] : grids[i];
        for (const Eigen::Vector3d& p : a.pts) d = std::min(d, g.nearest(p).first);
        dist[i * m + j] = dist[j * m + i] = d;
      }
    }
    return dist;
  }

  Builder& B_;
  std::vector<Contour>& C_;
  const std::vector<int>& pieceBand_;
  double s_;
  std::vector<std::vector<int>> pieceContours_;
  std::vector<uint8_t> pieceUsed_;
  std::deque<Branch> branches_;
  std::vector<int> separateChains_;  // children no host had room for: their own polylines
};

// Contours at levels, connected into paths (raw): centre lines when narrow, else spirals.
// Returns the number of contours; adds the contour extraction's time to contourMs.
int contourPaths(const SpiralSurface& surf, const std::vector<double>& levels, bool narrow, double s, double h,
                 double& contourMs, std::vector<std::vector<PathPoint>>& raw) {
  const auto tc = Clock::now();
  ContourSet set = extractContours(surf.mesh, surf.edges, surf.phi, levels);
  for (Contour& c : set.contours) orientUpLeft(c, surf.mesh, surf.phi, surf.faceNormal);
  const int count = static_cast<int>(set.contours.size());
  contourMs += msSince(tc);
  Builder B{surf.mesh, surf.phi, surf.faceNormal, surf.tree, s, std::max(0.25 * s, 0.5 * h),
            std::move(set.contours), {}};
  if (narrow) {
    centreLines(B.contours, s, raw);
  } else {
    SpiralConnector connector(B, set.pieces, set.pieceBand, s);
    connector.connect(raw);
  }
  return count;
}

// Build the candidates in rank order; keep the one whose path overlaps itself least (fewest
// polylines first), stopping at the first that is clearly fine. Its contour count goes to
// result.contours.
void bestSpiral(const SpiralSurface& surf, const std::vector<double>& steps, double s, double h, double D,
                SpiralResult& result, std::vector<std::vector<PathPoint>>& raw) {
  double bestScore = std::numeric_limits<double>::infinity();
  for (size_t c = 0; c < steps.size(); ++c) {
    bool seen = false;
    for (size_t d = 0; d < c; ++d) seen = seen || std::abs(steps[d] - steps[c]) < 1e-9 * s;
    if (seen) continue;
    std::vector<double> levels;
    for (int k = 0;; ++k) {
      const double v = s / 2 + k * steps[c];
      if (v >= D - 1e-9 * s) break;
      levels.push_back(v);
    }
    std::vector<std::vector<PathPoint>> candidate;
    const int count = contourPaths(surf, levels, false, s, h, result.contourMs, candidate);
    const double score = selfOverlapFraction(candidate, s) + 0.01 * static_cast<double>(candidate.size());
    if (score < bestScore) {
      bestScore = score;
      raw.swap(candidate);
      result.contours = count;
    }
    if (bestScore < 0.015) break;  // one polyline, under 0.5 % overlap: good enough, stop early
  }
}

}  // namespace

SpiralResult fermatSpiralPaths(const Mesh& region, const SpiralOptions& options) {
  const Outcome input = checkSpiralInput(region, options);
  if (!input.ok()) return fail(input.status, input.message);
  const auto t0 = Clock::now();
  const Mesh welded = weldedRegion(region);
  BoundaryDistanceOptions dopt;
  dopt.timeFactor = options.timeFactor;
  dopt.boundaryCondition = options.heatBoundary;
  const BoundaryDistance dist = boundaryGeodesicDistance(welded, dopt);
  if (!dist.ok()) {
    SpiralResult r;
    r.status = dist.status;
    r.message = "fermat spiral: " + dist.message;
    return r;
  }
  SpiralResult result;
  result.distanceMs = msSince(t0);
  const auto t1 = Clock::now();
  const Mesh mesh = withoutRepeatedVertices(welded);
  const MeshEdges edges = buildEdges(mesh);
  const std::vector<Eigen::Vector3d> faceNormal = orientedFaceNormals(mesh, edges);
  const std::vector<double>& phi = dist.distance;
  const double s = options.spacing;
  const double D = dist.maxDistance;
  if (D / s > kMaxLevels) {
    return fail(Status::InvalidOption, "fermat spiral: spacing too small for the region (too many contours)");
  }
  const double h = meanEdgeLength(mesh, edges);
  const std::vector<double> steps = candidateSteps(mesh, phi, s, D);
  // Narrower than about 1.5 beads (a single level would give a loop thinner than half a bead):
  // one centre line instead, as wide as the region (up to a bead). Slivers down to an eighth of a
  // bead are printed: a layer region left out leaves the region above it two layers over the
  // last printed one (a split front entering a side branch starts as such a sliver).
  const bool narrow = D < 0.75 * s;
  if (narrow && !(D > s / 16)) {
    result.contourMs = msSince(t1);
    return result;  // narrower than an eighth of a bead: nothing to print
  }
  const AabbTree tree(mesh);
  const SpiralSurface surf{mesh, edges, phi, faceNormal, tree};
  std::vector<std::vector<PathPoint>> raw;
  if (narrow) {
    // A thin loop around the ridge, collapsed to one side.
    result.contours = contourPaths(surf, {0.8 * D}, true, s, h, result.contourMs, raw);
  } else {
    bestSpiral(surf, steps, s, h, D, result, raw);
  }

  double rawLength = 0;
  for (const auto& path : raw) {
    for (size_t i = 1; i < path.size(); ++i) rawLength += (path[i].p - path[i - 1].p).norm();
  }
  if (rawLength / options.resample > 5e7) {
    return fail(Status::InvalidOption, "fermat spiral: resample step too small for the path length");
  }
  for (const auto& path : raw) {
    // 1 % short of the step: projecting hop points onto the surface may lengthen a step slightly.
    SurfacePath sp = resamplePath(path, 0.99 * options.resample, tree, faceNormal);
    if (narrow) sp.width = std::min(s, 2 * D);
    if (sp.points.size() >= 2) result.paths.push_back(std::move(sp));
  }
  result.connectMs = msSince(t1) - result.contourMs;
  return result;
}

}  // namespace omnislice
