// SPDX-License-Identifier: MIT
// Beam-guided search of clipping planes (paper 000 Sections III-IV). Design (measurements in the
// commit messages and tests/core/multidir/decomposition_test.cpp):
// - A search state (the remaining model: the solid cut by the planes so far) keeps every face as
//   removed, whole, or cut (the convex polygon left of it), the occupancy cells whose centres it
//   keeps, and ~1500 coarse volume samples (blocks of cells).
// - J_L (Eq. 8) and R (Eq. 11) of every offset k * step of a normal are suffix sums of one
//   difference array per normal: a whole face adds its area at floor(t_min / step) and, at each
//   offset strictly inside its projection, the exact area above by the closed form of a
//   triangle (stored per normal once); cut faces are clipped. Only faces risky along +Z or along
//   the normal enter. So J_L, R and J_G are exact w.r.t. the planes, not centroid-classified.
//   The arrays are fixed point (2^-40 mm^2, coarser on huge surfaces; integer sums do not depend
//   on their order), so a child's are its parent's with the faces its plane removed or cut
//   replaced, bit for bit the same as from scratch.
// - Criterion IV prefilters offsets by the coarse samples (lenient) and decides on the fine
//   cells; Criterion II is a flood fill over the remaining cells from the platform layer, run in
//   priority order until the beams are full (after one failure of a (state, normal), a
//   union-find sweep answers all its offsets at once).
// - Each node stores only its last plane and a parent link (backward links, Section IV-B).
// - Beyond the paper: each level gives every frontier node its fair share of the beams before
//   filling by priority, and the 5dof beam restarts on turned spheres of normals (the result
//   depends on which normals exist); both measured in their commit messages.
// - Refinement: coordinate descent on the found planes (nearby normals and offsets), exact.
#include "common/det_math.h"
#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "multidir/candidate_normals.h"
#include "multidir/decomposition.h"
#include "multidir/decomposition_model.h"
#include "multidir/plane_refinement.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <tuple>
#include <utility>

namespace omnislice {
namespace {

using namespace decomposition_detail;

constexpr int kMaxLevels = 256;  // safety bound; Criterion IV already limits parts to w

enum class Scheme { Greedy, Constrained, Beam };

// ---- options ---------------------------------------------------------------------------------

Outcome checkSearchOptions(const MultidirOptions& o, Scheme& scheme, bool& fourDof) {
  Outcome common = checkCommonOptions(o);
  if (!common.ok()) return common;
  auto bad = [](const std::string& what) { return failed<Outcome>(Status::InvalidOption, what); };
  if (o.samples < 1) return bad("samples must be >= 1");
  if (!(o.offsetStepMm > 0) || !std::isfinite(o.offsetStepMm)) return bad("offsetStepMm must be finite and > 0");
  if (o.dof == "5dof") fourDof = false;
  else if (o.dof == "4dof") fourDof = true;
  else return bad("dof must be \"5dof\" or \"4dof\", got \"" + o.dof + "\"");
  if (!(o.maxTiltDeg > 0 && o.maxTiltDeg <= 180)) return bad("maxTiltDeg must be in (0, 180]");
  if (!isFinite(o.rotationAxis)) return bad("rotationAxis must be finite");
  if (fourDof && o.axisSearch == 0) {
    const double len = o.rotationAxis.norm();
    if (!(len > 0)) return bad("rotationAxis must not be zero");
    if (std::abs(o.rotationAxis.z()) > 1e-9 * len) return bad("rotationAxis must be horizontal (z = 0)");
  }
  if (o.axisSearch < 0) return bad("axisSearch must be >= 0");
  if (o.axisFullSearches < 0) return bad("axisFullSearches must be >= 0");
  if (!(o.stepAngleDeg >= 0 && o.stepAngleDeg < 180)) return bad("stepAngleDeg must be in [0, 180)");
  if (!(o.rangeDeg > 0 && o.rangeDeg <= 180)) return bad("rangeDeg must be in (0, 180]");
  for (const Vec3& n : o.candidateNormals) {
    if (!isFinite(n) || !(n.norm() > 0)) return bad("candidateNormals must be finite and non-zero");
  }
  if (o.beamWidth < 1) return bad("beamWidth must be >= 1");
  if (o.restarts < 1 || o.restarts > 64) return bad("restarts must be in [1, 64]");
  if (o.perturbations < 0 || o.perturbations > 10000) return bad("perturbations must be in [0, 10000]");
  if (!(o.delta0 > 0) || !std::isfinite(o.delta0)) return bad("delta0 must be finite and > 0");
  if (!(o.relaxFactor > 1) || !std::isfinite(o.relaxFactor)) return bad("relaxFactor must be finite and > 1");
  if (o.scheme == "greedy") scheme = Scheme::Greedy;
  else if (o.scheme == "constrained") scheme = Scheme::Constrained;
  else if (o.scheme == "beam") scheme = Scheme::Beam;
  else return bad("scheme must be \"greedy\", \"constrained\" or \"beam\", got \"" + o.scheme + "\"");
  if (!(o.similarityFraction >= 0) || !std::isfinite(o.similarityFraction)) {
    return bad("similarityFraction must be finite and >= 0");
  }
  if (!(o.similarityAngleDeg >= 0) || !std::isfinite(o.similarityAngleDeg)) {
    return bad("similarityAngleDeg must be finite and >= 0");
  }
  if (!(o.similarityOffsetMm >= 0) || !std::isfinite(o.similarityOffsetMm)) {
    return bad("similarityOffsetMm must be finite and >= 0");
  }
  return {};
}

// ---- the search ------------------------------------------------------------------------------

// The J_L / R difference arrays hold areas in fixed point: integer multiples of 2^-40 mm^2 (a
// coarser power of 2 when the model's surface area S is 2^22 mm^2 = 4.2e6 mm^2 or more, see
// Search::fxUnits_), each contribution (a face's area, or its area above one offset) rounded once,
// then weighted by -1, 0 or 1 and summed modulo 2^64 (unsigned: wrap-around is defined). Integer
// sums do not depend on their order, so a state's arrays are the same however they are built
// (from scratch or from its parent's) and the same in native and wasm. Range: a suffix sum is at
// most S (weights are +-1) plus 1/2 unit per contribution, below 2^62 units. Rounding adds at most
// 2^-41 mm^2 per contribution (< 1e-7 mm^2 over 10^5 faces): far below kMinGainMm2, and the
// noise of a small model's J_G (< 1e-11 mm^2 over 10^3 contributions) stays below the 1e-9 mm^2
// a plane costs in the axis screening.
using Fx = uint64_t;
inline Fx fxTimes(int w, int64_t v) { return static_cast<Fx>(w * v); }

// A face along a normal it matters for (risky along it, or risky on the platform part) with its
// whole-triangle contribution: fully above offsets <= kFull, partly above the next `straddles`
// offsets by the stored areas above them (fixed point, from Search::fractions_[frac]). Stored
// face-major (a face's entries together), so that a child's changed faces are read in sequence.
struct Entry {
  int32_t kFull;       // relative to the normal's kLo
  uint32_t frac;       // first of its areas above in Search::fractions_
  uint32_t normal;
  int16_t straddles;   // <= 20000 offsets per normal (searchDecomposition refuses more)
  int8_t wj, wr;       // J_L weight (platform risk - risk along n) and R weight
  int64_t area;        // fixed point
};
static_assert(sizeof(Entry) == 24, "an entry per (face, normal) that matters: keep it small");

struct NormalData {
  Vec3 n;
  int kLo = 0, kHi = 0;  // offsets spanning the model: kLo*step < every point < kHi*step
  int kStart = 0;        // lowest offset allowed: above kLo and with the platform below (III)
  size_t base = 0;       // first offset of this normal in a node's difference arrays
  std::vector<int32_t> sampleKey;  // per coarse volume sample: the offset index (k - kLo) whose
                                   // plane has it just above, clamped to [kLo, kHi]
};

struct Node {
  int parent = -1;
  int line = -1;        // search line that made it (-1: the root, shared)
  int normal = -1;
  int k = 0;
  int level = 0;
  Vec3 n{0, 0, 1};
  double d = 0;
  std::vector<uint8_t> faceState;  // 0 removed, 1 whole, 2 cut
  std::vector<uint32_t> cutFace;   // ascending
  std::vector<Poly> cutPoly;
  Bits cells;                      // fine occupancy cells kept
  size_t cellCount = 0;
  Bits samples;                    // coarse volume samples kept
  // J_L / R difference arrays of every normal (J(k) = sum over k' >= k of dJ[k']), fixed point,
  // interleaved (dJ, dR at 2 * (base + k - kLo)), held while the node may still be expanded.
  std::vector<Fx> diff;
  double jg = 0;        // exact J_G of this decomposition
  double platRisk = 0;  // risky area (+Z) left on the remaining model
  double partRisk = 0;  // R of the part cut off by the last plane
  size_t partCells = 0;
  double sampleWeight = 0;   // volume samples kept (in fine cells)
  double removedWeight = 0;  // volume samples the last plane cut off
  bool terminal = false;
};

// A face the child's plane removed or cut: its polygon in the parent (-1: whole) and in the child
// (-1: removed), as indices into their cutPoly.
struct FaceChange {
  uint32_t face;
  int32_t oldPoly, newPoly;
};

struct Cand {
  uint32_t node;
  uint32_t normal;
  int k;
  double jl, r;
};

class Search {
 public:
  Search(const Model& m, const MultidirOptions& o, MultidirStats& stats, const ProgressFn& progress)
      : m_(m), o_(o), stats_(stats), progress_(progress) {
    minPartCells_ = static_cast<size_t>(std::ceil(static_cast<double>(m_.cells) / o_.w - 1e-9));
    // 2^40 units per mm^2, fewer when S >= 2^22 mm^2 so that S * fxUnits_ < 2^62.
    int e = 0;
    std::frexp(m_.surfaceArea, &e);  // S < 2^e
    fxUnits_ = std::ldexp(1.0, std::min(40, 62 - e));
  }

