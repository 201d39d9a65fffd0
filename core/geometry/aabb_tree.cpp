// SPDX-License-Identifier: MIT
#include "geometry/aabb_tree.h"

#include <algorithm>
#include <Eigen/Geometry>
#include <cmath>

#include "geometry/segment.h"

namespace omnislice {

namespace {

constexpr int32_t kLeafSize = 4;

double boxDistance2(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
    d2 += d * d;
  }
  return d2;
}

// Edge function of the directed 2D edge P->Q at r, computed from the lexicographically smaller
// endpoint so that E(P,Q,r) == -E(Q,P,r) exactly: two faces sharing an edge agree on which side
// r lies, bit for bit.
double edgeFunction(double px, double py, double qx, double qy, double rx, double ry) {
  const bool swap = (qx < px) || (qx == px && qy < py);
  if (swap) {
    std::swap(px, qx);
    std::swap(py, qy);
  }
  const double e = (qx - px) * (ry - py) - (qy - py) * (rx - px);
  return swap ? -e : e;
}

// Half-open ownership of a point lying exactly on edge P->Q (interior on the left): the edge owns
// it when the point shifted by (e, e^2) would be on the left. Antisymmetric in P, Q.
bool ownsBoundary(double px, double py, double qx, double qy) {
  const double dy = qy - py, dx = qx - px;
  return dy < 0 || (dy == 0 && dx > 0);
}

}  // namespace

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a;
  if (ab.cross(ac).squaredNorm() <= 1e-30 * std::max(1.0, ab.squaredNorm() * ac.squaredNorm())) {
    // Degenerate (needle or point): nearest of the three edges.
    Eigen::Vector3d best = closestPointOnSegment(p, a, b);
    for (const Eigen::Vector3d& q : {closestPointOnSegment(p, b, c), closestPointOnSegment(p, c, a)}) {
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    }
    return best;
  }
  // Voronoi regions of the vertices, then the edges, else the face interior.
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const double inv = 1.0 / (va + vb + vc);
  return a + ab * (vb * inv) + ac * (vc * inv);
}

AabbTree::AabbTree(const Mesh& mesh) {
  const size_t nv = mesh.vertexCount();
  // The median splits move (centroid, face) pairs held side by side: partitioning indices into a
  // separate centroid array, and bounding every node from its triangles' corners, cost a cache
  // miss per triangle and level (the tree build was 8 % of a voxel bunny slice, trees of every
  // layer and region). Same comparisons on the same keys, so nth_element makes the same
  // permutation and the tree is the one it was. The corners are copied once, in leaf order, so
  // a leaf reads them contiguously (no temporary copies: natively, every large fresh array is
  // page faults, a quarter of a 20k-triangle build).
  std::vector<BuildItem> items;
  items.reserve(mesh.faceCount());
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const uint32_t i = mesh.triangles[3 * f], j = mesh.triangles[3 * f + 1],
                   k = mesh.triangles[3 * f + 2];
    if (i >= nv || j >= nv || k >= nv) continue;
    items.push_back({(mesh.vertex(i) + mesh.vertex(j) + mesh.vertex(k)) / 3.0, static_cast<int64_t>(f)});
  }
  const int32_t n = static_cast<int32_t>(items.size());
  nodes_.reserve(n > 0 ? 2 * (n / kLeafSize + 1) : 0);
  if (n > 0) build(0, n, items, mesh);
  a_.resize(n);
  b_.resize(n);
  c_.resize(n);
  faceIndex_.resize(n);
  for (int32_t i = 0; i < n; ++i) {
    const size_t f = static_cast<size_t>(items[i].face);
    a_[i] = mesh.vertex(mesh.triangles[3 * f]);
    b_[i] = mesh.vertex(mesh.triangles[3 * f + 1]);
    c_[i] = mesh.vertex(mesh.triangles[3 * f + 2]);
    faceIndex_[i] = items[i].face;
  }
}

