// SPDX-License-Identifier: MIT
// Iso-planar NL curves (paper 003 Algorithm 2): plane sweep over triangles sorted by their span
// along q, crossings linked per plane, Eq. 12 forward step, Eq. 14 side step (tilt-corrected, see
// the header), zig-zag ordering and boundary joins. The surface's topology is built by
// isoplanar_topology.cpp, the printing-time estimate is isoplanar_time.cpp.
#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "isoplanar/isoplanar_paths.h"
#include "isoplanar/isoplanar_topology.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

namespace omnislice {

// Direction-independent data of a prepared surface.
struct IsoplanarSurface::Data {
  Mesh mesh;
  std::vector<SurfaceSample> samples;
  isoplanar_detail::Topology topo;
  std::vector<Eigen::Matrix3d> tensors;  // shape tensors in the part frame
  double scale = 0;                      // bounding-box diagonal, mm
};

namespace {

using isoplanar_detail::kNone;
using isoplanar_detail::Topology;
constexpr double kInf = std::numeric_limits<double>::infinity();

IsoplanarResult fail(Status s, std::string message) { return failed<IsoplanarResult>(s, std::move(message)); }

// One crossing of the current plane with a mesh edge.
struct Node {
  uint32_t edge = 0;
  double t = 0;  // from ea to eb
  Eigen::Vector3d p{0, 0, 0};
  uint32_t adj[2] = {kNone, kNone};
};

// Geometry of a crossing for the width and the forward step.
struct PointEval {
  Eigen::Vector3d normal{0, 0, 1};
  double kappaFeed = 0;   // normal curvature along f
  double kappaCross = 0;  // normal curvature along k
  double height = 0;
  double cross = 1;       // |k.q| = |n x q|
  double width = 0;       // w_eff
};

// A monotone stand-in for atan2(y, x) on (-pi, pi], values in [-2, 2] (no trigonometry).
double pseudoAngle(double x, double y) {
  const double ax = std::abs(x), ay = std::abs(y);
  if (ax + ay == 0) return 0;
  const double t = x >= 0 ? ay / (ax + ay) : 2 - ay / (ax + ay);
  return y >= 0 ? t : -t;
}

struct Planner {
  const Mesh& mesh;
  const std::vector<SurfaceSample>& samples;
  const WidthFn& widthFn;
  const IsoplanarOptions& options;
  const Topology& topo;
  const std::vector<Eigen::Matrix3d>& tensors;
  std::vector<double> dist;  // q.x per vertex
  Eigen::Vector3d q{0, 1, 0}, u{1, 0, 0};
  // Per-plane scratch.
  std::vector<uint32_t> edgeStamp, edgeNode;
  std::vector<Node> nodes;
  std::vector<uint8_t> visited;
  uint32_t stamp = 0;
  std::string error;

  Planner(const IsoplanarSurface::Data& d, const WidthFn& w, const IsoplanarOptions& o)
      : mesh(d.mesh), samples(d.samples), widthFn(w), options(o), topo(d.topo), tensors(d.tensors) {}

  // Crossings of the plane q.x = c with the given triangles, linked.
  void cut(double c, const std::vector<uint32_t>& crossed) {
    ++stamp;
    nodes.clear();
    // The node of edge e with a free link; an edge of more than two triangles gets a further
    // node (same point) once its node has two links.
    auto nodeOf = [&](uint32_t e) {
      if (edgeStamp[e] == stamp && nodes[edgeNode[e]].adj[1] == kNone) return edgeNode[e];
      edgeStamp[e] = stamp;
      const uint32_t id = static_cast<uint32_t>(nodes.size());
      edgeNode[e] = id;
      Node n;
      n.edge = e;
      const uint32_t a = topo.ea[e], b = topo.eb[e];
      const double da = dist[a], db = dist[b];
      n.t = std::clamp((c - da) / (db - da), 0.0, 1.0);
      n.p = (1 - n.t) * mesh.vertex(a) + n.t * mesh.vertex(b);
      nodes.push_back(n);
      return id;
    };
    for (uint32_t k : crossed) {
      const uint32_t* v = &topo.tris[3 * k];
      const bool above[3] = {dist[v[0]] >= c, dist[v[1]] >= c, dist[v[2]] >= c};
      uint32_t ends[2];
      int count = 0;
      for (int j = 0; j < 3; ++j) {
        if (above[j] != above[(j + 1) % 3] && count < 2) ends[count++] = nodeOf(topo.triEdge[3 * k + j]);
      }
      if (count != 2) continue;
      Node& n0 = nodes[ends[0]];
      (n0.adj[0] == kNone ? n0.adj[0] : n0.adj[1]) = ends[1];
      Node& n1 = nodes[ends[1]];
      (n1.adj[0] == kNone ? n1.adj[0] : n1.adj[1]) = ends[0];
    }
  }

  // Connected components of the linked crossings: node sequences (closed loops not repeated).
  void components(std::vector<std::vector<uint32_t>>& out, std::vector<uint8_t>& closed) {
    out.clear();
    closed.clear();
    visited.assign(nodes.size(), 0);
    auto walk = [&](uint32_t n0) {
      std::vector<uint32_t> seq{n0};
      visited[n0] = 1;
      uint32_t cur = n0;
      for (;;) {
        uint32_t next = kNone;
        for (uint32_t a : nodes[cur].adj) {
          if (a != kNone && !visited[a]) {
            next = a;
            break;
          }
        }
        if (next == kNone) break;
        visited[next] = 1;
        seq.push_back(next);
        cur = next;
      }
      const Node& last = nodes[cur];
      const bool loop = seq.size() >= 3 && (last.adj[0] == n0 || last.adj[1] == n0);
      out.push_back(std::move(seq));
      closed.push_back(loop ? 1 : 0);
    };
    for (uint32_t n = 0; n < nodes.size(); ++n) {
      if (!visited[n] && (nodes[n].adj[0] == kNone) != (nodes[n].adj[1] == kNone)) walk(n);
    }
    for (uint32_t n = 0; n < nodes.size(); ++n) {
      if (!visited[n]) walk(n);
    }
  }