  // Per-normal tables and the root state with its full J_L / R sweep.
  void setNormals(const std::vector<Vec3>& normals) {
    auto t0 = Clock::now();
    const double step = o_.offsetStepMm;
    nd_.clear();
    size_t base = 0;
    for (const Vec3& n : normals) {
      NormalData nd;
      nd.n = n;
      double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
      for (int c = 0; c < 8; ++c) {
        const Vec3 p((c & 1) ? m_.hi.x() : m_.lo.x(), (c & 2) ? m_.hi.y() : m_.lo.y(),
                     (c & 4) ? m_.hi.z() : m_.lo.z());
        tmin = std::min(tmin, n.dot(p));
        tmax = std::max(tmax, n.dot(p));
      }
      nd.kLo = static_cast<int>(std::floor(tmin / step)) - 1;
      nd.kHi = static_cast<int>(std::ceil(tmax / step)) + 1;
      const int kPlat = static_cast<int>(std::ceil((m_.platformLimit(n) - 1e-9) / step));
      nd.kStart = std::max(nd.kLo + 1, kPlat);
      nd.base = base;
      base += static_cast<size_t>(nd.kHi - nd.kLo + 1);
      nd.sampleKey.resize(m_.samplePos.size());
      for (size_t c = 0; c < m_.samplePos.size(); ++c) {
        const int key = static_cast<int>(std::ceil(n.dot(m_.samplePos[c]) / step)) - 1;
        nd.sampleKey[c] = std::clamp(key, nd.kLo, nd.kHi) - nd.kLo;
      }
      nd_.push_back(std::move(nd));
    }
    arrayLen_ = base;
    entries_.clear();
    fractions_.clear();
    entryStart_.assign(m_.tri.size() + 1, 0);
    for (uint32_t f = 0; f < m_.tri.size(); ++f) {
      entryStart_[f] = static_cast<uint32_t>(entries_.size());
      const auto& t = m_.corner[f];
      for (size_t j = 0; j < nd_.size(); ++j) {
        const NormalData& nd = nd_[j];
        const Vec3& n = nd.n;
        const int wr = m_.riskyAlong(f, n) ? 1 : 0;
        const int wj = (m_.platRisk[f] > 0 ? 1 : 0) - wr;
        if (wr == 0 && wj == 0) continue;
        double a = n.dot(t[0]), b = n.dot(t[1]), c = n.dot(t[2]);
        sort3(a, b, c);
        const int kFull = static_cast<int>(std::floor(a / step));
        const int kTop = static_cast<int>(std::ceil(c / step));
        Entry e;
        e.kFull = kFull - nd.kLo;
        e.frac = static_cast<uint32_t>(fractions_.size());
        e.straddles = static_cast<int16_t>(std::max(0, kTop - kFull - 1));
        e.normal = static_cast<uint32_t>(j);
        e.wj = static_cast<int8_t>(wj);
        e.wr = static_cast<int8_t>(wr);
        e.area = toFx(m_.area[f]);
        // area above each straddled offset
        for (int k = kFull + 1; k < kTop; ++k) {
          fractions_.push_back(toFx(m_.area[f] * triFractionAbove(a, b, c, k * step)));
        }
        entries_.push_back(e);
      }
    }
    entryStart_[m_.tri.size()] = static_cast<uint32_t>(entries_.size());
    nodes_.clear();
    Node root;
    root.faceState.assign(m_.tri.size(), 1);
    root.cells.assign((m_.cells + 63) / 64, 0);
    for (size_t c = 0; c < m_.cells; ++c) setBit(root.cells, c);
    root.cellCount = m_.cells;
    root.samples.assign((m_.samplePos.size() + 63) / 64, 0);
    for (size_t c = 0; c < m_.samplePos.size(); ++c) setBit(root.samples, c);
    root.sampleWeight = static_cast<double>(m_.cells);
    root.jg = m_.jgBefore;
    root.platRisk = m_.jgBefore;
    root.terminal = isTerminal(root);
    stats_.msNormals += msSince(t0);
    t0 = Clock::now();
    if (!root.terminal) fullArrays(root);
    stats_.msSweep += msSince(t0);
    nodes_.push_back(std::move(root));
  }

