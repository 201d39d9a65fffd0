// SPDX-License-Identifier: MIT
// Growing field by convex-front advancing (paper 001 Sections 4.2-4.4, Algorithm 1).
//
// Speed (the paper spent ~90% of its time in shadow checks):
// - Every unprocessed, not yet shadowed voxel keeps a cached separating plane (an id in a plane
//   registry shared by all hulls). A hull "activates" its planes by stamping their ids, so the
//   question "is this voxel still outside the new hull by eps?" costs one array read while the
//   cached plane survives; only voxels whose plane was removed are re-tested (hinted scans).
// - The potentially shadowed set S_p of Section 4.3 is computed once per layer against
//   C_p = C(C_c U L_next); the sub-tests with C_t (subset of C_p) only scan S_p and stop at the
//   first shadowed voxel.
// - Rejected voxels of L_next that lie inside or on the accepted hull are added back (they do not
//   change the hull, so they cannot shadow anything), so shadow prevention never shadows its own
//   rejects.
// - Inverse peeling builds each hull from the remaining voxels with a non-remaining face
//   neighbour only (a voxel whose 6 face neighbours remain is at least 1/sqrt(3) > eps deep), and
//   finds each sheet by rasterising the eps-band of every hull triangle instead of testing every
//   boundary voxel against every plane.
#include "voxel/growth_field.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <queue>
#include <random>
#include <unordered_map>

#include "common/stopwatch.h"
#include "geometry/aabb_tree.h"
#include "voxel/lattice_hull.h"

namespace omnislice {

const char* growthStrategyName(GrowthStrategy s) {
  switch (s) {
    case GrowthStrategy::Gcfa: return "gcfa";
    case GrowthStrategy::SpGcfa: return "sp-gcfa";
    case GrowthStrategy::PgGcfa: return "pg-gcfa";
    case GrowthStrategy::PgSpGcfa: return "pg-sp-gcfa";
  }
  return "pg-sp-gcfa";
}

const char* shadowSchemeName(ShadowScheme s) {
  return s == ShadowScheme::Incremental ? "incremental" : "recursive";
}

bool parseGrowthStrategy(const std::string& text, GrowthStrategy& out) {
  for (GrowthStrategy s : {GrowthStrategy::Gcfa, GrowthStrategy::SpGcfa, GrowthStrategy::PgGcfa,
                           GrowthStrategy::PgSpGcfa})
    if (text == growthStrategyName(s)) {
      out = s;
      return true;
    }
  return false;
}

bool parseShadowScheme(const std::string& text, ShadowScheme& out) {
  if (text == "incremental") {
    out = ShadowScheme::Incremental;
    return true;
  }
  if (text == "recursive") {
    out = ShadowScheme::RecursivePca;
    return true;
  }
  return false;
}

namespace {

using V3 = Eigen::Vector3i;

bool gridConsistent(const VoxelGrid& grid) {
  if (grid.dims.minCoeff() <= 0) return false;
  const uint64_t n = static_cast<uint64_t>(grid.dims.x()) * static_cast<uint64_t>(grid.dims.y()) *
                     static_cast<uint64_t>(grid.dims.z());
  return n == static_cast<uint64_t>(grid.state.size()) && n < (uint64_t(1) << 32);
}

// Dense numbering of the printable cells.
struct Voxels {
  std::vector<uint32_t> cell;    // voxel -> cell
  std::vector<V3> pos;           // voxel -> (i, j, k)
  std::vector<int32_t> ofCell;   // cell -> voxel, -1 when not printable
  std::vector<V3> platform;      // platform cell coordinates
  explicit Voxels(const VoxelGrid& grid) {
    ofCell.assign(grid.cellCount(), -1);
    for (size_t c = 0; c < grid.cellCount(); ++c) {
      if (grid.printable(c)) {
        ofCell[c] = static_cast<int32_t>(cell.size());
        cell.push_back(static_cast<uint32_t>(c));
        pos.push_back(grid.cell(c));
      } else if (grid.state[c] == static_cast<uint8_t>(VoxelState::Platform)) {
        platform.push_back(grid.cell(c));
      }
    }
  }
  size_t size() const { return cell.size(); }
  // Voxel at p (-1 when out of range or not printable).
  int32_t at(const VoxelGrid& grid, const V3& p) const {
    if (!grid.inRange(p.x(), p.y(), p.z())) return -1;
    return ofCell[grid.index(p.x(), p.y(), p.z())];
  }
};

// Planes of all hulls built, keyed by (normal, offset); a hull marks its planes alive by stamping.
class PlaneRegistry {
 public:
  struct Active {
    LatticeHull hull;
    std::vector<int32_t> ids;  // registry id per hull plane
  };
  Active make(LatticeHull hull) {
    Active a;
    a.hull = std::move(hull);
    a.ids.reserve(a.hull.planes().size());
    for (const LatticeHull::Plane& p : a.hull.planes()) {
      const Key k{p.nx, p.ny, p.nz, p.offset};
      auto it = ids_.find(k);
      if (it == ids_.end()) {
        it = ids_.emplace(k, static_cast<int32_t>(stamp_.size())).first;
        stamp_.push_back(0);
        plane_.push_back(p);
      }
      a.ids.push_back(it->second);
    }
    return a;
  }
  // Make a the hull the cached planes are checked against.
  void activate(const Active& a) {
    ++current_;
    for (int32_t id : a.ids) stamp_[id] = current_;
  }
  bool alive(int32_t id) const { return id >= 0 && stamp_[id] == current_; }
  const LatticeHull::Plane& plane(int32_t id) const { return plane_[id]; }
  size_t size() const { return stamp_.size(); }
  void clear() {
    ids_.clear();
    stamp_.clear();
    plane_.clear();
  }

