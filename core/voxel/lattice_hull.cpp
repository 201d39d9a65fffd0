// SPDX-License-Identifier: MIT
// Exact lattice convex hull: Quickhull with conflict (outside) lists and exact integer orientation
// tests. A point is "outside" a facet only when strictly above its plane, so the many coplanar
// lattice points are simply absorbed (a point outside a 3D hull is always strictly above some
// facet, and new cone facets are never degenerate because the eye is strictly above a facet that
// holds the horizon edge). Coplanar triangles share one reduced plane (normal divided by the gcd).
#include "voxel/lattice_hull.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <tuple>
#include <unordered_map>

namespace omnislice {
namespace {

using V3 = Eigen::Vector3i;

struct Normal {
  int64_t x = 0, y = 0, z = 0;
};

Normal crossOf(const V3& a, const V3& b, const V3& c) {
  const int64_t ux = b.x() - a.x(), uy = b.y() - a.y(), uz = b.z() - a.z();
  const int64_t vx = c.x() - a.x(), vy = c.y() - a.y(), vz = c.z() - a.z();
  return {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
}

int64_t gcd64(int64_t a, int64_t b) {
  a = a < 0 ? -a : a;
  b = b < 0 ? -b : b;
  while (b) {
    const int64_t t = a % b;
    a = b;
    b = t;
  }
  return a;
}

Normal reduced(Normal n) {
  const int64_t g = gcd64(gcd64(n.x, n.y), n.z);
  if (g > 1) {
    n.x /= g;
    n.y /= g;
    n.z /= g;
  }
  return n;
}

LatticeHull::Plane makePlane(const Normal& n, const V3& on) {
  LatticeHull::Plane p;
  p.nx = n.x;
  p.ny = n.y;
  p.nz = n.z;
  p.offset = n.x * on.x() + n.y * on.y() + n.z * on.z();
  p.invNorm = 1.0 / std::sqrt(static_cast<double>(n.x) * n.x + static_cast<double>(n.y) * n.y +
                              static_cast<double>(n.z) * n.z);
  return p;
}

// Quickhull over exact integers. Acc is the accumulator of n.(p - a): int64_t when every
// coordinate is below 2^16 in magnitude, __int128 otherwise.
template <typename Acc>
class Builder {
 public:
  struct Facet {
    int v[3];
    int nb[3];  // neighbour across edge v[i] -> v[(i+1)%3]
    int64_t nx, ny, nz;
    bool alive = true;
    int mark = 0;
    int outside = -1;  // head of the facet's outside-point list (linked through next_)
  };

  explicit Builder(const std::vector<V3>& pts) : p_(pts), next_(pts.size(), -1) {
    facets_.reserve(64 + 8 * std::min<size_t>(pts.size(), 4096));
  }

  // Returns false when the points do not span 3D (the caller handles flat sets).
  bool run(int s0, int s1, int s2, int s3) {
    // Orient the tetrahedron so each facet's normal points away from the fourth vertex.
    if (orient(s0, s1, s2, s3) > 0) std::swap(s1, s2);
    // Now s3 is below plane (s0, s1, s2).
    const int f0 = addFacet(s0, s1, s2);
    const int f1 = addFacet(s0, s3, s1);
    const int f2 = addFacet(s1, s3, s2);
    const int f3 = addFacet(s2, s3, s0);
    linkAll({f0, f1, f2, f3});
    const int initial[4] = {f0, f1, f2, f3};
    for (int i = 0; i < static_cast<int>(p_.size()); ++i)
      if (i != s0 && i != s1 && i != s2 && i != s3) assign(i, initial, 4);
    std::vector<int> stack = {f0, f1, f2, f3};
    std::vector<int> visible, horizonA, horizonB, horizonOuter, created;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      if (!facets_[f].alive || facets_[f].outside < 0) continue;
      // Farthest point of f's outside set (same normal, so integer comparison is exact).
      int eye = -1;
      Acc best = 0;
      for (int q = facets_[f].outside; q >= 0; q = next_[q]) {
        const Acc d = eval(f, q);
        if (eye < 0 || d > best) {
          best = d;
          eye = q;
        }
      }
      // Visible facets: flood from f across neighbours strictly below eye.
      ++stamp_;
      visible.clear();
      visible.push_back(f);
      facets_[f].mark = stamp_;
      horizonA.clear();
      horizonB.clear();
      horizonOuter.clear();
      for (size_t i = 0; i < visible.size(); ++i) {
        const int g = visible[i];
        for (int e = 0; e < 3; ++e) {
          const int h = facets_[g].nb[e];
          if (facets_[h].mark == stamp_) continue;
          if (eval(h, eye) > 0) {
            facets_[h].mark = stamp_;
            visible.push_back(h);
          }
        }
      }
      for (int g : visible)
        for (int e = 0; e < 3; ++e) {
          const int h = facets_[g].nb[e];
          if (facets_[h].mark != stamp_) {
            horizonA.push_back(facets_[g].v[e]);
            horizonB.push_back(facets_[g].v[(e + 1) % 3]);
            horizonOuter.push_back(h);
          }
        }
      // Cone of new facets (a, b, eye) over the horizon edges a -> b.
      created.clear();
      for (size_t i = 0; i < horizonA.size(); ++i) {
        const int a = horizonA[i], b = horizonB[i], outer = horizonOuter[i];
        const int nf = addFacet(a, b, eye);
        created.push_back(nf);
        facets_[nf].nb[0] = outer;
        for (int e = 0; e < 3; ++e)
          if (facets_[outer].v[e] == b && facets_[outer].v[(e + 1) % 3] == a)
            facets_[outer].nb[e] = nf;
        startAt(a) = nf;
      }
      for (int nf : created) {
        const int b = facets_[nf].v[1];
        // Edge b -> eye (index 1) borders the new facet that starts at b (its edge eye -> b).
        const int next = startAt(b);
        facets_[nf].nb[1] = next;
        facets_[next].nb[2] = nf;
      }
      for (int g : visible) {
        facets_[g].alive = false;
        for (int q = facets_[g].outside; q >= 0;) {
          const int nq = next_[q];
          if (q != eye) assign(q, created.data(), static_cast<int>(created.size()));
          q = nq;
        }
        facets_[g].outside = -1;
      }
      for (int nf : created)
        if (facets_[nf].outside >= 0) stack.push_back(nf);
    }
    return true;
  }

  Acc orient(int a, int b, int c, int d) const {
    const Normal n = crossOf(p_[a], p_[b], p_[c]);
    return static_cast<Acc>(n.x) * (p_[d].x() - p_[a].x()) +
           static_cast<Acc>(n.y) * (p_[d].y() - p_[a].y()) +
           static_cast<Acc>(n.z) * (p_[d].z() - p_[a].z());
  }

  std::vector<Facet> facets_;

 private:
  int& startAt(int vertex) {
    if (start_.size() < p_.size()) start_.assign(p_.size(), -1);
    return start_[vertex];
  }

  int addFacet(int a, int b, int c) {
    Facet f;
    f.v[0] = a;
    f.v[1] = b;
    f.v[2] = c;
    f.nb[0] = f.nb[1] = f.nb[2] = -1;
    const Normal n = crossOf(p_[a], p_[b], p_[c]);
    f.nx = n.x;
    f.ny = n.y;
    f.nz = n.z;
    facets_.push_back(std::move(f));
    return static_cast<int>(facets_.size()) - 1;
  }

  void linkAll(const std::vector<int>& fs) {
    for (int f : fs)
      for (int e = 0; e < 3; ++e) {
        const int a = facets_[f].v[e], b = facets_[f].v[(e + 1) % 3];
        for (int g : fs) {
          if (g == f) continue;
          for (int k = 0; k < 3; ++k)
            if (facets_[g].v[k] == b && facets_[g].v[(k + 1) % 3] == a) facets_[f].nb[e] = g;
        }
      }
  }

  Acc eval(int f, int q) const {
    const Facet& F = facets_[f];
    const V3& a = p_[F.v[0]];
    return static_cast<Acc>(F.nx) * (p_[q].x() - a.x()) +
           static_cast<Acc>(F.ny) * (p_[q].y() - a.y()) +
           static_cast<Acc>(F.nz) * (p_[q].z() - a.z());
  }

  // Put point q on the outside list of the first facet of fs it is strictly above (else drop it).
  void assign(int q, const int* fs, int count) {
    for (int i = 0; i < count; ++i)
      if (eval(fs[i], q) > 0) {
        next_[q] = facets_[fs[i]].outside;
        facets_[fs[i]].outside = q;
        return;
      }
  }

  const std::vector<V3>& p_;
  std::vector<int> next_;
  std::vector<int> start_;
  int stamp_ = 0;
};

int64_t dot3(const Normal& n, const V3& p) { return n.x * p.x() + n.y * p.y() + n.z * p.z(); }

}  // namespace

LatticeHull::LatticeHull(const std::vector<Eigen::Vector3i>& input) {
  if (input.empty()) return;
  // Deduplicate (sort) so duplicates cost nothing and results are order independent.
  std::vector<V3> pts(input);
  auto less = [](const V3& a, const V3& b) {
    if (a.x() != b.x()) return a.x() < b.x();
    if (a.y() != b.y()) return a.y() < b.y();
    return a.z() < b.z();
  };
  std::sort(pts.begin(), pts.end(), less);
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  const int n = static_cast<int>(pts.size());
  int maxAbs = 0;
  for (const V3& p : pts) maxAbs = std::max(maxAbs, p.cwiseAbs().maxCoeff());

  // Initial simplex: s0 lexicographic min, s1 farthest from s0, s2 farthest from line, s3 from plane.
  const int s0 = 0;
  if (n == 1) {
    dimension_ = 0;
    vertices_ = {pts[0]};
    return;
  }
  int s1 = -1;
  int64_t best = -1;
  for (int i = 1; i < n; ++i) {
    const int64_t d = (pts[i] - pts[s0]).cast<int64_t>().squaredNorm();
    if (d > best) {
      best = d;
      s1 = i;
    }
  }
  int s2 = -1;
  double bestArea = 0;
  Normal planeN;
  for (int i = 0; i < n; ++i) {
    const Normal c = crossOf(pts[s0], pts[s1], pts[i]);
    const double a = static_cast<double>(c.x) * c.x + static_cast<double>(c.y) * c.y +
                     static_cast<double>(c.z) * c.z;
    if (a > bestArea) {
      bestArea = a;
      s2 = i;
      planeN = c;
    }
  }
  if (s2 < 0) {
    // Collinear: the segment between the two extreme points along the line.
    dimension_ = 1;
    const Eigen::Matrix<int64_t, 3, 1> dir = (pts[s1] - pts[s0]).cast<int64_t>();
    int lo = 0, hi = 0;
    for (int i = 0; i < n; ++i) {
      const int64_t t = dir.dot((pts[i] - pts[s0]).cast<int64_t>());
      if (t < dir.dot((pts[lo] - pts[s0]).cast<int64_t>())) lo = i;
      if (t > dir.dot((pts[hi] - pts[s0]).cast<int64_t>())) hi = i;
    }
    vertices_ = {pts[lo], pts[hi]};
    return;
  }
  int s3 = -1;
  double bestVol = 0;
  {
    const Normal pn = reduced(planeN);
    for (int i = 0; i < n; ++i) {
      const double v = std::fabs(static_cast<double>(dot3(pn, pts[i]) - dot3(pn, pts[s0])));
      if (v > bestVol) {
        bestVol = v;
        s3 = i;
      }
    }
  }
  if (s3 < 0) {
    // Flat: 2D hull (monotone chain) in the projection dropping the dominant normal axis.
    dimension_ = 2;
    const Normal pn = reduced(planeN);
    int drop = 0;
    const int64_t ax = std::llabs(pn.x), ay = std::llabs(pn.y), az = std::llabs(pn.z);
    if (ay >= ax && ay >= az) drop = 1;
    if (az >= ax && az >= ay) drop = 2;
    const int u = drop == 0 ? 1 : 0, w = drop == 2 ? 1 : 2;
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      if (pts[a][u] != pts[b][u]) return pts[a][u] < pts[b][u];
      return pts[a][w] < pts[b][w];
    });
    auto cross2 = [&](int o, int a, int b) {
      return static_cast<int64_t>(pts[a][u] - pts[o][u]) * (pts[b][w] - pts[o][w]) -
             static_cast<int64_t>(pts[a][w] - pts[o][w]) * (pts[b][u] - pts[o][u]);
    };
    std::vector<int> hull(2 * n);
    int k = 0;
    for (int i = 0; i < n; ++i) {
      while (k >= 2 && cross2(hull[k - 2], hull[k - 1], order[i]) <= 0) --k;
      hull[k++] = order[i];
    }
    for (int i = n - 2, t = k + 1; i >= 0; --i) {
      while (k >= t && cross2(hull[k - 2], hull[k - 1], order[i]) <= 0) --k;
      hull[k++] = order[i];
    }
    hull.resize(k - 1);
    for (int idx : hull) vertices_.push_back(pts[idx]);
    // Orient the polygon counter-clockwise seen from +pn.
    if (vertices_.size() >= 3) {
      const Normal c = crossOf(vertices_[0], vertices_[1], vertices_[2]);
      if (c.x * pn.x + c.y * pn.y + c.z * pn.z < 0) std::reverse(vertices_.begin(), vertices_.end());
    }
    planes_.push_back(makePlane(pn, vertices_[0]));
    planes_.push_back(makePlane(Normal{-pn.x, -pn.y, -pn.z}, vertices_[0]));
    const int m = static_cast<int>(vertices_.size());
    for (int i = 0; i < m; ++i) {
      const V3& a = vertices_[i];
      const V3& b = vertices_[(i + 1) % m];
      // Outward in-plane normal of a counter-clockwise edge: (b - a) x pn.
      const int64_t ex = b.x() - a.x(), ey = b.y() - a.y(), ez = b.z() - a.z();
      const Normal e = reduced(Normal{ey * pn.z - ez * pn.y, ez * pn.x - ex * pn.z,
                                      ex * pn.y - ey * pn.x});
      planes_.push_back(makePlane(e, a));
    }
    for (int i = 1; i + 1 < m; ++i) facets_.emplace_back(0, i, i + 1);
    return;
  }

  auto collect = [&](auto& builder) {
    builder.run(s0, s1, s2, s3);
    std::vector<int> remap(n, -1);
    std::vector<Normal> normals;
    std::vector<int> firstVertex;
    for (auto& f : builder.facets_) {
      if (!f.alive) continue;
      Eigen::Vector3i tri;
      for (int e = 0; e < 3; ++e) {
        int& r = remap[f.v[e]];
        if (r < 0) {
          r = static_cast<int>(vertices_.size());
          vertices_.push_back(pts[f.v[e]]);
        }
        tri[e] = r;
      }
      facets_.push_back(tri);
      normals.push_back(reduced(Normal{f.nx, f.ny, f.nz}));
      firstVertex.push_back(f.v[0]);
    }
    // Coplanar triangles share one plane: sort by reduced normal and number the runs.
    std::vector<int> order(normals.size());
    std::iota(order.begin(), order.end(), 0);
    auto key = [&](int i) { return std::make_tuple(normals[i].x, normals[i].y, normals[i].z); };
    std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
    facetPlane_.assign(normals.size(), -1);
    for (size_t r = 0; r < order.size(); ++r) {
      const int i = order[r];
      if (r == 0 || key(order[r - 1]) != key(i))
        planes_.push_back(makePlane(normals[i], pts[firstVertex[i]]));
      facetPlane_[i] = static_cast<int>(planes_.size()) - 1;
    }
  };
  dimension_ = 3;
  if (maxAbs < (1 << 16)) {
    Builder<int64_t> b(pts);
    collect(b);
  } else {
    Builder<__int128> b(pts);
    collect(b);
  }
}

