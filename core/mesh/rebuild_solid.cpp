// SPDX-License-Identifier: MIT
#include "mesh/rebuild_solid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace omnislice {
namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;

// The regular grid of samples: point (i, j, k) at origin + pitch (i, j, k), 0 <= i <= n[0] etc.;
// cell (i, j, k) is the cube from point (i, j, k) to (i+1, j+1, k+1).
struct Grid {
  Eigen::Vector3d origin;
  double pitch = 1;
  std::array<int, 3> n{};  // cells per axis (points: n + 1)

  size_t pointIndex(int i, int j, int k) const {
    return (size_t(k) * size_t(n[1] + 1) + size_t(j)) * size_t(n[0] + 1) + size_t(i);
  }
  size_t cellIndex(int i, int j, int k) const {
    return (size_t(k) * size_t(n[1]) + size_t(j)) * size_t(n[0]) + size_t(i);
  }
  size_t pointCount() const { return size_t(n[0] + 1) * size_t(n[1] + 1) * size_t(n[2] + 1); }
  size_t cellCount() const { return size_t(n[0]) * size_t(n[1]) * size_t(n[2]); }
  double coordinate(int axis, int index) const { return origin[axis] + pitch * index; }
};

// Where a line along +d crosses a triangle: the coordinate along d, and +1 when the triangle
// faces against the line (the line enters what it bounds), -1 when it faces along it.
struct Crossing {
  double t;
  int enter;
  bool operator<(const Crossing& o) const { return t < o.t; }
};

// The crossings of the soup with the lines along axis d through the grid points: lines are
// indexed by the point's two other coordinates (a = d+1, b = d+2, cyclic), a fastest.
struct Lines {
  int d = 0, a = 1, b = 2;
  int na = 0, nb = 0;
  std::vector<std::vector<Crossing>> crossings;  // sorted along d
  const std::vector<Crossing>& at(int ia, int ib) const { return crossings[size_t(ib) * size_t(na) + size_t(ia)]; }
};

Lines castLines(const Mesh& soup, const Grid& g, int d) {
  Lines L;
  L.d = d;
  L.a = (d + 1) % 3;
  L.b = (d + 2) % 3;
  L.na = g.n[L.a] + 1;
  L.nb = g.n[L.b] + 1;
  L.crossings.resize(size_t(L.na) * size_t(L.nb));
  const int a = L.a, b = L.b;
  for (size_t f = 0; f < soup.faceCount(); ++f) {
    const Eigen::Vector3d p0 = soup.vertex(soup.triangles[3 * f]);
    const Eigen::Vector3d p1 = soup.vertex(soup.triangles[3 * f + 1]);
    const Eigen::Vector3d p2 = soup.vertex(soup.triangles[3 * f + 2]);
    const double minA = std::min({p0[a], p1[a], p2[a]}), maxA = std::max({p0[a], p1[a], p2[a]});
    const double minB = std::min({p0[b], p1[b], p2[b]}), maxB = std::max({p0[b], p1[b], p2[b]});
    const int ia0 = std::max(0, int(std::ceil((minA - g.origin[a]) / g.pitch)));
    const int ia1 = std::min(L.na - 1, int(std::floor((maxA - g.origin[a]) / g.pitch)));
    const int ib0 = std::max(0, int(std::ceil((minB - g.origin[b]) / g.pitch)));
    const int ib1 = std::min(L.nb - 1, int(std::floor((maxB - g.origin[b]) / g.pitch)));
    for (int ib = ib0; ib <= ib1; ++ib) {
      const double y = g.coordinate(b, ib);
      for (int ia = ia0; ia <= ia1; ++ia) {
        const double x = g.coordinate(a, ia);
        // Signed areas of the sub-triangles opposite each corner, in the (a, b) plane.
        const double w0 = (p1[a] - x) * (p2[b] - y) - (p2[a] - x) * (p1[b] - y);
        const double w1 = (p2[a] - x) * (p0[b] - y) - (p0[a] - x) * (p2[b] - y);
        const double w2 = (p0[a] - x) * (p1[b] - y) - (p1[a] - x) * (p0[b] - y);
        const bool inside = (w0 > 0 && w1 > 0 && w2 > 0) || (w0 < 0 && w1 < 0 && w2 < 0);
        if (!inside) continue;
        const double sum = w0 + w1 + w2;  // twice the signed area in (a, b): the normal's d part
        const double t = (w0 * p0[d] + w1 * p1[d] + w2 * p2[d]) / sum;
        L.crossings[size_t(ib) * size_t(L.na) + size_t(ia)].push_back({t, sum < 0 ? 1 : -1});
      }
    }
  }
  for (auto& c : L.crossings) std::sort(c.begin(), c.end());
  return L;
}

}  // namespace

