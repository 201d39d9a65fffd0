// SPDX-License-Identifier: MIT
#include "pipeline/curved_supports.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <climits>
#include <map>
#include <unordered_map>

#include <Eigen/Geometry>

#include "common/math_constants.h"
#include "geometry/aabb_tree.h"
#include "geometry/segment.h"
#include "toolpath/bead.h"

namespace omnislice {

namespace {

// Consecutive samples of a stretch lie at most this far apart (verify samples every 0.5 mm).
constexpr double kStretchGapMm = 0.6;

bool extruding(const Move& m) {
  return (m.kind == MoveKind::Print || m.kind == MoveKind::Support) && m.filament > 0;
}

int64_t floorOf(double v) { return int64_t(std::floor(v)); }

// Every extruding move of a path sampled every 0.5 mm or closer, its ends included:
// visit(point, move index).
template <class Visit>
void forEachSample(const Toolpath& path, Visit&& visit) {
  Eigen::Vector3d prev = path.start;
  for (size_t k = 0; k < path.moves.size(); ++k) {
    const Move& m = path.moves[k];
    if (extruding(m)) {
      const int pieces = std::max(1, int(std::ceil((m.position - prev).norm() / 0.5)));
      for (int i = 0; i <= pieces; ++i) visit(Eigen::Vector3d(prev + (double(i) / pieces) * (m.position - prev)), k);
    }
    prev = m.position;
  }
}

// A cell's key: 21 bits per coordinate (1 mm cells over +-1 km).
uint64_t cellKey(int64_t x, int64_t y, int64_t z) {
  const uint64_t m = (uint64_t(1) << 21) - 1;
  return ((uint64_t(x) & m) << 42) | ((uint64_t(y) & m) << 21) | (uint64_t(z) & m);
}

// A coordinate of a key back (the 21-bit field sign-extended).
int64_t keyCoordinate(uint64_t key, int shift) {
  const int64_t v = int64_t((key >> shift) & ((uint64_t(1) << 21) - 1));
  return v >= (int64_t(1) << 20) ? v - (int64_t(1) << 21) : v;
}

// Extruding moves as segments in a uniform hash of cells (each segment in the cells its box, grown
// by `grow`, touches).
class SegmentHash {
 public:
  SegmentHash(const Toolpath& path, double cell, double grow) : path_(path), cell_(cell) {
    for (size_t k = 0; k < path.moves.size(); ++k) {
      if (!extruding(path.moves[k])) continue;
      const Eigen::Vector3d a = startOf(k), b = path.moves[k].position;
      const Eigen::Vector3d lo = a.cwiseMin(b).array() - grow, hi = a.cwiseMax(b).array() + grow;
      for (int64_t x = floorOf(lo.x() / cell_); x <= floorOf(hi.x() / cell_); ++x) {
        for (int64_t y = floorOf(lo.y() / cell_); y <= floorOf(hi.y() / cell_); ++y) {
          for (int64_t z = floorOf(lo.z() / cell_); z <= floorOf(hi.z() / cell_); ++z) {
            cells_[cellKey(x, y, z)].push_back(uint32_t(k));
          }
        }
      }
    }
  }

  Eigen::Vector3d startOf(size_t k) const { return k == 0 ? path_.start : path_.moves[k - 1].position; }

  // Visit every segment whose grown box holds p's cell (each at most once per cell).
  template <class Visit>
  void near(const Eigen::Vector3d& p, Visit&& visit) const {
    const auto it = cells_.find(cellKey(floorOf(p.x() / cell_), floorOf(p.y() / cell_), floorOf(p.z() / cell_)));
    if (it == cells_.end()) return;
    for (uint32_t k : it->second) visit(size_t(k));
  }

