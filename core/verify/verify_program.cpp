// SPDX-License-Identifier: MIT
// Verification by simulation (PROGRAM-FORMAT.md "What verification measures").
//
// Definitions made precise here:
// - Samples: every sampleSpacing mm along each extruding move (filament > 0, length > 0),
//   starting at the move's start; a move shorter than the spacing gives one sample.
// - Bead: a maximal run of consecutive extruding moves, each starting where the previous ended.
// - Reach of a centre-line segment [a, b] with nozzle axis u at grid point p: c = closest point of
//   the segment to p, d = p - c, axial = d.u, lateral = |d - (d.u) u|; covered when
//   (axial / (0.75 h))^2 + (lateral / (0.75 w))^2 <= 1.
// - Collision cone at sample s (axis u, half-angle t, length L, tolerance 0.001 mm): an earlier
//   sample p with d = p - s counts when d.u > h + tol, |d| < L - tol and the distance of p from
//   the axis is < (d.u) tan t - tol.
//
// Complexity (n samples, m segments, F triangles, G grid points):
// - inside / surface distance: each triangle visits the samples of a cell grid near it (the least
//   squared distance below w^2 per sample), one winding query per run of samples not within w/2:
//   O(n + F * samples near a triangle) typical.
// - supported: each centre-line piece (<= one hash cell long) is inserted into the cells its
//   1.5 h neighbourhood touches; one cell lookup per sample, its pieces laid before the sample
//   scanned latest first (found by binary search): O(n + m) typical.
// - collisions: O(1) per sample while all earlier material lies at or below the sample's plane
//   orthogonal to u plus h (every layer-by-layer print); otherwise a descent through 128 / 64 /
//   ... / 2 / 1 mm cells of the earlier samples, skipping every cell whose box lies below that
//   plane, beyond the cone length or outside the cone, with early exit: O(cells near the cone +
//   samples in it).
// - coverage: one vertical-line query per grid column, each triangle clearing the candidates
//   within w/2 of it (O(F) point tests near the surface, none deep inside), and a rasterisation of
//   each segment's reach over the grid cells near it: O(G + F + path * reach).
#include "verify/verify_program.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/math_constants.h"
#include "common/memory_budget.h"
#include "geometry/aabb_tree.h"
#include "geometry/segment.h"
#include "kinematics/kinematics.h"

namespace omnislice {

namespace {

constexpr double kMaxCoordinate = 1e6;  // mm

struct Segment {
  Eigen::Vector3d a, b, u;
  double length = 0;
  double beadStart = 0;  // arc length within its bead at a
  int bead = 0;
  int layer = -1;
  int line = 0;
  bool support = false;  // a support feature: outside the part by design
};

struct Sample {
  Eigen::Vector3d p;
  int segment = 0;   // its segment (nozzle axis, bead, layer, line)
  double beadS = 0;  // arc length within its bead
};

int64_t cellKey(int64_t x, int64_t y, int64_t z) {
  const int64_t o = 1 << 20;
  return ((x + o) & 0x1FFFFF) | (((y + o) & 0x1FFFFF) << 21) | (((z + o) & 0x1FFFFF) << 42);
}

class Bits {
 public:
  explicit Bits(size_t n = 0) : w_((n + 63) / 64, 0) {}
  void set(size_t i) { w_[i >> 6] |= uint64_t(1) << (i & 63); }
  void clear(size_t i) { w_[i >> 6] &= ~(uint64_t(1) << (i & 63)); }
  bool get(size_t i) const { return (w_[i >> 6] >> (i & 63)) & 1; }
  size_t countAnd(const Bits& o) const {
    size_t c = 0;
    for (size_t k = 0; k < w_.size(); ++k) c += __builtin_popcountll(w_[k] & o.w_[k]);
    return c;
  }
  size_t count() const { return countAnd(*this); }

 private:
  std::vector<uint64_t> w_;
};

// Periodic progress with cancellation.
struct Progress {
  const ProgressFn& fn;
  bool cancelled = false;
  bool tick(size_t i, size_t n, double from, double to) {
    if (cancelled) return false;
    if ((i & 4095) != 0) return true;
    const double f = n ? from + (to - from) * double(i) / double(n) : from;
    if (!reportProgress(fn, "verify", f)) cancelled = true;
    return !cancelled;
  }
};

// Each triangle of m with indices in range (as AabbTree), its corners and its bounding box grown
// by reach: visit(a, b, c, lo, hi). Progress ticks over the faces in [from, to]; false when
// cancelled.
template <class Visit>
bool forEachTriangleBox(const Mesh& m, double reach, Progress& progress, double from, double to, Visit&& visit) {
  const size_t nv = m.vertexCount(), faces = m.faceCount();
  for (size_t f = 0; f < faces; ++f) {
    if (!progress.tick(f, faces, from, to)) return false;
    const uint32_t* t = &m.triangles[3 * f];
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv) continue;
    const Eigen::Vector3d a = m.vertex(t[0]), b = m.vertex(t[1]), c = m.vertex(t[2]);
    const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c).array() - reach,
                          hi = a.cwiseMax(b).cwiseMax(c).array() + reach;
    visit(a, b, c, lo, hi);
  }
  return true;
}

// The samples bucketed into a dense grid of cells (CSR), for visiting those in a box. The cell
// size starts at `cell` and grows until the grid has at most about two cells per sample.
class SampleGrid {
 public:
  SampleGrid(const std::vector<Sample>& samples, double cell) : size_(cell) {
    const double inf = std::numeric_limits<double>::infinity();
    lo_ = Eigen::Vector3d::Constant(inf);
    Eigen::Vector3d hi = -lo_;
    for (const Sample& s : samples) {
      lo_ = lo_.cwiseMin(s.p);
      hi = hi.cwiseMax(s.p);
    }
    if (samples.empty()) return;
    const double maxCells = std::max(double(1 << 20), 2.0 * double(samples.size()));
    for (;;) {
      double cells = 1;
      for (int a = 0; a < 3; ++a) {
        dims_[a] = int64_t(std::floor((hi[a] - lo_[a]) / size_)) + 1;
        cells *= double(dims_[a]);
      }
      if (cells <= maxCells) break;
      size_ *= 1.5;
    }
    const size_t cellCount = size_t(dims_[0] * dims_[1] * dims_[2]);
    std::vector<uint32_t> cellOf(samples.size());
    offsets_.assign(cellCount + 1, 0);
    for (size_t i = 0; i < samples.size(); ++i) {
      int64_t c[3];
      for (int a = 0; a < 3; ++a) c[a] = clampIndex((samples[i].p[a] - lo_[a]) / size_, a);
      cellOf[i] = uint32_t((c[2] * dims_[1] + c[1]) * dims_[0] + c[0]);
      ++offsets_[cellOf[i] + 1];
    }
    for (size_t c = 0; c < cellCount; ++c) offsets_[c + 1] += offsets_[c];
    items_.resize(samples.size());
    std::vector<uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (size_t i = 0; i < samples.size(); ++i) items_[fill[cellOf[i]]++] = uint32_t(i);
  }

