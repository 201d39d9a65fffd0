// SPDX-License-Identifier: MIT
// Curved-layer tool-path assembly: orientation by Eq. 3 of paper 001 (Section 5.2), local bead
// height from the distance to the layers printed before (Section 6.2.1: thickness variations are
// compensated by the extrusion), gouging correction against the points printed before (Section
// 6.2.3), region order by nearest neighbour, travels with retraction and leave/approach along the
// nozzle axis.
#include "surface/curved_toolpath.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "geometry/aabb_tree.h"
#include "motion/axis_freedom.h"
#include "motion/orientation_smoothing.h"
#include "toolpath/bead.h"
#include "surface/printed_points.h"
#include "surface/surface_layers.h"

namespace omnislice {

namespace {

using Eigen::Vector3d;

CurvedToolpathResult fail(Status s, std::string message) { return failed<CurvedToolpathResult>(s, std::move(message)); }

bool positiveFinite(double v) { return std::isfinite(v) && v > 0; }
bool nonNegativeFinite(double v) { return std::isfinite(v) && v >= 0; }

// Orientation and local height of one path point.
struct Sample {
  Vector3d axis{0, 0, 1};
  Vector3d ideal{0, 0, 1};  // the axis before the motion term (Eq. 3 / the normal, tilt-limited)
  double height = 0;
  double distance = std::numeric_limits<double>::infinity();  // |q - c_q|
  int64_t layer = -1, triangle = -1;  // where c_q lies (-1: the platform)
  bool fallback = false;
  bool clamped = false;  // turned onto the tilt range
};

// Axis u turned toward +Z onto the cone of half-angle maxTilt when it leans further.
Vector3d limitTilt(const Vector3d& u, double maxTilt) {
  const double tilt = std::acos(std::clamp(u.z(), -1.0, 1.0));
  if (tilt <= maxTilt + 1e-12) return u;
  Vector3d horizontal(u.x(), u.y(), 0);
  const double hn = horizontal.norm();
  horizontal = hn > 1e-12 ? Vector3d(horizontal / hn) : Vector3d::UnitX();
  return std::cos(maxTilt) * Vector3d::UnitZ() + std::sin(maxTilt) * horizontal;
}

// The options and inputs: InvalidOption or NonFiniteVertex where buildToolpath cannot use them.
Outcome checkInputs(const std::vector<CurvedLayer>& layers,
                    const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                    const std::vector<std::pair<uint32_t, uint32_t>>* order, const CurvedToolpathOptions& o) {
  auto fail = [](Status s, std::string message) { return failed<Outcome>(s, std::move(message)); };
  if (!positiveFinite(o.lineWidth) || !positiveFinite(o.nominalHeight)) {
    return fail(Status::InvalidOption, "line width and nominal height must be > 0 mm");
  }
  if (!positiveFinite(o.minHeightFactor) || !positiveFinite(o.maxHeightFactor) ||
      o.minHeightFactor > o.maxHeightFactor) {
    return fail(Status::InvalidOption, "height factors must satisfy 0 < min <= max");
  }
  if (!positiveFinite(o.filamentDiameter)) return fail(Status::InvalidOption, "filament diameter must be > 0 mm");
  if (!positiveFinite(o.printSpeed) || !positiveFinite(o.firstLayerSpeed) || !positiveFinite(o.travelSpeed) ||
      !positiveFinite(o.retractSpeed)) {
    return fail(Status::InvalidOption, "speeds must be > 0 mm/s");
  }
  if (!nonNegativeFinite(o.retractLength) || !nonNegativeFinite(o.retractMinTravel) ||
      !nonNegativeFinite(o.travelClearance)) {
    return fail(Status::InvalidOption, "retraction length, minimum travel and clearance must be >= 0 mm");
  }
  if (o.earlierLayers < 1) return fail(Status::InvalidOption, "earlierLayers must be >= 1");
  if (!(o.axisFreedomDegrees >= 0 && o.axisFreedomDegrees <= 90)) {
    return fail(Status::InvalidOption, "axis freedom must be in [0, 90] degrees");
  }
  if (!(o.coneHalfAngleDegrees > 0 && o.coneHalfAngleDegrees < 90) || !positiveFinite(o.coneLength) ||
      !nonNegativeFinite(o.collisionClearance) || !nonNegativeFinite(o.gougingMarginDegrees) ||
      !nonNegativeFinite(o.maxCorrectionDegrees) || !positiveFinite(o.correctionTaperDegrees) ||
      !positiveFinite(o.filterThresholdDegrees) || o.coneHalfAngleDegrees + o.gougingMarginDegrees >= 90) {
    return fail(Status::InvalidOption,
                "gouging cone: half-angle (plus margin) in (0, 90) degrees, length > 0 mm, clearance, "
                "margin and largest correction >= 0, taper and filter threshold > 0");
  }
  if (paths.size() != layers.size()) {
    return fail(Status::InvalidOption, "paths must have one entry per layer");
  }
  for (size_t l = 0; l < layers.size(); ++l) {
    if (paths[l].size() != layers[l].regions.size()) {
      return fail(Status::InvalidOption, "paths[" + std::to_string(l) + "] must have one entry per region");
    }
    for (const LayerRegion& region : layers[l].regions) {
      if (region.mesh.positions.size() % 3 != 0 || region.mesh.triangles.size() % 3 != 0) {
        return fail(Status::InvalidOption, "layer " + std::to_string(l) + ": region mesh arrays are not a multiple of 3");
      }
      for (double c : region.mesh.positions) {
        if (!std::isfinite(c)) return fail(Status::NonFiniteVertex, "layer " + std::to_string(l) + ": non-finite region vertex");
      }
    }
    for (const auto& regionPaths : paths[l]) {
      for (const SurfacePath& p : regionPaths) {
        for (const Vector3d& q : p.points) {
          if (!q.allFinite()) return fail(Status::NonFiniteVertex, "layer " + std::to_string(l) + ": non-finite path point");
        }
      }
    }
  }
  if (order != nullptr) {
    for (const auto& [l, r] : *order) {
      if (l >= layers.size() || r >= layers[l].regions.size()) {
        return fail(Status::InvalidOption, "order names region " + std::to_string(r) + " of layer " +
                                               std::to_string(l) + ", which does not exist");
      }
    }
  }
  return {};
}

constexpr double kDeg = kPi / 180.0;
constexpr double kSpacing = 0.5;  // mm between printed points, as `omnislice verify` samples
const char* const kStage = "toolpath";

// The axes of one path's points while its gouging is corrected.
struct PathAxes {
  std::vector<Vector3d> base;  // the orientation's axes (Eq. 3 or the normal, leaned by the motion
                               // term within axisFreedomDegrees) through the planner's low-pass
                               // filter, within the tilt range: what the path prints with when
                               // nothing collides
  std::vector<Vector3d> axes;  // the corrected axes
  std::vector<Vector3d> ideal; // the axes before the motion term (tilt-limited): tried first
                               // where the base axis collides
  std::vector<uint8_t> bad;      // no free axis found (yet)
  std::vector<uint8_t> changed;  // turned to a free axis
  // noFree[i]: the search around base[i] found no free axis. Whether one exists depends only on
  // the point, its base axis and the printed set, which stays fixed while a path is corrected
  // (the preferred turn and the window only choose among free ones), so it is not searched again.
  std::vector<uint8_t> noFree;
};

// The tool path of curved layers, built region by region: orientation (Eq. 3), gouging
// correction against the points printed so far, then travels and print moves.
class CurvedToolpathBuilder {
 public:
  CurvedToolpathBuilder(const std::vector<CurvedLayer>& layers,
                        const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                        const CurvedToolpathOptions& o, const ProgressFn& progress)
      : layers_(layers), paths_(paths), o_(o), progress_(progress), tp_(result_.toolpath),
        trees_(layers.size()), merged_(layers.size()) {
    tp_.layerCount = static_cast<int32_t>(layers.size());
    hMin_ = o_.minHeightFactor * o_.nominalHeight;
    hMax_ = o_.maxHeightFactor * o_.nominalHeight;
    tinyDistance_ = 0.1 * o_.nominalHeight;
    cosLimit_ = std::cos(80.0 * kPi / 180.0);
    // The machine's tilt range: an axis leaning further from +Z is turned toward +Z in the plane
    // of the two onto the cone of half-angle maxTiltDegrees.
    maxTilt_ = std::clamp(o_.maxTiltDegrees, 0.0, 180.0) * kPi / 180.0;
    // ---- gouging correction (paper 001 Section 6.2.3) ----
    cone_.clearance = o_.collisionClearance > 0 ? o_.collisionClearance : o_.nominalHeight;
    cone_.length = o_.coneLength;
    cone_.tanAngle = std::tan((o_.coneHalfAngleDegrees + o_.gougingMarginDegrees) * kDeg);
    cone_.radius = 0.5 * kSpacing;
    exactCone_ = cone_;
    exactCone_.tanAngle = std::tan(o_.coneHalfAngleDegrees * kDeg);
    exactCone_.radius = 0;
    tightCone_ = cone_;
    tightCone_.tanAngle = exactCone_.tanAngle;
  }

