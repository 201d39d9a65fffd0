// SPDX-License-Identifier: MIT
// Projected supports (paper 000 Section V, projected_supports.h): the overhang samples of each
// subspace (roofs and their patches, grid samples, missed patches, point overhangs), tree merging,
// the progressive projection of each tree's trunk, Eq. 13 diameters; and the support primitives
// as meshes.
#include "common/math_constants.h"
#include "multidir/projected_supports.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <utility>

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

// Options, mesh and planes: InvalidOption, EmptyInput or NonFiniteVertex, else Ok with the planes
// scaled to unit normals in `planes`.
Outcome checkInput(const Mesh& mesh, const std::vector<Plane>& planesIn, const SupportOptions& o,
                   std::vector<Plane>& planes) {
  auto finitePos = [](double v) { return std::isfinite(v) && v > 0; };
  auto finiteNonNeg = [](double v) { return std::isfinite(v) && v >= 0; };
  if (!finitePos(o.samplingMm)) return failed<Outcome>(Status::InvalidOption, "support sampling interval must be > 0 mm");
  if (!(o.alphaMaxDeg > 0 && o.alphaMaxDeg < 90)) {
    return failed<Outcome>(Status::InvalidOption, "support overhang angle must be in (0, 90) degrees");
  }
  if (!finiteNonNeg(o.platformBandMm) || !finiteNonNeg(o.lambda) || !finiteNonNeg(o.minDiameterMm) ||
      !finiteNonNeg(o.roofMm)) {
    return failed<Outcome>(Status::InvalidOption, "support band, lambda, minimum diameter and roof must be finite and >= 0");
  }
  if (!(o.mergeAngleDeg >= 0 && o.mergeAngleDeg <= 60)) {
    return failed<Outcome>(Status::InvalidOption, "support merge angle must be in [0, 60] degrees");
  }
  if (mesh.empty()) return failed<Outcome>(Status::EmptyInput, "mesh has no triangles");
  const size_t nv = mesh.vertexCount();
  for (uint32_t i : mesh.triangles) {
    if (i >= nv) return failed<Outcome>(Status::InvalidOption, "triangle index out of range");
  }
  for (size_t v = 0; v < nv; ++v) {
    if (!mesh.vertex(v).allFinite()) return failed<Outcome>(Status::NonFiniteVertex, "vertex " + std::to_string(v) + " is not finite");
  }
  for (const Plane& p : planesIn) {
    const double len = p.normal.norm();
    if (!p.normal.allFinite() || !std::isfinite(p.offset) || !(len > 0)) {
      return failed<Outcome>(Status::InvalidOption, "a clipping plane is zero or not finite");
    }
    planes.push_back({p.normal / len, p.offset / len});
  }
  return {};
}

// Faces: unit normals, areas; vertices: neighbours (for point overhangs) and subspaces.
struct SurfaceTables {
  std::vector<Eigen::Vector3d> normal;
  std::vector<double> area;
  std::vector<std::vector<uint32_t>> neighbours;
  std::vector<int> vertexSubspace;
};

SurfaceTables surfaceTables(const Mesh& mesh, const std::vector<Plane>& planes) {
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  SurfaceTables t;
  t.normal.resize(nf);
  t.area.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]), b = mesh.vertex(mesh.triangles[3 * f + 1]),
                          c = mesh.vertex(mesh.triangles[3 * f + 2]);
    const Eigen::Vector3d cr = (b - a).cross(c - a);
    t.area[f] = 0.5 * cr.norm();
    t.normal[f] = t.area[f] > 0 ? Eigen::Vector3d(cr.normalized()) : Eigen::Vector3d::Zero();
  }
  t.neighbours.resize(nv);
  for (size_t f = 0; f < nf; ++f) {
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = mesh.triangles[3 * f + size_t(e)], b = mesh.triangles[3 * f + size_t((e + 1) % 3)];
      t.neighbours[a].push_back(b);
      t.neighbours[b].push_back(a);
    }
  }
  t.vertexSubspace.resize(nv);
  for (size_t v = 0; v < nv; ++v) t.vertexSubspace[v] = subspaceOf(mesh.vertex(v), planes);
  return t;
}

