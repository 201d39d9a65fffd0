// SPDX-License-Identifier: MIT
#include "common/math_constants.h"
#include "mesh/orient_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace omnislice {
namespace {

struct Component {
  std::vector<uint32_t> faces;
  bool orientable = true;
  bool closed = true;
  double volume = 0;
  Eigen::Vector3d min, max;
};

uint32_t otherHalfedge(const MeshEdges& edges, uint32_t h) {
  const uint32_t e = edges.edgeOfHalfedge[h];
  const uint32_t first = edges.firstHalfedge[e];
  return first == h ? edges.nextHalfedge[first] : first;
}

// Corners of face f after applying its flip flag.
void faceCorners(const Mesh& mesh, const std::vector<uint8_t>& flip, uint32_t f, Eigen::Vector3d& a,
                 Eigen::Vector3d& b, Eigen::Vector3d& c) {
  a = mesh.vertex(mesh.triangles[3 * f]);
  b = mesh.vertex(mesh.triangles[3 * f + 1]);
  c = mesh.vertex(mesh.triangles[3 * f + 2]);
  if (flip[f]) std::swap(b, c);
}

// Generalised winding number of point p with respect to the faces of comp (solid angles / 4 pi).
double windingNumber(const Mesh& mesh, const std::vector<uint8_t>& flip, const Component& comp,
                     const Eigen::Vector3d& p) {
  double sum = 0;
  for (uint32_t f : comp.faces) {
    Eigen::Vector3d a, b, c;
    faceCorners(mesh, flip, f, a, b, c);
    a -= p;
    b -= p;
    c -= p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double det = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2 * std::atan2(det, den);
  }
  return sum / (4 * kPi);
}

bool boxInside(const Component& inner, const Component& outer) {
  return (inner.min.array() >= outer.min.array()).all() && (inner.max.array() <= outer.max.array()).all();
}

}  // namespace

