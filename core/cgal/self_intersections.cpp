// SPDX-License-Identifier: MIT
#include "cgal/self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>

#include "geometry/exact_predicates.h"

namespace omnislice {
namespace {

using exact::orient2;
using exact::orient3;

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;

// Box whose id is the face index: deterministic, no global counter.
class FaceBox : public CGAL::Box_intersection_d::Box_d<double, 3, CGAL::Box_intersection_d::ID_NONE> {
 public:
  using Base = CGAL::Box_intersection_d::Box_d<double, 3, CGAL::Box_intersection_d::ID_NONE>;
  using ID = std::size_t;
  FaceBox(const CGAL::Bbox_3& b, uint32_t face) : Base(b), face_(face) {}
  std::size_t id() const { return face_; }
  uint32_t face() const { return face_; }

 private:
  uint32_t face_;
};

// Below this many boxes CGAL's segment tree scans pairs directly. CGAL's default is 10; 2000 (the
// value CGAL's Polygon_mesh_processing::self_intersections uses) was 2x faster on a 1.3M-face
// icosphere here (1.2 s vs 2.5 s CPU).
constexpr std::ptrdiff_t kCutoff = 2000;

struct StopSearch {};  // thrown from the callback to end box_intersection_d early

// The axis (0-2) on which all the points have bitwise the same coordinate (they lie exactly in
// that axis plane), or -1.
template <size_t N>
int commonAxis(const std::array<const Point*, N>& p) {
  for (int k = 0; k < 3; ++k) {
    bool same = true;
    for (size_t i = 1; i < N && same; ++i) same = (*p[i])[k] == (*p[0])[k];
    if (same) return k;
  }
  return -1;
}

// For q, r on one line through p (orient2 == 0, q != p): whether r lies on the same side of p
// as q, r == p counting as not. Exact: coordinate comparisons on an axis along which q moves.
bool sameRay(const Point& p, const Point& q, const Point& r, int i, int j) {
  const int a = q[i] != p[i] ? i : j;
  return (q[a] > p[a] && r[a] > p[a]) || (q[a] < p[a] && r[a] < p[a]);
}

// Tri-state answers of the shortcuts: decided (true / false) or ask CGAL.
enum class Answer { No, Yes, Unknown };

// The corners faces a and b share: ia[k] is the corner of b equal to corner k of a, or -1.
struct Sharing {
  int ia[3];
  int count = 0;
  Sharing(const uint32_t* a, const uint32_t* b) {
    for (int x = 0; x < 3; ++x) {
      ia[x] = -1;
      for (int y = 0; y < 3; ++y)
        if (a[x] == b[y]) ia[x] = y;
      if (ia[x] >= 0) ++count;
    }
  }
  // count == 2: a's corners p, q on the common edge, r opposite; s the corner of b opposite it.
  void edge(int& p, int& q, int& r, int& s) const {
    r = 0;
    while (ia[r] >= 0) ++r;
    p = (r + 1) % 3;
    q = (r + 2) % 3;
    s = 0;
    while (s == ia[p] || s == ia[q]) ++s;
  }
  // count == 1: the common vertex is a's corner va, b's corner vb.
  void vertex(int& va, int& vb) const {
    va = 0;
    while (ia[va] < 0) ++va;
    vb = ia[va];
  }
};

class PairTester {
 public:
  PairTester(const Mesh& mesh, std::vector<Point>& points, bool shortcuts)
      : mesh_(mesh), points_(points), shortcuts_(shortcuts) {
    exactSafe_ = exact::coordinatesInExactRange(mesh.positions);
  }

  bool degenerate(uint32_t f) const {
    const uint32_t* t = mesh_.triangles.data() + 3 * f;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
    const Point& a = points_[t[0]];
    const Point& b = points_[t[1]];
    const Point& c = points_[t[2]];
    if (shortcuts_) {
      const int k = commonAxis<3>({&a, &b, &c});
      if (k >= 0 && orient2(a, b, c, (k + 1) % 3, (k + 2) % 3) != 0) return false;
    }
    return CGAL::collinear(a, b, c);
  }

