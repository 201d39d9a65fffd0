// SPDX-License-Identifier: MIT
// The closed solid under an open height-field surface (see height_field_solid.h).
//
// Height-field test: with every triangle facing up the projection to the platform is a local
// homeomorphism away from the boundary; its covering number at a point off the projected boundary
// is the sum of the winding numbers of the projected boundary loops. When the loops are simple
// and pairwise disjoint and the covering number just left of every loop (the surface's side) is
// exactly 1, every region of the plane is covered 0 or 1 times: the projection is injective.
#include "surface/height_field_solid.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

namespace omnislice {
namespace {

HeightFieldSolid fail(Status status, std::string message) { return failed<HeightFieldSolid>(status, std::move(message)); }

uint64_t edgeKey(uint32_t a, uint32_t b) { return (static_cast<uint64_t>(a) << 32) | b; }

struct Seg {
  Eigen::Vector2d a, b;
  size_t loop = 0, index = 0;
};

double orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// Closed segments intersect (touching counts).
bool segmentsIntersect(const Seg& p, const Seg& q) {
  const double d1 = orient(p.a, p.b, q.a), d2 = orient(p.a, p.b, q.b);
  const double d3 = orient(q.a, q.b, p.a), d4 = orient(q.a, q.b, p.b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  auto onSeg = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    return std::min(a.x(), b.x()) <= c.x() && c.x() <= std::max(a.x(), b.x()) &&
           std::min(a.y(), b.y()) <= c.y() && c.y() <= std::max(a.y(), b.y());
  };
  return (d1 == 0 && onSeg(p.a, p.b, q.a)) || (d2 == 0 && onSeg(p.a, p.b, q.b)) ||
         (d3 == 0 && onSeg(q.a, q.b, p.a)) || (d4 == 0 && onSeg(q.a, q.b, p.b));
}

// Winding number of a closed polygon around p.
int winding(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  int w = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[(i + 1) % poly.size()];
    if (a.y() <= p.y()) {
      if (b.y() > p.y() && orient(a, b, p) > 0) ++w;
    } else if (b.y() <= p.y() && orient(a, b, p) < 0) {
      --w;
    }
  }
  return w;
}

struct HeightFieldCheck {
  Status status = Status::Ok;
  std::string message;
};

// Face normals up, loops simple/disjoint, covering number 1 on the surface's side of each loop.
HeightFieldCheck checkHeightField(const std::vector<Eigen::Vector3d>& v,
                                  const std::vector<uint32_t>& tris,
                                  const std::vector<std::vector<uint32_t>>& loops, double minNormalZ,
                                  const char* what) {
  HeightFieldCheck c;
  size_t down = 0;
  for (size_t f = 0; f < tris.size() / 3; ++f) {
    const Eigen::Vector3d n =
        (v[tris[3 * f + 1]] - v[tris[3 * f]]).cross(v[tris[3 * f + 2]] - v[tris[3 * f]]);
    const double len = n.norm();
    if (!(len > 0) || n.z() <= minNormalZ * len) ++down;
  }
  if (down > 0) {
    c.status = Status::DegenerateInput;
    c.message = std::string(what) + " is not a height field: " + std::to_string(down) +
                " triangles do not face up (normal z <= " + std::to_string(minNormalZ) +
                "): it folds over itself seen from above or is too steep";
    return c;
  }
  std::vector<std::vector<Eigen::Vector2d>> polys(loops.size());
  std::vector<Seg> segs;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (size_t l = 0; l < loops.size(); ++l) {
    for (uint32_t i : loops[l]) polys[l].emplace_back(v[i].x(), v[i].y());
    for (size_t i = 0; i < polys[l].size(); ++i) {
      Seg s{polys[l][i], polys[l][(i + 1) % polys[l].size()], l, i};
      lo = lo.cwiseMin(s.a);
      hi = hi.cwiseMax(s.a);
      segs.push_back(s);
    }
  }
  // Uniform grid over the boundary segments; test pairs sharing a cell.
  const size_t n = segs.size();
  const int g = std::max(1, std::min(2048, static_cast<int>(std::sqrt(static_cast<double>(n)))));
  const Eigen::Vector2d ext = (hi - lo).cwiseMax(Eigen::Vector2d(1e-12, 1e-12));
  auto cellOf = [&](double x, double y, int& i, int& j) {
    i = std::min(g - 1, std::max(0, static_cast<int>((x - lo.x()) / ext.x() * g)));
    j = std::min(g - 1, std::max(0, static_cast<int>((y - lo.y()) / ext.y() * g)));
  };
  std::vector<std::vector<uint32_t>> grid(static_cast<size_t>(g) * g);
  for (size_t k = 0; k < n; ++k) {
    int i0, j0, i1, j1;
    cellOf(std::min(segs[k].a.x(), segs[k].b.x()), std::min(segs[k].a.y(), segs[k].b.y()), i0, j0);
    cellOf(std::max(segs[k].a.x(), segs[k].b.x()), std::max(segs[k].a.y(), segs[k].b.y()), i1, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) grid[static_cast<size_t>(j) * g + i].push_back(k);
  }
  for (const auto& cell : grid)
    for (size_t x = 0; x < cell.size(); ++x)
      for (size_t y = x + 1; y < cell.size(); ++y) {
        const Seg& p = segs[cell[x]];
        const Seg& q = segs[cell[y]];
        if (p.loop == q.loop) {
          const size_t m = polys[p.loop].size();
          if (p.index == q.index) continue;
          const bool adjacent = (p.index + 1) % m == q.index || (q.index + 1) % m == p.index;
          if (adjacent) {
            // Adjacent edges share one end; they overlap only when folding back collinearly.
            const Eigen::Vector2d& shared = (p.index + 1) % m == q.index ? p.b : p.a;
            const Eigen::Vector2d& pOther = shared == p.b ? p.a : p.b;
            const Eigen::Vector2d& qOther = shared == q.a ? q.b : q.a;
            const Eigen::Vector2d u = pOther - shared, w = qOther - shared;
            if (m > 2 && !(std::fabs(u.x() * w.y() - u.y() * w.x()) == 0 && u.dot(w) > 0))
              continue;
          }
        }
        if (segmentsIntersect(p, q)) {
          c.status = Status::DegenerateInput;
          c.message = std::string(what) +
                      " is not a height field: its boundary seen from above crosses itself";
          return c;
        }
      }
  // Covering number on the surface's side (left) of each loop's first usable edge.
  for (size_t l = 0; l < polys.size(); ++l) {
    const auto& poly = polys[l];
    size_t e = 0;
    double best = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
      const double len = (poly[(i + 1) % poly.size()] - poly[i]).norm();
      if (len > best) best = len, e = i;
    }
    const Eigen::Vector2d a = poly[e], b = poly[(e + 1) % poly.size()];
    const Eigen::Vector2d d = (b - a) / best;
    // Step inside by a small fraction of the edge, less than the distance to any other segment.
    double step = 1e-3 * best;
    const Eigen::Vector2d mid = (a + b) / 2;
    for (const Seg& s : segs) {
      if (s.loop == l && s.index == e) continue;
      const Eigen::Vector2d ab = s.b - s.a;
      const double t = std::clamp((mid - s.a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0,
                                  1.0);
      step = std::min(step, 0.5 * (s.a + t * ab - mid).norm());
    }
    const Eigen::Vector2d p = mid + step * Eigen::Vector2d(-d.y(), d.x());
    int total = 0;
    for (const auto& other : polys) total += winding(other, p);
    if (total != 1) {
      c.status = Status::DegenerateInput;
      c.message = std::string(what) + " is not a height field: it covers part of the platform " +
                  std::to_string(total) + " times seen from above (overlapping sheets)";
      return c;
    }
  }
  return c;
}

}  // namespace

