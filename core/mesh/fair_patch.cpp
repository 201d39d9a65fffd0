// SPDX-License-Identifier: MIT
#include "mesh/fair_patch.h"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace omnislice {
namespace {

using Edge = std::pair<uint32_t, uint32_t>;  // (smaller, larger)

Edge key(uint32_t a, uint32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

// Split interior edges longer than maxEdge, longest first; false when nothing was split.
bool refinePass(HolePatch& p, double maxEdge, size_t maxTriangles) {
  std::map<Edge, std::vector<uint32_t>> faces;  // edge -> triangles holding it
  for (uint32_t t = 0; t < p.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) faces[key(p.triangles[t][k], p.triangles[t][(k + 1) % 3])].push_back(t);
  }
  std::vector<std::pair<double, Edge>> longEdges;
  for (const auto& [e, ts] : faces) {
    if (ts.size() != 2) continue;  // a rim edge (one patch triangle) is never split
    const double len = (p.points[e.first] - p.points[e.second]).norm();
    if (len > maxEdge) longEdges.emplace_back(len, e);
  }
  if (longEdges.empty()) return false;
  std::sort(longEdges.begin(), longEdges.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<uint8_t> touched(p.triangles.size(), 0);
  bool split = false;
  for (const auto& [len, e] : longEdges) {
    if (p.triangles.size() + 2 > maxTriangles) break;
    const std::vector<uint32_t>& ts = faces[e];
    if (touched[ts[0]] || touched[ts[1]]) continue;
    const uint32_t m = static_cast<uint32_t>(p.points.size());
    p.points.push_back(0.5 * (p.points[e.first] + p.points[e.second]));
    for (uint32_t t : ts) {
      touched[t] = 1;
      // Rotate the triangle so that it runs a -> b -> c with {a, b} the edge, then split at m.
      std::array<uint32_t, 3> tri = p.triangles[t];
      while (key(tri[0], tri[1]) != e) std::rotate(tri.begin(), tri.begin() + 1, tri.end());
      p.triangles[t] = {tri[0], m, tri[2]};
      p.triangles.push_back({m, tri[1], tri[2]});
      touched.push_back(1);
    }
    split = true;
  }
  return split;
}

}  // namespace

HolePatch refineAndFair(HolePatch p, size_t loopSize, const std::vector<std::vector<Eigen::Vector3d>>& outerRing) {
  if (loopSize < 3 || outerRing.size() != loopSize) return p;
  double rim = 0;
  for (size_t i = 0; i < loopSize; ++i) rim += (p.points[i] - p.points[(i + 1) % loopSize]).norm();
  const double maxEdge = std::sqrt(2.0) * rim / static_cast<double>(loopSize);
  const size_t maxTriangles = 16 * p.triangles.size();
  for (int pass = 0; pass < 64 && refinePass(p, maxEdge, maxTriangles); ++pass) {
  }
  const size_t n = p.points.size();
  if (n == loopSize) return p;

  // Uniform umbrella Laplacian rows for every patch point: L_i = mean of neighbours - x_i, the rim
  // points' neighbours including their outer ring (constants, gathered in c).
  std::vector<std::vector<uint32_t>> nbrs(n);
  for (const auto& t : p.triangles) {
    for (int k = 0; k < 3; ++k) {
      nbrs[t[k]].push_back(t[(k + 1) % 3]);
      nbrs[t[k]].push_back(t[(k + 2) % 3]);
    }
  }
  using Sparse = Eigen::SparseMatrix<double>;
  std::vector<Eigen::Triplet<double>> lt;
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), 3);
  for (size_t i = 0; i < n; ++i) {
    std::sort(nbrs[i].begin(), nbrs[i].end());
    nbrs[i].erase(std::unique(nbrs[i].begin(), nbrs[i].end()), nbrs[i].end());
    const size_t outer = i < loopSize ? outerRing[i].size() : 0;
    const double w = 1.0 / static_cast<double>(nbrs[i].size() + outer);
    for (uint32_t j : nbrs[i]) lt.emplace_back(static_cast<int>(i), static_cast<int>(j), w);
    lt.emplace_back(static_cast<int>(i), static_cast<int>(i), -1.0);
    for (size_t k = 0; k < outer; ++k) c.row(static_cast<Eigen::Index>(i)) += w * outerRing[i][k].transpose();
  }
  Sparse L(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  L.setFromTriplets(lt.begin(), lt.end());
  const Sparse L2 = L * L;
  const Eigen::MatrixXd Lc = L * c;
  // Rows and columns of the new points: L2[free, free] x_free = -L2[free, fixed] x_fixed - (L c)[free].
  const Eigen::Index nf = static_cast<Eigen::Index>(n - loopSize);
  const Eigen::Index off = static_cast<Eigen::Index>(loopSize);
  Eigen::MatrixXd fixed(off, 3);
  for (Eigen::Index i = 0; i < off; ++i) fixed.row(i) = p.points[static_cast<size_t>(i)].transpose();
  const Sparse A = L2.bottomRightCorner(nf, nf);
  const Eigen::MatrixXd b = -(L2.bottomLeftCorner(nf, off) * fixed) - Lc.bottomRows(nf);
  Eigen::SparseLU<Sparse> solver;
  solver.compute(A);
  if (solver.info() != Eigen::Success) return p;
  const Eigen::MatrixXd x = solver.solve(b);
  if (solver.info() != Eigen::Success || !x.allFinite()) return p;
  for (Eigen::Index i = 0; i < nf; ++i) p.points[static_cast<size_t>(off + i)] = x.row(i).transpose();
  return p;
}

}  // namespace omnislice
