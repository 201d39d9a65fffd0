// SPDX-License-Identifier: MIT
#include "geometry/triangulate_polygons.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace omnislice {
namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;

struct P2 {
  double x = 0, y = 0;
};

inline bool samePos(const P2& a, const P2& b) { return a.x == b.x && a.y == b.y; }
inline uint64_t edgeKey(uint32_t a, uint32_t b) {
  return a < b ? uint64_t(a) << 32 | b : uint64_t(b) << 32 | a;
}
// Twice the signed area of (a, b, c): > 0 when counter-clockwise.
inline double orient(const P2& a, const P2& b, const P2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}
inline double crossDir(double ux, double uy, double vx, double vy) { return ux * vy - uy * vx; }

// One vertex of the working polygon (a circular doubly linked list).
struct Node {
  P2 p;
  uint32_t id = 0;  // point index
  uint32_t prev = 0, next = 0;
  bool removed = false;
};

// Signed area (x2) of a loop, relative to its first point to limit cancellation.
double loopArea2(const std::vector<P2>& pts, const std::vector<uint32_t>& loop) {
  const P2 o = pts[loop[0]];
  double s = 0;
  for (size_t i = 1; i + 1 < loop.size(); ++i) {
    const P2& a = pts[loop[i]];
    const P2& b = pts[loop[i + 1]];
    s += (a.x - o.x) * (b.y - o.y) - (b.x - o.x) * (a.y - o.y);
  }
  return s;
}

struct Box2 {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -x0, y1 = -x0;
  void add(const P2& p) {
    x0 = std::min(x0, p.x);
    y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x);
    y1 = std::max(y1, p.y);
  }
  bool contains(const Box2& b) const {
    return b.x0 >= x0 && b.x1 <= x1 && b.y0 >= y0 && b.y1 <= y1;
  }
};

// Point in loop by winding number: +1 inside, 0 outside, -1 on an edge (inconclusive).
int pointInLoop(const std::vector<P2>& pts, const std::vector<uint32_t>& loop, const P2& q) {
  int winding = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const P2& a = pts[loop[i]];
    const P2& b = pts[loop[(i + 1) % loop.size()]];
    const double o = orient(a, b, q);
    if (o == 0 && q.x >= std::min(a.x, b.x) && q.x <= std::max(a.x, b.x) &&
        q.y >= std::min(a.y, b.y) && q.y <= std::max(a.y, b.y)) {
      return -1;
    }
    if (a.y <= q.y) {
      if (b.y > q.y && o > 0) ++winding;
    } else if (b.y <= q.y && o < 0) {
      --winding;
    }
  }
  return winding != 0 ? 1 : 0;
}

// Does segment [p, q] meet segment [u, v] anywhere? (Closed segments; collinear overlaps count.)
bool segmentsMeet(const P2& p, const P2& q, const P2& u, const P2& v) {
  const double o1 = orient(p, q, u), o2 = orient(p, q, v);
  const double o3 = orient(u, v, p), o4 = orient(u, v, q);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) {
    return true;
  }
  auto onSegment = [](const P2& a, const P2& b, const P2& c) {  // c on [a, b], given collinear
    return c.x >= std::min(a.x, b.x) && c.x <= std::max(a.x, b.x) && c.y >= std::min(a.y, b.y) &&
           c.y <= std::max(a.y, b.y);
  };
  return (o1 == 0 && onSegment(p, q, u)) || (o2 == 0 && onSegment(p, q, v)) ||
         (o3 == 0 && onSegment(u, v, p)) || (o4 == 0 && onSegment(u, v, q));
}