 private:
  const Toolpath& path_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

// The earliest tool-path move that puts material into a vertical nozzle's cone at a point: the
// extruding moves sampled every 0.5 mm (their ends included), the samples in 1 mm cells, and
// coarser cells of 2 to 64 mm holding their samples' least move index, so a query descends only
// into cells that meet the cone and hold material earlier than the best found. The cone is
// verify's (verify_program.cpp: a sample p counts at tip x when d = p - x has d.z > h + tol,
// |d| < L - tol and a distance from the axis < d.z tan t - tol), widened by the margins below.
class ConeBlocker {
 public:
  // Empty: points are added with add() in any order of their index.
  ConeBlocker(double h, double halfAngleDeg, double length)
      : h_(h), tan_(std::tan(halfAngleDeg * kPi / 180)), length_(length),
        radius_(length * std::sin(halfAngleDeg * kPi / 180)) {}

  // The extruding moves of a tool path (indices in print order).
  ConeBlocker(const Toolpath& path, double h, double halfAngleDeg, double length)
      : ConeBlocker(h, halfAngleDeg, length) {
    sorted_ = true;
    forEachSample(path, [&](const Eigen::Vector3d& p, size_t k) { add(p, uint32_t(k)); });
  }

  void add(const Eigen::Vector3d& p, uint32_t index) {
    const int64_t i = floorOf(p.x()), j = floorOf(p.y()), k = floorOf(p.z());
    std::vector<Point>& cell = points_[cellKey(i, j, k)];
    sorted_ = sorted_ && (cell.empty() || cell.back().move <= index);
    cell.push_back({p, index});
    for (int l = 1; l < kLevels; ++l) {
      auto [it, fresh] = least_[size_t(l)].emplace(cellKey(i >> l, j >> l, k >> l), index);
      if (!fresh) it->second = std::min(it->second, index);
    }
  }

  // The least index with material in the cone at x (SIZE_MAX when none).
  size_t earliest(const Eigen::Vector3d& x) const {
    size_t best = SIZE_MAX;
    const double s = cellAt(kLevels - 1);
    const double r = radius_ + kLateralMargin;
    const Eigen::Vector3d lo(x.x() - r, x.y() - r, x.z() + h_ - kAxialMargin);
    const Eigen::Vector3d hi(x.x() + r, x.y() + r, x.z() + length_ + r);
    for (int64_t i = floorOf(lo.x() / s); i <= floorOf(hi.x() / s); ++i) {
      for (int64_t j = floorOf(lo.y() / s); j <= floorOf(hi.y() / s); ++j) {
        for (int64_t k = floorOf(lo.z() / s); k <= floorOf(hi.z() / s); ++k) descend(kLevels - 1, i, j, k, x, best);
      }
    }
    return best;
  }

 private:
  static constexpr int kLevels = 7;  // 1, 2, 4, ..., 64 mm
  // Verify samples the paths every 0.5 mm from each move's start; its samples lie up to 0.25 mm
  // from these, and a fin's path up to kStretchGapMm / 2 from the copies: the cone is widened by
  // that much (and lowered a little for sloping paths).
  static constexpr double kLateralMargin = 0.35, kAxialMargin = 0.1;
  static double cellAt(int level) { return double(int64_t(1) << level); }

  // Whether the box of cell (i, j, k) at `level` may hold points of the cone at x.
  bool meets(int level, int64_t i, int64_t j, int64_t k, const Eigen::Vector3d& x) const {
    const double s = cellAt(level);
    const double top = double(k + 1) * s - x.z(), bottom = double(k) * s - x.z();
    if (top <= h_ - kAxialMargin || bottom >= length_ + kLateralMargin) return false;
    const double dx = std::max({double(i) * s - x.x(), 0.0, x.x() - double(i + 1) * s});
    const double dy = std::max({double(j) * s - x.y(), 0.0, x.y() - double(j + 1) * s});
    const double horizontal = std::sqrt(dx * dx + dy * dy);
    return horizontal < std::min(top * tan_, radius_) + kLateralMargin;
  }