  // Local geometry and w_eff at a point on edge e at t. False when the width is unusable.
  bool evaluate(uint32_t e, double t, PointEval& out) {
    const uint32_t a = topo.ea[e], b = topo.eb[e];
    Eigen::Vector3d n = (1 - t) * samples[a].normal + t * samples[b].normal;
    const double len = n.norm();
    n = len > 1e-12 ? Eigen::Vector3d(n / len) : samples[t < 0.5 ? a : b].normal.normalized();
    const Eigen::Matrix3d tensor = (1 - t) * tensors[a] + t * tensors[b];
    const Eigen::Vector3d nq = n.cross(q);
    const double cross = nq.norm();
    Eigen::Vector3d f, k;
    if (cross > 1e-9) {
      f = nq / cross;
    } else {  // plane tangent to the surface: any tangent direction in the plane
      f = n.cross(u).normalized();
    }
    k = n.cross(f);
    out.normal = n;
    out.kappaFeed = f.dot(tensor * f);
    out.kappaCross = k.dot(tensor * k);
    out.height = (1 - t) * samples[a].height + t * samples[b].height;
    out.cross = cross;
    out.width = widthFn(out.kappaCross, out.height);
    if (!(std::isfinite(out.width) && out.width > 0)) {
      error = "effective width " + std::to_string(out.width) + " at curvature " +
              std::to_string(out.kappaCross) + ", height " + std::to_string(out.height) +
              " is not positive";
      return false;
    }
    return true;
  }

  // Forward step of Eq. 12 at a point.
  double forwardLimit(const PointEval& pe) const {
    const double dc = options.chordError;
    double lf = kInf;
    const double kf = std::abs(pe.kappaFeed);
    if (kf > 1e-12) {
      const double r = 1 / kf;
      const double s = 8 * dc * r - 4 * dc * dc;
      lf = s > 0 ? std::sqrt(s) : 0.0;
    }
    if (options.maxStep > 0) lf = std::min(lf, options.maxStep);
    return lf;
  }

