// SPDX-License-Identifier: MIT
// Curved layers of paper 001 Section 4.5. The scalar field G lives on voxel centres (the dual
// grid). Iso-surfaces are extracted by marching tetrahedra on the dual cubes with the Freudenthal
// (Kuhn) split into 6 tetrahedra around the main diagonal: every cube is split the same way, so
// neighbouring cubes agree on their shared face diagonals and the piecewise-linear field has a
// manifold level set for every iso-value (no marching-cubes ambiguity, no dual-contouring
// non-manifold vertices). Vertices sit on lattice edges, so they are welded by edge index. The
// paper uses dual contouring for fewer polygons; we prefer the guaranteed manifold output, which
// the trimming, the region split and the geodesic tool-path fields downstream rely on.
#include "voxel/curved_layers.h"

#include "common/disjoint_sets.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <string>

#include "common/parallel.h"
#include "common/stopwatch.h"
#include "geometry/aabb_tree.h"

namespace omnislice {

namespace {


// Open-addressing map uint64 key -> uint32 value (keys never equal kEmpty), key and value in
// one slot so a lookup touches one cache line.
class KeyMap {
 public:
  void clear() {
    if (size_ > 0) {
      for (Slot& slot : slots_) slot.key = kEmpty;
    }
    size_ = 0;
  }
  size_t size() const { return size_; }
  // Value stored under key, or inserts value and returns it; added tells which.
  uint32_t getOrAdd(uint64_t key, uint32_t value, bool& added) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    const size_t mask = slots_.size() - 1;
    for (size_t i = mix(key) & mask;; i = (i + 1) & mask) {
      Slot& slot = slots_[i];
      if (slot.key == key) {
        added = false;
        return slot.value;
      }
      if (slot.key == kEmpty) {
        slot.key = key;
        slot.value = value;
        ++size_;
        added = true;
        return value;
      }
    }
  }
  // Value under key, or UINT32_MAX when absent.
  uint32_t find(uint64_t key) const {
    if (size_ == 0) return UINT32_MAX;
    const size_t mask = slots_.size() - 1;
    for (size_t i = mix(key) & mask;; i = (i + 1) & mask) {
      const Slot& slot = slots_[i];
      if (slot.key == key) return slot.value;
      if (slot.key == kEmpty) return UINT32_MAX;
    }
  }

