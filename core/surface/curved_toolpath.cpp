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

#include "geometry/aabb_tree.h"
#include "slice/plan_layers.h"

namespace omnislice {

namespace {

using Eigen::Vector3d;

CurvedToolpathResult fail(Status s, std::string message) {
  CurvedToolpathResult r;
  r.status = s;
  r.message = std::move(message);
  return r;
}

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

}  // namespace

CurvedToolpathResult buildCurvedToolpath(const std::vector<CurvedLayer>& layers,
                                         const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                                         const CurvedToolpathOptions& options,
                                         const ProgressFn& progress) {
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
  const char* stage = "toolpath";
  if (!reportProgress(progress, stage, 0)) return fail(Status::Cancelled, "cancelled");

  CurvedToolpathResult result;
  Toolpath& tp = result.toolpath;
  tp.layerCount = static_cast<int32_t>(layers.size());
  using Clock = std::chrono::steady_clock;
  double orientationMs = 0;

  // One AABB tree per layer, built when the layer is first needed as an "earlier" layer and kept
  // for the next earlierLayers layers.
  std::vector<std::unique_ptr<AabbTree>> trees(layers.size());
  std::vector<Mesh> merged(layers.size());
  const double hMin = o.minHeightFactor * o.nominalHeight, hMax = o.maxHeightFactor * o.nominalHeight;
  const double tinyDistance = 0.1 * o.nominalHeight;
  const double cosLimit = std::cos(80.0 * 3.14159265358979323846 / 180.0);

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
  const double maxTilt = std::clamp(o.maxTiltDegrees, 0.0, 180.0) * 3.14159265358979323846 / 180.0;
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
  for (size_t l = 0; l < layers.size(); ++l) {
    if (!reportProgress(progress, stage, double(l) / double(layers.size()))) {
      return fail(Status::Cancelled, "cancelled");
    }
    const auto t0 = Clock::now();
    if (l > 0) {
      const size_t first = l > size_t(o.earlierLayers) ? l - size_t(o.earlierLayers) : 0;
      for (size_t k = 0; k < first; ++k) {
        trees[k].reset();
        merged[k] = Mesh();
      }
      for (size_t k = first; k < l; ++k) {
        if (trees[k]) continue;
        merged[k] = mergeLayer(layers[k]);
        trees[k] = std::make_unique<AabbTree>(merged[k]);
      }
    }
    orientationMs += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const int32_t layer = static_cast<int32_t>(l);
    const double speed = l == 0 ? o.firstLayerSpeed : o.printSpeed;

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
      const bool support = layers[l].regions[pick].support;
      const Feature feature = support ? Feature::Support : Feature::Infill;
      const MoveKind printKind = support ? MoveKind::Support : MoveKind::Print;
      for (const SurfacePath& path : paths[l][pick]) {
        const size_t np = path.points.size();
        if (np < 2) continue;
        const auto s0 = Clock::now();
        samples.resize(np);
        const bool haveNormals = path.normals.size() == np;
        for (size_t i = 0; i < np; ++i) {
          // Long paths: keep cancellation within a few milliseconds (~10 us per point).
          if ((i & 1023) == 1023 &&
              !reportProgress(progress, stage, (double(l) + double(n) / double(nr)) / double(layers.size()))) {
            return fail(Status::Cancelled, "cancelled");
          }
          Vector3d nrm = haveNormals && path.normals[i].allFinite() ? path.normals[i] : Vector3d::Zero();
          samples[i] = clampTilt(sampleAt(l, path.points[i], nrm,
                                          i > 0 ? samples[i - 1].axis : Vector3d::UnitZ(),
                                          i > 0 ? &samples[i - 1] : nullptr));
          result.orientationFallbacks += samples[i].fallback;
        }
        orientationMs += std::chrono::duration<double, std::milli>(Clock::now() - s0).count();
        travelTo(path.points[0], samples[0].axis, layer);
        for (size_t i = 1; i < np; ++i) {
          const Vector3d& target = path.points[i];
          const double len = (target - pos).norm();
          if (len <= 1e-9) continue;
          // The bead of a segment takes the mean of its end heights.
          const double h = 0.5 * (samples[i - 1].height + samples[i].height);
          Move* m = push(target, samples[i].axis, printKind, layer);
          m->width = o.lineWidth;
          m->height = h;
          m->filament = filamentForBead(o.lineWidth, h, len, o.filamentDiameter);
          m->speed = speed;
          m->feature = feature;
          pos = target;
          axis = samples[i].axis;
          extruded = true;
        }
      }
    }
  }
  result.orientationMs = orientationMs;
  if (!reportProgress(progress, stage, 1)) return fail(Status::Cancelled, "cancelled");
  return result;
}

}  // namespace omnislice
