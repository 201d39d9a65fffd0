// SPDX-License-Identifier: MIT
// The topology of an iso-planar surface (isoplanar_topology.h): welded edges and ordered
// boundary loops with their arc lengths.
#include "isoplanar/isoplanar_topology.h"

#include <Eigen/Core>
#include <algorithm>
#include <numeric>
#include <utility>

namespace omnislice::isoplanar_detail {

void buildTopology(const Mesh& mesh, Topology& topo) {
  const size_t nv = mesh.vertexCount();
  std::vector<uint32_t> canon(nv);
  {
    std::vector<uint32_t> byPos(nv);
    std::iota(byPos.begin(), byPos.end(), 0u);
    const double* pos = mesh.positions.data();
    auto less = [pos](uint32_t a, uint32_t b) {
      for (int k = 0; k < 3; ++k) {
        if (pos[3 * a + k] != pos[3 * b + k]) return pos[3 * a + k] < pos[3 * b + k];
      }
      return a < b;
    };
    std::sort(byPos.begin(), byPos.end(), less);
    std::iota(canon.begin(), canon.end(), 0u);
    for (size_t i = 1; i < nv; ++i) {
      const uint32_t v = byPos[i], u = byPos[i - 1];
      if (pos[3 * v] == pos[3 * u] && pos[3 * v + 1] == pos[3 * u + 1] && pos[3 * v + 2] == pos[3 * u + 2]) {
        canon[v] = canon[u];
      }
    }
  }
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const uint32_t a = canon[mesh.triangles[3 * f]], b = canon[mesh.triangles[3 * f + 1]],
                   c = canon[mesh.triangles[3 * f + 2]];
    if (a == b || b == c || c == a) continue;
    topo.tris.insert(topo.tris.end(), {a, b, c});
  }
  const size_t nt = topo.tris.size() / 3;
  // Half-edges bucketed by their smaller vertex (counting sort), edges found within buckets.
  std::vector<uint32_t> start(nv + 1, 0);
  for (size_t h = 0; h < 3 * nt; ++h) {
    const uint32_t a = topo.tris[h], b = topo.tris[h - h % 3 + (h % 3 + 1) % 3];
    ++start[std::min(a, b) + 1];
  }
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<uint32_t> fill(start.begin(), start.end() - 1), other(3 * nt), half(3 * nt);
  for (size_t h = 0; h < 3 * nt; ++h) {
    const uint32_t a = topo.tris[h], b = topo.tris[h - h % 3 + (h % 3 + 1) % 3];
    const uint32_t slot = fill[std::min(a, b)]++;
    other[slot] = std::max(a, b);
    half[slot] = static_cast<uint32_t>(h);
  }
  topo.triEdge.assign(3 * nt, kNone);
  for (size_t v = 0; v < nv; ++v) {
    for (uint32_t s = start[v]; s < start[v + 1]; ++s) {
      uint32_t edge = kNone;
      for (uint32_t r = start[v]; r < s; ++r) {
        if (other[r] == other[s]) {
          edge = topo.triEdge[half[r]];
          break;
        }
      }
      if (edge == kNone) {
        edge = static_cast<uint32_t>(topo.ea.size());
        topo.ea.push_back(static_cast<uint32_t>(v));
        topo.eb.push_back(other[s]);
        topo.faces.push_back(0);
      }
      topo.triEdge[half[s]] = edge;
      if (topo.faces[edge] < 255) ++topo.faces[edge];
    }
  }
  // Boundary loops.
  const size_t ne = topo.ea.size();
  std::vector<uint32_t> bstart(nv + 1, 0);
  for (size_t e = 0; e < ne; ++e) {
    if (topo.faces[e] != 1) continue;
    ++bstart[topo.ea[e] + 1];
    ++bstart[topo.eb[e] + 1];
  }
  for (size_t v = 0; v < nv; ++v) bstart[v + 1] += bstart[v];
  std::vector<uint32_t> bfill(bstart.begin(), bstart.end() - 1), bedges(bstart[nv]);
  for (size_t e = 0; e < ne; ++e) {
    if (topo.faces[e] != 1) continue;
    bedges[bfill[topo.ea[e]]++] = static_cast<uint32_t>(e);
    bedges[bfill[topo.eb[e]]++] = static_cast<uint32_t>(e);
  }
  topo.edgeLoop.assign(ne, kNone);
  topo.edgeLoopIndex.assign(ne, 0);
  topo.edgeForward.assign(ne, 0);
  std::vector<uint8_t> used(ne, 0);
  auto vertexOf = [&](uint32_t v) { return mesh.vertex(v); };
  for (size_t e0 = 0; e0 < ne; ++e0) {
    if (topo.faces[e0] != 1 || used[e0]) continue;
    used[e0] = 1;
    const uint32_t first = topo.ea[e0];
    std::vector<uint32_t> verts{first}, edges{static_cast<uint32_t>(e0)};
    uint32_t cur = topo.eb[e0];
    bool closed = false;
    for (;;) {
      if (cur == first) {
        closed = true;
        break;
      }
      verts.push_back(cur);
      uint32_t next = kNone;
      for (uint32_t s = bstart[cur]; s < bstart[cur + 1]; ++s) {
        if (!used[bedges[s]]) {
          next = bedges[s];
          break;
        }
      }
      if (next == kNone) break;
      used[next] = 1;
      edges.push_back(next);
      cur = topo.ea[next] == cur ? topo.eb[next] : topo.ea[next];
    }
    const uint32_t id = static_cast<uint32_t>(topo.loops.size());
    std::vector<double> cum(edges.size() + 1, 0.0);
    for (size_t i = 0; i < edges.size(); ++i) {
      const uint32_t e = edges[i];
      topo.edgeLoop[e] = id;
      topo.edgeLoopIndex[e] = static_cast<uint32_t>(i);
      topo.edgeForward[e] = verts[i] == topo.ea[e] ? 1 : 0;
      cum[i + 1] = cum[i] + (vertexOf(topo.ea[e]) - vertexOf(topo.eb[e])).norm();
    }
    topo.loops.push_back(std::move(verts));
    topo.loopCum.push_back(std::move(cum));
    topo.loopClosed.push_back(closed ? 1 : 0);
  }
}

}  // namespace omnislice::isoplanar_detail