  // Samples the raw crossing sequence (points P, closed: P.back() == P.front()) into kept indices.
  void sample(const std::vector<Eigen::Vector3d>& pts, const std::vector<PointEval>& evals,
              std::vector<uint32_t>& keep) const {
    keep.clear();
    const size_t m = pts.size();
    if (m == 0) return;
    keep.push_back(0);
    const double dc = options.chordError;
    size_t i = 0;
    while (i + 1 < m) {
      const double lf = forwardLimit(evals[i]);
      // Drive-plane coordinates (the curve is planar): x along u, y along z.
      auto planar = [&](size_t j) {
        const Eigen::Vector3d d = pts[j] - pts[i];
        return Eigen::Vector2d(d.dot(u), d.z());
      };
      size_t best = i + 1;
      // Cone of chord directions passing within dc of every intermediate point (angles
      // relative to `ref`), plus the farthest intermediate distance for the segment ends.
      bool haveRef = false;
      Eigen::Vector2d ref(1, 0);
      double lo = -kInf, hi = kInf, far = 0;
      for (size_t j = i + 1; j < m; ++j) {
        const Eigen::Vector2d d = planar(j);
        const double len = d.norm();
        if (j > i + 1) {
          if (len > lf) break;
          // Is pts[j] a valid chord end? Its direction must lie in the cone.
          bool ok = true;
          if (len > 0) {
            if (!haveRef) {
              ref = d / len;
              haveRef = true;
            }
            const double ang = pseudoAngle(ref.dot(d), ref.x() * d.y() - ref.y() * d.x());
            ok = ang >= lo && ang <= hi;
          }
          if (ok && far > len) {  // an intermediate point beyond the chord's end: check exactly
            for (size_t k = i + 1; k < j && ok; ++k) {
              const Eigen::Vector3d ab = pts[j] - pts[i];
              const double l2 = ab.squaredNorm();
              const double tt = l2 > 0 ? std::clamp((pts[k] - pts[i]).dot(ab) / l2, 0.0, 1.0) : 0.0;
              ok = (pts[k] - (pts[i] + tt * ab)).norm() <= dc;
            }
          }
          if (!ok) break;
          best = j;
        }
        // Add pts[j] as an intermediate constraint for farther chord ends.
        far = std::max(far, len);
        if (len > dc) {
          if (!haveRef) {
            ref = d / len;
            haveRef = true;
          }
          // The directions within asin(dc / len) of pts[j]'s: its direction (relative to ref)
          // rotated both ways, mapped by the monotone pseudo-angle.
          const double x = ref.dot(d) / len, y = (ref.x() * d.y() - ref.y() * d.x()) / len;
          const double sn = dc / len, cs = std::sqrt(std::max(0.0, 1 - sn * sn));
          const double a0 = pseudoAngle(x * cs + y * sn, y * cs - x * sn);
          const double a1 = pseudoAngle(x * cs - y * sn, y * cs + x * sn);
          if (a0 > a1) break;  // the interval wraps past -pi/pi: the curve turns back
          lo = std::max(lo, a0);
          hi = std::min(hi, a1);
          if (lo > hi) break;
        }
      }
      if ((pts[best] - pts[keep.back()]).norm() > 1e-12 || best + 1 == m) {
        if ((pts[best] - pts[keep.back()]).norm() <= 1e-12 && keep.size() > 1) keep.pop_back();
        keep.push_back(static_cast<uint32_t>(best));
      }
      i = best;
    }
  }
};

double polylineLength(const std::vector<Eigen::Vector3d>& p) {
  double l = 0;
  for (size_t i = 1; i < p.size(); ++i) l += (p[i] - p[i - 1]).norm();
  return l;
}

}  // namespace

IsoplanarSurface prepareIsoplanarSurface(const Mesh& surface,
                                         const std::vector<SurfaceSample>& samples) {
  const auto t0 = Clock::now();
  IsoplanarSurface out;
  auto bad = [&](Status st, std::string message) {
    out.status = st;
    out.message = std::move(message);
    out.data.reset();
    return out;
  };
  if (surface.empty() || surface.vertexCount() == 0) return bad(Status::EmptyInput, "empty surface");
  if (surface.triangles.size() % 3 != 0 || surface.positions.size() % 3 != 0) {
    return bad(Status::InvalidOption, "mesh arrays are not multiples of 3");
  }
  if (samples.size() != surface.vertexCount()) {
    return bad(Status::InvalidOption, "samples: " + std::to_string(samples.size()) + " for " +
                                          std::to_string(surface.vertexCount()) +
                                          " vertices (one per vertex expected)");
  }
  const size_t nv = surface.vertexCount();
  for (double x : surface.positions) {
    if (!std::isfinite(x)) return bad(Status::NonFiniteVertex, "non-finite vertex coordinate");
  }
  for (uint32_t v : surface.triangles) {
    if (v >= nv) return bad(Status::InvalidOption, "triangle index out of range");
  }
  for (const SurfaceSample& s : samples) {
    if (!s.normal.allFinite() || !s.shape.allFinite() || !s.tangentU.allFinite() ||
        !s.tangentV.allFinite() || !std::isfinite(s.height) || s.normal.norm() < 1e-12) {
      return bad(Status::NonFiniteVertex, "a surface sample is not finite or has no normal");
    }
  }
  auto data = std::make_shared<IsoplanarSurface::Data>();
  data->mesh = surface;
  data->samples = samples;
  buildTopology(surface, data->topo);
  if (data->topo.tris.empty()) return bad(Status::EmptyInput, "no non-degenerate triangles");
  data->tensors.resize(nv);
  for (size_t v = 0; v < nv; ++v) {
    Eigen::Matrix<double, 3, 2> basis;
    basis.col(0) = samples[v].tangentU;
    basis.col(1) = samples[v].tangentV;
    data->tensors[v] = basis * samples[v].shape * basis.transpose();
  }
  const BoundingBox box = boundingBox(surface);
  data->scale = (box.max - box.min).norm();
  out.data = std::move(data);
  out.ms = msSince(t0);
  return out;
}

IsoplanarResult isoplanarPaths(const Mesh& surface, const std::vector<SurfaceSample>& samples,
                               const WidthFn& width, const IsoplanarOptions& options,
                               const ProgressFn& progress) {
  const auto t0 = Clock::now();
  const IsoplanarSurface prepared = prepareIsoplanarSurface(surface, samples);
  if (!prepared.ok()) return fail(prepared.status, prepared.message);
  IsoplanarResult r = isoplanarPaths(prepared, width, options, progress);
  r.ms = msSince(t0);
  return r;
}

namespace {

// The options of isoplanarPaths: InvalidOption (or the preparation's status) when unusable.
Outcome checkPathOptions(const IsoplanarSurface& prepared, const WidthFn& width, const IsoplanarOptions& options) {
  auto fail = [](Status s, std::string message) { return failed<Outcome>(s, std::move(message)); };
  if (!prepared.ok() || !prepared.data) {
    return fail(prepared.ok() ? Status::EmptyInput : prepared.status,
                prepared.message.empty() ? "surface not prepared" : prepared.message);
  }
  if (!width) return fail(Status::InvalidOption, "no width function");
  if (!std::isfinite(options.thetaDegrees)) return fail(Status::InvalidOption, "theta is not finite");
  if (!(std::isfinite(options.chordError) && options.chordError > 0)) {
    return fail(Status::InvalidOption, "chord error must be positive and finite");
  }
  if (!(std::isfinite(options.maxStep) && options.maxStep >= 0)) {
    return fail(Status::InvalidOption, "max step must be >= 0 and finite");
  }
  if (!(std::isfinite(options.minCross) && options.minCross > 0 && options.minCross <= 1)) {
    return fail(Status::InvalidOption, "minCross must be in (0, 1]");
  }
  if (!(std::isfinite(options.connectFactor) && options.connectFactor >= 0)) {
    return fail(Status::InvalidOption, "connect factor must be >= 0 and finite");
  }
  return {};
}

// One plane's curve before sampling: its crossings (unordered components).
struct RawCurve {
  std::vector<uint32_t> nodes;
  bool closed = false;
  double uMean = 0;
};

// A curve of the sweep, waiting for the print order.
struct PoolCurve {
  NlCurve curve;            // sampled (open curves); loops are sampled once their start is known
  std::vector<Node> raw;    // loops: the crossings (not repeated), oriented
  std::vector<PointEval> rawEval;
  uint32_t firstEdge = kNone, lastEdge = kNone;  // raw edges of the ends (open curves)
  double firstT = 0, lastT = 0;
  double step = 0;          // the side step computed on its plane
  size_t plane = 0;         // index among the planes with curves
};

// A curve end as a boundary-loop position: loop, segment index, arc position.
struct LoopPos {
  uint32_t loop = kNone;
  uint32_t index = 0;
  double s = 0;
};

// An end of a curve: position, normal, edge fields, raw edge.
struct End {
  Eigen::Vector3d p{0, 0, 0}, n{0, 0, 1};
  uint32_t a = 0, b = 0;
  float t = 0;
  uint32_t edge = kNone;
  double rawT = 0;
};

End endOf(const PoolCurve& pc, bool last) {
  const NlCurve& cv = pc.curve;
  const size_t i = last ? cv.points.size() - 1 : 0;
  End e;
  e.p = cv.points[i];
  e.n = cv.normals[i];
  e.a = cv.edgeA[i];
  e.b = cv.edgeB[i];
  e.t = cv.edgeT[i];
  e.edge = last ? pc.lastEdge : pc.firstEdge;
  e.rawT = last ? pc.lastT : pc.firstT;
  return e;
}

// The raw crossing of a loop nearest to a point.
size_t nearestRaw(const PoolCurve& pc, const Eigen::Vector3d& p, double& d) {
  size_t best = 0;
  double bd = kInf;
  for (size_t i = 0; i < pc.raw.size(); ++i) {
    const double di = (pc.raw[i].p - p).squaredNorm();
    if (di < bd) {
      bd = di;
      best = i;
    }
  }
  d = std::sqrt(bd);
  return best;
}

// The NL curves of one drive direction: the plane sweep (Eq. 12 forward steps, Eq. 14 side
// steps) into a pool of curves per plane, then the print order (boustrophedon chains joined
// along the boundary), then the paths.
class IsoplanarBuilder {
 public:
  IsoplanarBuilder(const IsoplanarSurface::Data& data, const WidthFn& width, const IsoplanarOptions& options)
      : surface_(data.mesh), samples_(data.samples), width_(width), options_(options), pl_(data, width, options),
        nt_(pl_.topo.tris.size() / 3), scale_(data.scale) {
    const size_t nv = surface_.vertexCount();
    const double theta = options.thetaDegrees * kPi / 180.0;
    pl_.q = Eigen::Vector3d(-std::sin(theta), std::cos(theta), 0);
    pl_.u = Eigen::Vector3d(std::cos(theta), std::sin(theta), 0);
    pl_.dist.resize(nv);
    for (size_t v = 0; v < nv; ++v) pl_.dist[v] = pl_.q.dot(surface_.vertex(v));
    pl_.edgeStamp.assign(pl_.topo.ea.size(), 0);
    pl_.edgeNode.assign(pl_.topo.ea.size(), 0);
    sortTriangles();
  }