// Does edge [u, v] get in the way of a bridge [a, b]: crossing it, or an end of it lying on the
// bridge's interior up to tol (a bridge along a line through other vertices would overlap their
// edges)? Edges meeting the bridge only at a or b (by position) do not count.
bool bridgeHits(const P2& a, const P2& b, const P2& u, const P2& v, double tol) {
  const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  auto onInterior = [&](const P2& p) {
    if (samePos(p, a) || samePos(p, b) || !(len2 > 0)) return false;
    const double t = ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2;
    return t > 0 && t < 1 &&
           std::abs(crossDir(dx, dy, p.x - a.x, p.y - a.y)) <= tol * std::sqrt(len2);
  };
  if (onInterior(u) || onInterior(v)) return true;
  if (samePos(u, a) || samePos(u, b) || samePos(v, a) || samePos(v, b)) return false;
  return segmentsMeet(a, b, u, v);
}

// Ear clipping of one polygon (an outer contour with its holes bridged in).
class Polygon {
 public:
  std::vector<Node> nodes;
  double tol = 0;  // distance below which a vertex counts as on a bridge (1e-12 x extent)

  uint32_t addLoop(const std::vector<P2>& pts, const std::vector<uint32_t>& loop) {
    const uint32_t first = static_cast<uint32_t>(nodes.size());
    const uint32_t n = static_cast<uint32_t>(loop.size());
    for (uint32_t i = 0; i < n; ++i) {
      Node node;
      node.p = pts[loop[i]];
      node.id = loop[i];
      node.prev = first + (i + n - 1) % n;
      node.next = first + (i + 1) % n;
      nodes.push_back(node);
    }
    return first;
  }

  // Is the direction from node a towards point b inside the polygon's interior wedge at a? The
  // interior lies on the left of the edges, from a->next counter-clockwise round to a->prev.
  bool locallyInside(uint32_t a, const P2& b) const {
    const P2& pa = nodes[a].p;
    const P2& pn = nodes[nodes[a].next].p;
    const P2& pp = nodes[nodes[a].prev].p;
    const double nx = pn.x - pa.x, ny = pn.y - pa.y, px = pp.x - pa.x, py = pp.y - pa.y;
    const double dx = b.x - pa.x, dy = b.y - pa.y;
    if (crossDir(nx, ny, px, py) >= 0) {
      return crossDir(nx, ny, dx, dy) > 0 && crossDir(dx, dy, px, py) > 0;
    }
    return !(crossDir(px, py, dx, dy) >= 0 && crossDir(dx, dy, nx, ny) >= 0);
  }

  // Does any edge of the cycle through start get in the way of the bridge [a, b] (bridgeHits)?
  bool segmentBlocked(const P2& a, const P2& b, uint32_t start) const {
    const double x0 = std::min(a.x, b.x) - tol, x1 = std::max(a.x, b.x) + tol;
    const double y0 = std::min(a.y, b.y) - tol, y1 = std::max(a.y, b.y) + tol;
    uint32_t u = start;
    do {
      const uint32_t v = nodes[u].next;
      const P2& pu = nodes[u].p;
      const P2& pv = nodes[v].p;
      const bool apart = std::max(pu.x, pv.x) < x0 || std::min(pu.x, pv.x) > x1 ||
                         std::max(pu.y, pv.y) < y0 || std::min(pu.y, pv.y) > y1;
      if (!apart && bridgeHits(a, b, pu, pv, tol)) return true;
      u = v;
    } while (u != start);
    return false;
  }

  // Splice the hole cycle starting at node h into the polygon after node c, through a bridge
  // c -> h ... h' -> c' (duplicated nodes), or, when h and c are the same point (the hole touches
  // the contour), c -> h.next ... h -> c' without a bridge edge.
  void splice(uint32_t c, uint32_t h, bool touching) {
    const uint32_t cNext = nodes[c].next;
    const uint32_t hPrev = nodes[h].prev;
    if (touching) {
      // c -> h.next ... h.prev -> h (standing for the second visit of c) -> cNext.
      const uint32_t hNext = nodes[h].next;
      nodes[c].next = hNext;
      nodes[hNext].prev = c;
      nodes[h].next = cNext;
      nodes[cNext].prev = h;
      return;
    }
    const Node cDup = nodes[c], hDup = nodes[h];
    const uint32_t cd = static_cast<uint32_t>(nodes.size());
    const uint32_t hd = cd + 1;
    nodes.push_back(cDup);
    nodes.push_back(hDup);
    // c -> h -> ... -> hPrev -> hd -> cd -> cNext
    nodes[c].next = h;
    nodes[h].prev = c;
    nodes[hPrev].next = hd;
    nodes[hd].prev = hPrev;
    nodes[hd].next = cd;
    nodes[cd].prev = hd;
    nodes[cd].next = cNext;
    nodes[cNext].prev = cd;
  }