 private:
  struct Key {
    int64_t a, b, c, d;
    bool operator==(const Key& o) const { return a == o.a && b == o.b && c == o.c && d == o.d; }
  };
  struct Hash {
    size_t operator()(const Key& k) const {
      uint64_t h = static_cast<uint64_t>(k.a) * 0x9E3779B97F4A7C15ULL;
      h ^= static_cast<uint64_t>(k.b) * 0xC2B2AE3D27D4EB4FULL + (h << 6) + (h >> 2);
      h ^= static_cast<uint64_t>(k.c) * 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
      h ^= static_cast<uint64_t>(k.d) * 0x27D4EB2F165667C5ULL + (h << 6) + (h >> 2);
      return static_cast<size_t>(h);
    }
  };
  std::unordered_map<Key, int32_t, Hash> ids_;
  std::vector<uint32_t> stamp_;
  std::vector<LatticeHull::Plane> plane_;
  uint32_t current_ = 0;
};

enum : uint8_t { Unprocessed = 0, Processed = 1, Shadowed = 2 };

class Grower {
 public:
  Grower(const VoxelGrid& grid, const GrowthOptions& options, const ProgressFn& progress,
         GrowthField& out)
      : grid_(grid), opt_(options), progress_(progress), out_(out), vox_(grid) {}