  // The regions in the given order (layers revisited keep their trees). False when cancelled.
  bool printInOrder(const std::vector<std::pair<uint32_t, uint32_t>>& order) {
    for (size_t k = 0; k < order.size(); ++k) {
      const double done = double(k) / double(order.size());
      if (!reportProgress(progress_, kStage, done)) return false;
      const size_t l = order[k].first, r = order[k].second;
      const auto t0 = Clock::now();
      prepareTrees(l, false);
      orientationMs_ += msSince(t0);
      if (!printRegion(l, r, done)) return false;
    }
    return true;
  }

  // Layer by layer, regions nearest-first from the current position. False when cancelled.
  bool printLayerByLayer() {
    for (size_t l = 0; l < layers_.size(); ++l) {
      if (!reportProgress(progress_, kStage, double(l) / double(layers_.size()))) return false;
      const auto t0 = Clock::now();
      prepareTrees(l, true);
      orientationMs_ += msSince(t0);
      const size_t nr = layers_[l].regions.size();
      std::vector<uint8_t> done(nr, 0);
      for (size_t n = 0; n < nr; ++n) {
        const size_t pick = nearestRegion(l, done);
        done[pick] = 1;
        if (!printRegion(l, pick, (double(l) + double(n) / double(nr)) / double(layers_.size()))) return false;
      }
    }
    return true;
  }

  CurvedToolpathResult result() {
    result_.orientationMs = orientationMs_;
    result_.gougingMs = gougingMs_;
    return std::move(result_);
  }

 private:
  // Regions nearest-first from the current position (distance to the first path's start).
  size_t nearestRegion(size_t l, const std::vector<uint8_t>& done) const {
    const size_t nr = layers_[l].regions.size();
    size_t pick = nr;
    double bestD = std::numeric_limits<double>::infinity();
    for (size_t r = 0; r < nr; ++r) {
      if (done[r]) continue;
      const Vector3d* startPoint = nullptr;
      for (const SurfacePath& p : paths_[l][r]) {
        if (p.points.size() >= 2) {
          startPoint = &p.points.front();
          break;
        }
      }
      const double dist = startPoint ? (*startPoint - pos_).norm() : 0;  // pathless regions: free
      if (pick == nr || dist < bestD) {
        pick = r;
        bestD = dist;
      }
    }
    return pick;
  }

  // The earlier layers' trees for layer l: one AABB tree per layer, built when the layer is
  // first needed as an "earlier" layer and kept for the next earlierLayers layers. Layer by
  // layer, trees below the window are freed; in a given order (layers revisited), they are kept.
  void prepareTrees(size_t l, bool freeBelow) {
    if (l == 0) return;
    const size_t first = l > size_t(o_.earlierLayers) ? l - size_t(o_.earlierLayers) : 0;
    if (freeBelow) {
      for (size_t k = 0; k < first; ++k) {
        trees_[k].reset();
        merged_[k] = Mesh();
      }
    }
    for (size_t k = first; k < l; ++k) {
      if (trees_[k]) continue;
      merged_[k] = layerMesh(layers_[k]);  // one AABB tree per layer
      trees_[k] = std::make_unique<AabbTree>(merged_[k]);
    }
  }

  // Eq. 3 for point q of layer l with surface normal n (may be zero when unknown). The platform
  // plane z = 0 counts as printed before every layer (T in C(V u T)), so a region of a later
  // layer that reaches down to the platform is oriented and sized against it.
  // hint: the axis of the path's previous point (+Z for the first), the side the normal is flipped
  // to where q - c_q is too short to give a direction.
  // prev: the path's previous sample (nullptr for the first): the triangle its c_q lies on gives
  // a near-tight first candidate, so the tree searches prune early.
  Sample sampleAt(size_t l, const Vector3d& q, Vector3d n, const Vector3d& hint, const Sample* prev) const {
    Sample s;
    if (l == 0) {
      s.axis = Vector3d::UnitZ();
      s.height = o_.nominalHeight;
      const double nn = n.norm();
      if (o_.axisFromNormals && nn > 0) s.axis = n / nn;
      return s;
    }
    double best = std::max(0.0, q.z());
    Vector3d c(q.x(), q.y(), 0);
    const double platformDistance = best;
    const size_t first = l > size_t(o_.earlierLayers) ? l - size_t(o_.earlierLayers) : 0;
    if (prev && prev->triangle >= 0) {
      const Mesh& m = merged_[size_t(prev->layer)];
      const size_t t = size_t(prev->triangle);
      const Vector3d p = closestPointOnTriangle(q, m.vertex(m.triangles[3 * t]), m.vertex(m.triangles[3 * t + 1]),
                                                m.vertex(m.triangles[3 * t + 2]));
      const double d = (p - q).norm();
      if (d < best) {
        best = d;
        c = p;
        s.layer = prev->layer;
        s.triangle = prev->triangle;
      }
    }
    for (size_t k = l; k-- > first;) {  // the layer just below first: it is usually the closest
      if (!trees_[k] || trees_[k]->triangleCount() == 0) continue;
      const ClosestPoint cp = trees_[k]->closest(q, best);
      if (cp.distance < best) {
        best = cp.distance;
        c = cp.point;
        s.layer = int64_t(k);
        s.triangle = cp.triangle;
      }
    }
    s.distance = best;
    s.height = std::clamp(best, hMin_, hMax_);
    // A partial layer (bounded thickness) sizes the bead but does not orient it: next to its cut
    // edge q - c_q would lean sideways, so the axis comes from the full layers below.
    if (s.layer >= 0 && layers_[size_t(s.layer)].partial) {
      double bestFull = platformDistance;
      c = Vector3d(q.x(), q.y(), 0);
      for (size_t k = l; k-- > first;) {
        if (layers_[k].partial || !trees_[k] || trees_[k]->triangleCount() == 0) continue;
        const ClosestPoint cp = trees_[k]->closest(q, bestFull);
        if (cp.distance < bestFull) {
          bestFull = cp.distance;
          c = cp.point;
        }
      }
    }
    const Vector3d t = q - c;
    const double d = t.norm();
    const double nn = n.norm();
    if (nn > 0) {
      n /= nn;
      // Flip the normal to the side away from the earlier layers (the previous axis of the path
      // when q sits on them: the direction of a tiny q - c_q is rounding noise).
      const Vector3d ref = d >= tinyDistance_ ? Vector3d(t / d) : hint;
      if (n.dot(ref) < 0) n = -n;
    }
    if (o_.axisFromNormals && nn > 0) {
      s.axis = n;  // the normal, on the side away from the earlier layers
      return s;
    }
    if (d >= tinyDistance_ && (nn == 0 || (t / d).dot(n) >= cosLimit_)) {
      s.axis = t / d;
      return s;
    }
    s.fallback = true;
    if (nn > 0) {
      s.axis = n;
    } else {
      s.axis = d >= tinyDistance_ ? Vector3d(t / d) : hint;
    }
    return s;
  }