  bool intersect(uint32_t f, uint32_t g) const {
    const uint32_t* a = mesh_.triangles.data() + 3 * f;
    const uint32_t* b = mesh_.triangles.data() + 3 * g;
    const Sharing sh(a, b);
    if (shortcuts_) {
      const Answer answer = planar(a, b, sh);
      if (answer != Answer::Unknown) {
        ++planarDecided;
        return answer == Answer::Yes;
      }
    }
    return exact(a, b, sh);
  }

  mutable size_t planarDecided = 0;
  mutable size_t orientDecided = 0;

 private:
  // Both faces exactly in one axis plane: the 2D decision where every orientation is certain.
  Answer planar(const uint32_t* a, const uint32_t* b, const Sharing& sh) const {
    const std::array<const Point*, 6> p = {&points_[a[0]], &points_[a[1]], &points_[a[2]],
                                           &points_[b[0]], &points_[b[1]], &points_[b[2]]};
    const int k = commonAxis<6>(p);
    if (k < 0) return Answer::Unknown;
    return coplanar(p, sh, (k + 1) % 3, (k + 2) % 3);
  }

  // Two faces in one plane (p: a's corners, then b's), decided in the coordinates (i, j): exact
  // when the plane projects onto them one to one (an affine bijection keeps every orientation,
  // collinearity and order along a line), i.e. when a's corners are not collinear there.
  Answer coplanar(const std::array<const Point*, 6>& p, const Sharing& sh, int i, int j) const {
    if (sh.count == 3) return Answer::Yes;
    if (sh.count == 2) {
      // Common edge p-q, r opposite in f, s in g: folded onto each other iff r and s lie on the
      // same side of p-q (CGAL::coplanar_orientation(P, Q, R, S) == POSITIVE).
      int pp, q, r, s;
      sh.edge(pp, q, r, s);
      const int o1 = orient2(*p[pp], *p[q], *p[r], i, j), o2 = orient2(*p[pp], *p[q], *p[3 + s], i, j);
      if (o1 == 0 || o2 == 0) return Answer::Unknown;
      return o1 == o2 ? Answer::Yes : Answer::No;
    }
    if (sh.count == 1) {
      // Common vertex v: the faces overlap beyond it iff their open corners at v do, i.e. no
      // line along one of the four edges at v separates them (touching along an edge: CGAL).
      int va, vb;
      sh.vertex(va, vb);
      const Point& v = *p[va];
      const Point* ra[2] = {p[(va + 1) % 3], p[(va + 2) % 3]};
      const Point* rb[2] = {p[3 + (vb + 1) % 3], p[3 + (vb + 2) % 3]};
      auto separates = [&](const Point* const (&own)[2], const Point* const (&other)[2]) {
        // own[e]'s line separates when other's rays lie on the side away from own[1 - e], or on
        // the line pointing away from own[e] (they then meet own only at v).
        for (int e = 0; e < 2; ++e) {
          const int inner = orient2(v, *own[e], *own[1 - e], i, j);
          if (inner == 0) return Answer::Unknown;
          bool apart = true;
          for (int k = 0; k < 2 && apart; ++k) {
            const int sk = orient2(v, *own[e], *other[k], i, j);
            apart = sk == -inner || (sk == 0 && !sameRay(v, *own[e], *other[k], i, j));
          }
          if (apart) return Answer::Yes;
        }
        return Answer::No;
      };
      const Answer sa = separates(ra, rb);
      if (sa == Answer::Unknown) return Answer::Unknown;
      const Answer sb = separates(rb, ra);
      if (sb == Answer::Unknown) return Answer::Unknown;
      return sa == Answer::Yes || sb == Answer::Yes ? Answer::No : Answer::Yes;
    }
    // No common vertex: disjoint iff the line of some edge strictly separates (convex polygons in
    // 2D). When the other face lies on the far side or on the line, it meets the line only in
    // its vertices there: they touch when those overlap the edge (exact 1D comparisons).
    enum class Side { Separated, Touching, Open, Unknown };
    auto edgeSeparates = [&](int base, int other) {
      for (int e = 0; e < 3; ++e) {
        const Point& u = *p[base + e];
        const Point& w = *p[base + (e + 1) % 3];
        const int inner = orient2(u, w, *p[base + (e + 2) % 3], i, j);
        if (inner == 0) return Side::Unknown;
        bool beyond = true;
        const Point* on[3];
        int onLine = 0;
        for (int x = 0; x < 3 && beyond; ++x) {
          const int o = orient2(u, w, *p[other + x], i, j);
          if (o == 0) on[onLine++] = p[other + x];
          else beyond = o == -inner;
        }
        if (!beyond) continue;
        if (onLine == 0) return Side::Separated;
        const int a = u[i] != w[i] ? i : j;
        const double lo = std::min(u[a], w[a]), hi = std::max(u[a], w[a]);
        double bl = (*on[0])[a], bh = bl;
        for (int x = 1; x < onLine; ++x) {
          bl = std::min(bl, (*on[x])[a]);
          bh = std::max(bh, (*on[x])[a]);
        }
        return std::max(lo, bl) <= std::min(hi, bh) ? Side::Touching : Side::Separated;
      }
      return Side::Open;
    };
    for (const auto& [base, other] : {std::pair{0, 3}, std::pair{3, 0}}) {
      const Side side = edgeSeparates(base, other);
      if (side == Side::Separated) return Answer::No;
      if (side == Side::Touching) return Answer::Yes;
      if (side == Side::Unknown) return Answer::Unknown;
    }
    return Answer::Yes;
  }