  // One line of search from the root: greedy / constrained (width 1) or the beam. Reports each
  // level as SearchLevelProgress `name` (level 0: the root). Returns false when cancelled.
  bool runLine(Scheme scheme, size_t width, double progressBase, double progressSpan, const char* name) {
    ++line_;
    std::vector<uint32_t> frontier;
    if (!nodes_[0].terminal) frontier.push_back(0);
    auto fractionAt = [&](int level) {
      return progressBase + progressSpan * std::min(0.99, level / (o_.w + 1));
    };
    double least = nodes_[0].jg;  // least J_G of the line's nodes so far
    auto reportLevel = [&](int level) {
      // A node's J_G is its parent's minus the plane's gain: it can end a few ulps below zero.
      const SearchLevelProgress s{name, level, std::max(0.0, least), static_cast<int>(frontier.size())};
      return reportProgress(progress_, "decompose", fractionAt(level), s);
    };
    if (!reportLevel(0)) return false;
    int level = 0;
    while (!frontier.empty() && level < kMaxLevels) {
      if (!reportProgress(progress_, "decompose", fractionAt(level))) return false;
      progressNow_ = fractionAt(level);
      ++level;
      ++stats_.levels;
      auto t0 = Clock::now();
      pool_.clear();
      for (uint32_t id : frontier) emit(id);
      stats_.msSweep += msSince(t0);
      const std::vector<uint32_t> children = select(frontier, width, scheme);
      if (cancelled_) return false;
      for (uint32_t id : frontier) {
        if (id == 0) continue;  // the root's arrays serve every line
        std::vector<Fx>().swap(nodes_[id].diff);
      }
      frontier.clear();
      for (uint32_t c : children) {
        least = std::min(least, nodes_[c].jg);
        if (!nodes_[c].terminal) frontier.push_back(c);
      }
      if (!reportLevel(level)) return false;
    }
    return true;
  }

  // Best node of a line (all lines when line < 0): least J_G; within delta0 of it, fewest
  // planes; then the first created.
  uint32_t best(int line = -1) const {
    auto inLine = [&](const Node& nd) { return line < 0 || nd.line < 0 || nd.line == line; };
    double least = std::numeric_limits<double>::infinity();
    for (const Node& nd : nodes_) {
      if (inLine(nd)) least = std::min(least, nd.jg);
    }
    uint32_t bestId = 0;
    bool have = false;
    for (uint32_t i = 0; i < nodes_.size(); ++i) {
      const Node& nd = nodes_[i];
      if (!inLine(nd) || nd.jg > least + o_.delta0) continue;
      if (!have || nd.level < nodes_[bestId].level ||
          (nd.level == nodes_[bestId].level && nd.jg < nodes_[bestId].jg)) {
        bestId = i;
        have = true;
      }
    }
    return bestId;
  }

  int lines() const { return line_; }
  const Node& node(uint32_t id) const { return nodes_[id]; }

 private:
  int64_t toFx(double areaMm2) const { return std::llround(areaMm2 * fxUnits_); }
  double fxToMm2(Fx v) const { return static_cast<double>(static_cast<int64_t>(v)) / fxUnits_; }

  bool isTerminal(const Node& nd) const {
    return nd.cellCount * o_.w < static_cast<double>(m_.cells) || nd.platRisk <= kMinGainMm2;
  }

  // J_L / R difference arrays of a state from all its faces: whole faces from their entries, cut
  // faces by clipping their polygons.
  void fullArrays(Node& s) const {
    s.diff.assign(2 * arrayLen_, 0);
    const uint8_t* state = s.faceState.data();
    size_t ci = 0;  // s.cutFace is ascending
    for (uint32_t f = 0; f < m_.tri.size(); ++f) {
      const uint8_t st = state[f];
      if (st == 0) continue;
      const Poly* p = st == 2 ? &s.cutPoly[ci++] : nullptr;
      for (uint32_t i = entryStart_[f]; i < entryStart_[f + 1]; ++i) addFace(s.diff.data(), f, entries_[i], p, 1);
    }
  }

  // J_L / R arrays of `child` from its parent's: the faces the plane changed leave with their old
  // contribution and come back cut. Integer sums: the same arrays as fullArrays(child).
  void childArrays(const Node& parent, Node& child, const std::vector<FaceChange>& changes) const {
    child.diff = parent.diff;
    Fx* diff = child.diff.data();
    for (const FaceChange& c : changes) {
      const Poly* oldPoly = c.oldPoly < 0 ? nullptr : &parent.cutPoly[static_cast<size_t>(c.oldPoly)];
      const Poly* newPoly = c.newPoly < 0 ? nullptr : &child.cutPoly[static_cast<size_t>(c.newPoly)];
      for (uint32_t i = entryStart_[c.face]; i < entryStart_[c.face + 1]; ++i) {
        addFace(diff, c.face, entries_[i], oldPoly, -1);
        if (newPoly) addFace(diff, c.face, entries_[i], newPoly, 1);
      }
    }
  }

  // sign * weights * (area above each offset) of face f along entry e's normal, whole (p null) or
  // cut to polygon p, into the interleaved arrays `diff` (all normals). The one place a face's
  // contribution is computed, for fullArrays and childArrays alike.
  void addFace(Fx* diff, uint32_t f, const Entry& e, const Poly* p, int sign) const {
    const NormalData& nd = nd_[e.normal];
    Fx* d = diff + 2 * nd.base;
    const int wj = sign * e.wj, wr = sign * e.wr;
    if (!p) {
      d[2 * e.kFull] += fxTimes(wj, e.area);
      d[2 * e.kFull + 1] += fxTimes(wr, e.area);
      const int64_t* frac = fractions_.data() + e.frac;
      for (int q = 0; q < e.straddles; ++q) {
        const int64_t above = frac[q];
        const int k = e.kFull + 1 + q;
        d[2 * k] += fxTimes(wj, above);
        d[2 * k - 2] -= fxTimes(wj, above);
        d[2 * k + 1] += fxTimes(wr, above);
        d[2 * k - 1] -= fxTimes(wr, above);
      }
      return;
    }
    const double step = o_.offsetStepMm;
    double a = std::numeric_limits<double>::infinity(), c = -a;
    for (const Vec3& q : *p) {
      const double t = nd.n.dot(q);
      a = std::min(a, t);
      c = std::max(c, t);
    }
    const Vec3& fn = m_.normal[f];
    const int64_t area = toFx(polyArea(*p, fn));
    const int kFull = static_cast<int>(std::floor(a / step)) - nd.kLo;
    const int kTop = static_cast<int>(std::ceil(c / step)) - nd.kLo;
    d[2 * kFull] += fxTimes(wj, area);
    d[2 * kFull + 1] += fxTimes(wr, area);
    for (int k = kFull + 1; k < kTop; ++k) {
      const int64_t above = toFx(polyArea(clipPoly(*p, nd.n, (k + nd.kLo) * step, true), fn));
      d[2 * k] += fxTimes(wj, above);
      d[2 * k - 2] -= fxTimes(wj, above);
      d[2 * k + 1] += fxTimes(wr, above);
      d[2 * k - 1] -= fxTimes(wr, above);
    }
  }

