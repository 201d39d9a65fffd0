// SPDX-License-Identifier: MIT
#include "mesh/repair_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <cstdio>

#include "cgal/hole_triangulation.h"
#include "common/disjoint_sets.h"
#include "common/math_constants.h"
#include "common/plural.h"
#include "mesh/fair_patch.h"
#include "mesh/mesh_topology.h"
#include "mesh/orient_mesh.h"

namespace omnislice {
namespace {

constexpr const char* kStage = "repair";
// Hole triangles of less area than this times the squared diagonal are not made (prepareMesh drops
// faces below 1e-12).
constexpr double kSliverArea = 1e-10;


std::string mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, v < 10 ? "%.2f" : "%.1f", v);
  return buf;
}

// T-junctions: a boundary vertex lying on another boundary edge (within tolerance of the
// segment, strictly between its ends) whose own boundary runs along that edge (two of its
// boundary neighbours lie on the edge's line), as where two faces of a CAD export were tessellated apart
// and one side of their common edge has vertices the other lacks. The face of that edge is split
// by a fan from its opposite corner through those vertices, so both sides then share the same
// edges and the crack closes without new geometry. A face with T-vertices on several edges is
// split one edge per pass (the fan keeps its other two edges). Returns the vertices inserted.
size_t zipTJunctions(Mesh& m) {
  size_t inserted = 0;
  for (int pass = 0; pass < 4; ++pass) {
    const MeshEdges edges = buildEdges(m);
    std::vector<uint32_t> open;  // boundary edges
    double length = 0;
    for (size_t e = 0; e < edges.edgeCount(); ++e) {
      if (edges.faceCount[e] != 1) continue;
      open.push_back(uint32_t(e));
      length += (m.vertex(uint32_t(edges.keys[e] >> 32)) - m.vertex(uint32_t(edges.keys[e]))).norm();
    }
    if (open.empty()) return inserted;
    const double cell = length / double(open.size());
    if (!(cell > 0)) return inserted;
    const BoundingBox box = boundingBox(m);
    const double tolerance = 1e-6 * (box.max - box.min).norm();
    // Boundary vertices hashed by cell.
    std::vector<uint8_t> isOpen(m.vertexCount(), 0);
    std::vector<std::pair<uint32_t, uint32_t>> links;  // (vertex, boundary neighbour), sorted
    for (uint32_t e : open) {
      const uint32_t u = uint32_t(edges.keys[e] >> 32), w = uint32_t(edges.keys[e] & 0xFFFFFFFFu);
      isOpen[u] = isOpen[w] = 1;
      links.emplace_back(u, w);
      links.emplace_back(w, u);
    }
    std::sort(links.begin(), links.end());
    auto cellOf = [&](const Eigen::Vector3d& p) {
      return Eigen::Vector3i(int(std::floor((p.x() - box.min.x()) / cell)), int(std::floor((p.y() - box.min.y()) / cell)),
                             int(std::floor((p.z() - box.min.z()) / cell)));
    };
    auto hash = [](const Eigen::Vector3i& c) {
      return (uint64_t(uint32_t(c.x())) * 73856093u) ^ (uint64_t(uint32_t(c.y())) * 19349663u) ^
             (uint64_t(uint32_t(c.z())) * 83492791u);
    };
    std::vector<std::pair<uint64_t, uint32_t>> buckets;  // (hash, vertex), sorted
    for (uint32_t v = 0; v < m.vertexCount(); ++v) {
      if (isOpen[v]) buckets.emplace_back(hash(cellOf(m.vertex(v))), v);
    }
    std::sort(buckets.begin(), buckets.end());
    // Per face: the T-vertices on one of its edges (its corner k to k+1), sorted along it.
    std::vector<std::pair<uint32_t, std::vector<std::pair<double, uint32_t>>>> splits;  // (half-edge, ...)
    std::vector<uint8_t> faceTaken(m.faceCount(), 0);
    std::vector<uint32_t> seen;
    for (uint32_t e : open) {
      const uint32_t h = edges.firstHalfedge[e], f = h / 3;
      if (faceTaken[f]) continue;
      const uint32_t a = m.triangles[h], b = m.triangles[3 * f + (h % 3 + 1) % 3];
      const Eigen::Vector3d pa = m.vertex(a), pb = m.vertex(b), ab = pb - pa;
      const double len2 = ab.squaredNorm();
      if (!(len2 > 0)) continue;
      std::vector<std::pair<double, uint32_t>> on;
      seen.clear();
      const int steps = int(std::ceil(std::sqrt(len2) / (0.5 * cell)));
      for (int s = 0; s <= steps; ++s) {
        const Eigen::Vector3i c = cellOf(pa + ab * (double(s) / steps));
        for (int dx = -1; dx <= 1; ++dx) {
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dz = -1; dz <= 1; ++dz) {
              const uint64_t key = hash(c + Eigen::Vector3i(dx, dy, dz));
              auto it = std::lower_bound(buckets.begin(), buckets.end(), std::make_pair(key, uint32_t(0)));
              for (; it != buckets.end() && it->first == key; ++it) {
                const uint32_t v = it->second;
                if (v == a || v == b || std::find(seen.begin(), seen.end(), v) != seen.end()) continue;
                seen.push_back(v);
                const Eigen::Vector3d pv = m.vertex(v);
                const double t = (pv - pa).dot(ab) / len2;
                if (!(t > 0 && t < 1)) continue;
                if ((pa + t * ab - pv).norm() > tolerance) continue;
                if ((pv - pa).norm() <= tolerance || (pv - pb).norm() <= tolerance) continue;
                // A crack: v's boundary runs along the edge (two of its boundary neighbours lie on
                // its line), not a boundary passing by it.
                int along = 0;
                for (auto l = std::lower_bound(links.begin(), links.end(), std::make_pair(v, uint32_t(0)));
                     l != links.end() && l->first == v; ++l) {
                  const uint32_t w = l->second;
                  const Eigen::Vector3d pw = m.vertex(w);
                  const double tw = (pw - pa).dot(ab) / len2;
                  along += w == a || w == b || (pa + tw * ab - pw).norm() <= tolerance;
                }
                if (along < 2) continue;
                on.emplace_back(t, v);
              }
            }
          }
        }
      }
      if (on.empty()) continue;
      std::sort(on.begin(), on.end());
      faceTaken[f] = 1;
      splits.emplace_back(h, std::move(on));
    }
    if (splits.empty()) return inserted;
    for (const auto& [h, on] : splits) {
      const uint32_t f = h / 3, k = h % 3;
      const uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3],
                     c = m.triangles[3 * f + (k + 2) % 3];
      // a, v1, ..., vn, b seen from c: triangles (prev, next, c), the first replacing face f.
      uint32_t prev = a;
      for (size_t i = 0; i <= on.size(); ++i) {
        const uint32_t next = i < on.size() ? on[i].second : b;
        if (i == 0) {
          m.triangles[3 * f] = prev;
          m.triangles[3 * f + 1] = next;
          m.triangles[3 * f + 2] = c;
        } else {
          m.triangles.insert(m.triangles.end(), {prev, next, c});
        }
        prev = next;
      }
      inserted += on.size();
    }
  }
  return inserted;
}