  // Faces in general position: exact orientations (orient3) first, CGAL where they leave it open.
  // Coplanar faces (every corner of one in the other's plane: flat regions of CAD parts off the
  // axis planes, planar quads of ruled surfaces) are decided in 2D (coplanar), which CGAL's
  // filters only reach through exact arithmetic (a thrown exception each in wasm, no GMP).
  bool exact(const uint32_t* a, const uint32_t* b, const Sharing& sh) const {
    const Point& a0 = points_[a[0]];
    const Point& a1 = points_[a[1]];
    const Point& a2 = points_[a[2]];
    const Point& b0 = points_[b[0]];
    const Point& b1 = points_[b[1]];
    const Point& b2 = points_[b[2]];
    if (sh.count == 3) return true;
    if (shortcuts_ && exactSafe_) {
      const Answer answer = byOrientations(a, b, sh);
      if (answer != Answer::Unknown) {
        ++orientDecided;
        return answer == Answer::Yes;
      }
    }
    if (sh.count == 0) return CGAL::do_intersect(Triangle(a0, a1, a2), Triangle(b0, b1, b2));
    if (sh.count == 2) {
      // Common edge p-q; r opposite in f, s opposite in g. Non-coplanar faces meet only on p-q.
      int p, q, r, s;
      sh.edge(p, q, r, s);
      const Point& P = points_[a[p]];
      const Point& Q = points_[a[q]];
      const Point& R = points_[a[r]];
      const Point& S = points_[b[s]];
      if (!CGAL::coplanar(P, Q, R, S)) return false;
      return CGAL::coplanar_orientation(P, Q, R, S) == CGAL::POSITIVE;
    }
    // One common vertex v: the faces overlap beyond v iff the edge of one opposite v meets the
    // other face (the intersection is a segment from v ending on such an edge). Quick exit, the
    // usual case in a smooth surface: the far corners of one face lie strictly on one side of the
    // other's plane, so that face touches the plane at v only.
    int va, vb;
    sh.vertex(va, vb);
    const CGAL::Orientation s1 = CGAL::orientation(a0, a1, a2, points_[b[(vb + 1) % 3]]);
    const CGAL::Orientation s2 = CGAL::orientation(a0, a1, a2, points_[b[(vb + 2) % 3]]);
    if (s1 != CGAL::COPLANAR && s1 == s2) return false;
    const CGAL::Orientation s3 = CGAL::orientation(b0, b1, b2, points_[a[(va + 1) % 3]]);
    const CGAL::Orientation s4 = CGAL::orientation(b0, b1, b2, points_[a[(va + 2) % 3]]);
    if (s3 != CGAL::COPLANAR && s3 == s4) return false;
    const Segment oppositeA(points_[a[(va + 1) % 3]], points_[a[(va + 2) % 3]]);
    const Segment oppositeB(points_[b[(vb + 1) % 3]], points_[b[(vb + 2) % 3]]);
    return CGAL::do_intersect(oppositeA, Triangle(b0, b1, b2)) ||
           CGAL::do_intersect(oppositeB, Triangle(a0, a1, a2));
  }