  // Bridge target for the hole whose rightmost node is m (the hole lies inside the cycle through
  // start): the classic ray cast to +x, the hit edge's endpoint of larger x, or the vertex inside
  // the triangle (m, hit, endpoint) making the smallest angle with the ray. kNone when nothing
  // valid is found.
  uint32_t findBridge(uint32_t m, uint32_t start) const {
    const P2 hm = nodes[m].p;
    double bestX = std::numeric_limits<double>::infinity();
    uint32_t hit = kNone;
    uint32_t u = start;
    do {
      const uint32_t v = nodes[u].next;
      const P2& a = nodes[u].p;
      const P2& b = nodes[v].p;
      // The region lies left of every edge, so a ray to +x leaves it through an edge going up.
      if (a.y <= hm.y && b.y >= hm.y && b.y > a.y) {
        const double x = a.y == hm.y   ? a.x
                         : b.y == hm.y ? b.x
                                       : a.x + (hm.y - a.y) * (b.x - a.x) / (b.y - a.y);
        if (x >= hm.x && x < bestX) {
          bestX = x;
          hit = a.y == hm.y ? u : b.y == hm.y ? v : (a.x >= b.x ? u : v);
          if (x == hm.x) break;
        }
      }
      u = v;
    } while (u != start);
    if (hit == kNone) return kNone;
    const P2 hitPoint{bestX, hm.y};
    const P2 c = nodes[hit].p;
    if (samePos(c, hitPoint)) return hit;
    // Vertices inside the triangle (hm, hitPoint, c) hide c; take the one closest in angle to the
    // ray (ties: the nearest).
    auto tangent = [&](const P2& r) {
      const double dx = r.x - hm.x;
      return dx > 0 ? std::abs(r.y - hm.y) / dx : std::numeric_limits<double>::infinity();
    };
    uint32_t best = hit;
    double bestTan = tangent(c);
    double bestDist = (c.x - hm.x) * (c.x - hm.x) + (c.y - hm.y) * (c.y - hm.y);
    const bool up = c.y > hm.y;
    const P2 t0 = up ? hm : hitPoint, t1 = up ? hitPoint : hm;  // (t0, t1, c) counter-clockwise
    u = start;
    do {
      const P2& r = nodes[u].p;
      if (u != hit && r.x >= hm.x && orient(t0, t1, r) >= 0 && orient(t1, c, r) >= 0 &&
          orient(c, t0, r) >= 0 && !samePos(r, hm)) {
        const double dx = r.x - hm.x, dy = r.y - hm.y;
        const double tan = tangent(r);
        const double dist = dx * dx + dy * dy;
        if ((tan < bestTan || (tan == bestTan && dist < bestDist)) && locallyInside(u, hm)) {
          best = u;
          bestTan = tan;
          bestDist = dist;
        }
      }
      u = nodes[u].next;
    } while (u != start);
    return best;
  }
};