 private:
  struct Slot {
    uint64_t key;
    uint32_t value;
  };
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  static uint64_t mix(uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
  }
  void grow() {
    std::vector<Slot> old = std::move(slots_);
    const size_t cap = std::max<size_t>(1024, old.size() * 2);
    slots_.assign(cap, Slot{kEmpty, 0});
    const size_t mask = cap - 1;
    for (const Slot& s : old) {
      if (s.key == kEmpty) continue;
      size_t i = mix(s.key) & mask;
      while (slots_[i].key != kEmpty) i = (i + 1) & mask;
      slots_[i] = s;
    }
  }
  std::vector<Slot> slots_;
  size_t size_ = 0;
};

// The six tetrahedra of the Freudenthal split of a unit cube: corner masks (bit 0 = +x, bit 1 =
// +y, bit 2 = +z) along monotone paths from corner 0 to corner 7.
constexpr uint8_t kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                 {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

// One layer's untrimmed or trimmed surface.
struct LayerSurface {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<uint8_t> boundary;  // per vertex
};

// Signed crossing of segment [c, p] with triangle (a, b, d): 0 none, -1 / +1 the change of the
// winding number along the segment (leaving / entering through the triangle's front), 2 when the
// segment meets the triangle's edge, touches its plane at an end or runs in it (callers then use
// a ray cast).
int segmentCrossing(const Eigen::Vector3d& c, const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                    const Eigen::Vector3d& b, const Eigen::Vector3d& d, double* at = nullptr) {
  const Eigen::Vector3d n = (b - a).cross(d - a);
  const double n2 = n.squaredNorm();
  if (!(n2 > 0)) return 0;  // degenerate triangle: no area to cross
  const double hc = n.dot(c - a), hp = n.dot(p - a);  // signed heights (times |n|)
  const double eps = 1e-9 * std::sqrt(n2) * std::max((p - c).norm(), (b - a).norm());
  if ((hc > eps && hp > eps) || (hc < -eps && hp < -eps)) return 0;
  const bool touch = std::abs(hc) <= eps || std::abs(hp) <= eps;
  const double den = hc - hp;
  Eigen::Vector3d x = c;
  if (std::abs(den) > 0) x = c + (hc / den) * (p - c);
  if (at) *at = std::abs(den) > 0 ? hc / den : 0;
  const double u = (b - a).cross(x - a).dot(n) / n2, v = (d - b).cross(x - b).dot(n) / n2,
               w = (a - d).cross(x - d).dot(n) / n2;
  constexpr double kTol = 1e-9;
  if (u < -kTol || v < -kTol || w < -kTol) return 0;
  if (touch || u <= kTol || v <= kTol || w <= kTol) return 2;
  return hp > hc ? -1 : +1;  // along the normal leaves (winding -1), against it enters
}

// Inside test for trimming: the input solid (winding number, as AabbTree::winding) or a support
// cell. Grid cells whose circumscribed sphere holds no surface are classified once (all inside /
// all outside). In a cell the surface crosses, the winding at p is the cell centre's (one ray
// cast per cell) plus the signed crossings of the segment centre -> p with the few solid
// triangles binned to that cell; a ray cast only when that segment grazes an edge.
class InsideTest {
 public:
  InsideTest(const VoxelGrid& grid, const AabbTree& tree, const Mesh& solid)
      : grid_(grid), tree_(tree), solid_(solid), cellClass_(grid.cellCount(), 0),
        radius_(0.5 * std::sqrt(3.0) * grid.width * (1 + 1e-9)) {
    binTriangles();
  }

  bool operator()(const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = (p - grid_.origin) / grid_.width;
    const int i = static_cast<int>(std::floor(q.x())), j = static_cast<int>(std::floor(q.y())),
              k = static_cast<int>(std::floor(q.z()));
    if (!grid_.inRange(i, j, k)) return tree_.inside(p);
    const size_t c = grid_.index(i, j, k);
    if (grid_.state[c] == static_cast<uint8_t>(VoxelState::Support)) return true;
    uint8_t& cls = cellClass_[c];
    if (cls == 0) cls = classify(i, j, k);
    if (cls == 1) return true;
    if (cls == 2) return false;
    return insideNearSurface(p, i, j, k);
  }
  // True when p is inside and no surface lies within clearance of it (conservatively, via its
  // cell: inside and no surface within clearance + half the cell diagonal of the centre).
  bool deep(const Eigen::Vector3d& p, double clearance) {
    const Eigen::Vector3d q = (p - grid_.origin) / grid_.width;
    const int i = static_cast<int>(std::floor(q.x())), j = static_cast<int>(std::floor(q.y())),
              k = static_cast<int>(std::floor(q.z()));
    if (!grid_.inRange(i, j, k)) return false;
    const size_t c = grid_.index(i, j, k);
    if (deepClass_.empty()) deepClass_.assign(grid_.cellCount(), 0);
    uint8_t& cls = deepClass_[c];
    if (cls == 0) {
      const Eigen::Vector3d centre = grid_.center(i, j, k);
      cls = (*this)(centre) && !tree_.anyWithin(centre, clearance + radius_) ? 1 : 2;
    }
    return cls == 1;
  }
  bool inSupport(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d q = (p - grid_.origin) / grid_.width;
    const int i = static_cast<int>(std::floor(q.x())), j = static_cast<int>(std::floor(q.y())),
              k = static_cast<int>(std::floor(q.z()));
    return grid_.inRange(i, j, k) &&
           grid_.state[grid_.index(i, j, k)] == static_cast<uint8_t>(VoxelState::Support);
  }
  size_t rayCasts = 0;

 private:
  static constexpr int32_t kUnknown = INT32_MIN, kUnreliable = INT32_MIN + 1;

  // Bins every solid triangle into the cells of its bounding box whose centre lies within half a
  // cell diagonal of its plane (a superset of the cells it meets), CSR.
  void binTriangles() {
    const size_t nv = solid_.vertexCount();
    const double w = grid_.width;
    auto forEachCell = [&](size_t t, auto&& visit) {
      const uint32_t ia = solid_.triangles[3 * t], ib = solid_.triangles[3 * t + 1],
                     ic = solid_.triangles[3 * t + 2];
      if (ia >= nv || ib >= nv || ic >= nv) return;
      const Eigen::Vector3d a = solid_.vertex(ia), b = solid_.vertex(ib), c = solid_.vertex(ic);
      const Eigen::Vector3d lo = (a.cwiseMin(b).cwiseMin(c) - grid_.origin) / w;
      const Eigen::Vector3d hi = (a.cwiseMax(b).cwiseMax(c) - grid_.origin) / w;
      int l[3], h[3];
      for (int m = 0; m < 3; ++m) {
        l[m] = std::max(0, static_cast<int>(std::floor(lo[m] - 1e-9)));
        h[m] = std::min(grid_.dims[m] - 1, static_cast<int>(std::floor(hi[m] + 1e-9)));
        if (l[m] > h[m]) return;
      }
      Eigen::Vector3d n = (b - a).cross(c - a);
      const double len = n.norm();
      if (!(len > 0)) {  // degenerate: its bounding box (tiny in practice)
        for (int k = l[2]; k <= h[2]; ++k)
          for (int j = l[1]; j <= h[1]; ++j)
            for (int i = l[0]; i <= h[0]; ++i) visit(grid_.index(i, j, k));
        return;
      }
      n /= len;
      // Columns along the dominant normal axis: only the cells whose centre lies within half a
      // diagonal of the plane, a few per column, so the work follows the triangle's area.
      int ax = 0;
      if (std::abs(n.y()) > std::abs(n[ax])) ax = 1;
      if (std::abs(n.z()) > std::abs(n[ax])) ax = 2;
      const int u = (ax + 1) % 3, v = (ax + 2) % 3;
      const double reach = radius_ / std::abs(n[ax]) / w;  // in cells along that axis
      int cell[3] = {l[0], l[1], l[2]};
      for (cell[u] = l[u]; cell[u] <= h[u]; ++cell[u])
        for (cell[v] = l[v]; cell[v] <= h[v]; ++cell[v]) {
          Eigen::Vector3d centre = grid_.center(cell[0], cell[1], cell[2]);
          // The plane's coordinate along the axis at this column's centre line.
          const double pu = centre[u], pv = centre[v];
          const double pt = a[ax] - (n[u] * (pu - a[u]) + n[v] * (pv - a[v])) / n[ax];
          const double q = (pt - grid_.origin[ax]) / w - 0.5;  // fractional cell index of the plane
          const int first = std::max(l[ax], static_cast<int>(std::ceil(q - reach - 1e-9)));
          const int last = std::min(h[ax], static_cast<int>(std::floor(q + reach + 1e-9)));
          for (cell[ax] = first; cell[ax] <= last; ++cell[ax]) {
            centre = grid_.center(cell[0], cell[1], cell[2]);
            if (std::abs(n.dot(centre - a)) > radius_) continue;
            visit(grid_.index(cell[0], cell[1], cell[2]));
          }
        }
    };
    binStart_.assign(grid_.cellCount() + 1, 0);
    for (size_t t = 0; t < solid_.faceCount(); ++t) forEachCell(t, [&](size_t c) { ++binStart_[c + 1]; });
    for (size_t c = 1; c < binStart_.size(); ++c) binStart_[c] += binStart_[c - 1];
    binTris_.resize(binStart_.back());
    std::vector<uint32_t> fill(binStart_.begin(), binStart_.end() - 1);
    for (size_t t = 0; t < solid_.faceCount(); ++t)
      forEachCell(t, [&](size_t c) { binTris_[fill[c]++] = static_cast<uint32_t>(t); });
  }

  static constexpr int kFace[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0},
                                      {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

  // Class of cell (i, j, k): 3 when surface lies within its circumscribed sphere, else 1 / 2
  // (inside / outside) taken from a classified surface-free face neighbour (two surface-free cubes
  // sharing a face lie on the same side), or from one ray cast at the centre.
  uint8_t classify(int i, int j, int k) {
    const Eigen::Vector3d centre = grid_.center(i, j, k);
    if (tree_.anyWithin(centre, radius_)) return 3;
    for (const auto& e : kFace) {
      if (!grid_.inRange(i + e[0], j + e[1], k + e[2])) continue;
      const uint8_t n = cellClass_[grid_.index(i + e[0], j + e[1], k + e[2])];
      if (n == 1 || n == 2) return n;
    }
    return tree_.inside(centre) ? 1 : 2;
  }

  // Sum of the signed crossings of segment [from, to] with the triangles binned to cell, counting
  // only crossings at segment parameters in [lo, hi); false when a crossing is degenerate.
  bool crossings(size_t cell, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double lo,
                 double hi, int32_t& sum) const {
    for (uint32_t b = binStart_[cell]; b < binStart_[cell + 1]; ++b) {
      const size_t t = binTris_[b];
      double at = 0;
      const int s = segmentCrossing(from, to, solid_.vertex(solid_.triangles[3 * t]),
                                    solid_.vertex(solid_.triangles[3 * t + 1]),
                                    solid_.vertex(solid_.triangles[3 * t + 2]), &at);
      if (s == 0) continue;
      if (s == 2 || std::abs(at - lo) < 1e-9 || std::abs(at - hi) < 1e-9) return false;
      if (at >= lo && at < hi) sum += s;
    }
    return true;
  }

  // Winding number at the centre of near-surface cell (i, j, k): from a face neighbour whose
  // centre winding is known plus the crossings of the segment between the centres (each crossing
  // lies in one of the two cubes: the first half of the segment in the neighbour's, the second in
  // this one's), else one ray cast. kUnreliable for a centre on the surface.
  int32_t centreWinding(int i, int j, int k) {
    const size_t cell = grid_.index(i, j, k);
    int32_t& wc = centreWinding_[cell];
    if (wc != kUnknown) return wc;
    const Eigen::Vector3d centre = grid_.center(i, j, k);
    if (tree_.anyWithin(centre, 1e-9 * grid_.width)) return wc = kUnreliable;
    for (const auto& e : kFace) {
      if (!grid_.inRange(i + e[0], j + e[1], k + e[2])) continue;
      const size_t n = grid_.index(i + e[0], j + e[1], k + e[2]);
      const int32_t wn = centreWinding_[n];
      if (wn == kUnknown || wn == kUnreliable) continue;
      const Eigen::Vector3d from = grid_.center(i + e[0], j + e[1], k + e[2]);
      int32_t sum = wn;
      if (crossings(n, from, centre, 0.0, 0.5, sum) && crossings(cell, from, centre, 0.5, 1.0, sum)) {
        return wc = sum;
      }
    }
    ++rayCasts;
    return wc = tree_.winding(centre);
  }

  bool insideNearSurface(const Eigen::Vector3d& p, int i, int j, int k) {
    if (centreWinding_.empty()) centreWinding_.assign(grid_.cellCount(), kUnknown);
    const int32_t wc = centreWinding(i, j, k);
    if (wc != kUnreliable) {
      int32_t w = wc;
      // The whole segment centre -> p lies in this cell's cube: every crossing is binned here.
      if (crossings(grid_.index(i, j, k), grid_.center(i, j, k), p, -1.0, 2.0, w)) return w != 0;
    }
    ++rayCasts;
    return tree_.inside(p);
  }

  const VoxelGrid& grid_;
  const AabbTree& tree_;
  const Mesh& solid_;
  std::vector<uint8_t> cellClass_;  // 0 unknown, 1 inside, 2 outside, 3 near the surface
  std::vector<uint8_t> deepClass_;  // 0 unknown, 1 deep, 2 not (allocated on first use)
  std::vector<int32_t> centreWinding_;  // near-surface cells: winding at the centre
  std::vector<uint32_t> binStart_, binTris_;
  double radius_;
};

// The scalar field on cell centres: G on grown cells, 0 on Platform cells, extended over every
// cell within one cell (26-neighbourhood) of a valued cell. An extension cell takes the average,
// over its valued face neighbours n (direction e), of the linear extrapolation 2 G(n) - G(n + e)
// (or G(n) when n + e has no value), in up to three passes; linear fields (flat growth) continue
// exactly, so iso-surfaces leave the voxel set straight, a ring of cells past H~.
struct CentreField {
  std::vector<float> value;   // NaN = no value
  std::vector<uint32_t> cells;  // cells with a value (grown, platform, extension)
  double maxG = 0;
};

CentreField buildField(const VoxelGrid& grid, const std::vector<int32_t>& g) {
  CentreField f;
  const size_t n = grid.cellCount();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  f.value.assign(n, nan);
  std::vector<uint32_t> valued;
  for (size_t c = 0; c < n; ++c) {
    if (g[c] >= 1) {
      f.value[c] = static_cast<float>(g[c]);
      f.maxG = std::max(f.maxG, static_cast<double>(g[c]));
      valued.push_back(static_cast<uint32_t>(c));
    }
  }
  // The platform's own plane (z = 0, half-way between the platform cells' centres and the first
  // grown cells') is the zero level: a platform cell under a grown cell takes minus that cell's
  // value, so g = 0 at z = 0 in every column whatever the field's scale, and layer i (g = i x step)
  // stands i layers above the bed. Other platform cells (the disc around the footprint) are
  // extension cells: with a fixed 0 they bent the layers near the rim down to the bed.
  const size_t nxy = static_cast<size_t>(grid.dims.x()) * static_cast<size_t>(grid.dims.y());
  for (size_t c = 0; c + nxy < n; ++c) {
    if (grid.state[c] != static_cast<uint8_t>(VoxelState::Platform) || g[c + nxy] < 1) continue;
    f.value[c] = -static_cast<float>(g[c + nxy]);
    valued.push_back(static_cast<uint32_t>(c));
  }
  // Extension band: cells within Chebyshev distance 1 of a valued cell.
  std::vector<uint8_t> inBand(n, 0);
  std::vector<uint32_t> band;
  for (uint32_t c : valued) {
    const Eigen::Vector3i v = grid.cell(c);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int i = v.x() + dx, j = v.y() + dy, k = v.z() + dz;
          if (!grid.inRange(i, j, k)) continue;
          const size_t m = grid.index(i, j, k);
          if (!std::isnan(f.value[m]) || inBand[m]) continue;
          inBand[m] = 1;
          band.push_back(static_cast<uint32_t>(m));
        }
  }
  static const int kFace[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<std::pair<uint32_t, float>> assigned;
  std::vector<uint32_t> pending = band, next;
  for (int pass = 0; pass < 4 && !pending.empty(); ++pass) {
    assigned.clear();
    next.clear();
    for (uint32_t c : pending) {
      const Eigen::Vector3i v = grid.cell(c);
      double sum = 0;
      int count = 0;
      for (const auto& e : kFace) {
        const int i = v.x() + e[0], j = v.y() + e[1], k = v.z() + e[2];
        if (!grid.inRange(i, j, k)) continue;
        const float fn = f.value[grid.index(i, j, k)];
        if (std::isnan(fn)) continue;
        double val = fn;
        const int bi = i + e[0], bj = j + e[1], bk = k + e[2];
        if (grid.inRange(bi, bj, bk)) {
          const float fb = f.value[grid.index(bi, bj, bk)];
          if (!std::isnan(fb)) val = 2.0 * fn - fb;
        }
        sum += val;
        ++count;
      }
      if (count > 0) {
        assigned.emplace_back(c, static_cast<float>(sum / count));
      } else {
        next.push_back(c);
      }
    }
    for (const auto& [c, val] : assigned) f.value[c] = val;
    pending.swap(next);
  }
  f.cells = std::move(valued);
  for (uint32_t c : band) {
    if (!std::isnan(f.value[c])) f.cells.push_back(c);
  }
  return f;
}

// Marching tetrahedra of one iso-value over the listed dual cubes (min-corner cell indices).
void extractIsoSurface(const VoxelGrid& grid, const CentreField& field,
                       const uint32_t* cubes, size_t cubeCount, double iso, KeyMap& edgeMap,
                       LayerSurface& out) {
  out.positions.clear();
  out.triangles.clear();
  out.boundary.clear();
  edgeMap.clear();
  const size_t nx = static_cast<size_t>(grid.dims.x());
  const size_t nxy = nx * static_cast<size_t>(grid.dims.y());
  const size_t offset[8] = {0, 1, nx, nx + 1, nxy, nxy + 1, nxy + nx, nxy + nx + 1};
  // Keeps t away from 0 and 1 so no two edge vertices coincide at a lattice point (a corner value
  // equal to the iso-value) and no triangle degenerates; moves a vertex by at most 1e-4 w.
  constexpr double kTMin = 1e-4;
  for (size_t q = 0; q < cubeCount; ++q) {
    const size_t base = cubes[q];
    double v[8];
    int above = 0;
    for (int c = 0; c < 8; ++c) {
      v[c] = field.value[base + offset[c]];
      above += v[c] >= iso;
    }
    if (above == 0 || above == 8) continue;
    const Eigen::Vector3i bc = grid.cell(base);
    auto corner = [&](int c) {
      return grid.center(bc.x() + (c & 1), bc.y() + ((c >> 1) & 1), bc.z() + ((c >> 2) & 1));
    };
    uint32_t local[8][8];  // this cube's edge vertices, [lower corner][upper corner]
    for (auto& row : local)
      for (uint32_t& x : row) x = UINT32_MAX;
    auto edgeVertex = [&](int p, int r) -> uint32_t {
      if (p > r) std::swap(p, r);  // chain order: corner p's bits are a subset of r's
      if (local[p][r] != UINT32_MAX) return local[p][r];
      const uint64_t key = static_cast<uint64_t>(base + offset[p]) * 8 + static_cast<uint64_t>(p ^ r);
      bool added = false;
      const uint32_t id = edgeMap.getOrAdd(key, static_cast<uint32_t>(out.positions.size()), added);
      if (added) {
        const double t = std::clamp((iso - v[p]) / (v[r] - v[p]), kTMin, 1 - kTMin);
        const Eigen::Vector3d a = corner(p), b = corner(r);
        out.positions.push_back(a + t * (b - a));
      }
      local[p][r] = id;
      return id;
    };
    for (const auto& tet : kTets) {
      int s[4], pos = 0;
      for (int m = 0; m < 4; ++m) {
        s[m] = v[tet[m]] >= iso;
        pos += s[m];
      }
      if (pos == 0 || pos == 4) continue;
      // Gradient of the linear interpolant along the monotone path 0 -> A -> A|B -> 7.
      Eigen::Vector3d grad;
      for (int m = 0; m < 3; ++m) {
        const int bit = tet[m + 1] ^ tet[m];
        const int axis = bit == 1 ? 0 : (bit == 2 ? 1 : 2);
        grad[axis] = v[tet[m + 1]] - v[tet[m]];
      }
      auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
        const Eigen::Vector3d n =
            (out.positions[b] - out.positions[a]).cross(out.positions[c] - out.positions[a]);
        // Orient every triangle so its normal points towards increasing G (the print direction).
        if (n.dot(grad) < 0) std::swap(b, c);
        out.triangles.push_back({a, b, c});
      };
      if (pos == 1 || pos == 3) {
        const int lone = [&] {
          for (int m = 0; m < 4; ++m)
            if (s[m] == (pos == 1)) return m;
          return 0;
        }();
        uint32_t e[3];
        int ne = 0;
        for (int m = 0; m < 4; ++m)
          if (m != lone) e[ne++] = edgeVertex(tet[lone], tet[m]);
        emit(e[0], e[1], e[2]);
      } else {
        int P[2], N[2], np = 0, nn = 0;
        for (int m = 0; m < 4; ++m) {
          if (s[m]) P[np++] = tet[m];
          else N[nn++] = tet[m];
        }
        // Quad P0N0 - P0N1 - P1N1 - P1N0, split along its shorter diagonal.
        const uint32_t a = edgeVertex(P[0], N[0]), b = edgeVertex(P[0], N[1]),
                       c = edgeVertex(P[1], N[1]), d = edgeVertex(P[1], N[0]);
        if ((out.positions[a] - out.positions[c]).squaredNorm() <=
            (out.positions[b] - out.positions[d]).squaredNorm()) {
          emit(a, b, c);
          emit(a, c, d);
        } else {
          emit(a, b, d);
          emit(b, c, d);
        }
      }
    }
  }
  out.boundary.assign(out.positions.size(), 0);
}

// Intersection parameter s in [0, 1] of segment [p, q] with triangle (a, b, c), edges included
// (a tiny relative slack), or -1.
double segmentTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double den = n.dot(q - p);
  if (!(std::abs(den) > 1e-300)) return -1;
  const double s = n.dot(a - p) / den;
  if (s < 0 || s > 1) return -1;
  const Eigen::Vector3d x = p + s * (q - p);
  const double n2 = n.squaredNorm(), slack = -1e-9 * n2;
  if ((b - a).cross(x - a).dot(n) < slack || (c - b).cross(x - b).dot(n) < slack ||
      (a - c).cross(x - c).dot(n) < slack) {
    return -1;
  }
  return s;
}

// Crossing of segment [in, out] with the boundary of the inside set. The solid triangle nearest
// the bracket's middle usually holds the crossing: intersect the segment with it exactly (one
// closest-point query); otherwise halve the bracket by an inside test and try again, down to the
// tolerance (a support cell's face, or a crossing near a mesh edge, ends there).
Eigen::Vector3d trimCrossing(Eigen::Vector3d lo, Eigen::Vector3d hi, InsideTest& inside,
                             const AabbTree& tree, const Mesh& solid, double tolerance) {
  for (int it = 0; it < 64; ++it) {
    const Eigen::Vector3d mid = 0.5 * (lo + hi);
    const double len = (hi - lo).norm();
    const ClosestPoint cp = tree.closest(mid, 0.5 * len * (1 + 1e-9) + 1e-12);
    if (cp.triangle >= 0) {
      const size_t t = static_cast<size_t>(cp.triangle);
      const double s = segmentTriangle(lo, hi, solid.vertex(solid.triangles[3 * t]),
                                       solid.vertex(solid.triangles[3 * t + 1]),
                                       solid.vertex(solid.triangles[3 * t + 2]));
      if (s >= 0) return lo + s * (hi - lo);
    }
    if (len <= tolerance) return mid;
    if (inside(mid)) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

// Splits edges whose two ends are inside but whose middle leaves the inside set (the surface
// crosses a reflex corner of the solid's section between them): each such edge gets a vertex at
// an outside sample point (1/2, 1/4 or 3/4), and its one or two triangles are re-triangulated, so
// trimming then cuts the notch out. Edges with an end deep inside, or whose ball holds no surface,
// are skipped without ray casts. isIn is extended for the new vertices.
void splitExitingEdges(LayerSurface& s, std::vector<uint8_t>& isIn, InsideTest& inside,
                       const AabbTree& tree, double maxEdge, KeyMap& edgeMap) {
  edgeMap.clear();
  const size_t nv = s.positions.size();
  std::vector<uint8_t> deep(nv, 2);  // 2 = not computed
  auto edgeKey = [](uint32_t a, uint32_t b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
  };
  // The surface is consistently oriented: an interior edge appears once as a -> b with a < b.
  for (const auto& t : s.triangles) {
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = t[e], b = t[(e + 1) % 3];
      if (a > b || !isIn[a] || !isIn[b]) continue;
      for (uint32_t v : {a, b})
        if (deep[v] == 2) deep[v] = inside.deep(s.positions[v], maxEdge) ? 1 : 0;
      if (deep[a] || deep[b]) continue;
      const Eigen::Vector3d pa = s.positions[a], pb = s.positions[b];
      if (!tree.anyWithin(0.5 * (pa + pb), 0.5 * (pb - pa).norm())) continue;
      for (double u : {0.5, 0.25, 0.75}) {
        const Eigen::Vector3d x = pa + u * (pb - pa);
        if (inside(x)) continue;
        bool added = false;
        edgeMap.getOrAdd(edgeKey(a, b), static_cast<uint32_t>(s.positions.size()), added);
        s.positions.push_back(x);
        s.boundary.push_back(0);
        isIn.push_back(0);
        break;
      }
    }
  }
  if (edgeMap.size() == 0) return;
  auto splitOf = [&](uint32_t a, uint32_t b) -> uint32_t {
    if (a >= nv || b >= nv || !isIn[a] || !isIn[b]) return UINT32_MAX;
    return edgeMap.find(edgeKey(a, b));
  };
  std::vector<std::array<uint32_t, 3>> out;
  out.reserve(s.triangles.size() + 16);
  for (const auto& t : s.triangles) {
    uint32_t m[3];  // m[e]: split vertex of edge t[e] - t[e+1]
    int count = 0;
    for (int e = 0; e < 3; ++e) {
      m[e] = splitOf(t[e], t[(e + 1) % 3]);
      count += m[e] != UINT32_MAX;
    }
    if (count == 0) {
      out.push_back(t);
      continue;
    }
    if (count == 3) {
      out.push_back({t[0], m[0], m[2]});
      out.push_back({m[0], t[1], m[1]});
      out.push_back({m[2], m[1], t[2]});
      out.push_back({m[0], m[1], m[2]});
      continue;
    }
    // Rotate so that edge 0 is split and (for two splits) edge 1 too: the unsplit edges follow.
    int r = 0;
    for (int e = 0; e < 3; ++e) {
      const bool here = m[e] != UINT32_MAX, next = m[(e + 1) % 3] != UINT32_MAX;
      const bool prev = m[(e + 2) % 3] != UINT32_MAX;
      if (count == 1 ? here : (here && next && !prev)) r = e;
    }
    const uint32_t a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
    const uint32_t mab = m[r], mbc = m[(r + 1) % 3];
    if (count == 1) {
      out.push_back({a, mab, c});
      out.push_back({mab, b, c});
    } else {
      out.push_back({mab, b, mbc});
      out.push_back({a, mab, mbc});
      out.push_back({a, mbc, c});
    }
  }
  s.triangles.swap(out);
}

// Keeps the inside part of a surface: triangles with every vertex inside stay, crossing
// triangles are cut at the welded crossing point of each crossing edge (boundary vertices).
void trimSurface(LayerSurface& in, InsideTest& inside, const AabbTree& tree, const Mesh& solid,
                 double tolerance, double maxEdge, KeyMap& edgeMap, LayerSurface& out) {
  out.positions.clear();
  out.triangles.clear();
  out.boundary.clear();
  std::vector<uint8_t> isIn(in.positions.size());
  for (size_t v = 0; v < isIn.size(); ++v) isIn[v] = inside(in.positions[v]) ? 1 : 0;
  splitExitingEdges(in, isIn, inside, tree, maxEdge, edgeMap);
  edgeMap.clear();
  const size_t nv = in.positions.size();
  std::vector<uint32_t> remap(nv, UINT32_MAX);
  auto keep = [&](uint32_t v) {
    if (remap[v] == UINT32_MAX) {
      remap[v] = static_cast<uint32_t>(out.positions.size());
      out.positions.push_back(in.positions[v]);
      out.boundary.push_back(0);
    }
    return remap[v];
  };
  auto crossing = [&](uint32_t a, uint32_t b) {  // a inside, b outside
    const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    bool added = false;
    const uint32_t id = edgeMap.getOrAdd(key, static_cast<uint32_t>(out.positions.size()), added);
    if (added) {
      out.positions.push_back(
          trimCrossing(in.positions[a], in.positions[b], inside, tree, solid, tolerance));
      out.boundary.push_back(1);
    }
    return id;
  };
  for (const auto& t : in.triangles) {
    const int count = isIn[t[0]] + isIn[t[1]] + isIn[t[2]];
    if (count == 0) continue;
    if (count == 3) {
      out.triangles.push_back({keep(t[0]), keep(t[1]), keep(t[2])});
      continue;
    }
    // Rotate (keeping orientation) so that t[r] is the lone vertex.
    int r = 0;
    for (int m = 0; m < 3; ++m)
      if (isIn[t[m]] == (count == 1)) r = m;
    const uint32_t a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
    if (count == 1) {  // a inside
      const uint32_t ka = keep(a);
      const uint32_t xab = crossing(a, b), xac = crossing(a, c);
      out.triangles.push_back({ka, xab, xac});
    } else {  // a outside, b and c inside
      const uint32_t kb = keep(b), kc = keep(c);
      const uint32_t xba = crossing(b, a), xca = crossing(c, a);
      out.triangles.push_back({kb, kc, xca});
      out.triangles.push_back({kb, xca, xba});
    }
  }
}

// Collapses edges shorter than minLength, shortest first: an interior endpoint moves onto the
// other (boundary vertices keep their exact positions on the surface); a boundary edge may drop
// one of its two boundary vertices when that vertex lies within flatness of the new boundary
// chord. Only when the link condition holds (the endpoints share exactly the opposite vertices,
// so the mesh stays a manifold with boundary) and no surrounding triangle turns over. Marching
// tetrahedra leave clusters of vertices near lattice points and trimming leaves crossing points
// next to kept vertices; this removes those slivers without moving any vertex off the surface.
void collapseShortEdges(LayerSurface& s, double minLength, double flatness,
                        std::vector<std::vector<uint32_t>>& vt) {
  const size_t nv = s.positions.size(), nt = s.triangles.size();
  if (nt == 0 || !(minLength > 0)) return;
  const double min2 = minLength * minLength;
  struct Candidate {
    double len2;
    uint32_t a, b;
  };
  std::vector<Candidate> candidates;
  for (const auto& t : s.triangles)
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = t[e], b = t[(e + 1) % 3];
      if (a > b && s.boundary[a] + s.boundary[b] < 2) continue;  // interior edges: one side
      const double l2 = (s.positions[a] - s.positions[b]).squaredNorm();
      if (l2 < min2) candidates.push_back({l2, a, b});
    }
  if (candidates.empty()) return;
  // Total order (ties by index) so native and wasm collapse identically.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    if (x.len2 != y.len2) return x.len2 < y.len2;
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  // Vertex -> triangles.
  if (vt.size() < nv) vt.resize(nv);  // reused across layers: inner capacities persist
  for (size_t v = 0; v < nv; ++v) vt[v].clear();
  for (uint32_t f = 0; f < nt; ++f)
    for (uint32_t v : s.triangles[f]) vt[v].push_back(f);
  // Open-boundary vertices are pinned like trimmed-boundary vertices: on a consistently oriented
  // surface, side a -> b is open when no triangle of b has the side b -> a.
  std::vector<uint8_t> pinned(s.boundary);
  for (const auto& t : s.triangles)
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = t[e], b = t[(e + 1) % 3];
      bool twin = false;
      for (uint32_t f : vt[b]) {
        const auto& u = s.triangles[f];
        for (int m = 0; m < 3 && !twin; ++m) twin = u[m] == b && u[(m + 1) % 3] == a;
        if (twin) break;
      }
      if (!twin) pinned[a] = pinned[b] = 1;
    }
  std::vector<uint8_t> deadTri(nt, 0), removed(nv, 0);
  std::vector<uint32_t> ringK, ringR, shared;
  auto normal = [&](const std::array<uint32_t, 3>& t) {
    return Eigen::Vector3d((s.positions[t[1]] - s.positions[t[0]])
                               .cross(s.positions[t[2]] - s.positions[t[0]]));
  };
  for (const Candidate& c : candidates) {
    if (removed[c.a] || removed[c.b]) continue;
    uint32_t k = c.a, r = c.b;  // keep k, remove r (r pinned only when both are)
    if (pinned[r]) std::swap(k, r);
    const bool alongBoundary = pinned[r] != 0;
    if ((s.positions[k] - s.positions[r]).squaredNorm() >= min2) continue;
    shared.clear();
    ringR.clear();
    ringK.clear();
    Eigen::Vector3d average = Eigen::Vector3d::Zero();
    for (uint32_t f : vt[r]) {
      if (deadTri[f]) continue;
      const auto& t = s.triangles[f];
      average += normal(t);
      if (t[0] == k || t[1] == k || t[2] == k) shared.push_back(f);
      for (uint32_t v : t)
        if (v != r) ringR.push_back(v);
    }
    // An interior r: its edge to k has two triangles. Two pinned ends: only a boundary edge (one
    // triangle) may collapse, r leaving the boundary polyline (both ends lie on the surface).
    if (shared.size() != (alongBoundary ? 1u : 2u)) continue;
    for (uint32_t f : vt[k]) {
      if (deadTri[f]) continue;
      for (uint32_t v : s.triangles[f])
        if (v != k) ringK.push_back(v);
    }
    std::sort(ringR.begin(), ringR.end());
    ringR.erase(std::unique(ringR.begin(), ringR.end()), ringR.end());
    std::sort(ringK.begin(), ringK.end());
    ringK.erase(std::unique(ringK.begin(), ringK.end()), ringK.end());
    size_t common = 0;
    for (size_t i = 0, j = 0; i < ringR.size() && j < ringK.size();) {
      if (ringR[i] < ringK[j]) ++i;
      else if (ringK[j] < ringR[i]) ++j;
      else {
        ++common;
        ++i;
        ++j;
      }
    }
    if (common != shared.size()) continue;  // link condition: only the opposite vertices
    if (alongBoundary) {
      // r must lie within flatness of the chord from its other boundary neighbour to k (keeps
      // corners of the trimmed outline and the outline on the surface).
      int other = -1, open = 0;
      for (uint32_t v : ringR) {
        int uses = 0;
        for (uint32_t f : vt[r]) {
          if (deadTri[f]) continue;
          const auto& t = s.triangles[f];
          uses += (t[0] == v || t[1] == v || t[2] == v);
        }
        if (uses == 1 && v != k) {
          other = static_cast<int>(v);
          ++open;
        }
      }
      if (open != 1) continue;
      const Eigen::Vector3d& p = s.positions[static_cast<size_t>(other)];
      const Eigen::Vector3d& q = s.positions[k];
      const Eigen::Vector3d d = q - p;
      const double len2 = d.squaredNorm();
      const Eigen::Vector3d x = s.positions[r] - p;
      const double off2 = len2 > 0 ? (x - d * (x.dot(d) / len2)).squaredNorm() : x.squaredNorm();
      if (off2 > flatness * flatness) continue;
    }
    bool ok = true;
    const double avgNorm = average.norm();
    for (uint32_t f : vt[r]) {
      if (deadTri[f] || std::find(shared.begin(), shared.end(), f) != shared.end()) continue;
      std::array<uint32_t, 3> t = s.triangles[f];
      for (uint32_t& v : t)
        if (v == r) v = k;
      const Eigen::Vector3d n = normal(t);
      if (!(n.dot(average) > 0.3 * n.norm() * avgNorm)) {
        ok = false;
        break;
      }
    }
    if (!ok) continue;
    for (uint32_t f : shared) deadTri[f] = 1;
    for (uint32_t f : vt[r]) {
      if (deadTri[f]) continue;
      for (uint32_t& v : s.triangles[f])
        if (v == r) v = k;
      vt[k].push_back(f);
    }
    vt[r].clear();
    removed[r] = 1;
  }
  // Compact.
  std::vector<uint32_t> remap(nv, UINT32_MAX);
  LayerSurface out;
  for (uint32_t f = 0; f < nt; ++f) {
    if (deadTri[f]) continue;
    std::array<uint32_t, 3> t = s.triangles[f];
    for (uint32_t& v : t) {
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<uint32_t>(out.positions.size());
        out.positions.push_back(s.positions[v]);
        out.boundary.push_back(s.boundary[v]);
      }
      v = remap[v];
    }
    out.triangles.push_back(t);
  }
  s = std::move(out);
}