  // The decisions exact orientations settle (sh.count < 3), with the faces' corners p (a's,
  // then b's). For each face against the other's plane:
  // - its unshared corners strictly on one side: the faces meet at most in their shared corners
  //   (apart, or adjacent);
  // - all its corners in the plane: coplanar, decided in 2D;
  // - touching the plane without crossing it (ruled surfaces, fans, a corner on a plane): it
  //   meets the plane in T, the hull of its corners there (a point or a segment), so the faces
  //   meet where T meets the other face, decided in 2D in that plane.
  // - both crossing each other's planes from a common vertex: decided by four orientations.
  // Unknown (CGAL): faces without a common corner crossing each other's planes, or a degenerate
  // projection.
  Answer byOrientations(const uint32_t* a, const uint32_t* b, const Sharing& sh) const {
    const std::array<const Point*, 6> p = {&points_[a[0]], &points_[a[1]], &points_[a[2]],
                                           &points_[b[0]], &points_[b[1]], &points_[b[2]]};
    for (int pass = 0; pass < 2; ++pass) {
      const int base = pass == 0 ? 0 : 3, other = 3 - base;
      const uint32_t* baseIdx = pass == 0 ? a : b;
      const uint32_t* otherIdx = pass == 0 ? b : a;
      // Orientations of the other face's corners against base's plane (0 for shared corners).
      int o[3], pos = 0, neg = 0;
      bool shared[3];
      for (int x = 0; x < 3; ++x) {
        const uint32_t v = otherIdx[x];
        shared[x] = v == baseIdx[0] || v == baseIdx[1] || v == baseIdx[2];
        o[x] = shared[x] ? 0 : orient3(*p[base], *p[base + 1], *p[base + 2], *p[other + x]);
        pos += o[x] > 0;
        neg += o[x] < 0;
      }
      if (pos + neg == 3 - sh.count && (pos == 0 || neg == 0)) return Answer::No;
      if (pos > 0 && neg > 0) continue;  // crosses base's plane: try the other way round
      int i, j;
      if (!projection(p, base, i, j)) return Answer::Unknown;
      if (pos + neg == 0) return coplanar(p, sh, i, j);  // (pass 0: every corner of b in a's plane)
      // Touching: T = the other face's corners in base's plane (1 or 2 of them; count < 2 here).
      const Point* t[2];
      int n = 0;
      for (int x = 0; x < 3; ++x)
        if (o[x] == 0) t[n++] = p[other + x];
      const Point& c0 = *p[base];
      const Point& c1 = *p[base + 1];
      const Point& c2 = *p[base + 2];
      if (sh.count == 1) {
        // T = v-c from the common vertex v: the faces meet beyond v iff v-c runs into base's
        // closed corner at v.
        int va, vb;
        sh.vertex(va, vb);
        const int vBase = pass == 0 ? va : vb;
        const Point& v = *p[base + vBase];
        const Point& c = *(t[0] == &v ? t[1] : t[0]);
        if (c == v) return Answer::Unknown;  // a duplicate of v (unwelded): CGAL
        const Point& r1 = *p[base + (vBase + 1) % 3];
        const Point& r2 = *p[base + (vBase + 2) % 3];
        const int inner = orient2(v, r1, r2, i, j);
        const int o1 = orient2(v, r1, c, i, j), o2 = orient2(v, c, r2, i, j);
        if (o1 == inner && o2 == inner) return Answer::Yes;            // into the corner
        if (o1 == 0 && sameRay(v, r1, c, i, j)) return Answer::Yes;     // along its edge v-r1
        if (o2 == 0 && sameRay(v, r2, c, i, j)) return Answer::Yes;     // along its edge v-r2
        return Answer::No;
      }
      // No common vertex: do T (a point, or a segment) and base's closed triangle meet?
      if (n == 2 && *t[0] == *t[1]) n = 1;
      const int inner = orient2(c0, c1, c2, i, j);
      auto inside = [&](const Point& q) {
        const Point* c[3] = {&c0, &c1, &c2};
        for (int e = 0; e < 3; ++e) {
          const int s = orient2(*c[e], *c[(e + 1) % 3], q, i, j);
          if (s == -inner) return false;
        }
        return true;
      };
      if (inside(*t[0]) || (n == 2 && inside(*t[1]))) return Answer::Yes;
      if (n == 1) return Answer::No;
      const Point* c[3] = {&c0, &c1, &c2};
      for (int e = 0; e < 3; ++e)
        if (segmentsMeet(*t[0], *t[1], *c[e], *c[(e + 1) % 3], i, j)) return Answer::Yes;
      return Answer::No;
    }
    if (sh.count == 1) {
      // Both cross each other's planes (every unshared corner strictly off the other plane):
      // A meets the planes' common line L in [v, X], X on a1-a2, and B in [v, Y], Y on b1-b2;
      // they overlap beyond v iff Y lies in A's corner at v (the ray v-X). Y's side of the line
      // v-a1 within A's plane is its side of the plane (v, a1, b1), which b1 lies on and Y
      // between b1 and b2 (so b2's side); that plane misses a2 and b2 (a2 in it would put b1 in
      // A's plane, b2 in it a1 in B's): all four orientations are nonzero.
      int va, vb;
      sh.vertex(va, vb);
      const Point& v = *p[va];
      const Point& a1 = *p[(va + 1) % 3];
      const Point& a2 = *p[(va + 2) % 3];
      const Point& b1 = *p[3 + (vb + 1) % 3];
      const Point& b2 = *p[3 + (vb + 2) % 3];
      const bool side1 = orient3(v, a1, b1, b2) == orient3(v, a1, b1, a2);
      const bool side2 = orient3(v, a2, b1, b2) == orient3(v, a2, b1, a1);
      return side1 && side2 ? Answer::Yes : Answer::No;
    }
    return Answer::Unknown;  // both cross each other's planes: CGAL
  }