LatticeHull LatticeHull::extended(const std::vector<Eigen::Vector3i>& points) const {
  std::vector<Eigen::Vector3i> all;
  all.reserve(vertices_.size() + points.size());
  all.insert(all.end(), vertices_.begin(), vertices_.end());
  if (dimension_ == 3) {
    // Points inside or on the hull cannot become vertices: drop them first.
    int hint = 0;
    for (const Eigen::Vector3i& p : points)
      if (!insideOrOn(p, &hint)) all.push_back(p);
  } else {
    all.insert(all.end(), points.begin(), points.end());
  }
  return LatticeHull(all);
}

bool LatticeHull::insideOrOn(const Eigen::Vector3i& p, int* hint) const {
  const int np = static_cast<int>(planes_.size());
  if (hint && *hint >= 0 && *hint < np) {
    const Plane& h = planes_[*hint];
    if (h.nx * p.x() + h.ny * p.y() + h.nz * p.z() > h.offset) return false;
  }
  for (int i = 0; i < np; ++i) {
    const Plane& h = planes_[i];
    if (h.nx * p.x() + h.ny * p.y() + h.nz * p.z() > h.offset) {
      if (hint) *hint = i;
      return false;
    }
  }
  return true;
}

namespace {
double segmentDistance(const Eigen::Vector3i& p, const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
  const Eigen::Vector3d pa = (p - a).cast<double>(), ba = (b - a).cast<double>();
  const double len2 = ba.squaredNorm();
  const double t = len2 > 0 ? std::clamp(pa.dot(ba) / len2, 0.0, 1.0) : 0.0;
  return (pa - t * ba).norm();
}
}  // namespace