int32_t AabbTree::build(int32_t first, int32_t count, std::vector<BuildItem>& items, const Mesh& mesh) {
  const int32_t id = static_cast<int32_t>(nodes_.size());
  nodes_.emplace_back();
  if (count <= kLeafSize) {
    const uint32_t* t = &mesh.triangles[3 * static_cast<size_t>(items[first].face)];
    Eigen::Vector3d lo = mesh.vertex(t[0]), hi = lo;
    for (int32_t i = first; i < first + count; ++i) {
      t = &mesh.triangles[3 * static_cast<size_t>(items[i].face)];
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d p = mesh.vertex(t[k]);
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    nodes_[id].lo = lo;
    nodes_[id].hi = hi;
    nodes_[id].first = first;
    nodes_[id].count = count;
    return id;
  }
  Eigen::Vector3d clo = items[first].centroid, chi = clo;
  for (int32_t i = first; i < first + count; ++i) {
    clo = clo.cwiseMin(items[i].centroid);
    chi = chi.cwiseMax(items[i].centroid);
  }
  int axis = 0;
  const Eigen::Vector3d ext = chi - clo;
  if (ext.y() > ext[axis]) axis = 1;
  if (ext.z() > ext[axis]) axis = 2;
  const int32_t half = count / 2;
  std::nth_element(items.begin() + first, items.begin() + first + half, items.begin() + first + count,
                   [axis](const BuildItem& s, const BuildItem& t) { return s.centroid[axis] < t.centroid[axis]; });
  const int32_t left = build(first, half, items, mesh);
  const int32_t right = build(first + half, count - half, items, mesh);
  // A node's box is the union of its children's (min and max are exact: the same box as from
  // all its corners).
  nodes_[id].lo = nodes_[left].lo.cwiseMin(nodes_[right].lo);
  nodes_[id].hi = nodes_[left].hi.cwiseMax(nodes_[right].hi);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

ClosestPoint AabbTree::closest(const Eigen::Vector3d& p, double maxDistance) const {
  ClosestPoint best;
  if (nodes_.empty()) return best;
  double best2 = maxDistance * maxDistance;
  if (!std::isfinite(best2)) best2 = std::numeric_limits<double>::infinity();
  int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistance2(p, node.lo, node.hi) >= best2) continue;
    if (node.left < 0) {
      for (int32_t i = node.first; i < node.first + node.count; ++i) {
        const Eigen::Vector3d q = closestPointOnTriangle(p, a_[i], b_[i], c_[i]);
        const double d2 = (q - p).squaredNorm();
        if (d2 < best2) {
          best2 = d2;
          best.distance = std::sqrt(d2);
          best.point = q;
          best.triangle = faceIndex_[i];
        }
      }
      continue;
    }
    // Visit the nearer child first (pushed last).
    const Node& l = nodes_[node.left];
    const Node& r = nodes_[node.right];
    const double dl = boxDistance2(p, l.lo, l.hi), dr = boxDistance2(p, r.lo, r.hi);
    if (dl < dr) {
      if (dr < best2) stack[top++] = node.right;
      if (dl < best2) stack[top++] = node.left;
    } else {
      if (dl < best2) stack[top++] = node.left;
      if (dr < best2) stack[top++] = node.right;
    }
  }
  return best;
}

bool AabbTree::anyWithin(const Eigen::Vector3d& p, double r) const {
  if (nodes_.empty()) return false;
  const double r2 = r * r;
  int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistance2(p, node.lo, node.hi) > r2) continue;
    if (node.left < 0) {
      for (int32_t i = node.first; i < node.first + node.count; ++i) {
        if ((closestPointOnTriangle(p, a_[i], b_[i], c_[i]) - p).squaredNorm() <= r2) return true;
      }
      continue;
    }
    stack[top++] = node.left;
    stack[top++] = node.right;
  }
  return false;
}

bool AabbTree::crossing(int32_t t, double x, double y, ColumnCrossing& out) const {
  const Eigen::Vector3d& a = a_[t];
  Eigen::Vector3d b = b_[t], c = c_[t];
  const double area2 = edgeFunction(a.x(), a.y(), b.x(), b.y(), c.x(), c.y());
  if (area2 == 0) return false;  // vertical face: no signed contribution
  int sign = -1;                  // counter-clockwise seen from above: face looks up, line leaves
  if (area2 < 0) {
    std::swap(b, c);
    sign = +1;
  }
  const Eigen::Vector3d* v[3] = {&a, &b, &c};
  double w[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& P = *v[k];
    const Eigen::Vector3d& Q = *v[(k + 1) % 3];
    const double e = edgeFunction(P.x(), P.y(), Q.x(), Q.y(), x, y);
    if (e < 0 || (e == 0 && !ownsBoundary(P.x(), P.y(), Q.x(), Q.y()))) return false;
    w[k] = e;  // weight of the vertex opposite edge k
  }
  const double sum = w[0] + w[1] + w[2];
  // w[0] is opposite c (edge a-b), w[1] opposite a (edge b-c), w[2] opposite b (edge c-a).
  out.z = sum > 0 ? (w[1] * a.z() + w[2] * b.z() + w[0] * c.z()) / sum
                  : std::min({a.z(), b.z(), c.z()});
  out.sign = sign;
  return true;
}

template <class Visit>
void AabbTree::visitColumn(double x, double y, double zAbove, Visit&& visit) const {
  if (nodes_.empty()) return;
  int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (x < node.lo.x() || x > node.hi.x() || y < node.lo.y() || y > node.hi.y()) continue;
    if (node.hi.z() <= zAbove) continue;
    if (node.left < 0) {
      for (int32_t i = node.first; i < node.first + node.count; ++i) visit(i, node);
      continue;
    }
    stack[top++] = node.left;
    stack[top++] = node.right;
  }
}

void AabbTree::columnCrossings(double x, double y, std::vector<ColumnCrossing>& out) const {
  out.clear();
  visitColumn(x, y, -std::numeric_limits<double>::infinity(), [&](int32_t t, const Node&) {
    ColumnCrossing c;
    if (crossing(t, x, y, c)) out.push_back(c);
  });
}

int AabbTree::winding(const Eigen::Vector3d& p) const {
  int w = 0;
  // Subtrees wholly at or below p hold no crossing above it: not visited.
  visitColumn(p.x(), p.y(), p.z(), [&](int32_t t, const Node&) {
    ColumnCrossing c;
    if (crossing(t, p.x(), p.y(), c) && c.z > p.z()) w -= c.sign;  // leaving above counts +1
  });
  return w;
}

}  // namespace omnislice