// One subspace seen along its printing direction: which points rest on the platform, which faces
// are risky (Eq. 1).
struct Subspace {
  int index = 0;
  bool isPlatform = false;
  Basis basis;
  double platformBandMm = 0;
  double sinAlpha = 0;
  bool resting(const Eigen::Vector3d& p) const { return isPlatform && p.z() < platformBandMm; }
  bool risky(const SurfaceTables& t, size_t f) const {
    return t.area[f] > 0 && riskyAlong(t.normal[f], basis.d, sinAlpha);
  }
};

struct Sample {
  Eigen::Vector3d p;
  int subspace;
};

// Roofs and patches: risky faces whose centroid lies in this subspace (and does not rest on the
// platform) become roofs; returns their flags.
std::vector<char> roofFaces(const Mesh& mesh, const SurfaceTables& t, const std::vector<Plane>& planes,
                            const Subspace& sub, double roofMm, SupportResult& res) {
  const size_t nf = mesh.faceCount();
  const Eigen::Vector3d& d = sub.basis.d;
  std::vector<char> inPatch(nf, 0);
  for (size_t f = 0; f < nf; ++f) {
    if (!sub.risky(t, f)) continue;
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]), b = mesh.vertex(mesh.triangles[3 * f + 1]),
                          c = mesh.vertex(mesh.triangles[3 * f + 2]);
    const Eigen::Vector3d centroid = (a + b + c) / 3;
    if (subspaceOf(centroid, planes) != sub.index || sub.resting(centroid)) continue;
    inPatch[f] = 1;
    res.roofs.push_back({a, b, c, sub.index});
    res.riskyAreaMm2 += t.area[f];
    res.roofVolumeMm3 += t.area[f] * std::abs(t.normal[f].dot(d)) * roofMm;
  }
  return inPatch;
}

// Patches: the roof faces joined through shared vertices.
DisjointSets roofPatches(const Mesh& mesh, const std::vector<char>& inPatch) {
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  DisjointSets patches(nf);
  std::vector<int64_t> firstFace(nv, -1);
  for (size_t f = 0; f < nf; ++f) {
    if (!inPatch[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[3 * f + size_t(k)];
      if (firstFace[v] < 0) firstFace[v] = int64_t(f);
      else patches.unite(size_t(firstFace[v]), f);
    }
  }
  return patches;
}

// Face overhangs: grid nodes (i R, j R) in (e1, e2) inside a risky face's projection, once per
// grid node and height; marks the patches they fall on in patchSampled.
void gridSamples(const Mesh& mesh, const SurfaceTables& t, const std::vector<Plane>& planes, const Subspace& sub,
                 double R, const std::vector<char>& inPatch, DisjointSets& patches, std::vector<char>& patchSampled,
                 std::vector<Sample>& samples) {
  const size_t nf = mesh.faceCount();
  const Basis& basis = sub.basis;
  const Eigen::Vector3d& d = basis.d;
  const int si = sub.index;
  std::set<std::tuple<long, long, long>> seen;
  for (size_t f = 0; f < nf; ++f) {
    if (!sub.risky(t, f)) continue;
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
        if (subspaceOf(p, planes) != si || sub.resting(p)) continue;
        if (inPatch[f]) patchSampled[patches.find(f)] = 1;
        if (!seen.insert({i, j, std::lround(p.dot(d) / 0.01)}).second) continue;
        samples.push_back({p, si});
      }
    }
  }
}