  Status run() {
    const auto t0 = Clock::now();
    const size_t n = vox_.size();
    state_.assign(n, Unprocessed);
    sep_.assign(n, -1);
    inFrontier_.assign(n, 0);
    mark_.assign(n, 0);
    g_.assign(n, -1);
    blocker_.assign(n, -1);
    const bool pg = opt_.strategy == GrowthStrategy::PgGcfa ||
                    opt_.strategy == GrowthStrategy::PgSpGcfa;
    sp_ = opt_.strategy == GrowthStrategy::SpGcfa || opt_.strategy == GrowthStrategy::PgSpGcfa;
    if (pg) {
      const auto tp = Clock::now();
      std::vector<int32_t> peel = inversePeelingField(grid_, opt_.epsilon, progress_);
      out_.peelingMs = msSince(tp);
      if (peel.size() != grid_.cellCount()) return Status::Cancelled;
      peel_.resize(n);
      for (size_t v = 0; v < n; ++v) peel_[v] = peel[vox_.cell[v]];
      out_.peel = std::move(peel);
      peelMax_ = *std::max_element(peel_.begin(), peel_.end());
    }
    if (sp_) {
      alive_.resize(n);
      for (size_t v = 0; v < n; ++v) alive_[v] = static_cast<int32_t>(v);
    }

    // Layer 1: printable cells resting on platform cells.
    std::vector<int32_t> layer;
    for (size_t v = 0; v < n; ++v) {
      const V3& p = vox_.pos[v];
      if (p.z() == grid_.platformK + 1 && grid_.inRange(p.x(), p.y(), p.z() - 1) &&
          grid_.at(p.x(), p.y(), p.z() - 1) == VoxelState::Platform)
        layer.push_back(static_cast<int32_t>(v));
    }
    double fTau = pg ? opt_.peelStep : std::numeric_limits<double>::infinity();
    int32_t tau = 1;
    for (int32_t v : layer) g_[v] = tau;
    PlaneRegistry::Active cPrev = planes_.make(LatticeHull(vox_.platform));
    ++out_.hullBuilds;
    bool havePrepared = false;  // cNext already holds C(C_prev U layer) from shadow prevention
    PlaneRegistry::Active cNext;
    size_t grown = layer.size();
    size_t sinceReport = 0;
    while (true) {
      while (!layer.empty()) {
        for (int32_t v : layer) {
          state_[v] = Processed;
          for (const V3& o : amStableOffsets()) {
            const int32_t w = vox_.at(grid_, vox_.pos[v] + o);
            if (w >= 0 && state_[w] == Unprocessed && !inFrontier_[w]) {
              inFrontier_[w] = 1;
              frontier_.push_back(w);
            }
          }
        }
        PlaneRegistry::Active cC;
        if (havePrepared) {
          cC = std::move(cNext);
        } else {
          cC = planes_.make(cPrev.hull.extended(positions(layer)));
          ++out_.hullBuilds;
        }
        havePrepared = false;
        if (sp_) {
          const auto ts = Clock::now();
          updateAlive(cC);
          out_.shadowMs += msSince(ts);
        }
        ++tau;
        // Candidates: unprocessed printable ASN of the layer, not inside C_c.
        std::vector<int32_t> next;
        ++markStamp_;
        int hint = 0;
        for (int32_t v : layer)
          for (const V3& o : amStableOffsets()) {
            const int32_t w = vox_.at(grid_, vox_.pos[v] + o);
            if (w < 0 || state_[w] != Unprocessed || mark_[w] == markStamp_) continue;
            mark_[w] = markStamp_;
            if (pg && peel_[w] > fTau) continue;
            if (cC.hull.inside(vox_.pos[w], opt_.epsilon, &hint)) {
              state_[w] = Shadowed;  // the hull only grows: never reachable again
              continue;
            }
            next.push_back(w);
          }
        if (sp_ && !next.empty()) {
          // No sacrifice here: a stuck front first re-seeds from the whole frontier and raises
          // f_tau; shadows are only accepted when nothing else can grow (below).
          const auto ts = Clock::now();
          next = preventShadows(cC, next, cNext, false);
          if (cancelled_) return Status::Cancelled;
          havePrepared = !next.empty();
          out_.shadowMs += msSince(ts);
        }
        if (next.empty()) --tau;
        for (int32_t w : next) g_[w] = tau;
        grown += next.size();
        grownSoFar_ = grown;
        cPrev = std::move(cC);
        layer = std::move(next);
        sinceReport += layer.size();
        if (sinceReport > 2000 || layer.empty()) {
          sinceReport = 0;
          if (!reportProgress(progress_, "growth", n ? double(grown) / double(n) : 1.0))
            return Status::Cancelled;
        }
        if (planes_.size() > 500000) {
          // Bound memory: forget cached planes (they are only hints) and restart the registry.
          planes_.clear();
          std::fill(sep_.begin(), sep_.end(), -1);
          cPrev = planes_.make(LatticeHull(cPrev.hull));
          if (havePrepared) cNext = planes_.make(LatticeHull(cNext.hull));
        }
      }
      // Front stuck (or threshold step): re-seed from every unprocessed voxel touching V that is
      // not inside C_prev (Algorithm 1 never re-seeds; deferred voxels are found here too).
      std::vector<int32_t> seeds;
      size_t keep = 0;
      int hint = 0;
      for (size_t i = 0; i < frontier_.size(); ++i) {
        const int32_t w = frontier_[i];
        if (state_[w] != Unprocessed) continue;
        frontier_[keep++] = w;
        if (pg && peel_[w] > fTau) continue;
        if (cPrev.hull.inside(vox_.pos[w], opt_.epsilon, &hint)) {
          state_[w] = Shadowed;
          --keep;
          continue;
        }
        seeds.push_back(w);
      }
      frontier_.resize(keep);
      if (seeds.empty()) {
        if (fTau > peelMax_ || !pg) break;
        fTau += opt_.peelStep;
        continue;
      }
      if (sp_) {
        const auto ts = Clock::now();
        updateAlive(cPrev);
        const bool last = !pg || fTau > peelMax_;
        seeds = preventShadows(cPrev, seeds, cNext, last);
        if (cancelled_) return Status::Cancelled;
        havePrepared = !seeds.empty();
        out_.shadowMs += msSince(ts);
        if (seeds.empty()) {
          fTau += opt_.peelStep;
          continue;
        }
      }
      ++tau;
      for (int32_t w : seeds) g_[w] = tau;
      grown += seeds.size();
      grownSoFar_ = grown;
      layer = std::move(seeds);
    }

    out_.g.assign(grid_.cellCount(), 0);
    out_.layers = 0;
    for (size_t v = 0; v < n; ++v) {
      out_.g[vox_.cell[v]] = g_[v];
      if (g_[v] >= 1) {
        ++out_.grown;
        out_.layers = std::max(out_.layers, g_[v]);
      } else {
        ++out_.missed;
      }
    }
    out_.totalMs = msSince(t0);
    reportProgress(progress_, "growth", 1.0);
    return Status::Ok;
  }