// Corner of face f at vertex v (f has v).
uint32_t cornerAt(const Mesh& m, uint32_t f, uint32_t v) {
  for (uint32_t k = 0; k < 3; ++k) {
    if (m.triangles[3 * f + k] == v) return 3 * f + k;
  }
  return 3 * f;
}

// Pairs of half-edges (faces) that are neighbours across their edge: the two of a manifold edge,
// and, at an edge of more than two faces, faces sorted by angle about the edge and paired with an
// angular neighbour that runs the edge the other way, choosing the pairing whose wedges hold
// material (the normals of both faces point out of the wedge).
// A face left unpaired at an edge of an odd number of faces goes to leftOver.
std::vector<std::pair<uint32_t, uint32_t>> pairHalfedges(const Mesh& m, const MeshEdges& edges,
                                                         size_t& unpairedEdges, std::vector<uint32_t>& leftOver) {
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  pairs.reserve(m.faceCount() * 3 / 2);
  std::vector<uint32_t> hs;
  struct Around {
    uint32_t h;
    double angle;
    bool forward;  // runs the edge from its lower vertex to its higher one
    Eigen::Vector3d normal;
  };
  std::vector<Around> around;
  for (size_t e = 0; e < edges.edgeCount(); ++e) {
    hs.clear();
    for (uint32_t h = edges.firstHalfedge[e]; h != kNoIndex; h = edges.nextHalfedge[h]) hs.push_back(h);
    if (hs.size() == 2) {
      pairs.emplace_back(hs[0], hs[1]);
      continue;
    }
    if (hs.size() < 2) continue;
    ++unpairedEdges;
    const uint32_t p = static_cast<uint32_t>(edges.keys[e] >> 32);
    const uint32_t q = static_cast<uint32_t>(edges.keys[e] & 0xFFFFFFFFu);
    const Eigen::Vector3d P = m.vertex(p);
    const Eigen::Vector3d d = (m.vertex(q) - P).normalized();
    const Eigen::Vector3d e1 = d.unitOrthogonal();
    const Eigen::Vector3d e2 = d.cross(e1);
    around.clear();
    for (uint32_t h : hs) {
      const uint32_t f = h / 3;
      const uint32_t* t = m.triangles.data() + 3 * f;
      uint32_t w = t[0];
      for (int k = 0; k < 3; ++k) {
        if (t[k] != p && t[k] != q) w = t[k];
      }
      const Eigen::Vector3d r = m.vertex(w) - P;
      const Eigen::Vector3d n = (m.vertex(t[1]) - m.vertex(t[0])).cross(m.vertex(t[2]) - m.vertex(t[0]));
      around.push_back({h, std::atan2(r.dot(e2), r.dot(e1)), m.triangles[h] == p, n});
    }
    std::sort(around.begin(), around.end(), [](const Around& a, const Around& b) { return a.angle < b.angle; });
    const size_t k = around.size();
    // Score of the pairing that starts at offset o: pairs (o + 2i, o + 2i + 1) around the edge.
    auto score = [&](size_t o) {
      int s = 0;
      for (size_t i = 0; i + 1 < k; i += 2) {
        const Around& a = around[(o + i) % k];
        const Around& b = around[(o + i + 1) % k];
        if (a.forward == b.forward) continue;
        double span = b.angle - a.angle;
        if (span < 0) span += 2 * kPi;
        const double mid = a.angle + span / 2;
        const Eigen::Vector3d w = std::cos(mid) * e1 + std::sin(mid) * e2;
        s += 1 + (a.normal.dot(w) < 0 && b.normal.dot(w) < 0 ? 1 : 0);
      }
      return s;
    };
    // An even count pairs from offset 0 or 1; an odd one leaves one face out (at (o + k - 1) % k):
    // every offset is tried.
    size_t o = 0;
    int best = score(0);
    for (size_t trial = 1; trial < (k % 2 ? k : 2); ++trial) {
      const int sc = score(trial);
      if (sc > best) best = sc, o = trial;
    }
    for (size_t i = 0; i + 1 < k; i += 2) {
      pairs.emplace_back(around[(o + i) % k].h, around[(o + i + 1) % k].h);
    }
    if (k % 2) leftOver.push_back(around[(o + k - 1) % k].h / 3);
  }
  return pairs;
}