  void descend(int level, int64_t i, int64_t j, int64_t k, const Eigen::Vector3d& x, size_t& best) const {
    if (!meets(level, i, j, k, x)) return;
    if (level == 0) {
      const auto it = points_.find(cellKey(i, j, k));
      if (it == points_.end()) return;
      for (const auto& [p, move] : it->second) {
        if (move >= best) {
          if (sorted_) break;  // the cell's points are in index order
          continue;
        }
        const Eigen::Vector3d d = p - x;
        if (d.z() <= h_ - kAxialMargin || d.norm() >= length_ + kLateralMargin) continue;
        if (std::sqrt(d.x() * d.x() + d.y() * d.y()) < d.z() * tan_ + kLateralMargin) {
          best = move;
          if (sorted_) break;
        }
      }
      return;
    }
    const auto it = least_[size_t(level)].find(cellKey(i, j, k));
    if (it == least_[size_t(level)].end() || it->second >= best) return;
    for (int c = 0; c < 8; ++c) descend(level - 1, 2 * i + (c & 1), 2 * j + ((c >> 1) & 1), 2 * k + (c >> 2), x, best);
  }

  struct Point {
    Eigen::Vector3d p;
    uint32_t move;
  };
  double h_, tan_, length_, radius_;
  bool sorted_ = false;  // every cell's points in increasing index
  std::unordered_map<uint64_t, std::vector<Point>> points_;
  std::array<std::unordered_map<uint64_t, uint32_t>, kLevels> least_;
};

// Whether tool-path material printed after a given move has a point in its own nozzle cone: the
// extruding moves sampled every 0.5 mm with their nozzle axes, in 1 mm cells, and coarser cells
// of 2 to 64 mm holding the latest move index of their samples, their mean axis and how far
// (angle) their axes stray from it, so a query descends only into cells printed late enough whose
// cones can reach the point: a cell of centre c and half diagonal r, seen from x at distance D,
// holds directions within asin(r / D) of x - c.
class LaterCones {
 public:
  LaterCones(const Toolpath& path, double h, double halfAngleDeg, double length)
      : h_(h), t_(halfAngleDeg * kPi / 180), length_(length) {
    forEachSample(path, [&](const Eigen::Vector3d& p, size_t k) {
      const Eigen::Vector3d u = path.moves[k].axis.normalized();
      const int64_t a = floorOf(p.x()), b = floorOf(p.y()), c = floorOf(p.z());
      points_[cellKey(a, b, c)].push_back({p, u, uint32_t(k)});
      for (int l = 1; l < kLevels; ++l) {
        Cell& cell = cells_[size_t(l)][cellKey(a >> l, b >> l, c >> l)];
        cell.latest = std::max(cell.latest, uint32_t(k));
        cell.axis += u;
      }
    });
    // The spread of the axes about each cell's mean: from the points at level 1, from the
    // children above it.
    for (int l = 1; l < kLevels; ++l) {
      for (auto& [key, cell] : cells_[size_t(l)]) {
        cell.axis = cell.axis.norm() > 1e-12 ? Eigen::Vector3d(cell.axis.normalized()) : Eigen::Vector3d::UnitZ();
      }
    }
    for (const auto& [key, pts] : points_) {
      const int64_t a = keyCoordinate(key, 42), b = keyCoordinate(key, 21), c = keyCoordinate(key, 0);
      Cell& parent = cells_[1][cellKey(a >> 1, b >> 1, c >> 1)];
      for (const Point& q : pts) parent.spread = std::max(parent.spread, angle(parent.axis, q.u));
    }
    for (int l = 2; l < kLevels; ++l) {
      for (const auto& [key, child] : cells_[size_t(l - 1)]) {
        const int64_t a = keyCoordinate(key, 42), b = keyCoordinate(key, 21), c = keyCoordinate(key, 0);
        Cell& parent = cells_[size_t(l)][cellKey(a >> 1, b >> 1, c >> 1)];
        parent.spread = std::max(parent.spread, angle(parent.axis, child.axis) + child.spread);
      }
    }
  }