  // False when the surface lies in one drive plane: no curve (not an error).
  bool hasExtent() const { return extent_ > 1e-9 * std::max(scale_, 1e-9); }

  // The planes from the first to the last, their curves into the pool; the plane count and side
  // step range into result. InvalidOption (width, step, planes) or Cancelled.
  Outcome sweep(const ProgressFn& progress, IsoplanarResult& result) {
    eps_ = 1e-9 * std::max(extent_, scale_);
    double c = 0, step = 0;
    Outcome ok = firstPlane(c, step);
    if (!ok.ok()) return ok;
    ok = sweepFrom(c, step, progress);
    if (!ok.ok()) return ok;
    sideStepRange(result);
    return {};
  }

  // ---- Print order: boustrophedon chains joined along the boundary. ----
  void chainCurves() {
    printed_.assign(pool_.size(), 0);
    remaining_ = pool_.size();
    size_t lowest = 0;
    while (remaining_ > 0) {
      while (lowest < planeCurves_.size() &&
             std::all_of(planeCurves_[lowest].begin(), planeCurves_[lowest].end(),
                         [&](uint32_t i) { return printed_[i] != 0; })) {
        ++lowest;
      }
      if (lowest >= planeCurves_.size()) break;
      uint32_t cur = startChain(lowest);
      size_t plane = pool_[cur].plane;
      // Follow the chain: the next plane's curve whose end joins this curve's end.
      while (plane + 1 < planeCurves_.size()) {
        const uint32_t nextCurve = joinNext(cur, plane + 1);
        if (nextCurve == kNone) break;
        cur = nextCurve;
        ++plane;
      }
    }
  }

  // ---- Curves in print order, joins, paths. ----
  void assemblePaths(IsoplanarResult& result) {
    for (size_t k = 0; k < printOrder_.size(); ++k) {
      NlCurve& cv = pool_[printOrder_[k]].curve;
      if (cv.closed) ++result.closedCurves;
      result.pathMm += polylineLength(cv.points);
      if (k == 0 || !joinedToNext_[k - 1]) {
        result.paths.emplace_back();
        result.pathCurves.emplace_back();
        result.pathJoins.emplace_back();
        result.paths.back().points = cv.points;
        result.paths.back().normals = cv.normals;
        result.pathPointCurve.emplace_back(cv.points.size(), static_cast<uint32_t>(k + 1));
      } else {
        IsoplanarJoin& j = joinAfter_[k - 1];
        j.fromCurve = static_cast<uint32_t>(k - 1);
        j.toCurve = static_cast<uint32_t>(k);
        SurfacePath& sp = result.paths.back();
        sp.points.insert(sp.points.end(), j.points.begin() + 1, j.points.end() - 1);
        sp.normals.insert(sp.normals.end(), j.normals.begin() + 1, j.normals.end() - 1);
        sp.points.insert(sp.points.end(), cv.points.begin(), cv.points.end());
        sp.normals.insert(sp.normals.end(), cv.normals.begin(), cv.normals.end());
        std::vector<uint32_t>& pc = result.pathPointCurve.back();
        pc.insert(pc.end(), j.points.size() - 2, 0u);
        pc.insert(pc.end(), cv.points.size(), static_cast<uint32_t>(k + 1));
        result.pathMm += j.length;
        result.pathJoins.back().push_back(static_cast<uint32_t>(result.joins.size()));
        result.joins.push_back(std::move(j));
      }
      result.pathCurves.back().push_back(static_cast<uint32_t>(k));
      result.curves.push_back(std::move(cv));
    }
  }