  // Calls visit(sample index) for every sample in the cells the box [lo, hi] touches (a superset
  // of the samples in the box).
  template <class Visit>
  void forEachIn(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Visit&& visit) const {
    if (items_.empty()) return;
    int64_t c0[3], c1[3];
    for (int a = 0; a < 3; ++a) {
      const double f0 = (lo[a] - lo_[a]) / size_, f1 = (hi[a] - lo_[a]) / size_;
      if (f1 < 0 || f0 >= double(dims_[a])) return;
      c0[a] = clampIndex(f0, a);
      c1[a] = clampIndex(f1, a);
    }
    for (int64_t z = c0[2]; z <= c1[2]; ++z)
      for (int64_t y = c0[1]; y <= c1[1]; ++y) {
        const size_t row = size_t((z * dims_[1] + y) * dims_[0]);
        for (uint32_t e = offsets_[row + size_t(c0[0])]; e < offsets_[row + size_t(c1[0]) + 1]; ++e) {
          visit(items_[e]);
        }
      }
  }

 private:
  int64_t clampIndex(double f, int a) const {
    return std::clamp(int64_t(std::floor(std::max(f, 0.0))), int64_t(0), dims_[a] - 1);
  }
  double size_;
  Eigen::Vector3d lo_;
  int64_t dims_[3] = {0, 0, 0};
  std::vector<uint32_t> offsets_, items_;
};

// The nozzle cone at a sample (PROGRAM-FORMAT.md, collisions) and the tests on it.
struct Cone {
  Eigen::Vector3d tip, u;
  double level = 0;  // tip.u + h + tol: earlier material at or below this height along u is clear
  double h = 0, tol = 0, length = 0, tanT = 0;
  double cosT = 0, sinT = 0;  // of the half-angle, from tanT; both 0 when the cone is not narrow

  // Largest x.u over the box [lo, hi].
  double support(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
    double s = 0;
    for (int k = 0; k < 3; ++k) s += u[k] * (u[k] > 0 ? hi[k] : lo[k]);
    return s;
  }
  // The point p strictly inside the cone (the definition of a collision).
  bool hits(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = p - tip;
    const double a = d.dot(u);
    if (a <= h + tol) return false;
    const double len2 = d.squaredNorm();
    if (len2 >= (length - tol) * (length - tol)) return false;
    const double lat = std::sqrt(std::max(0.0, len2 - a * a));
    return lat < a * tanT - tol;
  }
  // The box tests of the scan in print order: a box wholly at or below the level, or at least the
  // cone length away, holds no point the cone hits.
  bool boxClear(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
    if (support(lo, hi) <= level) return true;
    const Eigen::Vector3d q = tip.cwiseMax(lo).cwiseMin(hi);
    return (q - tip).norm() >= length;
  }
  // A further test that only prunes: the ball around the box lies outside the (untrimmed) cone by
  // more than 1e-6 mm. In the meridian plane of the ball's centre c (axial a, lateral l), the cone
  // lies on the side l cos t - a sin t <= 0 of its edge line, and 3D distances are at least the
  // meridian ones; a point hit lies inside the cone by about tol, far more than rounding.
  bool ballOutside(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
    if (!(cosT > 0)) return false;
    const Eigen::Vector3d d = 0.5 * (lo + hi) - tip;
    const double a = d.dot(u);
    const double lateral = (d - a * u).norm();
    return lateral * cosT - a * sinT > 0.5 * (hi - lo).norm() + 1e-6;
  }
};

// The earlier samples of the collision test in a hierarchy of cells of 1, 2, 4, ..., 128 mm, each
// node with the box of its samples; the 2 mm cells are those of the scan in print order (keyed and
// ordered as that scan needs). Samples are added in print order, lazily (addUpTo) when a cone has
// to look at them. A node's box contains its children's boxes, so the support and distance tests
// clear it only when they clear every cell under it (min, max, sums and the square root round
// monotonically).
class EarlierSamples {
 public:
  static constexpr double kCell = 2.0;  // the cells of the scan in print order

  explicit EarlierSamples(const std::vector<Sample>& samples) : samples_(samples) {
    for (int l = 0; l < kLevels; ++l) lastKey_[l] = std::numeric_limits<int64_t>::min();
  }

  void addUpTo(size_t end) {
    for (; added_ < end; ++added_) {
      const Eigen::Vector3d& p = samples_[added_].p;
      // p / kFine and p / kCell are exact (powers of two), so floor(p / kCell), the scan's cell,
      // is the finest index shifted right (floor division by 2).
      const int64_t c[3] = {int64_t(std::floor(p.x() / kFine)), int64_t(std::floor(p.y() / kFine)),
                            int64_t(std::floor(p.z() / kFine))};
      uint32_t child = uint32_t(added_);
      bool childFresh = true;
      for (int l = 0; l < kLevels; ++l) {  // cells of 2^l mm
        const int64_t key = cellKey(c[0] >> l, c[1] >> l, c[2] >> l);
        bool fresh = false;
        if (key != lastKey_[l]) {
          auto [it, inserted] = index_[l].try_emplace(key, uint32_t(nodes_[l].size()));
          if (inserted) {
            nodes_[l].push_back({p, p, {}, {}});
            fresh = true;
          }
          lastKey_[l] = key;
          lastId_[l] = it->second;
        }
        Node& n = nodes_[l][lastId_[l]];
        n.lo = n.lo.cwiseMin(p);
        n.hi = n.hi.cwiseMax(p);
        if (childFresh) n.children.push_back(child);
        if (l == kScanLevel) n.samples.push_back(uint32_t(added_));
        childFresh = fresh;
        child = lastId_[l];
      }
      if (childFresh) top_.push_back(child);
    }
  }

  // Some earlier sample (all added) inside the cone.
  bool anyHit(const Cone& cone) const {
    for (uint32_t id : top_) {
      if (anyHit(kLevels - 1, id, cone)) return true;
    }
    return false;
  }

  // The first earlier sample inside the cone in the order of the plain scan: the occupied cells in
  // the order they were first occupied, or (when there are more of them than cells in the box of
  // side 2 ceil(L / C) + 1 around the tip) the cells of that box, x then y then z; the samples of
  // a cell in print order. Returns false when there is none.
  bool firstHitInScanOrder(const Cone& cone, uint32_t& hitPoint) const {
    auto checkCell = [&](const Node& cell) {
      if (cone.boxClear(cell.lo, cell.hi)) return false;
      for (uint32_t pi : cell.samples) {
        if (cone.hits(samples_[pi].p)) {
          hitPoint = pi;
          return true;
        }
      }
      return false;
    };
    const std::vector<Node>& cells = nodes_[kScanLevel];
    const int64_t span = int64_t(std::ceil(cone.length / kCell));
    const size_t boxCells = size_t(2 * span + 1) * size_t(2 * span + 1) * size_t(2 * span + 1);
    if (cells.size() < boxCells) {
      for (const Node& cell : cells) {
        if (checkCell(cell)) return true;
      }
      return false;
    }
    const Eigen::Vector3d& p = cone.tip;
    const int64_t cx = int64_t(std::floor(p.x() / kCell)), cy = int64_t(std::floor(p.y() / kCell)),
                  cz = int64_t(std::floor(p.z() / kCell));
    for (int64_t x = cx - span; x <= cx + span; ++x)
      for (int64_t y = cy - span; y <= cy + span; ++y)
        for (int64_t z = cz - span; z <= cz + span; ++z) {
          auto it = index_[kScanLevel].find(cellKey(x, y, z));
          if (it != index_[kScanLevel].end() && checkCell(cells[it->second])) return true;
        }
    return false;
  }