// Uniform grid over the nodes of a polygon for the "is any vertex inside this ear" queries.
class NodeGrid {
 public:
  NodeGrid(const std::vector<Node>& nodes, uint32_t start) {
    Box2 box;
    size_t n = 0;
    uint32_t u = start;
    do {
      box.add(nodes[u].p);
      ++n;
      u = nodes[u].next;
    } while (u != start);
    x0_ = box.x0;
    y0_ = box.y0;
    const double w = std::max(box.x1 - box.x0, 0.0), h = std::max(box.y1 - box.y0, 0.0);
    extent_ = std::hypot(w, h);
    const double cellsWanted = std::max<double>(1, static_cast<double>(n) / 2);
    double cell = std::sqrt(std::max(w * h, 0.0) / cellsWanted);
    if (!(cell > 0)) cell = std::max(w, h) / cellsWanted;
    if (!(cell > 0) || !std::isfinite(cell)) cell = 1;
    inv_ = 1 / cell;
    nx_ = static_cast<int>(std::min(4096.0, std::floor(w * inv_) + 1));
    ny_ = static_cast<int>(std::min(4096.0, std::floor(h * inv_) + 1));
    start_.assign(static_cast<size_t>(nx_) * ny_ + 1, 0);
    u = start;
    do {
      ++start_[cellOf(nodes[u].p) + 1];
      u = nodes[u].next;
    } while (u != start);
    for (size_t i = 1; i < start_.size(); ++i) start_[i] += start_[i - 1];
    items_.resize(n);
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    u = start;
    do {
      items_[fill[cellOf(nodes[u].p)]++] = u;
      u = nodes[u].next;
    } while (u != start);
  }

  double extent() const { return extent_; }  // diagonal of the nodes' bounding box

  // Calls fn(node) for the nodes in the cells overlapping [x0,x1]x[y0,y1]; stops when fn is true.
  template <class Fn>
  bool any(double x0, double y0, double x1, double y1, Fn&& fn) const {
    const int i0 = clampX(x0), i1 = clampX(x1), j0 = clampY(y0), j1 = clampY(y1);
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const size_t c = static_cast<size_t>(j) * nx_ + i;
        for (uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
          if (fn(items_[k])) return true;
        }
      }
    }
    return false;
  }

 private:
  int clampX(double x) const {
    const double f = std::floor((x - x0_) * inv_);
    return static_cast<int>(std::clamp(f, 0.0, double(nx_ - 1)));
  }
  int clampY(double y) const {
    const double f = std::floor((y - y0_) * inv_);
    return static_cast<int>(std::clamp(f, 0.0, double(ny_ - 1)));
  }
  size_t cellOf(const P2& p) const { return static_cast<size_t>(clampY(p.y)) * nx_ + clampX(p.x); }

  double x0_ = 0, y0_ = 0, inv_ = 1, extent_ = 0;
  int nx_ = 1, ny_ = 1;
  std::vector<uint32_t> start_;
  std::vector<uint32_t> items_;
};

// Does the edge of node r leaving towards q enter the open corner of a triangle at point o, the
// corner spanning counter-clockwise from direction o->from to o->to?
inline bool entersCorner(const P2& o, const P2& from, const P2& to, const P2& q) {
  const double dx = q.x - o.x, dy = q.y - o.y;
  return crossDir(from.x - o.x, from.y - o.y, dx, dy) > 0 &&
         crossDir(dx, dy, to.x - o.x, to.y - o.y) > 0;
}

class EarClipper {
 public:
  EarClipper(std::vector<Node>& nodes, uint32_t start, double minArea2,
             const std::vector<uint64_t>& avoid, std::vector<uint32_t>& out, size_t& forced)
      : n_(nodes),
        start_(start),
        minArea2_(minArea2),
        avoid_(avoid),
        out_(out),
        forced_(forced),
        grid_(nodes, start) {}