 private:
  // Triangles sorted by the low end of their span along q.
  void sortTriangles() {
    lo_.resize(nt_);
    hi_.resize(nt_);
    for (size_t k = 0; k < nt_; ++k) {
      const uint32_t* v = &pl_.topo.tris[3 * k];
      lo_[k] = std::min({pl_.dist[v[0]], pl_.dist[v[1]], pl_.dist[v[2]]});
      hi_[k] = std::max({pl_.dist[v[0]], pl_.dist[v[1]], pl_.dist[v[2]]});
      dmin_ = std::min(dmin_, lo_[k]);
      dmax_ = std::max(dmax_, hi_[k]);
    }
    std::vector<std::pair<double, uint32_t>> sorted(nt_);
    for (uint32_t k = 0; k < nt_; ++k) sorted[k] = {lo_[k], k};
    std::sort(sorted.begin(), sorted.end());
    order_.resize(nt_);
    for (size_t k = 0; k < nt_; ++k) order_[k] = sorted[k].second;
    extent_ = dmax_ - dmin_;
  }

  // Evaluate every crossing: min over the plane's points of w_eff |k.q| (floored).
  bool planeStep(double& step) {
    nodeEval_.resize(pl_.nodes.size());
    step = kInf;
    for (size_t n = 0; n < pl_.nodes.size(); ++n) {
      if (!pl_.evaluate(pl_.nodes[n].edge, pl_.nodes[n].t, nodeEval_[n])) return false;
      step = std::min(step, nodeEval_[n].width * std::max(nodeEval_[n].cross, options_.minCross));
    }
    return true;
  }

  void scanPlane(double c) {
    crossed_.clear();
    for (uint32_t k = 0; k < nt_; ++k) {
      if (lo_[k] < c && hi_[k] >= c) crossed_.push_back(k);
    }
    pl_.cut(c, crossed_);
  }

  // First plane half a step inside the extreme (fixed point on the step of its own curve).
  Outcome firstPlane(double& c, double& step) {
    c = dmin_ + 0.5 * std::max(width_(0.0, samples_[0].height), 1e-6 * extent_);
    if (!(std::isfinite(c))) c = dmin_ + 0.01 * extent_;
    step = 0;
    for (int it = 0; it < 4; ++it) {
      c = std::min(c, dmin_ + 0.5 * extent_);
      scanPlane(c);
      if (!planeStep(step)) return failed<Outcome>(Status::InvalidOption, pl_.error);
      if (pl_.nodes.empty()) break;
      const double cn = std::min(dmin_ + 0.5 * step, dmin_ + 0.5 * extent_);
      if (std::abs(cn - c) <= eps_) break;
      c = cn;
    }
    return {};
  }

  // Sweep. Curves go to a pool per plane (ascending u, open curves oriented along +u, loops
  // counter-clockwise in (u, z)); the print order is decided afterwards.
  Outcome sweepFrom(double c, double step, const ProgressFn& progress) {
    const size_t maxPlanes = 2000000;
    std::vector<uint32_t> active;
    size_t next = 0;
    lastStep_ = step > 0 && std::isfinite(step) ? step : 0.01 * extent_;
    bool atEnd = false;
    for (;;) {
      while (next < nt_ && lo_[order_[next]] < c) active.push_back(order_[next++]);
      size_t w = 0;
      for (uint32_t k : active) {
        if (hi_[k] >= c) active[w++] = k;
      }
      active.resize(w);
      if (active.empty()) {
        if (next >= nt_) break;
        c = std::max(c + eps_, lo_[order_[next]] + 0.5 * lastStep_);
        continue;
      }
      pl_.cut(c, active);
      if (!planeStep(step)) return failed<Outcome>(Status::InvalidOption, pl_.error);
      if (pl_.nodes.empty()) {
        if (next >= nt_) break;
        c = std::max(c + eps_, lo_[order_[next]] + 0.5 * lastStep_);
        continue;
      }
      if (!(step > 1e-9 * extent_) || extent_ / step > static_cast<double>(maxPlanes)) {
        return failed<Outcome>(Status::InvalidOption, "side step " + std::to_string(step) +
                                                          " mm is too small for the surface's extent");
      }
      lastStep_ = step;
      poolPlaneCurves(c, step);
      ++planeIndex_;
      // Last plane: its bead reaches the far extreme (or leaves a sliver narrower than a quarter
      // step, which the squeezed bead covers: one more plane there would print a near-duplicate
      // curve a fraction of a step away), or it was placed half a step before it.
      if (atEnd || c + 0.75 * step >= dmax_ - eps_) {
        planeOffsets_.push_back(0);
        break;
      }
      double cn = c + step;
      if (cn >= dmax_ - 0.5 * step - eps_) {
        cn = dmax_ - 0.5 * step;
        atEnd = true;
        shortened_ = static_cast<uint32_t>(planeOffsets_.size());
      }
      planeOffsets_.push_back(cn - c);
      for (size_t i = pool_.size(); i-- > 0 && pool_[i].curve.plane == c;) pool_[i].curve.sideStep = cn - c;
      c = cn;
      if (!reportProgress(progress, "paths", std::clamp((c - dmin_) / extent_, 0.0, 1.0))) {
        return failed<Outcome>(Status::Cancelled, "cancelled");
      }
      if (planeIndex_ > maxPlanes) return failed<Outcome>(Status::InvalidOption, "too many drive planes");
    }
    return {};
  }