  // True when a sample of a move after `after` has x in its cone.
  bool reaches(const Eigen::Vector3d& x, size_t after) const {
    const double s = double(int64_t(1) << (kLevels - 1)), r = length_ + kMargin;
    for (int64_t i = floorOf((x.x() - r) / s); i <= floorOf((x.x() + r) / s); ++i) {
      for (int64_t j = floorOf((x.y() - r) / s); j <= floorOf((x.y() + r) / s); ++j) {
        for (int64_t k = floorOf((x.z() - r) / s); k <= floorOf((x.z() + r) / s); ++k) {
          if (descend(kLevels - 1, i, j, k, x, after)) return true;
        }
      }
    }
    return false;
  }

 private:
  static constexpr int kLevels = 7;          // 1, 2, 4, ..., 64 mm
  static constexpr double kMargin = 0.35, kAxialMargin = 0.1;  // as ConeBlocker's margins
  struct Point {
    Eigen::Vector3d p, u;
    uint32_t move;
  };
  struct Cell {
    uint32_t latest = 0;
    Eigen::Vector3d axis{0, 0, 0};
    double spread = 0;  // largest angle of a sample's axis from `axis`, rad
  };
  static double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b));
  }

  bool descend(int level, int64_t i, int64_t j, int64_t k, const Eigen::Vector3d& x, size_t after) const {
    const double s = double(int64_t(1) << level);
    const Eigen::Vector3d lo(double(i) * s, double(j) * s, double(k) * s);
    const Eigen::Vector3d c = lo + Eigen::Vector3d::Constant(0.5 * s);
    const double half = 0.5 * std::sqrt(3.0) * s;
    const Eigen::Vector3d v = x - c;
    const double dist = v.norm();
    if (dist - half >= length_ + kMargin) return false;
    if (level == 0) {
      const auto it = points_.find(cellKey(i, j, k));
      if (it == points_.end()) return false;
      for (const Point& q : it->second) {
        if (q.move <= after) continue;
        const Eigen::Vector3d d = x - q.p;
        const double axial = d.dot(q.u);
        if (axial <= h_ - kAxialMargin || d.norm() >= length_ + kMargin) continue;
        if ((d - axial * q.u).norm() < axial * std::tan(t_) + kMargin) return true;
      }
      return false;
    }
    const auto it = cells_[size_t(level)].find(cellKey(i, j, k));
    if (it == cells_[size_t(level)].end() || it->second.latest <= after) return false;
    if (dist > half + kMargin) {
      const double seen = std::asin(std::min(1.0, (half + kMargin) / dist));
      if (angle(it->second.axis, v) > t_ + it->second.spread + seen) return false;
    }
    for (int q = 0; q < 8; ++q) {
      if (descend(level - 1, 2 * i + (q & 1), 2 * j + ((q >> 1) & 1), 2 * k + (q >> 2), x, after)) return true;
    }
    return false;
  }

  double h_, t_, length_;
  std::unordered_map<uint64_t, std::vector<Point>> points_;
  std::array<std::unordered_map<uint64_t, Cell>, kLevels> cells_;
};

struct Hit {
  size_t move = 0;        // the extruding move the sample lies on
  double t = 0;           // its parameter along the move
  Eigen::Vector3d p;      // the sample
  double top = 0;         // the highest copy's tip height (a support layer j h)
  double land = 0;        // what the column stands on: the platform (0) or the part's surface
  int levels = 0;         // copies under the sample (0: no column)
  std::vector<size_t> at; // per copy from the top (at[0] = the highest): where it is printed
};

// A piece of a fin on one support layer: consecutive samples of a stretch printed at one place.
struct Piece {
  std::vector<Eigen::Vector3d> line;
  double z = 0;  // its support layer's height
};

}  // namespace