 private:
  std::vector<V3> positions(const std::vector<int32_t>& vs) const {
    std::vector<V3> p;
    p.reserve(vs.size());
    for (int32_t v : vs) p.push_back(vox_.pos[v]);
    return p;
  }

  // True when voxel v is inside hull a by eps; caches a separating plane otherwise. The cached
  // plane is alive in ~58 % of the ~420M calls of the voxel bunny 540k: that test stays inline in
  // the scans, the plane search is a call (in wasm the whole function stayed out of line, a call
  // per voxel scanned: wasm growth 5.5 -> 4.5 s with this split).
  bool insideActive(const PlaneRegistry::Active& a, int32_t v) {
    if (planes_.alive(sep_[v])) return false;
    return searchSeparatingPlane(a, v);
  }

  // insideActive past a dead cached plane (kept out of line, else clang folds it back in and
  // leaves insideActive itself out of line).
#if defined(__GNUC__) || defined(__clang__)
  __attribute__((noinline))
#endif
  bool searchSeparatingPlane(const PlaneRegistry::Active& a, int32_t v) {
    ++out_.shadowChecks;
    const std::vector<LatticeHull::Plane>& pl = a.hull.planes();
    const V3& p = vox_.pos[v];
    if (a.hull.dimension() < 3) return a.hull.inside(p, opt_.epsilon);
    const int np = static_cast<int>(pl.size());
    int start = rolling_ < np ? rolling_ : 0;
    for (int k = 0; k < np; ++k) {
      int i = start + k;
      if (i >= np) i -= np;
      if (pl[i].distance(p) > -opt_.epsilon) {
        sep_[v] = a.ids[i];
        rolling_ = i;
        return false;
      }
    }
    return true;
  }

  // Drop processed voxels from the alive list and mark the ones inside c as shadowed.
  void updateAlive(const PlaneRegistry::Active& c) {
    planes_.activate(c);
    size_t keep = 0;
    for (size_t i = 0; i < alive_.size(); ++i) {
      const int32_t v = alive_[i];
      if (state_[v] != Unprocessed) continue;
      if (insideActive(c, v)) {
        state_[v] = Shadowed;
        continue;
      }
      alive_[keep++] = v;
    }
    alive_.resize(keep);
  }