  // The curves of the plane just cut (at c, side step `step`) into the pool, by ascending u:
  // open curves oriented along +u and sampled, loops counter-clockwise in (u, z) kept raw.
  void poolPlaneCurves(double c, double step) {
    pl_.components(comps_, compClosed_);
    raw_.clear();
    for (size_t i = 0; i < comps_.size(); ++i) {
      RawCurve rc;
      rc.nodes = std::move(comps_[i]);
      rc.closed = compClosed_[i] != 0;
      double su = 0;
      for (uint32_t n : rc.nodes) su += pl_.u.dot(pl_.nodes[n].p);
      rc.uMean = su / static_cast<double>(rc.nodes.size());
      raw_.push_back(std::move(rc));
    }
    std::sort(raw_.begin(), raw_.end(),
              [](const RawCurve& x, const RawCurve& y) { return x.uMean < y.uMean; });
    std::vector<uint32_t> thisPlane;
    for (RawCurve& rc : raw_) {
      std::vector<uint32_t>& ns = rc.nodes;
      PoolCurve pc;
      pc.step = step;
      pc.plane = planeCurves_.size();
      if (!rc.closed) {
        const double u0 = pl_.u.dot(pl_.nodes[ns.front()].p), u1 = pl_.u.dot(pl_.nodes[ns.back()].p);
        if (u0 > u1) std::reverse(ns.begin(), ns.end());
        nodeSeq_.clear();
        evals_.clear();
        for (uint32_t n : ns) {
          nodeSeq_.push_back(pl_.nodes[n]);
          evals_.push_back(nodeEval_[n]);
        }
        buildCurve(nodeSeq_, evals_, false, c, pc);
        // A plane touching the surface at a point.
        if (pc.curve.points.size() < 2 || polylineLength(pc.curve.points) <= 1e-12) continue;
      } else {
        double area = 0;
        for (size_t i = 0; i < ns.size(); ++i) {
          const Eigen::Vector3d& pa = pl_.nodes[ns[i]].p;
          const Eigen::Vector3d& pb = pl_.nodes[ns[(i + 1) % ns.size()]].p;
          area += pl_.u.dot(pa) * pb.z() - pl_.u.dot(pb) * pa.z();
        }
        if (area < 0) std::reverse(ns.begin(), ns.end());
        for (uint32_t n : ns) {
          pc.raw.push_back(pl_.nodes[n]);
          pc.rawEval.push_back(nodeEval_[n]);
        }
        pc.curve.plane = c;
        pc.curve.closed = true;
      }
      thisPlane.push_back(static_cast<uint32_t>(pool_.size()));
      pool_.push_back(std::move(pc));
    }
    if (!thisPlane.empty()) planeCurves_.push_back(std::move(thisPlane));
  }

  void sideStepRange(IsoplanarResult& result) {
    result.planes = planeIndex_;
    // The offset to the last plane is shortened to land it half a step before the far extreme:
    // left out of the range unless it is the only one.
    if (shortened_ != kNone && planeOffsets_.size() > 2) planeOffsets_[shortened_] = 0;
    double mn = kInf, mx = 0;
    for (double o : planeOffsets_) {
      if (o > 0) {
        mn = std::min(mn, o);
        mx = std::max(mx, o);
      }
    }
    if (mn == kInf) mn = mx = result.planes > 0 ? lastStep_ : 0;
    result.minSideStep = mn;
    result.maxSideStep = mx;
  }

  // Samples a crossing sequence (closed: first repeated last) into a curve.
  void buildCurve(const std::vector<Node>& ns, const std::vector<PointEval>& ev, bool closed, double plane,
                  PoolCurve& out) {
    pts_.clear();
    for (const Node& n : ns) pts_.push_back(n.p);
    pl_.sample(pts_, ev, keep_);
    if (closed && keep_.size() < 4) {  // a loop within the chord error: keep every crossing
      keep_.resize(pts_.size());
      std::iota(keep_.begin(), keep_.end(), 0u);
    }
    NlCurve& curve = out.curve;
    curve = NlCurve();
    curve.plane = plane;
    curve.closed = closed;
    for (uint32_t i : keep_) {
      const Node& nd = ns[i];
      curve.points.push_back(nd.p);
      curve.normals.push_back(ev[i].normal);
      uint32_t ea = pl_.topo.ea[nd.edge], eb = pl_.topo.eb[nd.edge];
      float t = static_cast<float>(nd.t);
      if (nd.t <= 0) {
        eb = ea;
        t = 0;
      } else if (nd.t >= 1) {
        ea = eb;
        t = 0;
      }
      curve.edgeA.push_back(ea);
      curve.edgeB.push_back(eb);
      curve.edgeT.push_back(t);
      curve.width.push_back(ev[i].width);
    }
    if (!keep_.empty()) {
      out.firstEdge = ns[keep_.front()].edge;
      out.firstT = ns[keep_.front()].t;
      out.lastEdge = ns[keep_.back()].edge;
      out.lastT = ns[keep_.back()].t;
    }
  }

  LoopPos loopPos(uint32_t e, double t) const {
    LoopPos lp;
    if (e == kNone || pl_.topo.edgeLoop[e] == kNone) return lp;
    lp.loop = pl_.topo.edgeLoop[e];
    lp.index = pl_.topo.edgeLoopIndex[e];
    const std::vector<double>& cum = pl_.topo.loopCum[lp.loop];
    const double len = cum[lp.index + 1] - cum[lp.index];
    lp.s = cum[lp.index] + (pl_.topo.edgeForward[e] ? t : 1 - t) * len;
    return lp;
  }