// Small face and edge overhangs: the lowest vertex of every patch the grid missed.
void missedPatchSamples(const Mesh& mesh, const SurfaceTables& t, const Subspace& sub,
                        const std::vector<char>& inPatch, DisjointSets& patches,
                        const std::vector<char>& patchSampled, std::vector<Sample>& samples, SupportResult& res) {
  const size_t nf = mesh.faceCount();
  const Eigen::Vector3d& d = sub.basis.d;
  std::vector<int64_t> lowest(nf, -1);
  for (size_t f = 0; f < nf; ++f) {
    if (!inPatch[f] || patchSampled[patches.find(f)]) continue;
    const size_t root = patches.find(f);
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[3 * f + size_t(k)];
      if (t.vertexSubspace[v] != sub.index || sub.resting(mesh.vertex(v))) continue;
      if (lowest[root] < 0 || mesh.vertex(v).dot(d) < mesh.vertex(size_t(lowest[root])).dot(d)) lowest[root] = v;
    }
  }
  for (size_t f = 0; f < nf; ++f) {
    if (lowest[f] < 0) continue;
    samples.push_back({mesh.vertex(size_t(lowest[f])), sub.index});
    ++res.patchSamples;
  }
}

// Point overhangs: vertices lower than all their neighbours.
void pointOverhangSamples(const Mesh& mesh, const SurfaceTables& t, const Subspace& sub,
                          std::vector<Sample>& samples, SupportResult& res) {
  const size_t nv = mesh.vertexCount();
  const Eigen::Vector3d& d = sub.basis.d;
  for (size_t v = 0; v < nv; ++v) {
    if (t.vertexSubspace[v] != sub.index || t.neighbours[v].empty()) continue;
    const Eigen::Vector3d p = mesh.vertex(v);
    if (sub.resting(p)) continue;
    const double h = p.dot(d);
    bool minimum = true;
    for (uint32_t u : t.neighbours[v]) {
      if (!(mesh.vertex(u).dot(d) > h + 1e-9)) {
        minimum = false;
        break;
      }
    }
    if (!minimum) continue;
    samples.push_back({p, sub.index});
    ++res.pointOverhangs;
  }
}

// A strut piece with its diameter.
struct Piece {
  Eigen::Vector3d top, bottom;
  int s;
  double diameter = 0;
};

// A piece's prism keeps its cross-section orthogonal to d (the layers' plane), so its volume is
// that area times its height along d (its length for a straight strut).
double pieceVolume(const Piece& q, const std::vector<Eigen::Vector3d>& directions) {
  return kPi * 0.25 * q.diameter * q.diameter * (q.top - q.bottom).dot(directions[size_t(q.s)]);
}

// Eq. 13: the diameter of a piece whose top is `top`, from the torque of the pieces above.
double diameterBelow(const std::vector<Piece>& above, const Eigen::Vector3d& top,
                     const std::vector<Eigen::Vector3d>& directions, const SupportOptions& o) {
  const double R = o.samplingMm;
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  for (const Piece& q : above) {
    const double vol = pieceVolume(q, directions);
    torque += vol * (0.5 * (q.top + q.bottom) - top).cross(-kGravity * directions[size_t(q.s)]);
  }
  return std::max(o.minDiameterMm, (1 + o.lambda * torque.norm()) * R / 4);
}

constexpr double kSkin = 1e-4;  // mm: a ray ignores its own starting surface

// Length along -d of subspace s from x to its base plane (the platform's: z = 0).
double exitLength(const Eigen::Vector3d& x, int s, int platform, const std::vector<Plane>& planes) {
  return s == platform ? std::max(0.0, x.z()) : std::max(0.0, planes[size_t(s)].normal.dot(x) - planes[size_t(s)].offset);
}

// A tree node: a sample, or two nodes joined, with the branches of its tree.
struct Node {
  Eigen::Vector3d p;
  int s;
  size_t samples = 1;
  std::vector<Piece> above;  // the branches of this node's tree
};

