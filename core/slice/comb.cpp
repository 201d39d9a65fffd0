// SPDX-License-Identifier: MIT
#include "slice/comb.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace omnislice {
namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

constexpr size_t kMaxCellsPerQuery = 4096;  // beyond this a query scans every edge

}  // namespace

CombRegion::CombRegion(std::vector<std::vector<Vec2>> loops) {
  for (auto& loop : loops) {
    if (loop.size() >= 3) loops_.push_back(std::move(loop));
  }
  if (loops_.empty()) return;
  Vec2 lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  size_t edges = 0;
  for (const auto& loop : loops_) {
    edgeBase_.push_back(edges);
    edges += loop.size();
    for (const Vec2& p : loop) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  stamp_.assign(edges, 0);
  const Vec2 size = (hi - lo).cwiseMax(1e-6);
  // About one edge per cell, at most 512 cells a side.
  cell_ = std::max({std::sqrt(size.x() * size.y() / static_cast<double>(edges)), size.x() / 512, size.y() / 512, 1e-6});
  origin_ = lo;
  nx_ = static_cast<long>(std::floor(size.x() / cell_)) + 1;
  ny_ = static_cast<long>(std::floor(size.y() / cell_)) + 1;
  auto cellRange = [&](const Vec2& a, const Vec2& b, long& x0, long& x1, long& y0, long& y1) {
    x0 = std::clamp(static_cast<long>(std::floor((std::min(a.x(), b.x()) - origin_.x()) / cell_)), 0L, nx_ - 1);
    x1 = std::clamp(static_cast<long>(std::floor((std::max(a.x(), b.x()) - origin_.x()) / cell_)), 0L, nx_ - 1);
    y0 = std::clamp(static_cast<long>(std::floor((std::min(a.y(), b.y()) - origin_.y()) / cell_)), 0L, ny_ - 1);
    y1 = std::clamp(static_cast<long>(std::floor((std::max(a.y(), b.y()) - origin_.y()) / cell_)), 0L, ny_ - 1);
  };
  std::vector<size_t> count(static_cast<size_t>(nx_ * ny_) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t l = 0; l < loops_.size(); ++l) {
      const auto& loop = loops_[l];
      for (size_t e = 0; e < loop.size(); ++e) {
        long x0, x1, y0, y1;
        cellRange(loop[e], loop[(e + 1) % loop.size()], x0, x1, y0, y1);
        for (long y = y0; y <= y1; ++y) {
          for (long x = x0; x <= x1; ++x) {
            const size_t c = static_cast<size_t>(y * nx_ + x);
            if (pass == 0) {
              ++count[c + 1];
            } else {
              cellEdges_[count[c]++] = {l, e};
            }
          }
        }
      }
    }
    if (pass == 0) {
      for (size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
      cellStart_ = count;
      cellEdges_.resize(count.back());
    }
  }
}

void CombRegion::crossings(const Vec2& a, const Vec2& b, std::vector<Crossing>& out, bool firstOnly) const {
  out.clear();
  const Vec2 d = b - a;
  auto test = [&](size_t l, size_t e) {
    const size_t flat = edgeBase_[l] + e;
    if (stamp_[flat] == query_) return;
    stamp_[flat] = query_;
    const auto& loop = loops_[l];
    const Vec2& p = loop[e];
    const Vec2 q = loop[(e + 1) % loop.size()];
    // The edge crosses the segment's line when its ends lie on either side, a point on the line
    // counting as right of it (so a line through a vertex crosses there once, or twice where it
    // touches the loop from the left, an entry and exit at one point, never an odd count).
    const double sp = cross(d, p - a), sq = cross(d, q - a);
    if ((sp > 0) == (sq > 0)) return;
    const Vec2 ed = q - p;
    const double t = cross(p - a, ed) / cross(d, ed);
    if (!(t > 1e-9 && t < 1 - 1e-9)) return;
    out.push_back({t, l, e, a + t * d});
  };
  ++query_;
  if (query_ == 0) {  // wrapped: reset the stamps
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    query_ = 1;
  }
  const long x0 = std::clamp(static_cast<long>(std::floor((std::min(a.x(), b.x()) - origin_.x()) / cell_)), 0L, nx_ - 1);
  const long x1 = std::clamp(static_cast<long>(std::floor((std::max(a.x(), b.x()) - origin_.x()) / cell_)), 0L, nx_ - 1);
  const long y0 = std::clamp(static_cast<long>(std::floor((std::min(a.y(), b.y()) - origin_.y()) / cell_)), 0L, ny_ - 1);
  const long y1 = std::clamp(static_cast<long>(std::floor((std::max(a.y(), b.y()) - origin_.y()) / cell_)), 0L, ny_ - 1);
  if (static_cast<size_t>((x1 - x0 + 1) * (y1 - y0 + 1)) > kMaxCellsPerQuery) {
    for (size_t l = 0; l < loops_.size() && !(firstOnly && !out.empty()); ++l) {
      for (size_t e = 0; e < loops_[l].size(); ++e) test(l, e);
    }
  } else {
    for (long y = y0; y <= y1 && !(firstOnly && !out.empty()); ++y) {
      for (long x = x0; x <= x1; ++x) {
        const size_t c = static_cast<size_t>(y * nx_ + x);
        for (size_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k) test(cellEdges_[k].first, cellEdges_[k].second);
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const Crossing& p, const Crossing& q) { return p.t < q.t; });
}

bool CombRegion::clear(const Vec2& a, const Vec2& b) const {
  std::vector<Crossing> found;
  crossings(a, b, found, true);
  // No crossing inside the segment: it lies in the region, or wholly outside it between two
  // points of the boundary; its middle decides.
  return found.empty() && inside(0.5 * (a + b));
}

bool CombRegion::inside(const Vec2& m) const {
  // Even-odd count of the edges a ray to +x crosses (an edge counts when its ends lie on either
  // side of the ray's line, the upper end strictly above: each vertex is counted once).
  ++query_;
  if (query_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    query_ = 1;
  }
  const long y = static_cast<long>(std::floor((m.y() - origin_.y()) / cell_));
  if (y < 0 || y >= ny_) return false;
  const long x0 = std::clamp(static_cast<long>(std::floor((m.x() - origin_.x()) / cell_)), 0L, nx_ - 1);
  bool in = false;
  for (long x = x0; x < nx_; ++x) {
    const size_t c = static_cast<size_t>(y * nx_ + x);
    for (size_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k) {
      const auto [l, e] = cellEdges_[k];
      const size_t flat = edgeBase_[l] + e;
      if (stamp_[flat] == query_) continue;
      stamp_[flat] = query_;
      const auto& loop = loops_[l];
      const Vec2& p = loop[e];
      const Vec2& q = loop[(e + 1) % loop.size()];
      if ((p.y() > m.y()) == (q.y() > m.y())) continue;
      const double xCross = p.x() + (m.y() - p.y()) / (q.y() - p.y()) * (q.x() - p.x());
      if (xCross > m.x()) in = !in;
    }
  }
  return in;
}

void CombRegion::walk(const Crossing& from, const Crossing& to, std::vector<Vec2>& out) const {
  const auto& loop = loops_[from.loop];
  const size_t n = loop.size();
  if (from.edge == to.edge) {
    out.push_back(to.point);
    return;
  }
  // Forward: from -> v[i+1] -> ... -> v[j] -> to; backward: from -> v[i] -> ... -> v[j+1] -> to.
  std::vector<Vec2> fwd, bwd;
  double lf = 0, lb = 0;
  Vec2 last = from.point;
  for (size_t v = (from.edge + 1) % n;; v = (v + 1) % n) {
    lf += (loop[v] - last).norm();
    last = loop[v];
    fwd.push_back(loop[v]);
    if (v == to.edge) break;
  }
  lf += (to.point - last).norm();
  last = from.point;
  for (size_t v = from.edge;; v = (v + n - 1) % n) {
    lb += (loop[v] - last).norm();
    last = loop[v];
    bwd.push_back(loop[v]);
    if (v == (to.edge + 1) % n) break;
  }
  lb += (to.point - last).norm();
  const std::vector<Vec2>& way = lf <= lb ? fwd : bwd;
  out.insert(out.end(), way.begin(), way.end());
  out.push_back(to.point);
}

bool CombRegion::route(const Vec2& a, const Vec2& b, std::vector<Vec2>& out) const {
  out.clear();
  if (loops_.empty()) return false;
  std::vector<Crossing> found;
  crossings(a, b, found, false);
  if (found.empty()) {
    out.push_back(b);
    return true;
  }
  if (found.size() % 2 != 0) return false;
  std::vector<Vec2> pts{a};
  for (size_t k = 0; k < found.size(); k += 2) {
    if (found[k].loop != found[k + 1].loop) return false;
    pts.push_back(found[k].point);
    walk(found[k], found[k + 1], pts);
  }
  pts.push_back(b);
  // Each point to the farthest next one it sees (forward, stopping at the first one hidden).
  for (size_t i = 0; i + 1 < pts.size();) {
    size_t j = i + 1;
    while (j + 1 < pts.size() && clear(pts[i], pts[j + 1])) ++j;
    out.push_back(pts[j]);
    i = j;
  }
  return true;
}

}  // namespace omnislice
