// SPDX-License-Identifier: MIT
// Planar tool-path planning.
//
// Regions of an island (w = line width, h = the layer's thickness, k = 0..walls-1, s = the solid
// spacing w - h (1 - pi/4): beads with a rounded-rectangle section (w - h) h + pi h^2 / 4 (the
// extrusion model, filamentForBead) laid s apart fill exactly s h of section each, as in Slic3r's
// flow model; laid w apart they would leave ~10 % voids at 0.45 x 0.2 mm):
//   wall loop k      = boundary of L_k: L_0 = island offset by -w/2 (outer wall, touches the
//                      surface); L_k+1 = L_k offset by -s, opened by 0.3 s (where the level would
//                      be narrower than 0.6 s, its loop doubling back, it is left to gap fill)
//   fill region F    = island offset by -(w + (walls - 1) s - overlap) (overlap =
//                      infillOverlapPercent % of w; with no walls: -w/2, so bead edges stay inside)
//   sparse region    = F intersected with the sections of layers i-bottomLayers..i+topLayers (i
//                      excluded; a layer beyond the part is empty) = what is covered above and below
//   skin region      = F minus the sparse region (solid: lines spaced s, +45 / -45 deg by layer)
//   gap fill         = per wall level k below the last, L_k offset by -s/2 minus L_k+1 offset by
//                      s/2 (all of it where level k+1 was left out), minus F, opened by 0.15 w:
//                      lines spaced s across each gap's long axis (PlanarOptions::gapFill),
//                      printed as skin after the walls (F lies within the last level's band)
//   bridge regions   = skin over air (not on layer i-1) whose lines, in some direction, land on
//                      layer i-1 at both ends (PlanarOptions::bridges): lines spaced w across the
//                      span, widened 2w onto the anchors, in the best anchored direction
// Sparse infill: Lines pattern at infillAngle + 90 deg on odd layers, spacing w*100/percent; Grid:
// both infillAngle and infillAngle + 90 on every layer, spacing twice that; 100 % = solid lines.
//
// Order: islands nearest-first from the nozzle; within an island inner walls first, then the outer
// wall (the outer surface is laid against walls already in place), each wall level's loops nearest-
// first, each loop starting at its seam (SeamPlacer below); then bridge lines, skin lines, sparse
// lines, each set nearest-first with either end allowed (zig-zag). Travels within an island keep
// inside it (comb.h).
// Travel: longer than retractMinTravel -> Retract, Travel(s), Unretract (never before the first
// extrusion); a travel routed inside its island (travelInside) retracts only when its route is
// longer than retractInsideMaxTravel. Each layer begins with a travel to its first point at the
// layer top.
#include "slice/plan_layers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "common/math_constants.h"
#include "slice/clipper_adapter.h"
#include "slice/comb.h"
#include "slice/infill.h"
#include "slice/travel_order.h"
#include "toolpath/bead.h"

namespace omnislice {


namespace {

using ClipperLib::Path;
using ClipperLib::Paths;
using Vec2 = Eigen::Vector2d;

constexpr double kParkClearanceMm = 2.0;  // toolpath.start sits this far above the first point
constexpr double kGapMinWidth = 0.3;      // line widths: narrower gaps between walls get no gap fill
constexpr double kWallMinWidth = 0.6;     // bead spacings: an inner wall level's region narrower than
                                          // this (its loop doubling back on itself) is left to gap fill

struct Run {
  std::vector<Vec2> points;
  bool closed = false;  // a loop: may start at any vertex, ends back at its start
  Feature feature = Feature::None;
};

std::vector<Vec2> toPoints(const Path& path) {
  std::vector<Vec2> pts;
  pts.reserve(path.size());
  for (const auto& ip : path) pts.push_back(clip::toVec(ip));
  return pts;
}

std::vector<std::vector<Vec2>> loopsOf(const Paths& paths) {
  std::vector<std::vector<Vec2>> loops;
  loops.reserve(paths.size());
  for (const Path& path : paths) loops.push_back(toPoints(path));
  return loops;
}

// Index of the vertex of `pts` nearest to `from` and its squared distance.
std::pair<size_t, double> nearestVertex(const std::vector<Vec2>& pts, const Vec2& from) {
  size_t best = 0;
  double bestD = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < pts.size(); ++i) {
    const double d = (pts[i] - from).squaredNorm();
    if (d < bestD) {
      bestD = d;
      best = i;
    }
  }
  return {best, bestD};
}

// Seams (PlanarOptions::seam). A vertex's corner is its turn measured over a stretch of the loop
// (the points kCornerReach line widths before and after it along the loop), so an offset's rounded
// corner of many small turns counts as the corner it is; its sign says concave or convex (wall
// loops keep material on their left: Clipper's outer contours run counter-clockwise, holes
// clockwise). Only the turn beyond kCornerFloor counts (a tessellated cylinder has no corner).
class SeamPlacer {
 public:
  SeamPlacer(SeamPlacement mode, double lineWidth) : mode_(mode), w_(lineWidth) {}

