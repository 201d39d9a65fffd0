// SPDX-License-Identifier: MIT
#include "surface/printed_points.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace omnislice {

namespace {

using Eigen::Vector3d;

constexpr double kCell = 2.0;  // mm, edge of a level-0 cell
constexpr int kBlockLevel = 2;  // 8 mm blocks: the boxes the scan this index replaced tested
constexpr int kTopLevel = 5;    // 64 mm roots
// Added to the cone of the search's box tests (mm): they only skip boxes no point in the cone can
// lie in, so they must not reject by rounding (~1e-13 mm here) what the point test accepts.
constexpr double kMargin = 1e-6;

int64_t floorDiv(int64_t v, int64_t d) { return v >= 0 ? v / d : -((-v + d - 1) / d); }
int64_t key(int64_t x, int64_t y, int64_t z) {
  return ((x & 0x1FFFFF) << 42) | ((y & 0x1FFFFF) << 21) | (z & 0x1FFFFF);
}

// Conservative: false only when no point of the box can be in the cone.
// cosT, sinT: cos and sin of the cone's half-angle, from its tangent as coneCosSin gives them.
// center, halfDiagonal: the box's, as boxSphere gives them.
bool boxMayHit(const Vector3d& lo, const Vector3d& hi, const Vector3d& center, double halfDiagonal,
               const Vector3d& s, const Vector3d& u, const GougingCone& cone, double cosT, double sinT) {
  double top = 0;  // max of (p - s).u over the box
  for (int k = 0; k < 3; ++k) top += u[k] * ((u[k] > 0 ? hi[k] : lo[k]) - s[k]);
  if (top <= cone.clearance) return false;
  const Vector3d q = s.cwiseMax(lo).cwiseMin(hi);
  if ((q - s).squaredNorm() >= cone.length * cone.length) return false;
  // Bounding sphere against the cone widened by the point radius.
  const Vector3d& c = center;
  const double r = halfDiagonal + cone.radius;
  const Vector3d d = c - s;
  const double a = d.dot(u);
  const double lat = (d - a * u).norm();
  if (lat <= a * cone.tanAngle) return true;
  // Distance from c to the cone surface in the (axial, lateral) half-plane.
  const double along = a * cosT + lat * sinT;
  const double dist = along >= 0 ? lat * cosT - a * sinT : d.norm();
  return dist < r;
}

// The cone at s along u as the search's box tests use it, widened by kMargin (computed once a query).
struct SearchCone {
  Vector3d s, u, absU, tanU;     // absU: |u| per coordinate; tanU: tanAngle u
  double floor, reach2, radius;  // clearance - margin, (length + margin)^2, radius + margin
  SearchCone(const Vector3d& s, const Vector3d& u, const GougingCone& cone)
      : s(s), u(u), absU(u.cwiseAbs()), tanU(cone.tanAngle * u), floor(cone.clearance - kMargin),
        reach2((cone.length + kMargin) * (cone.length + kMargin)), radius(cone.radius + kMargin) {}
};

// Conservative with a margin far above rounding: false only when no point of the box (centre c,
// half its edges halfSize) can be in the cone, i.e. the box lies below the clearance, beyond the
// length, or beyond the cone's tangent plane on the side of c. A point p in the cone has
// (p - s).w <= its distance from the axis < (p - s).u tanAngle + radius for every unit w across
// the axis, so (p - s).(w - tanAngle u) < radius; with w toward c, the box's least value of that
// linear function (at a corner) decides. Sharper than the bounding sphere for the flat cells of a
// layer, whose half-diagonal overstates their reach.
inline bool boxMayHold(const Vector3d& c, const Vector3d& halfSize, const SearchCone& k) {
  const Vector3d d = c - k.s;
  const double a = d.dot(k.u);
  if (a + k.absU.dot(halfSize) <= k.floor) return false;
  if ((d.cwiseAbs() - halfSize).cwiseMax(0.0).squaredNorm() >= k.reach2) return false;
  const Vector3d lateral = d - a * k.u;
  const double lat = lateral.norm();
  // Near the axis the direction toward c is ill-conditioned (and the plane would not reject).
  if (lat <= 1e-3) return true;
  const Vector3d n = (1 / lat) * lateral - k.tanU;
  return d.dot(n) - n.cwiseAbs().dot(halfSize) < k.radius;
}

void boxSphere(const Vector3d& lo, const Vector3d& hi, Vector3d& center, double& halfDiagonal) {
  center = 0.5 * (lo + hi);
  halfDiagonal = 0.5 * (hi - lo).norm();
}

void coneCosSin(const GougingCone& cone, double& cosT, double& sinT) {
  cosT = 1 / std::sqrt(1 + cone.tanAngle * cone.tanAngle);
  sinT = cone.tanAngle * cosT;
}

// Point p in the cone at s along u; lateral, lat: p's offset from the axis and its length.
bool inCone(const Vector3d& p, const Vector3d& s, const Vector3d& u, const GougingCone& cone, Vector3d& lateral,
            double& lat) {
  const Vector3d d = p - s;
  const double a = d.dot(u);
  if (a <= cone.clearance) return false;
  const double len2 = d.squaredNorm();
  if (len2 >= cone.length * cone.length) return false;
  lateral = d - a * u;
  lat = lateral.norm();
  return lat < a * cone.tanAngle + cone.radius;
}

}  // namespace