  // Section 4.3: the subset of next that can be added to C_c without new shadowed voxels (all of
  // next when nothing can be added without shadowing: step 6 sacrifices the new shadows).
  // hullOut receives C(C_c U result).
  std::vector<int32_t> preventShadows(const PlaneRegistry::Active& cC,
                                      const std::vector<int32_t>& next,
                                      PlaneRegistry::Active& hullOut, bool allowSacrifice) {
    ++markStamp_;
    for (int32_t v : next) mark_[v] = markStamp_;
    PlaneRegistry::Active cP = planes_.make(cC.hull.extended(positions(next)));
    ++out_.hullBuilds;
    planes_.activate(cP);
    std::vector<int32_t> sP;  // S_p minus S_c: unshadowed unprocessed voxels inside C_p
    for (int32_t v : alive_)
      if (state_[v] == Unprocessed && mark_[v] != markStamp_ && insideActive(cP, v)) sP.push_back(v);
    if (sP.empty()) {
      hullOut = std::move(cP);
      return next;
    }
    std::vector<int32_t> accepted;
    PlaneRegistry::Active base = cC;
    std::vector<int32_t> free;  // voxels of next not known to shadow an unprocessed voxel
    for (int32_t v : next)
      if (blocker_[v] < 0 || state_[blocker_[v]] != Unprocessed) free.push_back(v);
    std::vector<int32_t> pending;  // accepted voxels not yet built into base
    // Each voxel of S_p keeps a supporting half-space of base U pending it lies within eps of
    // (initially its separating plane of C_c). A subset that crosses none of a voxel's half-space
    // cannot shadow it, so only the voxels whose half-space is crossed need the built hull C_t.
    std::vector<int32_t> halfSpace(sP.size());  // registry plane id
    planes_.activate(cC);
    for (size_t i = 0; i < sP.size(); ++i) {
      insideActive(cC, sP[i]);  // not inside C_c: finds (or keeps) a separating plane of C_c
      halfSpace[i] = sep_[sP[i]];
    }
    std::vector<int32_t> crossedByPending, failing;
    std::unordered_map<int32_t, char> crossedCache;
    auto crosses = [&](int32_t id, const std::vector<int32_t>& list) {
      const LatticeHull::Plane& h = planes_.plane(id);
      for (int32_t v : list) {
        const V3& x = vox_.pos[v];
        if (h.nx * x.x() + h.ny * x.y() + h.nz * x.z() > h.offset) return true;
      }
      return false;
    };
    std::unordered_map<int32_t, char> pendingCrossed;  // plane id -> crossed by pending
    auto tryAdd = [&](const std::vector<int32_t>& sub) {
      if (cancelled_) return false;
      if ((++tries_ & 255) == 0 &&
          !reportProgress(progress_, "growth", double(grownSoFar_) / double(vox_.size()))) {
        cancelled_ = true;  // unwinds quickly: every later tryAdd rejects
        return false;
      }
      crossedCache.clear();
      failing.clear();
      for (size_t i = 0; i < sP.size(); ++i) {
        const int32_t id = halfSpace[i];
        auto it = crossedCache.find(id);
        if (it == crossedCache.end()) {
          auto pc = pendingCrossed.find(id);
          if (pc == pendingCrossed.end()) pc = pendingCrossed.emplace(id, crosses(id, pending)).first;
          it = crossedCache.emplace(id, pc->second || crosses(id, sub)).first;
        }
        if (it->second) failing.push_back(static_cast<int32_t>(i));
      }
      if (failing.empty()) {
        for (auto& pc : pendingCrossed)
          if (!pc.second) pc.second = crosses(pc.first, sub);
        pending.insert(pending.end(), sub.begin(), sub.end());
        accepted.insert(accepted.end(), sub.begin(), sub.end());
        return true;
      }
      std::vector<V3> pts = positions(pending);
      for (int32_t v : sub) pts.push_back(vox_.pos[v]);
      PlaneRegistry::Active h = planes_.make(base.hull.extended(pts));
      ++out_.hullBuilds;
      planes_.activate(h);
      for (int32_t i : failing)
        if (insideActive(h, sP[i])) {
          if (sub.size() == 1) blocker_[sub[0]] = sP[i];
          return false;
        }
      for (int32_t i : failing) halfSpace[i] = sep_[sP[i]];  // a plane of the new base
      accepted.insert(accepted.end(), sub.begin(), sub.end());
      base = std::move(h);
      pending.clear();
      pendingCrossed.clear();
      return true;
    };
    if (opt_.shadowScheme == ShadowScheme::RecursivePca) {
      std::vector<std::vector<int32_t>> stack;
      if (!free.empty()) stack.push_back(free);
      bool first = free.size() == next.size();
      while (!stack.empty()) {
        std::vector<int32_t> sub = std::move(stack.back());
        stack.pop_back();
        // The whole of L_next is known to shadow (S_p is not empty).
        if (!first && tryAdd(sub)) continue;
        first = false;
        if (sub.size() == 1) continue;
        auto halves = splitPca(sub);
        // Depth-first, left half first.
        stack.push_back(std::move(halves.second));
        stack.push_back(std::move(halves.first));
      }
    } else {
      for (int32_t v : dijkstraOrder(next))
        if (blocker_[v] < 0 || state_[blocker_[v]] != Unprocessed) tryAdd({v});
    }
    if (!pending.empty()) {
      base = planes_.make(base.hull.extended(positions(pending)));
      ++out_.hullBuilds;
    }
    if (accepted.empty()) {
      if (!allowSacrifice) return {};
      hullOut = std::move(cP);
      return next;
    }
    // Rejected voxels inside or on the accepted hull cost nothing: add them back.
    ++markStamp_;
    for (int32_t v : accepted) mark_[v] = markStamp_;
    int hint = 0;
    for (int32_t v : next)
      if (mark_[v] != markStamp_ && base.hull.insideOrOn(vox_.pos[v], &hint)) accepted.push_back(v);
    hullOut = std::move(base);
    return accepted;
  }