// Tree merging (Vanek et al., as the paper's Section V): within each subspace, from the highest
// node down, a node joins its nearest neighbour at the highest point both reach with branches
// at most mergeAngleDeg from -d, when both branches keep clear of the model, the meeting point
// stays in the subspace, and the two branches plus one trunk are shorter than two trunks.
class TreeMerger {
 public:
  TreeMerger(const Mesh& mesh, const std::vector<Plane>& planes, const std::vector<Basis>& bases,
             const std::vector<std::unique_ptr<DownRays>>& rays, const std::vector<Eigen::Vector3d>& directions,
             const SupportOptions& o, const ProgressFn& progress, std::vector<Node>& nodes, SupportResult& res)
      : planes_(planes), bases_(bases), rays_(rays), directions_(directions), o_(o), progress_(progress),
        nodes_(nodes), res_(res), platform_(static_cast<int>(planes.size())) {
    if (o_.mergeAngleDeg > 0 && !nodes_.empty()) surfaceTree_ = std::make_unique<AabbTree>(mesh);
    tanMerge_ = det::sin(o_.mergeAngleDeg * kPi / 180) / det::cos(o_.mergeAngleDeg * kPi / 180);
    clearance_ = 0.5 * o_.minDiameterMm + 0.2;
  }

  // The nodes that go straight down (roots of the trees) into `finals`, every node when
  // mergeAngleDeg is 0. False when cancelled.
  bool run(std::vector<size_t>& finals) {
    if (o_.mergeAngleDeg > 0) {
      for (size_t si = 0; si < bases_.size(); ++si) {
        if (!mergeSubspace(si, finals)) return false;
      }
    } else {
      for (size_t n = 0; n < nodes_.size(); ++n) finals.push_back(n);
    }
    return true;
  }

 private:
  // Straight length along -d of subspace s from x to the model, the platform or the base plane.
  double straightLength(const Eigen::Vector3d& x, int s) const {
    const double tExit = exitLength(x, s, platform_, planes_);
    return std::min(tExit, rays_[size_t(s)]->firstHit(x, kSkin));
  }