// Step 1: one vertex per fan of faces linked through paired half-edges.
Mesh splitFans(const Mesh& input, SolidRepairStats& stats) {
  // A face left over at an edge of an odd number of faces (a fin, a wall inside) would keep the
  // edge non-manifold whatever the vertices do: it goes (faces it leaves hanging go next, in
  // repairSolid's pruning).
  Mesh m = input;
  MeshEdges edges = buildEdges(m);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (int round = 0;; ++round) {  // dropping a face can leave another edge odd
    std::vector<uint32_t> leftOver;
    size_t unpaired = 0;
    pairs = pairHalfedges(m, edges, unpaired, leftOver);
    if (round == 0) stats.edgesUnpaired = unpaired;
    // The pairs are of this mesh: stop before changing it once enough rounds have run.
    if (leftOver.empty() || round == 8) break;
    std::sort(leftOver.begin(), leftOver.end());
    leftOver.erase(std::unique(leftOver.begin(), leftOver.end()), leftOver.end());
    size_t kept = 0;
    for (size_t f = 0; f < m.faceCount(); ++f) {
      if (std::binary_search(leftOver.begin(), leftOver.end(), static_cast<uint32_t>(f))) continue;
      for (int k = 0; k < 3; ++k) m.triangles[3 * kept + k] = m.triangles[3 * f + k];
      ++kept;
    }
    m.triangles.resize(3 * kept);
    stats.facesLeftOver += leftOver.size();
    edges = buildEdges(m);
  }
  DisjointSets uf(m.triangles.size());
  for (const auto& [h1, h2] : pairs) {
    const uint32_t f1 = h1 / 3, f2 = h2 / 3;
    const uint32_t a = m.triangles[h1], b = m.triangles[3 * f1 + (h1 % 3 + 1) % 3];
    uf.unite(cornerAt(m, f1, a), cornerAt(m, f2, a));
    uf.unite(cornerAt(m, f1, b), cornerAt(m, f2, b));
  }
  Mesh out;
  out.positions = m.positions;
  out.triangles.resize(m.triangles.size());
  std::vector<uint32_t> vertexOfRoot(m.triangles.size(), kNoIndex);
  std::vector<uint8_t> used(m.vertexCount(), 0);
  for (uint32_t c = 0; c < m.triangles.size(); ++c) {
    const uint32_t root = uf.find(c);
    if (vertexOfRoot[root] == kNoIndex) {
      const uint32_t v = m.triangles[c];
      if (!used[v]) {
        used[v] = 1;
        vertexOfRoot[root] = v;
      } else {
        vertexOfRoot[root] = static_cast<uint32_t>(out.vertexCount());
        for (int k = 0; k < 3; ++k) out.positions.push_back(m.positions[3 * v + k]);
        ++stats.verticesSplit;
      }
    }
    out.triangles[c] = vertexOfRoot[root];
  }
  return out;
}

double triangleArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

// The surface around a hole is smooth and the hole not flat, so a fill should bend with it: the
// faces on consecutive rim edges turn by less than 30 degrees (no crease runs into the hole, as at
// a CAD part's edge), and the rim leaves its best plane by more than 1 % of its size.
bool smoothAround(const Mesh& m, const MeshEdges& edges, const std::vector<uint32_t>& loop) {
  const size_t n = loop.size();
  std::vector<Eigen::Vector3d> normals;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), planeNormal = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) centroid += m.vertex(loop[i]) / static_cast<double>(n);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t a = loop[i], b = loop[(i + 1) % n];
    planeNormal += (m.vertex(a) - centroid).cross(m.vertex(b) - centroid);
    const uint64_t k = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
    const auto it = std::lower_bound(edges.keys.begin(), edges.keys.end(), k);
    if (it == edges.keys.end() || *it != k) return false;
    const uint32_t f = edges.firstHalfedge[static_cast<size_t>(it - edges.keys.begin())] / 3;
    const uint32_t* t = m.triangles.data() + 3 * f;
    normals.push_back((m.vertex(t[1]) - m.vertex(t[0])).cross(m.vertex(t[2]) - m.vertex(t[0])).normalized());
  }
  for (size_t i = 0; i < n; ++i) {
    if (normals[i].dot(normals[(i + 1) % n]) < std::cos(30 * kPi / 180)) return false;
  }
  if (planeNormal.norm() == 0) return false;
  planeNormal.normalize();
  double size = 0, off = 0;
  for (size_t i = 0; i < n; ++i) {
    size = std::max(size, (m.vertex(loop[i]) - centroid).norm());
    off = std::max(off, std::abs((m.vertex(loop[i]) - centroid).dot(planeNormal)));
  }
  return off > 0.01 * size;
}

}  // namespace

