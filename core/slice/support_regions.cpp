// SPDX-License-Identifier: MIT
#include "slice/support_regions.h"

#include <cmath>
#include <exception>

#include "slice/clipper_adapter.h"

namespace omnislice {

SupportRegionsResult supportRegions(const Mesh& support, const SliceResult& part, const SliceOptions& partOptions,
                                    const std::vector<Plane>& keepBelow, double gapMm) {
  using namespace ClipperLib;
  SupportRegionsResult out;
  out.layers.resize(part.layers.size());
  if (support.empty() || part.layers.empty()) return out;
  if (!std::isfinite(gapMm) || gapMm < 0) {
    out.status = Status::InvalidOption;
    out.message = "support gap must be >= 0 mm";
    return out;
  }
  SliceOptions so = partOptions;
  so.baseHeight = part.minHeight;
  so.maxLayers = part.layers.size();
  so.closingRadius = 0;
  SliceResult sup = sliceMesh(support, so);
  if (!sup.ok()) {
    out.status = sup.status;
    out.message = "supports: " + sup.message;
    return out;
  }
  const SliceFrame& f = part.frame;
  try {
    for (size_t i = 0; i < sup.layers.size() && i < part.layers.size(); ++i) {
      if (sup.layers[i].islands.empty()) continue;
      Paths region = clip::toPaths(sup.layers[i].islands);
      // The layer plane's share of each kept half-space, as a big clipped square.
      const double z = part.minHeight + part.layers[i].sliceHeight;
      double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
      for (const Path& p : region) {
        for (const IntPoint& q : p) {
          const Eigen::Vector2d v = clip::toVec(q);
          for (int k = 0; k < 2; ++k) {
            lo[k] = std::min(lo[k], v[k]);
            hi[k] = std::max(hi[k], v[k]);
          }
        }
      }
      std::vector<Eigen::Vector2d> poly = {{lo[0] - 1, lo[1] - 1}, {hi[0] + 1, lo[1] - 1}, {hi[0] + 1, hi[1] + 1},
                                           {lo[0] - 1, hi[1] + 1}};
      for (const Plane& pl : keepBelow) {
        // n . (x e1 + y e2 + z d) <= offset  <=>  a x + b y <= c
        const double a = pl.normal.dot(f.e1), b = pl.normal.dot(f.e2);
        const double c = pl.offset - z * pl.normal.dot(f.d) - pl.normal.dot(f.origin);
        std::vector<Eigen::Vector2d> next;
        for (size_t k = 0; k < poly.size(); ++k) {
          const Eigen::Vector2d& p = poly[k];
          const Eigen::Vector2d& q = poly[(k + 1) % poly.size()];
          const double sp = a * p.x() + b * p.y() - c, sq = a * q.x() + b * q.y() - c;
          if (sp <= 0) next.push_back(p);
          if ((sp < 0 && sq > 0) || (sp > 0 && sq < 0)) next.push_back(p + (sp / (sp - sq)) * (q - p));
        }
        poly.swap(next);
        if (poly.size() < 3) break;
      }
      if (poly.size() < 3) continue;
      Path keep;
      for (const Eigen::Vector2d& p : poly) keep.push_back(clip::toPoint(p));
      if (!Orientation(keep)) ReversePath(keep);
      // Inside the subspace, minus the part grown by the gap (islands need the tree).
      Clipper d;
      d.AddPaths(clip::intersect(region, {keep}), ptSubject, true);
      d.AddPaths(clip::offset(clip::toPaths(part.layers[i].islands), gapMm), ptClip, true);
      PolyTree tree;
      d.Execute(ctDifference, tree, pftNonZero, pftNonZero);
      out.layers[i] = clip::toIslands(tree);
      double area = 0;
      for (const ExPolygon2& ex : out.layers[i]) area += islandArea(ex);
      out.volumeMm3 += area * (part.layers[i].top - part.layers[i].bottom);
    }
  } catch (const std::exception& e) {
    out.status = Status::Internal;
    out.message = std::string("support clipping failed: ") + e.what();
  }
  return out;
}

}  // namespace omnislice