 private:
  static constexpr int kLevels = 8;     // 1, 2, 4, ..., 128 mm
  static constexpr int kScanLevel = 1;  // the 2 mm cells
  static constexpr double kFine = 1.0;  // kCell / 2
  struct Node {
    Eigen::Vector3d lo, hi;
    std::vector<uint32_t> children;  // level 0: samples; else nodes one level down
    std::vector<uint32_t> samples;   // the scan's cells: their samples in print order
  };

  bool anyHit(int l, uint32_t id, const Cone& cone) const {
    const Node& n = nodes_[l][id];
    if (cone.boxClear(n.lo, n.hi) || cone.ballOutside(n.lo, n.hi)) return false;
    if (l == 0) {
      for (uint32_t pi : n.children) {
        if (cone.hits(samples_[pi].p)) return true;
      }
      return false;
    }
    for (uint32_t c : n.children) {
      if (anyHit(l - 1, c, cone)) return true;
    }
    return false;
  }

  const std::vector<Sample>& samples_;
  size_t added_ = 0;
  std::vector<Node> nodes_[kLevels];
  std::unordered_map<int64_t, uint32_t> index_[kLevels];
  int64_t lastKey_[kLevels];
  uint32_t lastId_[kLevels] = {};
  std::vector<uint32_t> top_;  // nodes of the top level
};

Outcome cancelled() { return failed<Outcome>(Status::Cancelled, "verify cancelled"); }

// The program, part mesh and options: their failure (unreadable, empty, non-finite, out of range).
Outcome checkVerifyInput(const ParsedProgram& program, const Mesh& partMesh, const VerifyOptions& options) {
  auto fail = [](Status s, const std::string& msg) { return failed<Outcome>(s, msg); };
  if (!program.ok()) return fail(program.status, "program not readable: " + program.message);
  if (partMesh.empty()) return fail(Status::EmptyInput, "part mesh has no triangles");
  for (double v : partMesh.positions) {
    if (!std::isfinite(v)) return fail(Status::NonFiniteVertex, "part mesh has a non-finite vertex");
    if (std::abs(v) > kMaxCoordinate) {
      return fail(Status::InvalidOption, "part mesh has a coordinate beyond 1e6 mm");
    }
  }
  const double h = program.layerHeight, w = program.lineWidth;
  if (!(h > 0) || !(w > 0) || !std::isfinite(h) || !std::isfinite(w)) {
    return fail(Status::InvalidOption, "program declares no positive layer_height / line_width");
  }
  if (!(options.sampleSpacing > 0) || !std::isfinite(options.sampleSpacing) ||
      options.gridSpacing < 0 || !std::isfinite(options.gridSpacing)) {
    return fail(Status::InvalidOption, "sample spacing must be > 0 and grid spacing >= 0");
  }
  return {};
}

// ---- limits, extrusion, segments ----
// Limits by value index (machineLimits(): axis letters of G-code kinds, joint limits of robot6).
// A move cut into pieces by the reader counts once, by its end (its last piece): the values
// change linearly, so a move within limits at both ends is within them all along. The extruding
// moves become segments, grouped in beads. InvalidOption for a coordinate beyond 1e6 mm.
Outcome extrudingSegments(const ParsedProgram& program, std::vector<Segment>& segments, VerifyReport& rep) {
  const std::vector<std::pair<double, double>> limits = machineLimits(program.machine);
  const auto supportAt = std::find(program.features.begin(), program.features.end(), "support");
  const int support = supportAt == program.features.end() ? -1 : int(supportAt - program.features.begin());
  int bead = -1;
  bool prevExtruding = false;
  Eigen::Vector3d prevEnd(0, 0, 0);
  double beadS = 0;
  for (size_t mi = 0; mi < program.moves.size(); ++mi) {
    const ProgramMove& m = program.moves[mi];
    const bool lastPiece = m.line <= 0 || mi + 1 == program.moves.size() ||
                           program.moves[mi + 1].line != m.line;
    for (size_t i = 0; lastPiece && i < limits.size() && i < m.axes.size(); ++i) {
      if (m.axes[i] < limits[i].first - 1e-9 || m.axes[i] > limits[i].second + 1e-9) {
        ++rep.limitViolations;
        break;
      }
    }
    if (m.filament > 0) rep.extrusionMm += m.filament;
    // Hash-cell and grid indices are 64-bit integers: keep coordinates in a sane range.
    if (m.from.cwiseAbs().maxCoeff() > kMaxCoordinate || m.to.cwiseAbs().maxCoeff() > kMaxCoordinate ||
        !m.from.allFinite() || !m.to.allFinite()) {
      return failed<Outcome>(Status::InvalidOption, "move on line " + std::to_string(m.line) +
                                                        " has a coordinate beyond 1e6 mm or not finite");
    }
    const double len = (m.to - m.from).norm();
    const bool extruding = m.filament > 0 && len > 1e-9;
    if (!extruding) {
      prevExtruding = false;
      continue;
    }
    if (!prevExtruding || (m.from - prevEnd).norm() > 1e-6) {
      ++bead;
      beadS = 0;
    }
    Segment s;
    s.a = m.from;
    s.b = m.to;
    s.u = m.axis.normalized();
    s.length = len;
    s.beadStart = beadS;
    s.bead = bead;
    s.layer = m.layer;
    s.line = m.line;
    s.support = m.feature == support;
    segments.push_back(s);
    beadS += len;
    rep.pathMm += len;
    prevExtruding = true;
    prevEnd = m.to;
  }
  return {};
}

// ---- samples ----
// Every `spacing` mm along each segment from its start; one sample on a shorter segment.
std::vector<Sample> pathSamples(const std::vector<Segment>& segments, double spacing) {
  std::vector<Sample> samples;
  auto sampleCount = [&](const Segment& s) {  // k = 0, 1, ... while k = 0 or k spacing < length
    size_t k = 1;
    while (double(k) * spacing < s.length) ++k;
    return k;
  };
  {
    size_t count = 0;
    for (const Segment& s : segments) count += sampleCount(s);
    samples.reserve(count);
  }
  for (size_t si = 0; si < segments.size(); ++si) {
    const Segment& s = segments[si];
    const size_t n = sampleCount(s);
    for (size_t k = 0; k < n; ++k) {
      const double t = double(k) * spacing;
      samples.push_back({s.a + (t / s.length) * (s.b - s.a), int(si), s.beadStart + t});
    }
  }
  return samples;
}