  // Whether the closed segments p1-p2 and p3-p4 (non-degenerate, in one plane projecting one to
  // one onto (i, j)) meet: exact orientations, collinear cases by 1D comparisons.
  static bool segmentsMeet(const Point& p1, const Point& p2, const Point& p3, const Point& p4, int i, int j) {
    const int d1 = orient2(p3, p4, p1, i, j), d2 = orient2(p3, p4, p2, i, j);
    const int d3 = orient2(p1, p2, p3, i, j), d4 = orient2(p1, p2, p4, i, j);
    if (d1 * d2 < 0 && d3 * d4 < 0) return true;
    // q on the closed segment u-w, given collinear: compare along an axis where u-w moves.
    auto onSegment = [&](const Point& u, const Point& w, const Point& q) {
      const int k = u[i] != w[i] ? i : j;
      return std::min(u[k], w[k]) <= q[k] && q[k] <= std::max(u[k], w[k]);
    };
    return (d1 == 0 && onSegment(p3, p4, p1)) || (d2 == 0 && onSegment(p3, p4, p2)) ||
           (d3 == 0 && onSegment(p1, p2, p3)) || (d4 == 0 && onSegment(p1, p2, p4));
  }

  // Coordinates (i, j) onto which the plane of the face with corners p[base..base+2] projects
  // one to one: those across the axis its normal leans on most, else any other in which it stays
  // a triangle (exactly).
  static bool projection(const std::array<const Point*, 6>& p, int base, int& i, int& j) {
    const Point& a0 = *p[base];
    const Point& a1 = *p[base + 1];
    const Point& a2 = *p[base + 2];
    const double n[3] = {(a1[1] - a0[1]) * (a2[2] - a0[2]) - (a1[2] - a0[2]) * (a2[1] - a0[1]),
                         (a1[2] - a0[2]) * (a2[0] - a0[0]) - (a1[0] - a0[0]) * (a2[2] - a0[2]),
                         (a1[0] - a0[0]) * (a2[1] - a0[1]) - (a1[1] - a0[1]) * (a2[0] - a0[0])};
    int first = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(n[k]) > std::abs(n[first])) first = k;
    for (int t = 0; t < 3; ++t) {
      const int k = (first + t) % 3;
      i = (k + 1) % 3;
      j = (k + 2) % 3;
      if (orient2(a0, a1, a2, i, j) != 0) return true;
    }
    return false;
  }