  void run() {
    size_t count = 0;
    uint32_t u = start_;
    do {
      ++count;
      u = n_[u].next;
    } while (u != start_);
    uint32_t ear = start_;
    uint32_t stop = ear;
    int level = 0;
    while (count > 3) {
      const uint32_t a = n_[ear].prev, c = n_[ear].next;
      if (n_[a].id == n_[c].id || n_[a].id == n_[ear].id) {
        // A spike a -> ear -> a (the polygon pinched at a point, its part on one side done), or a
        // zero-length edge: the two edges pair with each other, no triangle. Drop ear and c.
        const uint32_t d = n_[c].next;
        n_[a].next = d;
        n_[d].prev = a;
        n_[ear].removed = n_[c].removed = true;
        count -= 2;
        ear = stop = a;
        level = 0;
        continue;
      }
      if (isEar(a, ear, c, level)) {
        clip(a, ear, c);
        --count;
        level = 0;
        // Skip one node: clipping every other vertex per round keeps the triangles local (going on
        // at c would fan out from a, with ever larger triangles to test).
        ear = stop = n_[dropSpikes(c, count)].next;
        continue;
      }
      ear = c;
      if (ear == stop) {
        ++level;
        if (level >= 3) {
          // No valid ear anywhere: cut the most convex corner so that the loop still closes.
          const uint32_t b = mostConvex(ear);
          const uint32_t c = n_[b].next;
          clip(n_[b].prev, b, c);
          ++forced_;
          --count;
          level = 0;
          ear = dropSpikes(c, count);
        }
        stop = ear;
      }
    }
    if (count < 3) return;  // two nodes left: their two edges pair up
    const uint32_t a = n_[ear].prev, c = n_[ear].next;
    if (n_[a].id == n_[c].id || n_[a].id == n_[ear].id || n_[ear].id == n_[c].id) return;
    if (!(orient(n_[a].p, n_[ear].p, n_[c].p) > 0)) ++forced_;
    emit(a, ear, c);
  }

 private:
  void emit(uint32_t a, uint32_t b, uint32_t c) {
    out_.insert(out_.end(), {n_[a].id, n_[b].id, n_[c].id});
  }
  void clip(uint32_t a, uint32_t b, uint32_t c) {
    emit(a, b, c);
    n_[a].next = c;
    n_[c].prev = a;
    n_[b].removed = true;
  }

  // Once a part of the polygon pinched off at a point is done, what is left of it is a spike
  // x -> v -> x' (x and x' the same point index): its two edges pair with each other, so v and
  // x' go without a triangle. Checks round u after a change there; returns a node still in use.
  uint32_t dropSpikes(uint32_t u, size_t& count) {
    for (bool again = true; again && count > 3;) {
      again = false;
      for (uint32_t v : {n_[u].prev, u, n_[u].next}) {
        const uint32_t a = n_[v].prev, c = n_[v].next;
        if (n_[a].id != n_[c].id) continue;
        const uint32_t d = n_[c].next;
        n_[a].next = d;
        n_[d].prev = a;
        n_[v].removed = n_[c].removed = true;
        count -= 2;
        u = a;
        again = true;
        break;
      }
    }
    return u;
  }

  uint32_t mostConvex(uint32_t start) const {
    uint32_t best = start;
    double bestScore = -std::numeric_limits<double>::infinity();
    uint32_t u = start;
    do {
      const P2& a = n_[n_[u].prev].p;
      const P2& b = n_[u].p;
      const P2& c = n_[n_[u].next].p;
      const double lab = std::hypot(b.x - a.x, b.y - a.y), lbc = std::hypot(c.x - b.x, c.y - b.y);
      // A zero-length edge or a spike is the cheapest thing to cut.
      const double score = lab > 0 && lbc > 0 ? orient(a, b, c) / (lab * lbc) : 2.0;
      if (score > bestScore) {
        bestScore = score;
        best = u;
      }
      u = n_[u].next;
    } while (u != start);
    return best;
  }