// ---- inside and surface samples ----
// Squared distance of each sample to the surface where it is below w^2 (else w^2): the least
// (closestPointOnTriangle(p, a, b, c) - p).squaredNorm() over the triangles, the expression of
// AabbTree::closest(p, w), found by each triangle visiting the samples in its box grown by w.
// False when cancelled.
bool surfaceDistances2(const Mesh& partMesh, const std::vector<Sample>& samples, double w, Progress& progress,
                       std::vector<double>& near2) {
  near2.assign(samples.size(), w * w);
  const SampleGrid grid(samples, w);
  const double reach = w + 1e-9;  // grows the boxes by far more than rounding
  return forEachTriangleBox(partMesh, reach, progress, 0.0, 0.2, [&](const Eigen::Vector3d& a,
      const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    // A sample that close lies within w of the triangle's plane too (1e-9 mm over it: far more
    // than rounding); degenerate triangles skip this test.
    Eigen::Vector3d n = (b - a).cross(c - a);
    const double nn = n.norm();
    const bool plane = nn > 0;
    if (plane) n /= nn;
    grid.forEachIn(lo, hi, [&](uint32_t i) {
      const Eigen::Vector3d& p = samples[i].p;
      if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) return;
      if (plane && std::abs(n.dot(p - a)) > reach) return;
      const double d2 = (closestPointOnTriangle(p, a, b, c) - p).squaredNorm();
      if (d2 < near2[i]) near2[i] = d2;
    });
  });
}

// The fraction of part samples inside the solid (rep.inside, rep.supportSamples) and which
// samples lie within w of the surface (nearSurface).
Outcome insideSamples(const AabbTree& tree, const Mesh& partMesh, const std::vector<Segment>& segments,
                      const std::vector<Sample>& samples, double w, Progress& progress,
                      std::vector<uint8_t>& nearSurface, VerifyReport& rep) {
  std::vector<double> near2;
  if (!surfaceDistances2(partMesh, samples, w, progress, near2)) return cancelled();
  nearSurface.assign(samples.size(), 0);
  size_t insideCount = 0, partSamples = 0;
  // Two samples both farther than w from the surface and closer than 2w to each other see no
  // surface between them (every point of the chord is within half its length of an end), so the
  // second has the first's winding: one winding query per run of far samples, same result.
  bool prevFar = false, prevInside = false;
  Eigen::Vector3d prevP(0, 0, 0);
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!progress.tick(i, samples.size(), 0.2, 0.3)) return cancelled();
    const Eigen::Vector3d& p = samples[i].p;
    // As AabbTree::closest(p, w).distance: infinity when no triangle is closer than w.
    const double distance =
        near2[i] < w * w ? std::sqrt(near2[i]) : std::numeric_limits<double>::infinity();
    const bool far = !(distance <= w);
    if (!far) nearSurface[i] = 1;
    bool in;
    if (distance <= 0.5 * w) {
      in = true;
    } else if (far && prevFar && (p - prevP).squaredNorm() < 4 * w * w * (1 - 1e-9)) {
      in = prevInside;
    } else {
      in = tree.inside(p);
    }
    if (!segments[samples[i].segment].support) {
      ++partSamples;
      if (in) ++insideCount;
    }
    prevFar = far;
    prevInside = in;
    prevP = p;
  }
  rep.supportSamples = samples.size() - partSamples;
  rep.inside = partSamples ? double(insideCount) / double(partSamples) : 1.0;
  return {};
}

// ---- supported ----
// A centre-line piece (at most one hash cell long) with its arc lengths within its bead.
struct Piece {
  Eigen::Vector3d a, b;
  double s0, s1;
};

// Pieces in print order, bucketed once into a dense cell grid (CSR): a piece is listed in every
// cell its R-expanded box touches, in increasing index, so a sample scans the list of its own
// cell while the index is below nextPiece (the prefix laid before it).
struct PieceGrid {
  Eigen::Vector3d glo, ghi;
  double gs = 0;  // cell size: grows until the grid has at most ~4 cells per piece
  int64_t dims[3] = {0, 0, 0};
  size_t cellCount = 0;
  std::vector<uint32_t> offsets, entries;
};

// InvalidOption when there are too many pieces.
Outcome buildPieceGrid(const std::vector<Piece>& pieces, double R, double cs, PieceGrid& grid) {
  Eigen::Vector3d& glo = grid.glo;
  Eigen::Vector3d& ghi = grid.ghi;
  glo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  ghi = -glo;
  for (const Piece& p : pieces) {
    const Eigen::Vector3d lo = p.a.cwiseMin(p.b).array() - R, hi = p.a.cwiseMax(p.b).array() + R;
    glo = glo.cwiseMin(lo);
    ghi = ghi.cwiseMax(hi);
  }
  double& gs = grid.gs;
  int64_t* dims = grid.dims;
  gs = cs;
  const double maxCells = std::max(double(1 << 20), 4.0 * double(pieces.size()));
  for (;;) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) {
      dims[a] = pieces.empty() ? 0 : int64_t(std::floor((ghi[a] - glo[a]) / gs)) + 1;
      cells *= double(std::max<int64_t>(dims[a], 0));
    }
    if (cells <= maxCells) break;
    gs *= 1.5;
  }
  auto cellRange = [&](double lo, double hi, int a, int64_t& c0, int64_t& c1) {
    c0 = std::clamp(int64_t(std::floor((lo - glo[a]) / gs)), int64_t(0), dims[a] - 1);
    c1 = std::clamp(int64_t(std::floor((hi - glo[a]) / gs)), int64_t(0), dims[a] - 1);
  };
  const size_t cellCount = size_t(dims[0] * dims[1] * dims[2]);
  grid.cellCount = cellCount;
  std::vector<uint32_t>& offsets = grid.offsets;
  std::vector<uint32_t>& entries = grid.entries;
  offsets.assign(cellCount + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<uint32_t> fill;
    if (pass == 1) {
      for (size_t c = 0; c < cellCount; ++c) offsets[c + 1] += offsets[c];
      if (offsets[cellCount] > std::numeric_limits<uint32_t>::max() / 2) {
        return failed<Outcome>(Status::InvalidOption, "too many centre-line pieces to check support");
      }
      entries.resize(offsets[cellCount]);
      fill.assign(offsets.begin(), offsets.end() - 1);
    }
    for (uint32_t pi = 0; pi < pieces.size(); ++pi) {
      const Piece& p = pieces[pi];
      const Eigen::Vector3d lo = p.a.cwiseMin(p.b).array() - R, hi = p.a.cwiseMax(p.b).array() + R;
      int64_t x0, x1, y0, y1, z0, z1;
      cellRange(lo.x(), hi.x(), 0, x0, x1);
      cellRange(lo.y(), hi.y(), 1, y0, y1);
      cellRange(lo.z(), hi.z(), 2, z0, z1);
      for (int64_t z = z0; z <= z1; ++z)
        for (int64_t y = y0; y <= y1; ++y)
          for (int64_t x = x0; x <= x1; ++x) {
            const size_t c = size_t((z * dims[1] + y) * dims[0] + x);
            if (pass == 0) ++offsets[c + 1];
            else entries[fill[c]++] = pi;
          }
    }
  }
  return {};
}