  std::pair<std::vector<int32_t>, std::vector<int32_t>> splitPca(std::vector<int32_t> sub) const {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int32_t v : sub) mean += vox_.pos[v].cast<double>();
    mean /= double(sub.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int32_t v : sub) {
      const Eigen::Vector3d d = vox_.pos[v].cast<double>() - mean;
      cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d axis = es.eigenvectors().col(2);  // largest eigenvalue last
    const size_t half = sub.size() / 2;
    std::nth_element(sub.begin(), sub.begin() + half, sub.end(), [&](int32_t a, int32_t b) {
      const double pa = vox_.pos[a].cast<double>().dot(axis), pb = vox_.pos[b].cast<double>().dot(axis);
      return pa < pb || (pa == pb && a < b);
    });
    return {std::vector<int32_t>(sub.begin(), sub.begin() + half),
            std::vector<int32_t>(sub.begin() + half, sub.end())};
  }

  // Section 4.3.1 sequence Q: Dijkstra over ASN links from a seeded random source (further
  // components start from their first voxel).
  std::vector<int32_t> dijkstraOrder(const std::vector<int32_t>& next) {
    std::unordered_map<int32_t, size_t> index;
    for (size_t i = 0; i < next.size(); ++i) index[next[i]] = i;
    std::vector<double> dist(next.size(), std::numeric_limits<double>::infinity());
    std::vector<char> done(next.size(), 0);
    std::vector<int32_t> order;
    std::mt19937 rng(opt_.seed + static_cast<uint32_t>(out_.hullBuilds));
    size_t source = std::uniform_int_distribution<size_t>(0, next.size() - 1)(rng);
    using Item = std::pair<double, size_t>;
    while (order.size() < next.size()) {
      while (done[source]) source = (source + 1) % next.size();
      std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
      dist[source] = 0;
      q.push({0, source});
      while (!q.empty()) {
        const auto [d, i] = q.top();
        q.pop();
        if (done[i]) continue;
        done[i] = 1;
        order.push_back(next[i]);
        for (const V3& o : amStableOffsets()) {
          const int32_t w = vox_.at(grid_, vox_.pos[next[i]] + o);
          auto it = w >= 0 ? index.find(w) : index.end();
          if (it == index.end() || done[it->second]) continue;
          const double nd = d + o.cast<double>().norm();
          if (nd < dist[it->second]) {
            dist[it->second] = nd;
            q.push({nd, it->second});
          }
        }
      }
    }
    return order;
  }