  // The vertex of `loop` to start at, with the nozzle at `cur`; remembers the seam for the next
  // layer's alignment.
  size_t place(const std::vector<Vec2>& loop, const Vec2& cur) {
    size_t v = 0;
    switch (mode_) {
      case SeamPlacement::Nearest: v = nearestVertex(loop, cur).first; break;
      case SeamPlacement::Random: v = randomVertex(loop.size()); break;
      case SeamPlacement::Aligned: v = cheapest(loop, 1.0, 3.0, 2.0); break;
      case SeamPlacement::Sharpest: v = cheapest(loop, 0.02, 10.0, 0.02); break;
    }
    now_.push_back(loop[v]);
    return v;
  }

  // Starts the next layer: this layer's seams become the ones to align with.
  void nextLayer() {
    below_.swap(now_);
    now_.clear();
    ++layer_;
    loopInLayer_ = 0;
  }

 private:
  static constexpr double kCornerReach = 1.5;  // line widths each side
  static constexpr double kCornerFloor = 20 * kPi / 180;
  static constexpr double kConvexShare = 0.6;  // a convex corner counts this much of a concave one
  static constexpr double kAlignReach = 20;    // line widths: seams below farther are not aligned with

  // Signed turn at every vertex (radians, > 0 convex).
  std::vector<double> turns(const std::vector<Vec2>& loop) const {
    const size_t n = loop.size();
    std::vector<double> seg(n);
    for (size_t i = 0; i < n; ++i) seg[i] = (loop[(i + 1) % n] - loop[i]).norm();
    const double reach = kCornerReach * w_;
    std::vector<double> out(n, 0.0);
    for (size_t i = 0; i < n; ++i) {
      size_t a = i, b = i;
      double back = 0, ahead = 0;
      for (size_t k = 0; k + 1 < n && back < reach; ++k) {
        a = (a + n - 1) % n;
        back += seg[a];
      }
      for (size_t k = 0; k + 1 < n && ahead < reach; ++k) {
        ahead += seg[b];
        b = (b + 1) % n;
      }
      const Vec2 in = loop[i] - loop[a], outDir = loop[b] - loop[i];
      if (in.squaredNorm() == 0 || outDir.squaredNorm() == 0) continue;
      out[i] = std::atan2(in.x() * outDir.y() - in.y() * outDir.x(), in.dot(outDir));
    }
    return out;
  }

  // The vertex of least cost: alignWeight x (distance to the nearest seam of the layer below) / w
  // - cornerWeight x corner, where corner = the concave turn beyond the floor, or kConvexShare of
  // the convex one; without seams below (within kAlignReach line widths of the loop's box), the
  // distance term is the rear preference: rearWeight x how far the vertex is from the loop's rear
  // edge, as a share of its depth.
  size_t cheapest(const std::vector<Vec2>& loop, double alignWeight, double cornerWeight, double rearWeight) const {
    const std::vector<double> turn = turns(loop);
    Vec2 lo = loop[0], hi = loop[0];
    for (const Vec2& p : loop) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double yMin = lo.y(), yMax = hi.y();
    const Vec2 margin = Vec2::Constant(kAlignReach * w_);
    std::vector<Vec2> below;
    for (const Vec2& q : below_) {
      if ((q.array() >= (lo - margin).array()).all() && (q.array() <= (hi + margin).array()).all()) below.push_back(q);
    }
    size_t best = 0;
    double bestCost = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < loop.size(); ++i) {
      const double t = turn[i];
      const double corner = t < 0 ? std::max(0.0, -t - kCornerFloor) : kConvexShare * std::max(0.0, t - kCornerFloor);
      double place;
      if (below.empty()) {
        place = rearWeight * (yMax - loop[i].y()) / std::max(yMax - yMin, 1e-9);
      } else {
        double d2 = std::numeric_limits<double>::infinity();
        for (const Vec2& q : below) d2 = std::min(d2, (q - loop[i]).squaredNorm());
        place = alignWeight * std::sqrt(d2) / w_;
      }
      const double cost = place - cornerWeight * corner;
      if (cost < bestCost - 1e-12) {
        bestCost = cost;
        best = i;
      }
    }
    return best;
  }