// Up to `keep` of the samples `which` (spread evenly over them) as #*3 float positions.
void keepSpread(const std::vector<Sample>& samples, const std::vector<size_t>& which, size_t keep,
                std::vector<float>& out) {
  const size_t n = std::min(keep, which.size());
  out.reserve(3 * n);
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d& p = samples[which[k * which.size() / n]].p;
    for (int a = 0; a < 3; ++a) out.push_back(static_cast<float>(p[a]));
  }
}

// An unsupported sample as an example: where, and the overhang of the nearest face.
UnsupportedExample unsupportedExample(const Sample& smp, const std::vector<Segment>& segments, const AabbTree& tree,
                                      const Mesh& partMesh) {
  UnsupportedExample ex;
  for (int a = 0; a < 3; ++a) ex.tip[a] = smp.p[a];
  ex.layer = segments[smp.segment].layer;
  ex.line = segments[smp.segment].line;
  const ClosestPoint c = tree.closest(smp.p);
  if (c.triangle >= 0) {
    const size_t f = size_t(c.triangle);
    const Eigen::Vector3d a = partMesh.vertex(partMesh.triangles[3 * f]),
                          b = partMesh.vertex(partMesh.triangles[3 * f + 1]),
                          cc = partMesh.vertex(partMesh.triangles[3 * f + 2]);
    const Eigen::Vector3d n = (b - a).cross(cc - a);
    if (n.norm() > 0) {
      const Eigen::Vector3d u = n.normalized();
      const double overhang =
          std::acos(std::clamp(-u.dot(segments[smp.segment].u), -1.0, 1.0)) * 180 / kPi;
      ex.overhangDeg = 90 - overhang;  // 90 = a face looking straight down along -u
    }
  }
  return ex;
}

// A sample is supported when earlier material (earlier beads, and its own bead laid more than
// the exclusion before it) or the platform lies within R = 1.5 h: rep.supported over the surface
// samples of the part, rep.supportedAll over all, and up to 10 examples.
Outcome supportedSamples(const AabbTree& tree, const Mesh& partMesh, const std::vector<Segment>& segments,
                         const std::vector<Sample>& samples, const std::vector<uint8_t>& nearSurface, double h,
                         size_t keepPoints, Progress& progress, VerifyReport& rep) {
  const double R = 1.5 * h;
  const double exclusion = std::max(0.5, 3.0 * h);
  const double cs = std::max(2.0 * R, 0.5);
  std::vector<Piece> pieces;
  std::vector<int> pieceBead;
  {
    size_t count = 0;
    for (const Segment& s : segments) count += size_t(std::max(1, int(std::ceil(s.length / cs))));
    pieces.reserve(count);
    pieceBead.reserve(count);
  }
  for (const Segment& s : segments) {
    const int n = std::max(1, int(std::ceil(s.length / cs)));
    for (int k = 0; k < n; ++k) {
      const double t0 = double(k) / n, t1 = double(k + 1) / n;
      pieces.push_back({s.a + t0 * (s.b - s.a), s.a + t1 * (s.b - s.a),
                        s.beadStart + t0 * s.length, s.beadStart + t1 * s.length});
      pieceBead.push_back(s.bead);
    }
  }
  PieceGrid grid;
  const Outcome built = buildPieceGrid(pieces, R, cs, grid);
  if (!built.ok()) return built;
  const Eigen::Vector3d& glo = grid.glo;
  const double gs = grid.gs;
  const int64_t* dims = grid.dims;
  size_t nextPiece = 0;  // pieces [0, nextPiece) were laid before the current sample
  size_t supportedSurface = 0, surfaceCount = 0, supportedAll = 0;
  std::vector<size_t> unsupported;  // surface samples not supported
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!progress.tick(i, samples.size(), 0.3, 0.5)) return cancelled();
    const Sample& smp = samples[i];
    const int myBead = segments[smp.segment].bead;
    const double cutoff = smp.beadS - exclusion;
    // Everything of earlier beads, and this bead's path laid before the cut-off.
    while (nextPiece < pieces.size() &&
           (pieceBead[nextPiece] < myBead ||
            (pieceBead[nextPiece] == myBead && pieces[nextPiece].s1 <= cutoff))) {
      ++nextPiece;
    }
    bool ok = smp.p.z() <= R;  // the platform z = 0
    if (!ok && nextPiece < pieces.size() && pieceBead[nextPiece] == myBead &&
        pieces[nextPiece].s0 < cutoff) {
      // The piece straddling the cut-off, clipped to the part laid before it.
      const Piece& p = pieces[nextPiece];
      const double t = (cutoff - p.s0) / (p.s1 - p.s0);
      ok = pointSegmentDistance2(smp.p, p.a, p.a + t * (p.b - p.a)) <= R * R;
    }
    if (!ok && grid.cellCount > 0) {
      bool inGrid = true;
      int64_t cx[3];
      for (int a = 0; a < 3; ++a) {
        const double f = std::floor((smp.p[a] - glo[a]) / gs);
        inGrid = inGrid && f >= 0 && f < double(dims[a]);
        cx[a] = inGrid ? int64_t(f) : 0;
      }
      if (inGrid) {
        // The pieces of the cell laid before the sample, latest first (the layer below is met
        // before older ones): "any within R" does not depend on the order.
        const size_t c = size_t((cx[2] * dims[1] + cx[1]) * dims[0] + cx[0]);
        const uint32_t* const first = grid.entries.data() + grid.offsets[c];
        const uint32_t* const last = grid.entries.data() + grid.offsets[c + 1];
        const uint32_t* end = std::lower_bound(first, last, uint32_t(nextPiece));
        while (end != first) {
          const Piece& p = pieces[*--end];
          if (pointSegmentDistance2(smp.p, p.a, p.b) <= R * R) {
            ok = true;
            break;
          }
        }
      }
    }
    if (ok) ++supportedAll;
    if (nearSurface[i] && !segments[smp.segment].support) {
      ++surfaceCount;
      if (ok) ++supportedSurface;
      else unsupported.push_back(i);
    }
  }
  rep.supported = surfaceCount ? double(supportedSurface) / double(surfaceCount) : 1.0;
  rep.surfaceSamples = surfaceCount;
  rep.unsupportedSamples = surfaceCount - supportedSurface;
  rep.supportedAll = double(supportedAll) / double(samples.size());
  const size_t shown = std::min<size_t>(10, unsupported.size());
  for (size_t k = 0; k < shown; ++k) {
    const Sample& smp = samples[unsupported[k * unsupported.size() / shown]];
    rep.unsupportedExamples.push_back(unsupportedExample(smp, segments, tree, partMesh));
  }
  keepSpread(samples, unsupported, keepPoints, rep.unsupportedPoints);
  return {};
}

