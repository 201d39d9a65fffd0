// SPDX-License-Identifier: MIT
// Internal to the multidir decomposition: the beam-guided search of clipping planes (paper 000
// Sections III-IV) and its greedy and constrained-greedy lines. Design (measurements in the
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
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/progress.h"
#include "multidir/decomposition.h"
#include "multidir/decomposition_model.h"

namespace omnislice::decomposition_detail {

constexpr int kMaxLevels = 256;  // safety bound; Criterion IV already limits parts to w

// The schemes of Section IV (decomposition.h SearchScheme).
using Scheme = SearchScheme;

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


// The search over one set of candidate normals (setNormals): the root state with its arrays, then
// any number of lines from it (runLine), whose nodes stay for best() and node().
class Search {
 public:
  Search(const Model& m, const MultidirOptions& o, MultidirStats& stats, const ProgressFn& progress);

  // Per-normal tables and the root state with its full J_L / R sweep.
  void setNormals(const std::vector<Vec3>& normals);

  // One line of search from the root: greedy / constrained (width 1) or the beam. Reports each
  // level as SearchLevelProgress `name` (level 0: the root). Returns false when cancelled.
  bool runLine(Scheme scheme, size_t width, double progressBase, double progressSpan, const char* name);

  // Best node of a line (all lines when line < 0): least J_G; within delta0 of it, fewest
  // planes; then the first created.
  uint32_t best(int line = -1) const;

  int lines() const { return line_; }
  const Node& node(uint32_t id) const { return nodes_[id]; }

 private:
  int64_t toFx(double areaMm2) const { return std::llround(areaMm2 * fxUnits_); }
  double fxToMm2(Fx v) const { return static_cast<double>(static_cast<int64_t>(v)) / fxUnits_; }

  bool isTerminal(const Node& nd) const;

  // J_L / R difference arrays of a state from all its faces: whole faces from their entries, cut
  // faces by clipping their polygons.
  void fullArrays(Node& s) const;

  // J_L / R arrays of `child` from its parent's: the faces the plane changed leave with their old
  // contribution and come back cut. Integer sums: the same arrays as fullArrays(child).
  void childArrays(const Node& parent, Node& child, const std::vector<FaceChange>& changes) const;

  // sign * weights * (area above each offset) of face f along entry e's normal, whole (p null) or
  // cut to polygon p, into the interleaved arrays `diff` (all normals). The one place a face's
  // contribution is computed, for fullArrays and childArrays alike.
  void addFace(Fx* diff, uint32_t f, const Entry& e, const Poly* p, int sign) const;

  // Candidates of one state: every normal, every offset from kStart up to the highest whose part
  // above holds ~V/w (coarse samples, lenient: the fine grid decides), with J_L > 0.
  void emit(uint32_t id);

  // Face state of the child of `parent` by plane (n, d) into `out`, the faces that changed into
  // `changes` (ascending); returns the number of faces the child keeps (whole or cut).
  size_t childFaces(const Node& parent, const Vec3& n, double d, Node& out, std::vector<FaceChange>& changes) const;

  // "Close" results (paper IV-B, after Chopper): the same parent and nearly the same plane, or
  // remaining models whose volume samples differ by at most similarityFraction of the smaller
  // volume their last planes cut off.
  bool similar(const Node& a, const Node& b) const;

  // Fine cells of state `id` above each offset of normal j (suffix counts), on first use.
  const std::vector<uint32_t>& fineAbove(uint32_t id, uint32_t j);

  // Criterion II for plane (normal j, offset k) of state `id`, leaving `count` cells below: a
  // flood fill from the platform layer; after a first failure for this (state, normal), one
  // union-find sweep answers every offset of it.
  bool connected(uint32_t id, uint32_t j, int k, size_t count);

  // valid[k - kLo] = no cell of S n {n . x <= k * step} is cut off from the platform layer: cells
  // join a union-find in order of height along n; a component is grounded once it holds a
  // platform cell; the offset is valid when no component is ungrounded.
  void connectedOffsets(const Node& s, const NormalData& nd, std::vector<uint8_t>& valid);

  // Orders the pool by the scheme's priority and accepts valid, dissimilar planes up to width.
  std::vector<uint32_t> select(const std::vector<uint32_t>& frontier, size_t width, Scheme scheme);

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
void lineEnds(const Search& s, std::vector<LineEnd>& out);

}  // namespace omnislice::decomposition_detail