  // Candidates of one state: every normal, every offset from kStart up to the highest whose part
  // above holds ~V/w (coarse samples, lenient: the fine grid decides), with J_L > 0.
  void emit(uint32_t id) {
    const Node& s = nodes_[id];
    const double lenient = 0.8 * static_cast<double>(m_.cells) / o_.w;
    for (size_t j = 0; j < nd_.size(); ++j) {
      const NormalData& nd = nd_[j];
      const size_t K = static_cast<size_t>(nd.kHi - nd.kLo + 1);
      hist_.assign(K + 1, 0);
      const int32_t* key = nd.sampleKey.data();
      forEachBit(s.samples, [&](size_t c) { hist_[key[c]] += m_.sampleWeight[c]; });
      int kMaxVol = nd.kStart - 1;
      double above = 0;
      for (int k = nd.kHi; k >= nd.kStart; --k) {
        above += hist_[k - nd.kLo];
        if (above >= lenient) {
          kMaxVol = k;
          break;
        }
      }
      const Fx* d = s.diff.data() + 2 * nd.base;
      Fx sumJ = 0, sumR = 0;
      for (int k = nd.kHi; k >= nd.kStart; --k) {
        sumJ += d[2 * (k - nd.kLo)];
        sumR += d[2 * (k - nd.kLo) + 1];
        if (k > kMaxVol) continue;
        ++stats_.candidatesEvaluated;
        const double jl = fxToMm2(sumJ);
        if (jl > kMinGainMm2) pool_.push_back({id, static_cast<uint32_t>(j), k, jl, std::max(0.0, fxToMm2(sumR))});
      }
    }
  }

  // Face state of the child of `parent` by plane (n, d) into `out`, the faces that changed into
  // `changes` (ascending); returns the number of faces the child keeps (whole or cut).
  size_t childFaces(const Node& parent, const Vec3& n, double d, Node& out, std::vector<FaceChange>& changes) const {
    out.faceState = parent.faceState;
    out.cutFace.clear();
    out.cutPoly.clear();
    changes.clear();
    size_t kept = 0;
    int ci = -1;
    for (uint32_t f = 0; f < m_.tri.size(); ++f) {
      const uint8_t st = parent.faceState[f];
      if (st == 1) {
        const auto& t = m_.corner[f];
        const double a = n.dot(t[0]), b = n.dot(t[1]), c = n.dot(t[2]);
        const double tmin = std::min({a, b, c}), tmax = std::max({a, b, c});
        if (tmax <= d && tmin < d) {
          ++kept;
          continue;
        }
        Poly p;
        if (tmin < d) p = clipPoly({t[0], t[1], t[2]}, n, d, false);
        if (p.empty()) {
          out.faceState[f] = 0;
          changes.push_back({f, -1, -1});
        } else {
          out.faceState[f] = 2;
          changes.push_back({f, -1, static_cast<int32_t>(out.cutPoly.size())});
          out.cutFace.push_back(f);
          out.cutPoly.push_back(std::move(p));
          ++kept;
        }
      } else if (st == 2) {
        const Poly& p = parent.cutPoly[++ci];
        double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
        for (const Vec3& q : p) {
          tmin = std::min(tmin, n.dot(q));
          tmax = std::max(tmax, n.dot(q));
        }
        if (tmax <= d && tmin < d) {
          out.cutFace.push_back(f);
          out.cutPoly.push_back(p);
          ++kept;
          continue;
        }
        Poly q;
        if (tmin < d) q = clipPoly(p, n, d, false);
        if (q.empty()) {
          out.faceState[f] = 0;
          changes.push_back({f, ci, -1});
        } else {
          changes.push_back({f, ci, static_cast<int32_t>(out.cutPoly.size())});
          out.cutFace.push_back(f);
          out.cutPoly.push_back(std::move(q));
          ++kept;
        }
      }
    }
    return kept;
  }

  // "Close" results (paper IV-B, after Chopper): the same parent and nearly the same plane, or
  // remaining models whose volume samples differ by at most similarityFraction of the smaller
  // volume their last planes cut off.
  bool similar(const Node& a, const Node& b) const {
    if (a.parent == b.parent && o_.similarityAngleDeg > 0 && o_.similarityOffsetMm > 0) {
      const double cosAngle = std::clamp(a.n.dot(b.n), -1.0, 1.0);
      if (det::acos(cosAngle) * 180 / kPi <= o_.similarityAngleDeg &&
          std::abs(a.d - b.d) <= o_.similarityOffsetMm) {
        return true;
      }
    }
    const double limit = o_.similarityFraction * std::min(a.removedWeight, b.removedWeight);
    double diff = 0;
    for (size_t w = 0; w < a.samples.size(); ++w) {
      uint64_t x = a.samples[w] ^ b.samples[w];
      while (x) {
        diff += m_.sampleWeight[w * 64 + static_cast<size_t>(__builtin_ctzll(x))];
        if (diff > limit) return false;
        x &= x - 1;
      }
    }
    return true;
  }

  // Fine cells of state `id` above each offset of normal j (suffix counts), on first use.
  const std::vector<uint32_t>& fineAbove(uint32_t id, uint32_t j) {
    std::vector<uint32_t>& slot = fine_[key(id, j)];
    if (!slot.empty()) return slot;
    const NormalData& nd = nd_[j];
    const double step = o_.offsetStepMm;
    const size_t K = static_cast<size_t>(nd.kHi - nd.kLo + 1);
    slot.assign(K + 1, 0);
    forEachBit(nodes_[id].cells, [&](size_t c) {
      // above offset k iff t > k * step iff k <= ceil(t / step) - 1
      int key = static_cast<int>(std::ceil(nd.n.dot(m_.centre[c]) / step)) - 1;
      key = std::clamp(key, nd.kLo, nd.kHi);
      ++slot[key - nd.kLo];
    });
    for (size_t k = K; k-- > 0;) slot[k] += slot[k + 1];
    return slot;
  }

  // Criterion II for plane (normal j, offset k) of state `id`, leaving `count` cells below: a
  // flood fill from the platform layer; after a first failure for this (state, normal), one
  // union-find sweep answers every offset of it.
  bool connected(uint32_t id, uint32_t j, int k, size_t count) {
    ConnCache& cc = conn_[key(id, j)];
    if (cc.valid.empty() && cc.failures > 0) {
      ++stats_.connectivityChecks;
      connectedOffsets(nodes_[id], nd_[j], cc.valid);
    }
    if (!cc.valid.empty()) return cc.valid[k - nd_[j].kLo];
    ++stats_.connectivityChecks;
    const size_t reached = reachableBelow(m_, nodes_[id].cells, nd_[j].n, k * o_.offsetStepMm, flood_);
    const bool ok = static_cast<double>(count - reached) <= o_.floatingToleranceCells;
    if (!ok) ++cc.failures;
    return ok;
  }

