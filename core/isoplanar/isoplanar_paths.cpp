// SPDX-License-Identifier: MIT
// Iso-planar NL curves (paper 003 Algorithm 2): plane sweep over triangles sorted by their span
// along q, crossings linked per plane, Eq. 12 forward step, Eq. 14 side step (tilt-corrected, see
// the header), zig-zag ordering and boundary joins; and the printing-time estimate.
#include "isoplanar/isoplanar_paths.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

namespace omnislice {
namespace isoplanar_detail {

constexpr uint32_t kNone = 0xffffffffu;

// Edges, triangle-edge incidence and ordered boundary loops of the surface.
struct Topology {
  std::vector<uint32_t> tris;       // kept (non-degenerate) triangles, 3 vertices each
  std::vector<uint32_t> triEdge;    // per kept triangle: edges v0v1, v1v2, v2v0
  std::vector<uint32_t> ea, eb;     // edge endpoints, ea < eb
  std::vector<uint8_t> faces;       // triangles per edge (saturating)
  std::vector<std::vector<uint32_t>> loops;  // boundary loops: vertices in order
  std::vector<std::vector<double>> loopCum;  // arc length at loop vertex i (closed: size m + 1)
  std::vector<uint8_t> loopClosed;
  std::vector<uint32_t> edgeLoop, edgeLoopIndex;  // boundary edge -> loop, index of its segment
  std::vector<uint8_t> edgeForward;                // loop walks the edge from ea to eb
};

}  // namespace isoplanar_detail

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

IsoplanarResult fail(Status s, std::string message) {
  IsoplanarResult r;
  r.status = s;
  r.message = std::move(message);
  return r;
}

// Returns false (with a message) on a non-manifold edge.
bool buildTopology(const Mesh& mesh, Topology& topo, std::string& message) {
  const size_t nv = mesh.vertexCount();
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    const uint32_t a = mesh.triangles[3 * f], b = mesh.triangles[3 * f + 1],
                   c = mesh.triangles[3 * f + 2];
    if (a == b || b == c || c == a) continue;
    topo.tris.insert(topo.tris.end(), {a, b, c});
  }
  const size_t nt = topo.tris.size() / 3;
  // Half-edges bucketed by their smaller vertex (counting sort), edges found within buckets.
  std::vector<uint32_t> start(nv + 1, 0);
  for (size_t h = 0; h < 3 * nt; ++h) {
    const uint32_t a = topo.tris[h], b = topo.tris[h - h % 3 + (h % 3 + 1) % 3];
    ++start[std::min(a, b) + 1];
  }
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<uint32_t> fill(start.begin(), start.end() - 1), other(3 * nt), half(3 * nt);
  for (size_t h = 0; h < 3 * nt; ++h) {
    const uint32_t a = topo.tris[h], b = topo.tris[h - h % 3 + (h % 3 + 1) % 3];
    const uint32_t slot = fill[std::min(a, b)]++;
    other[slot] = std::max(a, b);
    half[slot] = static_cast<uint32_t>(h);
  }
  topo.triEdge.assign(3 * nt, kNone);
  for (size_t v = 0; v < nv; ++v) {
    for (uint32_t s = start[v]; s < start[v + 1]; ++s) {
      uint32_t edge = kNone;
      for (uint32_t r = start[v]; r < s; ++r) {
        if (other[r] == other[s]) {
          edge = topo.triEdge[half[r]];
          break;
        }
      }
      if (edge == kNone) {
        edge = static_cast<uint32_t>(topo.ea.size());
        topo.ea.push_back(static_cast<uint32_t>(v));
        topo.eb.push_back(other[s]);
        topo.faces.push_back(0);
      }
      topo.triEdge[half[s]] = edge;
      if (topo.faces[edge] < 255) ++topo.faces[edge];
      if (topo.faces[edge] > 2) {
        message = "non-manifold edge (" + std::to_string(v) + ", " + std::to_string(other[s]) +
                  ") shared by more than two triangles";
        return false;
      }
    }
  }
  // Boundary loops.
  const size_t ne = topo.ea.size();
  std::vector<uint32_t> bstart(nv + 1, 0);
  for (size_t e = 0; e < ne; ++e) {
    if (topo.faces[e] != 1) continue;
    ++bstart[topo.ea[e] + 1];
    ++bstart[topo.eb[e] + 1];
  }
  for (size_t v = 0; v < nv; ++v) bstart[v + 1] += bstart[v];
  std::vector<uint32_t> bfill(bstart.begin(), bstart.end() - 1), bedges(bstart[nv]);
  for (size_t e = 0; e < ne; ++e) {
    if (topo.faces[e] != 1) continue;
    bedges[bfill[topo.ea[e]]++] = static_cast<uint32_t>(e);
    bedges[bfill[topo.eb[e]]++] = static_cast<uint32_t>(e);
  }
  topo.edgeLoop.assign(ne, kNone);
  topo.edgeLoopIndex.assign(ne, 0);
  topo.edgeForward.assign(ne, 0);
  std::vector<uint8_t> used(ne, 0);
  auto vertexOf = [&](uint32_t v) { return mesh.vertex(v); };
  for (size_t e0 = 0; e0 < ne; ++e0) {
    if (topo.faces[e0] != 1 || used[e0]) continue;
    used[e0] = 1;
    const uint32_t first = topo.ea[e0];
    std::vector<uint32_t> verts{first}, edges{static_cast<uint32_t>(e0)};
    uint32_t cur = topo.eb[e0];
    bool closed = false;
    for (;;) {
      if (cur == first) {
        closed = true;
        break;
      }
      verts.push_back(cur);
      uint32_t next = kNone;
      for (uint32_t s = bstart[cur]; s < bstart[cur + 1]; ++s) {
        if (!used[bedges[s]]) {
          next = bedges[s];
          break;
        }
      }
      if (next == kNone) break;
      used[next] = 1;
      edges.push_back(next);
      cur = topo.ea[next] == cur ? topo.eb[next] : topo.ea[next];
    }
    const uint32_t id = static_cast<uint32_t>(topo.loops.size());
    std::vector<double> cum(edges.size() + 1, 0.0);
    for (size_t i = 0; i < edges.size(); ++i) {
      const uint32_t e = edges[i];
      topo.edgeLoop[e] = id;
      topo.edgeLoopIndex[e] = static_cast<uint32_t>(i);
      topo.edgeForward[e] = verts[i] == topo.ea[e] ? 1 : 0;
      cum[i + 1] = cum[i] + (vertexOf(topo.ea[e]) - vertexOf(topo.eb[e])).norm();
    }
    topo.loops.push_back(std::move(verts));
    topo.loopCum.push_back(std::move(cum));
    topo.loopClosed.push_back(closed ? 1 : 0);
  }
  return true;
}

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
    auto nodeOf = [&](uint32_t e) {
      if (edgeStamp[e] == stamp) return edgeNode[e];
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
            const double ang = std::atan2(ref.x() * d.y() - ref.y() * d.x(), ref.dot(d));
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
          const double ang = std::atan2(ref.x() * d.y() - ref.y() * d.x(), ref.dot(d));
          const double half = std::asin(dc / len);
          lo = std::max(lo, ang - half);
          hi = std::min(hi, ang + half);
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
  const auto t0 = std::chrono::steady_clock::now();
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
  std::string message;
  if (!buildTopology(surface, data->topo, message)) return bad(Status::NonManifoldInput, message);
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
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

IsoplanarResult isoplanarPaths(const Mesh& surface, const std::vector<SurfaceSample>& samples,
                               const WidthFn& width, const IsoplanarOptions& options,
                               const ProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const IsoplanarSurface prepared = prepareIsoplanarSurface(surface, samples);
  if (!prepared.ok()) return fail(prepared.status, prepared.message);
  IsoplanarResult r = isoplanarPaths(prepared, width, options, progress);
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

IsoplanarResult isoplanarPaths(const IsoplanarSurface& prepared, const WidthFn& width,
                               const IsoplanarOptions& options, const ProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
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
  const IsoplanarSurface::Data& data = *prepared.data;
  const Mesh& surface = data.mesh;
  const std::vector<SurfaceSample>& samples = data.samples;
  const size_t nv = surface.vertexCount();
  Planner pl(data, width, options);
  const size_t nt = pl.topo.tris.size() / 3;
  const double theta = options.thetaDegrees * M_PI / 180.0;
  pl.q = Eigen::Vector3d(-std::sin(theta), std::cos(theta), 0);
  pl.u = Eigen::Vector3d(std::cos(theta), std::sin(theta), 0);
  pl.dist.resize(nv);
  for (size_t v = 0; v < nv; ++v) pl.dist[v] = pl.q.dot(surface.vertex(v));
  pl.edgeStamp.assign(pl.topo.ea.size(), 0);
  pl.edgeNode.assign(pl.topo.ea.size(), 0);

  // Triangles sorted by the low end of their span along q.
  std::vector<double> lo(nt), hi(nt);
  double dmin = kInf, dmax = -kInf;
  for (size_t k = 0; k < nt; ++k) {
    const uint32_t* v = &pl.topo.tris[3 * k];
    lo[k] = std::min({pl.dist[v[0]], pl.dist[v[1]], pl.dist[v[2]]});
    hi[k] = std::max({pl.dist[v[0]], pl.dist[v[1]], pl.dist[v[2]]});
    dmin = std::min(dmin, lo[k]);
    dmax = std::max(dmax, hi[k]);
  }
  std::vector<std::pair<double, uint32_t>> sorted(nt);
  for (uint32_t k = 0; k < nt; ++k) sorted[k] = {lo[k], k};
  std::sort(sorted.begin(), sorted.end());
  std::vector<uint32_t> order(nt);
  for (size_t k = 0; k < nt; ++k) order[k] = sorted[k].second;
  const double extent = dmax - dmin;
  IsoplanarResult result;
  const double scale = data.scale;
  if (!(extent > 1e-9 * std::max(scale, 1e-9))) {
    // The surface lies in one drive plane: no curve (not an error).
    result.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return result;
  }
  const double eps = 1e-9 * std::max(extent, scale);

  // ---- One plane: curves (unordered components), their raw evaluations, the side step. ----
  struct RawCurve {
    std::vector<uint32_t> nodes;
    bool closed = false;
    double uMean = 0;
  };
  std::vector<std::vector<uint32_t>> comps;
  std::vector<uint8_t> compClosed;
  std::vector<RawCurve> raw;
  // Evaluate every crossing: min over the plane's points of w_eff |k.q| (floored).
  std::vector<PointEval> nodeEval;
  auto planeStep = [&](double& step) -> bool {
    nodeEval.resize(pl.nodes.size());
    step = kInf;
    for (size_t n = 0; n < pl.nodes.size(); ++n) {
      if (!pl.evaluate(pl.nodes[n].edge, pl.nodes[n].t, nodeEval[n])) return false;
      step = std::min(step, nodeEval[n].width * std::max(nodeEval[n].cross, options.minCross));
    }
    return true;
  };
  std::vector<uint32_t> crossed;
  auto scanPlane = [&](double c) {
    crossed.clear();
    for (uint32_t k = 0; k < nt; ++k) {
      if (lo[k] < c && hi[k] >= c) crossed.push_back(k);
    }
    pl.cut(c, crossed);
  };

  // First plane half a step inside the extreme (fixed point on the step of its own curve).
  double c = dmin + 0.5 * std::max(width(0.0, samples[0].height), 1e-6 * extent);
  if (!(std::isfinite(c))) c = dmin + 0.01 * extent;
  double step = 0;
  for (int it = 0; it < 4; ++it) {
    c = std::min(c, dmin + 0.5 * extent);
    scanPlane(c);
    if (!planeStep(step)) return fail(Status::InvalidOption, pl.error);
    if (pl.nodes.empty()) break;
    const double cn = std::min(dmin + 0.5 * step, dmin + 0.5 * extent);
    if (std::abs(cn - c) <= eps) break;
    c = cn;
  }

  // Sweep.
  std::vector<uint32_t> active;
  size_t next = 0;
  std::vector<double> planeOffsets;
  std::vector<double> curveStepRef;  // per curve: the side step computed on its plane
  struct CurveEnds {
    uint32_t firstEdge;
    double firstT;
    uint32_t lastEdge;
    double lastT;
  };
  std::vector<CurveEnds> curveEnds;
  std::vector<Eigen::Vector3d> pts;
  std::vector<PointEval> evals;
  std::vector<uint32_t> keep;
  double lastStep = step > 0 && std::isfinite(step) ? step : 0.01 * extent;
  bool haveEnd = false;
  Eigen::Vector3d prevEnd(0, 0, 0);
  size_t planeIndex = 0;
  bool atEnd = false;
  const size_t maxPlanes = 2000000;
  for (;;) {
    while (next < nt && lo[order[next]] < c) active.push_back(order[next++]);
    size_t w = 0;
    for (uint32_t k : active) {
      if (hi[k] >= c) active[w++] = k;
    }
    active.resize(w);
    if (active.empty()) {
      if (next >= nt) break;
      c = std::max(c + eps, lo[order[next]] + 0.5 * lastStep);
      continue;
    }
    pl.cut(c, active);
    if (!planeStep(step)) return fail(Status::InvalidOption, pl.error);
    if (pl.nodes.empty()) {
      if (next >= nt) break;
      c = std::max(c + eps, lo[order[next]] + 0.5 * lastStep);
      continue;
    }
    if (!(step > 1e-9 * extent) || extent / step > static_cast<double>(maxPlanes)) {
      return fail(Status::InvalidOption, "side step " + std::to_string(step) +
                                             " mm is too small for the surface's extent");
    }
    lastStep = step;
    // Components, ordered along u, zig-zag directions.
    pl.components(comps, compClosed);
    raw.clear();
    for (size_t i = 0; i < comps.size(); ++i) {
      RawCurve rc;
      rc.nodes = std::move(comps[i]);
      rc.closed = compClosed[i] != 0;
      double su = 0;
      for (uint32_t n : rc.nodes) su += pl.u.dot(pl.nodes[n].p);
      rc.uMean = su / static_cast<double>(rc.nodes.size());
      raw.push_back(std::move(rc));
    }
    const bool ascending = planeIndex % 2 == 0;
    std::sort(raw.begin(), raw.end(), [&](const RawCurve& a, const RawCurve& b) {
      return ascending ? a.uMean < b.uMean : a.uMean > b.uMean;
    });
    for (RawCurve& rc : raw) {
      std::vector<uint32_t>& ns = rc.nodes;
      if (!rc.closed) {
        const double u0 = pl.u.dot(pl.nodes[ns.front()].p), u1 = pl.u.dot(pl.nodes[ns.back()].p);
        if ((ascending && u0 > u1) || (!ascending && u0 < u1)) std::reverse(ns.begin(), ns.end());
      } else {
        // Orientation by the signed area in the plane (u, z), alternating; start nearest the
        // previous end.
        double area = 0;
        for (size_t i = 0; i < ns.size(); ++i) {
          const Eigen::Vector3d& a = pl.nodes[ns[i]].p;
          const Eigen::Vector3d& b = pl.nodes[ns[(i + 1) % ns.size()]].p;
          area += pl.u.dot(a) * b.z() - pl.u.dot(b) * a.z();
        }
        if ((ascending && area < 0) || (!ascending && area > 0)) std::reverse(ns.begin(), ns.end());
        if (haveEnd) {
          size_t bestI = 0;
          double bestD = kInf;
          for (size_t i = 0; i < ns.size(); ++i) {
            const double d = (pl.nodes[ns[i]].p - prevEnd).squaredNorm();
            if (d < bestD) {
              bestD = d;
              bestI = i;
            }
          }
          std::rotate(ns.begin(), ns.begin() + static_cast<std::ptrdiff_t>(bestI), ns.end());
        }
        ns.push_back(ns.front());
      }
      pts.clear();
      evals.clear();
      for (uint32_t n : ns) {
        pts.push_back(pl.nodes[n].p);
        evals.push_back(nodeEval[n]);
      }
      pl.sample(pts, evals, keep);
      NlCurve curve;
      curve.plane = c;
      curve.closed = rc.closed;
      for (uint32_t i : keep) {
        const Node& nd = pl.nodes[ns[i]];
        curve.points.push_back(nd.p);
        curve.normals.push_back(nodeEval[ns[i]].normal);
        uint32_t a = pl.topo.ea[nd.edge], b = pl.topo.eb[nd.edge];
        float t = static_cast<float>(nd.t);
        if (nd.t <= 0) {
          b = a;
          t = 0;
        } else if (nd.t >= 1) {
          a = b;
          t = 0;
        }
        curve.edgeA.push_back(a);
        curve.edgeB.push_back(b);
        curve.edgeT.push_back(t);
        curve.width.push_back(nodeEval[ns[i]].width);
      }
      if (curve.points.size() < 2) continue;  // a plane touching the surface at one point
      prevEnd = curve.points.back();
      haveEnd = true;
      if (curve.closed) ++result.closedCurves;
      result.curves.push_back(std::move(curve));
      curveStepRef.push_back(step);
      // The raw edges of the ends (a vertex crossing's edge is not in the curve's fields).
      const Node& nf = pl.nodes[ns[keep.front()]];
      const Node& nl = pl.nodes[ns[keep.back()]];
      curveEnds.push_back({nf.edge, nf.t, nl.edge, nl.t});
    }
    ++planeIndex;
    // Last plane: its bead reaches the far extreme, or it was placed half a step before it.
    if (atEnd || c + 0.5 * step >= dmax - eps) {
      planeOffsets.push_back(0);
      break;
    }
    double cn = c + step;
    if (cn >= dmax - 0.5 * step - eps) {
      cn = dmax - 0.5 * step;
      atEnd = true;
    }
    planeOffsets.push_back(cn - c);
    // Side step of the curves just added.
    for (size_t i = result.curves.size(); i-- > 0 && result.curves[i].plane == c;) {
      result.curves[i].sideStep = cn - c;
    }
    c = cn;
    if (!reportProgress(progress, "paths", std::clamp((c - dmin) / extent, 0.0, 1.0))) {
      return fail(Status::Cancelled, "cancelled");
    }
    if (planeIndex > maxPlanes) return fail(Status::InvalidOption, "too many drive planes");
  }
  result.planes = planeIndex;
  {
    double mn = kInf, mx = 0;
    for (double o : planeOffsets) {
      if (o > 0) {
        mn = std::min(mn, o);
        mx = std::max(mx, o);
      }
    }
    if (mn == kInf) mn = mx = result.planes > 0 ? lastStep : 0;
    result.minSideStep = mn;
    result.maxSideStep = mx;
  }

  // ---- Zig-zag joins along the boundary and paths. ----
  // A curve end as a boundary-loop position: loop, segment index, arc position.
  struct LoopPos {
    uint32_t loop = kNone;
    uint32_t index = 0;
    double s = 0;
  };
  auto loopPos = [&](uint32_t e, double t) -> LoopPos {
    LoopPos lp;
    if (e == kNone || pl.topo.edgeLoop[e] == kNone) return lp;
    lp.loop = pl.topo.edgeLoop[e];
    lp.index = pl.topo.edgeLoopIndex[e];
    const std::vector<double>& cum = pl.topo.loopCum[lp.loop];
    const double len = cum[lp.index + 1] - cum[lp.index];
    lp.s = cum[lp.index] + (pl.topo.edgeForward[e] ? t : 1 - t) * len;
    return lp;
  };
  auto vertexNormal = [&](uint32_t v) { return samples[v].normal.normalized(); };

  std::vector<uint8_t> joinedToNext(result.curves.size(), 0);
  std::vector<IsoplanarJoin> joinAfter(result.curves.size());
  for (size_t i = 0; i + 1 < result.curves.size(); ++i) {
    const NlCurve& a = result.curves[i];
    const NlCurve& b = result.curves[i + 1];
    const double limit = options.connectFactor * std::max(curveStepRef[i], curveStepRef[i + 1]);
    if (a.closed || b.closed) {
      // A loop has no boundary to follow: a short straight move to the next curve's start
      // (nearest to this end by construction) when the surface between is about flat.
      const double d = (b.points.front() - a.points.back()).norm();
      if (d <= limit && a.normals.back().dot(b.normals.front()) > 0.9) {
        IsoplanarJoin join;
        join.fromCurve = static_cast<uint32_t>(i);
        join.toCurve = static_cast<uint32_t>(i + 1);
        join.points = {a.points.back(), b.points.front()};
        join.normals = {a.normals.back(), b.normals.front()};
        join.edgeA = {a.edgeA.back(), b.edgeA.front()};
        join.edgeB = {a.edgeB.back(), b.edgeB.front()};
        join.edgeT = {a.edgeT.back(), b.edgeT.front()};
        join.length = d;
        joinedToNext[i] = 1;
        joinAfter[i] = std::move(join);
      }
      continue;
    }
    const LoopPos pa = loopPos(curveEnds[i].lastEdge, curveEnds[i].lastT);
    const LoopPos pb = loopPos(curveEnds[i + 1].firstEdge, curveEnds[i + 1].firstT);
    if (pa.loop == kNone || pa.loop != pb.loop) continue;
    const std::vector<uint32_t>& loopV = pl.topo.loops[pa.loop];
    const std::vector<double>& cum = pl.topo.loopCum[pa.loop];
    const bool closedLoop = pl.topo.loopClosed[pa.loop] != 0;
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
    if (!(arc <= limit)) continue;
    IsoplanarJoin join;
    join.fromCurve = static_cast<uint32_t>(i);
    join.toCurve = static_cast<uint32_t>(i + 1);
    auto push = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n, uint32_t ea, uint32_t eb,
                    float t) {
      if (!join.points.empty() && (join.points.back() - p).norm() <= 1e-12) return;
      join.points.push_back(p);
      join.normals.push_back(n);
      join.edgeA.push_back(ea);
      join.edgeB.push_back(eb);
      join.edgeT.push_back(t);
    };
    push(a.points.back(), a.normals.back(), a.edgeA.back(), a.edgeB.back(), a.edgeT.back());
    const bool sameSeg = pa.index == pb.index && ((forward && pb.s >= pa.s) || (!forward && pb.s <= pa.s));
    if (!sameSeg) {
      const size_t m = loopV.size();
      if (forward) {
        size_t k = pa.index + 1;
        for (size_t guard = 0; guard <= segs; ++guard, ++k) {
          const uint32_t v = loopV[k % m];
          push(surface.vertex(v), vertexNormal(v), v, v, 0);
          if (k % m == pb.index % m) break;
        }
      } else {
        size_t k = pa.index;
        for (size_t guard = 0; guard <= segs; ++guard) {
          const uint32_t v = loopV[k % m];
          push(surface.vertex(v), vertexNormal(v), v, v, 0);
          if (k % m == (pb.index + 1) % m) break;
          k = (k + m - 1) % m;
        }
      }
    }
    push(b.points.front(), b.normals.front(), b.edgeA.front(), b.edgeB.front(), b.edgeT.front());
    if (join.points.size() < 2) {  // the curves meet at one point: a zero-length join
      join.points.push_back(b.points.front());
      join.normals.push_back(b.normals.front());
      join.edgeA.push_back(b.edgeA.front());
      join.edgeB.push_back(b.edgeB.front());
      join.edgeT.push_back(b.edgeT.front());
    }
    join.length = polylineLength(join.points);
    joinedToNext[i] = 1;
    joinAfter[i] = std::move(join);
  }
  for (size_t i = 0; i < result.curves.size(); ++i) {
    const NlCurve& cv = result.curves[i];
    result.pathMm += polylineLength(cv.points);
    if (i == 0 || !joinedToNext[i - 1]) {
      result.paths.emplace_back();
      result.pathCurves.emplace_back();
      result.pathJoins.emplace_back();
      result.paths.back().points = cv.points;
      result.paths.back().normals = cv.normals;
    } else {
      IsoplanarJoin& j = joinAfter[i - 1];
      SurfacePath& sp = result.paths.back();
      sp.points.insert(sp.points.end(), j.points.begin() + 1, j.points.end() - 1);
      sp.normals.insert(sp.normals.end(), j.normals.begin() + 1, j.normals.end() - 1);
      sp.points.insert(sp.points.end(), cv.points.begin(), cv.points.end());
      sp.normals.insert(sp.normals.end(), cv.normals.begin(), cv.normals.end());
      result.pathMm += j.length;
      result.pathJoins.back().push_back(static_cast<uint32_t>(result.joins.size()));
      result.joins.push_back(std::move(j));
    }
    result.pathCurves.back().push_back(static_cast<uint32_t>(i));
  }
  reportProgress(progress, "paths", 1.0);
  result.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

namespace {

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