  bool branchClear(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const {
    const double len = (to - from).norm();
    const double step = std::max(0.1, 0.5 * clearance_);
    // Skip the first stretch near the overhang the branch starts from (it leaves that surface at
    // >= cos(alpha_max + mergeAngle) per mm).
    for (double t = 2 * clearance_; t <= len; t += step) {
      if (surfaceTree_->anyWithin(from + (to - from) * (t / len), clearance_)) return false;
    }
    return !surfaceTree_->anyWithin(to, clearance_);
  }

  // The nodes of subspace si, highest first, each joined with a near one or kept as a root.
  bool mergeSubspace(size_t si, std::vector<size_t>& finals) {
    const Eigen::Vector3d& d = bases_[si].d;
    std::vector<size_t> active;
    for (size_t n = 0; n < nodes_.size(); ++n)
      if (size_t(nodes_[n].s) == si) active.push_back(n);
    while (!active.empty()) {
      if ((++res_.mergeSteps & 255) == 0 && !reportProgress(progress_, "supports", 0.5)) return false;
      // The highest active node (ties: lowest index, for a deterministic order).
      size_t ai = 0;
      for (size_t k = 1; k < active.size(); ++k) {
        const double hk = nodes_[active[k]].p.dot(d), ha = nodes_[active[ai]].p.dot(d);
        if (hk > ha || (hk == ha && active[k] < active[ai])) ai = k;
      }
      const size_t A = active[ai];
      active.erase(active.begin() + std::ptrdiff_t(ai));
      if (!joinNearest(si, A, active)) finals.push_back(A);
    }
    return true;
  }

  // Joins node A with one of the (at most three) nearest active nodes within 4 R horizontally,
  // where the meeting point qualifies; the joined node becomes active. False when none does.
  bool joinNearest(size_t si, size_t A, std::vector<size_t>& active) {
    const Basis& basis = bases_[si];
    const Eigen::Vector3d& d = basis.d;
    const double R = o_.samplingMm;
    const Eigen::Vector3d pa = nodes_[A].p;
    const double ha = pa.dot(d);
    const double maxReach = 4 * R;
    // Candidates by horizontal distance, nearest first (at most three tried).
    std::vector<std::pair<double, size_t>> near;
    for (size_t k = 0; k < active.size(); ++k) {
      const Eigen::Vector3d dp = nodes_[active[k]].p - pa;
      const double D = std::sqrt(sq(dp.dot(basis.e1)) + sq(dp.dot(basis.e2)));
      if (D <= maxReach) near.push_back({D, k});
    }
    std::sort(near.begin(), near.end());
    for (size_t c = 0; c < near.size() && c < 3; ++c) {
      const size_t bk = near[c].second, B = active[bk];
      const Eigen::Vector3d pb = nodes_[B].p;
      const double hb = pb.dot(d), D = near[c].first;
      // Meeting point: x along the horizontal from A to B with ha - x / tan = hb - (D - x) / tan.
      double x = 0.5 * ((ha - hb) * tanMerge_ + D);
      x = std::clamp(x, 0.0, D);
      const double hm = std::min(ha - x / tanMerge_, hb - (D - x) / tanMerge_);
      const Eigen::Vector3d horiz = (pb - pa) - (pb - pa).dot(d) * d;
      const Eigen::Vector3d m = pa - pa.dot(d) * d + (D > 0 ? Eigen::Vector3d(horiz * (x / D)) : Eigen::Vector3d::Zero()) + hm * d;
      if (subspaceOf(m, planes_) != int(si) || (int(si) == platform_ && m.z() < o_.platformBandMm)) continue;
      const double lm = straightLength(m, int(si));
      const double la = straightLength(pa, int(si)), lb = straightLength(pb, int(si));
      if (!((m - pa).norm() + (m - pb).norm() + lm < la + lb)) continue;
      if (!branchClear(pa, m) || !branchClear(pb, m)) continue;
      Node joined{m, int(si), nodes_[A].samples + nodes_[B].samples, {}};
      for (size_t from : {A, B}) {
        Piece q{nodes_[from].p, m, int(si), 0};
        q.diameter = diameterBelow(nodes_[from].above, q.top, directions_, o_);
        joined.above.insert(joined.above.end(), nodes_[from].above.begin(), nodes_[from].above.end());
        joined.above.push_back(q);
      }
      active.erase(active.begin() + std::ptrdiff_t(bk));
      nodes_.push_back(std::move(joined));
      active.push_back(nodes_.size() - 1);
      ++res_.merges;
      return true;
    }
    return false;
  }

  const std::vector<Plane>& planes_;
  const std::vector<Basis>& bases_;
  const std::vector<std::unique_ptr<DownRays>>& rays_;
  const std::vector<Eigen::Vector3d>& directions_;
  const SupportOptions& o_;
  const ProgressFn& progress_;
  std::vector<Node>& nodes_;
  SupportResult& res_;
  int platform_;
  std::unique_ptr<AabbTree> surfaceTree_;
  double tanMerge_ = 0, clearance_ = 0;
};

// Progressive projection (Algorithm 2) of a tree's root at x in subspace s: the trunk's pieces
// along -d of each subspace down to the model or the platform; `ok` false when it would cross
// into a subspace printed later (blocked).
struct Trunk {
  std::vector<Piece> pieces;
  bool ok = false, onModel = false;
};

Trunk projectTrunk(Eigen::Vector3d x, int s, const std::vector<Plane>& planes,
                   const std::vector<Eigen::Vector3d>& directions, const std::vector<std::unique_ptr<DownRays>>& rays) {
  const int platform = static_cast<int>(planes.size());
  const size_t subspaces = planes.size() + 1;
  Trunk trunk;
  for (size_t guard = 0; guard <= subspaces; ++guard) {
    const Eigen::Vector3d& d = directions[size_t(s)];
    // Leaving through the base plane (or reaching the platform).
    const double tExit = exitLength(x, s, platform, planes);
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
    if (t > 1e-9) trunk.pieces.push_back({x, end, s, 0});
    if (tHit <= tExit) {
      trunk.ok = trunk.onModel = true;
      break;
    }
    if (s == platform) {
      trunk.ok = true;
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
  return trunk;
}

// Eq. 13, top-down: the struts of a tree's branches (their diameters as merged) and of its
// trunk's pieces (each from the torque of the branches and trunk pieces above).
void addTreeStruts(const Node& node, int trace, std::vector<Piece>& trunk,
                   const std::vector<Eigen::Vector3d>& directions, const SupportOptions& o, SupportResult& res) {
  std::vector<Piece> above = node.above;
  for (const Piece& q : above) {
    res.struts.push_back({q.top, q.bottom, q.diameter, q.s, trace});
    res.strutVolumeMm3 += pieceVolume(q, directions);
  }
  for (Piece& q : trunk) {
    q.diameter = diameterBelow(above, q.top, directions, o);
    above.push_back(q);
    res.struts.push_back({q.top, q.bottom, q.diameter, q.s, trace});
    res.strutVolumeMm3 += pieceVolume(q, directions);
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
  std::vector<Plane> planes;
  const Outcome input = checkInput(mesh, planesIn, o, planes);
  if (!input.ok()) return failed<SupportResult>(input);
  const int platform = static_cast<int>(planes.size());
  const size_t subspaces = planes.size() + 1;

  SupportResult res;
  for (const Plane& p : planes) res.directions.push_back(p.normal);
  res.directions.push_back(Eigen::Vector3d::UnitZ());
  const double sinAlpha = sinAlphaMax(o.alphaMaxDeg);
  const double R = o.samplingMm;
  const SurfaceTables tables = surfaceTables(mesh, planes);

  // Overhang samples of every subspace, and its rays along -d.
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
    const Subspace sub{si, si == platform, basis, o.platformBandMm, sinAlpha};
    const std::vector<char> inPatch = roofFaces(mesh, tables, planes, sub, o.roofMm, res);
    DisjointSets patches = roofPatches(mesh, inPatch);
    std::vector<char> patchSampled(mesh.faceCount(), 0);
    gridSamples(mesh, tables, planes, sub, R, inPatch, patches, patchSampled, samples);
    missedPatchSamples(mesh, tables, sub, inPatch, patches, patchSampled, samples, res);
    pointOverhangSamples(mesh, tables, sub, samples, res);
    rays[s] = std::make_unique<DownRays>(mesh, basis);
  }
  res.samples = samples.size();

  std::vector<Node> nodes;
  nodes.reserve(samples.size());
  for (const Sample& sm : samples) nodes.push_back({sm.p, sm.subspace, 1, {}});
  std::vector<size_t> finals;  // nodes that go straight down (roots of the trees)
  TreeMerger merger(mesh, planes, bases, rays, res.directions, o, progress, nodes, res);
  if (!merger.run(finals)) return fail(Status::Cancelled, "cancelled");

  // Progressive projection (Algorithm 2) of every tree's root (every sample without merging).
  for (size_t fi = 0; fi < finals.size(); ++fi) {
    if ((fi & 255) == 0 && !reportProgress(progress, "supports", 0.5 + 0.5 * double(fi) / double(finals.size()))) {
      return fail(Status::Cancelled, "cancelled");
    }
    const size_t n = finals[fi];
    Trunk trunk = projectTrunk(nodes[n].p, nodes[n].s, planes, res.directions, rays);
    if (!trunk.ok) {
      res.blocked += nodes[n].samples;
      continue;
    }
    if (trunk.onModel) ++res.landedOnModel;
    else ++res.landedOnPlatform;
    addTreeStruts(nodes[n], static_cast<int>(n), trunk.pieces, res.directions, o, res);
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
