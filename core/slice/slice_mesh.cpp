// SPDX-License-Identifier: MIT
// Planar slicing along an arbitrary direction.
//
// Robustness: a vertex whose height equals the cutting plane counts as ABOVE it (symbolic
// perturbation of the plane downwards by an infinitesimal). Then every triangle either misses the
// plane or crosses it in exactly two edges, a face lying in the plane is "above" and produces no
// segment, and each crossed mesh edge yields one point computed from that edge alone (interpolated
// from its lower-index vertex), so the two triangles sharing the edge agree bit for bit. Segments are
// chained by the undirected edge key, which closes every loop of a closed, welded mesh exactly.
//
// Layer count: layer 0 spans [0, first], layer i >= 1 spans [first + (i-1) h, first + i h] above
// minHeight. A layer is kept only when its cutting plane (mid-layer) lies strictly below the part's
// top (max height): the part fills at most half of a layer whose plane is at or above the top. So
// the printed height (top of the last layer) is within h/2 of the part's height: at most h/2 short
// (the part ends in the lower half of a layer that is dropped) or less than h/2 above it.
// Because on-plane vertices count as above, a plane through a horizontal face gives the section
// just below that face (the limit from below).
#include "slice/slice_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "slice/clipper_adapter.h"

namespace omnislice {

// Loops of one layer above which the union goes through plain paths before the island tree.
constexpr size_t kDirectTreeLoops = 64;

SliceFrame makeSliceFrame(const Eigen::Vector3d& direction) {
  SliceFrame frame;
  const double n = direction.norm();
  if (!(n > 0) || !std::isfinite(n)) return frame;
  const Eigen::Vector3d d = direction / n;
  // The axis among X, Y least aligned with d, projected onto the plane normal to d.
  const Eigen::Vector3d a =
      std::abs(d.x()) <= std::abs(d.y()) ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Eigen::Vector3d e1 = a - a.dot(d) * d;
  if (e1.norm() < 1e-9) e1 = Eigen::Vector3d::UnitZ() - d.z() * d;  // unreachable for |d| = 1
  e1.normalize();
  frame.d = d;
  frame.e1 = e1;
  frame.e2 = d.cross(e1).normalized();
  frame.origin = Eigen::Vector3d::Zero();
  return frame;
}

double polygonArea(const Polygon2& polygon) {
  const size_t n = polygon.size();
  if (n < 3) return 0;
  double twice = 0;
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    twice += (polygon[j].x() - polygon[i].x()) * (polygon[j].y() + polygon[i].y());
  }
  return 0.5 * twice;
}

double islandArea(const ExPolygon2& island) {
  double a = std::abs(polygonArea(island.contour));
  for (const Polygon2& hole : island.holes) a -= std::abs(polygonArea(hole));
  return a;
}

namespace {

struct Segment {
  uint64_t startKey;  // mesh edge (lo << 32 | hi) where the segment starts
  uint64_t endKey;    // mesh edge where it ends (= start edge of the next segment of the loop)
  Eigen::Vector2d start;
};

inline uint64_t edgeKey(uint32_t a, uint32_t b) {
  const uint32_t lo = std::min(a, b), hi = std::max(a, b);
  return (static_cast<uint64_t>(lo) << 32) | hi;
}

SliceResult fail(Status s, std::string message) { return failed<SliceResult>(s, std::move(message)); }

}  // namespace

