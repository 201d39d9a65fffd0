// SPDX-License-Identifier: MIT
// Contours of the boundary distance for the Fermat spirals (fermat_contours.h): consistent face
// normals, marching-triangles contours with the band pieces (cells of a triangle within one band,
// united across shared edges), and their orientation (larger phi on the left).
#include "surface/fermat_contours.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <deque>
#include <unordered_map>
#include <utility>

#include "common/disjoint_sets.h"

namespace omnislice::fermat_detail {

// Consistent face normals: breadth-first over manifold edges, flipping a neighbour that runs the
// shared edge the same way; each component keeps its majority orientation.
std::vector<Eigen::Vector3d> orientedFaceNormals(const Mesh& mesh, const MeshEdges& edges) {
  const size_t nf = mesh.faceCount();
  std::vector<int8_t> flip(nf, -1);
  std::vector<Eigen::Vector3d> normals(nf);
  for (size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]), b = mesh.vertex(mesh.triangles[3 * f + 1]),
                          c = mesh.vertex(mesh.triangles[3 * f + 2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    normals[f] = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d(0, 0, 1);
  }
  std::deque<uint32_t> queue;
  std::vector<uint32_t> component;
  for (size_t seed = 0; seed < nf; ++seed) {
    if (flip[seed] >= 0) continue;
    flip[seed] = 0;
    queue.push_back(static_cast<uint32_t>(seed));
    component.clear();
    while (!queue.empty()) {
      const uint32_t f = queue.front();
      queue.pop_front();
      component.push_back(f);
      for (int k = 0; k < 3; ++k) {
        const uint32_t h = 3 * f + k;
        const uint32_t e = edges.edgeOfHalfedge[h];
        if (edges.faceCount[e] != 2) continue;
        for (uint32_t o = edges.firstHalfedge[e]; o != kNoIndex; o = edges.nextHalfedge[o]) {
          if (o == h) continue;
          const uint32_t g = o / 3;
          if (flip[g] >= 0) continue;
          const bool same = mesh.triangles[h] == mesh.triangles[o];
          flip[g] = static_cast<int8_t>(flip[f] ^ (same ? 1 : 0));
          queue.push_back(g);
        }
      }
    }
    size_t flipped = 0;
    for (uint32_t f : component) flipped += flip[f];
    const int8_t invert = 2 * flipped > component.size() ? 1 : 0;
    for (uint32_t f : component) {
      if (flip[f] ^ invert) normals[f] = -normals[f];
    }
  }
  return normals;
}

// Marching-triangles contours of phi at the given increasing levels and the band pieces.
// Convention: a vertex is "above" level v when phi >= v, so a level through a vertex is handled
// as if the vertex were infinitesimally above it.
ContourSet extractContours(const Mesh& mesh, const MeshEdges& edges, const std::vector<double>& phi,
                           const std::vector<double>& levels) {
  ContourSet out;
  auto band = [&](double x) {
    return static_cast<int>(std::upper_bound(levels.begin(), levels.end(), x) - levels.begin());
  };
  const size_t ne = edges.edgeCount(), nf = mesh.faceCount();
  // Crossings per edge: levels k with band(lo) <= k < band(hi).
  std::vector<int> edgeFirstLevel(ne), edgeStart(ne + 1, 0);
  std::vector<Eigen::Vector3d> crossingPoint;
  for (size_t e = 0; e < ne; ++e) {
    const uint32_t a = static_cast<uint32_t>(edges.keys[e] >> 32);
    const uint32_t b = static_cast<uint32_t>(edges.keys[e] & 0xFFFFFFFFu);
    const double pa = phi[a], pb = phi[b];
    const int k0 = band(std::min(pa, pb)), k1 = band(std::max(pa, pb));
    edgeFirstLevel[e] = k0;
    edgeStart[e + 1] = edgeStart[e] + (k1 - k0);
    for (int k = k0; k < k1; ++k) {
      const double t = (levels[k] - pa) / (pb - pa);
      crossingPoint.push_back(mesh.vertex(a) + std::clamp(t, 0.0, 1.0) * (mesh.vertex(b) - mesh.vertex(a)));
    }
  }
  const size_t nc = crossingPoint.size();
  std::vector<int> linkTo(2 * nc, -1), linkTri(2 * nc, -1);
  std::vector<int> crossingLevel(nc, 0);
  for (size_t e = 0; e < ne; ++e) {
    for (int c = edgeStart[e]; c < edgeStart[e + 1]; ++c) crossingLevel[c] = edgeFirstLevel[e] + (c - edgeStart[e]);
  }
  auto link = [&](int c, int d, int t) {
    const int slot = linkTo[2 * c] < 0 ? 0 : 1;
    if (linkTo[2 * c + slot] >= 0) return;  // non-manifold situation: keep the first two
    linkTo[2 * c + slot] = d;
    linkTri[2 * c + slot] = t;
  };
  // Cells: the part of a face inside one band.
  std::vector<int> cellStart(nf + 1, 0), faceBandLo(nf);
  for (size_t f = 0; f < nf; ++f) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int k = 0; k < 3; ++k) {
      lo = std::min(lo, phi[mesh.triangles[3 * f + k]]);
      hi = std::max(hi, phi[mesh.triangles[3 * f + k]]);
    }
    const int b0 = band(lo), b1 = band(hi);
    faceBandLo[f] = b0;
    cellStart[f + 1] = cellStart[f] + (b1 - b0 + 1);
    for (int k = b0; k < b1; ++k) {
      int found[2], nfound = 0;
      for (int j = 0; j < 3 && nfound < 2; ++j) {
        const uint32_t e = edges.edgeOfHalfedge[3 * f + j];
        if (k >= edgeFirstLevel[e] && k < edgeFirstLevel[e] + (edgeStart[e + 1] - edgeStart[e])) {
          found[nfound++] = edgeStart[e] + (k - edgeFirstLevel[e]);
        }
      }
      if (nfound == 2) {
        link(found[0], found[1], static_cast<int>(f));
        link(found[1], found[0], static_cast<int>(f));
      }
    }
  }
  DisjointSets cells(static_cast<size_t>(cellStart[nf]));
  auto cellOf = [&](size_t f, int b) { return static_cast<uint32_t>(cellStart[f] + (b - faceBandLo[f])); };
  for (size_t e = 0; e < ne; ++e) {
    if (edges.faceCount[e] != 2) continue;
    const uint32_t h1 = edges.firstHalfedge[e], h2 = edges.nextHalfedge[h1];
    const uint32_t f1 = h1 / 3, f2 = h2 / 3;
    const int k0 = edgeFirstLevel[e], k1 = k0 + (edgeStart[e + 1] - edgeStart[e]);
    for (int b = k0; b <= k1; ++b) cells.unite(cellOf(f1, b), cellOf(f2, b));
  }
  std::vector<int> pieceId(cellStart[nf], -1);
  for (size_t f = 0; f < nf; ++f) {
    for (int b = faceBandLo[f]; b < faceBandLo[f] + (cellStart[f + 1] - cellStart[f]); ++b) {
      const uint32_t r = cells.find(cellOf(f, b));
      if (pieceId[r] < 0) {
        pieceId[r] = out.pieces++;
        out.pieceBand.push_back(b);
      }
    }
  }
  // Walk the closed contours.
  std::vector<uint8_t> visited(nc, 0);
  for (size_t start = 0; start < nc; ++start) {
    if (visited[start] || linkTo[2 * start] < 0 || linkTo[2 * start + 1] < 0) continue;
    Contour c;
    c.level = crossingLevel[start];
    int cur = static_cast<int>(start), viaTri = linkTri[2 * start + 1];
    bool closed = false;
    while (true) {
      visited[cur] = 1;
      c.pts.push_back(crossingPoint[cur]);
      const int slot = linkTri[2 * cur] == viaTri ? 1 : 0;
      const int next = linkTo[2 * cur + slot], t = linkTri[2 * cur + slot];
      if (next < 0 || t < 0) break;
      c.tri.push_back(t);
      viaTri = t;
      if (next == static_cast<int>(start)) {
        closed = true;
        break;
      }
      if (visited[next]) break;
      cur = next;
    }
    if (!closed || c.pts.size() < 3) continue;
    // Drop zero-length segments (levels through vertices give repeated points).
    {
      std::vector<Eigen::Vector3d> p;
      std::vector<int> t;
      for (size_t i = 0; i < c.pts.size(); ++i) {
        const Eigen::Vector3d& next = c.pts[(i + 1) % c.pts.size()];
        if ((next - c.pts[i]).squaredNorm() <= 1e-24) continue;
        p.push_back(c.pts[i]);
        t.push_back(c.tri[i]);
      }
      if (p.size() < 3) continue;
      c.pts.swap(p);
      c.tri.swap(t);
    }
    const size_t f = static_cast<size_t>(c.tri[0]);
    c.lower = pieceId[cells.find(cellOf(f, c.level))];
    c.upper = pieceId[cells.find(cellOf(f, c.level + 1))];
    c.computeArcLength();
    out.contours.push_back(std::move(c));
  }
  return out;
}

// Orient a contour so that larger phi lies on its left (seen against the face normals).
void orientUpLeft(Contour& c, const Mesh& mesh, const std::vector<double>& phi,
                  const std::vector<Eigen::Vector3d>& faceNormal) {
  double score = 0;
  const size_t n = c.size();
  for (size_t i = 0; i < n; ++i) {
    const int f = c.tri[i];
    uint32_t top = mesh.triangles[3 * f];
    for (int k = 1; k < 3; ++k) {
      if (phi[mesh.triangles[3 * f + k]] > phi[top]) top = mesh.triangles[3 * f + k];
    }
    const Eigen::Vector3d dir = c.pts[(i + 1) % n] - c.pts[i];
    score += faceNormal[f].cross(dir).dot(mesh.vertex(top) - c.pts[i]);
  }
  if (score < 0) c.reverse();
}

}  // namespace omnislice::fermat_detail