SolidRepairResult repairSolid(const Mesh& input, const SolidRepairOptions& options,
                              const ProgressFn& progress) {
  SolidRepairResult result;
  SolidRepairStats& stats = result.stats;
  auto cancelled = [&]() {
    SolidRepairResult r;
    r.status = Status::Cancelled;
    r.message = "cancelled";
    return r;
  };
  if (!reportProgress(progress, kStage, 0)) return cancelled();

  // (0) T-junctions zipped; (1) non-manifold edges and vertices.
  Mesh zipped = input;
  if (options.zipTJunctions) stats.tJunctionsZipped = zipTJunctions(zipped);
  Mesh mesh = splitFans(zipped, stats);
  if (!reportProgress(progress, kStage, 0.3)) return cancelled();

  // (2) Consistent orientation per piece.
  MeshEdges edges = buildEdges(mesh);
  {
    OrientOptions oo;
    oo.outward = false;
    const OrientResult orient = orientMesh(mesh, edges, oo);
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
      if (orient.flip[f]) std::swap(mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2]);
    }
    edges = buildEdges(mesh);
  }
  // Faces hanging into a hole by one edge (two or three boundary edges), as cutting or a scanner
  // leaves on a hole's rim: a triangulation of the hole would run over them again. Dropped, again
  // until none is left, unless that would take more than maxPrunedShare of the faces; a piece
  // that would lose every face (a small sheet, a ribbon) keeps them all, for the sheet and debris
  // rules below.
  {
    const FaceComponents before = edgeComponents(mesh, edges);
    Mesh pruned = mesh;
    std::vector<uint32_t> id(mesh.faceCount());  // original face of each face of pruned
    std::iota(id.begin(), id.end(), 0u);
    for (int pass = 0; pass < 16; ++pass) {
      const MeshEdges pe = buildEdges(pruned);
      size_t kept = 0;
      for (size_t f = 0; f < pruned.faceCount(); ++f) {
        int open = 0;
        for (int k = 0; k < 3; ++k) open += pe.faceCount[pe.edgeOfHalfedge[3 * f + k]] == 1;
        if (open >= 2) continue;
        for (int k = 0; k < 3; ++k) pruned.triangles[3 * kept + k] = pruned.triangles[3 * f + k];
        id[kept++] = id[f];
      }
      if (kept == pruned.faceCount()) break;
      pruned.triangles.resize(3 * kept);
      id.resize(kept);
    }
    std::vector<uint8_t> keep(mesh.faceCount(), 0), pieceKept(before.count, 0);
    for (uint32_t f : id) keep[f] = 1, pieceKept[before.label[f]] = 1;
    for (size_t f = 0; f < mesh.faceCount(); ++f) keep[f] = keep[f] || !pieceKept[before.label[f]];
    const size_t dropped = mesh.faceCount() - static_cast<size_t>(std::count(keep.begin(), keep.end(), 1));
    if (dropped > 0 && dropped <= options.maxPrunedShare * double(mesh.faceCount())) {
      size_t kept = 0;
      for (size_t f = 0; f < mesh.faceCount(); ++f) {
        if (!keep[f]) continue;
        for (int k = 0; k < 3; ++k) mesh.triangles[3 * kept + k] = mesh.triangles[3 * f + k];
        ++kept;
      }
      mesh.triangles.resize(3 * kept);
      edges = buildEdges(mesh);
      stats.facesPruned = dropped;
    }
  }
  if (!reportProgress(progress, kStage, 0.4)) return cancelled();

  // (3) Holes: boundary loops, followed along the hole (opposite to their faces' half-edges).
  const FaceComponents pieces = edgeComponents(mesh, edges);
  std::vector<double> pieceArea(pieces.count, 0), capArea(pieces.count, 0);
  std::vector<double> pieceVolume(pieces.count, 0);  // of the piece closed by its caps
  const BoundingBox whole = boundingBox(mesh);
  const Eigen::Vector3d origin = 0.5 * (whole.min + whole.max);
  auto signedVolume = [&origin](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return (a - origin).dot((b - origin).cross(c - origin)) / 6;
  };
  for (uint32_t f = 0; f < mesh.faceCount(); ++f) {
    const uint32_t* t = mesh.triangles.data() + 3 * f;
    pieceArea[pieces.label[f]] += triangleArea(mesh.vertex(t[0]), mesh.vertex(t[1]), mesh.vertex(t[2]));
    pieceVolume[pieces.label[f]] += signedVolume(mesh.vertex(t[0]), mesh.vertex(t[1]), mesh.vertex(t[2]));
  }
  const double diagonal2 = (whole.max - whole.min).squaredNorm();
  std::vector<uint32_t> holeNext(mesh.vertexCount(), kNoIndex);
  std::vector<uint32_t> holePiece(mesh.vertexCount(), kNoIndex);
  std::vector<uint32_t> starts;
  for (size_t e = 0; e < edges.edgeCount(); ++e) {
    if (edges.faceCount[e] != 1) continue;
    const uint32_t h = edges.firstHalfedge[e];
    const uint32_t a = mesh.triangles[h], b = mesh.triangles[3 * (h / 3) + (h % 3 + 1) % 3];
    if (holeNext[b] == kNoIndex) {
      holeNext[b] = a;
      holePiece[b] = pieces.label[h / 3];
      starts.push_back(b);
    }
  }
  struct Loop {
    std::vector<uint32_t> vertices;
    uint32_t piece;
    std::vector<std::array<uint32_t, 3>> triangles;  // indices into vertices; centroid = size()
    bool fan = false;
    double area = 0;
  };
  std::vector<Loop> loops;
  std::vector<uint8_t> visited(mesh.vertexCount(), 0);
  std::sort(starts.begin(), starts.end());
  for (uint32_t s : starts) {
    if (visited[s]) continue;
    Loop loop;
    loop.piece = holePiece[s];
    uint32_t v = s;
    while (v != kNoIndex && !visited[v]) {
      visited[v] = 1;
      loop.vertices.push_back(v);
      v = holeNext[v];
    }
    if (v != s || loop.vertices.size() < 3) continue;  // not closed: left for prepareMesh to report
    loops.push_back(std::move(loop));
  }
  for (size_t i = 0; i < loops.size(); ++i) {
    Loop& loop = loops[i];
    std::vector<Eigen::Vector3d> points;
    points.reserve(loop.vertices.size());
    for (uint32_t v : loop.vertices) points.push_back(mesh.vertex(v));
    if (points.size() <= options.maxTriangulatedLoop) loop.triangles = triangulateHoleLoop(points);
    // A chord of the triangulation that is already an edge of the mesh would make it
    // non-manifold: cap from the centroid instead (its new edges all end at the new vertex).
    for (const auto& t : loop.triangles) {
      bool clash = false;
      for (int k = 0; k < 3 && !clash; ++k) {
        const uint32_t u = t[k], w = t[(k + 1) % 3];
        const uint32_t gap = w > u ? w - u : u - w;
        if (gap == 1 || gap + 1 == points.size()) continue;  // a side of the loop
        const uint32_t a = loop.vertices[u], b = loop.vertices[w];
        const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
        clash = std::binary_search(edges.keys.begin(), edges.keys.end(), key);
      }
      // A triangle of (almost) no area, over collinear points of the loop as CAD edges have them:
      // validation would drop it and open the hole again.
      clash = clash || triangleArea(points[t[0]], points[t[1]], points[t[2]]) <= kSliverArea * diagonal2;
      if (clash) {
        loop.triangles.clear();
        break;
      }
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : points) centroid += p;
    centroid /= static_cast<double>(points.size());
    if (loop.triangles.empty()) {
      loop.fan = true;
      const uint32_t n = static_cast<uint32_t>(points.size());
      for (uint32_t k = 0; k < n; ++k) loop.triangles.push_back({k, (k + 1) % n, n});
    }
    for (const auto& t : loop.triangles) {
      auto at = [&](uint32_t k) { return k < points.size() ? points[k] : centroid; };
      loop.area += triangleArea(at(t[0]), at(t[1]), at(t[2]));
      pieceVolume[loop.piece] += signedVolume(at(t[0]), at(t[1]), at(t[2]));
    }
    capArea[loop.piece] += loop.area;
    if (!reportProgress(progress, kStage, 0.4 + 0.4 * double(i + 1) / double(loops.size()))) {
      return cancelled();
    }
  }
  // A sheet: its caps would be a large share of its area and the solid they close is flat (its
  // isoperimetric quotient 36 pi V^2 / A^3, 1 for a ball, is small: a cap copies the sheet).
  std::vector<uint8_t> sheet(pieces.count, 0);
  for (size_t p = 0; p < pieces.count; ++p) {
    const double area = capArea[p] + pieceArea[p];
    const double quotient = area > 0 ? 36 * kPi * pieceVolume[p] * pieceVolume[p] / (area * area * area) : 0;
    if (capArea[p] > options.maxCapAreaShare * area && quotient < options.sheetQuotient) {
      sheet[p] = 1;
      ++stats.sheets;
    }
  }
  // Mesh neighbours of rim points (the ring a faired patch continues).
  std::vector<std::vector<uint32_t>> neighbours(mesh.vertexCount());
  if (options.fair) {
    std::vector<uint8_t> onRim(mesh.vertexCount(), 0);
    for (const Loop& loop : loops) {
      for (uint32_t v : loop.vertices) onRim[v] = 1;
    }
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
      const uint32_t* t = mesh.triangles.data() + 3 * f;
      for (int k = 0; k < 3; ++k) {
        if (!onRim[t[k]]) continue;
        for (int j = 1; j < 3; ++j) {
          std::vector<uint32_t>& list = neighbours[t[k]];
          if (std::find(list.begin(), list.end(), t[(k + j) % 3]) == list.end()) list.push_back(t[(k + j) % 3]);
        }
      }
    }
  }
  std::vector<uint32_t> faceLabel = pieces.label;
  const size_t patchStart = mesh.faceCount();  // the filled faces follow the mesh's own
  result.firstFilledFace = patchStart;
  for (const Loop& loop : loops) {
    if (sheet[loop.piece]) {
      ++stats.holesLeft;
      continue;
    }
    ++stats.holesFilled;
    if (loop.fan) ++stats.holesCapped;
    Eigen::Vector3d lo = mesh.vertex(loop.vertices[0]), hi = lo;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (uint32_t v : loop.vertices) {
      lo = lo.cwiseMin(mesh.vertex(v)), hi = hi.cwiseMax(mesh.vertex(v));
      centroid += mesh.vertex(v);
    }
    stats.largestHoleMm = std::max(stats.largestHoleMm, (hi - lo).norm());
    uint32_t centre = kNoIndex;
    if (loop.fan) {
      centroid /= static_cast<double>(loop.vertices.size());
      centre = static_cast<uint32_t>(mesh.vertexCount());
      for (int k = 0; k < 3; ++k) mesh.positions.push_back(centroid[k]);
    }
    if (!loop.fan && options.fair && loop.vertices.size() <= options.maxFairedLoop &&
        smoothAround(mesh, edges, loop.vertices)) {
      // A hole in a smooth surface: refined and bent to continue it (mesh/fair_patch.h).
      HolePatch patch;
      for (uint32_t v : loop.vertices) patch.points.push_back(mesh.vertex(v));
      patch.triangles = loop.triangles;
      std::vector<std::vector<Eigen::Vector3d>> ring;
      for (uint32_t v : loop.vertices) {
        ring.emplace_back();
        for (uint32_t w : neighbours[v]) {
          if (std::find(loop.vertices.begin(), loop.vertices.end(), w) == loop.vertices.end()) {
            ring.back().push_back(mesh.vertex(w));
          }
        }
      }
      patch = refineAndFair(std::move(patch), loop.vertices.size(), ring);
      const uint32_t first = static_cast<uint32_t>(mesh.vertexCount());
      const size_t n = loop.vertices.size();
      for (size_t i = n; i < patch.points.size(); ++i) {
        for (int k = 0; k < 3; ++k) mesh.positions.push_back(patch.points[i][k]);
      }
      double area = 0;
      for (const auto& t : patch.triangles) {
        for (int k = 0; k < 3; ++k) {
          mesh.triangles.push_back(t[k] < n ? loop.vertices[t[k]] : first + static_cast<uint32_t>(t[k] - n));
        }
        area += triangleArea(patch.points[t[0]], patch.points[t[1]], patch.points[t[2]]);
        faceLabel.push_back(loop.piece);
        ++stats.filledFaces;
      }
      if (patch.points.size() > n) ++stats.holesFaired;
      stats.filledAreaMm2 += area;
      continue;
    }
    for (const auto& t : loop.triangles) {
      for (int k = 0; k < 3; ++k) {
        mesh.triangles.push_back(t[k] < loop.vertices.size() ? loop.vertices[t[k]] : centre);
      }
      faceLabel.push_back(loop.piece);
      ++stats.filledFaces;
    }
    stats.filledAreaMm2 += loop.area;
  }
  if (!reportProgress(progress, kStage, 0.85)) return cancelled();

  // (4) Debris: small closed pieces (volume by the divergence theorem about the model's centre).
  {
    const BoundingBox box = boundingBox(mesh);
    const Eigen::Vector3d centre = 0.5 * (box.min + box.max);
    const double diagonal = (box.max - box.min).norm();
    std::vector<double> volume(pieces.count, 0);
    std::vector<Eigen::Vector3d> lo(pieces.count, Eigen::Vector3d::Constant(1e300));
    std::vector<Eigen::Vector3d> hi(pieces.count, Eigen::Vector3d::Constant(-1e300));
    for (uint32_t f = 0; f < mesh.faceCount(); ++f) {
      const uint32_t* t = mesh.triangles.data() + 3 * f;
      const uint32_t p = faceLabel[f];
      const Eigen::Vector3d a = mesh.vertex(t[0]), b = mesh.vertex(t[1]), c = mesh.vertex(t[2]);
      volume[p] += (a - centre).dot((b - centre).cross(c - centre)) / 6;
      lo[p] = lo[p].cwiseMin(a).cwiseMin(b).cwiseMin(c);
      hi[p] = hi[p].cwiseMax(a).cwiseMax(b).cwiseMax(c);
    }
    double largest = 0;
    for (size_t p = 0; p < pieces.count; ++p) {
      if (!sheet[p]) largest = std::max(largest, std::abs(volume[p]));
    }
    const double largestArea = *std::max_element(pieceArea.begin(), pieceArea.end());
    std::vector<uint8_t> holed(pieces.count, 0);
    for (const Loop& loop : loops) holed[loop.piece] = 1;
    constexpr uint8_t kDropDebris = 1, kDropSheet = 2;
    std::vector<uint8_t> drop(pieces.count, 0);
    for (size_t p = 0; p < pieces.count; ++p) {
      // Closed pieces, however small, are the model's (an ogre's teeth); open ones are debris
      // when they are small.
      const bool tiny = holed[p] && (sheet[p] || std::abs(volume[p]) < options.debrisVolumeShare * largest) &&
                        (hi[p] - lo[p]).norm() < options.debrisSizeShare * diagonal;
      // An island of surface left between holes: a sheet of a small share of the largest piece.
      const bool island = sheet[p] && pieceArea[p] < options.debrisAreaShare * largestArea;
      if (pieces.count > 1 && (tiny || island)) {
        drop[p] = kDropDebris;
        ++stats.debrisPieces;
        if (sheet[p]) {  // a small open piece: debris, not a sheet to refuse
          --stats.sheets;
          for (const Loop& loop : loops) stats.holesLeft -= loop.piece == p;
        }
      }
    }
    // Sheets beside solids (single-sided panels of a CAD model): when what is left of the solid
    // pieces has more area than the sheets, the sheets go and the solid prints; otherwise they stay
    // and the mesh is refused.
    double sheetArea = 0, solidArea = 0;
    for (size_t p = 0; p < pieces.count; ++p) {
      if (drop[p]) continue;
      (sheet[p] ? sheetArea : solidArea) += pieceArea[p];
    }
    if (sheetArea > 0 && solidArea > sheetArea) {
      for (size_t p = 0; p < pieces.count; ++p) {
        if (drop[p] || !sheet[p]) continue;
        drop[p] = kDropSheet;
        ++stats.sheetsDropped;
        --stats.sheets;
        stats.sheetAreaDroppedMm2 += pieceArea[p];
        for (const Loop& loop : loops) stats.holesLeft -= loop.piece == p;
      }
    }
    if (stats.debrisPieces > 0 || stats.sheetsDropped > 0) {
      size_t kept = 0;
      for (size_t f = 0; f < mesh.faceCount(); ++f) {
        if (drop[faceLabel[f]]) {
          ++(drop[faceLabel[f]] == kDropSheet ? stats.sheetFacesDropped : stats.debrisFaces);
          if (f < patchStart) --result.firstFilledFace;
          else --stats.filledFaces;  // a cap of a piece dropped as debris
          continue;
        }
        for (int k = 0; k < 3; ++k) mesh.triangles[3 * kept + k] = mesh.triangles[3 * f + k];
        ++kept;
      }
      mesh.triangles.resize(3 * kept);
    }
  }

  if (stats.tJunctionsZipped > 0) {
    result.repairs.push_back("closed cracks at " + plural(stats.tJunctionsZipped, "T-junction", "T-junctions") +
                             " (vertices of one face lying on another's edge: that face split there)");
  }
  if (stats.edgesUnpaired > 0) {
    result.repairs.push_back("split " + plural(stats.edgesUnpaired, "edge", "edges") +
                             " shared by more than two faces into pairs of faces");
  }
  if (stats.facesLeftOver > 0) {
    result.repairs.push_back("dropped " + plural(stats.facesLeftOver, "face", "faces") +
                             " left over at edges of an odd number of faces (fins, inner walls)");
  }
  if (stats.verticesSplit > 0) {
    result.repairs.push_back("split " + plural(stats.verticesSplit, "vertex", "vertices") +
                             " where separate sheets of faces touched");
  }
  if (stats.facesPruned > 0) {
    result.repairs.push_back("dropped " + plural(stats.facesPruned, "face", "faces") +
                             " hanging into holes by one edge");
  }
  if (stats.holesFilled > 0) {
    std::string s = "filled " + plural(stats.holesFilled, "hole", "holes") + " with " +
                    plural(stats.filledFaces, "face", "faces") + " (" + mm(stats.filledAreaMm2) +
                    " mm2; largest " + mm(stats.largestHoleMm) + " mm across";
    if (stats.holesFaired > 0) s += "; " + std::to_string(stats.holesFaired) + " faired to the surface around";
    if (stats.holesCapped > 0) s += "; " + std::to_string(stats.holesCapped) + " capped from their centre";
    result.repairs.push_back(s + ")");
  }
  if (stats.sheetsDropped > 0) {
    result.repairs.push_back("dropped " + plural(stats.sheetsDropped, "open sheet", "open sheets") + " (" +
                             plural(stats.sheetFacesDropped, "face", "faces") + ", " +
                             mm(stats.sheetAreaDroppedMm2) + " mm2) beside the solid: they bound no volume");
  }
  if (stats.debrisPieces > 0) {
    result.repairs.push_back("dropped " + plural(stats.debrisPieces, "tiny piece", "tiny pieces") + " (" +
                             plural(stats.debrisFaces, "face", "faces") + ")");
  }
  result.mesh = std::move(mesh);
  if (!reportProgress(progress, kStage, 1)) return cancelled();
  return result;
}

}  // namespace omnislice