  // The sample with its axis turned onto the tilt range (counted in tiltClamped).
  Sample clampTilt(Sample s) {
    const double tilt = std::acos(std::clamp(s.axis.z(), -1.0, 1.0));
    if (tilt <= maxTilt_ + 1e-12) return s;
    Vector3d horizontal(s.axis.x(), s.axis.y(), 0);
    const double hn = horizontal.norm();
    horizontal = hn > 1e-12 ? Vector3d(horizontal / hn) : Vector3d::UnitX();
    s.axis = std::cos(maxTilt_) * Vector3d::UnitZ() + std::sin(maxTilt_) * horizontal;
    s.clamped = true;
    ++result_.tiltClamped;
    return s;
  }

  // Positions checked for path point i: its segment from point i - 1 (the move ending at i carries
  // its axis), every <= kSpacing mm, both ends.
  void pathPositions(const std::vector<Vector3d>& pts) {
    positions_.assign(pts.size(), {});
    seqOf_.assign(pts.size(), 0);
    for (size_t i = 0; i < pts.size(); ++i) {
      seqOf_[i] = nextSeq_++;
      if (i == 0) {
        positions_[i].push_back(pts[0]);
        continue;
      }
      const double len = (pts[i] - pts[i - 1]).norm();
      const int n = std::max(1, int(std::ceil(len / kSpacing)));
      for (int k = 0; k <= n; ++k) positions_[i].push_back(pts[i - 1] + (double(k) / n) * (pts[i] - pts[i - 1]));
    }
  }

  bool collides(size_t i, const Vector3d& u, Vector3d* away) const {
    return collides(i, u, away, i < tight_.size() && tight_[i] ? tightCone_ : cone_);
  }
  bool collides(size_t i, const Vector3d& u, Vector3d* away, const GougingCone& cone) const {
    bool any = false;
    for (const Vector3d& p : positions_[i]) {
      if (printed_.hit(p, u, seqOf_[i], cone, away)) {
        any = true;
        if (!away) return true;
      }
    }
    return any;
  }

  // The move ending at point i turns the axis from a0 to a1 on the way (the writers interpolate
  // it): the positions checked with the axis at their share of the turn.
  bool collidesTurning(size_t i, const Vector3d& a0, const Vector3d& a1) const {
    return collidesTurning(i, a0, a1, cone_);
  }
  bool collidesTurning(size_t i, const Vector3d& a0, const Vector3d& a1, const GougingCone& cone) const {
    const size_t n = positions_[i].size();
    const double angle = axisAngleDegrees(a0, a1);
    if (n < 2 || angle < 1) return false;
    // Every <= 0.5 mm and every <= 2 degrees of the turn (the planner's steps).
    const Vector3d& p0 = positions_[i].front();
    const Vector3d& p1 = positions_[i].back();
    const size_t steps = std::max(n - 1, size_t(std::ceil(angle / 2.0)));
    for (size_t k = 0; k <= steps; ++k) {
      const double t = double(k) / double(steps);
      const Vector3d u = slerpAxis(a0, a1, t);
      if (u.allFinite() && printed_.hit(p0 + t * (p1 - p0), u, seqOf_[i], cone, nullptr)) return true;
    }
    return false;
  }

  // collides(i, u, &away) from away = 0, remembered within one path: alignTurns and taperTurns
  // search again around the same base axes, and the sum of `away` runs over every printed point
  // in the cone, the costliest query at real sizes (a profile of fertility at 100 mm: 70 % of the
  // tool-path stage in it). Forgotten whenever the printed set changes (a new path's points,
  // retired segments), so the answers are those of the query itself.
  bool collidesAway(size_t i, const Vector3d& u, Vector3d& away) const {
    away = Vector3d::Zero();
    const bool tight = i < tight_.size() && tight_[i];
    std::vector<AwayEntry>& entries = awayCache_[i];
    for (const AwayEntry& e : entries) {
      if (e.tight == tight && e.u == u) {
        away = e.away;
        return e.hit;
      }
    }
    const bool hit = collides(i, u, &away);
    entries.push_back({u, away, tight, hit});
    return hit;
  }
  void forgetAway() { awayCache_.clear(); }

  // Free axis near u: rings of increasing angle around u (azimuths from the side away from the
  // offending points); among the free candidates of the first free ring and the next few, the one
  // of least turn + half its angle to ref (the neighbour's axis: consistent turns along a path).
  // False when none within maxCorrectionDegrees and the tilt range.
  bool searchFree(size_t i, Vector3d& u, const Vector3d& ref, double window) const {
    Vector3d away;
    if (!collidesAway(i, u, away)) return true;
    away -= away.dot(u) * u;
    if (away.norm() < 1e-9) away = u.unitOrthogonal();
    const Vector3d e1 = away.normalized(), e2 = u.cross(e1);
    constexpr int kAzimuths = 48;
    double firstFree = -1, bestCost = std::numeric_limits<double>::infinity();
    Vector3d best = u;
    for (double delta = 2; delta <= o_.maxCorrectionDegrees + 1e-9; delta += 2) {
      if (firstFree >= 0 && delta > firstFree + window + 1e-9) break;
      for (int k = 0; k < kAzimuths; ++k) {
        const int step = (k + 1) / 2 * (k % 2 ? 1 : -1);  // 0, +1, -1, +2, -2, ...
        const double phi = 2 * kPi * step / kAzimuths;
        const Vector3d c = ringAxis(u, e1, e2, delta, phi);
        if (!withinTilt(c)) continue;
        const double cost = delta + axisAngleDegrees(c, ref);
        if (cost >= bestCost) continue;
        if (!collides(i, c, nullptr)) {
          if (firstFree < 0) firstFree = delta;
          bestCost = cost;
          best = c;
        }
      }
    }
    if (firstFree < 0) return false;
    u = best;
    return true;
  }