  // splitmix64 of (layer, loop in layer): the same seams on every run.
  size_t randomVertex(size_t n) {
    uint64_t x = (static_cast<uint64_t>(layer_) << 32) ^ static_cast<uint64_t>(loopInLayer_++);
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    x ^= x >> 31;
    return static_cast<size_t>(x % n);
  }

  SeamPlacement mode_;
  double w_;
  std::vector<Vec2> below_, now_;
  size_t layer_ = 0, loopInLayer_ = 0;
};

// Orders runs nearest-first from `cur`: loops rotated to start at their seam (seams; without, the
// nearest vertex), open runs reversed when their far end is nearer. Updates cur to the end of the
// last run. A loop is picked by its nearest probe (up to 32 evenly spaced vertices).
std::vector<Run> orderRuns(std::vector<Run> runs, Vec2& cur, SeamPlacer* seams = nullptr) {
  std::vector<std::vector<Vec2>> probes(runs.size());
  for (size_t r = 0; r < runs.size(); ++r) {
    const std::vector<Vec2>& pts = runs[r].points;
    if (runs[r].closed) {
      const size_t step = std::max<size_t>(1, pts.size() / 32);
      for (size_t i = 0; i < pts.size(); i += step) probes[r].push_back(pts[i]);
    } else {
      probes[r] = {pts.front(), pts.back()};
    }
  }
  NearestIndex index(probes);
  std::vector<Run> out;
  out.reserve(runs.size());
  for (size_t n = 0; n < runs.size(); ++n) {
    const NearestIndex::Hit hit = index.nearest(cur);
    if (!hit.found) break;
    index.take(hit.item);
    Run run = std::move(runs[hit.item]);
    if (run.closed) {
      const size_t v = seams ? seams->place(run.points, cur) : nearestVertex(run.points, cur).first;
      std::rotate(run.points.begin(), run.points.begin() + v, run.points.end());
      run.points.push_back(run.points.front());
    } else if (hit.probe == 1) {
      std::reverse(run.points.begin(), run.points.end());
    }
    cur = run.points.back();
    out.push_back(std::move(run));
  }
  return out;
}

// Even-odd point-in-region over closed paths (contours and holes).
bool insideRegion(const Paths& region, const Vec2& p) {
  const ClipperLib::IntPoint q = clip::toPoint(p);
  bool in = false;
  for (const Path& path : region) {
    if (ClipperLib::PointInPolygon(q, path) != 0) in = !in;
  }
  return in;
}

// A bridge over `air` (one connected region of skin not on the layer below): the line angle
// (degrees, 0..175 in 5-degree steps) whose lines across `span` (air widened onto its anchors)
// land on `below` at both ends for the largest share of their length; -1 when no angle anchors
// at least half (the region hangs from one side: not a bridge).
double bridgeAngle(const Paths& span, const Paths& below, double lineWidth) {
  double best = -1, bestShare = 0.5;
  for (int a = 0; a < 180; a += 5) {
    double anchored = 0, total = 0;
    for (const Path& line : fillLines(span, {double(a)}, 2 * lineWidth, 0.25 * lineWidth)) {
      const Vec2 p = clip::toVec(line.front()), q = clip::toVec(line.back());
      const double len = (q - p).norm();
      total += len;
      if (insideRegion(below, p) && insideRegion(below, q)) anchored += len;
    }
    if (total > 0 && anchored / total > bestShare + 1e-9) {
      bestShare = anchored / total;
      best = a;
    }
  }
  return best;
}

// Closed paths with their bounding boxes, so a Boolean operation can skip far-away paths.
struct BoxedPaths {
  Paths paths;
  std::vector<ClipperLib::IntRect> boxes;
};

ClipperLib::IntRect boundsOf(const Path& path) {
  ClipperLib::IntRect r{0, 0, -1, -1};
  if (path.empty()) return r;
  r.left = r.right = path[0].X;
  r.top = r.bottom = path[0].Y;
  for (const auto& p : path) {
    r.left = std::min(r.left, p.X);
    r.right = std::max(r.right, p.X);
    r.top = std::min(r.top, p.Y);
    r.bottom = std::max(r.bottom, p.Y);
  }
  return r;
}

ClipperLib::IntRect boundsOf(const Paths& paths) {
  ClipperLib::IntRect r{0, 0, -1, -1};
  bool first = true;
  for (const Path& path : paths) {
    if (path.empty()) continue;
    const ClipperLib::IntRect b = boundsOf(path);
    if (first) {
      r = b;
      first = false;
    } else {
      r.left = std::min(r.left, b.left);
      r.right = std::max(r.right, b.right);
      r.top = std::min(r.top, b.top);
      r.bottom = std::max(r.bottom, b.bottom);
    }
  }
  return r;
}