HeightFieldSolid heightFieldSolid(const Mesh& surface, double offset, double minNormalZ) {
  if (!std::isfinite(offset) || offset < 0)
    return fail(Status::InvalidOption, "offset must be a finite number >= 0 mm");
  if (!std::isfinite(minNormalZ) || minNormalZ < 0 || minNormalZ >= 1)
    return fail(Status::InvalidOption, "minNormalZ must be in [0, 1)");
  if (surface.empty() || surface.vertexCount() == 0)
    return fail(Status::EmptyInput, "the surface has no triangles");
  const size_t nv = surface.vertexCount(), nf = surface.faceCount();
  for (double c : surface.positions)
    if (!std::isfinite(c)) return fail(Status::NonFiniteVertex, "the surface has a non-finite vertex");
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &surface.triangles[3 * f];
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv)
      return fail(Status::DegenerateInput, "triangle " + std::to_string(f) +
                                               " refers to a vertex that does not exist");
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      return fail(Status::DegenerateInput,
                  "triangle " + std::to_string(f) + " repeats a vertex");
  }
  // Directed edges: each must occur once; an undirected edge at most twice, opposite ways.
  std::unordered_map<uint64_t, uint32_t> directed;
  directed.reserve(3 * nf);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = surface.triangles[3 * f + k], b = surface.triangles[3 * f + (k + 1) % 3];
      if (!directed.emplace(edgeKey(a, b), static_cast<uint32_t>(f)).second) {
        const bool third = directed.count(edgeKey(b, a)) > 0;
        return fail(Status::NonManifoldInput,
                    third ? "edge " + std::to_string(a) + "-" + std::to_string(b) +
                                " is shared by more than two triangles"
                          : "the surface is not consistently oriented (edge " +
                                std::to_string(a) + "-" + std::to_string(b) +
                                " runs the same way in two triangles)");
      }
    }
  // Boundary edges (no opposite): next boundary vertex of each boundary vertex.
  std::vector<int64_t> next(nv, -1);
  size_t boundaryEdges = 0;
  for (const auto& [key, f] : directed) {
    const uint32_t a = static_cast<uint32_t>(key >> 32), b = static_cast<uint32_t>(key);
    if (directed.count(edgeKey(b, a))) continue;
    ++boundaryEdges;
    if (next[a] >= 0)
      return fail(Status::NonManifoldInput, "boundary loops touch at vertex " + std::to_string(a) +
                                                " (the surface is pinched there)");
    next[a] = b;
  }
  if (boundaryEdges == 0)
    return fail(Status::DegenerateInput,
                "the surface is closed (no boundary): a height field surface must be open");
  std::vector<std::vector<uint32_t>> loops;
  std::vector<char> used(nv, 0);
  for (size_t v = 0; v < nv; ++v) {
    if (next[v] < 0 || used[v]) continue;
    std::vector<uint32_t> loop;
    int64_t c = static_cast<int64_t>(v);
    while (c >= 0 && !used[c]) {
      used[c] = 1;
      loop.push_back(static_cast<uint32_t>(c));
      c = next[c];
    }
    if (c != static_cast<int64_t>(v))
      return fail(Status::NonManifoldInput, "a boundary loop does not close");
    loops.push_back(std::move(loop));
  }
  // Orientation: flip everything when most of the area faces down.
  std::vector<uint32_t> tris = surface.triangles;
  std::vector<Eigen::Vector3d> v(nv);
  for (size_t i = 0; i < nv; ++i) v[i] = surface.vertex(i);
  double up = 0, down = 0;
  for (size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d n = (v[tris[3 * f + 1]] - v[tris[3 * f]]).cross(v[tris[3 * f + 2]] - v[tris[3 * f]]);
    (n.z() >= 0 ? up : down) += n.norm();
  }
  if (down > up) {
    for (size_t f = 0; f < nf; ++f) std::swap(tris[3 * f + 1], tris[3 * f + 2]);
    for (auto& loop : loops) std::reverse(loop.begin(), loop.end());
  }
  HeightFieldCheck check = checkHeightField(v, tris, loops, minNormalZ, "the surface");
  if (check.status != Status::Ok) return fail(check.status, check.message);
  if (offset > 0) {
    std::vector<Eigen::Vector3d> normals(nv, Eigen::Vector3d::Zero());
    for (size_t f = 0; f < nf; ++f) {
      const Eigen::Vector3d n =
          (v[tris[3 * f + 1]] - v[tris[3 * f]]).cross(v[tris[3 * f + 2]] - v[tris[3 * f]]);
      for (int k = 0; k < 3; ++k) normals[tris[3 * f + k]] += n;
    }
    for (size_t i = 0; i < nv; ++i)
      if (normals[i].norm() > 0) v[i] -= offset * normals[i].normalized();
    check = checkHeightField(v, tris, loops, minNormalZ, "the offset surface");
    if (check.status != Status::Ok) return fail(check.status, check.message);
  }
  HeightFieldSolid r;
  r.minTopZ = std::numeric_limits<double>::infinity();
  for (uint32_t i : tris) r.minTopZ = std::min(r.minTopZ, v[i].z());
  if (!(r.minTopZ > 0))
    return fail(Status::DegenerateInput,
                std::string(offset > 0 ? "the offset surface" : "the surface") +
                    " reaches down to z = " + std::to_string(r.minTopZ) +
                    " mm: every vertex must lie above the platform (z > 0)");
  // Only vertices used by triangles go into the solid (isolated ones would be unreferenced).
  std::vector<char> usedVertex(nv, 0);
  for (uint32_t i : tris) usedVertex[i] = 1;
  std::vector<int64_t> remap(nv, -1);  // keeps the order (identity when every vertex is used)
  uint32_t count = 0;
  for (size_t i = 0; i < nv; ++i)
    if (usedVertex[i]) remap[i] = count++;
  r.top.positions.resize(3 * static_cast<size_t>(count));
  for (size_t i = 0; i < nv; ++i)
    if (remap[i] >= 0)
      for (int k = 0; k < 3; ++k) r.top.positions[3 * remap[i] + k] = v[i][k];
  r.top.triangles.reserve(tris.size());
  for (uint32_t i : tris) r.top.triangles.push_back(static_cast<uint32_t>(remap[i]));
  // Solid: top vertices 0..count-1, their projections count..2count-1.
  Mesh& s = r.solid;
  s.positions = r.top.positions;
  s.positions.reserve(6 * static_cast<size_t>(count));
  for (uint32_t i = 0; i < count; ++i)
    s.positions.insert(s.positions.end(), {r.top.positions[3 * i], r.top.positions[3 * i + 1], 0.0});
  s.triangles = r.top.triangles;
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &r.top.triangles[3 * f];
    s.triangles.insert(s.triangles.end(), {t[0] + count, t[2] + count, t[1] + count});
  }
  for (const auto& loop : loops)
    for (size_t i = 0; i < loop.size(); ++i) {
      // The surface lies left of a -> b seen from above; the wall faces right (outward).
      const uint32_t a = static_cast<uint32_t>(remap[loop[i]]);
      const uint32_t b = static_cast<uint32_t>(remap[loop[(i + 1) % loop.size()]]);
      s.triangles.insert(s.triangles.end(), {a, a + count, b + count, a, b + count, b});
    }
  return r;
}

}  // namespace omnislice