// Level 0: a cell with its points; above: a box over 2 x 2 x 2 nodes of the level below. Every
// node keeps the bounding box and the least seq of the points under it.
struct PrintedPoints::Node {
  // What the search reads of every node it meets, side by side.
  uint32_t minSeq = std::numeric_limits<uint32_t>::max();
  Vector3d center = Vector3d::Zero();  // of the box (kept with it: queries test it many times)
  Vector3d halfSize = Vector3d::Zero();
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
  Vector3d hi = Vector3d::Constant(-std::numeric_limits<double>::infinity());
  double halfDiagonal = 0;
  Node* parent = nullptr;
  std::vector<Node*> children;  // creation order
  std::vector<Vector3d> points;  // level 0
  std::vector<uint32_t> seq;     // level 0, per point
  uint32_t order = 0;          // cells and blocks: creation index among their level
  const Node* block = nullptr;  // cells: their block
};

struct PrintedPoints::Query {
  Query(const Vector3d& s, const Vector3d& u, uint32_t limit, const GougingCone& cone)
      : s(s), u(u), limit(limit), cone(cone), search(s, u, cone) {
    coneCosSin(cone, cosT, sinT);
  }
  Vector3d s, u;
  uint32_t limit = 0;
  GougingCone cone;
  SearchCone search;
  double cosT = 1, sinT = 0;  // of the cone's half-angle
  mutable const Node* hitCell = nullptr;  // the cell and index of the point found
  mutable size_t hitIndex = 0;
  // Collect the cells that pass instead of testing points, keyed by their place in the scan's
  // order (block, then cell, creation order).
  std::vector<std::pair<uint64_t, const Node*>>* found = nullptr;
};

PrintedPoints::PrintedPoints() : levels_(kTopLevel + 1) {}
PrintedPoints::~PrintedPoints() = default;

void PrintedPoints::add(const Vector3d& p, uint32_t seq) {
  const Eigen::Array3d g = (p.array() / kCell).floor();
  const int64_t x = int64_t(g.x()), y = int64_t(g.y()), z = int64_t(g.z());
  Node* cell = nullptr;
  Node* child = nullptr;
  for (int level = 0; level <= kTopLevel; ++level) {
    const int64_t d = int64_t(1) << level;
    auto [it, fresh] = levels_[size_t(level)].try_emplace(key(floorDiv(x, d), floorDiv(y, d), floorDiv(z, d)));
    if (fresh) {
      it->second = std::make_unique<Node>();
      if (level == 0) it->second->order = cellCount_++;
      if (level == kBlockLevel) it->second->order = blockCount_++;
      if (level == kTopLevel) roots_.push_back(it->second.get());
    }
    Node* n = it->second.get();
    if (level == 0) cell = n;
    if (child) {
      n->children.push_back(child);
      child->parent = n;
    }
    if (!fresh) break;
    child = n;
  }
  if (!cell->block) {
    cell->block = cell;
    for (int level = 0; level < kBlockLevel; ++level) cell->block = cell->block->parent;
  }
  cell->points.push_back(p);
  cell->seq.push_back(seq);
  for (Node* n = cell; n; n = n->parent) {
    n->lo = n->lo.cwiseMin(p);
    n->hi = n->hi.cwiseMax(p);
    boxSphere(n->lo, n->hi, n->center, n->halfDiagonal);
    n->halfSize = 0.5 * (n->hi - n->lo);
    n->minSeq = std::min(n->minSeq, seq);
  }
}

void PrintedPoints::retire(const Vector3d& p, uint32_t seq) {
  const Eigen::Array3d g = (p.array() / kCell).floor();
  auto it = levels_[0].find(key(int64_t(g.x()), int64_t(g.y()), int64_t(g.z())));
  if (it == levels_[0].end()) return;
  Node& c = *it->second;
  for (size_t k = 0; k < c.points.size(); ++k) {
    if (c.seq[k] == seq && c.points[k] == p) c.seq[k] = std::numeric_limits<uint32_t>::max();
  }
}