// The paths of `all` whose box meets `box`: within `box` they bound the same region (a hole's
// box lies inside its contour's box, so a kept hole always comes with its contour).
Paths nearby(const BoxedPaths& all, const ClipperLib::IntRect& box) {
  Paths out;
  for (size_t i = 0; i < all.paths.size(); ++i) {
    const ClipperLib::IntRect& b = all.boxes[i];
    if (b.right < box.left || b.left > box.right || b.bottom < box.top || b.top > box.bottom) continue;
    out.push_back(all.paths[i]);
  }
  return out;
}

struct IslandWork {
  Paths outline;                       // contour + holes
  std::vector<Vec2> probes;            // up to ~64 outline points, for nearest-island choice
  std::vector<std::vector<Run>> walls; // per level, 0 = outer
  Paths fill;                          // fill region F
  std::vector<Run> gaps;               // gap fill lines
};

// Direction (degrees) of a region's long axis: the principal axis of its area's second moments
// (contour CCW adds, holes CW subtract); 0 for a region too round to have one.
double longAxisDegrees(const Paths& region) {
  if (region.empty() || region[0].empty()) return 0;
  const Vec2 ref = clip::toVec(region[0][0]);
  double a = 0, cx = 0, cy = 0, ixx = 0, iyy = 0, ixy = 0;  // moments about ref
  for (const Path& path : region) {
    for (size_t j = 0, n = path.size(); j < n; ++j) {
      const Vec2 p = clip::toVec(path[j]) - ref, q = clip::toVec(path[(j + 1) % n]) - ref;
      const double c = p.x() * q.y() - q.x() * p.y();
      a += c / 2;
      cx += (p.x() + q.x()) * c / 6;
      cy += (p.y() + q.y()) * c / 6;
      ixx += (p.y() * p.y() + p.y() * q.y() + q.y() * q.y()) * c / 12;  // integral of y^2
      iyy += (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) * c / 12;  // integral of x^2
      ixy += (p.x() * q.y() + 2 * p.x() * p.y() + 2 * q.x() * q.y() + q.x() * p.y()) * c / 24;
    }
  }
  if (!(std::abs(a) > 0)) return 0;
  cx /= a;
  cy /= a;
  const double sxx = iyy / a - cx * cx, syy = ixx / a - cy * cy, sxy = ixy / a - cx * cy;  // covariance
  if (std::abs(sxx - syy) < 1e-12 && std::abs(sxy) < 1e-12) return 0;
  return 0.5 * std::atan2(2 * sxy, sxx - syy) * 180 / kPi;
}

PlanLayersResult fail(Status s, std::string message) { return failed<PlanLayersResult>(s, std::move(message)); }

bool positiveFinite(double v) { return std::isfinite(v) && v > 0; }

}  // namespace