CurvedSupportResult addCurvedSupports(const Toolpath& path, const Mesh& part, const std::vector<float>& unsupported,
                                      const CurvedSupportOptions& o, const ProgressFn& progress) {
  CurvedSupportResult r;
  r.samples = unsupported.size() / 3;
  const double h = o.layerHeightMm, w = o.lineWidthMm;
  const size_t n = path.moves.size();

  // Runs of consecutive extruding moves: the first move of each move's run.
  std::vector<size_t> runStart(n, 0);
  for (size_t k = 0; k < n; ++k) {
    runStart[k] = (k > 0 && extruding(path.moves[k]) && extruding(path.moves[k - 1])) ? runStart[k - 1] : k;
  }

  // 1. Each sample on its move.
  const SegmentHash hash(path, 1.0, std::max(o.matchMm, w + h));
  std::vector<Hit> hits;
  for (size_t i = 0; i + 2 < unsupported.size(); i += 3) {
    const Eigen::Vector3d p(unsupported[i], unsupported[i + 1], unsupported[i + 2]);
    double best = o.matchMm * o.matchMm;
    Hit hit;
    bool found = false;
    hash.near(p, [&](size_t k) {
      const Eigen::Vector3d a = hash.startOf(k), b = path.moves[k].position;
      const double d2 = pointSegmentDistance2(p, a, b);
      if (d2 < best || (d2 == best && found && k < hit.move)) {
        best = d2;
        hit.move = k;
        const double l2 = (b - a).squaredNorm();
        hit.t = l2 > 0 ? std::clamp((p - a).dot(b - a) / l2, 0.0, 1.0) : 0.0;
        found = true;
      }
    });
    if (!found) continue;
    hit.p = p;
    hits.push_back(hit);
  }
  r.matched = hits.size();
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
    return a.move != b.move ? a.move < b.move : a.t < b.t;
  });

  // Where a copy printed before move m goes: after the retraction that ends the path before m's
  // run (or where that path ends when it does not retract), before the travel to the run.
  auto insertionBefore = [&](size_t m) {
    if (m >= n) return n;
    size_t t = runStart[m];
    while (t > 0 && !extruding(path.moves[t - 1])) --t;
    return t < runStart[m] && path.moves[t].kind == MoveKind::Retract ? t + 1 : t;
  };

  // 2. The columns: what lies under each sample on its vertical line, and where each copy is
  // printed: before the path holding the sample, before any material enters the vertical nozzle's
  // cone at the copy, and before the copy above it.
  const AabbTree tree(part);
  const ConeBlocker cones(path, h, o.coneHalfAngleDeg, o.coneLengthMm);
  std::vector<ColumnCrossing> crossings;
  for (Hit& hit : hits) {
    crossings.clear();
    tree.columnCrossings(hit.p.x(), hit.p.y(), crossings);
    std::sort(crossings.begin(), crossings.end(), [](const ColumnCrossing& a, const ColumnCrossing& b) {
      return a.z < b.z;
    });
    // The underside: the highest face looking down at most w/2 above the sample's tip.
    int under = -1;
    for (int c = 0; c < int(crossings.size()); ++c) {
      if (crossings[size_t(c)].z <= hit.p.z() + 0.5 * w && crossings[size_t(c)].sign > 0) under = c;
    }
    if (under < 0 || hit.p.z() - crossings[size_t(under)].z > 1.5 * h) {
      ++r.notUnderside;
      continue;
    }
    hit.land = under > 0 && crossings[size_t(under) - 1].sign < 0 ? crossings[size_t(under) - 1].z : 0.0;
    // Copies on the heights j h (planar support layers shared by every column): the highest
    // within [h/2, 3h/2) under the sample, the lowest at least h/2 over what it rests on.
    const int jTop = int(std::floor((hit.p.z() - 0.5 * h) / h));
    const int jBottom = std::max(1, int(std::ceil((hit.land + 0.5 * h) / h - 1e-9)));
    hit.top = double(jTop) * h;
    hit.levels = std::max(0, jTop - jBottom + 1);
    if (hit.levels == 0) ++r.blocked;
  }

  // Where each copy is printed, highest copies first: before the path holding its sample, before
  // the copy above it, before any tool-path material enters the vertical nozzle's cone at it, and
  // no later than any copy in that cone (at the same place the lower pieces are printed first).
  struct Copy {
    size_t hit;
    int level;  // 1 = the highest
    double z;
  };
  for (const Hit& hit : hits) r.copies += size_t(hit.levels);
  if (r.copies > o.maxCopies) return r;
  std::vector<Copy> copies;
  for (size_t i = 0; i < hits.size(); ++i) {
    hits[i].at.assign(size_t(hits[i].levels), n);
    for (int k = 1; k <= hits[i].levels; ++k) copies.push_back({i, k, hits[i].top - double(k - 1) * h});
  }
  std::stable_sort(copies.begin(), copies.end(), [](const Copy& a, const Copy& b) { return a.z > b.z; });
  ConeBlocker finCones(h, o.coneHalfAngleDeg, o.coneLengthMm);
  for (size_t ci = 0; ci < copies.size(); ++ci) {
    const Copy& c = copies[ci];
    if ((ci & 4095) == 0 && !reportProgress(progress, "supports", 0.9 * double(ci) / double(copies.size()))) {
      r.cancelled = true;
      return r;
    }
    Hit& hit = hits[c.hit];
    const Eigen::Vector3d x(hit.p.x(), hit.p.y(), c.z);
    size_t at = c.level == 1 ? insertionBefore(runStart[hit.move]) : hit.at[size_t(c.level - 2)];
    at = std::min({at, insertionBefore(cones.earliest(x)), finCones.earliest(x)});
    hit.at[size_t(c.level - 1)] = at;
    finCones.add(x, uint32_t(at));
  }

  // A column is dropped when a path printed after one of its copies would put that copy in its
  // nozzle cone.
  const LaterCones later(path, h, o.coneHalfAngleDeg, o.coneLengthMm);
  for (Hit& hit : hits) {
    if (hit.levels == 0) continue;
    bool struck = false;
    for (int k = 0; !struck && k < hit.levels; ++k) {
      struck = later.reaches(Eigen::Vector3d(hit.p.x(), hit.p.y(), hit.top - double(k) * h), hit.at[size_t(k)]);
    }
    // The surface it lands on must be printed before its lowest copy.
    bool landsLater = false;
    if (!struck && hit.land > 0) {
      const Eigen::Vector3d q(hit.p.x(), hit.p.y(), hit.land);
      const size_t before = hit.at.back();
      const double reach = w + h;
      bool printed = false;
      hash.near(q, [&](size_t k) {
        printed = printed ||
                  (k < before && pointSegmentDistance2(q, hash.startOf(k), path.moves[k].position) <= reach * reach);
      });
      landsLater = !printed;
    }
    if (struck || landsLater) {
      hit.levels = 0;
      hit.at.clear();
      ++r.blocked;
      ++(struck ? r.inLaterCones : r.landsLater);
      continue;
    }
    ++r.columns;
    if (hit.land == 0) ++r.onPlatform;
  }

  // 3. Stretches along the beads; their copies cut where consecutive samples are printed at
  // different places.
  std::map<size_t, std::vector<Piece>> blocks;  // insertion index -> the pieces printed there
  size_t s0 = 0;
  while (s0 < hits.size()) {
    size_t s1 = s0 + 1;
    while (s1 < hits.size() && runStart[hits[s1].move] == runStart[hits[s0].move] &&
           (hits[s1].p - hits[s1 - 1].p).norm() <= kStretchGapMm) {
      ++s1;
    }
    // The support layers the stretch's columns cross, and a sample's copy on layer j.
    int jLow = INT32_MAX, jHigh = INT32_MIN;
    auto topOf = [&](size_t q) { return int(std::lround(hits[q].top / h)); };
    for (size_t i = s0; i < s1; ++i) {
      if (hits[i].levels == 0) continue;
      jHigh = std::max(jHigh, topOf(i));
      jLow = std::min(jLow, topOf(i) - hits[i].levels + 1);
    }
    if (jHigh >= jLow) ++r.fins;
    auto has = [&](size_t q, int layer) {
      return hits[q].levels > 0 && layer <= topOf(q) && layer > topOf(q) - hits[q].levels;
    };
    auto placeOf = [&](size_t q, int layer) { return hits[q].at[size_t(topOf(q) - layer)]; };
    for (int layer = jLow; layer <= jHigh; ++layer) {
      size_t i = s0;
      while (i < s1) {
        if (!has(i, layer)) {
          ++i;
          continue;
        }
        const size_t where = placeOf(i, layer);
        size_t j = i + 1;
        while (j < s1 && has(j, layer) && placeOf(j, layer) == where) ++j;
        auto copy = [&](size_t q) { return Eigen::Vector3d(hits[q].p.x(), hits[q].p.y(), double(layer) * h); };
        Piece piece;
        if (j - i == 1) {
          // One sample: a dash of one line width along its move.
          Eigen::Vector3d d = path.moves[hits[i].move].position - hash.startOf(hits[i].move);
          d.z() = 0;
          d = d.norm() > 1e-9 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::UnitX();
          piece.line = {copy(i) - 0.5 * w * d, copy(i) + 0.5 * w * d};
        } else {
          for (size_t q = i; q < j; ++q) piece.line.push_back(copy(q));
        }
        piece.z = double(layer) * h;
        blocks[where].push_back(std::move(piece));
        i = j;
      }
    }
    s0 = s1;
  }

  // 4. The tool path with the pieces in it: at each place the lowest support layer first, printed
  // with the nozzle vertical; after a retraction the filament is pushed back for them and pulled
  // again after them.
  r.toolpath.start = path.start;
  r.toolpath.layerCount = path.layerCount;
  r.toolpath.moves.reserve(n);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  auto block = blocks.begin();
  for (size_t k = 0; k <= n; ++k) {
    if (block != blocks.end() && block->first == k) {
      std::vector<Piece>& pieces = block->second;
      std::stable_sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) { return a.z < b.z; });
      const int32_t layer = k < n ? path.moves[k].layer : (n > 0 ? path.moves[n - 1].layer : 0);
      const bool retracted = k > 0 && path.moves[k - 1].kind == MoveKind::Retract && o.retractMm > 0;
      Move m;
      m.axis = up;
      m.layer = layer;
      for (size_t pi = 0; pi < pieces.size(); ++pi) {
        const std::vector<Eigen::Vector3d>& line = pieces[pi].line;
        m.position = line.front();
        m.kind = MoveKind::Travel;
        m.feature = Feature::None;
        m.width = m.height = m.filament = 0;
        m.speed = o.travelSpeedMmS;
        r.toolpath.moves.push_back(m);
        if (pi == 0 && retracted) {
          m.kind = MoveKind::Unretract;
          m.filament = o.retractMm;
          m.speed = o.retractSpeedMmS;
          r.toolpath.moves.push_back(m);
        }
        for (size_t q = 1; q < line.size(); ++q) {
          const double len = (line[q] - line[q - 1]).norm();
          m.position = line[q];
          m.kind = MoveKind::Support;
          m.feature = Feature::Support;
          m.width = w;
          m.height = h;
          m.filament = filamentForBead(w, h, len, o.filamentDiameterMm);
          m.speed = o.speedMmS;
          r.toolpath.moves.push_back(m);
          r.pathMm += len;
          r.filamentMm += m.filament;
        }
        ++r.beads;
      }
      if (retracted) {
        m.kind = MoveKind::Retract;
        m.feature = Feature::None;
        m.width = m.height = 0;
        m.filament = -o.retractMm;
        m.speed = o.retractSpeedMmS;
        r.toolpath.moves.push_back(m);
      }
      ++block;
    }
    if (k < n) r.toolpath.moves.push_back(path.moves[k]);
  }
  return r;
}

}  // namespace omnislice