  // level 0: a clearly convex corner (sine of the turn above 1e-12, area above minArea), and no
  // vertex within 1e-12 of the polygon's extent outside the new diagonal c-a either (a vertex on
  // the diagonal up to rounding would leave a T-junction or a zero-area triangle for later);
  // level 1: any convex corner, exact tests; level 2: the same, allowing options.avoidEdges as
  // the new diagonal. Always: no other vertex in the closed triangle, and no edge leaving a vertex
  // at the same point as a corner entering the triangle (bridges, touching loops). Spikes and
  // repeated points never reach the forced cut (level 3): every pass drops them first, so a
  // forced triangle has three distinct points.
  bool isEar(uint32_t ia, uint32_t ib, uint32_t ic, int level) const {
    const P2 &a = n_[ia].p, &b = n_[ib].p, &c = n_[ic].p;
    const double o = orient(a, b, c);
    if (!(o > 0)) return false;
    if (level < 2 && !avoid_.empty() &&
        std::binary_search(avoid_.begin(), avoid_.end(), edgeKey(n_[ia].id, n_[ic].id))) {
      return false;
    }
    double slack = 0;  // how far outside the diagonal a vertex still blocks (as an orient value)
    if (level == 0) {
      const double lab = std::hypot(b.x - a.x, b.y - a.y), lbc = std::hypot(c.x - b.x, c.y - b.y);
      if (!(o > 1e-12 * lab * lbc) || !(o > minArea2_)) return false;
      slack = 1e-12 * grid_.extent() * std::hypot(c.x - a.x, c.y - a.y);
    }
    const double pad = level == 0 ? 1e-12 * grid_.extent() : 0;
    const double x0 = std::min({a.x, b.x, c.x}) - pad, x1 = std::max({a.x, b.x, c.x}) + pad;
    const double y0 = std::min({a.y, b.y, c.y}) - pad, y1 = std::max({a.y, b.y, c.y}) + pad;
    return !grid_.any(x0, y0, x1, y1, [&](uint32_t r) {
      if (r == ia || r == ib || r == ic || n_[r].removed) return false;
      const P2& p = n_[r].p;
      if (p.x < x0 || p.x > x1 || p.y < y0 || p.y > y1) return false;
      const P2& pp = n_[n_[r].prev].p;
      const P2& pn = n_[n_[r].next].p;
      if (samePos(p, a)) return entersCorner(a, b, c, pp) || entersCorner(a, b, c, pn);
      if (samePos(p, b)) return entersCorner(b, c, a, pp) || entersCorner(b, c, a, pn);
      if (samePos(p, c)) return entersCorner(c, a, b, pp) || entersCorner(c, a, b, pn);
      return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= -slack;
    });
  }

  std::vector<Node>& n_;
  uint32_t start_;
  double minArea2_;                     // twice options.minArea
  const std::vector<uint64_t>& avoid_;  // sorted edgeKey of options.avoidEdges
  std::vector<uint32_t>& out_;
  size_t& forced_;
  NodeGrid grid_;
};

struct LoopInfo {
  double area2 = 0;
  Box2 box;
  uint32_t rightmost = 0;  // position in the loop of the point of largest x (then smallest y)
};

}  // namespace

