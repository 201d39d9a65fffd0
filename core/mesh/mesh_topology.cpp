// SPDX-License-Identifier: MIT
#include "common/math_constants.h"
#include "mesh/mesh_topology.h"

#include "common/disjoint_sets.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace omnislice {
namespace {

inline uint32_t fromVertex(const Mesh& m, uint32_t h) { return m.triangles[h]; }
inline uint32_t nextInFace(uint32_t h) { return h - h % 3 + (h % 3 + 1) % 3; }

}  // namespace

MeshEdges buildEdges(const Mesh& mesh) {
  // Bucket the half-edges by their smaller vertex (a counting sort), then group each small bucket
  // by the larger vertex: edges come out sorted by (min, max) key with sequential memory access,
  // where a hash of 3M keys would miss the cache on nearly every probe.
  const size_t halfedges = mesh.triangles.size();
  const size_t nv = mesh.vertexCount();
  const uint32_t* t = mesh.triangles.data();
  auto minVertex = [&](uint32_t h) { return std::min(t[h], t[nextInFace(h)]); };
  auto maxVertex = [&](uint32_t h) { return std::max(t[h], t[nextInFace(h)]); };
  std::vector<uint32_t> start(nv + 1, 0);
  for (uint32_t h = 0; h < halfedges; ++h) ++start[minVertex(h) + 1];
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<uint32_t> bucket(halfedges);
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t h = 0; h < halfedges; ++h) bucket[fill[minVertex(h)]++] = h;
  }
  MeshEdges e;
  e.edgeOfHalfedge.resize(halfedges);
  e.nextHalfedge.assign(halfedges, kNoIndex);
  e.keys.reserve(halfedges / 2 + 16);
  e.faceCount.reserve(halfedges / 2 + 16);
  e.firstHalfedge.reserve(halfedges / 2 + 16);
  for (size_t v = 0; v < nv; ++v) {
    uint32_t* b = bucket.data() + start[v];
    uint32_t* bEnd = bucket.data() + start[v + 1];
    // Stable order by the other vertex (half-edge ids ascending within an edge).
    if (bEnd - b <= 32) {
      for (uint32_t* i = b + 1; i < bEnd; ++i) {
        const uint32_t h = *i;
        const uint32_t key = maxVertex(h);
        uint32_t* j = i;
        for (; j > b && maxVertex(*(j - 1)) > key; --j) *j = *(j - 1);
        *j = h;
      }
    } else {
      std::stable_sort(b, bEnd, [&](uint32_t x, uint32_t y) { return maxVertex(x) < maxVertex(y); });
    }
    for (uint32_t* i = b; i < bEnd;) {
      const uint32_t other = maxVertex(*i);
      const uint32_t edge = static_cast<uint32_t>(e.keys.size());
      e.keys.push_back(uint64_t(v) << 32 | other);
      e.firstHalfedge.push_back(*i);
      uint32_t count = 0, prev = kNoIndex;
      for (; i < bEnd && maxVertex(*i) == other; ++i) {
        e.edgeOfHalfedge[*i] = edge;
        if (prev != kNoIndex) e.nextHalfedge[prev] = *i;
        prev = *i;
        ++count;
      }
      e.faceCount.push_back(count);
    }
  }
  return e;
}

FaceComponents edgeComponents(const Mesh& mesh, const MeshEdges& edges) {
  const size_t faces = mesh.faceCount();
  DisjointSets sets(faces);
  for (size_t edge = 0; edge < edges.edgeCount(); ++edge) {
    const uint32_t first = edges.firstHalfedge[edge];
    for (uint32_t h = edges.nextHalfedge[first]; h != kNoIndex; h = edges.nextHalfedge[h]) {
      sets.unite(first / 3, h / 3);
    }
  }
  FaceComponents out;
  out.label.assign(faces, kNoIndex);
  for (uint32_t f = 0; f < faces; ++f) {
    const uint32_t root = sets.find(f);
    if (out.label[root] == kNoIndex) out.label[root] = static_cast<uint32_t>(out.count++);
    out.label[f] = out.label[root];
  }
  return out;
}

namespace {

// Generalised winding number of the closed triangle set faces (of mesh) around point p: the sum
// of the signed solid angles over 4 pi (van Oosterom and Strackee's formula per triangle).
double windingNumber(const Mesh& mesh, const std::vector<uint32_t>& faces, const Eigen::Vector3d& p) {
  double total = 0;
  for (uint32_t f : faces) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]) - p;
    const Eigen::Vector3d b = mesh.vertex(mesh.triangles[3 * f + 1]) - p;
    const Eigen::Vector3d c = mesh.vertex(mesh.triangles[3 * f + 2]) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2 * std::atan2(num, den);
  }
  return total / (4 * kPi);
}

}  // namespace

