// SPDX-License-Identifier: MIT
#include "common/math_constants.h"
#include "multidir/projected_supports.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <tuple>

#include "common/det_math.h"
#include "common/disjoint_sets.h"
#include "geometry/aabb_tree.h"
#include "multidir/risky_faces.h"

namespace omnislice {
namespace {

constexpr double kGravity = 9.81;
constexpr double kInf = std::numeric_limits<double>::infinity();

SupportResult fail(Status s, std::string message) { return failed<SupportResult>(s, std::move(message)); }

double sq(double v) { return v * v; }

struct Basis {
  Eigen::Vector3d e1, e2, d;
};

Basis basisFor(const Eigen::Vector3d& d) {
  const Eigen::Vector3d a = std::abs(d.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Basis b;
  b.d = d;
  b.e1 = (a - a.dot(d) * d).normalized();
  b.e2 = d.cross(b.e1);
  return b;
}

// Rays along -d against the surface: the mesh turned so that d is +Z, then vertical columns.
class DownRays {
 public:
  DownRays(const Mesh& mesh, const Basis& basis) : basis_(basis) {
    Mesh turned = mesh;
    for (size_t v = 0; v < mesh.vertexCount(); ++v) {
      const Eigen::Vector3d q = turn(mesh.vertex(v));
      for (int k = 0; k < 3; ++k) turned.positions[3 * v + size_t(k)] = q[k];
    }
    tree_ = std::make_unique<AabbTree>(turned);
  }
  // Distance along -d from x to the first surface crossing farther than minT; infinity if none.
  double firstHit(const Eigen::Vector3d& x, double minT) const {
    const Eigen::Vector3d q = turn(x);
    crossings_.clear();
    tree_->columnCrossings(q.x(), q.y(), crossings_);
    double best = kInf;
    for (const ColumnCrossing& c : crossings_) {
      const double t = q.z() - c.z;
      if (t > minT && t < best) best = t;
    }
    return best;
  }

 private:
  Eigen::Vector3d turn(const Eigen::Vector3d& p) const {
    return {p.dot(basis_.e1), p.dot(basis_.e2), p.dot(basis_.d)};
  }
  Basis basis_;
  std::unique_ptr<AabbTree> tree_;
  mutable std::vector<ColumnCrossing> crossings_;
};

// A closed prism: polygon `top` (any orientation) and the same polygon moved by `offset`,
// appended to out with outward orientation.
void appendPrism(const std::vector<Eigen::Vector3d>& top, const Eigen::Vector3d& offset, Mesh& out) {
  const size_t k = top.size();
  const uint32_t base = static_cast<uint32_t>(out.vertexCount());
  for (const Eigen::Vector3d& p : top) out.positions.insert(out.positions.end(), {p.x(), p.y(), p.z()});
  for (const Eigen::Vector3d& p : top) {
    const Eigen::Vector3d q = p + offset;
    out.positions.insert(out.positions.end(), {q.x(), q.y(), q.z()});
  }
  const size_t first = out.triangles.size();
  auto tri = [&](size_t a, size_t b, size_t c) {
    out.triangles.insert(out.triangles.end(), {base + uint32_t(a), base + uint32_t(b), base + uint32_t(c)});
  };
  for (size_t i = 1; i + 1 < k; ++i) {
    tri(0, i + 1, i);          // top
    tri(k, k + i, k + i + 1);  // bottom
  }
  for (size_t i = 0; i < k; ++i) {
    const size_t j = (i + 1) % k;
    tri(i, j, k + j);
    tri(i, k + j, k + i);
  }
  // Orient outward: flip every triangle of this prism when its signed volume is negative.
  double vol = 0;
  for (size_t t = first; t < out.triangles.size(); t += 3) {
    const Eigen::Vector3d a = out.vertex(out.triangles[t]), b = out.vertex(out.triangles[t + 1]),
                          c = out.vertex(out.triangles[t + 2]);
    vol += a.dot(b.cross(c));
  }
  if (vol < 0) {
    for (size_t t = first; t < out.triangles.size(); t += 3) std::swap(out.triangles[t + 1], out.triangles[t + 2]);
  }
}

}  // namespace

int subspaceOf(const Eigen::Vector3d& x, const std::vector<Plane>& planes) {
  for (size_t k = 0; k < planes.size(); ++k) {
    if (planes[k].normal.dot(x) > planes[k].offset) return static_cast<int>(k);
  }
  return static_cast<int>(planes.size());
}

SupportResult projectedSupports(const Mesh& mesh, const std::vector<Plane>& planesIn,
                                const SupportOptions& o, const ProgressFn& progress) {
  auto finitePos = [](double v) { return std::isfinite(v) && v > 0; };
  auto finiteNonNeg = [](double v) { return std::isfinite(v) && v >= 0; };
  if (!finitePos(o.samplingMm)) return fail(Status::InvalidOption, "support sampling interval must be > 0 mm");
  if (!(o.alphaMaxDeg > 0 && o.alphaMaxDeg < 90)) {
    return fail(Status::InvalidOption, "support overhang angle must be in (0, 90) degrees");
  }
  if (!finiteNonNeg(o.platformBandMm) || !finiteNonNeg(o.lambda) || !finiteNonNeg(o.minDiameterMm) ||
      !finiteNonNeg(o.roofMm)) {
    return fail(Status::InvalidOption, "support band, lambda, minimum diameter and roof must be finite and >= 0");
  }
  if (!(o.mergeAngleDeg >= 0 && o.mergeAngleDeg <= 60)) {
    return fail(Status::InvalidOption, "support merge angle must be in [0, 60] degrees");
  }
  if (mesh.empty()) return fail(Status::EmptyInput, "mesh has no triangles");
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  for (uint32_t i : mesh.triangles) {
    if (i >= nv) return fail(Status::InvalidOption, "triangle index out of range");
  }
  for (size_t v = 0; v < nv; ++v) {
    if (!mesh.vertex(v).allFinite()) return fail(Status::NonFiniteVertex, "vertex " + std::to_string(v) + " is not finite");
  }
  std::vector<Plane> planes;
  for (const Plane& p : planesIn) {
    const double len = p.normal.norm();
    if (!p.normal.allFinite() || !std::isfinite(p.offset) || !(len > 0)) {
      return fail(Status::InvalidOption, "a clipping plane is zero or not finite");
    }
    planes.push_back({p.normal / len, p.offset / len});
  }
  const int platform = static_cast<int>(planes.size());
  const size_t subspaces = planes.size() + 1;

  SupportResult res;
  for (const Plane& p : planes) res.directions.push_back(p.normal);
  res.directions.push_back(Eigen::Vector3d::UnitZ());
  const double sinAlpha = sinAlphaMax(o.alphaMaxDeg);
  const double R = o.samplingMm;

  // Faces: unit normals, areas; vertex neighbours (for point overhangs).
  std::vector<Eigen::Vector3d> normal(nf);
  std::vector<double> area(nf);
  for (size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]), b = mesh.vertex(mesh.triangles[3 * f + 1]),
                          c = mesh.vertex(mesh.triangles[3 * f + 2]);
    const Eigen::Vector3d cr = (b - a).cross(c - a);
    area[f] = 0.5 * cr.norm();
    normal[f] = area[f] > 0 ? Eigen::Vector3d(cr.normalized()) : Eigen::Vector3d::Zero();
  }
  std::vector<std::vector<uint32_t>> neighbours(nv);
  for (size_t f = 0; f < nf; ++f) {
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = mesh.triangles[3 * f + size_t(e)], b = mesh.triangles[3 * f + size_t((e + 1) % 3)];
      neighbours[a].push_back(b);
      neighbours[b].push_back(a);
    }
  }
  std::vector<int> vertexSubspace(nv);
  for (size_t v = 0; v < nv; ++v) vertexSubspace[v] = subspaceOf(mesh.vertex(v), planes);

  struct Sample {
    Eigen::Vector3d p;
    int subspace;
  };
  std::vector<Sample> samples;
  std::vector<std::unique_ptr<DownRays>> rays(subspaces);
  std::vector<Basis> bases(subspaces);
  for (size_t s = 0; s < subspaces; ++s) {
    if (!reportProgress(progress, "supports", 0.5 * double(s) / double(subspaces))) {
      return fail(Status::Cancelled, "cancelled");
    }
    const int si = static_cast<int>(s);
    const Basis basis = basisFor(res.directions[s]);
    bases[s] = basis;
    const Eigen::Vector3d& d = basis.d;
    auto resting = [&](const Eigen::Vector3d& p) { return si == platform && p.z() < o.platformBandMm; };
    auto risky = [&](size_t f) { return area[f] > 0 && riskyAlong(normal[f], d, sinAlpha); };

    // Roofs and patches: risky faces whose centroid lies in this subspace.
    std::vector<char> inPatch(nf, 0);
    for (size_t f = 0; f < nf; ++f) {
      if (!risky(f)) continue;
      const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]), b = mesh.vertex(mesh.triangles[3 * f + 1]),
                            c = mesh.vertex(mesh.triangles[3 * f + 2]);
      const Eigen::Vector3d centroid = (a + b + c) / 3;
      if (subspaceOf(centroid, planes) != si || resting(centroid)) continue;
      inPatch[f] = 1;
      res.roofs.push_back({a, b, c, si});
      res.riskyAreaMm2 += area[f];
      res.roofVolumeMm3 += area[f] * std::abs(normal[f].dot(d)) * o.roofMm;
    }
    DisjointSets patches(nf);
    {
      std::vector<int64_t> firstFace(nv, -1);
      for (size_t f = 0; f < nf; ++f) {
        if (!inPatch[f]) continue;
        for (int k = 0; k < 3; ++k) {
          const uint32_t v = mesh.triangles[3 * f + size_t(k)];
          if (firstFace[v] < 0) firstFace[v] = int64_t(f);
          else patches.unite(size_t(firstFace[v]), f);
        }
      }
    }
    std::vector<char> patchSampled(nf, 0);

    // Face overhangs: grid nodes (i R, j R) in (e1, e2) inside a risky face's projection.
    std::set<std::tuple<long, long, long>> seen;
    for (size_t f = 0; f < nf; ++f) {
      if (!risky(f)) continue;
      Eigen::Vector3d p3[3];
      Eigen::Vector2d q[3];
      for (int k = 0; k < 3; ++k) {
        p3[k] = mesh.vertex(mesh.triangles[3 * f + size_t(k)]);
        q[k] = {p3[k].dot(basis.e1), p3[k].dot(basis.e2)};
      }
      const double det = (q[1] - q[0]).x() * (q[2] - q[0]).y() - (q[1] - q[0]).y() * (q[2] - q[0]).x();
      if (!(std::abs(det) > 1e-14)) continue;
      const Eigen::Vector2d lo = q[0].cwiseMin(q[1]).cwiseMin(q[2]), hi = q[0].cwiseMax(q[1]).cwiseMax(q[2]);
      for (long i = long(std::ceil(lo.x() / R)); double(i) * R <= hi.x(); ++i) {
        for (long j = long(std::ceil(lo.y() / R)); double(j) * R <= hi.y(); ++j) {
          const Eigen::Vector2d g(double(i) * R, double(j) * R);
          const double l1 = ((g - q[0]).x() * (q[2] - q[0]).y() - (g - q[0]).y() * (q[2] - q[0]).x()) / det;
          const double l2 = ((q[1] - q[0]).x() * (g - q[0]).y() - (q[1] - q[0]).y() * (g - q[0]).x()) / det;
          const double l0 = 1 - l1 - l2;
          if (l0 < -1e-12 || l1 < -1e-12 || l2 < -1e-12) continue;
          const Eigen::Vector3d p = l0 * p3[0] + l1 * p3[1] + l2 * p3[2];
          if (subspaceOf(p, planes) != si || resting(p)) continue;
          if (inPatch[f]) patchSampled[patches.find(f)] = 1;
          if (!seen.insert({i, j, std::lround(p.dot(d) / 0.01)}).second) continue;
          samples.push_back({p, si});
        }
      }
    }
    // Small face and edge overhangs: the lowest vertex of every patch the grid missed.
    std::vector<int64_t> lowest(nf, -1);
    for (size_t f = 0; f < nf; ++f) {
      if (!inPatch[f] || patchSampled[patches.find(f)]) continue;
      const size_t root = patches.find(f);
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh.triangles[3 * f + size_t(k)];
        if (vertexSubspace[v] != si || resting(mesh.vertex(v))) continue;
        if (lowest[root] < 0 || mesh.vertex(v).dot(d) < mesh.vertex(size_t(lowest[root])).dot(d)) lowest[root] = v;
      }
    }
    for (size_t f = 0; f < nf; ++f) {
      if (lowest[f] < 0) continue;
      samples.push_back({mesh.vertex(size_t(lowest[f])), si});
      ++res.patchSamples;
    }
    // Point overhangs: vertices lower than all their neighbours.
    for (size_t v = 0; v < nv; ++v) {
      if (vertexSubspace[v] != si || neighbours[v].empty()) continue;
      const Eigen::Vector3d p = mesh.vertex(v);
      if (resting(p)) continue;
      const double h = p.dot(d);
      bool minimum = true;
      for (uint32_t u : neighbours[v]) {
        if (!(mesh.vertex(u).dot(d) > h + 1e-9)) {
          minimum = false;
          break;
        }
      }
      if (!minimum) continue;
      samples.push_back({p, si});
      ++res.pointOverhangs;
    }
    rays[s] = std::make_unique<DownRays>(mesh, basis);
  }
  res.samples = samples.size();

  // A strut piece with its diameter, and Eq. 13's torque of pieces above a point.
  struct Piece {
    Eigen::Vector3d top, bottom;
    int s;
    double diameter = 0;
  };
  // A piece's prism keeps its cross-section orthogonal to d (the layers' plane), so its volume is
  // that area times its height along d (its length for a straight strut).
  auto pieceVolume = [&](const Piece& q) {
    return kPi * 0.25 * q.diameter * q.diameter * (q.top - q.bottom).dot(res.directions[size_t(q.s)]);
  };
  auto diameterBelow = [&](const std::vector<Piece>& above, const Eigen::Vector3d& top) {
    Eigen::Vector3d torque = Eigen::Vector3d::Zero();
    for (const Piece& q : above) {
      const double vol = pieceVolume(q);
      torque += vol * (0.5 * (q.top + q.bottom) - top).cross(-kGravity * res.directions[size_t(q.s)]);
    }
    return std::max(o.minDiameterMm, (1 + o.lambda * torque.norm()) * R / 4);
  };
  constexpr double kSkin = 1e-4;  // mm: a ray ignores its own starting surface
  // Straight length along -d of subspace s from x to the model, the platform or the base plane.
  auto straightLength = [&](const Eigen::Vector3d& x, int s) {
    const double tExit = s == platform ? std::max(0.0, x.z())
                                       : std::max(0.0, planes[size_t(s)].normal.dot(x) - planes[size_t(s)].offset);
    return std::min(tExit, rays[size_t(s)]->firstHit(x, kSkin));
  };

  // Tree merging (Vanek et al., as the paper's Section V): within each subspace, from the highest
  // node down, a node joins its nearest neighbour at the highest point both reach with branches
  // at most mergeAngleDeg from -d, when both branches keep clear of the model, the meeting point
  // stays in the subspace, and the two branches plus one trunk are shorter than two trunks.
  struct Node {
    Eigen::Vector3d p;
    int s;
    size_t samples = 1;
    std::vector<Piece> above;  // the branches of this node's tree
  };
  std::vector<Node> nodes;
  nodes.reserve(samples.size());
  for (const Sample& sm : samples) nodes.push_back({sm.p, sm.subspace, 1, {}});
  std::unique_ptr<AabbTree> surfaceTree;
  if (o.mergeAngleDeg > 0 && !samples.empty()) surfaceTree = std::make_unique<AabbTree>(mesh);
  const double tanMerge = det::sin(o.mergeAngleDeg * kPi / 180) / det::cos(o.mergeAngleDeg * kPi / 180);
  const double clearance = 0.5 * o.minDiameterMm + 0.2;
  auto branchClear = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
    const double len = (to - from).norm();
    const double step = std::max(0.1, 0.5 * clearance);
    // Skip the first stretch near the overhang the branch starts from (it leaves that surface at
    // >= cos(alpha_max + mergeAngle) per mm).
    for (double t = 2 * clearance; t <= len; t += step) {
      if (surfaceTree->anyWithin(from + (to - from) * (t / len), clearance)) return false;
    }
    return !surfaceTree->anyWithin(to, clearance);
  };
  std::vector<size_t> finals;  // nodes that go straight down (roots of the trees)
  if (o.mergeAngleDeg > 0) {
    for (size_t si = 0; si < subspaces; ++si) {
      const Basis& basis = bases[si];
      const Eigen::Vector3d& d = basis.d;
      std::vector<size_t> active;
      for (size_t n = 0; n < nodes.size(); ++n)
        if (size_t(nodes[n].s) == si) active.push_back(n);
      while (!active.empty()) {
        if ((++res.mergeSteps & 255) == 0 && !reportProgress(progress, "supports", 0.5)) {
          return fail(Status::Cancelled, "cancelled");
        }
        // The highest active node (ties: lowest index, for a deterministic order).
        size_t ai = 0;
        for (size_t k = 1; k < active.size(); ++k) {
          const double hk = nodes[active[k]].p.dot(d), ha = nodes[active[ai]].p.dot(d);
          if (hk > ha || (hk == ha && active[k] < active[ai])) ai = k;
        }
        const size_t A = active[ai];
        active.erase(active.begin() + std::ptrdiff_t(ai));
        const Eigen::Vector3d pa = nodes[A].p;
        const double ha = pa.dot(d);
        const double maxReach = 4 * R;
        // Candidates by horizontal distance, nearest first (at most three tried).
        std::vector<std::pair<double, size_t>> near;
        for (size_t k = 0; k < active.size(); ++k) {
          const Eigen::Vector3d dp = nodes[active[k]].p - pa;
          const double D = std::sqrt(sq(dp.dot(basis.e1)) + sq(dp.dot(basis.e2)));
          if (D <= maxReach) near.push_back({D, k});
        }
        std::sort(near.begin(), near.end());
        bool merged = false;
        for (size_t c = 0; c < near.size() && c < 3 && !merged; ++c) {
          const size_t bk = near[c].second, B = active[bk];
          const Eigen::Vector3d pb = nodes[B].p;
          const double hb = pb.dot(d), D = near[c].first;
          // Meeting point: x along the horizontal from A to B with ha - x / tan = hb - (D - x) / tan.
          double x = 0.5 * ((ha - hb) * tanMerge + D);
          x = std::clamp(x, 0.0, D);
          const double hm = std::min(ha - x / tanMerge, hb - (D - x) / tanMerge);
          const Eigen::Vector3d horiz = (pb - pa) - (pb - pa).dot(d) * d;
          const Eigen::Vector3d m = pa - pa.dot(d) * d + (D > 0 ? Eigen::Vector3d(horiz * (x / D)) : Eigen::Vector3d::Zero()) + hm * d;
          if (subspaceOf(m, planes) != int(si) || (int(si) == platform && m.z() < o.platformBandMm)) continue;
          const double lm = straightLength(m, int(si));
          const double la = straightLength(pa, int(si)), lb = straightLength(pb, int(si));
          if (!((m - pa).norm() + (m - pb).norm() + lm < la + lb)) continue;
          if (!branchClear(pa, m) || !branchClear(pb, m)) continue;
          Node joined{m, int(si), nodes[A].samples + nodes[B].samples, {}};
          for (size_t from : {A, B}) {
            Piece q{nodes[from].p, m, int(si), 0};
            q.diameter = diameterBelow(nodes[from].above, q.top);
            joined.above.insert(joined.above.end(), nodes[from].above.begin(), nodes[from].above.end());
            joined.above.push_back(q);
          }
          active.erase(active.begin() + std::ptrdiff_t(bk));
          nodes.push_back(std::move(joined));
          active.push_back(nodes.size() - 1);
          ++res.merges;
          merged = true;
        }
        if (!merged) finals.push_back(A);
      }
    }
  } else {
    for (size_t n = 0; n < nodes.size(); ++n) finals.push_back(n);
  }

  // Progressive projection (Algorithm 2) of every tree's root (every sample without merging).
  for (size_t fi = 0; fi < finals.size(); ++fi) {
    if ((fi & 255) == 0 && !reportProgress(progress, "supports", 0.5 + 0.5 * double(fi) / double(finals.size()))) {
      return fail(Status::Cancelled, "cancelled");
    }
    const size_t n = finals[fi];
    Eigen::Vector3d x = nodes[n].p;
    int s = nodes[n].s;
    std::vector<Piece> pieces;
    bool ok = false, onModel = false;
    for (size_t guard = 0; guard <= subspaces; ++guard) {
      const Eigen::Vector3d& d = res.directions[size_t(s)];
      // Leaving through the base plane (or reaching the platform).
      const double tExit = s == platform ? std::max(0.0, x.z()) : std::max(0.0, planes[size_t(s)].normal.dot(x) - planes[size_t(s)].offset);
      // Crossing into a subspace printed later: above an earlier plane.
      double tBlock = kInf;
      for (int j = 0; j < s; ++j) {
        const double rate = -planes[size_t(j)].normal.dot(d);
        if (rate <= 1e-12) continue;
        const double v = planes[size_t(j)].normal.dot(x) - planes[size_t(j)].offset;  // <= 0 here
        tBlock = std::min(tBlock, std::max(0.0, -v / rate));
      }
      const double tHit = rays[size_t(s)]->firstHit(x, kSkin);
      if (tBlock < tExit && tBlock < tHit) break;  // blocked
      const double t = std::min(tExit, tHit);
      const Eigen::Vector3d end = x - t * d;
      if (t > 1e-9) pieces.push_back({x, end, s, 0});
      if (tHit <= tExit) {
        ok = onModel = true;
        break;
      }
      if (s == platform) {
        ok = true;
        break;
      }
      // Into the subspace below the base plane: the first later plane whose above side holds it.
      x = end;
      int next = platform;
      for (size_t k = size_t(s) + 1; k < planes.size(); ++k) {
        if (planes[k].normal.dot(x) > planes[k].offset) {
          next = static_cast<int>(k);
          break;
        }
      }
      s = next;
    }
    if (!ok) {
      res.blocked += nodes[n].samples;
      continue;
    }
    if (onModel) ++res.landedOnModel;
    else ++res.landedOnPlatform;
    // Eq. 13, top-down: the torque of the tree's branches and the trunk pieces above.
    std::vector<Piece> above = nodes[n].above;
    const int trace = static_cast<int>(n);
    for (const Piece& q : above) {
      res.struts.push_back({q.top, q.bottom, q.diameter, q.s, trace});
      res.strutVolumeMm3 += pieceVolume(q);
    }
    for (Piece& q : pieces) {
      q.diameter = diameterBelow(above, q.top);
      above.push_back(q);
      res.struts.push_back({q.top, q.bottom, q.diameter, q.s, trace});
      res.strutVolumeMm3 += pieceVolume(q);
    }
  }
  if (!reportProgress(progress, "supports", 1.0)) return fail(Status::Cancelled, "cancelled");
  return res;
}