  // One path: its points enter the printed set, then every colliding axis is turned to a free
  // one and the turn is tapered over the neighbours (so the motion planner's low-pass filter,
  // which acts on neighbours more than 10 degrees apart, leaves it), re-checked until stable.
  void correctPath(const std::vector<Vector3d>& pts, std::vector<Sample>& smp, int32_t layer) {
    const auto g0 = Clock::now();
    const size_t np = pts.size();
    skip_.assign(np, 0);
    tight_.assign(np, 0);
    selfBlocked_.clear();
    pathPositions(pts);
    for (size_t i = 0; i < np; ++i) {
      for (const Vector3d& p : positions_[i]) printed_.add(p, seqOf_[i]);
    }
    forgetAway();
    if (!o_.correctGouging) return;
    PathAxes a = filteredAxes(smp);
    const bool anyChange = turnCollidingAxes(a);
    if (anyChange) {
      alignTurns(a);
      taperTurns(a);
      smoothJumps(a);
    }
    // Paths without a collision keep their Eq. 3 axes (the planner filters them as checked),
    // unless a turn between them collides.
    std::vector<Vector3d> written(np);
    for (size_t i = 0; i < np; ++i) written[i] = anyChange ? a.axes[i] : smp[i].axis;
    const size_t turnsLeft = checkAsPrinted(written, a.bad);
    if (anyChange || turnsLeft != kUnchanged) {
      for (size_t i = 0; i < np; ++i) {
        result_.gougingCorrections += axisAngleDegrees(written[i], a.base[i]) > 1e-6;
        smp[i].axis = written[i];
      }
    }
    if (!o_.skipUncorrectable) {
      for (size_t i = 0; i < np; ++i) {
        result_.gougingUncorrected += a.bad[i];
        // Of those, the ones the exact cone of `omnislice verify` still finds colliding (the
        // search's cone is wider and its points blown up: most bad points are only near misses).
        if (a.bad[i] && collides(i, written[i], nullptr, exactCone_)) ++exactBad_;
      }
      // Turns left colliding count as bad points (they are collisions as verify finds them).
      if (turnsLeft != kUnchanged) {
        result_.gougingUncorrected += turnsLeft;
        exactBad_ += turnsLeft;
      }
    } else {
      skipCollidingSegments(pts, smp, layer);
      for (size_t i = 0; i < np; ++i) result_.gougingUncorrected += skip_[i];
    }
    gougingMs_ += msSince(g0);
  }

  // The axes as the program prints them (the planner's low-pass filter over the path's print
  // moves; the travel to the path arrives with point 0's axis, and each move turns on the way),
  // checked with tightCone_. Where a move's turn collides (its end axes are free: the obstacle
  // lies between them), its end point takes an axis on rings around it (2 to 30 degrees, least
  // turn first) that is free and from and to which both of its moves turn freely; again until
  // none changes, at most 3 rounds. Points in `bad` (no free axis) are left as they are. Returns
  // kUnchanged when no turn collided; otherwise the turns still colliding.
  static constexpr size_t kUnchanged = std::numeric_limits<size_t>::max();
  size_t checkAsPrinted(std::vector<Vector3d>& axes, const std::vector<uint8_t>& bad) const {
    const size_t np = axes.size();
    if (np < 2) return kUnchanged;
    bool changedAny = false;
    size_t left = 0;
    for (int round = 0; round < 4; ++round) {
      std::vector<Vector3d> f = filteredAsPrinted(axes);
      left = 0;
      bool changed = false;
      for (size_t i = 1; i < np; ++i) {
        const Vector3d from = moveStartAxis(i, axes, f);
        if (bad[i] || !collidesTurning(i, from, f[i], tightCone_)) continue;
        if (round == 3) {
          ++left;
          continue;
        }
        // The first move: the travel may arrive with the new axis (no turn on the way).
        auto ok = [&](const Vector3d& c) {
          return !collides(i, c, nullptr, tightCone_) && (i == 1 || !collidesTurning(i, from, c, tightCone_)) &&
                 (i + 1 >= np || !collidesTurning(i + 1, c, f[i + 1], tightCone_));
        };
        Vector3d u = axes[i];
        if (i == 1 && ok(u)) {
          axes[0] = u;
          changed = true;
        } else if (ringSearch(u, from, ok)) {
          if (i == 1) axes[0] = u;
          axes[i] = u;
          f[i] = u;
          changed = true;
        } else {
          ++left;
        }
      }
      if (!changed) break;
      changedAny = true;
    }
    return changedAny || left > 0 ? left : kUnchanged;
  }

  // The axis delta degrees from u toward azimuth phi (radians) in the frame (e1, e2) normal to u:
  // the candidates of the rings the gouging searches walk.
  static Vector3d ringAxis(const Vector3d& u, const Vector3d& e1, const Vector3d& e2, double delta, double phi) {
    return (std::cos(delta * kDeg) * u + std::sin(delta * kDeg) * (std::cos(phi) * e1 + std::sin(phi) * e2)).normalized();
  }
  bool withinTilt(const Vector3d& c) const { return std::acos(std::clamp(c.z(), -1.0, 1.0)) <= maxTilt_ + 1e-9; }

  // The axes as the program moves them: the planner's low-pass filter over each run of printed
  // segments (a segment in skip_ ends a run: a travel follows).
  std::vector<Vector3d> filteredAsPrinted(const std::vector<Vector3d>& axes) const {
    const size_t np = axes.size();
    std::vector<int> runs(np, -1);
    int id = 0;
    for (size_t i = 1; i < np; ++i) {
      if (skip_[i]) {
        ++id;
        continue;
      }
      runs[i] = id;
    }
    std::vector<Vector3d> filtered = axes;
    filterOrientations(filtered, runs, o_.filterThresholdDegrees);
    return filtered;
  }
  // The axis move i starts turning from: the travel to point i - 1 arrives with the axis of point
  // 0 (path start) or of point i (after a skipped segment); otherwise the previous move's.
  const Vector3d& moveStartAxis(size_t i, const std::vector<Vector3d>& axes, const std::vector<Vector3d>& filtered) const {
    return i == 1 ? axes[0] : skip_[i - 1] ? axes[i] : filtered[i - 1];
  }

  // The axis on rings of 2 to 30 degrees around u (24 azimuths, within the tilt range) that
  // satisfies ok, on the first ring that has one, nearest to ref. False when none.
  template <class Ok>
  bool ringSearch(Vector3d& u, const Vector3d& ref, const Ok& ok) const {
    const Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
    constexpr int kAzimuths = 24;
    for (double delta = 2; delta <= 30 + 1e-9; delta += 2) {
      double best = std::numeric_limits<double>::infinity();
      Vector3d pick = u;
      for (int k = 0; k < kAzimuths; ++k) {
        const double phi = 2 * kPi * k / kAzimuths;
        const Vector3d c = ringAxis(u, e1, e2, delta, phi);
        if (!withinTilt(c)) continue;
        const double d = axisAngleDegrees(c, ref);
        if (d < best && ok(c)) {
          best = d;
          pick = c;
        }
      }
      if (best < std::numeric_limits<double>::infinity()) {
        u = pick;
        return true;
      }
    }
    return false;
  }