  const Mesh& mesh_;
  std::vector<Point>& points_;
  bool shortcuts_;
  bool exactSafe_ = true;
};

}  // namespace

SelfIntersectionResult findSelfIntersections(const Mesh& mesh, const SelfIntersectionOptions& options,
                                             const ProgressFn& progress, double from, double to) {
  SelfIntersectionResult result;
  try {
    std::vector<Point> points;
    points.reserve(mesh.vertexCount());
    for (size_t i = 0; i < mesh.vertexCount(); ++i) {
      const double* p = mesh.positions.data() + 3 * i;
      points.emplace_back(p[0], p[1], p[2]);
    }
    PairTester tester(mesh, points, options.planarShortcuts);
    std::vector<FaceBox> boxes;
    boxes.reserve(mesh.faceCount());
    for (uint32_t f = 0; f < mesh.faceCount(); ++f) {
      if (tester.degenerate(f)) continue;
      const uint32_t* t = mesh.triangles.data() + 3 * f;
      boxes.emplace_back(points[t[0]].bbox() + points[t[1]].bbox() + points[t[2]].bbox(), f);
    }
    if (!reportProgress(progress, "validate", from)) {
      result.status = Status::Cancelled;
      result.message = "cancelled during the self-intersection test";
      return result;
    }
    size_t candidates = 0;
    bool cancelled = false;
    // Candidate pairs are not known in advance: the fraction creeps towards `to` as they come.
    auto callback = [&](const FaceBox& x, const FaceBox& y) {
      if ((++candidates & 0xFFFF) == 0) {
        const double frac = from + (to - from) * (1.0 - 1.0 / (1.0 + double(candidates) / 4e6));
        if (!reportProgress(progress, "validate", frac)) {
          cancelled = true;
          throw StopSearch{};
        }
      }
      if (!tester.intersect(x.face(), y.face())) return;
      ++result.count;
      if (options.collectPairs) {
        result.pairs.emplace_back(std::min(x.face(), y.face()), std::max(x.face(), y.face()));
      }
      if (options.cap > 0 && result.count >= options.cap) {
        result.capped = true;
        throw StopSearch{};
      }
    };
    try {
      CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), callback, kCutoff);
    } catch (const StopSearch&) {
    }
    if (cancelled) {
      result.status = Status::Cancelled;
      result.message = "cancelled during the self-intersection test";
      result.pairs.clear();
      return result;
    }
    std::sort(result.pairs.begin(), result.pairs.end());
    result.candidates = candidates;
    result.planarDecided = tester.planarDecided;
    result.orientDecided = tester.orientDecided;
    if (!reportProgress(progress, "validate", to)) {
      result = SelfIntersectionResult{};
      result.status = Status::Cancelled;
      result.message = "cancelled during the self-intersection test";
    }
  } catch (const std::exception& e) {
    result = SelfIntersectionResult{};
    result.status = Status::Internal;
    result.message = std::string("self-intersection test failed: ") + e.what();
  } catch (...) {
    result = SelfIntersectionResult{};
    result.status = Status::Internal;
    result.message = "self-intersection test failed with an unknown CGAL error";
  }
  return result;
}

}  // namespace omnislice