PlanLayersResult planLayers(const SliceResult& slices, const PlanarOptions& options, int partIndex,
                            const ProgressFn& progress,
                            const std::vector<std::vector<ExPolygon2>>* supportRegions) {
  if (!slices.ok()) return fail(Status::InvalidOption, "slices carry an error: " + slices.message);
  const double w = options.lineWidth;
  if (!positiveFinite(w)) return fail(Status::InvalidOption, "line_width must be > 0 mm");
  if (!positiveFinite(options.filamentDiameter)) {
    return fail(Status::InvalidOption, "filament_diameter must be > 0 mm");
  }
  if (options.walls < 0 || options.walls > 1000) return fail(Status::InvalidOption, "walls must be in 0..1000");
  if (options.topLayers < 0 || options.bottomLayers < 0 || options.topLayers > 1000 ||
      options.bottomLayers > 1000) {
    return fail(Status::InvalidOption, "top_layers and bottom_layers must be in 0..1000");
  }
  if (!std::isfinite(options.infillPercent) || options.infillPercent < 0 ||
      options.infillPercent > 100) {
    return fail(Status::InvalidOption, "infill must be in 0..100 %");
  }
  if (!std::isfinite(options.infillOverlapPercent) || options.infillOverlapPercent < 0 ||
      options.infillOverlapPercent > 100) {
    return fail(Status::InvalidOption, "infill_overlap must be in 0..100 % of the line width");
  }
  if (!std::isfinite(options.infillAngleDegrees)) return fail(Status::InvalidOption, "infill_angle must be finite");
  for (double speed : {options.printSpeed, options.outerWallSpeed, options.infillSpeed,
                       options.firstLayerSpeed, options.travelSpeed}) {
    if (!positiveFinite(speed)) return fail(Status::InvalidOption, "speeds must be > 0 mm/s");
  }
  if (!std::isfinite(options.retractLength) || options.retractLength < 0 ||
      !std::isfinite(options.retractMinTravel) || options.retractMinTravel < 0) {
    return fail(Status::InvalidOption, "retract_length and retract_min_travel must be >= 0 mm");
  }
  if (!std::isfinite(options.retractInsideMaxTravel) || options.retractInsideMaxTravel < 0) {
    return fail(Status::InvalidOption, "retract_inside_max_travel must be >= 0 mm");
  }
  if (!positiveFinite(options.bridgeSpeed)) return fail(Status::InvalidOption, "bridge_speed must be > 0 mm/s");
  if (!(options.bridgeFlowPercent > 0 && options.bridgeFlowPercent <= 200)) {
    return fail(Status::InvalidOption, "bridge_flow must be in (0, 200] %");
  }
  if (options.retractLength > 0 && !positiveFinite(options.retractSpeed)) {
    return fail(Status::InvalidOption, "retract_speed must be > 0 mm/s");
  }

  PlanLayersResult result;
  const SliceFrame& frame = slices.frame;
  const size_t layerCount = slices.layers.size();
  result.toolpath.layerCount = static_cast<int32_t>(layerCount);
  result.skinAreaMm2.assign(layerCount, 0.0);
  result.infillAreaMm2.assign(layerCount, 0.0);
  result.bridgeAreaMm2.assign(layerCount, 0.0);
  Toolpath& tp = result.toolpath;

  const int walls = options.walls;
  const double overlap = options.infillOverlapPercent / 100.0 * w;
  const double minLine = 0.25 * w;
  const bool retractOn = options.retractLength > 0;

  SeamPlacer seams(options.seam, w);
  Vec2 cur(0, 0);             // nozzle in the layer plane
  Eigen::Vector3d pos(0, 0, 0);
  bool started = false;       // first travel not yet emitted
  bool extruded = false;

  try {
    std::vector<BoxedPaths> sections(layerCount);
    for (size_t i = 0; i < layerCount; ++i) {
      sections[i].paths = clip::toPaths(slices.layers[i].islands);
      for (const Path& path : sections[i].paths) sections[i].boxes.push_back(boundsOf(path));
    }

    for (size_t i = 0; i < layerCount; ++i) {
      if (!reportProgress(progress, "toolpath", static_cast<double>(i) / layerCount)) {
        return fail(Status::Cancelled, "cancelled");
      }
      const SliceLayer& layer = slices.layers[i];
      const double thickness = layer.top - layer.bottom;
      const double z = slices.minHeight + layer.top;
      const bool firstLayer = i == 0;
      const double spacing = std::max(0.5 * w, w - thickness * (1 - kPi / 4));
      const double fillInset = walls > 0 ? w + (walls - 1) * spacing - overlap : 0.5 * w;

      // Islands of this layer with their walls and fill regions.
      std::vector<IslandWork> islands;
      for (const ExPolygon2& ex : layer.islands) {
        IslandWork iw;
        iw.outline = clip::toPaths(ex);
        for (const Path& path : iw.outline) {
          const size_t step = std::max<size_t>(1, path.size() / 64);
          for (size_t p = 0; p < path.size(); p += step) iw.probes.push_back(clip::toVec(path[p]));
        }
        // Wall level k's loops are the boundary of the region L_k: L_0 = the island offset by
        // -w/2; L_k+1 = L_k offset by -s and opened by kWallMinWidth s / 2, so a level is left
        // out where it would be narrower than kWallMinWidth beads (its loop would come back on
        // itself, two beads on one line); that strip goes to gap fill.
        std::vector<Paths> levels;
        for (int k = 0; k < walls; ++k) {
          const double open = 0.5 * kWallMinWidth * spacing;
          Paths region = k == 0 ? clip::offset(iw.outline, -0.5 * w)
                                : clip::offset(clip::offset(levels.back(), -(spacing + open)), open);
          if (region.empty()) break;
          std::vector<Run> level;
          for (const Path& loop : region) {
            if (loop.size() < 3) continue;
            Run run;
            run.points = toPoints(loop);
            run.closed = true;
            run.feature = k == 0 ? Feature::WallOuter : Feature::WallInner;
            level.push_back(std::move(run));
          }
          if (level.empty()) break;
          iw.walls.push_back(std::move(level));
          levels.push_back(std::move(region));
        }
        iw.fill = clip::offset(iw.outline, -fillInset);
        // Gap fill: the area inside level k's band (a bead covers s across: L_k offset by -s/2)
        // that the next level's band (L_k+1 offset by s/2) does not reach, where level k+1 was
        // left out or never fits. (After the last level the fill region reaches further than the
        // band: no gap there.) Gaps narrower than kGapMinWidth lines are left (the beads' spread
        // covers most of them); each is filled by lines across its long axis, spaced s, which
        // lays a bead's section per s of its length whatever its width. A level whose region
        // the next level's, grown by s, covers to within a quarter of a square line has no gap
        // worth filling and costs one offset (a gap of the smallest area filled leaves at least
        // twice that uncovered).
        if (options.gapFill && !levels.empty()) {
          Paths gaps;
          for (size_t k = 0; k < levels.size() && static_cast<int>(k) + 1 < walls; ++k) {
            const bool last = k + 1 == levels.size();
            if (!last) {
              const double uncovered =
                  clip::areaMm2(levels[k]) - clip::areaMm2(clip::offset(levels[k + 1], spacing));
              if (uncovered < 0.25 * w * w) continue;
            }
            const Paths inner = clip::offset(levels[k], -0.5 * spacing);
            if (inner.empty()) continue;
            const Paths gap = last ? inner : clip::subtract(inner, clip::offset(levels[k + 1], 0.5 * spacing));
            gaps.insert(gaps.end(), gap.begin(), gap.end());
          }
          const double open = 0.5 * kGapMinWidth * w;
          if (!gaps.empty()) gaps = clip::offset(clip::offset(clip::unite(gaps), -open), open);
          if (!gaps.empty() && !iw.fill.empty()) gaps = clip::subtract(gaps, iw.fill);
          if (!gaps.empty()) {
            ClipperLib::Clipper c;
            c.AddPaths(gaps, ClipperLib::ptSubject, true);
            ClipperLib::PolyTree tree;
            c.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
            for (const Paths& gap : clip::islandPaths(tree)) {
              const double gapArea = clip::areaMm2(gap);
              if (gapArea < 0.5 * w * w) continue;
              bool any = false;
              for (const Path& line : fillLines(gap, {longAxisDegrees(gap) + 90}, spacing, minLine)) {
                iw.gaps.push_back(Run{toPoints(line), false, Feature::Skin});
                any = true;
              }
              if (any) result.gapAreaMm2 += gapArea;
            }
          }
        }
        const double area = clip::areaMm2(iw.outline);
        result.sectionAreaMm2 += area;
        if (iw.walls.empty() && iw.fill.empty()) {
          result.thinAreaMm2 += area;
          ++result.thinIslands;
          if (result.thinFirstLayer < 0) result.thinFirstLayer = static_cast<int>(i);
          result.thinLastLayer = static_cast<int>(i);
        }
        islands.push_back(std::move(iw));
      }

      // Skin versus sparse: covered by every section within topLayers above and bottomLayers below.
      // fill = isoplanar (paper 003 on planar layers): every line of every layer along the drive
      // direction, which the pipeline put in infillAngleDegrees.
      const bool isoplanar = options.allLinesAlongInfillAngle;
      const double skinAngle = isoplanar ? options.infillAngleDegrees : (i % 2 == 0) ? 45.0 : -45.0;
      const double pct = options.infillPercent;
      std::vector<std::vector<Run>> skinRuns(islands.size()), infillRuns(islands.size()), bridgeRuns(islands.size());
      // Window of layers whose sections must all cover a point for it to be sparse (computed per
      // island with bbox-filtered sections, which keeps Clipper's scan lines short on layers with
      // many islands); a window reaching beyond the part leaves nothing sparse (all skin).
      const long lo = static_cast<long>(i) - options.bottomLayers;
      const long hi = static_cast<long>(i) + options.topLayers;
      const bool noSkin = options.bottomLayers == 0 && options.topLayers == 0;
      for (size_t k = 0; k < islands.size(); ++k) {
        const Paths& fill = islands[k].fill;
        if (fill.empty()) continue;
        Paths sparse = fill;
        if (!noSkin) {
          if (lo < 0 || hi >= static_cast<long>(layerCount)) {
            sparse.clear();
          } else {
            for (long j = lo; j <= hi && !sparse.empty(); ++j) {
              if (j == static_cast<long>(i)) continue;
              sparse = clip::intersect(sparse, nearby(sections[j], boundsOf(sparse)));
            }
          }
        }
        Paths skin = sparse.empty() ? fill : clip::subtract(fill, sparse);
        // Bridges: skin over air (opened by half a line, so wall edges leave no slivers), each
        // region widened by two lines onto what holds it and crossed in its best anchored angle.
        if (options.bridges && i > 0 && !skin.empty()) {
          const Paths below = nearby(sections[i - 1], boundsOf(skin));
          Paths air = below.empty() ? skin : clip::subtract(skin, below);
          air = clip::offset(clip::offset(air, -0.5 * w), 0.5 * w);
          if (!air.empty()) {
            ClipperLib::Clipper c;
            c.AddPaths(air, ClipperLib::ptSubject, true);
            ClipperLib::PolyTree tree;
            c.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
            Paths bridged;  // spans taken by earlier regions: widened spans must not overlap
            for (const Paths& region : clip::islandPaths(tree)) {
              Paths span = clip::intersect(clip::offset(region, 2 * w), fill);
              if (!bridged.empty()) span = clip::subtract(span, bridged);
              if (span.empty()) continue;
              const double angle = below.empty() ? -1 : bridgeAngle(span, below, w);
              if (angle < 0) continue;
              for (const Path& line : fillLines(span, {angle}, w, minLine)) {
                bridgeRuns[k].push_back(Run{toPoints(line), false, Feature::Bridge});
              }
              result.bridgeAreaMm2[i] += clip::areaMm2(span);
              ++result.bridges;
              skin = clip::subtract(skin, span);
              bridged.insert(bridged.end(), span.begin(), span.end());
            }
          }
        }
        result.skinAreaMm2[i] += clip::areaMm2(skin);
        result.infillAreaMm2[i] += clip::areaMm2(sparse);
        for (const Path& line : fillLines(skin, {skinAngle}, spacing, minLine)) {
          skinRuns[k].push_back(Run{toPoints(line), false, Feature::Skin});
        }
        if (pct > 0 && !sparse.empty()) {
          Paths lines;
          if (pct >= 100) {
            lines = fillLines(sparse, {skinAngle}, spacing, minLine);
          } else if (options.infillPattern == InfillPattern::Lines || isoplanar) {
            const double angle = options.infillAngleDegrees + (i % 2 == 0 || isoplanar ? 0.0 : 90.0);
            lines = fillLines(sparse, {angle}, w * 100.0 / pct, minLine);
          } else {
            lines = fillLines(sparse, {options.infillAngleDegrees, options.infillAngleDegrees + 90.0},
                              2.0 * w * 100.0 / pct, minLine);
          }
          for (const Path& line : lines) infillRuns[k].push_back(Run{toPoints(line), false, Feature::Infill});
        }
      }

      // Emit the layer: islands nearest-first, walls inner to outer, then skin, then infill.
      auto speedOf = [&](Feature f) {
        if (firstLayer) return options.firstLayerSpeed;
        if (f == Feature::WallOuter) return options.outerWallSpeed;
        if (f == Feature::Bridge) return options.bridgeSpeed;
        if (f == Feature::Infill) return options.infillSpeed;
        return options.printSpeed;
      };
      auto baseMove = [&](const Eigen::Vector3d& p, MoveKind kind) {
        Move m;
        m.position = p;
        m.axis = frame.d;
        m.kind = kind;
        m.part = partIndex;
        m.layer = static_cast<int32_t>(i);
        return m;
      };
      // Travel to `target` (the layer point `target2` at height z): inside the island (comb) when
      // the nozzle is in it and a route exists, retracting only when that route is longer than
      // retractInsideMaxTravel; else straight, retracting over retractMinTravel.
      const CombRegion* comb = nullptr;
      std::vector<Vec2> route;
      auto travelTo = [&](const Eigen::Vector3d& target, const Vec2& target2) {
        if (!started) {
          tp.start = target + kParkClearanceMm * frame.d;
          pos = tp.start;
          started = true;
        }
        const double len = (target - pos).norm();
        if (len <= 1e-9) return;
        route.clear();
        bool inside = false;
        double routeLen = len;
        if (comb && std::abs((target - pos).dot(frame.d)) < 1e-9 && comb->route(cur, target2, route)) {
          inside = true;
          routeLen = 0;
          Vec2 at = cur;
          for (const Vec2& p : route) {
            routeLen += (p - at).norm();
            at = p;
          }
          route.pop_back();  // the last point is the target itself
        }
        const bool retract = retractOn && extruded && routeLen > options.retractMinTravel &&
                             (!inside || routeLen > options.retractInsideMaxTravel);
        if (retract) {
          Move r = baseMove(pos, MoveKind::Retract);
          r.filament = -options.retractLength;
          r.speed = options.retractSpeed;
          tp.moves.push_back(r);
        }
        for (const Vec2& p : route) {
          Move t = baseMove(frame.toPart(p, z), MoveKind::Travel);
          t.speed = options.travelSpeed;
          tp.moves.push_back(t);
        }
        Move t = baseMove(target, MoveKind::Travel);
        t.speed = options.travelSpeed;
        tp.moves.push_back(t);
        if (retract) {
          Move u = baseMove(target, MoveKind::Unretract);
          u.filament = options.retractLength;
          u.speed = options.retractSpeed;
          tp.moves.push_back(u);
        }
        pos = target;
      };
      auto emitRun = [&](const Run& run) {
        travelTo(frame.toPart(run.points.front(), z), run.points.front());
        cur = run.points.front();
        const double speed = speedOf(run.feature);
        for (size_t p = 1; p < run.points.size(); ++p) {
          const Eigen::Vector3d target = frame.toPart(run.points[p], z);
          const double len = (target - pos).norm();
          if (len <= 1e-9) continue;
          Move m = baseMove(target, run.feature == Feature::Support ? MoveKind::Support : MoveKind::Print);
          m.width = w;
          m.height = thickness;
          m.filament = filamentForBead(w, thickness, len, options.filamentDiameter);
          if (run.feature == Feature::Bridge) m.filament *= options.bridgeFlowPercent / 100.0;
          m.speed = speed;
          m.feature = run.feature;
          tp.moves.push_back(m);
          pos = target;
          extruded = true;
        }
        cur = run.points.back();
      };

      if (supportRegions && i < supportRegions->size() && !(*supportRegions)[i].empty()) {
        std::vector<Run> supportRuns;
        for (const Path& line : fillLines(clip::toPaths((*supportRegions)[i]), {i % 2 ? 90.0 : 0.0}, spacing, minLine)) {
          supportRuns.push_back(Run{toPoints(line), false, Feature::Support});
        }
        Vec2 probe = cur;
        for (const Run& run : orderRuns(std::move(supportRuns), probe)) emitRun(run);
      }
      std::vector<std::vector<Vec2>> islandProbes(islands.size());
      for (size_t k = 0; k < islands.size(); ++k) islandProbes[k] = islands[k].probes;
      NearestIndex islandIndex(islandProbes);
      for (size_t n = 0; n < islands.size(); ++n) {
        const NearestIndex::Hit hit = islandIndex.nearest(cur);
        if (!hit.found) break;
        islandIndex.take(hit.item);
        const size_t best = hit.item;
        IslandWork& iw = islands[best];
        // The island's travel region: a quarter line inside its outline (every run's points lie
        // half a line or more inside). The travel to its first run comes from elsewhere: straight.
        std::optional<CombRegion> region;
        if (options.travelInside) region.emplace(loopsOf(clip::offset(iw.outline, -0.25 * w)));
        comb = nullptr;
        auto emitInIsland = [&](const Run& run) {
          emitRun(run);
          if (region && !region->empty()) comb = &*region;
        };
        for (size_t level = iw.walls.size(); level-- > 0;) {
          Vec2 probe = cur;
          for (const Run& run : orderRuns(std::move(iw.walls[level]), probe, &seams)) emitInIsland(run);
        }
        Vec2 probe = cur;
        for (const Run& run : orderRuns(std::move(iw.gaps), probe)) emitInIsland(run);
        probe = cur;
        for (const Run& run : orderRuns(std::move(bridgeRuns[best]), probe)) emitInIsland(run);
        probe = cur;
        for (const Run& run : orderRuns(std::move(skinRuns[best]), probe)) emitInIsland(run);
        probe = cur;
        for (const Run& run : orderRuns(std::move(infillRuns[best]), probe)) emitInIsland(run);
        comb = nullptr;
      }
      seams.nextLayer();
    }
  } catch (const std::exception& e) {
    return fail(Status::Internal, std::string("polygon clipping failed: ") + e.what());
  }
  if (!started) tp.start = frame.toPart(Vec2(0, 0), slices.minHeight + kParkClearanceMm);
  if (!reportProgress(progress, "toolpath", 1.0)) return fail(Status::Cancelled, "cancelled");
  return result;
}

std::optional<Warning> thinSectionsWarning(double thinAreaMm2, double sectionAreaMm2, size_t thinIslands,
                                           double lineWidthMm) {
  if (!(thinAreaMm2 >= 1.0) || !(thinAreaMm2 >= 0.005 * sectionAreaMm2)) return std::nullopt;
  char text[400];
  std::snprintf(text, sizeof text,
                "%zu sections of the part (%.1f mm^2, %.1f %% of the sliced area) are narrower than the %.2f mm "
                "line and get no path: those parts of the model are not printed. Scale the part up, or use a "
                "smaller nozzle and line width",
                thinIslands, thinAreaMm2, 100 * thinAreaMm2 / std::max(sectionAreaMm2, 1e-9), lineWidthMm);
  return Warning{"thin_sections", text};
}

}  // namespace omnislice