// ---- collisions ----
// Exactly the samples that have an earlier sample in their cone (PROGRAM-FORMAT.md): while all
// earlier material lies at or below the level no scan is needed (every layer-by-layer print);
// otherwise the cell hierarchy of EarlierSamples prunes whole regions, and the example's earlier
// point is the one the plain scan in print order meets first.
Outcome collidingSamples(const ParsedProgram& program, const std::vector<Segment>& segments,
                         const std::vector<Sample>& samples, double h, size_t keepPoints, Progress& progress,
                         VerifyReport& rep) {
  std::vector<size_t> colliding;  // keepPoints: the colliding samples
  Cone cone;
  cone.h = h;
  cone.tol = 0.001;
  cone.length = program.machine.nozzle.coneLength;
  cone.tanT = std::tan(program.machine.nozzle.coneHalfAngleDegrees * kPi / 180.0);
  if (cone.tanT > 0 && std::isfinite(cone.tanT)) {
    cone.cosT = 1.0 / std::sqrt(1.0 + cone.tanT * cone.tanT);
    cone.sinT = cone.tanT * cone.cosT;
  }
  EarlierSamples earlier(samples);
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Vector3d glo(inf, inf, inf), ghi(-inf, -inf, -inf);
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!progress.tick(i, samples.size(), 0.5, 0.6)) return cancelled();
    const Sample& s = samples[i];
    cone.tip = s.p;
    cone.u = segments[size_t(s.segment)].u;
    cone.level = s.p.dot(cone.u) + h + cone.tol;
    if (i > 0 && cone.support(glo, ghi) > cone.level) {
      earlier.addUpTo(i);
      if (earlier.anyHit(cone)) {
        ++rep.collisions;
        if (keepPoints > 0) colliding.push_back(i);
        uint32_t hitPoint = 0;
        if (rep.collisionExamples.size() < 10 && earlier.firstHitInScanOrder(cone, hitPoint)) {
          CollisionExample e;
          for (int k = 0; k < 3; ++k) {
            e.tip[k] = s.p[k];
            e.axis[k] = cone.u[k];
            e.earlier[k] = samples[hitPoint].p[k];
          }
          e.layer = segments[size_t(s.segment)].layer;
          e.line = segments[size_t(s.segment)].line;
          rep.collisionExamples.push_back(e);
        }
      }
    }
    glo = glo.cwiseMin(s.p);
    ghi = ghi.cwiseMax(s.p);
  }
  keepSpread(samples, colliding, keepPoints, rep.collisionPoints);
  return {};
}

// ---- coverage ----
// The grid points (spacing g) of the part's bounding box: index ranges i0..i1, j0..j1, k0..k1.
struct CoverageGrid {
  double g = 0;
  int64_t i0 = 0, i1 = 0, j0 = 0, j1 = 0, k0 = 0, k1 = 0;
  int64_t nx = 0, ny = 0;
  size_t n = 0;
  // The grid points inside the box [lo, hi], clamped to the grid: indices [a, b] per axis
  // (empty when a > b on some axis).
  struct Cells {
    int64_t a[3], b[3];
    bool empty() const { return a[0] > b[0] || a[1] > b[1] || a[2] > b[2]; }
  };
  Cells cellsIn(const Eigen::Vector3d& boxLo, const Eigen::Vector3d& boxHi) const {
    const int64_t first[3] = {i0, j0, k0}, last[3] = {i1, j1, k1};
    Cells c;
    for (int d = 0; d < 3; ++d) {
      c.a[d] = std::max(first[d], int64_t(std::ceil(boxLo[d] / g)));
      c.b[d] = std::min(last[d], int64_t(std::floor(boxHi[d] / g)));
    }
    return c;
  }
  size_t index(int64_t i, int64_t j, int64_t k) const {
    return size_t(((k - k0) * ny + (j - j0)) * nx + (i - i0));
  }
};

// InvalidOption when the grid would have more than maxGridPoints points.
Outcome coverageGrid(const Mesh& partMesh, double g, size_t maxGridPoints, CoverageGrid& grid) {
  const BoundingBox box = boundingBox(partMesh);
  // Index ranges in double first: nothing is cast to an integer before the size check.
  const Eigen::Vector3d lo = (box.min / g).array().ceil(), hi = (box.max / g).array().floor();
  const Eigen::Vector3d counts = (hi - lo).array() + 1.0;
  const double total = counts.minCoeff() <= 0 ? 0.0 : counts.x() * counts.y() * counts.z();
  if (total > double(maxGridPoints) || !std::isfinite(total)) {
    char msg[160];
    std::snprintf(msg, sizeof msg,
                  "coverage grid of %.0f points at spacing %g mm exceeds maxGridPoints %zu", total,
                  g, maxGridPoints);
    return failed<Outcome>(Status::InvalidOption, msg);
  }
  grid.g = g;
  grid.i0 = int64_t(lo.x());
  grid.i1 = int64_t(hi.x());
  grid.j0 = int64_t(lo.y());
  grid.j1 = int64_t(hi.y());
  grid.k0 = int64_t(lo.z());
  grid.k1 = int64_t(hi.z());
  grid.nx = std::max<int64_t>(0, grid.i1 - grid.i0 + 1);
  grid.ny = std::max<int64_t>(0, grid.j1 - grid.j0 + 1);
  grid.n = size_t(total);
  return {};
}

// Interior points: the candidates lie between a crossing where their column enters the solid
// and the next one, at least w/2 from both; a candidate is interior when no triangle lies
// within w/2 of it (the test of AabbTree::anyWithin, same expression and bound). Each triangle
// clears the candidates it is that close to: those lie in its box grown by w/2 and, on a
// column, within w/2 / |n_z| of its plane.
bool interiorPoints(const AabbTree& tree, const Mesh& partMesh, const CoverageGrid& grid, double w,
                    Progress& progress, Bits& interior) {
  const double g = grid.g;
  const double half = 0.5 * w;
  std::vector<ColumnCrossing> xs;
  size_t column = 0;
  const size_t columns = size_t(grid.nx * grid.ny);
  for (int64_t j = grid.j0; j <= grid.j1; ++j) {
    for (int64_t i = grid.i0; i <= grid.i1; ++i, ++column) {
      if (!progress.tick(column, columns, 0.6, 0.7)) return false;
      const double x = double(i) * g, y = double(j) * g;
      tree.columnCrossings(x, y, xs);
      std::sort(xs.begin(), xs.end(),
                [](const ColumnCrossing& a, const ColumnCrossing& b) { return a.z < b.z; });
      int wind = 0;
      for (size_t m = 0; m + 1 < xs.size(); ++m) {
        wind += xs[m].sign;
        if (wind == 0) continue;
        const double zLo = xs[m].z + half, zHi = xs[m + 1].z - half;
        const int64_t kEnd = std::min(grid.k1, int64_t(std::floor(zHi / g)));
        for (int64_t k = std::max(grid.k0, int64_t(std::ceil(zLo / g))); k <= kEnd; ++k) {
          interior.set(grid.index(i, j, k));
        }
      }
    }
  }
  const double r = half * (1 - 1e-9), r2 = r * r;
  const double reach = r + 1e-9;  // grows the boxes by far more than rounding
  return forEachTriangleBox(partMesh, reach, progress, 0.7, 0.8, [&](const Eigen::Vector3d& a,
      const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const CoverageGrid::Cells cells = grid.cellsIn(lo, hi);
    if (cells.empty()) return;
    const int64_t ia = cells.a[0], ib = cells.b[0], ja = cells.a[1], jb = cells.b[1], ka = cells.a[2],
                  kb = cells.b[2];
    // The plane: |n.(p - a)| <= reach for every point that close. Only for faces not steeper
    // than about 78 degrees; the 1e-6 mm margin covers the rounding of zc.
    Eigen::Vector3d nrm = (b - a).cross(c - a);
    const double nn = nrm.norm();
    const bool slab = nn > 0 && std::abs(nrm.z()) > 0.2 * nn;
    if (slab) nrm /= nn;
    const double slabHalf = slab ? reach / std::abs(nrm.z()) + 1e-6 : 0.0;
    for (int64_t j = ja; j <= jb; ++j) {
      const double y = double(j) * g;
      for (int64_t i = ia; i <= ib; ++i) {
        const double x = double(i) * g;
        int64_t kLo = ka, kHi = kb;
        if (slab) {
          const double zc = a.z() - (nrm.x() * (x - a.x()) + nrm.y() * (y - a.y())) / nrm.z();
          kLo = std::max(kLo, int64_t(std::ceil((zc - slabHalf) / g)));
          kHi = std::min(kHi, int64_t(std::floor((zc + slabHalf) / g)));
        }
        for (int64_t k = kLo; k <= kHi; ++k) {
          const size_t idx = grid.index(i, j, k);
          if (!interior.get(idx)) continue;
          const Eigen::Vector3d p(x, y, double(k) * g);
          if ((closestPointOnTriangle(p, a, b, c) - p).squaredNorm() <= r2) interior.clear(idx);
        }
      }
    }
  });
}

