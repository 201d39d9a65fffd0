// SPDX-License-Identifier: MIT
// The plane search of the multidir decomposition (plane_search.h): per-normal tables, the J_L / R
// difference arrays of each state, candidates, Criteria II and IV, similarity, and the levels of
// a search line.
#include "multidir/plane_search.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/det_math.h"
#include "common/math_constants.h"
#include "common/stopwatch.h"

namespace omnislice::decomposition_detail {

Search::Search(const Model& m, const MultidirOptions& o, MultidirStats& stats, const ProgressFn& progress)
    : m_(m), o_(o), stats_(stats), progress_(progress) {
  minPartCells_ = static_cast<size_t>(std::ceil(static_cast<double>(m_.cells) / o_.w - 1e-9));
  // 2^40 units per mm^2, fewer when S >= 2^22 mm^2 so that S * fxUnits_ < 2^62.
  int e = 0;
  std::frexp(m_.surfaceArea, &e);  // S < 2^e
  fxUnits_ = std::ldexp(1.0, std::min(40, 62 - e));
}

void Search::setNormals(const std::vector<Vec3>& normals) {
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

bool Search::runLine(Scheme scheme, size_t width, double progressBase, double progressSpan, const char* name) {
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

uint32_t Search::best(int line) const {
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

bool Search::isTerminal(const Node& nd) const {
  return nd.cellCount * o_.w < static_cast<double>(m_.cells) || nd.platRisk <= kMinGainMm2;
}

void Search::fullArrays(Node& s) const {
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

void Search::childArrays(const Node& parent, Node& child, const std::vector<FaceChange>& changes) const {
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

void Search::addFace(Fx* diff, uint32_t f, const Entry& e, const Poly* p, int sign) const {
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

void Search::emit(uint32_t id) {
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

size_t Search::childFaces(const Node& parent, const Vec3& n, double d, Node& out, std::vector<FaceChange>& changes) const {
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

bool Search::similar(const Node& a, const Node& b) const {
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

const std::vector<uint32_t>& Search::fineAbove(uint32_t id, uint32_t j) {
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

bool Search::connected(uint32_t id, uint32_t j, int k, size_t count) {
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

void Search::connectedOffsets(const Node& s, const NormalData& nd, std::vector<uint8_t>& valid) {
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

std::vector<uint32_t> Search::select(const std::vector<uint32_t>& frontier, size_t width, Scheme scheme) {
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

}  // namespace omnislice::decomposition_detail
