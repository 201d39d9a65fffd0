// SPDX-License-Identifier: MIT
// The printing-time estimate of iso-planar paths (estimateIsoplanarTime, isoplanar_paths.h): each
// curve and join timed at the feed rate its points allow, with the geodesic curvature of the
// polyline, plus the travels between paths.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "isoplanar/isoplanar_paths.h"

namespace omnislice {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct PolylineTime {
  double seconds = 0, length = 0;
  size_t unreachable = 0;
};

PolylineTime timePolyline(const std::vector<Eigen::Vector3d>& p, const std::vector<Eigen::Vector3d>& n,
                          const std::vector<uint32_t>& ea, const std::vector<uint32_t>& eb,
                          const std::vector<float>& et, const FeedFn& feed, double maxFeed,
                          double minFeed) {
  PolylineTime out;
  const size_t m = p.size();
  if (m < 2) return out;
  std::vector<double> kg(m, 0.0);
  for (size_t i = 1; i + 1 < m; ++i) {
    const Eigen::Vector3d d0 = p[i] - p[i - 1], d1 = p[i + 1] - p[i];
    const double l0 = d0.norm(), l1 = d1.norm();
    if (l0 <= 0 || l1 <= 0) continue;
    const Eigen::Vector3d kvec = 2 * (d1 / l1 - d0 / l0) / (l0 + l1);
    Eigen::Vector3d tan = d0 / l0 + d1 / l1;
    if (tan.norm() < 1e-12) continue;
    tan.normalize();
    kg[i] = kvec.dot(n[i].cross(tan));
  }
  for (size_t i = 0; i + 1 < m; ++i) {
    const Eigen::Vector3d d = p[i + 1] - p[i];
    const double len = d.norm();
    if (len <= 0) continue;
    const Eigen::Vector3d dir = d / len;
    double f = kInf;
    bool bad = false;
    for (size_t j : {i, i + 1}) {
      const double fj = feed ? feed(ea[j], eb[j], et[j], dir, kg[j]) : kInf;
      if (std::isnan(fj) || fj <= 0) bad = true;
      f = std::min(f, fj);
    }
    if (maxFeed > 0 && std::isfinite(maxFeed)) f = std::min(f, maxFeed);
    if (bad || !std::isfinite(f)) {
      f = minFeed;
      ++out.unreachable;
    }
    out.seconds += len / f;
    out.length += len;
  }
  return out;
}

}  // namespace

IsoplanarTime estimateIsoplanarTime(const IsoplanarResult& paths, const FeedFn& feed,
                                    double maxFeed, double travelSpeed, double minFeed) {
  IsoplanarTime t;
  if (!(minFeed > 0) || !std::isfinite(minFeed)) minFeed = 1;
  for (size_t p = 0; p < paths.pathCurves.size(); ++p) {
    const std::vector<uint32_t>& cs = paths.pathCurves[p];
    for (size_t j = 0; j < cs.size(); ++j) {
      if (cs[j] >= paths.curves.size()) continue;
      const NlCurve& c = paths.curves[cs[j]];
      const PolylineTime pt =
          timePolyline(c.points, c.normals, c.edgeA, c.edgeB, c.edgeT, feed, maxFeed, minFeed);
      t.printS += pt.seconds;
      t.pathMm += pt.length;
      t.unreachableSegments += pt.unreachable;
      if (j > 0 && p < paths.pathJoins.size() && j - 1 < paths.pathJoins[p].size()) {
        const uint32_t ji = paths.pathJoins[p][j - 1];
        if (ji < paths.joins.size()) {
          const IsoplanarJoin& jn = paths.joins[ji];
          const PolylineTime jt = timePolyline(jn.points, jn.normals, jn.edgeA, jn.edgeB, jn.edgeT,
                                               feed, maxFeed, minFeed);
          t.joinS += jt.seconds;
          t.pathMm += jt.length;
          t.unreachableSegments += jt.unreachable;
        }
      }
    }
    if (p > 0 && p < paths.paths.size() && !paths.paths[p].points.empty() &&
        !paths.paths[p - 1].points.empty()) {
      const double d = (paths.paths[p].points.front() - paths.paths[p - 1].points.back()).norm();
      t.travelMm += d;
      if (travelSpeed > 0 && std::isfinite(travelSpeed)) t.travelS += d / travelSpeed;
    }
  }
  t.totalS = t.printS + t.joinS + t.travelS;
  t.meanFeed = t.printS + t.joinS > 0 ? t.pathMm / (t.printS + t.joinS) : 0;
  return t;
}

}  // namespace omnislice