OrientResult orientMesh(const Mesh& mesh, const MeshEdges& edges, const OrientOptions& options) {
  const uint32_t faces = static_cast<uint32_t>(mesh.faceCount());
  const uint32_t* t = mesh.triangles.data();
  OrientResult r;
  r.flip.assign(faces, 0);
  std::vector<uint32_t> label(faces, kNoIndex);
  std::vector<Component> comps;
  std::vector<uint32_t> queue;
  queue.reserve(faces);

  // 1. Components over two-face edges; relative flips by breadth-first search.
  for (uint32_t seed = 0; seed < faces; ++seed) {
    if (label[seed] != kNoIndex) continue;
    const uint32_t id = static_cast<uint32_t>(comps.size());
    comps.emplace_back();
    Component& comp = comps.back();
    label[seed] = id;
    queue.clear();
    queue.push_back(seed);
    for (size_t qi = 0; qi < queue.size(); ++qi) {
      const uint32_t f = queue[qi];
      comp.faces.push_back(f);
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t h = 3 * f + k;
        const uint32_t e = edges.edgeOfHalfedge[h];
        if (edges.faceCount[e] == 1) comp.closed = false;
        if (edges.faceCount[e] != 2) continue;
        const uint32_t o = otherHalfedge(edges, h);
        const uint32_t g = o / 3;
        if (label[g] != kNoIndex) continue;
        const uint8_t sameDirection = t[h] == t[o] ? 1 : 0;
        r.flip[g] = r.flip[f] ^ sameDirection;
        label[g] = id;
        queue.push_back(g);
      }
    }
    // Flip the minority: a box with one face reversed gets that one face flipped.
    size_t flipped = 0;
    for (uint32_t f : comp.faces) flipped += r.flip[f];
    if (2 * flipped > comp.faces.size()) {
      for (uint32_t f : comp.faces) r.flip[f] ^= 1;
      flipped = comp.faces.size() - flipped;
    }
    r.reorientedFaces += flipped;
  }
  r.components = comps.size();

  // 2. Edges that still disagree make their component non-orientable.
  for (size_t e = 0; e < edges.edgeCount(); ++e) {
    if (edges.faceCount[e] != 2) continue;
    const uint32_t h1 = edges.firstHalfedge[e];
    const uint32_t h2 = edges.nextHalfedge[h1];
    const bool same = (t[h1] == t[h2]) != (r.flip[h1 / 3] != r.flip[h2 / 3]);
    if (same) {
      ++r.misorientedEdges;
      comps[label[h1 / 3]].orientable = false;
    }
  }
  for (const Component& c : comps) r.nonOrientableComponents += c.orientable ? 0 : 1;
  if (!options.outward) return r;

  // 3. Signed volume and bounds of each closed orientable component (origin at the mesh centre
  //    to keep the triple products well conditioned).
  const BoundingBox box = boundingBox(mesh);
  const Eigen::Vector3d centre = 0.5 * (box.min + box.max);
  std::vector<uint32_t> closedIds;
  for (uint32_t id = 0; id < comps.size(); ++id) {
    Component& c = comps[id];
    // Fewer than four faces bound no volume (single faces between non-manifold edges count as
    // closed): their sign means nothing, and thousands of them made the nesting test quadratic.
    if (!c.closed || !c.orientable || c.faces.size() < 4) continue;
    closedIds.push_back(id);
    c.min = Eigen::Vector3d::Constant(INFINITY);
    c.max = -c.min;
    for (uint32_t f : c.faces) {
      Eigen::Vector3d a, b, cc;
      faceCorners(mesh, r.flip, f, a, b, cc);
      c.min = c.min.cwiseMin(a).cwiseMin(b).cwiseMin(cc);
      c.max = c.max.cwiseMax(a).cwiseMax(b).cwiseMax(cc);
      c.volume += (a - centre).dot((b - centre).cross(cc - centre)) / 6;
    }
  }

  // 4. Nesting: the container of a closed component is the smallest other closed component that
  //    holds it (a few face centroids all inside, |winding| > 1/2, so components that merely
  //    overlap are not nested). Each nesting tree is flipped as a whole when its outermost
  //    component has a negative volume: relative orientations, and so what the non-zero rule
  //    makes of nested shells (cavity or union), are never changed.
  std::vector<uint32_t> parent(comps.size(), kNoIndex);
  double work = 0;
  for (uint32_t id : closedIds) {
    const Component& inner = comps[id];
    bool unchecked = false;
    for (uint32_t other : closedIds) {
      const Component& outer = comps[other];
      if (other == id || !(std::abs(outer.volume) > std::abs(inner.volume)) || !boxInside(inner, outer)) {
        continue;
      }
      if (parent[id] != kNoIndex && std::abs(comps[parent[id]].volume) <= std::abs(outer.volume)) continue;
      const size_t samples = std::min<size_t>(5, inner.faces.size());
      const double cost = double(samples) * double(outer.faces.size());
      if (work + cost > options.nestingBudget) {
        unchecked = true;
        continue;
      }
      work += cost;
      bool inside = true;
      for (size_t s = 0; s < samples && inside; ++s) {
        const uint32_t f = inner.faces[s * inner.faces.size() / samples];
        Eigen::Vector3d a, b, c;
        faceCorners(mesh, r.flip, f, a, b, c);
        inside = std::abs(windingNumber(mesh, r.flip, outer, (a + b + c) / 3)) > 0.5;
      }
      if (inside) parent[id] = other;
    }
    r.nestingUnchecked += unchecked ? 1 : 0;
  }
  for (uint32_t id : closedIds) {
    Component& c = comps[id];
    if (parent[id] != kNoIndex) {
      const bool opposite = (c.volume < 0) != (comps[parent[id]].volume < 0);
      r.cavities += opposite ? 1 : 0;
      r.nestedSameOrientation += opposite ? 0 : 1;
    }
    // Containers have strictly larger |volume|, so the chain ends.
    uint32_t root = id;
    while (parent[root] != kNoIndex) root = parent[root];
    if (comps[root].volume < 0) {
      for (uint32_t f : c.faces) r.flip[f] ^= 1;
      ++r.outwardComponents;
      r.outwardFaces += c.faces.size();
    }
  }
  return r;
}

}  // namespace omnislice