  Eigen::Vector3d vertexNormal(uint32_t v) const { return samples_[v].normal.normalized(); }

  // Length of the boundary walk from `from` to `to` (infinite when not on one loop); fills
  // `join` when given.
  double boundaryWalk(const End& from, const End& to, IsoplanarJoin* join) const {
    const LoopPos pa = loopPos(from.edge, from.rawT), pb = loopPos(to.edge, to.rawT);
    if (pa.loop == kNone || pa.loop != pb.loop) return kInf;
    const std::vector<uint32_t>& loopV = pl_.topo.loops[pa.loop];
    const std::vector<double>& cum = pl_.topo.loopCum[pa.loop];
    const bool closedLoop = pl_.topo.loopClosed[pa.loop] != 0;
    const double perimeter = cum.back();
    const size_t segs = cum.size() - 1;
    double fwd = pb.s - pa.s, bwd = pa.s - pb.s;
    if (closedLoop) {
      if (fwd < 0) fwd += perimeter;
      bwd = perimeter - fwd;
    } else {
      if (fwd < 0) fwd = kInf;
      if (bwd < 0) bwd = kInf;
    }
    const bool forward = fwd <= bwd;
    const double arc = forward ? fwd : bwd;
    if (!join) return arc;
    auto push = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n, uint32_t ea, uint32_t eb,
                    float t) {
      if (!join->points.empty() && (join->points.back() - p).norm() <= 1e-12) return;
      join->points.push_back(p);
      join->normals.push_back(n);
      join->edgeA.push_back(ea);
      join->edgeB.push_back(eb);
      join->edgeT.push_back(t);
    };
    push(from.p, from.n, from.a, from.b, from.t);
    const bool sameSeg =
        pa.index == pb.index && ((forward && pb.s >= pa.s) || (!forward && pb.s <= pa.s));
    if (!sameSeg) {
      const size_t m = loopV.size();
      if (forward) {
        size_t k = pa.index + 1;
        for (size_t guard = 0; guard <= segs; ++guard, ++k) {
          const uint32_t v = loopV[k % m];
          push(surface_.vertex(v), vertexNormal(v), v, v, 0);
          if (k % m == pb.index % m) break;
        }
      } else {
        size_t k = pa.index;
        for (size_t guard = 0; guard <= segs; ++guard) {
          const uint32_t v = loopV[k % m];
          push(surface_.vertex(v), vertexNormal(v), v, v, 0);
          if (k % m == (pb.index + 1) % m) break;
          k = (k + m - 1) % m;
        }
      }
    }
    // The walk ends exactly at the next curve's start (a boundary vertex it meets is dropped).
    if (join->points.size() > 1 && (join->points.back() - to.p).norm() <= 1e-12) {
      join->points.pop_back();
      join->normals.pop_back();
      join->edgeA.pop_back();
      join->edgeB.pop_back();
      join->edgeT.pop_back();
    }
    push(to.p, to.n, to.a, to.b, to.t);
    if (join->points.size() < 2) {  // the curves meet at one point: a zero-length join
      join->points.push_back(to.p);
      join->normals.push_back(to.n);
      join->edgeA.push_back(to.a);
      join->edgeB.push_back(to.b);
      join->edgeT.push_back(to.t);
    }
    join->length = polylineLength(join->points);
    return arc;
  }

  // Makes a pool curve start at its other end (open: reverse when true) or, for a loop, at its
  // raw crossing `start`, and samples loops.
  void orient(PoolCurve& pc, bool reverse, size_t start) {
    if (!pc.curve.closed) {
      if (!reverse) return;
      NlCurve& cv = pc.curve;
      std::reverse(cv.points.begin(), cv.points.end());
      std::reverse(cv.normals.begin(), cv.normals.end());
      std::reverse(cv.edgeA.begin(), cv.edgeA.end());
      std::reverse(cv.edgeB.begin(), cv.edgeB.end());
      std::reverse(cv.edgeT.begin(), cv.edgeT.end());
      std::reverse(cv.width.begin(), cv.width.end());
      std::swap(pc.firstEdge, pc.lastEdge);
      std::swap(pc.firstT, pc.lastT);
      return;
    }
    std::vector<Node> ns(pc.raw.begin() + static_cast<std::ptrdiff_t>(start), pc.raw.end());
    ns.insert(ns.end(), pc.raw.begin(), pc.raw.begin() + static_cast<std::ptrdiff_t>(start));
    std::vector<PointEval> ev(pc.rawEval.begin() + static_cast<std::ptrdiff_t>(start), pc.rawEval.end());
    ev.insert(ev.end(), pc.rawEval.begin(), pc.rawEval.begin() + static_cast<std::ptrdiff_t>(start));
    ns.push_back(ns.front());
    ev.push_back(ev.front());
    const double side = pc.curve.sideStep;
    buildCurve(ns, ev, true, pc.curve.plane, pc);
    pc.curve.sideStep = side;
  }

  // Curve i into the print order.
  void emit(uint32_t i) {
    printed_[i] = 1;
    --remaining_;
    printOrder_.push_back(i);
    joinedToNext_.push_back(0);
    joinAfter_.emplace_back();
    lastPoint_ = pool_[i].curve.points.back();
    haveLast_ = true;
  }