// Splits a trimmed layer into connected regions (triangles sharing vertices).
void splitRegions(const LayerSurface& s, const InsideTest& inside,
                  double minArea, CurvedLayer& layer) {
  const size_t nv = s.positions.size();
  DisjointSets sets(nv);
  auto find = [&](uint32_t x) { return sets.find(x); };
  for (const auto& t : s.triangles) {
    sets.unite(t[0], t[1]);
    sets.unite(t[0], t[2]);
  }
  std::vector<uint32_t> regionOf(nv, UINT32_MAX);
  std::vector<std::vector<uint32_t>> trisOf;
  for (size_t f = 0; f < s.triangles.size(); ++f) {
    const uint32_t root = find(s.triangles[f][0]);
    if (regionOf[root] == UINT32_MAX) {
      regionOf[root] = static_cast<uint32_t>(trisOf.size());
      trisOf.emplace_back();
    }
    trisOf[regionOf[root]].push_back(static_cast<uint32_t>(f));
  }
  std::vector<uint32_t> local(nv, UINT32_MAX);
  for (const auto& tris : trisOf) {
    LayerRegion region;
    double supportArea = 0;
    for (uint32_t f : tris) {
      const auto& t = s.triangles[f];
      const Eigen::Vector3d &a = s.positions[t[0]], &b = s.positions[t[1]], &c = s.positions[t[2]];
      const double area = 0.5 * (b - a).cross(c - a).norm();
      region.area += area;
      if (inside.inSupport((a + b + c) / 3.0)) supportArea += area;
      for (uint32_t v : t) {
        if (local[v] == UINT32_MAX) {
          local[v] = static_cast<uint32_t>(region.boundaryVertex.size());
          region.boundaryVertex.push_back(s.boundary[v]);
          region.mesh.positions.insert(region.mesh.positions.end(),
                                       {s.positions[v].x(), s.positions[v].y(), s.positions[v].z()});
        }
        region.mesh.triangles.push_back(local[v]);
      }
    }
    for (uint32_t f : tris)
      for (uint32_t v : s.triangles[f]) local[v] = UINT32_MAX;
    if (region.area < minArea) continue;
    region.support = supportArea > 0.5 * region.area;
    layer.regions.push_back(std::move(region));
  }
}