// The interior points within some segment's bead ellipsoid (axial 0.75 h, lateral 0.75 w).
bool coveredPoints(const std::vector<Segment>& segments, const CoverageGrid& grid, const Bits& interior, double h,
                   double w, Progress& progress, Bits& covered) {
  const double g = grid.g;
  const double rax = 0.75 * h, rlat = 0.75 * w;
  const double pieceLen = std::max(4.0 * g, 1.0);
  for (size_t si = 0; si < segments.size(); ++si) {
    if (!progress.tick(si, segments.size(), 0.8, 1.0)) return false;
    const Segment& s = segments[si];
    const Eigen::Vector3d ab = s.b - s.a;
    const double len2 = ab.squaredNorm();
    // A covered point lies within the bead's ellipsoid of a point of the segment, so within the
    // ellipsoid's extent along each grid axis, sqrt(rax^2 u_k^2 + rlat^2 (1 - u_k^2)), of the
    // piece holding that point (1e-9 mm over it: far more than rounding).
    Eigen::Vector3d reach;
    for (int k = 0; k < 3; ++k) {
      const double uk2 = s.u[k] * s.u[k];
      reach[k] = std::sqrt(std::max(0.0, rax * rax * uk2 + rlat * rlat * (1 - uk2))) + 1e-9;
    }
    const int pieces = std::max(1, int(std::ceil(s.length / pieceLen)));
    for (int q = 0; q < pieces; ++q) {
      const Eigen::Vector3d pa = s.a + (double(q) / pieces) * ab,
                            pb = s.a + (double(q + 1) / pieces) * ab;
      const Eigen::Vector3d lo = pa.cwiseMin(pb) - reach, hi = pa.cwiseMax(pb) + reach;
      const CoverageGrid::Cells cells = grid.cellsIn(lo, hi);
      for (int64_t k = cells.a[2]; k <= cells.b[2]; ++k)
        for (int64_t j = cells.a[1]; j <= cells.b[1]; ++j)
          for (int64_t i = cells.a[0]; i <= cells.b[0]; ++i) {
            const size_t idx = grid.index(i, j, k);
            if (!interior.get(idx) || covered.get(idx)) continue;
            const Eigen::Vector3d p(double(i) * g, double(j) * g, double(k) * g);
            const double t = std::clamp((p - s.a).dot(ab) / len2, 0.0, 1.0);
            const Eigen::Vector3d d = p - (s.a + t * ab);
            const double axial = d.dot(s.u);
            const double lat2 = std::max(0.0, d.squaredNorm() - axial * axial);
            if ((axial * axial) / (rax * rax) + lat2 / (rlat * rlat) <= 1.0) covered.set(idx);
          }
    }
  }
  return true;
}

// rep.gridPoints (interior points) and rep.coverage (the fraction covered by some bead).
Outcome coverage(const AabbTree& tree, const Mesh& partMesh, const std::vector<Segment>& segments, double g,
                 double h, double w, size_t maxGridPoints, Progress& progress, VerifyReport& rep) {
  CoverageGrid grid;
  const Outcome ok = coverageGrid(partMesh, g, maxGridPoints, grid);
  if (!ok.ok()) return ok;
  Bits interior(grid.n), covered(grid.n);
  if (!interiorPoints(tree, partMesh, grid, w, progress, interior)) return cancelled();
  rep.gridPoints = interior.count();
  if (!coveredPoints(segments, grid, interior, h, w, progress, covered)) return cancelled();
  rep.coverage = rep.gridPoints ? double(covered.countAnd(interior)) / double(rep.gridPoints) : 0.0;
  return {};
}