PolygonTriangulation triangulatePolygons(const std::vector<Eigen::Vector2d>& points,
                                         const std::vector<std::vector<uint32_t>>& loops,
                                         const TriangulateOptions& options) {
  PolygonTriangulation result;
  if (!(options.minArea >= 0) || !std::isfinite(options.minArea)) {
    result.status = Status::InvalidOption;
    result.message = "minArea must be finite and >= 0";
    return result;
  }
  std::vector<P2> pts(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i].x()) || !std::isfinite(points[i].y())) {
      result.status = Status::InvalidOption;
      result.message = "point " + std::to_string(i) + " is not finite";
      return result;
    }
    pts[i] = {points[i].x(), points[i].y()};
  }
  for (size_t l = 0; l < loops.size(); ++l) {
    for (uint32_t id : loops[l]) {
      if (id >= pts.size()) {
        result.status = Status::InvalidOption;
        result.message = "loop " + std::to_string(l) + " refers to point " + std::to_string(id) +
                         " of " + std::to_string(pts.size());
        return result;
      }
    }
  }

  std::vector<uint64_t> avoid;
  for (const auto& e : options.avoidEdges) avoid.push_back(edgeKey(e[0], e[1]));
  std::sort(avoid.begin(), avoid.end());

  std::vector<LoopInfo> info(loops.size());
  std::vector<uint32_t> outers, holes;
  for (uint32_t l = 0; l < loops.size(); ++l) {
    const std::vector<uint32_t>& loop = loops[l];
    if (loop.size() < 3) {
      ++result.skippedLoops;
      continue;
    }
    LoopInfo& li = info[l];
    li.area2 = loopArea2(pts, loop);
    for (uint32_t i = 0; i < loop.size(); ++i) {
      const P2& p = pts[loop[i]];
      li.box.add(p);
      const P2& r = pts[loop[li.rightmost]];
      if (p.x > r.x || (p.x == r.x && p.y < r.y)) li.rightmost = i;
    }
    (li.area2 >= 0 ? outers : holes).push_back(l);
  }
  result.outerLoops = outers.size();

  // Each hole goes to the smallest outer loop that contains it (islands inside holes are outer
  // loops of their own). The test point is a hole vertex that is not a vertex of the candidate
  // (loops may touch); a majority of up to three conclusive winding tests decides.
  std::stable_sort(outers.begin(), outers.end(),
                   [&](uint32_t a, uint32_t b) { return info[a].area2 < info[b].area2; });
  std::vector<uint32_t> stamp(pts.size(), kNone);
  std::vector<std::vector<uint32_t>> holesOf(loops.size());
  std::vector<uint32_t> orphans;
  std::vector<uint32_t> candidates;
  for (uint32_t h : holes) {
    uint32_t parent = kNone;
    candidates.clear();
    for (uint32_t o : outers) {
      if (info[o].box.contains(info[h].box)) candidates.push_back(o);
    }
    // Loops do not cross, so the hole lies in one of the candidates: the last one needs no test.
    for (size_t ci = 0; ci < candidates.size(); ++ci) {
      const uint32_t o = candidates[ci];
      if (ci + 1 == candidates.size()) {
        parent = o;
        break;
      }
      for (uint32_t id : loops[o]) stamp[id] = o;
      int inside = 0, outside = 0;
      auto vote = [&](const P2& q) {
        const int r = pointInLoop(pts, loops[o], q);
        if (r == 1) ++inside;
        if (r == 0) ++outside;
      };
      for (size_t i = 0; i < loops[h].size() && inside + outside < 3; ++i) {
        if (stamp[loops[h][i]] != o) vote(pts[loops[h][i]]);
      }
      for (size_t i = 0; i < loops[h].size() && inside + outside == 0; ++i) {
        const P2& a = pts[loops[h][i]];
        const P2& b = pts[loops[h][(i + 1) % loops[h].size()]];
        vote({0.5 * (a.x + b.x), 0.5 * (a.y + b.y)});
      }
      for (uint32_t id : loops[o]) stamp[id] = kNone;
      if (inside > outside || inside + outside == 0) {
        parent = o;
        break;
      }
    }
    if (parent == kNone) {
      orphans.push_back(h);
    } else {
      holesOf[parent].push_back(h);
      ++result.holeLoops;
    }
  }
  result.orphanHoles = orphans.size();

  for (uint32_t o : outers) {
    Polygon poly;
    const uint32_t start = poly.addLoop(pts, loops[o]);
    poly.tol = 1e-12 * std::hypot(info[o].box.x1 - info[o].box.x0, info[o].box.y1 - info[o].box.y0);
    std::vector<uint32_t>& hs = holesOf[o];
    // Right to left: a bridge to the right of a hole's rightmost point cannot cross holes not yet
    // merged.
    std::stable_sort(hs.begin(), hs.end(),
                     [&](uint32_t a, uint32_t b) { return info[a].box.x1 > info[b].box.x1; });
    for (uint32_t id : loops[o]) stamp[id] = o;
    for (size_t k = 0; k < hs.size(); ++k) {
      const std::vector<uint32_t>& hole = loops[hs[k]];
      const uint32_t hFirst = poly.addLoop(pts, hole);
      bool done = false;
      // A hole touching the polygon at a shared point is spliced in there, at the copy of that
      // point whose interior wedge holds the hole's edges.
      for (uint32_t i = 0; i < hole.size() && !done; ++i) {
        if (stamp[hole[i]] != o) continue;
        const uint32_t hn = hFirst + i;
        const P2 out = poly.nodes[poly.nodes[hn].next].p;
        uint32_t u = start, fallback = kNone;
        do {
          if (!poly.nodes[u].removed && poly.nodes[u].id == hole[i] && u < hFirst) {
            if (fallback == kNone) fallback = u;
            if (poly.locallyInside(u, out)) {
              fallback = u;
              break;
            }
          }
          u = poly.nodes[u].next;
        } while (u != start);
        if (fallback != kNone) {
          poly.splice(fallback, hn, true);
          done = true;
        }
      }
      if (!done) {
        const uint32_t m = hFirst + info[hs[k]].rightmost;
        uint32_t c = poly.findBridge(m, start);
        const P2 pm = poly.nodes[m].p;
        const bool valid = c != kNone && poly.locallyInside(c, pm) &&
                           !poly.segmentBlocked(pm, poly.nodes[c].p, start);
        if (!valid) {
          // Degenerate geometry defeated the ray cast: nearest polygon vertex that sees m,
          // checked against every edge (polygon, this hole and the holes still to come).
          std::vector<uint32_t> cand;
          uint32_t u = start;
          do {
            if (u < hFirst) cand.push_back(u);
            u = poly.nodes[u].next;
          } while (u != start);
          auto d2 = [&](uint32_t v) {
            const P2& p = poly.nodes[v].p;
            return (p.x - pm.x) * (p.x - pm.x) + (p.y - pm.y) * (p.y - pm.y);
          };
          std::stable_sort(cand.begin(), cand.end(),
                           [&](uint32_t a, uint32_t b) { return d2(a) < d2(b); });
          c = kNone;
          for (uint32_t v : cand) {
            const P2& pv = poly.nodes[v].p;
            if (!poly.locallyInside(v, pm) || poly.segmentBlocked(pm, pv, start) ||
                poly.segmentBlocked(pm, pv, hFirst)) {
              continue;
            }
            bool clear = true;
            for (size_t j = k + 1; j < hs.size() && clear; ++j) {
              const std::vector<uint32_t>& other = loops[hs[j]];
              for (size_t i = 0; i < other.size() && clear; ++i) {
                const P2& a = pts[other[i]];
                const P2& b = pts[other[(i + 1) % other.size()]];
                if (bridgeHits(pm, pv, a, b, poly.tol)) clear = false;
              }
            }
            if (clear) {
              c = v;
              break;
            }
          }
          // Nothing sees m (crossing loops): bridge to the nearest vertex anyway, keeping the
          // cycle closed; the ear clipper will force its way through.
          if (c == kNone && !cand.empty()) c = cand.front();
        }
        poly.splice(c, m, false);
      }
      for (uint32_t id : hole) stamp[id] = o;
    }
    for (const Node& nd : poly.nodes) stamp[nd.id] = kNone;
    EarClipper(poly.nodes, start, 2 * options.minArea, avoid, result.triangles,
               result.forcedTriangles)
        .run();
  }

  // Orphan holes: triangulate the reversed (counter-clockwise) loop, then reverse the triangles
  // so that every loop edge is still covered in its own direction.
  for (uint32_t h : orphans) {
    std::vector<uint32_t> rev(loops[h].rbegin(), loops[h].rend());
    Polygon poly;
    const uint32_t start = poly.addLoop(pts, rev);
    const size_t first = result.triangles.size();
    EarClipper(poly.nodes, start, 2 * options.minArea, avoid, result.triangles,
               result.forcedTriangles)
        .run();
    for (size_t t = first; t < result.triangles.size(); t += 3) {
      std::swap(result.triangles[t + 1], result.triangles[t + 2]);
    }
  }

  for (size_t t = 0; t < result.triangles.size(); t += 3) {
    result.area += 0.5 * orient(pts[result.triangles[t]], pts[result.triangles[t + 1]],
                                pts[result.triangles[t + 2]]);
  }
  return result;
}

}  // namespace omnislice