RebuildResult rebuildSolid(const Mesh& soup, const RebuildOptions& options, const ProgressFn& progress,
                           double from, double to) {
  RebuildResult r;
  auto report = [&](double t) { return reportProgress(progress, "repair", from + (to - from) * t); };
  auto cancelled = [] {
    RebuildResult c;
    c.status = Status::Cancelled;
    c.message = "cancelled";
    return c;
  };
  if (soup.empty()) {
    r.status = Status::EmptyInput;
    r.message = "no faces to rebuild a solid from";
    return r;
  }
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (uint32_t v : soup.triangles) {
    lo = lo.cwiseMin(soup.vertex(v));
    hi = hi.cwiseMax(soup.vertex(v));
  }
  const double longest = (hi - lo).maxCoeff();
  if (!(longest > 0) || !std::isfinite(longest)) return r;  // flat or degenerate: not accepted
  Grid g;
  g.pitch = longest / std::max(8, options.cells);
  // Points off round coordinates (CAD parts and cell exports put faces and edges on them), one
  // and a half cells of margin so the outer layer of points is outside.
  const Eigen::Vector3d offset(0.3183098862, 0.2718281828, 0.1414213562);
  g.origin = lo - (Eigen::Vector3d::Constant(1.5) + offset) * g.pitch;
  for (int k = 0; k < 3; ++k) g.n[k] = int(std::ceil((hi[k] - g.origin[k]) / g.pitch + 1.5));
  r.pitchMm = g.pitch;

  // Votes per point and direction, by two rules: parity (an odd number of crossings before the
  // point) and winding (entries minus exits before it, non-zero). Parity needs no orientation and
  // cancels walls present twice; winding also fills where bodies overlap (parity empties them)
  // but needs the faces turned consistently. The rule whose directions disagree less decides
  // (winding on a tie: an oriented file means what its winding says).
  std::array<Lines, 3> lines;
  std::vector<uint8_t> parityVotes(g.pointCount(), 0), windingVotes(g.pointCount(), 0);
  for (int d = 0; d < 3; ++d) {
    lines[d] = castLines(soup, g, d);
    const Lines& L = lines[d];
    for (int ib = 0; ib < L.nb; ++ib) {
      for (int ia = 0; ia < L.na; ++ia) {
        const std::vector<Crossing>& c = L.at(ia, ib);
        if (c.empty()) continue;
        size_t passed = 0;
        int winding = 0;
        for (int id = 0; id <= g.n[d]; ++id) {
          const double x = g.coordinate(d, id);
          while (passed < c.size() && c[passed].t < x) winding += c[passed++].enter;
          if (passed % 2 == 0 && winding == 0) continue;
          std::array<int, 3> p{};
          p[d] = id;
          p[L.a] = ia;
          p[L.b] = ib;
          const size_t at = g.pointIndex(p[0], p[1], p[2]);
          parityVotes[at] += passed % 2;
          windingVotes[at] += winding != 0 ? 1 : 0;
        }
      }
    }
    if (!report(0.2 * (d + 1))) return cancelled();
  }
  size_t parityDisagreeing = 0, windingDisagreeing = 0;
  for (size_t i = 0; i < parityVotes.size(); ++i) {
    parityDisagreeing += parityVotes[i] == 1 || parityVotes[i] == 2;
    windingDisagreeing += windingVotes[i] == 1 || windingVotes[i] == 2;
  }
  r.winding = windingDisagreeing <= parityDisagreeing;
  const std::vector<uint8_t>& votes = r.winding ? windingVotes : parityVotes;
  std::vector<uint8_t> inside(votes.size(), 0);
  for (int k = 0; k <= g.n[2]; ++k) {
    for (int j = 0; j <= g.n[1]; ++j) {
      for (int i = 0; i <= g.n[0]; ++i) {
        const uint8_t v = votes[g.pointIndex(i, j, k)];
        if (v == 1 || v == 2) ++r.disagreeing;
        if (v >= 1) ++r.touchedSamples;
        if (v < 2) continue;
        inside[g.pointIndex(i, j, k)] = 1;
        ++r.insideSamples;
        if (i == 0 || j == 0 || k == 0 || i == g.n[0] || j == g.n[1] || k == g.n[2]) r.touchesBorder = true;
      }
    }
  }
  if (r.insideSamples == 0 || r.touchesBorder ||
      double(r.disagreeing) > options.maxDisagreement * double(r.insideSamples)) {
    return r;
  }

  // The crossing on the edge from point p along axis d: the one of its line nearest the middle.
  auto crossing = [&](const std::array<int, 3>& p, int d, bool& found) {
    const Lines& L = lines[d];
    const std::vector<Crossing>& c = L.at(p[L.a], p[L.b]);
    const double x0 = g.coordinate(d, p[d]), mid = x0 + 0.5 * g.pitch;
    double best = mid, bestGap = INFINITY;
    auto it = std::lower_bound(c.begin(), c.end(), Crossing{x0, 0});
    for (; it != c.end() && it->t <= x0 + g.pitch; ++it) {
      if (std::abs(it->t - mid) < bestGap) {
        bestGap = std::abs(it->t - mid);
        best = it->t;
        found = true;
      }
    }
    Eigen::Vector3d q(g.coordinate(0, p[0]), g.coordinate(1, p[1]), g.coordinate(2, p[2]));
    q[d] = best;
    return q;
  };
  auto isInside = [&](const std::array<int, 3>& p) { return inside[g.pointIndex(p[0], p[1], p[2])] != 0; };

  std::vector<uint32_t> cellVertex(g.cellCount(), kNone);
  Mesh& out = r.mesh;
  auto vertexOf = [&](int ci, int cj, int ck) {
    uint32_t& id = cellVertex[g.cellIndex(ci, cj, ck)];
    if (id != kNone) return id;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    bool found = false;
    for (int d = 0; d < 3; ++d) {
      const int a = (d + 1) % 3, b = (d + 2) % 3;
      for (int oa = 0; oa < 2; ++oa) {
        for (int ob = 0; ob < 2; ++ob) {
          std::array<int, 3> p = {ci, cj, ck};
          p[a] += oa;
          p[b] += ob;
          std::array<int, 3> q = p;
          ++q[d];
          if (isInside(p) == isInside(q)) continue;
          sum += crossing(p, d, found);
          ++count;
        }
      }
    }
    const Eigen::Vector3d v = sum / std::max(count, 1);
    r.inventedVertices += found ? 0 : 1;
    id = uint32_t(out.vertexCount());
    out.positions.insert(out.positions.end(), {v.x(), v.y(), v.z()});
    return id;
  };
  for (int d = 0; d < 3; ++d) {
    const int a = (d + 1) % 3, b = (d + 2) % 3;
    for (int k = 0; k <= g.n[2]; ++k) {
      for (int j = 0; j <= g.n[1]; ++j) {
        for (int i = 0; i <= g.n[0]; ++i) {
          std::array<int, 3> p = {i, j, k};
          if (p[d] == g.n[d]) continue;
          std::array<int, 3> q = p;
          ++q[d];
          const bool in = isInside(p);
          if (in == isInside(q)) continue;
          // The four cells around the edge, counter-clockwise seen from +d (a x b = d).
          std::array<uint32_t, 4> quad;
          const int offsets[4][2] = {{-1, -1}, {0, -1}, {0, 0}, {-1, 0}};
          for (int c = 0; c < 4; ++c) {
            std::array<int, 3> cell = p;
            cell[a] += offsets[c][0];
            cell[b] += offsets[c][1];
            quad[c] = vertexOf(cell[0], cell[1], cell[2]);
          }
          if (!in) std::swap(quad[1], quad[3]);  // the outside is toward -d: turn the other way
          out.triangles.insert(out.triangles.end(), {quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]});
        }
      }
    }
    if (!report(0.6 + 0.13 * (d + 1))) return cancelled();
  }
  r.netVertices = out.vertexCount();
  if (double(r.inventedVertices) > options.maxInventedShare * double(r.netVertices)) {
    out = {};
    return r;
  }
  r.accepted = true;
  return r;
}

}  // namespace omnislice