// The scan's tests of the cell and its block, for a point the point test accepts: the box tests
// of the search only skip boxes without such points, so the answers are those of the scan.
bool PrintedPoints::scanTakes(const Node& cell, const Query& q) const {
  const Node& b = *cell.block;
  return boxMayHit(cell.lo, cell.hi, cell.center, cell.halfDiagonal, q.s, q.u, q.cone, q.cosT, q.sinT) &&
         boxMayHit(b.lo, b.hi, b.center, b.halfDiagonal, q.s, q.u, q.cone, q.cosT, q.sinT);
}

bool PrintedPoints::mayHold(const Node& node, const Query& q) const {
  return node.minSeq < q.limit && boxMayHold(node.center, node.halfSize, q.search);
}

// For a node that passed mayHold.
bool PrintedPoints::visit(const Node& node, int level, const Query& q) const {
  if (level > 0) {
    // Newest first: the material just printed is the likeliest in the way (any order answers the same).
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) {
      if (mayHold(**c, q) && visit(**c, level - 1, q)) return true;
    }
    return false;
  }
  if (q.found) {
    q.found->emplace_back(uint64_t(node.block->order) << 32 | node.order, &node);
    return false;
  }
  Vector3d lateral;
  double lat;
  for (size_t k = 0; k < node.points.size(); ++k) {
    if (node.seq[k] < q.limit && inCone(node.points[k], q.s, q.u, q.cone, lateral, lat)) {
      // The scan's box tests hold for all points of the cell or none.
      if (!scanTakes(node, q)) return false;
      q.hitCell = &node;
      q.hitIndex = k;
      return true;
    }
  }
  return false;
}

bool PrintedPoints::hit(const Vector3d& s, const Vector3d& u, uint32_t limit, const GougingCone& cone,
                        Vector3d* away) const {
  Query q(s, u, limit, cone);
  if (!away) {
    // The point that answered the last query first: the gouging search asks about many axes
    // around one, and one point is often in the way of the next axis too. It answers when it
    // passes the point test and the tests of its cell and block, as in the scan.
    for (int e = 0; e < kRecent && recentCell_[e]; ++e) {
      const Node* c = recentCell_[e];
      const size_t k = recentIndex_[e];
      if (c->seq[k] >= limit) continue;
      Vector3d lateral;
      double lat;
      if (inCone(c->points[k], s, u, cone, lateral, lat) && scanTakes(*c, q)) {
        std::swap(recentCell_[e], recentCell_[0]);
        std::swap(recentIndex_[e], recentIndex_[0]);
        return true;
      }
    }
    for (auto r = roots_.rbegin(); r != roots_.rend(); ++r) {
      if (mayHold(**r, q) && visit(**r, kTopLevel, q)) {
        for (int e = kRecent - 1; e > 0; --e) {
          recentCell_[e] = recentCell_[e - 1];
          recentIndex_[e] = recentIndex_[e - 1];
        }
        recentCell_[0] = q.hitCell;
        recentIndex_[0] = q.hitIndex;
        return true;
      }
    }
    return false;
  }
  // The sum in the scan's order: blocks, then their cells, in creation order.
  std::vector<std::pair<uint64_t, const Node*>> found;
  q.found = &found;
  for (const Node* r : roots_) {
    if (mayHold(*r, q)) visit(*r, kTopLevel, q);
  }
  std::sort(found.begin(), found.end());
  bool any = false;
  // The cells come block by block: each block's test of the scan is made once (at the first cell
  // with a point in the cone), the cell's at its first point in the cone.
  const Node* block = nullptr;
  int blockTakes = -1;
  for (const auto& [order, c] : found) {
    if (c->block != block) {
      block = c->block;
      blockTakes = -1;
    }
    int takes = -1;  // the scan's box tests, once the cell has a point in the cone
    for (size_t k = 0; k < c->points.size(); ++k) {
      Vector3d lateral;
      double lat;
      if (c->seq[k] >= limit || !inCone(c->points[k], s, u, cone, lateral, lat)) continue;
      if (takes < 0) {
        if (blockTakes < 0) blockTakes = boxMayHit(block->lo, block->hi, block->center, block->halfDiagonal, s, u, cone, q.cosT, q.sinT);
        takes = blockTakes && boxMayHit(c->lo, c->hi, c->center, c->halfDiagonal, s, u, cone, q.cosT, q.sinT);
      }
      if (!takes) break;
      any = true;
      if (lat > 1e-9) *away -= lateral / lat;
    }
  }
  return any;
}

}  // namespace omnislice