  // A new chain: on the lowest plane left, the curve (and end) nearest the last point; returns it.
  uint32_t startChain(size_t lowest) {
    uint32_t cur = kNone;
    bool reverse = false;
    size_t start = 0;
    double best = kInf;
    for (uint32_t i : planeCurves_[lowest]) {
      if (printed_[i]) continue;
      if (!haveLast_) {
        cur = i;
        break;
      }
      const PoolCurve& pc = pool_[i];
      if (pc.curve.closed) {
        double d;
        const size_t k = nearestRaw(pc, lastPoint_, d);
        if (d < best) {
          best = d, cur = i, reverse = false, start = k;
        }
      } else {
        const double d0 = (pc.curve.points.front() - lastPoint_).norm();
        const double d1 = (pc.curve.points.back() - lastPoint_).norm();
        if (std::min(d0, d1) < best) {
          best = std::min(d0, d1), cur = i, reverse = d1 < d0;
        }
      }
    }
    orient(pool_[cur], reverse, start);
    emit(cur);
    return cur;
  }

  // The curve of plane `plane` that continues the chain after curve cur (its end joins cur's end
  // within connectFactor side steps), oriented, joined and emitted; kNone when none.
  uint32_t joinNext(uint32_t cur, size_t plane) {
    const PoolCurve& a = pool_[cur];
    const End from = endOf(a, true);
    uint32_t nextCurve = kNone;
    bool nextReverse = false;
    size_t nextStart = 0;
    double bestCost = kInf;
    for (uint32_t i : planeCurves_[plane]) {
      if (printed_[i]) continue;
      const PoolCurve& b = pool_[i];
      const double limit = options_.connectFactor * std::max(a.step, b.step);
      if (b.curve.closed) {
        // A loop has no boundary to follow: a short straight move to its nearest crossing
        // when the surface between is about flat.
        double d;
        const size_t k = nearestRaw(b, from.p, d);
        if (d <= limit && d < bestCost && from.n.dot(b.rawEval[k].normal) > 0.9) {
          bestCost = d, nextCurve = i, nextReverse = false, nextStart = k;
        }
        continue;
      }
      for (bool rev : {false, true}) {
        const End to = endOf(b, rev);
        double cost;
        if (a.curve.closed) {
          cost = (to.p - from.p).norm();
          if (from.n.dot(to.n) <= 0.9) cost = kInf;
        } else {
          cost = boundaryWalk(from, to, nullptr);
        }
        if (cost <= limit && cost < bestCost) {
          bestCost = cost, nextCurve = i, nextReverse = rev, nextStart = 0;
        }
      }
    }
    if (nextCurve == kNone) return kNone;
    orient(pool_[nextCurve], nextReverse, nextStart);
    const PoolCurve& b = pool_[nextCurve];
    IsoplanarJoin join;
    const End to = endOf(b, false);
    if (a.curve.closed || b.curve.closed) {
      join.points = {from.p, to.p};
      join.normals = {from.n, to.n};
      join.edgeA = {from.a, to.a};
      join.edgeB = {from.b, to.b};
      join.edgeT = {from.t, to.t};
      join.length = (to.p - from.p).norm();
    } else {
      boundaryWalk(from, to, &join);
    }
    joinedToNext_.back() = 1;
    joinAfter_.back() = std::move(join);
    emit(nextCurve);
    return nextCurve;
  }

  const Mesh& surface_;
  const std::vector<SurfaceSample>& samples_;
  const WidthFn& width_;
  const IsoplanarOptions& options_;
  Planner pl_;
  size_t nt_ = 0;
  double scale_ = 0;
  // The triangles' spans along q, sorted by their low ends, and the surface's.
  std::vector<double> lo_, hi_;
  std::vector<uint32_t> order_;
  double dmin_ = kInf, dmax_ = -kInf, extent_ = 0, eps_ = 0;
  // Sweep scratch.
  std::vector<std::vector<uint32_t>> comps_;
  std::vector<uint8_t> compClosed_;
  std::vector<RawCurve> raw_;
  std::vector<PointEval> nodeEval_;
  std::vector<uint32_t> crossed_;
  std::vector<Node> nodeSeq_;
  std::vector<Eigen::Vector3d> pts_;
  std::vector<PointEval> evals_;
  std::vector<uint32_t> keep_;
  // Sweep results: the curves, per plane with curves, the plane offsets.
  std::vector<PoolCurve> pool_;
  std::vector<std::vector<uint32_t>> planeCurves_;
  std::vector<double> planeOffsets_;
  double lastStep_ = 0;
  size_t planeIndex_ = 0;
  uint32_t shortened_ = kNone;  // index in planeOffsets_ of the offset to the last plane
  // Print order.
  std::vector<uint8_t> printed_;
  std::vector<uint32_t> printOrder_;
  std::vector<uint8_t> joinedToNext_;
  std::vector<IsoplanarJoin> joinAfter_;
  size_t remaining_ = 0;
  bool haveLast_ = false;
  Eigen::Vector3d lastPoint_{0, 0, 0};
};

}  // namespace

IsoplanarResult isoplanarPaths(const IsoplanarSurface& prepared, const WidthFn& width,
                               const IsoplanarOptions& options, const ProgressFn& progress) {
  const auto t0 = Clock::now();
  const Outcome input = checkPathOptions(prepared, width, options);
  if (!input.ok()) return fail(input.status, input.message);
  IsoplanarBuilder builder(*prepared.data, width, options);
  IsoplanarResult result;
  if (!builder.hasExtent()) {
    // The surface lies in one drive plane: no curve (not an error).
    result.ms = msSince(t0);
    return result;
  }
  const Outcome swept = builder.sweep(progress, result);
  if (!swept.ok()) return fail(swept.status, swept.message);
  builder.chainCurves();
  builder.assemblePaths(result);
  reportProgress(progress, "paths", 1.0);
  result.ms = msSince(t0);
  return result;
}

}  // namespace omnislice