// Bounded thickness (CurvedLayersOptions::maxThickness): the partial layers between the full
// layers g_(i-1) (previous) and g_i (layer), in print order. The levels needed follow from the
// largest distance of the layer's vertices to the previous one or the platform (z = 0); the sub-surface at fraction
// k / 2^levels of the step is kept where the two full layers lie further apart (sum of the
// distances to both) than kPartialClip x maxThickness x 2^(its level - 1).
constexpr double kPartialClip = 0.95;
constexpr int kMaxPartialLevels = 3;

template <class SurfaceAt>
std::vector<CurvedLayer> partialLayersBetween(int i, const CurvedLayer& layer, const AabbTree& previous,
                                              const AabbTree& current, SurfaceAt&& surfaceAt, double isoLo,
                                              double isoHi, double maxThickness, double minArea) {
  std::vector<CurvedLayer> out;
  const double reach = 8 * maxThickness;  // farther counts as nothing below (a new island)
  double worst = 0;
  for (const LayerRegion& r : layer.regions)
    for (size_t v = 0; v < r.mesh.vertexCount(); ++v) {
      const Eigen::Vector3d p = r.mesh.vertex(v);
      const double d = std::min(std::max(0.0, p.z()), previous.closest(p, reach).distance);  // platform z = 0
      if (std::isfinite(d) && d < reach) worst = std::max(worst, d);
    }
  if (!(worst > maxThickness)) return out;
  const int levels = std::min(kMaxPartialLevels, static_cast<int>(std::ceil(std::log2(worst / maxThickness))));
  const int pieces = 1 << levels;
  for (int k = 1; k < pieces; ++k) {
    int zeros = 0;
    while (((k >> zeros) & 1) == 0) ++zeros;
    const int level = levels - zeros;
    const double threshold = kPartialClip * maxThickness * double(1 << (level - 1));
    CurvedLayer sub = surfaceAt(i, isoLo + (isoHi - isoLo) * double(k) / double(pieces));
    clipLayerRegions(
        sub,
        [&](const Eigen::Vector3d& p) {
          const double a = std::min(std::max(0.0, p.z()), previous.closest(p, reach).distance),
                       b = current.closest(p, reach).distance;
          if (!std::isfinite(a) || !std::isfinite(b)) return -1.0;
          return a + b - threshold;
        },
        minArea);
    if (sub.regions.empty()) continue;
    sub.partial = true;
    out.push_back(std::move(sub));
  }
  return out;
}

}  // namespace