  // The axes as the planner will print them: its low-pass filter first, so the check sees the
  // axes it will print with, then the tilt range.
  PathAxes filteredAxes(const std::vector<Sample>& smp) const {
    const size_t np = smp.size();
    PathAxes a;
    std::vector<Vector3d>& base = a.base;
    base.resize(np);
    for (size_t i = 0; i < np; ++i) base[i] = smp[i].axis;
    std::vector<int> run(np, 0);
    filterOrientations(base, run, o_.filterThresholdDegrees);
    for (size_t i = 0; i < np; ++i) base[i] = limitTilt(base[i].normalized(), maxTilt_);
    a.ideal.resize(np);
    for (size_t i = 0; i < np; ++i) a.ideal[i] = limitTilt(smp[i].ideal.normalized(), maxTilt_);
    a.axes = base;
    a.bad.assign(np, 0);
    a.changed.assign(np, 0);
    a.noFree.assign(np, 0);
    return a;
  }

  // Each colliding axis turned to a free one near it (preferring the previous point's turn).
  // True when any collided.
  bool turnCollidingAxes(PathAxes& a) {
    const size_t np = a.axes.size();
    std::vector<Vector3d>& axes = a.axes;
    bool anyChange = false;
    for (size_t i = 0; i < np; ++i) {
      Vector3d u = axes[i];
      if (!collides(i, u, nullptr)) continue;
      anyChange = true;
      // The motion term leaned it: its ideal axis first (the surface term wins over motion).
      if (o_.axisFreedomDegrees > 0 && (a.ideal[i] - u).norm() > 1e-9 && !collides(i, a.ideal[i], nullptr)) {
        axes[i] = a.ideal[i];
        a.changed[i] = 1;
        continue;
      }
      bool found = searchFree(i, u, i > 0 ? axes[i - 1] : u, 8);
      if (!found) {
        // None with the search's margin: one with verify's cone angle, checked again as printed
        // (checkAsPrinted).
        tight_[i] = 1;
        u = axes[i];
        found = searchFree(i, u, i > 0 ? axes[i - 1] : u, 8);
        if (!found) tight_[i] = 0;
      }
      if (found) {
        axes[i] = u;
        a.changed[i] = 1;
      } else {
        a.bad[i] = 1;
        a.noFree[i] = 1;
        // Blocked only by this path's own earlier points (free against all printed before it):
        // printed before them, it would be free (printRegion tries that order).
        bool before = false;
        for (const Vector3d& p : positions_[i]) {
          if (printed_.hit(p, axes[i], seqOf_.empty() ? 0 : seqOf_[0], cone_, nullptr)) {
            before = true;
            break;
          }
        }
        if (!before) selfBlocked_.push_back(i);
      }
    }
    return anyChange;
  }

  // Consistent turns: the changed points again, backward then forward, preferring the turn
  // nearest their neighbour's (a point near the end of a wall may turn either way; the next
  // point under the wall only one).
  void alignTurns(PathAxes& a) const {
    const size_t np = a.axes.size();
    for (int pass = 0; pass < 2; ++pass) {
      for (size_t k = 0; k < np; ++k) {
        const size_t i = pass == 0 ? np - 1 - k : k;
        if (!a.changed[i]) continue;
        const size_t nb = pass == 0 ? (i + 1 < np ? i + 1 : i) : (i > 0 ? i - 1 : i);
        if (nb == i || !a.changed[nb]) continue;
        Vector3d u = a.base[i];
        if (searchFree(i, u, a.axes[nb], 30)) a.axes[i] = u;
      }
    }
  }

  // Taper: the turns spread over the unchanged neighbours, then re-checked, up to 4 rounds until
  // stable.
  void taperTurns(PathAxes& a) const {
    const size_t np = a.axes.size();
    const std::vector<Vector3d>& base = a.base;
    std::vector<Vector3d>& axes = a.axes;
    std::vector<uint8_t>& changed = a.changed;
    std::vector<uint8_t>& bad = a.bad;
    std::vector<uint8_t>& noFree = a.noFree;
    for (int round = 0; round < 4; ++round) {
      // Taper: the turn of each changed point i as a rotation vector w_i (of its base axis);
      // an unchanged point j takes the sum of the turns of the nearest changed point on each
      // side, each shortened by correctionTaperDegrees per point of distance (opposite turns
      // of two sides blend through zero), applied to its base axis.
      std::vector<Vector3d> w(np, Vector3d::Zero());
      for (size_t i = 0; i < np; ++i) {
        if (!changed[i]) continue;
        const Vector3d k = base[i].cross(axes[i]);
        const double th = std::atan2(k.norm(), base[i].dot(axes[i]));
        if (th > 1e-9) w[i] = th * k.normalized();
      }
      const double taper = o_.correctionTaperDegrees * kDeg;
      auto shortened = [&](const Vector3d& v, size_t dist) {
        const double th = v.norm(), t = th - double(dist) * taper;
        return t > 0 ? Vector3d(v * (t / th)) : Vector3d::Zero();
      };
      std::vector<Vector3d> rot(np, Vector3d::Zero());
      long last = -1;
      for (size_t j = 0; j < np; ++j) {
        if (changed[j]) {
          rot[j] = w[j];
          last = long(j);
        } else if (last >= 0) {
          rot[j] = shortened(w[size_t(last)], j - size_t(last));
        }
      }
      last = -1;
      for (size_t j = np; j-- > 0;) {
        if (changed[j]) {
          last = long(j);
        } else if (last >= 0) {
          rot[j] += shortened(w[size_t(last)], size_t(last) - j);
        }
      }
      std::vector<double> angle(np, 0);
      std::vector<Vector3d> rotAxis(np, Vector3d::UnitZ());
      for (size_t j = 0; j < np; ++j) {
        angle[j] = rot[j].norm();
        if (angle[j] > 1e-12) rotAxis[j] = rot[j] / angle[j];
      }
      std::vector<Vector3d> next(np);
      for (size_t j = 0; j < np; ++j) {
        next[j] = angle[j] > 0 ? limitTilt((Eigen::AngleAxisd(angle[j], rotAxis[j]) * base[j]).normalized(), maxTilt_)
                               : base[j];
      }
      // Re-check the tapered axes; points that collide search again around their base axis,
      // preferring turns near the tapered one.
      bool stable = true;
      for (size_t j = 0; j < np; ++j) {
        if ((next[j] - axes[j]).norm() < 1e-12 && !bad[j]) continue;
        Vector3d u = next[j];
        if (!collides(j, u, nullptr)) {
          axes[j] = u;
          continue;
        }
        u = base[j];
        if (!noFree[j] && searchFree(j, u, next[j], 8)) {
          if ((u - axes[j]).norm() > 1e-9) stable = false;
          axes[j] = u;
          changed[j] = 1;
          bad[j] = 0;
        } else {
          axes[j] = next[j];
          bad[j] = 1;
          noFree[j] = 1;
        }
      }
      if (stable) break;
    }
  }

  // Remaining jumps between neighbours (turns chosen on separate rings): average with the
  // neighbours where the average is free.
  void smoothJumps(PathAxes& a) const {
    const size_t np = a.axes.size();
    std::vector<Vector3d>& axes = a.axes;
    for (int round = 0; round < 8; ++round) {
      bool any = false;
      for (size_t j = 1; j + 1 < np; ++j) {
        if (axisAngleDegrees(axes[j], axes[j - 1]) <= 6 && axisAngleDegrees(axes[j], axes[j + 1]) <= 6) continue;
        const Vector3d c = limitTilt((axes[j - 1] + 2 * axes[j] + axes[j + 1]).normalized(), maxTilt_);
        if (!c.allFinite() || collides(j, c, nullptr)) continue;
        axes[j] = c;
        any = true;
      }
      if (!any) break;
    }
  }