bool LatticeHull::inside(const Eigen::Vector3i& p, double eps, int* hint) const {
  if (dimension_ < 0) return false;
  if (dimension_ == 0) return (p - vertices_[0]).cast<double>().norm() <= eps;
  if (dimension_ == 1) return segmentDistance(p, vertices_[0], vertices_[1]) <= eps;
  if (dimension_ == 2) {
    // Flat hull: within eps of the support plane and inside (within eps of) every edge plane.
    if (std::fabs(planes_[0].distance(p)) > eps) return false;
    for (size_t i = 2; i < planes_.size(); ++i)
      if (planes_[i].distance(p) > eps) return false;
    return true;
  }
  const int np = static_cast<int>(planes_.size());
  if (hint && *hint >= 0 && *hint < np && planes_[*hint].distance(p) > -eps) return false;
  for (int i = 0; i < np; ++i)
    if (planes_[i].distance(p) > -eps) {
      if (hint) *hint = i;
      return false;
    }
  return true;
}

double LatticeHull::signedDistance(const Eigen::Vector3i& p) const {
  if (dimension_ < 0) return std::numeric_limits<double>::infinity();
  if (dimension_ == 0) return (p - vertices_[0]).cast<double>().norm();
  if (dimension_ == 1) return segmentDistance(p, vertices_[0], vertices_[1]);
  if (dimension_ == 2) {
    double d = std::fabs(planes_[0].distance(p));
    for (size_t i = 2; i < planes_.size(); ++i) d = std::max(d, planes_[i].distance(p));
    return std::max(d, 0.0);
  }
  double d = -std::numeric_limits<double>::infinity();
  for (const Plane& h : planes_) d = std::max(d, h.distance(p));
  return d;
}

}  // namespace omnislice