CurvedLayersResult extractCurvedLayers(const VoxelGrid& grid, const std::vector<int32_t>& g,
                                       const Mesh& solid, const CurvedLayersOptions& options,
                                       const ProgressFn& progress) {
  CurvedLayersResult result;
  auto fail = [&](Status s, std::string msg) {
    result.status = s;
    result.message = std::move(msg);
    result.layers.clear();
    result.regionCount = result.triangleCount = 0;
    return result;
  };
  const size_t cellCount = grid.cellCount();
  if (!(grid.width > 0) || !std::isfinite(grid.width) || grid.dims.minCoeff() <= 0 ||
      !grid.origin.allFinite()) {
    return fail(Status::InvalidOption, "curved layers: voxel grid has no cells or a bad width");
  }
  if (cellCount != static_cast<size_t>(grid.dims.x()) * grid.dims.y() * grid.dims.z() ||
      cellCount >= UINT32_MAX / 8) {
    return fail(Status::InvalidOption, "curved layers: voxel grid state size does not match dims");
  }
  if (g.size() != cellCount) {
    return fail(Status::InvalidOption, "curved layers: field has " + std::to_string(g.size()) +
                                           " values for " + std::to_string(cellCount) + " cells");
  }
  if (!(options.isoStep >= 0) || !std::isfinite(options.isoStep) ||
      (options.isoStep == 0 && !(options.nozzleDiameter > 0 && std::isfinite(options.nozzleDiameter)))) {
    return fail(Status::InvalidOption, "curved layers: isoStep must be >= 0 (0 = w/d with nozzleDiameter > 0)");
  }
  if (!(options.trimTolerance > 0) || !std::isfinite(options.trimTolerance) ||
      !(options.minRegionArea >= 0) || !std::isfinite(options.minRegionArea) ||
      !(options.collapseRatio >= 0 && options.collapseRatio < 1)) {
    return fail(Status::InvalidOption, "curved layers: trimTolerance must be > 0, minRegionArea >= 0, collapseRatio in [0, 1)");
  }
  if (solid.empty()) return fail(Status::EmptyInput, "curved layers: the solid has no triangles");
  for (double x : solid.positions)
    if (!std::isfinite(x)) return fail(Status::NonFiniteVertex, "curved layers: solid has a non-finite vertex");

  const auto t0 = Clock::now();
  const double step = options.isoStep > 0 ? options.isoStep : grid.width / options.nozzleDiameter;
  const CentreField field = buildField(grid, g);
  if (field.maxG < 1) return fail(Status::EmptyInput, "curved layers: no grown voxels (max G < 1)");
  // Layer i is the iso-surface g = i x step (its beads' tops: the first layer one step above the
  // bed); the top layer may lie in the extension band, half a cell above the last grown centres.
  const double layerCountD = std::ceil(field.maxG / step - 1e-9) + 1;
  if (layerCountD > 1e6) {
    return fail(Status::InvalidOption, "curved layers: isoStep " + std::to_string(step) +
                                           " gives over a million iso-values");
  }
  const int layerCount = std::max(1, static_cast<int>(layerCountD));
  auto isoValue = [&](int i) { return i * step; };

  // Dual cubes with all 8 corners valued, bucketed by the iso-values they may cross (CSR), so each
  // layer visits only its narrow band.
  const size_t nx = static_cast<size_t>(grid.dims.x());
  const size_t nxy = nx * static_cast<size_t>(grid.dims.y());
  const size_t offset[8] = {0, 1, nx, nx + 1, nxy, nxy + 1, nxy + nx, nxy + nx + 1};
  std::vector<uint32_t> cubes;
  std::vector<std::pair<int, int>> cubeRange;
  std::vector<uint64_t> bucketStart(static_cast<size_t>(layerCount) + 2, 0);
  for (uint32_t c : field.cells) {
    const Eigen::Vector3i v = grid.cell(c);
    if (v.x() + 1 >= grid.dims.x() || v.y() + 1 >= grid.dims.y() || v.z() + 1 >= grid.dims.z()) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    bool complete = true;
    for (size_t o : offset) {
      const float f = field.value[c + o];
      if (std::isnan(f)) {
        complete = false;
        break;
      }
      lo = std::min(lo, static_cast<double>(f));
      hi = std::max(hi, static_cast<double>(f));
    }
    if (!complete || hi <= lo) continue;
    // g_i > lo and g_i <= hi, widened by one for rounding; the per-tetrahedron test is exact.
    const int first = std::max(1, static_cast<int>(std::floor(lo / step + 0.5)));
    const int last = std::min(layerCount, static_cast<int>(std::floor(hi / step + 0.5)) + 1);
    if (first > last) continue;
    cubes.push_back(c);
    cubeRange.emplace_back(first, last);
    for (int i = first; i <= last; ++i) ++bucketStart[i + 1];
  }
  for (size_t i = 1; i < bucketStart.size(); ++i) bucketStart[i] += bucketStart[i - 1];
  if (bucketStart.back() > 400000000ULL) {
    return fail(Status::InvalidOption, "curved layers: too many iso-surface cells (isoStep too small)");
  }
  std::vector<uint32_t> bucket(bucketStart.back());
  {
    std::vector<uint64_t> fill(bucketStart.begin(), bucketStart.end() - 1);
    for (size_t q = 0; q < cubes.size(); ++q)
      for (int i = cubeRange[q].first; i <= cubeRange[q].second; ++i) bucket[fill[i]++] = cubes[q];
  }
  cubes.clear();
  cubes.shrink_to_fit();
  cubeRange.clear();
  cubeRange.shrink_to_fit();
  result.extractionMs += msSince(t0);
  if (!reportProgress(progress, "layers", 0.0)) return fail(Status::Cancelled, "curved layers: cancelled");

  const auto t1 = Clock::now();
  const AabbTree tree(solid);
  // Scratch space of one thread: the inside test (its caches), the iso-surface workspaces.
  struct Scratch {
    std::unique_ptr<InsideTest> inside;
    KeyMap edgeMap;
    LayerSurface raw, trimmed;
    std::vector<std::vector<uint32_t>> vertexTriangles;  // collapse workspace
    double extractionMs = 0, trimmingMs = 0;
  };
  const size_t threads = std::min<size_t>(std::max<size_t>(1, options.threads), size_t(layerCount));
  std::vector<Scratch> scratch(threads);
  scratch[0].inside = std::make_unique<InsideTest>(grid, tree, solid);
  result.trimmingMs += msSince(t1);

  // The iso-surface at `iso` (between g_(i-1) and g_i), trimmed and split into regions.
  auto surfaceWith = [&](Scratch& w, int i, double iso) {
    CurvedLayer layer;
    layer.isoValue = iso;
    const auto te = Clock::now();
    extractIsoSurface(grid, field, bucket.data() + bucketStart[i], bucketStart[i + 1] - bucketStart[i],
                      iso, w.edgeMap, w.raw);
    w.extractionMs += msSince(te);
    if (w.raw.triangles.empty()) return layer;
    const auto tt = Clock::now();
    if (!w.inside) w.inside = std::make_unique<InsideTest>(grid, tree, solid);
    trimSurface(w.raw, *w.inside, tree, solid, options.trimTolerance, std::sqrt(3.0) * grid.width,
                w.edgeMap, w.trimmed);
    collapseShortEdges(w.trimmed, options.collapseRatio * grid.width, options.trimTolerance,
                       w.vertexTriangles);
    splitRegions(w.trimmed, *w.inside, options.minRegionArea, layer);
    w.trimmingMs += msSince(tt);
    return layer;
  };
  auto keep = [&](CurvedLayer&& layer) {
    for (const LayerRegion& r : layer.regions) result.triangleCount += r.mesh.faceCount();
    result.regionCount += layer.regions.size();
    result.partialLayers += layer.partial ? 1 : 0;
    result.layers.push_back(std::move(layer));
  };
  // Every full layer on its own, on the threads (the same surfaces on any number of them).
  std::vector<CurvedLayer> full(static_cast<size_t>(layerCount) + 1);
  const bool extracted = parallelFor(
      size_t(layerCount), threads,
      [&](size_t k, size_t worker) {
        const int i = int(k) + 1;
        full[size_t(i)] = surfaceWith(scratch[worker], i, isoValue(i));
      },
      [&](size_t done) { return reportProgress(progress, "layers", 0.5 * double(done) / layerCount); });
  if (!extracted) return fail(Status::Cancelled, "curved layers: cancelled");
  // Bounded thickness: the partial layers between consecutive full layers g_(i-1) and g_i (both
  // with regions), printed before g_i, found from the two layers' surface trees.
  std::vector<std::vector<CurvedLayer>> partials(static_cast<size_t>(layerCount) + 1);
  if (options.maxThickness > 0) {
    const auto tp = Clock::now();
    auto between = [&](int i, const AabbTree& previous, const AabbTree& current, Scratch& w) {
      partials[size_t(i)] = partialLayersBetween(
          i, full[size_t(i)], previous, current, [&](int j, double iso) { return surfaceWith(w, j, iso); },
          isoValue(i - 1), isoValue(i), options.maxThickness, options.minRegionArea);
    };
    auto paired = [&](int i) { return i >= 2 && !full[size_t(i)].regions.empty() && !full[size_t(i - 1)].regions.empty(); };
    auto tick = [&](size_t done) {
      return reportProgress(progress, "layers", 0.5 + 0.5 * double(done) / layerCount);
    };
    // Blocks of consecutive layers, each on one thread, building each layer's tree once (and the
    // one below the block's first): one block when one thread runs them all.
    const int block = threads == 1 ? layerCount : 8;
    const size_t blocks = size_t((layerCount + block - 1) / block);
    bool cancelled = false;  // one thread: its progress, layer by layer
    const bool finished = parallelFor(
        blocks, threads,
        [&](size_t b, size_t worker) {
          const int first = int(b) * block + 1, last = std::min(layerCount, first + block - 1);
          std::unique_ptr<AabbTree> previousTree;
          if (paired(first)) previousTree = std::make_unique<AabbTree>(layerMesh(full[size_t(first - 1)]));
          for (int i = first; i <= last; ++i) {
            if (threads == 1 && !tick(size_t(i - 1))) {
              cancelled = true;
              return;
            }
            if (full[size_t(i)].regions.empty()) {
              previousTree.reset();
              continue;
            }
            auto currentTree = std::make_unique<AabbTree>(layerMesh(full[size_t(i)]));
            if (paired(i)) between(i, *previousTree, *currentTree, scratch[worker]);
            previousTree = std::move(currentTree);
          }
        },
        [&](size_t done) { return tick(std::min(size_t(layerCount), done * size_t(block))); });
    if (!finished || cancelled) return fail(Status::Cancelled, "curved layers: cancelled");
    result.partialMs += msSince(tp);
  }
  for (int i = 1; i <= layerCount; ++i) {
    if (full[size_t(i)].regions.empty()) continue;
    for (CurvedLayer& partial : partials[size_t(i)]) keep(std::move(partial));
    keep(std::move(full[size_t(i)]));
  }
  for (const Scratch& w : scratch) {
    result.extractionMs += w.extractionMs;
    result.trimmingMs += w.trimmingMs;
  }
  if (!reportProgress(progress, "layers", 1.0)) return fail(Status::Cancelled, "curved layers: cancelled");

  const auto t2 = Clock::now();
  result.thickness = layerThicknessStats(result.layers, grid.width);
  result.thicknessMs = msSince(t2);
  return result;
}

}  // namespace omnislice