  const VoxelGrid& grid_;
  const GrowthOptions& opt_;
  const ProgressFn& progress_;
  GrowthField& out_;
  Voxels vox_;
  PlaneRegistry planes_;
  bool sp_ = false;
  std::vector<uint8_t> state_;
  std::vector<int32_t> sep_;
  std::vector<uint8_t> inFrontier_;
  std::vector<uint32_t> mark_;
  uint32_t markStamp_ = 0;
  std::vector<int32_t> g_;
  // A voxel v that alone shadowed s keeps s here: the hull only grows, so v keeps shadowing s
  // while s is unprocessed (C(B' U v) contains C(B U v) for B' containing B), and any subset
  // holding v is rejected without building a hull.
  std::vector<int32_t> blocker_;
  std::vector<int32_t> peel_;
  int32_t peelMax_ = 0;
  std::vector<int32_t> frontier_;
  std::vector<int32_t> alive_;
  int rolling_ = 0;
  bool cancelled_ = false;
  size_t tries_ = 0;
  size_t grownSoFar_ = 0;  // for progress reports from inside shadow prevention
};

// Euclidean distance band of one hull triangle: calls visit(cell index) for every lattice point
// inside the hull within eps of the triangle (scanline over the projection along the dominant
// normal axis, then an exact-enough double distance check).
template <class Visit>
void rasteriseBand(const VoxelGrid& grid, const V3& a, const V3& b, const V3& c,
                   const LatticeHull::Plane& pl, double eps, Visit&& visit) {
  const int64_t n[3] = {pl.nx, pl.ny, pl.nz};
  int w = 0;
  for (int i = 1; i < 3; ++i)
    if (std::llabs(n[i]) > std::llabs(n[w])) w = i;
  const int u = (w + 1) % 3, v = (w + 2) % 3;
  const Eigen::Vector3d A = a.cast<double>(), B = b.cast<double>(), C = c.cast<double>();
  const double vmin = std::min({A[v], B[v], C[v]}) - eps, vmax = std::max({A[v], B[v], C[v]}) + eps;
  const double norm = 1.0 / pl.invNorm;
  const Eigen::Vector3d P[3] = {A, B, C};
  for (int vi = static_cast<int>(std::ceil(vmin)); vi <= static_cast<int>(std::floor(vmax)); ++vi) {
    // u-range of the projected triangle within the strip [vi - eps, vi + eps].
    const double s0 = vi - eps, s1 = vi + eps;
    double umin = std::numeric_limits<double>::infinity(), umax = -umin;
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector3d& p = P[e];
      const Eigen::Vector3d& q = P[(e + 1) % 3];
      double t0 = 0, t1 = 1;
      const double dv = q[v] - p[v];
      if (dv == 0) {
        if (p[v] < s0 || p[v] > s1) continue;
      } else {
        double ta = (s0 - p[v]) / dv, tb = (s1 - p[v]) / dv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) continue;
      }
      const double ua = p[u] + t0 * (q[u] - p[u]), ub = p[u] + t1 * (q[u] - p[u]);
      umin = std::min({umin, ua, ub});
      umax = std::max({umax, ua, ub});
    }
    if (umin > umax) continue;
    for (int ui = static_cast<int>(std::ceil(umin - eps)); ui <= static_cast<int>(std::floor(umax + eps)); ++ui) {
      // n_w * w in [offset - n_u u - n_v v - eps |n|, offset - n_u u - n_v v] (inside, within eps).
      const double rest = static_cast<double>(pl.offset - n[u] * ui - n[v] * vi);
      double w0 = (rest - eps * norm) / n[w], w1 = rest / n[w];
      if (w0 > w1) std::swap(w0, w1);
      for (int wi = static_cast<int>(std::ceil(w0 - 1e-9)); wi <= static_cast<int>(std::floor(w1 + 1e-9)); ++wi) {
        int q[3];
        q[u] = ui;
        q[v] = vi;
        q[w] = wi;
        if (!grid.inRange(q[0], q[1], q[2])) continue;
        const Eigen::Vector3d x(q[0], q[1], q[2]);
        if ((closestPointOnTriangle(x, A, B, C) - x).norm() <= eps + 1e-9) visit(grid.index(q[0], q[1], q[2]));
      }
    }
  }
}

}  // namespace