  // valid[k - kLo] = no cell of S n {n . x <= k * step} is cut off from the platform layer: cells
  // join a union-find in order of height along n; a component is grounded once it holds a
  // platform cell; the offset is valid when no component is ungrounded.
  void connectedOffsets(const Node& s, const NormalData& nd, std::vector<uint8_t>& valid) {
    const double step = o_.offsetStepMm;
    const size_t K = static_cast<size_t>(nd.kHi - nd.kLo + 1);
    if (dsuParent_.size() != m_.cells) {
      dsuParent_.assign(m_.cells, 0);
      dsuGrounded_.assign(m_.cells, 0);
      dsuAdded_.assign(m_.cells, 0);
      dsuKey_.assign(m_.cells, 0);
      dsuSize_.assign(m_.cells, 0);
    }
    if (++dsuGen_ == 0) {
      std::fill(dsuAdded_.begin(), dsuAdded_.end(), 0);
      dsuGen_ = 1;
    }
    std::vector<uint32_t> start(K + 1, 0);
    forEachBit(s.cells, [&](size_t c) {
      int key = static_cast<int>(std::ceil(nd.n.dot(m_.centre[c]) / step));
      key = std::clamp(key, nd.kLo, nd.kHi);
      dsuKey_[c] = static_cast<uint32_t>(key - nd.kLo);
      ++start[key - nd.kLo + 1];
    });
    for (size_t k = 0; k < K; ++k) start[k + 1] += start[k];
    order_.resize(s.cellCount);
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    forEachBit(s.cells, [&](size_t c) { order_[fill[dsuKey_[c]]++] = static_cast<uint32_t>(c); });
    auto find = [&](uint32_t x) {
      while (dsuParent_[x] != x) {
        dsuParent_[x] = dsuParent_[dsuParent_[x]];
        x = dsuParent_[x];
      }
      return x;
    };
    long floating = 0;  // cells in components without a platform cell
    valid.assign(K, 0);
    size_t q = 0;
    for (size_t k = 0; k < K; ++k) {
      for (; q < start[k + 1]; ++q) {
        const uint32_t c = order_[q];
        dsuParent_[c] = c;
        dsuGrounded_[c] = m_.isBase[c];
        dsuSize_[c] = 1;
        dsuAdded_[c] = dsuGen_;
        floating += dsuGrounded_[c] ? 0 : 1;
        for (int e = 0; e < 6; ++e) {
          const uint32_t nb = m_.nbr[6 * static_cast<size_t>(c) + e];
          if (nb == kNoCell || dsuAdded_[nb] != dsuGen_) continue;
          const uint32_t ra = find(c), rb = find(nb);
          if (ra == rb) continue;
          floating -= (dsuGrounded_[ra] ? 0 : dsuSize_[ra]) + (dsuGrounded_[rb] ? 0 : dsuSize_[rb]);
          dsuParent_[rb] = ra;
          dsuSize_[ra] += dsuSize_[rb];
          dsuGrounded_[ra] = dsuGrounded_[ra] || dsuGrounded_[rb];
          floating += dsuGrounded_[ra] ? 0 : dsuSize_[ra];
        }
      }
      valid[k] = static_cast<double>(floating) <= o_.floatingToleranceCells ? 1 : 0;
    }
  }

  // Orders the pool by the scheme's priority and accepts valid, dissimilar planes up to width.
  std::vector<uint32_t> select(const std::vector<uint32_t>& frontier, size_t width, Scheme scheme) {
    auto t0 = Clock::now();
    conn_.clear();
    fine_.clear();
    // Priority buckets: beam -> R < delta0 * relax^i (progressive relaxation); constrained ->
    // R < delta0 first; greedy -> one bucket. Within a bucket, larger J_L first.
    auto bucketOf = [&](double r) -> int {
      if (scheme == Scheme::Greedy || r < o_.delta0) return 0;
      if (scheme == Scheme::Constrained) return 1;
      int b = 1;
      double bound = o_.delta0 * o_.relaxFactor;
      while (!(r < bound) && b < 1000) {
        bound *= o_.relaxFactor;
        ++b;
      }
      return b;
    };
    std::vector<std::pair<int, uint32_t>> order(pool_.size());
    for (uint32_t i = 0; i < pool_.size(); ++i) order[i] = {bucketOf(pool_[i].r), i};
    std::sort(order.begin(), order.end(), [&](const auto& x, const auto& y) {
      if (x.first != y.first) return x.first < y.first;
      const Cand &a = pool_[x.second], &b = pool_[y.second];
      if (a.jl != b.jl) return a.jl > b.jl;
      if (a.node != b.node) return a.node < b.node;
      if (a.normal != b.normal) return a.normal < b.normal;
      return a.k < b.k;
    });
    std::vector<uint32_t> accepted;
    double msArrays = 0;
    // Every node of the frontier first gets at most its fair share of the width (children in
    // priority order), then what is left is filled in the same order: one parent's near-twin
    // children cannot take the whole beam (measured over 7 models x 3 turns about Z: better in 12
    // cases, worse in 2, same time).
    const size_t share = (width + frontier.size() - 1) / std::max<size_t>(1, frontier.size());
    std::unordered_map<uint32_t, size_t> perParent;
    std::vector<uint8_t> tried(order.size(), 0);
    for (int pass = 0; pass < 2; ++pass) {
      if (cancelled_ || accepted.size() >= width) break;
      for (size_t oi = 0; oi < order.size(); ++oi) {
        if (accepted.size() >= width) break;
        if (tried[oi] || (pass == 0 && perParent[pool_[order[oi].second].node] >= share)) continue;
        tried[oi] = 1;
        const Cand& c = pool_[order[oi].second];
        // A candidate costs up to a flood fill or a child's arrays (~1 ms on 10^5 cells / faces).
        if (!reportProgress(progress_, "decompose", progressNow_)) {
          cancelled_ = true;
          break;
        }
        ++stats_.candidatesChecked;
        Node child;
        child.line = line_;
        child.parent = static_cast<int>(c.node);
        child.normal = static_cast<int>(c.normal);
        child.k = c.k;
        child.level = nodes_[c.node].level + 1;
        child.n = nd_[c.normal].n;
        child.d = c.k * o_.offsetStepMm;
        const Node& parent = nodes_[c.node];
        child.samples.assign(parent.samples.size(), 0);
        double keptWeight = 0;
        forEachBit(parent.samples, [&](size_t q) {
          if (child.n.dot(m_.samplePos[q]) <= child.d) {
            setBit(child.samples, q);
            keptWeight += m_.sampleWeight[q];
          }
        });
        child.sampleWeight = keptWeight;
        child.removedWeight = parent.sampleWeight - keptWeight;
        bool close = false;
        for (uint32_t a : accepted) {
          if (similar(child, nodes_[a])) {
            close = true;
            break;
          }
        }
        if (close) {
          ++stats_.refusedSimilar;
          continue;
        }
        // Criterion IV on the fine grid.
        const std::vector<uint32_t>& aboveCells = fineAbove(c.node, c.normal);
        const size_t partCells = aboveCells[c.k - nd_[c.normal].kLo];
        const size_t below = parent.cellCount - partCells;
        if (partCells < minPartCells_ || partCells == 0) {
          ++stats_.refusedSmall;
          continue;
        }
        // Criterion II.
        if (!connected(c.node, c.normal, c.k, below)) {
          ++stats_.refusedFloating;
          continue;
        }
        const size_t kept = childFaces(parent, child.n, child.d, child, changes_);
        child.cells.assign(parent.cells.size(), 0);
        forEachBit(parent.cells, [&](size_t cell) {
          if (child.n.dot(m_.centre[cell]) <= child.d) setBit(child.cells, cell);
        });
        child.cellCount = below;
        child.partCells = partCells;
        child.jg = parent.jg - c.jl;
        child.partRisk = c.r;
        child.platRisk = parent.platRisk - (c.jl + c.r);
        child.terminal = isTerminal(child);
        if (!child.terminal) {
          const auto ta = Clock::now();
          // Same arrays either way (integer sums). From the parent's unless the plane changed more
          // faces than the child keeps (measured: a changed face costs about a kept one).
          if (changes_.size() <= kept) {
            childArrays(parent, child, changes_);
          } else {
            fullArrays(child);
          }
          msArrays += msSince(ta);
        }
        nodes_.push_back(std::move(child));
        ++perParent[c.node];
        ++stats_.beams;
        accepted.push_back(static_cast<uint32_t>(nodes_.size() - 1));
      }
    }
    stats_.msSweep += msArrays;
    stats_.msChecks += msSince(t0) - msArrays;
    return accepted;
  }