  // skipUncorrectable: what the program will do: the motion planner low-pass filters the axes of
  // each run of printed segments (a skipped segment ends a run: a travel follows), a travel
  // arrives with the next point's unfiltered axis, and each move turns the axis on the way. A
  // segment colliding anywhere in that motion is skipped (skip_); skips change the runs, so again
  // until none is added.
  void skipCollidingSegments(const std::vector<Vector3d>& pts, const std::vector<Sample>& smp, int32_t layer) {
    const size_t np = pts.size();
    std::vector<Vector3d> axes(np);
    for (size_t i = 0; i < np; ++i) axes[i] = smp[i].axis;
    for (int round = 0; round < 4; ++round) {
      const std::vector<Vector3d> filtered = filteredAsPrinted(axes);
      bool added = false;
      for (size_t i = 1; i < np; ++i) {
        if (skip_[i]) continue;
        const Vector3d& from = moveStartAxis(i, axes, filtered);
        if (!collides(i, filtered[i], nullptr, tightCone_) && !collidesTurning(i, from, filtered[i], tightCone_)) continue;
        skip_[i] = 1;
        added = true;
        ++result_.skippedPoints;
        result_.skippedMm += (pts[i] - pts[i - 1]).norm();
        result_.skippedEnds.push_back(pts[i - 1]);
        result_.skippedEnds.push_back(pts[i]);
        result_.skippedLayers.push_back(layer);
        // Later checks see only what is printed.
        for (size_t k = 1; k < positions_[i].size(); ++k) printed_.retire(positions_[i][k], seqOf_[i]);
        forgetAway();
      }
      if (!added) break;
    }
  }

  Move* push(const Vector3d& p, const Vector3d& u, MoveKind kind, int32_t layer) {
    Move m;
    m.position = p;
    m.axis = u;
    m.kind = kind;
    m.layer = layer;
    tp_.moves.push_back(m);
    return &tp_.moves.back();
  }

  // Travel to s (nozzle axis u there). Long travels retract, leave along the current axis by the
  // clearance, cross over at clearance height and approach along u.
  void travelTo(const Vector3d& s, const Vector3d& u, int32_t layer) {
    if (!started_) {
      tp_.start = s + o_.travelClearance * u;
      pos_ = tp_.start;
      axis_ = u;
      started_ = true;
    }
    const double len = (s - pos_).norm();
    if (len <= 1e-9) {
      pos_ = s;
      axis_ = u;
      return;
    }
    const bool retract = o_.retractLength > 0 && extruded_ && len > o_.retractMinTravel;
    if (retract) {
      Move* r = push(pos_, axis_, MoveKind::Retract, layer);
      r->filament = -o_.retractLength;
      r->speed = o_.retractSpeed;
      if (o_.travelClearance > 0) {
        push(pos_ + o_.travelClearance * axis_, axis_, MoveKind::Travel, layer)->speed = o_.travelSpeed;
        push(s + o_.travelClearance * u, u, MoveKind::Travel, layer)->speed = o_.travelSpeed;
      }
    }
    push(s, u, MoveKind::Travel, layer)->speed = o_.travelSpeed;
    if (retract) {
      Move* r = push(s, u, MoveKind::Unretract, layer);
      r->filament = o_.retractLength;
      r->speed = o_.retractSpeed;
    }
    pos_ = s;
    axis_ = u;
  }

  // Print region `pick` of layer l; progress reports the fraction `done` of the whole. False when
  // cancelled.
  bool printRegion(size_t l, size_t pick, double done) {
    const int32_t layer = static_cast<int32_t>(l);
    const double speed = l == 0 ? o_.firstLayerSpeed : o_.printSpeed;
    const bool support = layers_[l].regions[pick].support;
    const Feature feature = support ? Feature::Support : Feature::Infill;
    const MoveKind printKind = support ? MoveKind::Support : MoveKind::Print;
    for (const SurfacePath& path : paths_[l][pick]) {
      const size_t np = path.points.size();
      if (np < 2) continue;
      const double width = path.width > 0 ? std::min(path.width, o_.lineWidth) : o_.lineWidth;
      const Counters unoriented = counters();
      if (!orientPath(l, path, done)) return false;
      const Counters before = counters();
      correctPath(path.points, samples_, layer);
      if (o_.reorderSelfBlocked && !selfBlocked_.empty()) {
        const int reordered = printSelfBlockedFirst(l, path, before, width, speed, printKind, feature, done);
        if (reordered < 0) return false;
        if (reordered > 0) continue;
      }
      if (o_.skipUncorrectable && o_.retryLeftOutNearIdeal && o_.axisFreedomDegrees > 0 &&
          result_.skippedPoints > before.skippedPoints && !orientNearIdeal(l, path, unoriented, before, done)) {
        return false;
      }
      travelTo(path.points[0], samples_[0].axis, layer);
      printSegments(path, width, speed, printKind, feature, layer);
    }
    return true;
  }

  // The counters a path's orientation and correction add to (restored when a trial is undone).
  struct Counters {
    size_t fallbacks = 0, clamped = 0, freed = 0, corrections = 0, uncorrected = 0, skippedPoints = 0,
           skippedEnds = 0;
    double skippedMm = 0;
    size_t exactBad = 0;
  };
  Counters counters() const {
    return {result_.orientationFallbacks, result_.tiltClamped, result_.axesFreed, result_.gougingCorrections,
            result_.gougingUncorrected,
            result_.skippedPoints, result_.skippedEnds.size(), result_.skippedMm, exactBad_};
  }
  // What an order is judged by: left out (skipUncorrectable) or left colliding under the exact
  // cone since the counters c.
  size_t badSince(const Counters& c) const {
    return o_.skipUncorrectable ? result_.gougingUncorrected - c.uncorrected : exactBad_ - c.exactBad;
  }
  void restore(const Counters& c) {
    exactBad_ = c.exactBad;
    result_.orientationFallbacks = c.fallbacks;
    result_.tiltClamped = c.clamped;
    result_.axesFreed = c.freed;
    result_.gougingCorrections = c.corrections;
    result_.gougingUncorrected = c.uncorrected;
    result_.skippedPoints = c.skippedPoints;
    result_.skippedEnds.resize(c.skippedEnds);
    result_.skippedLayers.resize(c.skippedEnds / 2);
    result_.skippedMm = c.skippedMm;
  }

  // A corrected piece of a path, kept until the order is chosen.
  struct Piece {
    SurfacePath path;
    std::vector<Sample> samples;
    std::vector<uint8_t> skip;
    std::vector<std::vector<Vector3d>> positions;
    std::vector<uint32_t> seq;
  };
  Piece keep(SurfacePath path) {
    return {std::move(path), samples_, skip_, positions_, seqOf_};
  }
  // Takes a corrected path's points out of the printed set (a trial undone).
  void retire(const std::vector<std::vector<Vector3d>>& positions, const std::vector<uint32_t>& seq,
              const std::vector<uint8_t>& skip) {
    forgetAway();
    for (size_t i = 0; i < positions.size(); ++i) {
      // Segments skipped by skipCollidingSegments were retired already (all but their start).
      const size_t n = skip[i] ? std::min<size_t>(1, positions[i].size()) : positions[i].size();
      for (size_t k = 0; k < n; ++k) printed_.retire(positions[i][k], seq[i]);
    }
  }