std::vector<int32_t> inversePeelingField(const VoxelGrid& grid, double epsilon,
                                         const ProgressFn& progress) {
  if (!gridConsistent(grid) || !(epsilon >= 0) || !std::isfinite(epsilon)) return {};
  const Voxels vox(grid);
  const size_t n = vox.size();
  std::vector<int32_t> f(n, 0);
  std::vector<uint8_t> remaining(n, 1), inBoundary(n, 0);
  static const V3 faces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<int32_t> boundary;
  for (size_t v = 0; v < n; ++v)
    for (const V3& o : faces) {
      const int32_t w = vox.at(grid, vox.pos[v] + o);
      if (w < 0) {
        inBoundary[v] = 1;
        boundary.push_back(static_cast<int32_t>(v));
        break;
      }
    }
  // The platform contributes only its hull vertices.
  const LatticeHull platformHull(vox.platform);
  const std::vector<V3> platformPts =
      vox.platform.empty() ? std::vector<V3>{} : platformHull.vertices();
  size_t left = n;
  int32_t rank = 0;
  std::vector<uint8_t> inSheet(n, 0);
  std::vector<int32_t> sheet;
  const double eps = std::min(epsilon, 0.57);  // the boundary-only hull is exact below 1/sqrt(3)
  while (left > 0) {
    ++rank;
    std::vector<V3> pts = platformPts;
    for (int32_t v : boundary) pts.push_back(vox.pos[v]);
    const LatticeHull hull(pts);
    sheet.clear();
    auto take = [&](size_t cell) {
      const int32_t v = vox.ofCell[cell];
      if (v >= 0 && inBoundary[v] && !inSheet[v]) {
        inSheet[v] = 1;
        sheet.push_back(v);
      }
    };
    if (hull.dimension() == 3) {
      for (size_t t = 0; t < hull.facets().size(); ++t) {
        const V3& tri = hull.facets()[t];
        rasteriseBand(grid, hull.vertices()[tri[0]], hull.vertices()[tri[1]],
                      hull.vertices()[tri[2]], hull.planes()[hull.facetPlanes()[t]], eps, take);
      }
    }
    if (sheet.empty()) {
      // Flat remainder (or nothing within eps): peel the whole boundary.
      for (int32_t v : boundary) take(vox.cell[v]);
    }
    for (int32_t v : sheet) {
      f[v] = rank;
      remaining[v] = 0;
      inBoundary[v] = 0;
      --left;
    }
    // New boundary: the remaining old boundary plus remaining face neighbours of the sheet.
    size_t keep = 0;
    for (int32_t v : boundary)
      if (remaining[v]) boundary[keep++] = v;
    boundary.resize(keep);
    for (int32_t v : sheet)
      for (const V3& o : faces) {
        const int32_t w = vox.at(grid, vox.pos[v] + o);
        if (w >= 0 && remaining[w] && !inBoundary[w]) {
          inBoundary[w] = 1;
          boundary.push_back(w);
        }
      }
    if (!reportProgress(progress, "peeling", n ? double(n - left) / double(n) : 1.0)) return {};
  }
  std::vector<int32_t> out(grid.cellCount(), 0);
  for (size_t v = 0; v < n; ++v) out[vox.cell[v]] = 1 + rank - f[v];
  return out;
}

GrowthField growField(const VoxelGrid& grid, const GrowthOptions& options,
                      const ProgressFn& progress) {
  GrowthField out;
  if (!gridConsistent(grid)) {
    out.status = Status::InvalidOption;
    out.message = "voxel grid: dims do not match the state array";
    return out;
  }
  if (!(options.epsilon >= 0) || !std::isfinite(options.epsilon) || !(options.peelStep > 0) ||
      !std::isfinite(options.peelStep)) {
    out.status = Status::InvalidOption;
    out.message = "growth: epsilon must be >= 0 and peelStep > 0 (finite)";
    return out;
  }
  bool any = false;
  for (size_t c = 0; c < grid.cellCount() && !any; ++c) any = grid.printable(c);
  if (!any) {
    out.status = Status::EmptyInput;
    out.message = "growth: the voxel grid has no solid or support cells";
    return out;
  }
  Grower grower(grid, options, progress, out);
  const Status s = grower.run();
  if (s != Status::Ok) {
    GrowthField failed;
    failed.status = s;
    failed.message = s == Status::Cancelled ? "growth cancelled" : "growth failed";
    return failed;
  }
  return out;
}

}  // namespace omnislice
