// SPDX-License-Identifier: MIT
#include "slice/infill.h"

#include <cmath>
#include <limits>

#include "common/math_constants.h"
#include "slice/clipper_adapter.h"

namespace omnislice {


ClipperLib::Paths fillLines(const ClipperLib::Paths& region, const std::vector<double>& anglesDegrees,
                            double spacingMm, double minLengthMm) {
  using namespace ClipperLib;
  if (region.empty() || !(spacingMm > 0)) return {};
  std::vector<Eigen::Vector2d> pts;
  for (const Path& path : region) {
    for (const IntPoint& ip : path) pts.push_back(clip::toVec(ip));
  }
  Paths out;
  const double minUnits = minLengthMm * clip::kClipperScale;
  // One clipping pass per direction: lines of one direction never cross each other, whereas
  // crossing subject lines would make Clipper compute all their mutual intersections.
  for (double angleDegrees : anglesDegrees) {
    Paths lines;
    const double a = angleDegrees * kPi / 180.0;
    const Eigen::Vector2d u(std::cos(a), std::sin(a));   // along the lines
    const Eigen::Vector2d n(-std::sin(a), std::cos(a));  // across them
    double alo = std::numeric_limits<double>::infinity(), ahi = -alo, nlo = alo, nhi = -alo;
    for (const Eigen::Vector2d& p : pts) {
      alo = std::min(alo, p.dot(u));
      ahi = std::max(ahi, p.dot(u));
      nlo = std::min(nlo, p.dot(n));
      nhi = std::max(nhi, p.dot(n));
    }
    if (!(nhi > nlo)) continue;
    // Extend the lines 1 mm beyond the region so clipping, not the line ends, decides.
    alo -= 1.0;
    ahi += 1.0;
    const long k0 = static_cast<long>(std::ceil(nlo / spacingMm - 0.5));
    const long k1 = static_cast<long>(std::floor(nhi / spacingMm - 0.5));
    for (long k = k0; k <= k1; ++k) {
      const double off = (static_cast<double>(k) + 0.5) * spacingMm;
      const Eigen::Vector2d p0 = off * n + alo * u, p1 = off * n + ahi * u;
      lines.push_back(Path{clip::toPoint(p0), clip::toPoint(p1)});
    }
    for (Path& piece : clip::clipLines(lines, region)) {
      if (piece.size() < 2) continue;
      const IntPoint& s = piece.front();
      const IntPoint& e = piece.back();
      const double len = std::hypot(static_cast<double>(e.X - s.X), static_cast<double>(e.Y - s.Y));
      if (len < minUnits) continue;
      out.push_back(Path{s, e});
    }
  }
  return out;
}

}  // namespace omnislice
