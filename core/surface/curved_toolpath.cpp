// SPDX-License-Identifier: MIT
// Curved-layer tool-path assembly: orientation by Eq. 3 of paper 001 (Section 5.2), local bead
// height from the distance to the layers printed before (Section 6.2.1: thickness variations are
// compensated by the extrusion), region order by nearest neighbour, travels with retraction and
// leave/approach along the nozzle axis.
#include "surface/curved_toolpath.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "geometry/aabb_tree.h"
#include "motion/orientation_smoothing.h"
#include "toolpath/bead.h"
#include "surface/printed_points.h"

namespace omnislice {

namespace {

using Eigen::Vector3d;

CurvedToolpathResult fail(Status s, std::string message) { return failed<CurvedToolpathResult>(s, std::move(message)); }

bool positiveFinite(double v) { return std::isfinite(v) && v > 0; }
bool nonNegativeFinite(double v) { return std::isfinite(v) && v >= 0; }

// All regions of one layer as one mesh (for one AABB tree per layer).
Mesh mergeLayer(const CurvedLayer& layer) {
  Mesh out;
  for (const LayerRegion& region : layer.regions) {
    const uint32_t base = static_cast<uint32_t>(out.vertexCount());
    out.positions.insert(out.positions.end(), region.mesh.positions.begin(), region.mesh.positions.end());
    for (uint32_t t : region.mesh.triangles) out.triangles.push_back(t + base);
  }
  return out;
}

// Orientation and local height of one path point.
struct Sample {
  Vector3d axis{0, 0, 1};
  double height = 0;
  double distance = std::numeric_limits<double>::infinity();  // |q - c_q|
  int64_t layer = -1, triangle = -1;  // where c_q lies (-1: the platform)
  bool fallback = false;
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

}  // namespace

namespace {

CurvedToolpathResult buildToolpath(const std::vector<CurvedLayer>& layers,
                                   const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                                   const std::vector<std::pair<uint32_t, uint32_t>>* order,
                                   const CurvedToolpathOptions& options, const ProgressFn& progress) {
  const CurvedToolpathOptions& o = options;
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
  if (!(o.coneHalfAngleDegrees > 0 && o.coneHalfAngleDegrees < 90) || !positiveFinite(o.coneLength) ||
      !nonNegativeFinite(o.collisionClearance) || !nonNegativeFinite(o.gougingMarginDegrees) ||
      !nonNegativeFinite(o.maxCorrectionDegrees) || !positiveFinite(o.correctionTaperDegrees) ||
      o.coneHalfAngleDegrees + o.gougingMarginDegrees >= 90) {
    return fail(Status::InvalidOption,
                "gouging cone: half-angle (plus margin) in (0, 90) degrees, length > 0 mm, clearance, "
                "margin and largest correction >= 0, taper > 0");
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
  const char* stage = "toolpath";
  if (!reportProgress(progress, stage, 0)) return fail(Status::Cancelled, "cancelled");

  CurvedToolpathResult result;
  Toolpath& tp = result.toolpath;
  tp.layerCount = static_cast<int32_t>(layers.size());
  double orientationMs = 0;

  // One AABB tree per layer, built when the layer is first needed as an "earlier" layer and kept
  // for the next earlierLayers layers.
  std::vector<std::unique_ptr<AabbTree>> trees(layers.size());
  std::vector<Mesh> merged(layers.size());
  const double hMin = o.minHeightFactor * o.nominalHeight, hMax = o.maxHeightFactor * o.nominalHeight;
  const double tinyDistance = 0.1 * o.nominalHeight;
  const double cosLimit = std::cos(80.0 * kPi / 180.0);

  // Eq. 3 for point q of layer l with surface normal n (may be zero when unknown). The platform
  // plane z = 0 counts as printed before every layer (T in C(V u T)), so a region of a later
  // layer that reaches down to the platform is oriented and sized against it.
  // hint: the axis of the path's previous point (+Z for the first), the side the normal is flipped
  // to where q - c_q is too short to give a direction.
  // prev: the path's previous sample (nullptr for the first): the triangle its c_q lies on gives
  // a near-tight first candidate, so the tree searches prune early.
  auto sampleAt = [&](size_t l, const Vector3d& q, Vector3d n, const Vector3d& hint, const Sample* prev) {
    Sample s;
    if (l == 0) {
      s.axis = Vector3d::UnitZ();
      s.height = o.nominalHeight;
      const double nn = n.norm();
      if (o.axisFromNormals && nn > 0) s.axis = n / nn;
      return s;
    }
    double best = std::max(0.0, q.z());
    Vector3d c(q.x(), q.y(), 0);
    const size_t first = l > size_t(o.earlierLayers) ? l - size_t(o.earlierLayers) : 0;
    if (prev && prev->triangle >= 0) {
      const Mesh& m = merged[size_t(prev->layer)];
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
      if (!trees[k] || trees[k]->triangleCount() == 0) continue;
      const ClosestPoint cp = trees[k]->closest(q, best);
      if (cp.distance < best) {
        best = cp.distance;
        c = cp.point;
        s.layer = int64_t(k);
        s.triangle = cp.triangle;
      }
    }
    s.distance = best;
    s.height = std::clamp(best, hMin, hMax);
    const Vector3d t = q - c;
    const double d = t.norm();
    const double nn = n.norm();
    if (nn > 0) {
      n /= nn;
      // Flip the normal to the side away from the earlier layers (the previous axis of the path
      // when q sits on them: the direction of a tiny q - c_q is rounding noise).
      const Vector3d ref = d >= tinyDistance ? Vector3d(t / d) : hint;
      if (n.dot(ref) < 0) n = -n;
    }
    if (o.axisFromNormals && nn > 0) {
      s.axis = n;  // the normal, on the side away from the earlier layers
      return s;
    }
    if (d >= tinyDistance && (nn == 0 || (t / d).dot(n) >= cosLimit)) {
      s.axis = t / d;
      return s;
    }
    s.fallback = true;
    if (nn > 0) {
      s.axis = n;
    } else {
      s.axis = d >= tinyDistance ? Vector3d(t / d) : hint;
    }
    return s;
  };

  // The machine's tilt range: an axis leaning further from +Z is turned toward +Z in the plane of
  // the two onto the cone of half-angle maxTiltDegrees.
  const double maxTilt = std::clamp(o.maxTiltDegrees, 0.0, 180.0) * kPi / 180.0;
  auto clampTilt = [&](Sample s) {
    const double tilt = std::acos(std::clamp(s.axis.z(), -1.0, 1.0));
    if (tilt <= maxTilt + 1e-12) return s;
    Vector3d horizontal(s.axis.x(), s.axis.y(), 0);
    const double hn = horizontal.norm();
    horizontal = hn > 1e-12 ? Vector3d(horizontal / hn) : Vector3d::UnitX();
    s.axis = std::cos(maxTilt) * Vector3d::UnitZ() + std::sin(maxTilt) * horizontal;
    ++result.tiltClamped;
    return s;
  };


  // ---- gouging correction (paper 001 Section 6.2.3) ----
  constexpr double kDeg = kPi / 180.0;
  constexpr double kSpacing = 0.5;  // mm between printed points, as `omnislice verify` samples
  PrintedPoints printed;
  uint32_t nextSeq = 0;
  GougingCone cone;
  cone.clearance = o.collisionClearance > 0 ? o.collisionClearance : o.nominalHeight;
  cone.length = o.coneLength;
  cone.tanAngle = std::tan((o.coneHalfAngleDegrees + o.gougingMarginDegrees) * kDeg);
  cone.radius = 0.5 * kSpacing;
  double gougingMs = 0;
  // Positions checked for path point i: its segment from point i - 1 (the move ending at i carries
  // its axis), every <= kSpacing mm, both ends.
  std::vector<std::vector<Vector3d>> positions;
  std::vector<uint32_t> seqOf;
  auto pathPositions = [&](const std::vector<Vector3d>& pts) {
    positions.assign(pts.size(), {});
    seqOf.assign(pts.size(), 0);
    for (size_t i = 0; i < pts.size(); ++i) {
      seqOf[i] = nextSeq++;
      if (i == 0) {
        positions[i].push_back(pts[0]);
        continue;
      }
      const double len = (pts[i] - pts[i - 1]).norm();
      const int n = std::max(1, int(std::ceil(len / kSpacing)));
      for (int k = 0; k <= n; ++k) positions[i].push_back(pts[i - 1] + (double(k) / n) * (pts[i] - pts[i - 1]));
    }
  };
  auto collides = [&](size_t i, const Vector3d& u, Vector3d* away) {
    bool any = false;
    for (const Vector3d& p : positions[i]) {
      if (printed.hit(p, u, seqOf[i], cone, away)) {
        any = true;
        if (!away) return true;
      }
    }
    return any;
  };
  // The move ending at point i turns the axis from a0 to a1 on the way (the writers interpolate
  // it): the positions checked with the axis at their share of the turn.
  auto collidesTurning = [&](size_t i, const Vector3d& a0, const Vector3d& a1) {
    const size_t n = positions[i].size();
    const double angle = axisAngleDegrees(a0, a1);
    if (n < 2 || angle < 1) return false;
    // Every <= 0.5 mm and every <= 2 degrees of the turn (the planner's steps).
    const Vector3d& p0 = positions[i].front();
    const Vector3d& p1 = positions[i].back();
    const size_t steps = std::max(n - 1, size_t(std::ceil(angle / 2.0)));
    for (size_t k = 0; k <= steps; ++k) {
      const double t = double(k) / double(steps);
      const Vector3d u = slerpAxis(a0, a1, t);
      if (u.allFinite() && printed.hit(p0 + t * (p1 - p0), u, seqOf[i], cone, nullptr)) return true;
    }
    return false;
  };
  // Free axis near u: rings of increasing angle around u (azimuths from the side away from the
  // offending points); among the free candidates of the first free ring and the next few, the one
  // of least turn + half its angle to ref (the neighbour's axis: consistent turns along a path).
  // False when none within maxCorrectionDegrees and the tilt range.
  auto searchFree = [&](size_t i, Vector3d& u, const Vector3d& ref, double window) {
    Vector3d away = Vector3d::Zero();
    if (!collides(i, u, &away)) return true;
    away -= away.dot(u) * u;
    if (away.norm() < 1e-9) away = u.unitOrthogonal();
    const Vector3d e1 = away.normalized(), e2 = u.cross(e1);
    constexpr int kAzimuths = 48;
    double firstFree = -1, bestCost = std::numeric_limits<double>::infinity();
    Vector3d best = u;
    for (double delta = 2; delta <= o.maxCorrectionDegrees + 1e-9; delta += 2) {
      if (firstFree >= 0 && delta > firstFree + window + 1e-9) break;
      for (int k = 0; k < kAzimuths; ++k) {
        const int step = (k + 1) / 2 * (k % 2 ? 1 : -1);  // 0, +1, -1, +2, -2, ...
        const double phi = 2 * kPi * step / kAzimuths;
        const Vector3d c = (std::cos(delta * kDeg) * u +
                            std::sin(delta * kDeg) * (std::cos(phi) * e1 + std::sin(phi) * e2)).normalized();
        if (std::acos(std::clamp(c.z(), -1.0, 1.0)) > maxTilt + 1e-9) continue;
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
  };
  // One path: its points enter the printed set, then every colliding axis is turned to a free
  // one and the turn is tapered over the neighbours (so the motion planner's low-pass filter,
  // which acts on neighbours more than 10 degrees apart, leaves it), re-checked until stable.
  std::vector<uint8_t> skip;  // per path point: the segment ending there is not printed
  auto correctPath = [&](const std::vector<Vector3d>& pts, std::vector<Sample>& smp, int32_t layer) {
    const auto g0 = Clock::now();
    const size_t np = pts.size();
    skip.assign(np, 0);
    pathPositions(pts);
    for (size_t i = 0; i < np; ++i) {
      for (const Vector3d& p : positions[i]) printed.add(p, seqOf[i]);
    }
    if (!o.correctGouging) return;
    std::vector<Vector3d> base(np);
    for (size_t i = 0; i < np; ++i) base[i] = smp[i].axis;
    // The planner's low-pass filter first, so the check sees the axes it will print with.
    std::vector<int> run(np, 0);
    filterOrientations(base, run, 10.0);
    for (size_t i = 0; i < np; ++i) base[i] = limitTilt(base[i].normalized(), maxTilt);
    std::vector<Vector3d> axes = base;
    std::vector<uint8_t> bad(np, 0), changed(np, 0);
    // noFree[i]: the search around base[i] found no free axis. Whether one exists depends only on
    // the point, its base axis and the printed set, which stays fixed while a path is corrected
    // (the preferred turn and the window only choose among free ones), so it is not searched again.
    std::vector<uint8_t> noFree(np, 0);
    bool anyChange = false;
    for (size_t i = 0; i < np; ++i) {
      Vector3d u = axes[i];
      if (!collides(i, u, nullptr)) continue;
      anyChange = true;
      if (searchFree(i, u, i > 0 ? axes[i - 1] : u, 8)) {
        axes[i] = u;
        changed[i] = 1;
      } else {
        bad[i] = 1;
        noFree[i] = 1;
      }
    }
    // Consistent turns: the changed points again, backward then forward, preferring the turn
    // nearest their neighbour's (a point near the end of a wall may turn either way; the next
    // point under the wall only one).
    if (anyChange) {
      for (int pass = 0; pass < 2; ++pass) {
        for (size_t k = 0; k < np; ++k) {
          const size_t i = pass == 0 ? np - 1 - k : k;
          if (!changed[i]) continue;
          const size_t nb = pass == 0 ? (i + 1 < np ? i + 1 : i) : (i > 0 ? i - 1 : i);
          if (nb == i || !changed[nb]) continue;
          Vector3d u = base[i];
          if (searchFree(i, u, axes[nb], 30)) axes[i] = u;
        }
      }
    }
    if (anyChange) {
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
        const double taper = o.correctionTaperDegrees * kDeg;
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
          next[j] = angle[j] > 0 ? limitTilt((Eigen::AngleAxisd(angle[j], rotAxis[j]) * base[j]).normalized(), maxTilt)
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
    if (anyChange) {
      for (int round = 0; round < 8; ++round) {
        bool any = false;
        for (size_t j = 1; j + 1 < np; ++j) {
          if (axisAngleDegrees(axes[j], axes[j - 1]) <= 6 && axisAngleDegrees(axes[j], axes[j + 1]) <= 6) continue;
          const Vector3d c = limitTilt((axes[j - 1] + 2 * axes[j] + axes[j + 1]).normalized(), maxTilt);
          if (!c.allFinite() || collides(j, c, nullptr)) continue;
          axes[j] = c;
          any = true;
        }
        if (!any) break;
      }
    }
    // Paths without a collision keep their Eq. 3 axes (the planner filters them as checked).
    if (anyChange) {
      for (size_t i = 0; i < np; ++i) {
        result.gougingCorrections += axisAngleDegrees(axes[i], base[i]) > 1e-6;
        smp[i].axis = axes[i];
      }
    }
    if (!o.skipUncorrectable) {
      for (size_t i = 0; i < np; ++i) result.gougingUncorrected += bad[i];
    } else {
      // What the program will do: the motion planner low-pass filters the axes of each run of
      // printed segments (a skipped segment ends a run: a travel follows), a travel arrives with
      // the next point's unfiltered axis, and each move turns the axis on the way. A segment
      // colliding anywhere in that motion is skipped; skips change the runs, so again until none
      // is added.
      std::vector<Vector3d> filtered;
      for (int round = 0; round < 4; ++round) {
        std::vector<int> runs(np, -1);
        int id = 0;
        for (size_t i = 1; i < np; ++i) {
          if (skip[i]) {
            ++id;
            continue;
          }
          runs[i] = id;
        }
        filtered.resize(np);
        for (size_t i = 0; i < np; ++i) filtered[i] = smp[i].axis;
        filterOrientations(filtered, runs, 10.0);
        bool added = false;
        for (size_t i = 1; i < np; ++i) {
          if (skip[i]) continue;
          // The travel to point i - 1 arrives with the axis of point 0 (path start) or of point i
          // (after a skipped segment).
          const Vector3d& from = i == 1 ? smp[0].axis : skip[i - 1] ? smp[i].axis : filtered[i - 1];
          if (!collides(i, filtered[i], nullptr) && !collidesTurning(i, from, filtered[i])) continue;
          skip[i] = 1;
          added = true;
          ++result.skippedPoints;
          result.skippedMm += (pts[i] - pts[i - 1]).norm();
          result.skippedEnds.push_back(pts[i - 1]);
          result.skippedEnds.push_back(pts[i]);
          result.skippedLayers.push_back(layer);
          // Later checks see only what is printed.
          for (size_t k = 1; k < positions[i].size(); ++k) printed.retire(positions[i][k], seqOf[i]);
        }
        if (!added) break;
      }
      for (size_t i = 0; i < np; ++i) result.gougingUncorrected += skip[i];
    }
    gougingMs += msSince(g0);
  };

  bool started = false, extruded = false;
  Vector3d pos(0, 0, 0), axis(0, 0, 1);
  auto push = [&](const Vector3d& p, const Vector3d& u, MoveKind kind, int32_t layer) {
    Move m;
    m.position = p;
    m.axis = u;
    m.kind = kind;
    m.layer = layer;
    tp.moves.push_back(m);
    return &tp.moves.back();
  };
  // Travel to s (nozzle axis u there). Long travels retract, leave along the current axis by the
  // clearance, cross over at clearance height and approach along u.
  auto travelTo = [&](const Vector3d& s, const Vector3d& u, int32_t layer) {
    if (!started) {
      tp.start = s + o.travelClearance * u;
      pos = tp.start;
      axis = u;
      started = true;
    }
    const double len = (s - pos).norm();
    if (len <= 1e-9) {
      pos = s;
      axis = u;
      return;
    }
    const bool retract = o.retractLength > 0 && extruded && len > o.retractMinTravel;
    if (retract) {
      Move* r = push(pos, axis, MoveKind::Retract, layer);
      r->filament = -o.retractLength;
      r->speed = o.retractSpeed;
      if (o.travelClearance > 0) {
        push(pos + o.travelClearance * axis, axis, MoveKind::Travel, layer)->speed = o.travelSpeed;
        push(s + o.travelClearance * u, u, MoveKind::Travel, layer)->speed = o.travelSpeed;
      }
    }
    push(s, u, MoveKind::Travel, layer)->speed = o.travelSpeed;
    if (retract) {
      Move* r = push(s, u, MoveKind::Unretract, layer);
      r->filament = o.retractLength;
      r->speed = o.retractSpeed;
    }
    pos = s;
    axis = u;
  };

  std::vector<Sample> samples;
  // The earlier layers' trees for layer l. Layer by layer, trees below the window are freed; in a
  // given order (layers revisited), they are kept.
  auto prepareTrees = [&](size_t l, bool freeBelow) {
    if (l == 0) return;
    const size_t first = l > size_t(o.earlierLayers) ? l - size_t(o.earlierLayers) : 0;
    if (freeBelow) {
      for (size_t k = 0; k < first; ++k) {
        trees[k].reset();
        merged[k] = Mesh();
      }
    }
    for (size_t k = first; k < l; ++k) {
      if (trees[k]) continue;
      merged[k] = mergeLayer(layers[k]);
      trees[k] = std::make_unique<AabbTree>(merged[k]);
    }
  };
  // Print region `pick` of layer l; progress reports the fraction `done` of the whole.
  auto printRegion = [&](size_t l, size_t pick, double done) {
    const int32_t layer = static_cast<int32_t>(l);
    const double speed = l == 0 ? o.firstLayerSpeed : o.printSpeed;
    const bool support = layers[l].regions[pick].support;
    const Feature feature = support ? Feature::Support : Feature::Infill;
    const MoveKind printKind = support ? MoveKind::Support : MoveKind::Print;
    for (const SurfacePath& path : paths[l][pick]) {
      const size_t np = path.points.size();
      if (np < 2) continue;
      const double width = path.width > 0 ? std::min(path.width, o.lineWidth) : o.lineWidth;
      const auto s0 = Clock::now();
      samples.resize(np);
      const bool haveNormals = path.normals.size() == np;
      for (size_t i = 0; i < np; ++i) {
        // Long paths: keep cancellation within a few milliseconds (~10 us per point).
        if ((i & 1023) == 1023 && !reportProgress(progress, stage, done)) return false;
        Vector3d nrm = haveNormals && path.normals[i].allFinite() ? path.normals[i] : Vector3d::Zero();
        samples[i] = clampTilt(sampleAt(l, path.points[i], nrm,
                                        i > 0 ? samples[i - 1].axis : Vector3d::UnitZ(),
                                        i > 0 ? &samples[i - 1] : nullptr));
        result.orientationFallbacks += samples[i].fallback;
      }
      orientationMs += msSince(s0);
      correctPath(path.points, samples, layer);
      travelTo(path.points[0], samples[0].axis, layer);
      for (size_t i = 1; i < np; ++i) {
        if (skip[i]) continue;
        if ((path.points[i - 1] - pos).norm() > 1e-9) travelTo(path.points[i - 1], samples[i].axis, layer);
        const Vector3d& target = path.points[i];
        const double len = (target - pos).norm();
        if (len <= 1e-9) continue;
        // The bead of a segment takes the mean of its end heights.
        const double h = 0.5 * (samples[i - 1].height + samples[i].height);
        Move* m = push(target, samples[i].axis, printKind, layer);
        m->width = width;
        m->height = h;
        m->filament = o.ellipseBeads ? ellipseBeadFilament(width, h, len, o.filamentDiameter)
                                     : filamentForBead(width, h, len, o.filamentDiameter);
        if (path.curves.size() == np) m->curve = path.curves[i];
        m->speed = speed;
        m->feature = feature;
        pos = target;
        axis = samples[i].axis;
        extruded = true;
      }
    }
    return true;
  };

  if (order != nullptr) {
    for (size_t k = 0; k < order->size(); ++k) {
      const double done = double(k) / double(order->size());
      if (!reportProgress(progress, stage, done)) return fail(Status::Cancelled, "cancelled");
      const size_t l = (*order)[k].first, r = (*order)[k].second;
      const auto t0 = Clock::now();
      prepareTrees(l, false);
      orientationMs += msSince(t0);
      if (!printRegion(l, r, done)) return fail(Status::Cancelled, "cancelled");
    }
  }
  for (size_t l = 0; order == nullptr && l < layers.size(); ++l) {
    if (!reportProgress(progress, stage, double(l) / double(layers.size()))) {
      return fail(Status::Cancelled, "cancelled");
    }
    const auto t0 = Clock::now();
    prepareTrees(l, true);
    orientationMs += msSince(t0);

    // Regions nearest-first from the current position (distance to the first path's start).
    const size_t nr = layers[l].regions.size();
    std::vector<uint8_t> done(nr, 0);
    for (size_t n = 0; n < nr; ++n) {
      size_t pick = nr;
      double bestD = std::numeric_limits<double>::infinity();
      for (size_t r = 0; r < nr; ++r) {
        if (done[r]) continue;
        const Vector3d* startPoint = nullptr;
        for (const SurfacePath& p : paths[l][r]) {
          if (p.points.size() >= 2) {
            startPoint = &p.points.front();
            break;
          }
        }
        const double dist = startPoint ? (*startPoint - pos).norm() : 0;  // pathless regions: free
        if (pick == nr || dist < bestD) {
          pick = r;
          bestD = dist;
        }
      }
      done[pick] = 1;
      if (!printRegion(l, pick, (double(l) + double(n) / double(nr)) / double(layers.size()))) {
        return fail(Status::Cancelled, "cancelled");
      }
    }
  }
  result.orientationMs = orientationMs;
  result.gougingMs = gougingMs;
  if (!reportProgress(progress, stage, 1)) return fail(Status::Cancelled, "cancelled");
  return result;
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