  // The points i0..i1 (inclusive) of a path as a path of their own.
  static SurfacePath subPath(const SurfacePath& path, size_t i0, size_t i1) {
    SurfacePath out;
    out.width = path.width;
    out.points.assign(path.points.begin() + long(i0), path.points.begin() + long(i1) + 1);
    if (path.normals.size() == path.points.size()) {
      out.normals.assign(path.normals.begin() + long(i0), path.normals.begin() + long(i1) + 1);
    }
    if (path.curves.size() == path.points.size()) {
      out.curves.assign(path.curves.begin() + long(i0), path.curves.begin() + long(i1) + 1);
      out.curves[0] = 0;
    }
    return out;
  }

  // The pieces of a path in another order: runs-first (kind 0: the runs of self-blocked segments,
  // then the rest, each in path order) or reversed (kind 1: the whole path from its end).
  std::vector<SurfacePath> reordered(const SurfacePath& path, int kind) const {
    const size_t np = path.points.size();
    std::vector<SurfacePath> out;
    if (kind == 1) {
      SurfacePath r = path;
      std::reverse(r.points.begin(), r.points.end());
      std::reverse(r.normals.begin(), r.normals.end());
      if (!r.curves.empty()) {
        // curves[i] names the segment ending at i: reversed, the segment ending at i ends at i + 1.
        std::vector<uint32_t> c(np, 0);
        for (size_t i = 1; i < np; ++i) c[np - i] = path.curves[i];
        r.curves = std::move(c);
      }
      out.push_back(std::move(r));
      return out;
    }
    std::vector<uint8_t> first(np, 0);
    for (size_t i : selfBlocked_) first[i] = 1;
    first[0] = 0;
    std::vector<std::pair<size_t, size_t>> ahead, rest;  // point ranges [i0, i1]
    for (size_t i = 1; i < np;) {
      size_t j = i;
      while (j + 1 < np && first[j + 1] == first[i]) ++j;
      (first[i] ? ahead : rest).push_back({i - 1, j});
      i = j + 1;
    }
    ahead.insert(ahead.end(), rest.begin(), rest.end());
    for (const auto& [i0, i1] : ahead) out.push_back(subPath(path, i0, i1));
    return out;
  }

  // Orients and corrects pieces in order (their points enter the printed set). False when cancelled.
  bool correctPieces(size_t l, std::vector<SurfacePath> paths, std::vector<Piece>& pieces, double done) {
    pieces.clear();
    for (SurfacePath& piece : paths) {
      if (!orientPath(l, piece, done)) return false;
      correctPath(piece.points, samples_, static_cast<int32_t>(l));
      pieces.push_back(keep(std::move(piece)));
    }
    return true;
  }
  void undo(const std::vector<Piece>& pieces, const Counters& before) {
    for (auto k = pieces.rbegin(); k != pieces.rend(); ++k) retire(k->positions, k->seq, k->skip);
    restore(before);
  }

  // Where some points of a path have no free axis only because of the path's own earlier points
  // (a spiral closing on a layer that leans away from the nozzle at the machine's tilt limit: its
  // centre lies under the rings printed before it), two other orders are tried: the runs of those
  // segments first and the rest after them, and the whole path reversed. The order that leaves the
  // fewest points colliding under verify's exact cone (the search's wider cone flags many near
  // misses; with skipUncorrectable: the fewest segments left out) is printed, the path's own order
  // when no other leaves fewer (ties
  // keep it). Returns 1 when another order was printed, 0 when the path's order stays (corrected
  // again against the same live points, so samples_ and skip_ are the path's; the trials leave
  // retired points and cells behind, which can change the order of the `away` sums and so the
  // rounding of the search's starting azimuth), -1 when cancelled.
  int printSelfBlockedFirst(size_t l, const SurfacePath& path, const Counters& before, double width, double speed,
                            MoveKind printKind, Feature feature, double done) {
    const int32_t layer = static_cast<int32_t>(l);
    size_t bestBad = badSince(before);
    int bestKind = -1;
    std::vector<SurfacePath> orders[2] = {reordered(path, 0), reordered(path, 1)};
    std::vector<Piece> pieces;
    pieces.push_back(keep(path));
    for (int kind = 0; kind < 2; ++kind) {
      undo(pieces, before);
      if (!correctPieces(l, orders[kind], pieces, done)) return -1;
      const size_t bad = badSince(before);
      if (bad < bestBad) {
        bestBad = bad;
        bestKind = kind;
      }
    }
    if (bestKind != 1) {
      // Redo the chosen order against the points printed before the path.
      undo(pieces, before);
      if (bestKind < 0) {
        if (!orientPath(l, path, done)) return -1;
        correctPath(path.points, samples_, layer);
        return 0;
      }
      if (!correctPieces(l, orders[bestKind], pieces, done)) return -1;
    }
    ++result_.reorderedPaths;
    for (Piece& piece : pieces) {
      samples_ = std::move(piece.samples);
      skip_ = std::move(piece.skip);
      travelTo(piece.path.points[0], samples_[0].axis, layer);
      printSegments(piece.path, width, speed, printKind, feature, layer);
    }
    return 1;
  }

  // A path that left segments out (skip_, since the counters `before`) oriented again with the
  // freedom lowered to 0 at both ends of every segment left out, the limits of each round adding
  // to the last's (two rounds at most): the axis ramps to the ideal there (limitRampDegreesPerMm)
  // and afterwards relaxes back to the least tilted axis at kRelaxDegreesPerMm, so one lowered
  // point does not leave the rest of a spiral on a tilted axis that follows the rings' azimuth.
  // The orientation that leaves the least out stays in samples_ / skip_ (ties keep the first);
  // the orientation counters count it once (`unoriented`: before the path was first oriented).
  // False when cancelled.
  static constexpr double kRelaxDegreesPerMm = 5;
  bool orientNearIdeal(size_t l, const SurfacePath& path, const Counters& unoriented, const Counters& before,
                       double done) {
    auto reorient = [&](const std::vector<double>* limit) {
      result_.orientationFallbacks = unoriented.fallbacks;
      result_.tiltClamped = unoriented.clamped;
      result_.axesFreed = unoriented.freed;
      return orientPath(l, path, done, limit);
    };
    const int32_t layer = static_cast<int32_t>(l);
    const size_t np = path.points.size();
    size_t bestBad = badSince(before);
    std::vector<double> limit(np, std::numeric_limits<double>::infinity()), bestLimit;
    std::vector<Piece> pieces;
    pieces.push_back(keep(path));
    bool lastIsBest = true;
    for (int round = 0; round < 2 && bestBad > 0; ++round) {
      bool added = false;
      for (size_t i = 1; i < np; ++i) {
        if (!skip_[i]) continue;
        added = added || limit[i] != 0 || limit[i - 1] != 0;
        limit[i] = limit[i - 1] = 0;
      }
      if (!added) break;
      undo(pieces, before);
      if (!reorient(&limit)) return false;
      correctPath(path.points, samples_, layer);
      pieces.clear();
      pieces.push_back(keep(path));
      const size_t bad = badSince(before);
      lastIsBest = bad < bestBad;
      if (lastIsBest) {
        bestBad = bad;
        bestLimit = limit;
      }
    }
    if (!lastIsBest) {
      undo(pieces, before);
      if (!reorient(bestLimit.empty() ? nullptr : &bestLimit)) return false;
      correctPath(path.points, samples_, layer);
    }
    if (!bestLimit.empty()) ++result_.nearIdealPaths;
    return true;
  }

