// SPDX-License-Identifier: MIT
// The collision model of the IGDS (collision_surfaces.h, paper 002 Algorithm 2): each node's
// envelope (the nozzle cone swept over its IGDS) as exact primitives with bounding-volume
// hierarchies, and the dual traversal that finds every other node's test points inside it.
#include "geodesic/collision_surfaces.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "common/det_math.h"
#include "common/math_constants.h"
#include "common/parallel.h"
#include "common/stopwatch.h"
#include "geodesic/print_order_detail.h"

namespace omnislice {

// Collision model.
//
// The rule implemented (collision_surfaces.h; paper Fig. 15): the envelope of node i is the
// volume the nozzle cone sweeps over its IGDS S_i, closed as in the paper: the ring-like ruled
// surface of the cones along S_i's boundary on the sides, S_i itself below, and the top at axial
// length L. It is the union of two parts, each tested exactly on the triangle mesh:
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

using Vec3 = Eigen::Vector3d;
using print_order_detail::closestOnSegment;
using print_order_detail::edgeKey;
using print_order_detail::regionValid;

Vec3 unitNormal(const Vec3& a, const Vec3& b, const Vec3& c, double* area = nullptr) {
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  if (area) *area = 0.5 * len;
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

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
  std::vector<size_t> tested(n, 0);  // pairs tested per node, summed in order below
  auto testNode = [&](size_t i, size_t) {
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
      ++tested[i];
      if ((meetF && dualHit(si.faceBvh, si.faceOrder, sj, k.length, k.clearance, inFace)) ||
          (meetR && dualHit(si.ringBvh, si.ringOrder, sj, ringReach, k.clearance, inRing)))
        out.pcs[i].push_back(uint32_t(j));
    }
  };
  const bool finished = parallelFor(n, std::max<size_t>(1, options.threads), testNode, [&](size_t done) {
    return reportProgress(progress, "collision", 0.1 + 0.9 * double(done) / double(n));
  });
  if (!finished) return fail(Status::Cancelled, "collision: cancelled");
  for (size_t t : tested) out.pairsTested += t;
  reportProgress(progress, "collision", 1.0);
  out.ms = msSince(t0);
  return out;
}

}  // namespace omnislice