std::vector<Mesh> splitComponents(const Mesh& mesh, bool groupCavities) {
  const FaceComponents comp = edgeComponents(mesh, buildEdges(mesh));
  std::vector<std::vector<uint32_t>> facesOf(comp.count);
  for (uint32_t f = 0; f < mesh.faceCount(); ++f) facesOf[comp.label[f]].push_back(f);
  // owner[c] = the component whose mesh takes component c's faces.
  std::vector<uint32_t> owner(comp.count);
  std::iota(owner.begin(), owner.end(), 0u);
  if (groupCavities && comp.count > 1) {
    // Per-shell signed volume (about the mesh's bounding-box centre) and bounds, in one pass.
    std::vector<double> volume(comp.count, 0);
    std::vector<BoundingBox> box(comp.count);
    std::vector<uint8_t> seen(comp.count, 0);
    const BoundingBox all = boundingBox(mesh);
    const Eigen::Vector3d o = 0.5 * (all.min + all.max);
    for (uint32_t f = 0; f < mesh.faceCount(); ++f) {
      const uint32_t c = comp.label[f];
      const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]);
      const Eigen::Vector3d b = mesh.vertex(mesh.triangles[3 * f + 1]);
      const Eigen::Vector3d d = mesh.vertex(mesh.triangles[3 * f + 2]);
      volume[c] += (a - o).dot((b - o).cross(d - o));
      if (!seen[c]) {
        seen[c] = 1;
        box[c].min = box[c].max = a;
      }
      box[c].min = box[c].min.cwiseMin(a).cwiseMin(b).cwiseMin(d);
      box[c].max = box[c].max.cwiseMax(a).cwiseMax(b).cwiseMax(d);
    }
    for (uint32_t c = 0; c < comp.count; ++c) {
      if (!(volume[c] < 0)) continue;
      const uint32_t f = facesOf[c][0];
      const Eigen::Vector3d probe = (mesh.vertex(mesh.triangles[3 * f]) +
                                     mesh.vertex(mesh.triangles[3 * f + 1]) +
                                     mesh.vertex(mesh.triangles[3 * f + 2])) / 3;
      uint32_t best = c;
      for (uint32_t o = 0; o < comp.count; ++o) {
        if (!(volume[o] > 0) || (best != c && volume[o] >= volume[best])) continue;
        if ((box[c].min.array() < box[o].min.array()).any() ||
            (box[c].max.array() > box[o].max.array()).any()) {
          continue;
        }
        if (std::abs(windingNumber(mesh, facesOf[o], probe)) > 0.5) best = o;
      }
      owner[c] = best;
    }
  }
  std::vector<Mesh> out;
  std::vector<uint32_t> meshOf(comp.count, kNoIndex);
  for (uint32_t c = 0; c < comp.count; ++c) {
    if (owner[c] == c) {
      meshOf[c] = static_cast<uint32_t>(out.size());
      out.emplace_back();
    }
  }
  std::vector<uint32_t> newIndex(mesh.vertexCount(), kNoIndex);
  std::vector<std::vector<uint32_t>> groups(out.size());
  for (uint32_t c = 0; c < comp.count; ++c) {
    std::vector<uint32_t>& g = groups[meshOf[owner[c]]];
    g.insert(g.end(), facesOf[c].begin(), facesOf[c].end());
  }
  for (size_t m = 0; m < out.size(); ++m) {
    std::vector<uint32_t>& faces = groups[m];
    std::sort(faces.begin(), faces.end());
    std::vector<uint32_t> used;
    for (uint32_t f : faces) {
      for (int k = 0; k < 3; ++k) used.push_back(mesh.triangles[3 * f + k]);
    }
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    Mesh& part = out[m];
    part.positions.reserve(3 * used.size());
    for (uint32_t i = 0; i < used.size(); ++i) {
      newIndex[used[i]] = i;
      part.positions.insert(part.positions.end(), mesh.positions.begin() + 3 * used[i],
                            mesh.positions.begin() + 3 * used[i] + 3);
    }
    part.triangles.reserve(3 * faces.size());
    for (uint32_t f : faces) {
      for (int k = 0; k < 3; ++k) part.triangles.push_back(newIndex[mesh.triangles[3 * f + k]]);
    }
  }
  return out;
}

TopologyCounts countTopology(const Mesh& mesh, const MeshEdges& edges) {
  TopologyCounts c;
  c.shells = edgeComponents(mesh, edges).count;
  for (size_t edge = 0; edge < edges.edgeCount(); ++edge) {
    const uint32_t n = edges.faceCount[edge];
    if (n == 1) ++c.boundaryEdges;
    if (n > 2) ++c.nonManifoldEdges;
    if (n == 2) {
      const uint32_t h1 = edges.firstHalfedge[edge];
      const uint32_t h2 = edges.nextHalfedge[h1];
      if (fromVertex(mesh, h1) == fromVertex(mesh, h2)) ++c.misorientedEdges;
    }
  }
  // Vertex fans: corner 3f+k sits at triangles[3f+k]. Corners of faces that share an edge are
  // joined at both ends of that edge; a vertex whose corners end up in several sets is the apex
  // of several fans (a "bow-tie" where separate sheets touch at a point).
  DisjointSets corners(mesh.triangles.size());
  for (size_t edge = 0; edge < edges.edgeCount(); ++edge) {
    const uint32_t first = edges.firstHalfedge[edge];
    const uint32_t a = fromVertex(mesh, first);
    for (uint32_t h = edges.nextHalfedge[first]; h != kNoIndex; h = edges.nextHalfedge[h]) {
      const uint32_t hn = nextInFace(h);
      const uint32_t fn = nextInFace(first);
      if (fromVertex(mesh, h) == a) {  // same direction
        corners.unite(first, h);
        corners.unite(fn, hn);
      } else {
        corners.unite(first, hn);
        corners.unite(fn, h);
      }
    }
  }
  std::vector<uint32_t> rootOfVertex(mesh.vertexCount(), kNoIndex);
  std::vector<uint8_t> counted(mesh.vertexCount(), 0);
  for (uint32_t corner = 0; corner < mesh.triangles.size(); ++corner) {
    const uint32_t v = mesh.triangles[corner];
    const uint32_t root = corners.find(corner);
    if (rootOfVertex[v] == kNoIndex) {
      rootOfVertex[v] = root;
    } else if (rootOfVertex[v] != root && !counted[v]) {
      counted[v] = 1;
      ++c.nonManifoldVertices;
    }
  }
  return c;
}

}  // namespace omnislice