SliceResult sliceMesh(const Mesh& mesh, const SliceOptions& options, const ProgressFn& progress) {
  using namespace ClipperLib;
  if (mesh.empty() || mesh.vertexCount() == 0) return fail(Status::EmptyInput, "mesh has no triangles");
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0) {
    return fail(Status::InvalidOption, "mesh arrays are not multiples of 3");
  }
  const Eigen::Vector3d& dir = options.direction;
  if (!dir.allFinite() || dir.norm() < 1e-12) {
    return fail(Status::InvalidOption, "slice direction must be finite and non-zero");
  }
  if (!std::isfinite(options.layerHeight) || options.layerHeight <= 0) {
    return fail(Status::InvalidOption, "layer height must be > 0 mm");
  }
  if (!std::isfinite(options.firstLayerHeight) || options.firstLayerHeight < 0) {
    return fail(Status::InvalidOption, "first layer height must be >= 0 mm (0 = layer height)");
  }
  if (!std::isfinite(options.closingRadius) || options.closingRadius < 0) {
    return fail(Status::InvalidOption, "closing radius must be >= 0 mm");
  }
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  for (uint32_t idx : mesh.triangles) {
    if (idx >= nv) return fail(Status::InvalidOption, "triangle index out of range");
  }

  SliceResult result;
  result.frame = makeSliceFrame(dir);
  const SliceFrame& frame = result.frame;
  std::vector<double> height(nv);
  std::vector<Eigen::Vector2d> xy(nv);
  std::vector<char> used(nv, 0);
  for (uint32_t idx : mesh.triangles) used[idx] = 1;
  double minH = std::numeric_limits<double>::infinity(), maxH = -minH;
  for (size_t v = 0; v < nv; ++v) {
    const Eigen::Vector3d p = mesh.vertex(v);
    if (!p.allFinite()) {
      if (used[v]) return fail(Status::NonFiniteVertex, "vertex " + std::to_string(v) + " is not finite");
      continue;
    }
    if (p.cwiseAbs().maxCoeff() > clip::kMaxCoordinateMm) {
      return fail(Status::InvalidOption, "coordinates beyond 1e6 mm cannot be sliced");
    }
    const Eigen::Vector3d q = p - frame.origin;
    height[v] = q.dot(frame.d);
    xy[v] = Eigen::Vector2d(q.dot(frame.e1), q.dot(frame.e2));
    if (used[v]) {
      minH = std::min(minH, height[v]);
      maxH = std::max(maxH, height[v]);
    }
  }
  if (!std::isnan(options.baseHeight)) {
    if (!std::isfinite(options.baseHeight)) return fail(Status::InvalidOption, "base height must be finite");
    if (!(maxH > options.baseHeight)) {
      result.minHeight = options.baseHeight;
      return result;  // nothing above the base: no layers
    }
    minH = options.baseHeight;
  }
  result.minHeight = minH;
  const double total = maxH - minH;
  if (!(total > 0)) return fail(Status::EmptyInput, "mesh has zero extent along the slice direction");

  const double h = options.layerHeight;
  const double first = options.firstLayerHeight > 0 ? options.firstLayerHeight : h;
  auto bottomOf = [&](size_t i) { return i == 0 ? 0.0 : first + static_cast<double>(i - 1) * h; };
  auto topOf = [&](size_t i) { return i == 0 ? first : first + static_cast<double>(i) * h; };
  auto midOf = [&](size_t i) { return 0.5 * (bottomOf(i) + topOf(i)); };
  const double estimate = std::ceil(std::max(0.0, total - first) / h) + 1;
  if (estimate > 2e6) return fail(Status::InvalidOption, "too many layers (over 2 million)");
  size_t layerCount = static_cast<size_t>(estimate) + 1;
  while (layerCount > 1 && !(minH + midOf(layerCount - 1) < maxH)) --layerCount;
  if (options.maxLayers > 0) layerCount = std::min(layerCount, options.maxLayers);
  std::vector<double> planes(layerCount);
  result.layers.resize(layerCount);
  for (size_t i = 0; i < layerCount; ++i) {
    SliceLayer& layer = result.layers[i];
    layer.bottom = bottomOf(i);
    layer.top = topOf(i);
    layer.sliceHeight = midOf(i);
    // A part thinner than half the first layer: cut its only layer at half the part's height.
    if (i == 0 && !(minH + midOf(0) < maxH)) layer.sliceHeight = 0.5 * total;
    planes[i] = minH + layer.sliceHeight;
  }

  // Pass 1: count the segments of each layer; pass 2: fill them (one allocation per layer).
  auto layerRange = [&](size_t f, size_t& lo, size_t& hi) {
    const uint32_t* t = &mesh.triangles[3 * f];
    const double h0 = height[t[0]], h1 = height[t[1]], h2 = height[t[2]];
    const double hmin = std::min({h0, h1, h2}), hmax = std::max({h0, h1, h2});
    // Planes p with hmin < p <= hmax cut the triangle (a vertex at p counts as above).
    lo = std::upper_bound(planes.begin(), planes.end(), hmin) - planes.begin();
    hi = std::upper_bound(planes.begin(), planes.end(), hmax) - planes.begin();
  };
  std::vector<size_t> counts(layerCount, 0);
  for (size_t f = 0; f < nf; ++f) {
    size_t lo, hi;
    layerRange(f, lo, hi);
    for (size_t i = lo; i < hi; ++i) ++counts[i];
  }
  std::vector<std::vector<Segment>> segments(layerCount);
  for (size_t i = 0; i < layerCount; ++i) segments[i].reserve(counts[i]);
  auto edgePoint = [&](uint32_t a, uint32_t b, double plane) {
    const uint32_t lo = std::min(a, b), hi = std::max(a, b);
    const double t = (plane - height[lo]) / (height[hi] - height[lo]);
    return Eigen::Vector2d(xy[lo] + t * (xy[hi] - xy[lo]));
  };
  for (size_t f = 0; f < nf; ++f) {
    if ((f & 0xFFFF) == 0 && !reportProgress(progress, "slice", 0.3 * f / nf)) {
      return fail(Status::Cancelled, "cancelled");
    }
    size_t lo, hi;
    layerRange(f, lo, hi);
    const uint32_t* t = &mesh.triangles[3 * f];
    for (size_t i = lo; i < hi; ++i) {
      const double p = planes[i];
      const bool above[3] = {height[t[0]] >= p, height[t[1]] >= p, height[t[2]] >= p};
      // The segment runs from the edge crossed downwards to the edge crossed upwards (in the
      // triangle's CCW order): with an outward mesh the solid is then on its left seen from +d.
      int down = -1, up = -1;
      for (int e = 0; e < 3; ++e) {
        const int n = (e + 1) % 3;
        if (above[e] && !above[n]) down = e;
        if (!above[e] && above[n]) up = e;
      }
      if (down < 0 || up < 0) continue;  // cannot happen: hmin < p <= hmax
      Segment s;
      s.startKey = edgeKey(t[down], t[(down + 1) % 3]);
      s.endKey = edgeKey(t[up], t[(up + 1) % 3]);
      s.start = edgePoint(t[down], t[(down + 1) % 3], p);
      segments[i].push_back(s);
    }
  }

  // Per layer: chain segments into loops, unite loops (non-zero), build islands.
  const double cleanUnits = 1e-3 * clip::kClipperScale;  // 1 micron
  try {
    for (size_t i = 0; i < layerCount; ++i) {
      if ((i & 7) == 0 && !reportProgress(progress, "slice", 0.3 + 0.7 * i / layerCount)) {
        return fail(Status::Cancelled, "cancelled");
      }
      std::vector<Segment>& segs = segments[i];
      std::sort(segs.begin(), segs.end(),
                [](const Segment& a, const Segment& b) { return a.startKey < b.startKey; });
      std::vector<char> taken(segs.size(), 0);
      auto findNext = [&](uint64_t key) -> long {
        auto it = std::lower_bound(segs.begin(), segs.end(), key,
                                   [](const Segment& s, uint64_t k) { return s.startKey < k; });
        for (; it != segs.end() && it->startKey == key; ++it) {
          const size_t j = it - segs.begin();
          if (!taken[j]) return static_cast<long>(j);
        }
        return -1;
      };
      Paths loops;
      for (size_t s0 = 0; s0 < segs.size(); ++s0) {
        if (taken[s0]) continue;
        Path loop;
        size_t s = s0;
        bool closed = false;
        for (;;) {
          taken[s] = 1;
          loop.push_back(clip::toPoint(segs[s].start));
          if (segs[s].endKey == segs[s0].startKey) {
            closed = true;
            break;
          }
          const long next = findNext(segs[s].endKey);
          if (next < 0) break;
          s = static_cast<size_t>(next);
        }
        if (!closed) {
          ++result.openChains;
          continue;
        }
        if (loop.size() >= 3) loops.push_back(std::move(loop));
      }
      segs.clear();
      segs.shrink_to_fit();
      CleanPolygons(loops, cleanUnits);
      if (loops.empty()) continue;
      PolyTree tree;
      Clipper c;
      c.AddPaths(loops, ptSubject, true);
      if (options.closingRadius > 0) {
        Paths united;
        c.Execute(ctUnion, united, pftNonZero, pftNonZero);
        ClipperOffset grow(2.0, 0.005 * clip::kClipperScale);
        grow.AddPaths(united, jtRound, etClosedPolygon);
        Paths grown;
        grow.Execute(grown, options.closingRadius * clip::kClipperScale);
        ClipperOffset shrink(2.0, 0.005 * clip::kClipperScale);
        shrink.AddPaths(grown, jtRound, etClosedPolygon);
        shrink.Execute(tree, -options.closingRadius * clip::kClipperScale);
      } else if (loops.size() > kDirectTreeLoops) {
        // Many overlapping loops (a support soup of struts and roofs): Clipper's PolyTree union
        // fixes up its hierarchy at every joined edge against every output polygon (quadratic:
        // 55 % of a multidir slice of the 70k-face bunny). Union to plain paths first, then
        // build the tree from the disjoint result.
        Paths united;
        c.Execute(ctUnion, united, pftNonZero, pftNonZero);
        Clipper t;
        t.AddPaths(united, ptSubject, true);
        t.Execute(ctUnion, tree, pftNonZero, pftNonZero);
      } else {
        c.Execute(ctUnion, tree, pftNonZero, pftNonZero);
      }
      result.layers[i].islands = clip::toIslands(tree);
    }
  } catch (const std::exception& e) {
    return fail(Status::Internal, std::string("polygon clipping failed: ") + e.what());
  }
  if (!reportProgress(progress, "slice", 1.0)) return fail(Status::Cancelled, "cancelled");
  return result;
}

}  // namespace omnislice