  static uint64_t key(uint32_t a, uint32_t b) { return (static_cast<uint64_t>(a) << 32) | b; }

  struct ConnCache {
    int failures = 0;
    std::vector<uint8_t> valid;
  };

  const Model& m_;
  const MultidirOptions& o_;
  MultidirStats& stats_;
  const ProgressFn& progress_;
  std::vector<NormalData> nd_;
  double fxUnits_ = 0;  // fixed point units per mm^2 (a power of 2)
  std::vector<Entry> entries_;        // face-major: face f's are [entryStart_[f], entryStart_[f + 1])
  std::vector<uint32_t> entryStart_;
  std::vector<int64_t> fractions_;
  size_t arrayLen_ = 0;
  std::vector<Node> nodes_;
  std::vector<Cand> pool_;
  size_t minPartCells_ = 0;
  std::vector<double> hist_;
  std::unordered_map<uint64_t, ConnCache> conn_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> fine_;
  FloodScratch flood_;
  std::vector<uint32_t> dsuParent_, dsuAdded_, dsuKey_, dsuSize_, order_;
  std::vector<FaceChange> changes_;
  std::vector<uint8_t> dsuGrounded_;
  uint32_t dsuGen_ = 0;
  int line_ = 0;
  double progressNow_ = 0;
  bool cancelled_ = false;
};

// A plane sequence (clipping order) ending a search line, with J_G as the search summed it.
struct LineEnd {
  std::vector<Vec3> ns;
  std::vector<double> ds;
  double searchJg = 0;
};

// The best node of every line of a finished search (greedy, constrained, beam), as plane
// sequences; the root (no plane) when no line made a node.
void lineEnds(const Search& s, std::vector<LineEnd>& out) {
  std::vector<uint32_t> ends;
  for (int line = 1; line <= s.lines(); ++line) {
    const uint32_t id = s.best(line);
    if (std::find(ends.begin(), ends.end(), id) == ends.end()) ends.push_back(id);
  }
  if (ends.empty()) ends.push_back(0);
  for (uint32_t end : ends) {
    LineEnd e;
    e.searchJg = s.node(end).jg;
    for (int id = static_cast<int>(end); id > 0; id = s.node(static_cast<uint32_t>(id)).parent) {
      e.ns.push_back(s.node(static_cast<uint32_t>(id)).n);
      e.ds.push_back(s.node(static_cast<uint32_t>(id)).d);
    }
    std::reverse(e.ns.begin(), e.ns.end());
    std::reverse(e.ds.begin(), e.ds.end());
    out.push_back(std::move(e));
  }
}

// Fills planes/parts/numbers of `result` from the line ends of finished searches, each refined
// when asked; the least exact J_G wins (then fewer planes, then the first). The refinement
// reports progress at `fraction` (the end of these searches' span).
void fillResult(const Model& m, const std::vector<Vec3>& bestN, const std::vector<double>& bestD,
                MultidirResult& result);

bool collect(const Model& m, const MultidirOptions& o, bool fourDof, const Vec3& axis,
             std::vector<LineEnd> ends, bool perturb, const ProgressFn& progress, double fraction,
             MultidirResult& result) {
  std::vector<Vec3> bestN;
  std::vector<double> bestD;
  double bestJ = std::numeric_limits<double>::infinity();
  // Lines that ended on the same planes (often greedy and constrained) are refined once.
  std::vector<uint8_t> repeated(ends.size(), 0);
  for (size_t i = 0; i < ends.size(); ++i) {
    for (size_t q = 0; q < i && !repeated[i]; ++q) {
      repeated[i] = ends[q].ns == ends[i].ns && ends[q].ds == ends[i].ds;
    }
  }
  for (size_t i = 0; i < ends.size(); ++i) {
    if (repeated[i]) continue;
    LineEnd& e = ends[i];
    std::vector<Vec3>& ns = e.ns;
    std::vector<double>& ds = e.ds;
    if (o.refine && !ns.empty()) {
      const auto t0 = Clock::now();
      bool cancelled = false;
      result.stats.refineEvaluated += refinePlanes(m, o, fourDof, axis, ns, ds, progress, fraction, cancelled);
      result.stats.msRefine += msSince(t0);
      if (cancelled) return false;
    }
    const auto t0 = Clock::now();
    double jg = 0;
    for (double r : exactRisk(m, ns, ds)) jg += r;
    result.stats.msExact += msSince(t0);
    if (jg < bestJ - 1e-9 || (jg <= bestJ + 1e-9 && ns.size() < bestN.size())) {
      bestJ = jg;
      bestN = ns;
      bestD = ds;
      result.stats.searchJgMm2 = e.searchJg;
    }
  }
  if (perturb) {
    const auto t0 = Clock::now();
    bool cancelled = false;
    result.stats.perturbationsKept +=
        perturbPlanes(m, o, fourDof, axis, bestN, bestD, bestJ, progress, fraction, 0.99, cancelled, result.stats);
    result.stats.msPerturb += msSince(t0);
    if (cancelled) return false;
  }
  fillResult(m, bestN, bestD, result);
  return true;
}

// The planes, parts (directions, volumes, risky areas), J_G and J_G per level of a sequence.
void fillResult(const Model& m, const std::vector<Vec3>& bestN, const std::vector<double>& bestD,
                MultidirResult& result) {
  const auto t0 = Clock::now();
  result.planes.clear();
  result.parts.clear();
  result.stats.jgPerLevel.clear();
  const double cellVolume = m.h * m.h * m.h;
  size_t count = 0;
  Bits kept = cellsKept(m, bestN, bestD, 0, count);
  for (size_t k = 0; k < bestN.size(); ++k) {
    result.planes.push_back({bestN[k], bestD[k]});
    Bits below(kept.size(), 0);
    size_t nBelow = 0;
    forEachBit(kept, [&](size_t c) {
      if (bestN[k].dot(m.centre[c]) <= bestD[k]) {
        setBit(below, c);
        ++nBelow;
      }
    });
    MultidirPart part;
    part.direction = bestN[k];
    part.plane = static_cast<int>(k);
    part.volumeMm3 = (count - nBelow) * cellVolume;
    result.parts.push_back(part);
    kept.swap(below);
    count = nBelow;
  }
  MultidirPart base;
  base.volumeMm3 = count * cellVolume;
  result.parts.push_back(base);
  const std::vector<double> risk = exactRisk(m, bestN, bestD);
  result.jgAfterMm2 = 0;
  for (size_t k = 0; k < risk.size(); ++k) {
    result.parts[k].riskyAreaMm2 = risk[k];
    result.jgAfterMm2 += risk[k];
  }
  for (size_t k = 0; k <= bestN.size(); ++k) {
    const std::vector<Vec3> pn(bestN.begin(), bestN.begin() + k);
    const std::vector<double> pd(bestD.begin(), bestD.begin() + k);
    double jg = 0;
    for (double r : exactRisk(m, pn, pd)) jg += r;
    result.stats.jgPerLevel.push_back(jg);
  }
  result.stats.msExact += msSince(t0);
}

}  // namespace

MultidirResult searchDecomposition(const Mesh& mesh, const MultidirOptions& options,
                                   const ProgressFn& progress) {
  const auto tStart = Clock::now();
  MultidirResult result;
  Scheme scheme = Scheme::Beam;
  bool fourDof = false;
  Outcome ok = checkSearchOptions(options, scheme, fourDof);
  if (ok.ok()) ok = checkMesh(mesh);
  if (!ok.ok()) {
    result.status = ok.status;
    result.message = ok.message;
    return result;
  }
  Model m;
  auto t0 = Clock::now();
  ok = buildModel(mesh, options, m);
  result.stats.msPrepare = msSince(t0);
  if (!ok.ok()) {
    result.status = ok.status;
    result.message = ok.message;
    return result;
  }
  // Each state holds two arrays of (extent / step) offsets per normal: refuse absurd steps.
  if ((m.hi - m.lo).norm() / options.offsetStepMm > 20000) {
    result.status = Status::InvalidOption;
    result.message = "offsetStepMm is too small for the model (over 20000 offsets per normal)";
    return result;
  }
  result.jgBeforeMm2 = m.jgBefore;
  result.volumeMm3 = m.volume;
  result.stats.gridCells = m.cells;
  result.stats.cellMm = m.h;
  result.stats.orphanCells = m.orphans;
  auto cancelled = [&]() {
    MultidirResult c;
    c.status = Status::Cancelled;
    c.message = "decomposition cancelled";
    c.jgBeforeMm2 = m.jgBefore;
    c.volumeMm3 = m.volume;
    c.stats = result.stats;
    return c;
  };
  // The beam scheme also runs the greedy and constrained-greedy lines from the same root (two
  // extra beams of width 1): the best J_G over all of them wins, so the beam never does worse.
  auto runScheme = [&](Search& search, Scheme s, double base, double span) {
    if (s != Scheme::Beam) return search.runLine(s, 1, base, span, s == Scheme::Greedy ? "greedy" : "constrained");
    return search.runLine(Scheme::Greedy, 1, base, 0.1 * span, "greedy") &&
           search.runLine(Scheme::Constrained, 1, base + 0.1 * span, 0.1 * span, "constrained") &&
           search.runLine(Scheme::Beam, static_cast<size_t>(options.beamWidth), base + 0.2 * span,
                          0.8 * span, "beam");
  };
  // The beam's best sequence then goes through the iterated local search (the last 9% of the
  // progress).
  const bool perturb = scheme == Scheme::Beam && options.refine && options.perturbations > 0;
  const double searchEnd = perturb ? 0.9 : 0.99;
  if (!fourDof) {
    // Restart j samples the sphere turned about Z by 2 pi frac(j (sqrt 2 - 1)): the beam's choices
    // depend on which normals exist, so each restart explores other decompositions, and as the
    // turns never repeat, more restarts only add searches. The first runs the scheme (with the
    // greedy lines), the others the beam line only. They stop once a line ends at J_G <= delta0
    // (the search's own tolerance for "no risky area": refinement only lowers it).
    std::vector<LineEnd> ends;
    const int restarts = scheme == Scheme::Beam && options.candidateNormals.empty() ? options.restarts : 1;
    const double turn = std::sqrt(2.0) - 1;
    for (int j = 0; j < restarts; ++j) {
      Search search(m, options, result.stats, progress);
      const double phase = 2 * kPi * (j * turn - std::floor(j * turn));
      const std::vector<Vec3> normals = sphereNormals(options, phase);
      result.stats.normals = normals.size();
      search.setNormals(normals);
      const double base = searchEnd * j / restarts, span = searchEnd / restarts;
      const bool ran = j == 0 ? runScheme(search, scheme, base, span)
                              : search.runLine(Scheme::Beam, static_cast<size_t>(options.beamWidth), base, span, "beam");
      if (!ran) return cancelled();
      lineEnds(search, ends);
      ++result.stats.restartsRun;
      double least = std::numeric_limits<double>::infinity();
      for (const LineEnd& e : ends) least = std::min(least, e.searchJg);
      if (least <= options.delta0) break;
    }
    if (!collect(m, options, false, Vec3::Zero(), std::move(ends), perturb, progress, searchEnd, result)) {
      return cancelled();
    }
  } else {
    std::vector<Vec3> axes;
    if (options.axisSearch > 0) {
      for (int i = 0; i < options.axisSearch; ++i) {
        const double phi = kPi * i / options.axisSearch;
        axes.emplace_back(det::cos(phi), det::sin(phi), 0);
      }
    } else {
      axes.push_back(options.rotationAxis.normalized());
    }
    // Axis search with the beam: every axis is screened by the constrained greedy line, the beam
    // runs on the axisFullSearches best of them (all when 0).
    std::vector<size_t> full(axes.size());
    std::iota(full.begin(), full.end(), 0);
    const bool screen = scheme == Scheme::Beam && options.axisFullSearches > 0 &&
                        axes.size() > static_cast<size_t>(options.axisFullSearches);
    const double screenSpan = screen ? 0.5 : 0.0;
    if (screen) {
      // The screening only ranks the axes: the constrained greedy line on half the grid
      // resolution and, without a stepper, half the normals on each circle.
      MultidirOptions coarse = options;
      coarse.gridResolution = std::max(16, options.gridResolution / 2);
      if (coarse.stepAngleDeg == 0) coarse.samples = std::max(1, options.samples / 2);
      Model mc;
      const auto tc = Clock::now();
      ok = buildModel(mesh, coarse, mc);
      result.stats.msPrepare += msSince(tc);
      if (!ok.ok()) {
        result.status = ok.status;
        result.message = ok.message;
        return result;
      }
      // Rank: J_G + 1e-9 per plane, then (exact ties, e.g. two axes that both reach J_G 0 with
      // one plane) the larger model left on the platform.
      std::vector<std::tuple<double, size_t, size_t>> rank;
      for (size_t a = 0; a < axes.size(); ++a) {
        Search search(mc, coarse, result.stats, progress);
        search.setNormals(circleNormals(coarse, axes[a]));
        const double span = screenSpan / axes.size();
        if (!search.runLine(Scheme::Constrained, 1, a * span, span, "screen")) return cancelled();
        const Node& b = search.node(search.best());
        rank.emplace_back(b.jg + 1e-9 * b.level, mc.cells - b.cellCount, a);
      }
      std::stable_sort(rank.begin(), rank.end());
      // The best screened axes, at least 3 degrees apart (neighbours rank alike).
      full.clear();
      for (int pass = 0; pass < 2 && full.size() < static_cast<size_t>(options.axisFullSearches); ++pass) {
        for (const auto& r : rank) {
          if (full.size() >= static_cast<size_t>(options.axisFullSearches)) break;
          bool near = false;
          for (size_t f : full) {
            const double cosAngle = std::abs(axes[f].dot(axes[std::get<2>(r)]));
            near = near || f == std::get<2>(r) || (pass == 0 && cosAngle > det::cos(3 * kPi / 180));
          }
          if (!near) full.push_back(std::get<2>(r));
        }
      }
    }
    bool have = false;
    for (size_t i = 0; i < full.size(); ++i) {
      const size_t a = full[i];
      Search search(m, options, result.stats, progress);
      const std::vector<Vec3> normals = circleNormals(options, axes[a]);
      result.stats.normals = normals.size();
      search.setNormals(normals);
      const double span = ((perturb ? searchEnd : 1.0) - screenSpan) / full.size();
      if (!runScheme(search, scheme, screenSpan + i * span, span)) return cancelled();
      MultidirResult trial;
      std::vector<LineEnd> ends;
      lineEnds(search, ends);
      if (!collect(m, options, true, axes[a], std::move(ends), false, progress,
                   std::min(0.99, screenSpan + (i + 1) * span), trial)) {
        return cancelled();
      }
      result.stats.msExact += trial.stats.msExact;
      result.stats.msRefine += trial.stats.msRefine;
      result.stats.refineEvaluated += trial.stats.refineEvaluated;
      const bool better = !have || trial.jgAfterMm2 < result.jgAfterMm2 - 1e-9 ||
                          (trial.jgAfterMm2 <= result.jgAfterMm2 + 1e-9 &&
                           trial.planes.size() < result.planes.size());
      if (better) {
        have = true;
        result.planes = trial.planes;
        result.parts = trial.parts;
        result.jgAfterMm2 = trial.jgAfterMm2;
        result.rotationAxis = axes[a];
        result.stats.jgPerLevel = trial.stats.jgPerLevel;
        result.stats.searchJgMm2 = trial.stats.searchJgMm2;
      }
    }
    result.stats.axesTried = axes.size();
    // The iterated local search (beam scheme) once, on the chosen axis.
    if (perturb) {
      std::vector<Vec3> ns;
      std::vector<double> ds;
      for (const MultidirPlane& p : result.planes) {
        ns.push_back(p.normal);
        ds.push_back(p.offsetMm);
      }
      double jg = result.jgAfterMm2;
      const auto tp = Clock::now();
      bool stopped = false;
      const size_t kept =
          perturbPlanes(m, options, true, result.rotationAxis, ns, ds, jg, progress, 0.9, 0.99, stopped, result.stats);
      result.stats.msPerturb += msSince(tp);
      if (stopped) return cancelled();
      if (kept > 0) {
        result.stats.perturbationsKept += kept;
        fillResult(m, ns, ds, result);
      }
    }
  }
  result.stats.msTotal = msSince(tStart);
  // The returned sequence level by level, once the search (and in 4dof the axis) is decided.
  for (size_t k = 0; k < result.stats.jgPerLevel.size(); ++k) {
    const SearchLevelProgress s{"chosen", static_cast<int>(k), result.stats.jgPerLevel[k], 0};
    if (!reportProgress(progress, "decompose", 1.0, s)) return cancelled();
  }
  reportProgress(progress, "decompose", 1.0);
  return result;
}

MultidirEvaluation evaluateDecomposition(const Mesh& mesh, const std::vector<MultidirPlane>& planes,
                                         const MultidirOptions& options) {
  MultidirEvaluation result;
  Outcome ok = checkCommonOptions(options);
  for (const MultidirPlane& p : planes) {
    if (!ok.ok()) break;
    if (!isFinite(p.normal) || !(p.normal.norm() > 0) || !std::isfinite(p.offsetMm)) {
      ok = failed<Outcome>(Status::InvalidOption, "a plane has a zero or non-finite normal or offset");
    }
  }
  if (ok.ok()) ok = checkMesh(mesh);
  Model m;
  if (ok.ok()) ok = buildModel(mesh, options, m);
  if (!ok.ok()) {
    result.status = ok.status;
    result.message = ok.message;
    return result;
  }
  std::vector<Vec3> ns;
  std::vector<double> ds;
  for (const MultidirPlane& p : planes) {
    const double len = p.normal.norm();
    ns.push_back(p.normal / len);
    ds.push_back(p.offsetMm / len);
  }
  const std::vector<double> risk = exactRisk(m, ns, ds);
  result.jgBeforeMm2 = m.jgBefore;
  const double cellVolume = m.h * m.h * m.h;
  Bits s((m.cells + 63) / 64, 0);
  for (size_t c = 0; c < m.cells; ++c) setBit(s, c);
  size_t count = m.cells;
  FloodScratch fs;
  for (size_t k = 0; k < ns.size(); ++k) {
    MultidirPlaneCheck check;
    size_t nBelow = 0;
    Bits below = cellsBelow(m, s, ns[k], ds[k], nBelow);
    const size_t nAbove = count - nBelow;
    check.partVolumeMm3 = nAbove * cellVolume;
    check.partLargeEnough = nAbove > 0 && nAbove * options.w >= static_cast<double>(m.cells) - 1e-9;
    check.platformBelow = m.platformLimit(ns[k]) <= ds[k] + 1e-9;
    const size_t reached = reachableBelow(m, s, ns[k], ds[k], fs);
    check.connected = static_cast<double>(nBelow - reached) <= options.floatingToleranceCells;
    check.floatingVolumeMm3 = (nBelow - reached) * cellVolume;
    result.checks.push_back(check);
    MultidirPart part;
    part.direction = ns[k];
    part.plane = static_cast<int>(k);
    part.volumeMm3 = check.partVolumeMm3;
    part.riskyAreaMm2 = risk[k];
    result.parts.push_back(part);
    s.swap(below);
    count = nBelow;
  }
  MultidirPart base;
  base.volumeMm3 = count * cellVolume;
  base.riskyAreaMm2 = risk.back();
  result.parts.push_back(base);
  for (double r : risk) result.jgAfterMm2 += r;
  return result;
}

}  // namespace omnislice