// ---- surface reached ----
// The share of the part's surface area with a bead sample (support excluded) within `reach`:
// points at the centroids of an n x n subdivision of each triangle (n = ceil(longest edge /
// spacing), spacing reach / 2, raised to keep at most about four million points), each weighing
// its share of the area; the samples bucketed in cells of `reach`, 27 cells per point. A part of
// the model no bead comes near (a branch the layers never reach, a feature thinner than a bead)
// lowers it, where coverage, whose grid points stand w/2 inside the solid, sees nothing on a
// part thinner than a bead.
bool reachedSurface(const Mesh& partMesh, const std::vector<Segment>& segments, const std::vector<Sample>& samples,
                    double reach, Progress& progress, VerifyReport& rep) {
  const size_t faces = partMesh.faceCount();
  double spacing = 0.5 * reach, total = 0;
  auto corner = [&](size_t f, int k) { return partMesh.vertex(partMesh.triangles[3 * f + k]); };
  // Subdivisions per side of face f at spacing sp (its longest edge over sp, at least 1).
  auto divisions = [&](size_t f, double sp) {
    const Eigen::Vector3d a = corner(f, 0), b = corner(f, 1), c = corner(f, 2);
    return std::max(1.0, std::ceil(std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()}) / sp));
  };
  auto pointsAt = [&](double sp) {
    double count = 0;
    for (size_t f = 0; f < faces; ++f) count += divisions(f, sp) * divisions(f, sp);
    return count;
  };
  while (pointsAt(spacing) > 4e6) spacing *= 1.5;
  std::unordered_map<int64_t, std::vector<uint32_t>> cells;
  auto key = [&](const Eigen::Vector3d& p, int dx, int dy, int dz) {
    return cellKey(int64_t(std::floor(p.x() / reach)) + dx, int64_t(std::floor(p.y() / reach)) + dy,
                   int64_t(std::floor(p.z() / reach)) + dz);
  };
  for (size_t i = 0; i < samples.size(); ++i) {
    if (segments[samples[i].segment].support) continue;
    cells[key(samples[i].p, 0, 0, 0)].push_back(static_cast<uint32_t>(i));
  }
  const double reach2 = reach * reach;
  auto near = [&](const Eigen::Vector3d& p) {
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells.find(key(p, dx, dy, dz));
          if (it == cells.end()) continue;
          for (uint32_t i : it->second)
            if ((samples[i].p - p).squaredNorm() <= reach2) return true;
        }
    return false;
  };
  double reached = 0;
  for (size_t f = 0; f < faces; ++f) {
    if (!progress.tick(f, faces, 0.98, 1.0)) return false;
    const Eigen::Vector3d a = corner(f, 0), b = corner(f, 1), c = corner(f, 2);
    const double area = 0.5 * (b - a).cross(c - a).norm();
    if (!(area > 0)) continue;
    const int n = static_cast<int>(divisions(f, spacing));
    const double w = area / (double(n) * n);
    total += area;
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        // The sub-triangle with corner (i, j) pointing up, and the one pointing down beside it.
        const double u = (i + 1.0 / 3) / n, v = (j + 1.0 / 3) / n;
        if (near(a + u * (b - a) + v * (c - a))) reached += w;
        if (i + j + 1 < n) {
          const double u2 = (i + 2.0 / 3) / n, v2 = (j + 2.0 / 3) / n;
          if (near(a + u2 * (b - a) + v2 * (c - a))) reached += w;
        }
      }
  }
  rep.surfaceReached = total > 0 ? std::min(1.0, reached / total) : 1.0;
  rep.surfaceReach = reach;
  return true;
}

}  // namespace

VerifyReport verifyProgram(const ParsedProgram& program, const Mesh& partMesh,
                           const VerifyOptions& options, const ProgressFn& progressFn) {
  VerifyReport rep;
  auto fail = [](const Outcome& o) { return failed<VerifyReport>(o); };
  Outcome ok = checkVerifyInput(program, partMesh, options);
  if (!ok.ok()) return fail(ok);
  const double h = program.layerHeight, w = program.lineWidth;
  const double nozzle =
      program.nozzleDiameter > 0 ? program.nozzleDiameter : program.machine.nozzle.diameter;
  const double g = options.gridSpacing > 0 ? options.gridSpacing : std::min(nozzle, h);
  Progress progress{progressFn};
  if (!reportProgress(progressFn, "verify", 0)) return fail(cancelled());

  std::vector<Segment> segments;
  ok = extrudingSegments(program, segments, rep);
  if (!ok.ok()) return fail(ok);
  rep.layers = program.layerCount;
  if (segments.empty()) return fail(failed<Outcome>(Status::EmptyInput, "program has no extruding moves"));
  if (rep.pathMm / options.sampleSpacing + double(segments.size()) > double(options.maxSamples)) {
    return fail(failed<Outcome>(Status::InvalidOption, "program has more than maxSamples path samples"));
  }
  {
    // The samples and the coverage grid within the budget (the parsed program was checked before it
    // was read: checkProgramReadBudget).
    const BoundingBox box = boundingBox(partMesh);
    const Eigen::Vector3d counts = ((box.max - box.min) / g).array() + 1.0;
    const double samplesNeeded = rep.pathMm / options.sampleSpacing + double(segments.size());
    // (A grid past maxGridPoints is an absurd spacing, refused as such by coverageGrid.)
    const double gridPoints = counts.prod() <= double(options.maxGridPoints) ? counts.prod() : 0.0;
    const double bytes = samplesNeeded * memory_cost::kVerifySampleBytes +
                         gridPoints * memory_cost::kVerifyGridPointBytes;
    char what[120];
    std::snprintf(what, sizeof what, "verifying the program (%.0f mm of path, %.0f samples)", rep.pathMm,
                  samplesNeeded);
    ok = checkMemoryBudget(bytes, options.memoryBudgetMb, what, "raise memory_mb, or verify a smaller program");
    if (!ok.ok()) return fail(ok);
  }
  const std::vector<Sample> samples = pathSamples(segments, options.sampleSpacing);
  rep.samples = samples.size();

  const AabbTree tree(partMesh);
  std::vector<uint8_t> nearSurface;
  ok = insideSamples(tree, partMesh, segments, samples, w, progress, nearSurface, rep);
  if (ok.ok()) {
    ok = supportedSamples(tree, partMesh, segments, samples, nearSurface, h,
                          options.keepUnsupported > 0 ? options.keepUnsupported : options.keepPoints, progress, rep);
  }
  if (ok.ok()) ok = collidingSamples(program, segments, samples, h, options.keepPoints, progress, rep);
  if (ok.ok()) ok = coverage(tree, partMesh, segments, g, h, w, options.maxGridPoints, progress, rep);
  if (!ok.ok()) return fail(ok);
  if (!reachedSurface(partMesh, segments, samples, w + h + 0.5 * options.sampleSpacing, progress, rep)) {
    return fail(cancelled());
  }
  if (!reportProgress(progressFn, "verify", 1.0)) return fail(cancelled());
  return rep;
}

std::string verifyReportJson(const VerifyReport& r) {
  nlohmann::ordered_json j;
  j["inside"] = r.inside;
  j["coverage"] = r.coverage;
  j["surface_reached"] = r.surfaceReached;
  j["surface_reach_mm"] = r.surfaceReach;
  j["supported"] = r.supported;
  j["supported_all"] = r.supportedAll;
  j["support_samples"] = r.supportSamples;
  nlohmann::ordered_json ue = nlohmann::ordered_json::array();
  for (const UnsupportedExample& e : r.unsupportedExamples) {
    ue.push_back({{"tip", {e.tip[0], e.tip[1], e.tip[2]}}, {"layer", e.layer}, {"line", e.line},
                  {"overhang_deg", e.overhangDeg}});
  }
  j["unsupported_examples"] = ue;
  j["collisions"] = r.collisions;
  j["limits"] = r.limitViolations;
  j["extrusion_mm"] = r.extrusionMm;
  j["path_mm"] = r.pathMm;
  j["samples"] = r.samples;
  j["grid_points"] = r.gridPoints;
  j["layers"] = r.layers;
  j["collision_examples"] = nlohmann::ordered_json::array();
  for (const CollisionExample& e : r.collisionExamples) {
    j["collision_examples"].push_back({{"tip", {e.tip[0], e.tip[1], e.tip[2]}},
                                       {"axis", {e.axis[0], e.axis[1], e.axis[2]}},
                                       {"earlier", {e.earlier[0], e.earlier[1], e.earlier[2]}},
                                       {"layer", e.layer},
                                       {"line", e.line}});
  }
  return j.dump();
}

}  // namespace omnislice