Mesh supportMesh(const SupportResult& supports, int subspace, const SupportOptions& options, int sides) {
  Mesh out;
  if (subspace < 0 || size_t(subspace) >= supports.directions.size()) return out;
  sides = std::max(3, sides);
  const Eigen::Vector3d d = supports.directions[size_t(subspace)];
  const Basis basis = basisFor(d);
  for (const SupportStrut& s : supports.struts) {
    if (s.subspace != subspace) continue;
    const Eigen::Vector3d axis = s.top - s.bottom;
    if (!(axis.norm() > 1e-6) || !(s.diameterMm > 0)) continue;
    // Circumscribed polygon: its inscribed circle has the strut's diameter.
    const double r = 0.5 * s.diameterMm / det::cos(kPi / sides);
    std::vector<Eigen::Vector3d> ring(static_cast<size_t>(sides));
    for (int k = 0; k < sides; ++k) {
      const double a = 2 * kPi * k / sides;
      ring[size_t(k)] = s.top + r * (det::cos(a) * basis.e1 + det::sin(a) * basis.e2);
    }
    appendPrism(ring, -axis, out);
  }
  if (options.roofMm > 0) {
    for (const SupportRoof& f : supports.roofs) {
      if (f.subspace != subspace) continue;
      appendPrism({f.a, f.b, f.c}, -options.roofMm * d, out);
    }
  }
  return out;
}

}  // namespace omnislice