  // samples_ of a path's points (Eq. 3 within the tilt range); `limit` (one per point, when
  // given) lowers the motion term's freedom there (chooseAxesForMotion). False when cancelled.
  bool orientPath(size_t l, const SurfacePath& path, double done, const std::vector<double>* limit = nullptr) {
    const size_t np = path.points.size();
    const auto s0 = Clock::now();
    samples_.resize(np);
    const bool haveNormals = path.normals.size() == np;
    for (size_t i = 0; i < np; ++i) {
      // Long paths: keep cancellation within a few milliseconds (~10 us per point).
      if ((i & 1023) == 1023 && !reportProgress(progress_, kStage, done)) return false;
      Vector3d nrm = haveNormals && path.normals[i].allFinite() ? path.normals[i] : Vector3d::Zero();
      samples_[i] = clampTilt(sampleAt(l, path.points[i], nrm,
                                       i > 0 ? samples_[i - 1].axis : Vector3d::UnitZ(),
                                       i > 0 ? &samples_[i - 1] : nullptr));
      result_.orientationFallbacks += samples_[i].fallback;
      samples_[i].ideal = samples_[i].axis;
    }
    if (o_.axisFreedomDegrees > 0) {
      axes_.resize(np);
      freedom_.resize(np);
      for (size_t i = 0; i < np; ++i) {
        axes_[i] = samples_[i].axis;
        // An axis turned onto the tilt range already leans from Eq. 3: it keeps its axis.
        freedom_[i] = samples_[i].clamped ? 0.0 : o_.axisFreedomDegrees;
        if (limit && limit->size() == np) freedom_[i] = std::min(freedom_[i], (*limit)[i]);
      }
      AxisFreedomOptions fo;
      fo.freedomDegrees = o_.axisFreedomDegrees;
      fo.maxTiltDegrees = o_.maxTiltDegrees;
      if (limit) fo.relaxDegreesPerMm = kRelaxDegreesPerMm;
      result_.axesFreed += chooseAxesForMotion(path.points, axes_, fo, freedom_);
      for (size_t i = 0; i < np; ++i) samples_[i].axis = axes_[i];
    }
    orientationMs_ += msSince(s0);
    return true;
  }

  // One print move per segment not skipped (a travel first where the previous one was).
  void printSegments(const SurfacePath& path, double width, double speed, MoveKind printKind, Feature feature,
                     int32_t layer) {
    const size_t np = path.points.size();
    for (size_t i = 1; i < np; ++i) {
      if (skip_[i]) continue;
      if ((path.points[i - 1] - pos_).norm() > 1e-9) travelTo(path.points[i - 1], samples_[i].axis, layer);
      const Vector3d& target = path.points[i];
      const double len = (target - pos_).norm();
      if (len <= 1e-9) continue;
      // The bead of a segment takes the mean of its end heights.
      const double h = 0.5 * (samples_[i - 1].height + samples_[i].height);
      Move* m = push(target, samples_[i].axis, printKind, layer);
      m->width = width;
      m->height = h;
      m->filament = o_.ellipseBeads ? ellipseBeadFilament(width, h, len, o_.filamentDiameter)
                                    : filamentForBead(width, h, len, o_.filamentDiameter);
      if (path.curves.size() == np) m->curve = path.curves[i];
      m->speed = speed;
      m->feature = feature;
      pos_ = target;
      axis_ = samples_[i].axis;
      extruded_ = true;
    }
  }

  const std::vector<CurvedLayer>& layers_;
  const std::vector<std::vector<std::vector<SurfacePath>>>& paths_;
  const CurvedToolpathOptions& o_;
  const ProgressFn& progress_;
  CurvedToolpathResult result_;
  Toolpath& tp_;
  double orientationMs_ = 0, gougingMs_ = 0;
  // Orientation: the earlier layers' trees and merged meshes, the bead height range.
  std::vector<std::unique_ptr<AabbTree>> trees_;
  std::vector<Mesh> merged_;
  double hMin_ = 0, hMax_ = 0, tinyDistance_ = 0, cosLimit_ = 0, maxTilt_ = 0;
  std::vector<Sample> samples_;  // the current path's
  std::vector<Vector3d> axes_;   // scratch: its axes for the motion term
  std::vector<double> freedom_;  // and their freedom
  // Gouging: the points printed so far, the cone, the current path's checked positions, the
  // sequence number of each point and the segments it leaves out.
  PrintedPoints printed_;
  struct AwayEntry {
    Vector3d u, away;
    bool tight, hit;
  };
  mutable std::unordered_map<size_t, std::vector<AwayEntry>> awayCache_;  // collidesAway's, per point
  uint32_t nextSeq_ = 0;
  GougingCone cone_;
  GougingCone exactCone_;  // verify's cone: the half-angle alone, points as points
  // verify's half-angle with the points as balls of half the spacing (verify samples the same
  // segments at other points, at most that far from these): where the search's wider cone finds
  // no free axis, and for the check of the axes as the planner prints them.
  GougingCone tightCone_;
  std::vector<uint8_t> tight_;  // per path point: its free axis was found with tightCone_
  size_t exactBad_ = 0;    // bad points the exact cone finds colliding, so far
  std::vector<std::vector<Vector3d>> positions_;
  std::vector<uint32_t> seqOf_;
  std::vector<uint8_t> skip_;  // per path point: the segment ending there is not printed
  std::vector<size_t> selfBlocked_;  // path points with no free axis only because of the path itself
  // The nozzle: where the last move ended, with which axis.
  bool started_ = false, extruded_ = false;
  Vector3d pos_{0, 0, 0}, axis_{0, 0, 1};
};

CurvedToolpathResult buildToolpath(const std::vector<CurvedLayer>& layers,
                                   const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                                   const std::vector<std::pair<uint32_t, uint32_t>>* order,
                                   const CurvedToolpathOptions& options, const ProgressFn& progress) {
  const Outcome input = checkInputs(layers, paths, order, options);
  if (!input.ok()) return failed<CurvedToolpathResult>(input);
  if (!reportProgress(progress, kStage, 0)) return fail(Status::Cancelled, "cancelled");
  CurvedToolpathBuilder builder(layers, paths, options, progress);
  const bool ran = order != nullptr ? builder.printInOrder(*order) : builder.printLayerByLayer();
  if (!ran) return fail(Status::Cancelled, "cancelled");
  if (!reportProgress(progress, kStage, 1)) return fail(Status::Cancelled, "cancelled");
  return builder.result();
}

}  // namespace

CurvedToolpathResult buildCurvedToolpath(const std::vector<CurvedLayer>& layers,
                                         const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                                         const CurvedToolpathOptions& options,
                                         const ProgressFn& progress) {
  return buildToolpath(layers, paths, nullptr, options, progress);
}

CurvedToolpathResult buildCurvedToolpath(const std::vector<CurvedLayer>& layers,
                                         const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                                         const std::vector<std::pair<uint32_t, uint32_t>>& order,
                                         const CurvedToolpathOptions& options,
                                         const ProgressFn& progress) {
  return buildToolpath(layers, paths, &order, options, progress);
}

}  // namespace omnislice
